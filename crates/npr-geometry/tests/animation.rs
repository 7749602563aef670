//! glTF animation: the shipped animated files load and pose, posing keeps the loaded
//! layout, hand-computed skinning results, and every bad-input case is a typed error or
//! a note (built from small glTF documents with data-URI buffers).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::Vec3;
use npr_geometry::animation::Rig;
use npr_geometry::io::{self, Format, LoadNote, Loaded};
use npr_geometry::{Mesh, weld};

fn fixture(name: &str) -> Loaded {
    let path = format!(
        "{}/../../fixtures/meshes/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    io::load(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Largest distance of a vertex from the bounding box centre.
fn radius(m: &Mesh) -> f32 {
    let (lo, hi) = bounds(&m.positions);
    let c = 0.5 * (lo + hi);
    m.positions
        .iter()
        .map(|p| (*p - c).length())
        .fold(0.0, f32::max)
}

fn bounds(p: &[Vec3]) -> (Vec3, Vec3) {
    p.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), q| (lo.min(*q), hi.max(*q)),
    )
}

fn max_distance(a: &[Vec3], b: &[Vec3]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f32::max)
}

/// The bind pose gives the loaded mesh back, with the same layout.
fn check_bind_is_loaded(loaded: &Loaded) -> &Rig {
    let rig = loaded.rig.as_ref().expect("a rig");
    let posed = rig.pose_mesh(&rig.bind_pose());
    assert_eq!(posed.indices, loaded.mesh.indices);
    assert_eq!(posed.uvs, loaded.mesh.uvs);
    let r = radius(&loaded.mesh);
    let d = max_distance(&posed.positions, &loaded.mesh.positions);
    assert!(
        d <= 1e-5 * r,
        "bind pose is {d} from the loaded mesh (radius {r})"
    );
    let dn = max_distance(&posed.normals, &loaded.mesh.normals);
    assert!(dn < 1e-4, "bind pose normals differ by {dn}");
    rig
}

#[test]
fn fox_has_its_clips_and_joints_and_poses_in_the_loaded_layout() {
    let loaded = fixture("Fox.glb");
    assert_eq!(loaded.mesh.vertex_count(), 1728);
    assert_eq!(loaded.mesh.triangle_count(), 576);
    let rig = check_bind_is_loaded(&loaded);
    assert!(rig.recomputes_normals(), "the Fox has no normals");
    assert_eq!(rig.skins().len(), 1);
    assert_eq!(rig.skins()[0].joints.len(), 24);
    let names: Vec<_> = rig.clips().iter().map(|c| c.name().unwrap()).collect();
    assert_eq!(names, ["Survey", "Walk", "Run"]);
    // Durations as the source lists them (3.42 s, 0.71 s, 1.16 s).
    for (name, d) in [("Survey", 3.42), ("Walk", 0.71), ("Run", 1.16)] {
        let clip = rig.clip_named(name).unwrap();
        assert!(
            (clip.duration() - d).abs() < 0.01,
            "{name}: {}",
            clip.duration()
        );
    }
    assert!(rig.clip_named("Jump").is_none());
    // The Fox's joints at rest match its inverse bind matrices: rest pose = bind pose.
    let rest = rig.pose_mesh(&rig.rest_pose());
    let d = max_distance(&rest.positions, &loaded.mesh.positions);
    assert!(d < 1e-5 * radius(&loaded.mesh), "rest is {d} from bind");
    // Every vertex is skinned with weights summing to 1 and joints in range.
    for v in 0..rig.vertex_count() {
        let inf = rig.influences(v);
        assert!(!inf.is_empty());
        let sum: f32 = inf.iter().map(|x| x.1).sum();
        assert!((sum - 1.0).abs() < 1e-5);
        assert!(inf.iter().all(|x| usize::from(x.0) < 24));
    }
    // The map back to the file: a soup, so render vertex v is file vertex v.
    assert!(
        rig.file_vertices()
            .iter()
            .enumerate()
            .all(|(v, f)| f.vertex as usize == v && f.mesh == 0 && f.primitive == 0)
    );
    // Walking moves the fox; the posed mesh keeps the layout and the weld.
    let walk = rig.clip_named("Walk").unwrap();
    let a = rig.pose_mesh(&rig.sample(walk, 0.0));
    let b = rig.pose_mesh(&rig.sample(walk, 0.35));
    let r = radius(&loaded.mesh);
    assert!(max_distance(&a.positions, &b.positions) > 0.02 * r);
    let w0 = weld(&loaded.mesh);
    for m in [&a, &b] {
        m.validate().unwrap();
        assert_eq!(m.indices, loaded.mesh.indices);
        let w = weld(m);
        assert_eq!(w.render_to_welded, w0.render_to_welded);
        assert_eq!(w.indices, w0.indices);
        // Normals recomputed per pose: unit, and each agrees with its face's winding
        // on most faces.
        assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    }
    // Recomputed normals follow the pose: they differ between the two times.
    assert!(max_distance(&a.normals, &b.normals) > 0.1);
    // The clip's bounds hold every sampled pose.
    let (lo, hi) = rig.clip_bounds(walk, 16);
    for p in a.positions.iter().chain(&b.positions) {
        assert!(p.cmpge(lo - 1e-3).all() && p.cmple(hi + 1e-3).all());
    }
}

