//! Topology tests: invariants on clean and odd meshes, and the build against a plain
//! construction from the definitions.

use super::*;
use crate::{generate, weld};
use glam::DVec3;
#[test]
fn closed_torus_is_manifold_with_chi_zero() {
    let t = Topology::new(&weld(&generate::torus(2.0, 0.7, 24, 10)));
    assert_eq!(t.euler_characteristic(), 0);
    assert!((0..t.edges.len()).all(|e| t.edge_kind(e) == EdgeKind::Interior));
    assert!(t.dihedral.iter().all(|&b| b.abs() < 1.0));
    // Outer equator bends convexly, so most dihedral angles are positive.
    let pos = t.dihedral.iter().filter(|&&b| b > 0.0).count();
    assert!(pos > t.edges.len() / 2);
    assert!((0..t.face_count()).all(|f| t.face_neighbours(f).len() == 3));
}

#[test]
fn sphere_dihedrals_are_convex() {
    let t = Topology::new(&weld(&generate::icosphere(2, 1.0)));
    assert_eq!(t.euler_characteristic(), 2);
    assert!(t.dihedral.iter().all(|&b| b > 0.0));
}

#[test]
fn odd_cases_are_values() {
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::NEG_Y,
        Vec3::ONE,
    ];
    // Fan of three faces on edge 0-1, a duplicate face, a degenerate face, an
    // out-of-range face, and an isolated vertex 5.
    let tris = vec![
        [0, 1, 2],
        [1, 0, 3],
        [0, 1, 4],
        [0, 1, 2],
        [2, 2, 3],
        [0, 1, 99],
    ];
    let t = Topology::from_parts(p, tris);
    let e01 = t.edges.iter().position(|&e| e == [0, 1]).unwrap();
    assert_eq!(t.edge_kind(e01), EdgeKind::NonManifold);
    assert_eq!(t.dihedral[e01], 0.0);
    assert!(t.is_degenerate(4));
    assert!(t.is_degenerate(5));
    assert!(t.is_isolated(5));
    assert!(t.edge_face_normals(e01).is_none());
}

/// The chunked parallel edge build against a plain ordered-map reference: same
/// edges in the same order, same faces per edge, same edge per face corner; and the
/// dihedral angle's orientation test on a face flipped against its neighbours.
#[test]
fn edges_match_ordered_map_reference() {
    use std::collections::BTreeMap;
    let mut w = weld(&generate::icosphere(3, 1.0));
    // Add odd faces: a duplicate, a repeated vertex, an out-of-range index.
    let dup = w.indices[7];
    w.indices
        .extend_from_slice(&[dup, [0, 0, 5], [1, 2, 1 << 30]]);
    let t = Topology::new(&w);
    let nv = w.positions.len() as u32;
    let mut map: BTreeMap<(u32, u32), Vec<(usize, usize)>> = BTreeMap::new();
    for (f, tri) in w.indices.iter().enumerate() {
        if tri.iter().any(|&i| i >= nv) {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                map.entry((a.min(b), a.max(b))).or_default().push((f, k));
            }
        }
    }
    let want: Vec<[u32; 2]> = map.keys().map(|&(a, b)| [a, b]).collect();
    assert_eq!(t.edges, want);
    for (e, uses) in map.values().enumerate() {
        let mut got = t.edge_faces(e).to_vec();
        let mut exp: Vec<u32> = uses.iter().map(|&(f, _)| f as u32).collect();
        got.sort_unstable();
        exp.sort_unstable();
        assert_eq!(got, exp, "edge {e}");
        for &(f, k) in uses {
            assert_eq!(t.face_edges[f][k], e as u32);
        }
    }
    // Direction per half-edge corner: a flipped face makes its three edges
    // inconsistent (β = 0); every other interior edge of the sphere is convex.
    let mut flipped = weld(&generate::icosphere(3, 1.0));
    let [a, b, c] = flipped.indices[11];
    flipped.indices[11] = [b, a, c];
    let tf = Topology::new(&flipped);
    assert_eq!(
        (0..tf.edges.len())
            .filter(|&e| tf.edge_kind(e) == EdgeKind::Inconsistent)
            .count(),
        3
    );
    for e in 0..tf.edges.len() {
        let interior = tf.edge_kind(e) == EdgeKind::Interior;
        let sound = tf
            .edge_faces(e)
            .iter()
            .all(|&f| !tf.is_degenerate(f as usize));
        assert_eq!(tf.dihedral[e] > 0.0, interior && sound, "edge {e}");
    }
    let lens: f64 = want
        .iter()
        .map(|&[a, b]| (w.positions[b as usize] - w.positions[a as usize]).length() as f64)
        .sum();
    let mean = lens / want.len() as f64;
    assert!((f64::from(t.mean_edge_length) - mean).abs() < 1e-6 * mean);
}

