//! Analytic checks of the curvature field (Lee & Choi §2.2): sphere, cylinder,
//! torus, ellipsoid, plane; rigid motions and scaling; Gauss–Bonnet; bad meshes.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use glam::{DVec3, Mat4, Quat, Vec3};
use npr_geometry::analytic::{self, Principal};
use npr_geometry::stats::median;
use npr_geometry::{
    CurvatureField, CurvatureMethod, CurvatureOptions, CurvatureRadius, Mesh, Topology, generate,
    weld,
};
use proptest::prelude::*;

fn field(mesh: &Mesh) -> (Topology, CurvatureField) {
    let topo = Topology::new(&weld(mesh));
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    (topo, f)
}

/// Median errors (k_max %, k_min %, direction °) against `truth`, relative to `kref`,
/// over the vertices `keep` selects.
fn errors(
    topo: &Topology,
    f: &CurvatureField,
    kref: f64,
    keep: impl Fn(Vec3) -> bool,
    truth: impl Fn(Vec3) -> Principal,
) -> (f64, f64, f64) {
    let (mut ex, mut en, mut ed) = (vec![], vec![], vec![]);
    for v in 0..topo.vertex_count() {
        let p = topo.positions[v];
        if !keep(p) {
            continue;
        }
        assert!(f.valid[v], "vertex {v} invalid");
        let a = truth(p);
        ex.push((f64::from(f.kappa_max[v]) - a.kappa_max).abs() / kref * 100.0);
        en.push((f64::from(f.kappa_min[v]) - a.kappa_min).abs() / kref * 100.0);
        ed.push(analytic::axis_angle_deg(
            f.dir_kappa_max[v].as_dvec3(),
            a.dir_kappa_max,
        ));
    }
    assert!(!ex.is_empty());
    (median(ex), median(en), median(ed))
}

fn assert_frames(f: &CurvatureField) {
    for v in 0..f.len() {
        assert!(f.kappa_max[v].is_finite() && f.kappa_min[v].is_finite());
        assert!(f.normal[v].is_finite() && f.dir_kappa_max[v].is_finite());
        if f.valid[v] {
            assert!(f.kappa_max[v] >= f.kappa_min[v]);
            let n = f.dir_kappa_max[v].cross(f.dir_kappa_min[v]);
            assert!(
                n.distance(f.normal[v]) < 1e-4,
                "frame not right-handed at {v}"
            );
        }
    }
}

#[test]
fn sphere_curvatures_are_one_over_radius() {
    for radius in [0.5f32, 2.0] {
        let mesh = generate::icosphere(5, radius);
        let (topo, f) = field(&mesh);
        assert_frames(&f);
        let k = 1.0 / f64::from(radius);
        let (ex, en, _) = errors(
            &topo,
            &f,
            k,
            |_| true,
            |_| Principal {
                kappa_max: k,
                kappa_min: k,
                dir_kappa_max: DVec3::X,
            },
        );
        // Icosphere 10k k_max median ≤ 0.2 % (measured 0.16 %).
        assert!(ex < 0.2 && en < 0.2, "sphere errors {ex} {en} %");
        // Normals agree with the outward radial direction.
        for v in 0..topo.vertex_count() {
            assert!(f.normal[v].dot(topo.positions[v].normalize()) > 0.999);
        }
    }
}

#[test]
fn cylinder_interior_curvatures_and_direction() {
    let (r, h) = (0.5f32, 4.0f32);
    let mesh = generate::cylinder(r, h, 96, 120, false);
    let (topo, f) = field(&mesh);
    assert_frames(&f);
    let margin = f.radius_world + topo.mean_edge_length;
    let keep = |p: Vec3| p.y.abs() < h / 2.0 - margin;
    let (ex, en, ed) = errors(&topo, &f, 1.0 / f64::from(r), keep, |p| {
        analytic::cylinder(p, f64::from(r))
    });
    assert!(
        ex < 0.5 && en < 0.5 && ed < 0.5,
        "cylinder errors {ex} % {en} % {ed}°"
    );
}

