//! The N = H solve and the highlight-centre search (Eq. (3)–(6), §3.1).
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use glam::{Mat4, Quat, Vec3};
use npr_geometry::{
    CurvatureField, CurvatureOptions, HighlightSearch, LightEye, Mesh, NormalInterpolation,
    Topology, generate, try_solve_barycentric, try_solve_barycentric_eq6, weld,
};
use proptest::prelude::*;

fn vec3() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(Vec3::from)
}

/// Vertex fields N_i, H_i that are exactly equal at barycentric (α, β): H_i = N_i + D_i
/// with Σ w_i D_i = 0.
fn fields(n: [Vec3; 3], d0: Vec3, d1: Vec3, a: f32, b: f32) -> ([Vec3; 3], [Vec3; 3]) {
    let w = [1.0 - a - b, a, b];
    let d2 = -(w[0] * d0 + w[1] * d1) / w[2];
    (n, [n[0] + d0, n[1] + d1, n[2] + d2])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Inside points are recovered: the planted point, or (where the direction condition
    /// N ∥ H has a second root inside the triangle, as the planted fields allow) another
    /// point where the interpolated fields are parallel.
    #[test]
    fn solve_recovers_inside_point(
        n0 in vec3(), n1 in vec3(), n2 in vec3(), d0 in vec3(), d1 in vec3(),
        a in 0.0f32..0.8, t in 0.0f32..1.0,
    ) {
        let b = (1.0 - a) * t * 0.9 + 0.05 * (1.0 - a);
        let offset = Vec3::new(0.0, 0.0, 3.0); // keep N away from zero
        let (n, h) = fields([n0 + offset, n1 + offset, n2 + offset], d0, d1, a, b);
        // Only well-posed systems (columns of Eq. (6) not nearly dependent).
        let c1 = (n[1] - n[0]) - (h[1] - h[0]);
        let c2 = (n[2] - n[0]) - (h[2] - h[0]);
        prop_assume!(c1.cross(c2).length() > 0.05 * c1.length() * c2.length() && c1.length() > 0.05);
        for solve in [try_solve_barycentric, try_solve_barycentric_eq6] {
            let (sa, sb) = solve(n, h).expect("inside point must be found");
            let at = |f: &[Vec3; 3]| (1.0 - sa - sb) * f[0] + sa * f[1] + sb * f[2];
            let parallel = at(&n).normalize().cross(at(&h).normalize()).length();
            let inside = sa >= -1e-4 && sb >= -1e-4 && sa + sb <= 1.0 + 1e-4;
            prop_assert!(
                ((sa - a).abs() < 1e-3 && (sb - b).abs() < 1e-3) || (inside && parallel < 1e-4),
                "{sa} {sb} vs {a} {b} (N × H {parallel:e})"
            );
        }
    }

    /// Points clearly outside the triangle are rejected.
    #[test]
    fn solve_rejects_outside_point(
        n0 in vec3(), n1 in vec3(), n2 in vec3(), d0 in vec3(), d1 in vec3(),
        a in 0.6f32..1.5, b in 0.6f32..1.5,
    ) {
        let offset = Vec3::new(0.0, 0.0, 3.0);
        let (n, h) = fields([n0 + offset, n1 + offset, n2 + offset], d0, d1, a, b);
        prop_assume!(h.iter().all(|x| x.is_finite()));
        let c1 = (n[1] - n[0]) - (h[1] - h[0]);
        let c2 = (n[2] - n[0]) - (h[2] - h[0]);
        prop_assume!(c1.cross(c2).length() > 0.05 * c1.length() * c2.length() && c1.length() > 0.05);
        prop_assert!(try_solve_barycentric_eq6(n, h).is_none());
        prop_assert!(try_solve_barycentric(n, h).is_none());
    }
}

#[test]
fn degenerate_systems_give_none() {
    let n = [Vec3::Z; 3];
    assert_eq!(try_solve_barycentric(n, n), None);
    assert_eq!(try_solve_barycentric(n, [Vec3::X; 3]), None);
    assert_eq!(
        try_solve_barycentric([Vec3::ZERO; 3], [Vec3::ZERO; 3]),
        None
    );
    let nan = [Vec3::NAN; 3];
    assert_eq!(try_solve_barycentric(nan, n), None);
    // Collinear columns.
    let n = [Vec3::Z, Vec3::Z + Vec3::X, Vec3::Z + 2.0 * Vec3::X];
    assert_eq!(try_solve_barycentric(n, [Vec3::Z; 3]), None);
}

fn search(mesh: &Mesh) -> HighlightSearch {
    let topo = Topology::new(&weld(mesh));
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    HighlightSearch::new(&topo, &f)
}

#[test]
fn sphere_centre_is_the_analytic_point() {
    let s = search(&generate::icosphere(4, 1.0));
    // Directions: the centre lies along H.
    let (l, e) = (Vec3::new(1.0, 2.0, 0.5), Vec3::new(-0.3, 0.4, 1.0));
    let c = s.find(
        LightEye::Directions {
            to_light: l,
            to_eye: e,
        },
        Mat4::IDENTITY,
    );
    assert_eq!(c.len(), 1, "{c:?}");
    let h = (l.normalize() + e.normalize()).normalize();
    assert!(
        c[0].position_world
            .normalize()
            .angle_between(h)
            .to_degrees()
            < 0.2
    );
    assert!((c[0].kappa_max - 1.0).abs() < 0.02 && (c[0].kappa_min - 1.0).abs() < 0.02);
    // Positions, with the sphere moved, rotated and scaled by 2: the centre p (relative
    // to the sphere's centre) satisfies p̂ = normalize(L̂ + V̂) there.
    let m = Mat4::from_scale_rotation_translation(
        Vec3::splat(2.0),
        Quat::from_rotation_y(0.7),
        Vec3::new(1.0, 0.0, -2.0),
    );
    let centre = Vec3::new(1.0, 0.0, -2.0);
    let (light, eye) = (Vec3::new(6.0, 5.0, 4.0), Vec3::new(0.0, 1.0, 8.0));
    let mut p = (light - centre).normalize();
    for _ in 0..100 {
        let q = centre + 2.0 * p;
        p = ((light - q).normalize() + (eye - q).normalize()).normalize();
    }
    let c = s.find(LightEye::Positions { light, eye }, m);
    assert_eq!(c.len(), 1, "{c:?}");
    let got = (c[0].position_world - centre).normalize();
    assert!(got.angle_between(p).to_degrees() < 0.3, "{got} vs {p}");
    assert!(c[0].normal_world.angle_between(p).to_degrees() < 0.3);
    assert!(
        (c[0].kappa_max - 0.5).abs() < 0.01,
        "curvature scales by 1/s"
    );
    let frame = c[0].dir_kappa_max.cross(c[0].dir_kappa_min);
    assert!(frame.distance(c[0].normal_world) < 1e-4);
}

#[test]
fn knot_count_is_stable_under_tiny_light_moves() {
    let knot = generate::paper_knot();
    assert_eq!(knot.triangle_count(), 2880);
    let s = search(&knot);
    let eye = Vec3::new(0.0, 0.0, 6.0);
    for base in [
        Vec3::new(3.0, 4.0, 5.0),
        Vec3::new(-4.0, 2.0, 3.0),
        Vec3::new(0.5, -3.0, 4.0),
    ] {
        let count = s
            .find(LightEye::Positions { light: base, eye }, Mat4::IDENTITY)
            .len();
        assert!(
            count >= 2,
            "knot should show several highlights, got {count}"
        );
        for k in 0..20 {
            let a = k as f32 * 0.31;
            let light = base + 1e-4 * Vec3::new(a.cos(), a.sin(), (2.0 * a).cos());
            let c = s
                .find(LightEye::Positions { light, eye }, Mat4::IDENTITY)
                .len();
            assert_eq!(c, count, "count changed under a 1e-4 light move");
        }
    }
}

#[test]
fn search_equals_brute_force_on_knot() {
    // The cheap rejection must not lose centres: compare positions with solving every
    // face. "Matched" = within 1e-4 of the bounding radius, both ways.
    let knot = generate::paper_knot();
    let topo = Topology::new(&weld(&knot));
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let mut s = HighlightSearch::new(&topo, &f);
    let radius = topo
        .positions
        .iter()
        .map(|p| p.length())
        .fold(0f32, f32::max);
    let tol = 1e-4 * radius;
    // Every point of `a` has one of `b` within `tol`, and the other way round.
    let same = |a: &[Vec3], b: &[Vec3], what: &str| {
        let unmatched = |a: &[Vec3], b: &[Vec3]| -> Vec<Vec3> {
            a.iter()
                .filter(|p| !b.iter().any(|q| p.distance(*q) <= tol))
                .copied()
                .collect()
        };
        let (lost, extra) = (unmatched(a, b), unmatched(b, a));
        assert!(
            lost.is_empty() && extra.is_empty(),
            "{what}: {lost:?} / {extra:?}"
        );
    };
    let positions = |c: Vec<npr_geometry::HighlightCentre>| -> Vec<Vec3> {
        c.iter().map(|c| c.position_object).collect()
    };
    let (light, eye) = (Vec3::new(3.0, 4.0, 5.0), Vec3::new(0.0, 0.0, 6.0));
    // The default curvature-blended field: rejection loses nothing, over many views.
    for k in 0..24 {
        let a = k as f32 * 0.26;
        let le = LightEye::Positions {
            light: Vec3::new(5.0 * a.cos(), 3.0, 5.0 * a.sin()),
            eye: Vec3::new(6.0 * (a + 0.7).sin(), -1.0, 6.0 * (a + 0.7).cos()),
        };
        let fast = positions(s.find(le, Mat4::IDENTITY));
        let all = positions(s.find_exhaustive(le, Mat4::IDENTITY));
        assert!(!all.is_empty());
        same(&all, &fast, &format!("view {k}: exhaustive vs rejection"));
    }
    // The paper's linear field against an independent brute force over the public solve.
    s.interpolation = NormalInterpolation::Linear;
    let found = positions(s.find(LightEye::Positions { light, eye }, Mat4::IDENTITY));
    let mut brute: Vec<Vec3> = vec![];
    for t in &topo.triangles {
        let p = t.map(|i| topo.positions[i as usize]);
        let n = t.map(|i| f.normal[i as usize]);
        let h = p.map(|q| ((light - q).normalize() + (eye - q).normalize()).normalize());
        if let Some((a, b)) = try_solve_barycentric(n, h) {
            let q = p[0] + a * (p[1] - p[0]) + b * (p[2] - p[0]);
            if brute
                .iter()
                .all(|o| o.distance(q) > 0.01 * topo.mean_edge_length)
            {
                brute.push(q);
            }
        }
    }
    assert!(!brute.is_empty());
    same(&brute, &found, "brute force vs search");
}

#[test]
fn empty_mesh_has_no_centres() {
    let s = search(&Mesh::default());
    let c = s.find(
        LightEye::Directions {
            to_light: Vec3::Y,
            to_eye: Vec3::Z,
        },
        Mat4::IDENTITY,
    );
    assert!(c.is_empty());
}

#[test]
fn for_mesh_solves_on_the_mesh_normals() {
    // Normals tilted 25° about z (not the area-weighted ones): the centre must land where
    // the tilted normal equals H (the shaded peak), and `new` (field normals) must not.
    let mut mesh = generate::icosphere(4, 1.0);
    let tilt = glam::Mat3::from_rotation_z(25f32.to_radians());
    for n in &mut mesh.normals {
        *n = tilt * *n;
    }
    let welded = weld(&mesh);
    let topo = Topology::new(&welded);
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let le = LightEye::Directions {
        to_light: Vec3::Y,
        to_eye: Vec3::Y,
    };
    let shaded_peak = tilt.transpose() * Vec3::Y;
    let s = HighlightSearch::for_mesh(&mesh, &welded, &topo, &f);
    assert_eq!(s.normal_source(), npr_geometry::NormalSource::Mesh);
    let c = s.find(le, Mat4::IDENTITY);
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(c[0].position_object.distance(shaded_peak) < 0.01, "{c:?}");
    let field = HighlightSearch::new(&topo, &f);
    assert_eq!(field.normal_source(), npr_geometry::NormalSource::Field);
    let g = field.find(le, Mat4::IDENTITY);
    assert_eq!(g.len(), 1);
    assert!(g[0].position_object.distance(Vec3::Y) < 0.01, "{g:?}");
    // No normals: the field's.
    let mut bare = mesh.clone();
    bare.normals.clear();
    let s = HighlightSearch::for_mesh(&bare, &welded, &topo, &f);
    assert_eq!(s.normal_source(), npr_geometry::NormalSource::Field);
}

#[test]
fn cluster_rejection_keeps_every_centre_on_real_meshes_and_skips_most_vertices() {
    // The fast path (cluster cones, then per-vertex and per-face tests) against solving
    // every face, on the shipped scans, for point lights and near eyes around the model,
    // under a rotation with uniform scale: the same centres at the same positions.
    for file in ["stanford-bunny.obj", "spot.obj"] {
        let (topo, s, c, r) = fixture_search(file);
        let tol = 1e-4 * r;
        let world = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(1.0, -2.0, 0.5),
        );
        let (mut kept, mut total) = (0usize, 0usize);
        for k in 0..12 {
            let a = k as f32 * 0.52;
            let w = |p: Vec3| world.transform_point3(p);
            let le = LightEye::Positions {
                light: w(c + Vec3::new(4.0 * r * a.cos(), 2.0 * r, 4.0 * r * a.sin())),
                eye: w(c + Vec3::new(
                    3.0 * r * (a + 0.9).sin(),
                    0.5 * r,
                    3.0 * r * (a + 0.9).cos(),
                )),
            };
            let fast: Vec<Vec3> = s
                .find(le, world)
                .iter()
                .map(|c| c.position_object)
                .collect();
            let all: Vec<Vec3> = s
                .find_exhaustive(le, world)
                .iter()
                .map(|c| c.position_object)
                .collect();
            assert!(!all.is_empty(), "{file} view {k}: no centre at all");
            for p in &all {
                assert!(
                    fast.iter().any(|q| q.distance(*p) <= tol),
                    "{file} view {k}: lost {p}"
                );
            }
            for p in &fast {
                assert!(
                    all.iter().any(|q| q.distance(*p) <= tol),
                    "{file} view {k}: extra {p}"
                );
            }
            kept += s.candidate_vertices(le, world);
            total += topo.vertex_count();
        }
        // The clusters do reject: many vertices are never looked at one by one.
        println!("{file}: clusters kept {kept} of {total} vertex visits");
        assert!(
            (kept as f64) < 0.4 * total as f64,
            "{file}: clusters kept {kept} of {total} vertex visits"
        );
    }
}

