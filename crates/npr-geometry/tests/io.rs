//! Model loading (`npr_geometry::io`): the bad-input corpus, mutation fuzzing, the same
//! mesh through every format, and meshes at extreme scales or with broken topology.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Quat, Vec3};
use npr_geometry::io::write::{self, PlyEncoding};
use npr_geometry::io::{Format, LoadError, LoadNote, fixtures, load, load_bytes};
use npr_geometry::{CurvatureField, CurvatureOptions, Mesh, Topology, generate, weld};
use proptest::prelude::*;

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/bad")
}

#[test]
fn committed_bad_corpus_matches_the_code() {
    let dir = bad_dir();
    let mut problems = Vec::new();
    for (name, want, _) in fixtures::bad() {
        match std::fs::read(dir.join(name)) {
            Ok(have) if have == want => {}
            Ok(_) => problems.push(format!("{name}: differs from the code")),
            Err(e) => problems.push(format!("{name}: {e}")),
        }
    }
    match std::fs::read_to_string(dir.join("expected.txt")) {
        Ok(t) if t == fixtures::expected_txt() => {}
        _ => problems.push("expected.txt differs from the code".into()),
    }
    assert!(
        problems.is_empty(),
        "run `cargo xtask fixtures`:\n{}",
        problems.join("\n")
    );
}

#[test]
fn every_bad_file_gives_its_kind_and_names_the_file() {
    let dir = bad_dir();
    let manifest = std::fs::read_to_string(dir.join("expected.txt")).unwrap();
    let mut n = 0;
    for line in manifest.lines().filter(|l| !l.trim().is_empty()) {
        let (file, kind) = line.split_once(' ').unwrap();
        let path = dir.join(file);
        let err = match load(&path) {
            Ok(l) => panic!("{file} loaded ({} triangles)", l.mesh.triangle_count()),
            Err(e) => e,
        };
        let msg = err.to_string();
        assert_eq!(err.kind(), kind.trim(), "{file}: {msg}");
        assert!(
            msg.contains(file),
            "{file}: message does not name it: {msg}"
        );
        assert!(
            !msg.contains('\n'),
            "{file}: message is not one line: {msg}"
        );
        n += 1;
    }
    assert!(n >= 20, "only {n} bad files");
}

#[test]
fn missing_file_and_unsupported_extension_are_typed() {
    let e = load("/nonexistent/dir/model.glb").unwrap_err();
    assert_eq!(e.kind(), "missing");
    assert!(e.to_string().contains("/nonexistent/dir/model.glb"));
    let e = load("/nonexistent/model").unwrap_err();
    assert_eq!(e.kind(), "unsupported-format");
    let e = load_bytes(b"", Format::Ply).unwrap_err();
    assert_eq!(e.kind(), "empty");
}

#[test]
fn unsupported_extension_is_named() {
    for (name, _, kind) in fixtures::bad() {
        if kind == "unsupported-extension" {
            let bytes = std::fs::read(bad_dir().join(name)).unwrap();
            let e = load_bytes(&bytes, Format::Gltf).unwrap_err();
            let LoadError::UnsupportedExtension { extension, .. } = &e else {
                panic!("{name}: {e}");
            };
            assert!(e.to_string().contains(extension.as_str()));
            assert!(
                [
                    "KHR_draco_mesh_compression",
                    "EXT_meshopt_compression",
                    "KHR_mesh_quantization"
                ]
                .contains(&extension.as_str())
            );
        }
    }
}

/// Loads every valid format of the tetrahedron and the generated torus.
fn valid_samples() -> Vec<(Format, Vec<u8>)> {
    let tet = fixtures::tetrahedron();
    vec![
        (Format::Obj, write::obj(&tet).into_bytes()),
        (Format::Ply, write::ply(&tet, PlyEncoding::Ascii)),
        (
            Format::Ply,
            write::ply(&tet, PlyEncoding::BinaryLittleEndian),
        ),
        (Format::Ply, write::ply(&tet, PlyEncoding::BinaryBigEndian)),
        (Format::Glb, write::glb(&tet)),
    ]
}

