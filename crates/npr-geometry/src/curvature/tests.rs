//! Curvature tests on the private parts: the field at a scale, the closed-form 2×2
//! eigen-decomposition, and the corrected form's hot loop against a plain reference.

use super::eigen::{sym2_eigen, tangent_axes};
use super::*;
use crate::rng::XorShift64;
use crate::topology::NO_EDGE;
use nalgebra::{Matrix2, Matrix3, SymmetricEigen};

/// Largest angle (degrees) between a field's normal and the exact sphere normal.
fn worst_normal_deg(field: &CurvatureField, topo: &Topology) -> f32 {
    field
        .normal
        .iter()
        .zip(&topo.positions)
        .map(|(n, p)| n.dot(p.normalize()).clamp(-1.0, 1.0).acos().to_degrees())
        .fold(0.0, f32::max)
}

#[test]
fn a_scale_smooths_bumps_and_keeps_a_sphere() {
    let (_, topo, field) =
        CurvatureField::for_mesh(&crate::generate::icosphere(4, 1.0), &Default::default());
    // A sphere keeps its normals and its curvature (1/R) at a tenth of its radius.
    let scaled = field.at_scale(&topo, 0.1);
    assert!(worst_normal_deg(&scaled, &topo) < 0.5);
    let mean = scaled.kappa_max.iter().sum::<f32>() / scaled.len() as f32;
    assert!((mean - 1.0).abs() < 0.05, "κ_max {mean}");
    // Bumps of 1 % of the radius: their normals turn by degrees, and the scale takes
    // most of that away.
    let bumpy =
        crate::generate::displace_along_normals(&crate::generate::icosphere(4, 1.0), 0.01, 3);
    let (_, topo, field) = CurvatureField::for_mesh(&bumpy, &Default::default());
    let raw = worst_normal_deg(&field, &topo);
    let smooth = worst_normal_deg(&field.at_scale(&topo, 0.1), &topo);
    assert!(
        raw > 5.0 && smooth < 0.4 * raw,
        "raw {raw}°, at scale {smooth}°"
    );
    // Scale 0 is the field itself.
    assert_eq!(field.at_scale(&topo, 0.0), field);
}

#[test]
fn closed_form_2x2_matches_nalgebra() {
    let mut rng = XorShift64::new(3);
    for k in 0..2000 {
        let (a, mut b, c) = (rng.next_signed(), rng.next_signed(), rng.next_signed());
        if k % 10 == 0 {
            b = 0.0;
        }
        let (hi, lo, u) = sym2_eigen(a, b, c);
        let e = SymmetricEigen::new(Matrix2::new(a, b, b, c));
        let (nh, nl) = (e.eigenvalues.max(), e.eigenvalues.min());
        assert!((hi - nh).abs() < 1e-12 && (lo - nl).abs() < 1e-12);
        // u is an eigenvector of hi.
        let m = Matrix2::new(a, b, b, c) * nalgebra::Vector2::new(u[0], u[1]);
        assert!((m[0] - hi * u[0]).abs() < 1e-12 && (m[1] - hi * u[1]).abs() < 1e-12);
        assert!((u[0].hypot(u[1]) - 1.0).abs() < 1e-12);
    }
}

/// The corrected form written plainly, as a reference for the optimised hot loop:
/// `T_f` in f64 straight from the definition (share `A_f / Σ A_g` of each edge's
/// `β |e| ē ēᵀ`), a depth-first ball growth with a `Vec` stack and a `HashSet` of
/// visited faces (same push order as [`corrected_axes`]), and the same f32
/// accumulation order, so the results should agree to the bit.
fn corrected_reference(topo: &Topology, r: f32) -> Vec<PrincipalAxes> {
    use std::collections::HashSet;
    let tf = reference_faces(topo);
    (0..topo.vertex_count())
        .map(|v| {
            let pv = topo.positions[v];
            let n = topo.vertex_normals[v];
            if topo.is_isolated(v) {
                return invalid(n);
            }
            let (mut acc, mut area) = ([0f32; 6], 0f32);
            let mut seen: HashSet<u32> = topo.vertex_faces(v).iter().copied().collect();
            let mut stack = topo.vertex_faces(v).to_vec();
            while let Some(f) = stack.pop() {
                let ([cx, cy, cz, rad], t, a) = tf[f as usize];
                let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
                let d2 = dx * dx + dy * dy + dz * dz;
                if d2 < r * r {
                    let q = 1.0 - d2 * (1.0 / (r * r));
                    let w = q * q;
                    for (x, y) in acc.iter_mut().zip(t) {
                        *x += w * y;
                    }
                    area += w * a;
                } else if !(rad > 0.5 * r && d2 < (r + rad) * (r + rad)) {
                    continue;
                }
                for &g in topo.face_neighbours(f as usize) {
                    if seen.insert(g) {
                        stack.push(g);
                    }
                }
            }
            axes_of(acc, area, n)
        })
        .collect()
}

/// The corrected form's eigen-analysis of a summed `Σ w T_f` and `Σ w A_f`.
fn axes_of(acc: [f32; 6], area: f32, n: Vec3) -> PrincipalAxes {
    let area = f64::from(area);
    if !(area > 0.0) {
        return invalid(n);
    }
    let t = acc.map(|x| f64::from(x) / area);
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
    tangent_axes(&m, n.as_dvec3()).unwrap_or_else(|| invalid(n))
}