/// Every array of two topologies, floats by their bits.
fn assert_same(a: &Topology, b: &Topology, name: &str) {
    let v3 = |v: &[Vec3]| -> Vec<[u32; 3]> {
        v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    };
    let f1 = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
    assert_eq!(a.positions.len(), b.positions.len(), "{name}");
    assert_eq!(a.triangles, b.triangles, "{name}");
    assert_eq!(v3(&a.face_normals), v3(&b.face_normals), "{name}");
    assert_eq!(f1(&a.face_areas), f1(&b.face_areas), "{name}");
    assert_eq!(a.edges, b.edges, "{name}");
    assert_eq!(a.face_edges, b.face_edges, "{name}");
    assert_eq!(f1(&a.dihedral), f1(&b.dihedral), "{name}");
    assert_eq!(v3(&a.vertex_normals), v3(&b.vertex_normals), "{name}");
    assert_eq!(
        a.mean_edge_length.to_bits(),
        b.mean_edge_length.to_bits(),
        "{name}"
    );
    assert_eq!(a.edge_face_offsets, b.edge_face_offsets, "{name}");
    assert_eq!(a.edge_faces, b.edge_faces, "{name}");
    assert_eq!(a.vertex_face_offsets, b.vertex_face_offsets, "{name}");
    assert_eq!(a.vertex_faces, b.vertex_faces, "{name}");
    assert_eq!(a.face_adj_offsets, b.face_adj_offsets, "{name}");
    assert_eq!(a.face_adj, b.face_adj, "{name}");
}

/// A named test mesh: its positions and triangles.
type NamedMesh = (&'static str, Vec<Vec3>, Vec<[u32; 3]>);

/// The odd meshes the build must get right: a jittered, noisy torus with a hole, a
/// fin, a duplicate face, a flipped face, faces with a repeated vertex and an
/// out-of-range index and an isolated vertex; the scanned bunny; and a mesh smaller
/// than the build's chunk count.
fn odd_meshes() -> Vec<NamedMesh> {
    let mesh = generate::displace_along_normals(
        &generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5),
        0.01,
        9,
    );
    let mut w = weld(&mesh);
    w.indices
        .retain(|t| t.iter().all(|&i| !(200..260).contains(&i)));
    let [a, b, c] = w.indices[500];
    w.indices[500] = [b, a, c];
    let dup = w.indices[900];
    let fin = [w.indices[1000][0], w.indices[1000][1], 3000];
    w.indices
        .extend_from_slice(&[dup, fin, [7, 7, 8], [9, 10, 9], [1, 2, 1 << 30]]);
    w.positions.push(Vec3::splat(9.0));
    let bunny = crate::load_obj(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/meshes/stanford-bunny.obj"
    ))
    .unwrap();
    let wb = weld(&bunny);
    vec![
        ("torus", w.positions, w.indices),
        ("bunny", wb.positions, wb.indices),
        (
            "tetrahedron",
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]],
        ),
    ]
}

/// A mesh's relations written plainly from the definitions: every edge's uses (face,
/// corner starting the edge) in face and corner order, over ordered maps, and every
/// vertex's faces.
struct Plain<'a> {
    name: &'a str,
    positions: &'a [Vec3],
    triangles: &'a [[u32; 3]],
    edges: Vec<[u32; 2]>,
    uses: Vec<Vec<(usize, usize)>>,
    vertex_faces: Vec<Vec<u32>>,
}