#[test]
fn valid_samples_load() {
    for (format, bytes) in valid_samples() {
        let l = load_bytes(&bytes, format).unwrap_or_else(|e| panic!("{format:?}: {e}"));
        assert_eq!(l.mesh.triangle_count(), 4, "{format:?}");
    }
}

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1..=255u8).prop_map(|(i, x)| Mutation::Flip(i, x)),
        (any::<usize>(), any::<u8>()).prop_map(|(i, x)| Mutation::Insert(i, x)),
        any::<usize>().prop_map(Mutation::Delete),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn mutate(bytes: &mut Vec<u8>, m: &Mutation) {
    let n = bytes.len().max(1);
    match *m {
        Mutation::Flip(i, x) => {
            if let Some(b) = bytes.get_mut(i % n) {
                *b ^= x;
            }
        }
        Mutation::Insert(i, x) => bytes.insert(i % (bytes.len() + 1), x),
        Mutation::Delete(i) => {
            if !bytes.is_empty() {
                bytes.remove(i % n);
            }
        }
        Mutation::Truncate(i) => bytes.truncate(i % n),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

    /// Mutated OBJ, PLY (ASCII, binary LE/BE) and GLB bytes: an error or a valid mesh,
    /// never a panic.
    #[test]
    fn mutated_files_never_panic(
        which in 0..5usize,
        mutations in proptest::collection::vec(mutation(), 1..6),
    ) {
        let (format, mut bytes) = valid_samples().swap_remove(which);
        for m in &mutations {
            mutate(&mut bytes, m);
        }
        let result = std::panic::catch_unwind(|| load_bytes(&bytes, format));
        prop_assert!(result.is_ok(), "panic on {format:?} after {mutations:?}");
        if let Ok(Ok(l)) = result {
            prop_assert!(l.mesh.validate().is_ok());
        }
    }
}

/// A ring mesh, cut into two halves that become two primitives of two meshes in the GLB.
fn test_shape() -> Mesh {
    generate::torus(2.0, 0.6, 12, 8)
}

fn split(mesh: &Mesh, tris: std::ops::Range<usize>) -> Mesh {
    // Keep only the vertices the half uses, renumbered, to exercise per-primitive bases.
    let mut map = vec![u32::MAX; mesh.vertex_count()];
    let mut out = Mesh::default();
    for t in &mesh.indices[tris.start * 3..tris.end * 3] {
        let i = *t as usize;
        if map[i] == u32::MAX {
            map[i] = out.positions.len() as u32;
            out.positions.push(mesh.positions[i]);
            out.normals.push(mesh.normals[i]);
            out.uvs.push(mesh.uvs[i]);
        }
        out.indices.push(map[i]);
    }
    out
}

/// Triangles as position triples, sorted, rounded to 1e-4 so f32 paths compare equal.
fn soup(mesh: &Mesh) -> Vec<[[i64; 3]; 3]> {
    let q = |p: Vec3| (p * 1e4).round().as_i64vec3().to_array();
    let mut s: Vec<_> = mesh
        .triangles()
        .map(|t| {
            let mut c = t.map(|i| q(mesh.positions[i as usize]));
            // Rotate so the smallest corner is first (winding preserved).
            let k = (0..3).min_by_key(|&k| c[k]).unwrap();
            c.rotate_left(k);
            c
        })
        .collect();
    s.sort();
    s
}

#[test]
fn one_mesh_in_every_format_loads_to_the_same_triangles() {
    let mesh = test_shape();
    let want = soup(&mesh);
    let dir = std::env::temp_dir().join(format!("npr-io-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: Vec<(&str, Vec<u8>)> = vec![
        ("shape.obj", write::obj(&mesh).into_bytes()),
        ("shape.ply", write::ply(&mesh, PlyEncoding::Ascii)),
        (
            "shape-le.PLY",
            write::ply(&mesh, PlyEncoding::BinaryLittleEndian),
        ),
        (
            "shape-be.ply",
            write::ply(&mesh, PlyEncoding::BinaryBigEndian),
        ),
        ("shape.glb", write::glb(&mesh)),
    ];
    for (name, bytes) in files {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let l = load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(soup(&l.mesh), want, "{name}");
        assert_eq!(l.mesh.vertex_count(), mesh.vertex_count(), "{name}");
        // Vertex order may differ (OBJ renumbers by first use): match by position.
        for (p, a) in l.mesh.positions.iter().zip(&l.mesh.normals) {
            let k = mesh.positions.iter().position(|q| q == p).unwrap();
            let b = mesh.normals[k];
            assert!(a.distance(b) < 1e-5, "{name}: normal {a} vs {b}");
        }
        assert!(l.report.is_empty(), "{name}: {:?}", l.report);
    }
}

#[test]
fn glb_with_node_hierarchy_and_several_primitives() {
    let mesh = test_shape();
    let nt = mesh.triangle_count();
    let (a, b) = (split(&mesh, 0..nt / 3), split(&mesh, nt / 3..nt));
    let (a1, a2) = {
        let na = a.triangle_count();
        (split(&a, 0..na / 2), split(&a, na / 2..na))
    };
    // Parent: translation + rotation + non-uniform scale; child: its own translation and
    // rotation. Mesh 0 (two primitives a1, a2) on the parent, mesh 1 (b) on the child.
    let t = Vec3::new(1.0, -2.0, 3.0);
    let r = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 2.0).normalize(), 0.7);
    let s = Vec3::new(2.0, 0.5, 1.5);
    let ct = Vec3::new(0.0, 4.0, 0.0);
    let cr = Quat::from_rotation_z(1.1);
    let mut bin = Vec::new();
    let (mut views, mut accessors, mut prims) = (Vec::new(), Vec::new(), Vec::new());
    for m in [&a1, &a2, &b] {
        let (v, acc, p) = write::glb_primitive(m, &mut bin, accessors.len());
        views.extend(v);
        accessors.extend(acc);
        prims.push(p);
    }
    let arr = |v: &[f32]| {
        format!(
            "[{}]",
            v.iter().map(f32::to_string).collect::<Vec<_>>().join(",")
        )
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0,"children":[1],"translation":{},"rotation":{},"scale":{}}},
                 {{"mesh":1,"translation":{},"rotation":{}}}],
        "meshes":[{{"primitives":[{},{}]}},{{"primitives":[{}]}}],
        "accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        arr(&t.to_array()),
        arr(&r.to_array()),
        arr(&s.to_array()),
        arr(&ct.to_array()),
        arr(&cr.to_array()),
        prims[0],
        prims[1],
        prims[2],
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    let glb = write::glb_container(&json, Some(&bin));
    let l = load_bytes(&glb, Format::Glb).unwrap();

    // Expected world positions, computed here independently: p' = T R S p for the parent
    // and T R S (ct + cr p) for the child, composed by hand (no Mat4).
    let parent = |p: Vec3| t + r * (s * p);
    let child = |p: Vec3| parent(ct + cr * p);
    let mut want = Mesh::default();
    for (m, f) in [
        (&a1, &parent as &dyn Fn(Vec3) -> Vec3),
        (&a2, &parent),
        (&b, &child),
    ] {
        let base = want.positions.len() as u32;
        want.positions.extend(m.positions.iter().map(|&p| f(p)));
        want.indices.extend(m.indices.iter().map(|i| i + base));
    }
    let q = |m: &Mesh| {
        let mut s: Vec<_> = m
            .triangles()
            .map(|t| {
                t.map(|i| {
                    (m.positions[i as usize] * 1e3)
                        .round()
                        .as_i64vec3()
                        .to_array()
                })
            })
            .collect();
        s.sort();
        s
    };
    assert_eq!(q(&l.mesh), q(&want));
    // Normals: the inverse-transpose of the linear part, against the face normals of the
    // transformed triangles (the torus normals are smooth; compare each vertex normal with
    // the transformed-and-normalised original through M^-T computed from R and S).
    let m_parent = Mat3::from_quat(r) * Mat3::from_diagonal(s);
    let m_child = m_parent * Mat3::from_quat(cr);
    let mut k = 0;
    for (m, lin) in [(&a1, m_parent), (&a2, m_parent), (&b, m_child)] {
        for n in &m.normals {
            let want = (lin.inverse().transpose() * *n).normalize();
            assert!(l.mesh.normals[k].distance(want) < 1e-4, "normal {k}");
            k += 1;
        }
    }
    assert!(
        l.report
            .contains(&LoadNote::TransformsApplied { instances: 2 })
    );
    let _ = Mat4::IDENTITY;
}