#[test]
fn simple_skin_follows_its_joints_by_hand() {
    let loaded = fixture("SimpleSkin.gltf");
    let rig = check_bind_is_loaded(&loaded);
    assert_eq!(rig.skins()[0].joints, vec![1, 2]);
    let clip = &rig.clips()[0];
    assert!((clip.duration() - 5.5).abs() < 1e-6);
    // At t = 0 the rotation key is the identity, the rest rotation: the clip's first
    // pose is the rest pose.
    let rest = rig.pose_mesh(&rig.rest_pose());
    let t0 = rig.pose_mesh(&rig.sample(clip, 0.0));
    assert!(max_distance(&rest.positions, &t0.positions) < 1e-6);
    // The file's inverse bind matrices are both translate(-0.5, -1, 0) and both joints
    // sit at (0, 1, 0) at rest, so each joint matrix is translate(-0.5, 0, 0): the rest
    // pose is the file's mesh moved by -0.5 in x (the bind pose, identity joint
    // matrices, is the file's mesh).
    for (p, q) in t0.positions.iter().zip(&loaded.mesh.positions) {
        assert!(
            (*p - (*q - Vec3::new(0.5, 0.0, 0.0))).length() < 1e-6,
            "{p} {q}"
        );
    }
    // t = 1 s: key 2 rotates joint 1 by 90° about z (0.707, 0.707 normalised). The top
    // vertex (0, 2, 0), bound to joint 1 only: (0,1,0) + R90 · ((0,2,0) - (0.5,1,0))
    // = (0,1,0) + R90 · (-0.5, 1, 0) = (0,1,0) + (-1, -0.5, 0) = (-1, 0.5, 0).
    let t1 = rig.pose_mesh(&rig.sample(clip, 1.0));
    let top = (0..10)
        .find(|&v| loaded.mesh.positions[v] == Vec3::new(0.0, 2.0, 0.0))
        .unwrap();
    assert!((t1.positions[top] - Vec3::new(-1.0, 0.5, 0.0)).length() < 1e-5);
    // The middle vertex (0, 1, 0), half on each joint: 0.5·(-0.5, 1, 0) + 0.5·(0, 0.5, 0).
    let mid = (0..10)
        .find(|&v| loaded.mesh.positions[v] == Vec3::new(0.0, 1.0, 0.0))
        .unwrap();
    assert!((t1.positions[mid] - Vec3::new(-0.25, 0.75, 0.0)).length() < 1e-5);
    // The bottom row is bound to joint 0, which does not move.
    assert!((t1.positions[0] - t0.positions[0]).length() < 1e-6);
}