impl<'a> Plain<'a> {
    fn new(name: &'a str, positions: &'a [Vec3], triangles: &'a [[u32; 3]]) -> Self {
        use std::collections::BTreeMap;
        let nv = positions.len();
        let mut uses: BTreeMap<[u32; 2], Vec<(usize, usize)>> = BTreeMap::new();
        let mut vertex_faces = vec![Vec::new(); nv];
        for (f, tri) in triangles.iter().enumerate() {
            if !tri.iter().all(|&i| (i as usize) < nv) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if a != b {
                    uses.entry([a.min(b), a.max(b)]).or_default().push((f, k));
                }
                let around: &mut Vec<u32> = &mut vertex_faces[tri[k] as usize];
                if !around.contains(&(f as u32)) {
                    around.push(f as u32);
                }
            }
        }
        Self {
            name,
            positions,
            triangles,
            edges: uses.keys().copied().collect(),
            uses: uses.into_values().collect(),
            vertex_faces,
        }
    }

    fn valid(&self, tri: &[u32; 3]) -> bool {
        tri.iter().all(|&i| (i as usize) < self.positions.len())
    }

    /// Twice the area vector of face `f` (f64).
    fn cross(&self, f: usize) -> DVec3 {
        let [a, b, c] = self.triangles[f].map(|i| self.positions[i as usize].as_dvec3());
        (b - a).cross(c - a)
    }

    /// The same edges in order, faces per edge, edge per corner, faces per vertex, and
    /// neighbours per face.
    fn check_relations(&self, t: &Topology) {
        let (name, edges, tris) = (self.name, &self.edges, self.triangles);
        assert_eq!(&t.edges, edges, "{name}: edges");
        for (e, used) in self.uses.iter().enumerate() {
            let faces: Vec<u32> = used.iter().map(|&(f, _)| f as u32).collect();
            assert_eq!(
                t.edge_faces(e),
                faces.as_slice(),
                "{name}: faces of edge {e}"
            );
        }
        for (f, tri) in tris.iter().enumerate() {
            let want = [0, 1, 2].map(|k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if !self.valid(tri) || a == b {
                    NO_EDGE
                } else {
                    edges.binary_search(&[a.min(b), a.max(b)]).unwrap() as u32
                }
            });
            assert_eq!(t.face_edges[f], want, "{name}: corner edges of face {f}");
            let neighbours: Vec<u32> = want
                .iter()
                .filter(|&&e| e != NO_EDGE)
                .flat_map(|&e| t.edge_faces(e as usize).iter().copied())
                .filter(|&g| g != f as u32)
                .collect();
            assert_eq!(
                t.face_neighbours(f),
                neighbours.as_slice(),
                "{name}: face {f}"
            );
        }
        for (v, faces) in self.vertex_faces.iter().enumerate() {
            assert_eq!(
                t.vertex_faces(v),
                faces.as_slice(),
                "{name}: faces of vertex {v}"
            );
            assert_eq!(t.is_isolated(v), faces.is_empty(), "{name}: vertex {v}");
        }
    }

    /// Face normals and areas from the f64 cross product (degenerate faces zero), and
    /// vertex normals as the area-weighted sum of the faces' (`Z` without any).
    fn check_normals(&self, t: &Topology) {
        let (name, p, tris) = (self.name, self.positions, self.triangles);
        let cross = |f: usize| self.cross(f);
        for (f, tri) in tris.iter().enumerate() {
            let repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
            if !self.valid(tri) || repeated {
                assert!(t.is_degenerate(f), "{name}: face {f}");
                assert_eq!(t.face_normals[f], Vec3::ZERO, "{name}: face {f}");
                continue;
            }
            let c = cross(f);
            if t.is_degenerate(f) {
                let [a, b, d] = tri.map(|i| p[i as usize].as_dvec3());
                let scale = (b - a).length_squared().max((d - a).length_squared());
                assert!(!(c.length() > 1e-9 * scale), "{name}: face {f} has area");
                assert_eq!(t.face_normals[f], Vec3::ZERO, "{name}: face {f}");
                continue;
            }
            let area = 0.5 * c.length();
            assert!(
                (f64::from(t.face_areas[f]) - area).abs() <= 1e-6 * area,
                "{name}: area of face {f}"
            );
            let n = (c / c.length()).as_vec3();
            assert!(
                (t.face_normals[f] - n).length() < 1e-6,
                "{name}: normal of face {f}"
            );
        }
        for (v, faces) in self.vertex_faces.iter().enumerate() {
            let sum: DVec3 = faces
                .iter()
                .filter(|&&f| !t.is_degenerate(f as usize))
                .map(|&f| cross(f as usize))
                .sum();
            let scale: f64 = faces
                .iter()
                .filter(|&&f| !t.is_degenerate(f as usize))
                .map(|&f| cross(f as usize).length())
                .sum();
            if scale == 0.0 {
                assert_eq!(t.vertex_normals[v], Vec3::Z, "{name}: vertex {v}");
            } else if sum.length() > 1e-3 * scale {
                let n = sum.normalize().as_vec3();
                assert!(
                    (t.vertex_normals[v] - n).length() < 1e-5,
                    "{name}: normal of vertex {v}"
                );
            }
        }
    }

    /// Edge kinds and signed dihedral angles (convex positive, 0 off interior edges),
    /// and the mean edge length.
    fn check_edges(&self, t: &Topology) {
        let (name, p, tris, edges) = (self.name, self.positions, self.triangles, &self.edges);
        for (e, used) in self.uses.iter().enumerate() {
            let kind = match used.as_slice() {
                [_] => EdgeKind::Boundary,
                &[(f, k), (g, m)] if tris[f][k] != tris[g][m] => EdgeKind::Interior,
                [_, _] => EdgeKind::Inconsistent,
                _ => EdgeKind::NonManifold,
            };
            assert_eq!(t.edge_kind(e), kind, "{name}: kind of edge {e}");
            let want = match used.as_slice() {
                &[(f, k), (g, _)]
                    if kind == EdgeKind::Interior && !t.is_degenerate(f) && !t.is_degenerate(g) =>
                {
                    let (n1, n2) = (self.cross(f).normalize(), self.cross(g).normalize());
                    // The edge as face f runs it.
                    let (a, b) = (tris[f][k], tris[f][(k + 1) % 3]);
                    let dir = (p[b as usize].as_dvec3() - p[a as usize].as_dvec3()).normalize();
                    n1.cross(n2).dot(dir).atan2(n1.dot(n2))
                }
                _ => 0.0,
            };
            assert!(
                (f64::from(t.dihedral[e]) - want).abs() < 1e-5,
                "{name}: dihedral of edge {e}: {} vs {want}",
                t.dihedral[e]
            );
        }
        let lengths: Vec<f64> = edges
            .iter()
            .map(|&[a, b]| (p[b as usize].as_dvec3() - p[a as usize].as_dvec3()).length())
            .filter(|l| l.is_finite())
            .collect();
        let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
        assert!(
            (f64::from(t.mean_edge_length) - mean).abs() <= 1e-6 * mean,
            "{name}: mean edge length"
        );
    }
}