#[test]
fn report_lists_what_changed() {
    // A quad (triangulated), a point and a line (skipped), an unused vertex, no normals.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\np 1\nl 1 2\nf 1 2 3 4\n";
    let l = load_bytes(obj.as_bytes(), Format::Obj).unwrap();
    assert_eq!(l.mesh.triangle_count(), 2);
    assert!(l.report.contains(&LoadNote::Triangulated { polygons: 1 }));
    assert!(
        l.report
            .iter()
            .any(|n| matches!(n, LoadNote::Skipped { .. }))
    );
    assert!(
        l.report
            .iter()
            .any(|n| matches!(n, LoadNote::NormalsRecomputed { .. }))
    );
    // PLY: an unused vertex is removed, a degenerate face kept, a pentagon fanned.
    let ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty double x\nproperty double y\n\
               property double z\nelement face 2\nproperty list uchar int vertex_index\n\
               end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n-1 0.5 0\n7 7 7\n5 0 1 2 3 4\n3 0 0 1\n";
    let l = load_bytes(ply.as_bytes(), Format::Ply).unwrap();
    assert_eq!(l.mesh.vertex_count(), 5);
    assert_eq!(l.mesh.triangle_count(), 4);
    assert!(
        l.report
            .contains(&LoadNote::UnreferencedVerticesRemoved { count: 1 })
    );
    assert!(l.report.contains(&LoadNote::DegenerateKept { count: 1 }));
    assert!(l.report.contains(&LoadNote::Triangulated { polygons: 1 }));
    for note in &l.report {
        assert!(!note.to_string().is_empty());
    }
}