#[test]
fn torus_meridian_parallel_and_signs() {
    let (big_r, r) = (2.0f32, 0.7f32);
    let (nu, nv) = generate::torus_segments_for(big_r, r, 10_000);
    let mesh = generate::torus(big_r, r, nu, nv);
    let (topo, f) = field(&mesh);
    assert_frames(&f);
    let (ex, en, ed) = errors(
        &topo,
        &f,
        1.0 / f64::from(r),
        |_| true,
        |p| analytic::torus(p, f64::from(big_r), f64::from(r)),
    );
    // Torus 10k k_max median ≤ 0.5 % of max |k|.
    assert!(
        ex < 0.5 && en < 1.0 && ed < 0.2,
        "torus errors {ex} % {en} % {ed}°"
    );
    // Inner side (saddle): k_min < 0; outer side: both positive.
    for v in 0..topo.vertex_count() {
        let p = topo.positions[v];
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        if rho < big_r - 0.8 * r {
            assert!(f.kappa_min[v] < 0.0 && f.kappa_max[v] > 0.0);
        }
        if rho > big_r + 0.5 * r {
            assert!(f.kappa_min[v] > 0.0);
        }
    }
}

#[test]
fn ellipsoid_matches_closed_form() {
    let (a, b, c) = (2.0f32, 1.2, 0.8);
    let mesh = generate::ellipsoid(a, b, c, 45);
    let (topo, f) = field(&mesh);
    assert_frames(&f);
    let kmax = topo
        .positions
        .iter()
        .map(|&p| analytic::ellipsoid(p, 2.0, 1.2, 0.8).kappa_max)
        .fold(0.0, f64::max);
    let (ex, en, _) = errors(
        &topo,
        &f,
        kmax,
        |_| true,
        |p| analytic::ellipsoid(p, 2.0, 1.2, 0.8),
    );
    assert!(ex < 0.3 && en < 0.3, "ellipsoid errors {ex} {en} %");
}

#[test]
fn plane_is_flat() {
    let mesh = generate::plane(2.0, 2.0, 40, 40);
    let (topo, f) = field(&mesh);
    assert_frames(&f);
    for v in 0..topo.vertex_count() {
        assert!(f.valid[v]);
        assert!(f.kappa_max[v].abs() < 1e-4 && f.kappa_min[v].abs() < 1e-4);
        assert!(f.normal[v].y > 0.999);
    }
}

#[test]
fn paper_and_clipped_forms_read_their_documented_bias() {
    // docs/results.md: on the 10k torus the paper's approximation of Eq. (1) reads k_max
    // high by 9.9 % of max |k| (median), the clipped-edge form by 1.7 %, the corrected
    // form by 0.13 %. Bands of ±0.5 pp (±0.1 pp for the corrected form) keep the methods
    // apart, so a silent swap fails.
    let (big_r, r) = (2.0f32, 0.7f32);
    let (nu, nv) = generate::torus_segments_for(big_r, r, 10_000);
    let topo = Topology::new(&weld(&generate::torus(big_r, r, nu, nv)));
    let kref = 1.0 / f64::from(r);
    for (method, expected_pct, band_pp) in [
        (CurvatureMethod::Paper, 9.9, 0.5),
        (CurvatureMethod::Clipped, 1.7, 0.5),
        (CurvatureMethod::Corrected, 0.13, 0.1),
    ] {
        let f = CurvatureField::compute(
            &topo,
            &CurvatureOptions {
                method,
                radius: CurvatureRadius::default(),
            },
        );
        assert_frames(&f);
        let signed: Vec<f64> = (0..topo.vertex_count())
            .map(|v| {
                let a = analytic::torus(topo.positions[v], f64::from(big_r), f64::from(r));
                (f64::from(f.kappa_max[v]) - a.kappa_max) / kref * 100.0
            })
            .collect();
        let bias = median(signed.iter().copied());
        let abs = median(signed.iter().map(|e| e.abs()));
        eprintln!("{method:?}: k_max median signed error {bias:.3} %, |error| {abs:.3} %");
        assert!(
            (abs - expected_pct).abs() <= band_pp,
            "{method:?}: k_max median |error| {abs:.3} % of max |k|, documented {expected_pct} %"
        );
        if method != CurvatureMethod::Corrected {
            // "High": the error is a systematic over-estimate, not noise.
            assert!(
                (bias - abs).abs() <= 0.1 * abs,
                "{method:?}: signed {bias:.3} % vs |error| {abs:.3} %: not a high bias"
            );
        }
    }
}