/// The build against the topology written plainly from its definitions ([`Plain`]), on
/// [`odd_meshes`]: the same edges, in order; each edge's faces in face and corner order;
/// each corner's edge; each vertex's faces; each face's neighbours; the edge kinds; and
/// normals, areas, dihedral angles and the mean edge length to float precision.
#[test]
fn matches_a_plain_construction() {
    for (name, p, tris) in odd_meshes() {
        let t = Topology::from_parts(p.clone(), tris.clone());
        assert_eq!(
            (t.vertex_count(), t.face_count()),
            (p.len(), tris.len()),
            "{name}"
        );
        let plain = Plain::new(name, &p, &tris);
        plain.check_relations(&t);
        plain.check_normals(&t);
        plain.check_edges(&t);
    }
}

/// Invariants of the relations: a face is among the faces of each of its edges, face
/// adjacency is symmetric (counted with multiplicity), and a closed manifold mesh has
/// two faces per edge and `χ = 2 − 2g`.
#[test]
fn relations_are_consistent() {
    for (name, p, tris) in odd_meshes() {
        let t = Topology::from_parts(p, tris);
        for f in 0..t.face_count() {
            for &e in t.face_edges[f].iter().filter(|&&e| e != NO_EDGE) {
                assert!(
                    t.edge_faces(e as usize).contains(&(f as u32)),
                    "{name}: face {f}"
                );
            }
            for &g in t.face_neighbours(f) {
                let count =
                    |a: usize, b: u32| t.face_neighbours(a).iter().filter(|&&x| x == b).count();
                assert_eq!(
                    count(f, g),
                    count(g as usize, f as u32),
                    "{name}: faces {f}, {g}"
                );
            }
        }
    }
    let closed = [
        (
            "torus",
            weld(&generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5)),
            0,
        ),
        ("sphere", weld(&generate::icosphere(3, 1.0)), 2),
        ("knot", weld(&generate::paper_knot()), 0),
    ];
    for (name, w, chi) in closed {
        let t = Topology::new(&w);
        assert_eq!(t.euler_characteristic(), chi, "{name}");
        assert_eq!(2 * t.edges.len(), 3 * t.face_count(), "{name}");
        assert!(
            (0..t.edges.len()).all(|e| t.edge_kind(e) == EdgeKind::Interior),
            "{name}"
        );
    }
}

/// The parallel build gives the same topology, bit for bit, on one thread and on
/// several.
#[test]
fn any_thread_count_builds_the_same() {
    for (name, p, tris) in odd_meshes() {
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| Topology::from_parts(p.clone(), tris.clone()))
        };
        let one = build(1);
        for threads in [2, 3] {
            assert_same(&build(threads), &one, name);
        }
    }
}