#[test]
fn gltf_with_external_and_data_uri_buffers() {
    let mesh = fixtures::tetrahedron();
    let mut bin = Vec::new();
    let (views, accessors, prim) = write::glb_primitive(&mesh, &mut bin, 0);
    let doc = |uri: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{prim}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{},"uri":"{uri}"}}]}}"#,
            accessors.join(","),
            views.join(","),
            bin.len()
        )
    };
    let dir = std::env::temp_dir().join(format!("npr-io-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tet data.bin"), &bin).unwrap();
    std::fs::write(dir.join("tet.gltf"), doc("tet%20data.bin")).unwrap();
    let l = load(dir.join("tet.gltf")).unwrap();
    assert_eq!(soup(&l.mesh), soup(&mesh));
    // From bytes, the external buffer cannot be resolved.
    let e = load_bytes(doc("tet%20data.bin").as_bytes(), Format::Gltf).unwrap_err();
    assert_eq!(e.kind(), "unsupported-feature");
    // A data URI works anywhere.
    let b64 = base64_encode(&bin);
    let uri = format!("data:application/octet-stream;base64,{b64}");
    let l = load_bytes(doc(&uri).as_bytes(), Format::Gltf).unwrap();
    assert_eq!(soup(&l.mesh), soup(&mesh));
}

fn base64_encode(b: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in b.chunks(3) {
        let v = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..=c.len() {
            s.push(A[(v >> (18 - 6 * k) & 63) as usize] as char);
        }
    }
    while !s.len().is_multiple_of(4) {
        s.push('=');
    }
    s
}

/// `mesh` with every position multiplied by `s`.
fn scaled(mesh: &Mesh, s: f32) -> Mesh {
    let mut m = mesh.clone();
    for p in &mut m.positions {
        *p *= s;
    }
    m
}

/// Curvature at scale `s` of an ellipsoid, rescaled back (κ·s), against scale 1.
#[test]
fn curvature_is_consistent_across_extreme_scales() {
    let base = generate::ellipsoid(1.0, 0.7, 0.5, 6);
    let field_at = |s: f32| {
        let m = scaled(&base, s);
        let topo = Topology::new(&weld(&m));
        CurvatureField::compute(&topo, &CurvatureOptions::default())
    };
    let one = field_at(1.0);
    assert!(one.valid.iter().all(|&v| v));
    for s in [1e-30f32, 1e-20, 1e20, 1e30] {
        let f = field_at(s);
        assert!(f.valid.iter().all(|&v| v), "scale {s:e}: undefined rows");
        assert!((f.radius_world / s / one.radius_world - 1.0).abs() < 1e-5);
        for v in 0..f.len() {
            for (k, k1) in [
                (f.kappa_max[v], one.kappa_max[v]),
                (f.kappa_min[v], one.kappa_min[v]),
            ] {
                let rel = ((k * s) as f64 - k1 as f64).abs() / (k1.abs() as f64).max(1e-3);
                assert!(rel < 1e-4, "scale {s:e} vertex {v}: {} vs {k1}", k * s);
            }
            assert!(f.dir_kappa_max[v].abs().dot(one.dir_kappa_max[v].abs()) > 0.999);
        }
    }
}