#[test]
fn gauss_bonnet_angle_defects_sum_to_two_pi_chi() {
    use std::f64::consts::TAU;
    for (mesh, chi) in [
        (generate::icosphere(3, 1.3), 2),
        (generate::torus(2.0, 0.7, 60, 20), 0),
        (generate::paper_knot(), 0),
        (generate::ellipsoid(2.0, 1.2, 0.8, 10), 2),
    ] {
        let topo = Topology::new(&weld(&mesh));
        assert_eq!(topo.euler_characteristic(), chi);
        let total: f64 = topo.angle_defects().iter().sum();
        assert!(
            (total - TAU * chi as f64).abs() < 1e-6,
            "Σ defects {total} for χ = {chi}"
        );
    }
    // The tensor's K = κ_max κ_min, integrated with one third of each face's area per
    // vertex, approximates 2πχ (it is a pointwise estimate, not an exact invariant).
    for (mesh, chi) in [
        (generate::icosphere(4, 1.0), 2.0),
        (generate::torus(2.0, 0.7, 170, 60), 0.0),
    ] {
        let (topo, f) = field(&mesh);
        let mut area = vec![0f64; topo.vertex_count()];
        for (t, &a) in topo.triangles.iter().zip(&topo.face_areas) {
            for &i in t {
                area[i as usize] += f64::from(a) / 3.0;
            }
        }
        let total: f64 = (0..f.len())
            .map(|v| f64::from(f.kappa_max[v] * f.kappa_min[v]) * area[v])
            .sum();
        assert!(
            (total - TAU * chi).abs() < 0.02 * TAU * 2.0,
            "tensor ∫K = {total}, χ = {chi}"
        );
    }
}

fn base_torus() -> &'static (Mesh, CurvatureField) {
    static BASE: std::sync::OnceLock<(Mesh, CurvatureField)> = std::sync::OnceLock::new();
    BASE.get_or_init(|| {
        let mesh = generate::torus(2.0, 0.7, 50, 18);
        let w = weld(&mesh);
        let f = CurvatureField::compute(&Topology::new(&w), &CurvatureOptions::default());
        (mesh, f)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Rigid motions change nothing; a uniform scale s divides curvature by s.
    #[test]
    fn rigid_motion_and_scale(
        axis in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        angle in -3.1f32..3.1,
        shift in (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0),
        log_scale in -2.0f32..2.0,
    ) {
        let (mesh, base) = base_torus();
        let axis = Vec3::from(axis).try_normalize().unwrap_or(Vec3::Y);
        let q = Quat::from_axis_angle(axis, angle);
        let s = log_scale.exp();
        let m = Mat4::from_scale_rotation_translation(Vec3::splat(s), q, Vec3::from(shift));
        let mut moved = mesh.clone();
        for p in &mut moved.positions {
            *p = m.transform_point3(*p);
        }
        for n in &mut moved.normals {
            *n = q * *n;
        }
        let w = weld(&moved);
        let f = CurvatureField::compute(&Topology::new(&w), &CurvatureOptions::default());
        prop_assert_eq!(f.len(), base.len());
        let kref = 1.0 / 0.7;
        for v in 0..f.len() {
            prop_assert!((f.kappa_max[v] * s - base.kappa_max[v]).abs() < 2e-3 * kref);
            prop_assert!((f.kappa_min[v] * s - base.kappa_min[v]).abs() < 2e-3 * kref);
            let d = q * base.dir_kappa_max[v];
            prop_assert!(d.dot(f.dir_kappa_max[v]).abs() > 0.9995);
            prop_assert!((q * base.normal[v]).dot(f.normal[v]) > 0.9999);
        }
    }
}

#[test]
fn no_panic_on_bad_meshes() {
    // Empty mesh.
    let (_, f) = field(&Mesh::default());
    assert!(f.is_empty());
    // Single triangle: boundary everywhere, zero dihedral → flat.
    let tri = Mesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: vec![Vec3::Z; 3],
        uvs: vec![glam::Vec2::ZERO; 3],
        indices: vec![0, 1, 2],
    };
    let (_, f) = field(&tri);
    assert_frames(&f);
    assert!(f.kappa_max.iter().all(|&k| k == 0.0));
    // Non-manifold fan (five faces on one edge), duplicate faces, a degenerate face, an
    // isolated vertex.
    let mut fan = Mesh {
        positions: vec![Vec3::ZERO, Vec3::Y, Vec3::new(5.0, 5.0, 5.0)],
        ..Mesh::default()
    };
    for k in 0..5 {
        let a = k as f32 * 1.2;
        fan.positions.push(Vec3::new(a.cos(), 0.5, a.sin()));
        fan.indices.extend([0, 1, 3 + k]);
    }
    fan.indices.extend([0, 1, 3, 0, 1, 3, 0, 0, 1]);
    fan.normals = vec![Vec3::Z; fan.positions.len()];
    fan.uvs = vec![glam::Vec2::ZERO; fan.positions.len()];
    fan.validate().unwrap();
    let (topo, f) = field(&fan);
    assert_frames(&f);
    assert!(!f.valid[2], "isolated vertex must be invalid");
    assert!(topo.is_isolated(2));
    // NaN coordinates: a typed error from validation.
    let mut nan = tri.clone();
    nan.positions[1].x = f32::NAN;
    assert!(matches!(
        nan.validate(),
        Err(npr_geometry::GeometryError::NonFinite { .. })
    ));
    // ...and the computation itself still yields no NaN if called anyway.
    let (_, f) = field(&nan);
    assert_frames(&f);
}