/// The search over a shipped scan (`fixtures/meshes/FILE`) on its own normals, its
/// topology and bounding sphere (centre, radius).
fn fixture_search(file: &str) -> (Topology, HighlightSearch, Vec3, f32) {
    let path = format!(
        "{}/../../fixtures/meshes/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    let mesh = npr_geometry::load_obj(&path).unwrap();
    let welded = weld(&mesh);
    let topo = Topology::new(&welded);
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let s = HighlightSearch::for_mesh(&mesh, &welded, &topo, &f);
    let (lo, hi) = topo.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    (topo, s, c, r)
}

/// A sequence of inputs for the coherence test: turning object, still frames, jitter, a
/// jump of the light, directions, a non-similar map and a change of normal field.
fn coherence_sequence(c: Vec3, r: f32) -> Vec<(LightEye, Mat4, NormalInterpolation)> {
    let placed = |deg: f32| {
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1.7),
            Quat::from_rotation_y(deg.to_radians()),
            Vec3::new(0.3, -0.2, 0.1),
        )
    };
    let w = |m: Mat4, p: Vec3| m.transform_point3(p);
    let base = placed(0.0);
    let light = w(base, c + Vec3::new(30.0 * r, 40.0 * r, 50.0 * r));
    let eye = w(base, c + Vec3::new(0.0, 0.3 * r, 3.0 * r));
    let pos = |light, eye| LightEye::Positions { light, eye };
    let curved = NormalInterpolation::Curvature;
    let mut seq = Vec::new();
    // The specular bench's sequence: the object turns 3° per frame.
    for k in 0..40 {
        seq.push((pos(light, eye), placed(3.0 * k as f32), curved));
    }
    // Still frames, then a slow drift of the eye, then the light jumps.
    let still = placed(120.0);
    for _ in 0..3 {
        seq.push((pos(light, eye), still, curved));
    }
    for k in 0..12 {
        let e = eye + Vec3::new(0.002 * r * k as f32, 0.0, 0.0);
        seq.push((pos(light, e), still, curved));
    }
    let jumped = w(base, c + Vec3::new(-30.0 * r, 10.0 * r, 20.0 * r));
    for k in 0..6 {
        seq.push((pos(jumped, eye), placed(120.0 + k as f32), curved));
    }
    // Directional light and eye, the light circling.
    for k in 0..20 {
        let a = 0.04 * k as f32;
        let le = LightEye::Directions {
            to_light: Vec3::new(a.cos(), 0.6, a.sin()),
            to_eye: Vec3::new(0.1, 0.2, 1.0),
        };
        seq.push((le, placed(30.0), curved));
    }
    // A non-similar map with point light and eye (no coherence), then back.
    let squashed = placed(40.0) * Mat4::from_scale(Vec3::new(1.0, 0.6, 1.0));
    for k in 0..4 {
        seq.push((
            pos(light, eye),
            squashed * Mat4::from_rotation_y(0.05 * k as f32),
            curved,
        ));
    }
    // The paper's linear field, turning again.
    for k in 0..10 {
        seq.push((
            pos(light, eye),
            placed(40.0 + 2.0 * k as f32),
            NormalInterpolation::Linear,
        ));
    }
    seq
}