#[test]
fn broken_topology_loads_and_computes() {
    // Duplicate vertices, zero-area faces, a non-manifold edge (three faces), two
    // disconnected pieces, an isolated triangle far away.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nv 1 0 0\nv 2 0 0\n\
               v 10 10 10\nv 11 10 10\nv 10 11 10\n\
               f 1 2 3\nf 1 2 4\nf 1 2 5\nf 1 6 3\nf 1 2 7\nf 1 1 2\nf 8 9 10\n";
    let l = load_bytes(obj.as_bytes(), Format::Obj).unwrap();
    assert!(
        l.report
            .iter()
            .any(|n| matches!(n, LoadNote::DegenerateKept { .. }))
    );
    for scale in [1e-30f32, 1.0, 1e30] {
        let m = scaled(&l.mesh, scale);
        let (_, topo, f) = CurvatureField::for_mesh(&m, &CurvatureOptions::default());
        assert_eq!(topo.vertex_count(), 9);
        assert!(
            f.kappa_max
                .iter()
                .chain(&f.kappa_min)
                .all(|k| k.is_finite())
        );
        assert!(f.normal.iter().all(|n| n.is_finite()));
        let search = npr_geometry::HighlightSearch::new(&topo, &f);
        let centres = search.find(
            npr_geometry::LightEye::Directions {
                to_light: Vec3::Y,
                to_eye: Vec3::Z,
            },
            Mat4::IDENTITY,
        );
        assert!(centres.iter().all(|c| c.position_world.is_finite()));
    }
}

/// Highlight centres of the same mesh at 1e-30, 1 and 1e30: same faces and barycentric
/// coordinates, positions scaled.
#[test]
fn highlight_centres_are_consistent_across_extreme_scales() {
    let base = generate::ellipsoid(1.0, 0.7, 0.5, 6);
    let centres_at = |s: f32| {
        let m = scaled(&base, s);
        let (_, topo, field) = CurvatureField::for_mesh(&m, &CurvatureOptions::default());
        let search = npr_geometry::HighlightSearch::new(&topo, &field);
        let mut c = search.find(
            npr_geometry::LightEye::Directions {
                to_light: Vec3::new(0.3, 1.0, 0.2).normalize(),
                to_eye: Vec3::Z,
            },
            Mat4::IDENTITY,
        );
        c.sort_by_key(|c| c.face);
        c
    };
    let one = centres_at(1.0);
    assert!(!one.is_empty());
    for s in [1e-30f32, 1e30] {
        let c = centres_at(s);
        assert_eq!(c.len(), one.len(), "scale {s:e}");
        for (a, b) in c.iter().zip(&one) {
            assert_eq!(a.face, b.face);
            assert!((a.alpha - b.alpha).abs() < 1e-3 && (a.beta - b.beta).abs() < 1e-3);
            assert!((a.position_object / s).distance(b.position_object) < 1e-4);
        }
    }
}

/// The shipped meshes load through `io::load` as through `load_obj`, and survive a trip
/// through binary PLY and GLB unchanged.
#[test]
fn shipped_meshes_through_every_format() {
    for name in ["stanford-bunny.obj", "spot.obj"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fixtures/meshes")
            .join(name);
        let l = load(&path).unwrap();
        let m = npr_geometry::load_obj(&path).unwrap();
        assert_eq!(l.mesh, m, "{name}");
        for (format, bytes) in [
            (Format::Ply, write::ply(&m, PlyEncoding::BinaryLittleEndian)),
            (Format::Ply, write::ply(&m, PlyEncoding::BinaryBigEndian)),
            (Format::Glb, write::glb(&m)),
        ] {
            let back = load_bytes(&bytes, format).unwrap();
            assert_eq!(back.mesh.positions, m.positions, "{name} {format:?}");
            assert_eq!(back.mesh.indices, m.indices, "{name} {format:?}");
            assert_eq!(back.mesh.uvs, m.uvs, "{name} {format:?}");
        }
    }
}