/// Per face: (centroid, bounding radius), `T_f` and area, in f64 from the definition.
fn reference_faces(topo: &Topology) -> Vec<([f32; 4], [f32; 6], f32)> {
    topo.triangles
        .iter()
        .enumerate()
        .map(|(f, t)| {
            let p = t.map(|i| topo.positions[i as usize].as_dvec3());
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let rad = p.iter().map(|q| (*q - c).length()).fold(0.0, f64::max);
            let area = f64::from(topo.face_areas[f]);
            let mut m = [0f64; 6];
            for k in 0..3 {
                let e = topo.face_edges[f][k];
                if area == 0.0 || e == NO_EDGE || topo.dihedral[e as usize] == 0.0 {
                    continue;
                }
                let beta = f64::from(topo.dihedral[e as usize]);
                let total: f64 = topo
                    .edge_faces(e as usize)
                    .iter()
                    .map(|&g| f64::from(topo.face_areas[g as usize]))
                    .sum();
                let d = p[(k + 1) % 3] - p[k];
                let s = area / total * beta / d.length();
                let dd = [
                    d.x * d.x,
                    d.x * d.y,
                    d.x * d.z,
                    d.y * d.y,
                    d.y * d.z,
                    d.z * d.z,
                ];
                for (a, q) in m.iter_mut().zip(dd) {
                    *a += s * q;
                }
            }
            let c = c.as_vec3();
            (
                [c.x, c.y, c.z, rad as f32],
                m.map(|x| x as f32),
                area as f32,
            )
        })
        .collect()
}

/// The optimised corrected form against [`corrected_reference`] on irregular meshes:
/// a jittered, noisy torus with a hole cut out, a few large faces (the "large
/// against the ball" path), a fin and a duplicate face (non-manifold edges), and the
/// scanned bunny (holes, uneven triangles).
#[test]
fn corrected_matches_plain_reference() {
    use crate::generate;
    let mut mesh = generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5);
    mesh = generate::displace_along_normals(&mesh, 0.01, 9);
    let mut w = weld(&mesh);
    w.indices
        .retain(|t| t.iter().all(|&i| !(200..260).contains(&i)));
    // Large triangles spanning the torus, sharing vertices with it.
    w.indices
        .extend_from_slice(&[[0, 1500, 3000], [10, 2000, 3500]]);
    let bunny = crate::load_obj(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/meshes/stanford-bunny.obj"
    ))
    .unwrap();
    for (name, topo) in [
        ("torus", Topology::new(&w)),
        ("bunny", Topology::new(&weld(&bunny))),
    ] {
        let opts = CurvatureOptions::default();
        let got = CurvatureField::compute_at_scale(&topo, &opts);
        let want = corrected_reference(&topo, got.radius_world);
        let mut valid = 0;
        for (v, f) in want.iter().enumerate() {
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
            let close3 = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-6;
            assert_eq!(got.valid[v], f.valid, "{name} vertex {v}");
            assert!(close(got.kappa_max[v], f.kmax), "{name} vertex {v}");
            assert!(close(got.kappa_min[v], f.kmin), "{name} vertex {v}");
            assert!(close3(got.normal[v], f.n), "{name} vertex {v}");
            assert!(close3(got.dir_kappa_max[v], f.dmax), "{name} vertex {v}");
            assert!(close3(got.dir_kappa_min[v], f.dmin), "{name} vertex {v}");
            valid += usize::from(f.valid);
        }
        assert!(valid > want.len() * 9 / 10, "{name}: {valid} valid");
    }
}

/// The ball lists ([`CurvatureField::corrected_balls`]), summed with the corrected form's
/// weights in list order, give the corrected form's field on the same irregular meshes as
/// [`corrected_matches_plain_reference`]: they hold every face the walk weighs, in its order.
#[test]
fn ball_lists_reproduce_the_corrected_form() {
    use crate::generate;
    let mut mesh = generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5);
    mesh = generate::displace_along_normals(&mesh, 0.01, 9);
    let mut w = weld(&mesh);
    w.indices
        .retain(|t| t.iter().all(|&i| !(200..260).contains(&i)));
    w.indices
        .extend_from_slice(&[[0, 1500, 3000], [10, 2000, 3500]]);
    let topo = Topology::new(&w);
    let opts = CurvatureOptions::default();
    let got = CurvatureField::compute_at_scale(&topo, &opts);
    let r = got.radius_world;
    assert_eq!(opts.radius.world(&topo), r);
    let balls = CurvatureField::corrected_balls(&topo, r);
    assert_eq!(balls.offsets.len(), topo.vertex_count() + 1);
    let tf = reference_faces(&topo);
    let mut outside = 0;
    for v in 0..topo.vertex_count() {
        let pv = topo.positions[v];
        let list = balls.of(v);
        for f in topo.vertex_faces(v) {
            assert!(list.contains(f), "vertex {v}: own face {f} not listed");
        }
        let (mut acc, mut area) = ([0f32; 6], 0f32);
        for &f in list {
            let ([cx, cy, cz, _], t, a) = tf[f as usize];
            let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
            let d2 = dx * dx + dy * dy + dz * dz;
            if d2 < r * r {
                let q = 1.0 - d2 * (1.0 / (r * r));
                let w = q * q;
                for (x, y) in acc.iter_mut().zip(t) {
                    *x += w * y;
                }
                area += w * a;
            } else {
                outside += 1;
            }
        }
        let f = axes_of(acc, area, topo.vertex_normals[v]);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
        assert_eq!(got.valid[v], f.valid, "vertex {v}");
        assert!(close(got.kappa_max[v], f.kmax), "vertex {v}");
        assert!(close(got.kappa_min[v], f.kmin), "vertex {v}");
    }
    assert!(outside > 0, "the lists hold the ring around each ball too");
    assert!(
        CurvatureField::corrected_balls(&topo, f32::NAN)
            .faces
            .is_empty()
    );
}