#[test]
fn coherent_search_finds_what_the_full_search_finds_frame_by_frame() {
    // The frame-coherent search (watch lists kept while the light and eye move
    // within a budget) must return exactly `find`'s centres — the same faces solved in the
    // same order — on every frame, and those must be the exhaustive search's.
    for file in ["stanford-bunny.obj", "spot.obj"] {
        let (topo, mut s, c, r) = fixture_search(file);
        let mut state = npr_geometry::SearchCoherence::default();
        let (mut watched, mut reused, mut full, mut tested) = (0, 0, 0, 0usize);
        let mut centres = 0;
        for (k, (le, world, interp)) in coherence_sequence(c, r).into_iter().enumerate() {
            s.interpolation = interp;
            let coherent = s.find_coherent(&mut state, le, world);
            let reference = s.find(le, world);
            assert_eq!(coherent, reference, "{file} frame {k}");
            let st = state.stats();
            match (st.full, st.reused) {
                (true, _) => full += 1,
                (_, true) => reused += 1,
                _ => {
                    watched += 1;
                    tested += st.tested;
                }
            }
            centres += coherent.len();
            if k % 9 == 0 {
                let all = s.find_exhaustive(le, world);
                let tol = 1e-4 * r;
                for p in all.iter().map(|c| c.position_object) {
                    assert!(
                        coherent
                            .iter()
                            .any(|q| q.position_object.distance(p) <= tol),
                        "{file} frame {k}: lost {p}"
                    );
                }
                assert_eq!(all.len(), coherent.len(), "{file} frame {k}");
            }
        }
        println!(
            "{file}: {full} full, {watched} watch-list, {reused} reused frames; \
             {tested} vertices tested on watch-list frames ({} per frame of {}); {centres} centres",
            tested / watched.max(1),
            topo.vertex_count()
        );
        // The sequence exercises every path, and the watch lists are small.
        assert!(centres > 0);
        assert!(reused >= 2, "{file}: still frames reuse the last result");
        assert!(
            full >= 5,
            "{file}: jumps, the non-similar map and the field change"
        );
        assert!(watched >= 40, "{file}: {watched} watch-list frames");
        assert!(
            tested / watched.max(1) < topo.vertex_count() / 4,
            "{file}: watch lists average {} of {} vertices",
            tested / watched.max(1),
            topo.vertex_count()
        );
    }
}