/// glTF strips and fans become consistently wound triangle lists; point primitives are
/// skipped and reported; a primitive without normals makes the loader recompute them.
#[test]
fn gltf_strips_fans_points_and_partial_normals() {
    // A zig-zag strip of 6 vertices in the z = 0 plane, and a fan of 5 around the origin.
    let strip = Mesh {
        positions: (0..6)
            .map(|i| Vec3::new((i / 2) as f32, (i % 2) as f32, 0.0))
            .collect(),
        normals: vec![Vec3::Z; 6],
        uvs: vec![],
        indices: (0..6).collect(),
    };
    let fan = Mesh {
        positions: std::iter::once(Vec3::ZERO)
            .chain((0..4).map(|k| {
                let a = k as f32 * 0.5;
                Vec3::new(a.cos(), a.sin(), 0.0) + Vec3::X * 5.0
            }))
            .collect(),
        normals: vec![],
        uvs: vec![],
        indices: (0..5).collect(),
    };
    let points = Mesh {
        positions: vec![Vec3::ONE],
        normals: vec![],
        uvs: vec![],
        indices: vec![0],
    };
    let mut bin = Vec::new();
    let (mut views, mut accessors, mut prims) = (Vec::new(), Vec::new(), Vec::new());
    for (m, mode) in [(&strip, 5), (&fan, 6), (&points, 0)] {
        let (v, acc, p) = write::glb_primitive(m, &mut bin, accessors.len());
        views.extend(v);
        accessors.extend(acc);
        prims.push(p.replace(r#""mode":4"#, &format!(r#""mode":{mode}"#)));
    }
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{}]}}],"accessors":[{}],"bufferViews":[{}],
        "buffers":[{{"byteLength":{}}}]}}"#,
        prims.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    let l = load_bytes(&write::glb_container(&json, Some(&bin)), Format::Glb).unwrap();
    assert_eq!(l.mesh.triangle_count(), 4 + 3);
    // Every triangle faces the same way (+z for the strip as written, the fan too).
    for t in l.mesh.triangles() {
        let [a, b, c] = t.map(|i| l.mesh.positions[i as usize]);
        let n = (b - a).cross(c - a);
        assert!(
            n.z * (if t[0] < 6 { -1.0 } else { 1.0 }) > 0.0,
            "{t:?}: {n}"
        );
    }
    assert!(
        l.report
            .contains(&LoadNote::StripsConverted { primitives: 2 })
    );
    assert!(
        l.report
            .iter()
            .any(|n| matches!(n, LoadNote::Skipped { count: 1, .. }))
    );
    assert!(
        l.report
            .iter()
            .any(|n| matches!(n, LoadNote::NormalsRecomputed { .. }))
    );
    // The point's vertex is gone with its primitive.
    assert!(!l.mesh.positions.contains(&Vec3::ONE));
}

/// PLY with integer coordinates, `s t` texture coordinates, a `vertex_index` list of
/// `ushort` and extra elements before and after.
#[test]
fn ply_any_scalar_types_and_extra_elements() {
    let mut ply = b"ply\nformat binary_big_endian 1.0\ncomment made by hand\n\
        element material 1\nproperty uchar red\n\
        element vertex 3\nproperty short x\nproperty short y\nproperty short z\n\
        property float s\nproperty float t\nproperty uchar confidence\n\
        element face 1\nproperty list ushort ushort vertex_index\n\
        element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        .to_vec();
    ply.push(200);
    for (p, st) in [
        ([0i16, 0, 0], [0.0f32, 0.0]),
        ([10, 0, 0], [1.0, 0.0]),
        ([0, 10, 0], [0.0, 1.0]),
    ] {
        p.iter().for_each(|c| ply.extend(c.to_be_bytes()));
        st.iter().for_each(|c| ply.extend(c.to_be_bytes()));
        ply.push(7);
    }
    ply.extend(3u16.to_be_bytes());
    [0u16, 1, 2]
        .iter()
        .for_each(|i| ply.extend(i.to_be_bytes()));
    ply.extend(0i32.to_be_bytes());
    ply.extend(1i32.to_be_bytes());
    let l = load_bytes(&ply, Format::Ply).unwrap();
    assert_eq!(l.mesh.positions[1], Vec3::new(10.0, 0.0, 0.0));
    assert_eq!(l.mesh.uvs[2], glam::Vec2::new(0.0, 1.0));
    assert_eq!(l.mesh.indices, vec![0, 1, 2]);
    assert_eq!(l.mesh.normals, vec![Vec3::Z; 3]);
}

#[test]
fn obj_texture_and_normal_indices_are_checked_with_their_line() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1/1 2/5 3/1\n";
    let e = load_bytes(obj.as_bytes(), Format::Obj).unwrap_err();
    assert_eq!(e.kind(), "index-out-of-range");
    let msg = e.to_string();
    assert!(
        msg.contains("line 6 (`vt`") && msg.contains("index 5"),
        "{e}"
    );
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\nvn 0 0 1\n";
    let l = load_bytes(obj.as_bytes(), Format::Obj).unwrap();
    assert_eq!(l.mesh.normals, vec![Vec3::Z; 3]);
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nf -4 -2 -1\n";
    let e = load_bytes(obj.as_bytes(), Format::Obj).unwrap_err();
    assert!(e.to_string().contains("line 5"), "{e}");
}