#[test]
fn morph_stress_test_morphs_by_its_weights() {
    let loaded = fixture("MorphStressTest.gltf");
    let rig = check_bind_is_loaded(&loaded);
    assert!(rig.skins().is_empty());
    let names: Vec<_> = rig.clips().iter().map(|c| c.name().unwrap()).collect();
    assert_eq!(names, ["Individuals", "Pulse", "TheWave"]);
    assert_eq!(rig.instances()[0].weights, vec![0.0; 8]);
    // One target at weight 1 moves each vertex by that target's delta.
    for k in [0, 3, 7] {
        let mut pose = rig.bind_pose();
        let mut w = [0.0; 8];
        w[k] = 1.0;
        assert!(pose.set_morph_weights(0, &w));
        let posed = rig.pose_mesh(&pose);
        let mut moved = 0;
        for v in 0..rig.vertex_count() {
            let d = rig.morph_deltas(v).0[k];
            let got = posed.positions[v] - loaded.mesh.positions[v];
            assert!(
                (got - d).length() < 1e-5,
                "target {k} vertex {v}: {got} vs {d}"
            );
            moved += usize::from(d.length() > 1e-4);
        }
        assert!(moved > 0, "target {k} moves nothing");
    }
    // The clips animate the weights: some time of each clip differs from the bind pose.
    for clip in rig.clips() {
        let d = clip.duration();
        let moved = (0..32).any(|k| {
            let m = rig.pose_mesh(&rig.sample(clip, d * (k as f32 + 0.37) / 32.0));
            max_distance(&m.positions, &loaded.mesh.positions) > 1e-3
        });
        assert!(moved, "{:?} never moves", clip.name());
    }
}

#[test]
fn files_without_animation_have_no_rig() {
    let loaded = io::load_bytes(
        &io::write::glb(&npr_geometry::io::fixtures::tetrahedron()),
        Format::Glb,
    )
    .unwrap();
    assert!(loaded.rig.is_none());
}

// ---- Bad input, from a small skinned triangle ----------------------------------------

fn b64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// A triangle skinned to two joints (nodes 1 and 2, node 2 a child of node 1 at
/// (0, 1, 0)), inverse bind matrices absent (identity), one translation channel on
/// node 2.
struct Tri {
    joints: [[u8; 4]; 3],
    weights: [[f32; 4]; 3],
    with_joints: bool,
    times: Vec<f32>,
    values: Vec<[f32; 3]>,
    interpolation: &'static str,
    /// The JOINTS_0 component type (5121: unsigned byte).
    joints_type: u32,
    /// The channel's target path.
    path: &'static str,
    /// Extra members of the skinned mesh's node (e.g. a translation).
    mesh_node: &'static str,
}

impl Default for Tri {
    fn default() -> Self {
        Self {
            joints: [[0, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0]],
            weights: [[1.0, 0.0, 0.0, 0.0]; 3],
            with_joints: true,
            times: vec![0.0, 1.0],
            values: vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            interpolation: "LINEAR",
            joints_type: 5121,
            path: "translation",
            mesh_node: "",
        }
    }
}

impl Tri {
    fn gltf(&self) -> Vec<u8> {
        let mut bin: Vec<u8> = Vec::new();
        let f = |bin: &mut Vec<u8>, x: f32| bin.extend_from_slice(&x.to_le_bytes());
        for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for x in p {
                f(&mut bin, x);
            }
        }
        let joints_at = bin.len();
        for j in self.joints {
            bin.extend_from_slice(&j);
        }
        let weights_at = bin.len();
        for w in self.weights {
            for x in w {
                f(&mut bin, x);
            }
        }
        let times_at = bin.len();
        for &t in &self.times {
            f(&mut bin, t);
        }
        let values_at = bin.len();
        for v in &self.values {
            for &x in v {
                f(&mut bin, x);
            }
        }
        let view = |at: usize, len: usize| {
            format!(r#"{{"buffer":0,"byteOffset":{at},"byteLength":{len}}}"#)
        };
        let attributes = if self.with_joints {
            r#"{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}"#
        } else {
            r#"{"POSITION":0}"#
        };
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"skin":0{mesh_node}}},{{"children":[2]}},{{"translation":[0,1,0]}}],
"skins":[{{"joints":[1,2]}}],
"meshes":[{{"primitives":[{{"attributes":{attributes}}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":2,"path":"{path}"}}}}],
  "samplers":[{{"input":3,"output":4,"interpolation":"{interp}"}}]}}],
"accessors":[
 {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
 {{"bufferView":1,"componentType":{jt},"count":3,"type":"VEC4"}},
 {{"bufferView":2,"componentType":5126,"count":3,"type":"VEC4"}},
 {{"bufferView":3,"componentType":5126,"count":{nt},"type":"SCALAR"}},
 {{"bufferView":4,"componentType":5126,"count":{nv},"type":"VEC3"}}],
"bufferViews":[{v0},{v1},{v2},{v3},{v4}],
"buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{data}"}}]}}"#,
            interp = self.interpolation,
            mesh_node = self.mesh_node,
            path = self.path,
            jt = self.joints_type,
            nt = self.times.len(),
            nv = self.values.len(),
            v0 = view(0, 36),
            v1 = view(joints_at, 12),
            v2 = view(weights_at, 48),
            v3 = view(times_at, 4 * self.times.len()),
            v4 = view(values_at, 12 * self.values.len()),
            len = bin.len(),
            data = b64(&bin),
        )
        .into_bytes()
    }

    fn load(&self) -> Result<Loaded, io::LoadError> {
        io::load_bytes(&self.gltf(), Format::Gltf)
    }
}