#[test]
fn coherent_search_holds_at_the_edge_of_its_budget_and_never_mixes_meshes() {
    // A key frame is built when the light and eye move by more than its budget (3 × the
    // last step); then poses moved by just under the budget, in many directions, must be
    // watch-list frames (no rebuild) with exactly `find`'s centres: point light and eye
    // under a rotation with uniform scale 2.5, and directions under a shear.
    let (_, s, c, r) = fixture_search("stanford-bunny.obj");
    let world = Mat4::from_scale_rotation_translation(
        Vec3::splat(2.5),
        Quat::from_rotation_y(0.4),
        Vec3::new(0.5, 0.0, -1.0),
    );
    let w = |p: Vec3| world.transform_point3(p);
    let mut rng = 0x9e37_79b9_u32;
    let mut unit = || {
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            rng as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        Vec3::new(next(), next(), next()).normalize()
    };
    let (light, eye) = (
        w(c + Vec3::new(6.0 * r, 8.0 * r, 10.0 * r)),
        w(c + Vec3::new(0.0, 0.5 * r, 3.0 * r)),
    );
    let pos = |light, eye| LightEye::Positions { light, eye };
    let mut state = npr_geometry::SearchCoherence::default();
    // Two steps of 0.2 r (world units × 2.5): the second builds the key with a budget
    // of 3 × 0.2 r in object units for both light and eye.
    let step = 0.2 * r * 2.5;
    s.find_coherent(&mut state, pos(light, eye), world);
    let (light1, eye1) = (light + Vec3::X * step, eye + Vec3::X * step);
    s.find_coherent(&mut state, pos(light1, eye1), world);
    assert!(state.stats().full);
    let budget = 3.0 * step * 0.999;
    let mut watched = 0;
    for k in 0..80 {
        let (dl, de) = (unit() * budget, unit() * budget);
        let le = pos(light1 + dl, eye1 + de);
        let coherent = s.find_coherent(&mut state, le, world);
        assert_eq!(coherent, s.find(le, world), "point pose {k}");
        if !state.stats().full {
            watched += 1;
        }
    }
    assert!(
        watched >= 75,
        "{watched} of 80 poses within the budget were watch-list frames"
    );

    // Directions under a shear: the budget is an angle of the object-space half vector.
    let shear = Mat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 0.2, 1.3, 0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    let dir = |a: f32| LightEye::Directions {
        to_light: Vec3::new(a.cos(), 0.8, a.sin()),
        to_eye: Vec3::new(0.1, 0.3, 1.0),
    };
    let mut state = npr_geometry::SearchCoherence::default();
    s.find_coherent(&mut state, dir(0.0), shear);
    s.find_coherent(&mut state, dir(0.02), shear);
    let mut watched = 0;
    for k in 0..30 {
        let a = 0.02 + 0.05 * ((k as f32 * 0.7).sin());
        let coherent = s.find_coherent(&mut state, dir(a), shear);
        assert_eq!(coherent, s.find(dir(a), shear), "direction pose {k}");
        if !state.stats().full && !state.stats().reused {
            watched += 1;
        }
    }
    assert!(watched > 0, "some direction poses stay within the budget");

    // Two searches over meshes with the same vertex and face counts, one state: the
    // state must never hand one mesh's centres or watch list to the other.
    let sphere = generate::icosphere(3, 1.0);
    let mut squashed = sphere.clone();
    for p in &mut squashed.positions {
        *p *= Vec3::new(1.0, 0.5, 1.4);
    }
    let searches: Vec<HighlightSearch> = [sphere, squashed]
        .iter()
        .map(|m| {
            let welded = weld(m);
            let topo = Topology::new(&welded);
            let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
            HighlightSearch::for_mesh(m, &welded, &topo, &f)
        })
        .collect();
    let mut state = npr_geometry::SearchCoherence::default();
    let le = pos(Vec3::new(3.0, 4.0, 5.0), Vec3::new(0.0, 0.5, 4.0));
    for k in 0..6 {
        let s = &searches[k % 2];
        let coherent = s.find_coherent(&mut state, le, Mat4::IDENTITY);
        let reference = s.find(le, Mat4::IDENTITY);
        assert!(!reference.is_empty());
        assert_eq!(coherent, reference, "call {k}");
    }
    assert_ne!(
        searches[0].find(le, Mat4::IDENTITY),
        searches[1].find(le, Mat4::IDENTITY),
        "the two meshes must differ for this check to mean anything"
    );
}