#[test]
fn stanford_bunny_with_holes() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/meshes/stanford-bunny.obj"
    );
    let obj = npr_geometry::load_obj_with_vertex_map(path).unwrap();
    assert_eq!(obj.mesh.triangle_count(), 69_451);
    assert_eq!(obj.obj_to_welded.len(), 35_947);
    let topo = Topology::new(&obj.welded);
    assert!(topo.boundary_vertices().iter().any(|&b| b));
    for method in [CurvatureMethod::Corrected, CurvatureMethod::Paper] {
        let f = CurvatureField::compute(
            &topo,
            &CurvatureOptions {
                method,
                radius: CurvatureRadius::default(),
            },
        );
        assert_frames(&f);
        let valid = f.valid.iter().filter(|&&v| v).count();
        assert!(valid as f64 > 0.99 * f.len() as f64);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random bad meshes (out-of-range indices, repeated indices, NaN/inf coordinates,
    /// duplicate faces) never panic and never produce NaN in valid entries.
    #[test]
    fn random_bad_meshes_do_not_panic(
        pts in proptest::collection::vec((-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0, 0u8..20), 0..40),
        idx in proptest::collection::vec(0u32..45, 0..120),
    ) {
        let positions: Vec<Vec3> = pts
            .iter()
            .map(|&(x, y, z, k)| match k {
                0 => Vec3::new(f32::NAN, y, z),
                1 => Vec3::new(x, f32::INFINITY, z),
                _ => Vec3::new(x, y, z),
            })
            .collect();
        let n = positions.len();
        let mesh = Mesh {
            positions,
            normals: vec![Vec3::Z; n],
            uvs: vec![glam::Vec2::ZERO; n],
            indices: idx[..idx.len() / 3 * 3].to_vec(),
        };
        let _ = mesh.validate();
        let w = weld(&mesh);
        let topo = Topology::new(&w);
        for method in [CurvatureMethod::Corrected, CurvatureMethod::Paper, CurvatureMethod::Clipped] {
            let f = CurvatureField::compute(&topo, &CurvatureOptions { method, radius: CurvatureRadius::World(1.0) });
            assert_frames(&f);
            let s = npr_geometry::HighlightSearch::new(&topo, &f);
            for c in s.find(
                npr_geometry::LightEye::Positions { light: Vec3::new(3.0, 2.0, 1.0), eye: Vec3::Z * 4.0 },
                Mat4::IDENTITY,
            ) {
                prop_assert!(c.position_world.is_finite() && c.normal_world.is_finite());
            }
        }
    }
}