fn animation_error(tri: Tri) -> &'static str {
    match tri.load() {
        Err(io::LoadError::Animation { error, .. }) => error.kind(),
        Err(e) => panic!("expected an animation error, got {} ({e})", e.kind()),
        Ok(_) => panic!("expected an animation error, loaded"),
    }
}

#[test]
fn the_hand_made_triangle_is_valid_and_poses() {
    let loaded = Tri::default().load().unwrap();
    let rig = check_bind_is_loaded(&loaded);
    assert!(
        loaded
            .report
            .iter()
            .all(|n| !matches!(n, LoadNote::WeightsNormalised { .. }))
    );
    let clip = &rig.clips()[0];
    // t = 0.5: the channel replaces node 2's translation (0, 1, 0) by halfway from 0 to
    // (2, 0, 0), i.e. (1, 0, 0); its parent is at the origin, so joint 1's matrix is
    // translate(1, 0, 0) (identity inverse binds) and vertices 1 and 2 move by (1, 0, 0);
    // vertex 0 (joint 0, node 1 at the origin) stays.
    let m = rig.pose_mesh(&rig.sample(clip, 0.5));
    assert!((m.positions[0] - Vec3::ZERO).length() < 1e-6);
    assert!((m.positions[1] - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
    assert!((m.positions[2] - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
    // Rest pose: node 2 at (0, 1, 0) lifts vertices 1 and 2.
    let r = rig.pose_mesh(&rig.rest_pose());
    assert!((r.positions[1] - Vec3::new(1.0, 1.0, 0.0)).length() < 1e-6);
}

#[test]
fn joint_out_of_range_is_an_error() {
    let mut tri = Tri::default();
    tri.joints[1] = [5, 0, 0, 0];
    assert_eq!(animation_error(tri), "joint-out-of-range");
}

#[test]
fn weights_not_summing_to_one_are_normalised_with_a_note() {
    let mut tri = Tri::default();
    tri.weights[0] = [0.5, 0.0, 0.0, 0.0];
    tri.weights[2] = [0.25, 0.25, 0.0, 0.0];
    tri.joints[2] = [0, 1, 0, 0];
    let loaded = tri.load().unwrap();
    assert!(
        loaded
            .report
            .contains(&LoadNote::WeightsNormalised { vertices: 2 }),
        "{:?}",
        loaded.report
    );
    let rig = loaded.rig.unwrap();
    assert_eq!(rig.influences(0), &[(0, 1.0)]);
    assert_eq!(rig.influences(2), &[(0, 0.5), (1, 0.5)]);
}

#[test]
fn all_zero_or_negative_weights_are_errors() {
    let mut tri = Tri::default();
    tri.weights[1] = [0.0; 4];
    assert_eq!(animation_error(tri), "bad-weights");
    let mut tri = Tri::default();
    tri.weights[1] = [1.5, -0.5, 0.0, 0.0];
    assert_eq!(animation_error(tri), "bad-weights");
}

#[test]
fn nan_keys_are_errors() {
    let tri = Tri {
        times: vec![0.0, f32::NAN],
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "non-finite-key");
    let tri = Tri {
        values: vec![[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0]],
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "non-finite-key");
}

#[test]
fn key_times_that_do_not_increase_are_errors() {
    let tri = Tri {
        times: vec![0.0, 1.0, 1.0],
        values: vec![[0.0; 3]; 3],
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "times-not-increasing");
}

#[test]
fn cubic_spline_outputs_not_three_per_key_are_errors() {
    let tri = Tri {
        interpolation: "CUBICSPLINE",
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "cubic-spline-outputs");
    // Six outputs for two keys are right.
    let ok = Tri {
        interpolation: "CUBICSPLINE",
        values: vec![[0.0; 3]; 6],
        ..Tri::default()
    };
    ok.load().unwrap();
}

#[test]
fn a_skin_on_a_primitive_without_joints_is_an_error() {
    let tri = Tri {
        with_joints: false,
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "missing-skin-attribute");
}

// ---- Procedural rigged models -----------------------------------------------------

use npr_geometry::generate;

/// The bent tube at its keys is the torus section: every vertex at distance `r` from
/// the arc of radius ρ about (−ρ, 0, 0), its ring in the plane at angle s / ρ, its
/// normal pointing away from the arc.
#[test]
fn bent_tube_is_a_torus_section_at_its_keys() {
    let (r, rho, theta) = (0.3f32, 2.0f32, std::f32::consts::FRAC_PI_2);
    let m = generate::bent_tube(r, rho, theta, 32, 24);
    let rig = &m.rig;
    assert!(rig.skins()[0].joints.len() >= 16);
    let loaded = Loaded {
        mesh: m.mesh.clone(),
        report: Vec::new(),
        rig: Some(rig.clone()),
    };
    check_bind_is_loaded(&loaded);
    let clip = rig.clip_named("bend").unwrap();
    // t = 0: still the straight tube.
    let straight = rig.pose_mesh(&rig.sample(clip, 0.0));
    assert!(max_distance(&straight.positions, &m.mesh.positions) < 1e-5);
    for (t, big_r, angle) in [(1.0, rho, theta), (0.5, 2.0 * rho, theta / 2.0)] {
        let posed = rig.pose_mesh(&rig.sample(clip, t));
        let centre = Vec3::new(-big_r, 0.0, 0.0);
        let mut worst = (0.0f32, 0.0f32, 0.0f32);
        for v in 0..posed.vertex_count() {
            let s = m.mesh.positions[v].y; // arc length along the straight tube
            let q = posed.positions[v] - centre;
            let rxy = (q.x * q.x + q.y * q.y).sqrt();
            let tube = ((rxy - big_r).powi(2) + q.z * q.z).sqrt();
            let ring_angle = q.y.atan2(q.x);
            let on_arc = centre + big_r * Vec3::new(ring_angle.cos(), ring_angle.sin(), 0.0);
            let out = (posed.positions[v] - on_arc).normalize();
            worst.0 = worst.0.max((tube - r).abs());
            worst.1 = worst.1.max((ring_angle - s / big_r).abs());
            worst.2 = worst.2.max((posed.normals[v] - out).length());
        }
        assert!(
            worst.0 < 1e-5 * big_r,
            "t = {t}: off the torus by {}",
            worst.0
        );
        assert!(
            worst.1 < 1e-5,
            "t = {t}: ring planes off by {} rad",
            worst.1
        );
        assert!(worst.2 < 1e-4, "t = {t}: normals off by {}", worst.2);
        // The last ring is at the bend angle.
        let last = posed
            .positions
            .iter()
            .map(|p| (p.y).atan2(p.x - centre.x))
            .fold(f32::MIN, f32::max);
        assert!(
            (last - angle).abs() < 1e-4,
            "t = {t}: ends at {last}, not {angle}"
        );
    }
}

/// Curvature of the bent tube against the torus: `1/r` along the meridian and
/// `cos φ / (ρ + r cos φ)` along the parallel (φ measured from the outer equator), on
/// the outer half, away from the open ends.
#[test]
fn bent_tube_curvature_is_the_torus_curvature() {
    use npr_geometry::{CurvatureField, CurvatureOptions, Topology};
    let (r, rho, theta) = (0.4f32, 2.0f32, std::f32::consts::PI);
    let m = generate::bent_tube(r, rho, theta, 48, 96);
    let clip = &m.rig.clips()[0];
    let posed = m.rig.pose_mesh(&m.rig.sample(clip, 1.0));
    let topo = Topology::new(&weld(&posed));
    let field = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let centre = Vec3::new(-rho, 0.0, 0.0);
    let (mut checked, mut worst_max, mut worst_min) = (0, 0.0f32, 0.0f32);
    for (v, p) in topo.positions.iter().enumerate() {
        let q = *p - centre;
        let a = q.y.atan2(q.x);
        let rxy = (q.x * q.x + q.y * q.y).sqrt();
        let cos_phi = (rxy - rho) / r;
        if !(a > 0.2 * theta && a < 0.8 * theta && cos_phi > 0.2) {
            continue;
        }
        checked += 1;
        worst_max = worst_max.max((field.kappa_max[v] - 1.0 / r).abs() * r);
        let k_par = cos_phi / (rho + r * cos_phi);
        worst_min = worst_min.max((field.kappa_min[v] - k_par).abs() * r);
    }
    assert!(checked > 100);
    assert!(
        worst_max < 0.03,
        "k_max off 1/r by {worst_max} (relative to 1/r)"
    );
    assert!(
        worst_min < 0.03,
        "k_min off the torus by {worst_min} (relative to 1/r)"
    );
}

#[test]
fn stretched_sphere_is_the_ellipsoid() {
    let (a, b, c) = (2.0f32, 1.2f32, 0.8f32);
    let m = generate::stretched_sphere(a, b, c, 6);
    let clip = &m.rig.clips()[0];
    let posed = m.rig.pose_mesh(&m.rig.sample(clip, 1.0));
    let centre = Vec3::new(0.0, 2.0, 0.0);
    let reference = generate::ellipsoid(a, b, c, 6);
    assert_eq!(posed.vertex_count(), reference.vertex_count());
    for v in 0..posed.vertex_count() {
        let p = posed.positions[v] - centre;
        let f = (p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2);
        assert!((f - 1.0).abs() < 1e-5, "vertex {v}: F = {f}");
        assert!((p - reference.positions[v]).length() < 1e-5);
        let grad = Vec3::new(p.x / (a * a), p.y / (b * b), p.z / (c * c)).normalize();
        assert!((posed.normals[v] - grad).length() < 1e-4, "vertex {v}");
    }
    // Halfway the scale is (1.5, 1.1, 0.9).
    let half = m.rig.pose_mesh(&m.rig.sample(clip, 0.5));
    for (p, q) in half.positions.iter().zip(&m.mesh.positions) {
        let want = (*q - centre) * Vec3::new(1.5, 1.1, 0.9) + centre;
        assert!((*p - want).length() < 1e-5);
    }
}

#[test]
fn twisted_bar_wraps_like_a_candy_and_stays_finite() {
    let (width, length) = (0.5f32, 4.0f32);
    let m = generate::twisted_bar(width, length, 16);
    let clip = &m.rig.clips()[0];
    let half = 0.5 * length;
    let circumradius = width * std::f32::consts::FRAC_1_SQRT_2;
    for (t, mid_scale) in [(0.5, std::f32::consts::FRAC_1_SQRT_2), (1.0, 0.0)] {
        let posed = m.rig.pose_mesh(&m.rig.sample(clip, t));
        posed.validate().unwrap();
        assert_eq!(posed.indices, m.mesh.indices);
        assert_eq!(
            weld(&posed).render_to_welded,
            weld(&m.mesh).render_to_welded
        );
        let turn = glam::Quat::from_rotation_y((180.0 * t).to_radians());
        let mut seen = [0usize; 3];
        for (p, q) in posed.positions.iter().zip(&m.mesh.positions) {
            seen[usize::from(q.y != half) + usize::from(q.y.abs() < 1e-6)] += 1;
            if q.y == half {
                assert!((*p - turn * *q).length() < 1e-5, "top {q} → {p}");
            } else if q.y == -half {
                assert!((*p - *q).length() < 1e-6, "bottom {q} → {p}");
            } else if q.y.abs() < 1e-6 && (q.x != 0.0 || q.z != 0.0) {
                // Halfway along, weights ½ and ½: the blend ½ (I + R) scales the
                // cross-section by cos(angle / 2): 0.707 at 90°, 0 at 180°.
                let radial = Vec3::new(p.x, 0.0, p.z).length();
                assert!(
                    (radial - mid_scale * circumradius).abs() < 1e-5,
                    "mid {q} → {p}"
                );
            }
        }
        // Top vertices, others, and a middle ring were all there to check.
        assert!(seen.iter().all(|&k| k >= 4), "{seen:?}");
    }
}

#[test]
fn joints_of_a_type_gltf_forbids_are_errors() {
    let tri = Tri {
        joints_type: 5126,
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "attribute-type");
}

#[test]
fn channels_that_do_not_fit_their_target_are_errors() {
    // A rotation needs VEC4 outputs; the triangle's sampler has VEC3.
    let tri = Tri {
        path: "rotation",
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "output-width");
    // Node 2 has no mesh, so no morph targets to weigh.
    let tri = Tri {
        path: "weights",
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "morph-target");
}

#[test]
fn the_skinned_mesh_node_transform_is_ignored() {
    let plain = Tri::default().load().unwrap();
    let moved = Tri {
        mesh_node: r#","translation":[5,0,0],"scale":[2,2,2]"#,
        ..Tri::default()
    }
    .load()
    .unwrap();
    assert_eq!(moved.mesh.positions, plain.mesh.positions);
    assert!(
        moved
            .report
            .contains(&LoadNote::SkinnedTransformIgnored { instances: 1 }),
        "{:?}",
        moved.report
    );
    assert!(
        !plain
            .report
            .iter()
            .any(|n| matches!(n, LoadNote::SkinnedTransformIgnored { .. }))
    );
    // And in a pose: the joints alone place the vertices.
    let rig = moved.rig.as_ref().unwrap();
    let m = rig.pose_mesh(&rig.sample(&rig.clips()[0], 0.5));
    assert!((m.positions[1] - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn a_node_with_two_parents_is_an_error() {
    let tri = Tri {
        mesh_node: r#","children":[2]"#,
        ..Tri::default()
    };
    assert_eq!(animation_error(tri), "hierarchy");
}

#[test]
fn a_singular_node_matrix_loads() {
    // A zero-scale matrix (a hidden node) cannot be decomposed into TRS; it must still
    // load, and the rest pose keeps it exactly.
    let tri = Tri {
        mesh_node: r#","matrix":[0,0,0,0, 0,0,0,0, 0,0,0,0, 3,0,0,1]"#,
        ..Tri::default()
    };
    let loaded = tri.load().unwrap();
    let rig = loaded.rig.as_ref().unwrap();
    let m = rig.nodes()[0].matrix.unwrap();
    assert_eq!(rig.rest_pose().node_global(0), Some(m));
    check_bind_is_loaded(&loaded);
}

mod mutated {
    use super::*;
    use proptest::prelude::*;

    fn bytes(name: &str) -> Vec<u8> {
        std::fs::read(format!(
            "{}/../../fixtures/meshes/{name}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 600, ..ProptestConfig::default() })]

        /// Flipped bytes in the animated files (keys, weights, joints, matrices, JSON):
        /// loading and posing every clip give an error or a mesh, never a panic.
        #[test]
        fn mutated_animated_files_never_panic(
            which in 0..3usize,
            flips in proptest::collection::vec((any::<usize>(), 1..=255u8), 1..8),
        ) {
            let (name, format) = [
                ("Fox.glb", Format::Glb),
                ("SimpleSkin.gltf", Format::Gltf),
                ("Tri", Format::Gltf),
            ][which];
            let mut b = if name == "Tri" { Tri::default().gltf() } else { bytes(name) };
            let n = b.len();
            for &(i, x) in &flips {
                b[i % n] ^= x;
            }
            let result = std::panic::catch_unwind(|| {
                let loaded = io::load_bytes(&b, format)?;
                if let Some(rig) = &loaded.rig {
                    for clip in rig.clips() {
                        for t in [-1.0, 0.0, 0.37 * clip.duration(), clip.duration() + 1.0] {
                            let m = rig.pose_mesh(&rig.sample(clip, t));
                            assert_eq!(m.indices, loaded.mesh.indices);
                        }
                    }
                    let _ = rig.pose_mesh(&rig.bind_pose());
                }
                Ok::<_, io::LoadError>(())
            });
            prop_assert!(result.is_ok(), "panic on {name} after {flips:?}");
        }
    }
}

/// The curvature of the posed analytic rigs against the closed forms, as the effects
/// compute it on a pose: the median relative error of κ_max and κ_min at most 2 % and the
/// median angle of the direction of maximum curvature at most 2°, on the bent tube at its
/// key (a torus section; away from its open ends) and on the sphere stretched into an
/// ellipsoid (where its principal curvatures differ by at least 10 %).
#[test]
fn posed_rigs_have_the_analytic_curvature() {
    use npr_geometry::{CurvatureField, CurvatureOptions, analytic, line_angle_deg};
    let median = |mut v: Vec<f64>| {
        assert!(v.len() > 50, "{} samples", v.len());
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let check = |name: &str,
                 posed: &npr_geometry::Mesh,
                 exact: &dyn Fn(Vec3) -> Option<analytic::Principal>| {
        let (_, topo, field) = CurvatureField::for_mesh(posed, &CurvatureOptions::default());
        let (mut errors, mut angles) = (Vec::new(), Vec::new());
        for (v, p) in topo.positions.iter().enumerate() {
            let Some(e) = exact(*p) else { continue };
            if !field.valid[v] {
                continue;
            }
            let scale = e.kappa_max.abs().max(e.kappa_min.abs());
            errors.push((f64::from(field.kappa_max[v]) - e.kappa_max).abs() / scale);
            errors.push((f64::from(field.kappa_min[v]) - e.kappa_min).abs() / scale);
            if (e.kappa_max - e.kappa_min).abs() >= 0.1 * scale {
                if let Some(a) = line_angle_deg(
                    field.dir_kappa_max[v],
                    e.dir_kappa_max.as_vec3(),
                    field.normal[v],
                ) {
                    angles.push(a);
                }
            }
        }
        let (err, angle) = (median(errors), median(angles));
        eprintln!("{name}: median curvature error {err:.4}, direction {angle:.3}°");
        assert!(err <= 0.02, "{name}: median curvature error {err}");
        assert!(angle <= 2.0, "{name}: median direction error {angle}°");
    };
    // The bent tube: a torus section about the z axis through (−ρ, 0, 0); analytic::torus
    // is about y through the origin, so points are turned into its frame.
    let (r, rho, theta) = (0.4f32, 2.0f32, std::f32::consts::PI);
    let m = generate::bent_tube(r, rho, theta, 48, 96);
    let posed = m.rig.pose_mesh(&m.rig.sample(&m.rig.clips()[0], 1.0));
    let to_torus = |p: Vec3| {
        let q = p - Vec3::new(-rho, 0.0, 0.0);
        Vec3::new(q.x, q.z, q.y)
    };
    let from_torus = |d: glam::DVec3| glam::DVec3::new(d.x, d.z, d.y);
    check("bent tube", &posed, &|p| {
        let q = to_torus(p);
        let a = q.z.atan2(q.x);
        (a > 0.2 * theta && a < 0.8 * theta).then(|| {
            let e = analytic::torus(q, f64::from(rho), f64::from(r));
            analytic::Principal {
                dir_kappa_max: from_torus(e.dir_kappa_max),
                ..e
            }
        })
    });
    let (a, b, c) = (2.0f32, 1.2f32, 0.8f32);
    let m = generate::stretched_sphere(a, b, c, 24);
    let posed = m.rig.pose_mesh(&m.rig.sample(&m.rig.clips()[0], 1.0));
    let centre = Vec3::new(0.0, 2.0, 0.0);
    check("stretched sphere", &posed, &|p| {
        Some(analytic::ellipsoid(
            p - centre,
            f64::from(a),
            f64::from(b),
            f64::from(c),
        ))
    });
}

/// The sway rig on any mesh: the rest pose is the mesh, the lower third does not move,
/// the top turns by the clip's 15° about the middle joint, and posing stays finite.
#[test]
fn a_swaying_rig_holds_its_base_and_leans_its_top() {
    let mesh = generate::icosphere(3, 1.0);
    let m = generate::swaying(mesh.clone());
    let clip = &m.rig.clips()[0];
    let rest = m.rig.pose_mesh(&m.rig.sample(clip, 0.0));
    for (p, q) in rest.positions.iter().zip(&mesh.positions) {
        assert!((*p - *q).length() < 1e-6, "rest {q} → {p}");
    }
    let leaned = m.rig.pose_mesh(&m.rig.sample(clip, 0.5));
    leaned.validate().unwrap();
    let turn = glam::Quat::from_rotation_z(15f32.to_radians());
    let (mut base, mut top) = (0, 0);
    for (p, q) in leaned.positions.iter().zip(&mesh.positions) {
        if q.y < -1.0 / 3.0 - 1e-4 {
            assert!((*p - *q).length() < 1e-6, "base {q} → {p}");
            base += 1;
        } else if q.y > 1.0 / 3.0 + 1e-4 {
            assert!((*p - turn * *q).length() < 1e-5, "top {q} → {p}");
            top += 1;
        }
    }
    assert!(base > 10 && top > 10, "{base} base and {top} top vertices");
}
