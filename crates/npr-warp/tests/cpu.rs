//! CPU tests: the proxy (§3.2), the normal bins and their culling (§3.3.2), the blend plan
//! (§3.3.3), the schedule, and typed errors instead of panics on bad input.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Vec2, Vec3};
use npr_geometry::{Mesh, generate};
use npr_warp::bins::{DrawKind, Facing, NormalBins, PlanSettings, plan};
use npr_warp::{Proxy, WarpError, WarpSchedule};
use proptest::prelude::*;

fn knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot::trefoil(0.2, 300, 24))
}

fn face_normal_and_centroid(mesh: &Mesh, t: &[u32]) -> (Vec3, Vec3) {
    let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
    ((b - a).cross(c - a), (a + b + c) / 3.0)
}

#[test]
fn proxy_reaches_the_ratio_and_reports_a_growing_error() {
    let mesh = knot();
    let mut last_error = 0.0;
    for ratio in [0.2, 0.05, 0.01] {
        let proxy = Proxy::simplify(&mesh, ratio).unwrap();
        let achieved = proxy.ratio_achieved();
        assert!(
            achieved <= ratio * 1.05 && achieved >= ratio * 0.5,
            "ratio {ratio}: achieved {achieved}"
        );
        assert!(
            proxy.error_object > last_error,
            "error must grow as the ratio falls"
        );
        assert!(proxy.error_object > 0.0 && proxy.error_object < 0.2);
        last_error = proxy.error_object;
        proxy.mesh.validate().unwrap();
        assert_eq!(proxy.source_triangles, mesh.triangle_count());
    }
    let whole = Proxy::simplify(&mesh, 1.0).unwrap();
    assert_eq!(whole.triangles(), mesh.triangle_count());
    assert_eq!(whole.error_object, 0.0);
}

#[test]
fn bins_hold_every_face_exactly_once_and_ranges_cover_the_index_buffer() {
    let mesh = Proxy::simplify(&knot(), 0.1).unwrap().mesh;
    for n in [1, 2, 4, 8, 16, 33] {
        let bins = NormalBins::build(&mesh, n).unwrap();
        assert_eq!(bins.len(), (n * n) as usize);
        // Ranges are contiguous, in order, multiples of 3, and cover the whole buffer.
        let mut cursor = 0;
        for bin in &bins.bins {
            assert_eq!(bin.indices.start, cursor, "n {n}");
            assert_eq!(bin.indices.len() % 3, 0);
            cursor = bin.indices.end;
        }
        assert_eq!(cursor as usize, mesh.indices.len());
        // The sorted buffer is a permutation of the faces.
        let mut original: Vec<[u32; 3]> = mesh.triangles().collect();
        let mut sorted: Vec<[u32; 3]> = bins
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        original.sort_unstable();
        sorted.sort_unstable();
        assert_eq!(original, sorted);
        // Each face sits in the bin of its own normal, inside the bin's cone.
        for (b, bin) in bins.bins.iter().enumerate() {
            for t in
                bins.indices[bin.indices.start as usize..bin.indices.end as usize].chunks_exact(3)
            {
                let (n_face, _) = face_normal_and_centroid(&mesh, t);
                assert_eq!(npr_warp::bins::bin_of_normal(n_face, n) as usize, b);
                let angle = n_face.normalize().dot(bin.normal).clamp(-1.0, 1.0).acos();
                assert!(angle <= bin.half_angle_rad + 1e-5);
            }
        }
    }
}

#[test]
fn culling_removes_back_facing_bins_and_keeps_front_facing_ones() {
    let mesh = Proxy::simplify(&knot(), 0.1).unwrap().mesh;
    let bins = NormalBins::build(&mesh, 12).unwrap();
    let eyes = [
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::new(3.0, 2.0, -1.0),
        Vec3::new(-0.5, -6.0, 0.3),
        Vec3::new(20.0, 0.0, 0.0),
    ];
    for eye in eyes {
        let mut culled_faces = 0;
        for (b, bin) in bins.bins.iter().enumerate() {
            let facing = bins.facing(b, eye);
            for t in
                bins.indices[bin.indices.start as usize..bin.indices.end as usize].chunks_exact(3)
            {
                let (n, c) = face_normal_and_centroid(&mesh, t);
                let front = n.dot(eye - c) > 0.0;
                match facing {
                    Facing::Back => {
                        assert!(!front, "a front-facing face in culled bin {b} (eye {eye})");
                        culled_faces += 1;
                    }
                    Facing::Front => assert!(front, "a back-facing face in front bin {b}"),
                    Facing::Mixed => {}
                }
            }
        }
        // Culling does real work (it is conservative: the bin's normal cone and the
        // object's angular size at this distance widen the margin): over 10 % of the faces
        // near, over 30 % far.
        let share = culled_faces as f32 / mesh.triangle_count() as f32;
        let want = if eye.length() > 10.0 { 0.3 } else { 0.1 };
        assert!(share > want, "eye {eye}: {share} culled");
    }
    // The plan never draws a bin that faces away from the current camera and both
    // references, and draws every bin that faces the current camera.
    let eye_now = Vec3::new(0.0, 0.5, 4.0);
    let refs = [Vec3::new(-0.6, 0.5, 4.0), Vec3::new(0.6, 0.5, 4.0)];
    let p = plan(&bins, eye_now, refs, 0.5, &PlanSettings::default());
    for (b, bin) in bins.bins.iter().enumerate() {
        let drawn = p.draws.iter().any(|d| {
            d.indices.start <= bin.indices.start
                && bin.indices.end <= d.indices.end
                && !bin.indices.is_empty()
        });
        if bin.indices.is_empty() {
            continue;
        }
        if bins.facing(b, eye_now) == Facing::Back {
            assert!(!drawn, "bin {b} faces away from the current camera");
        } else {
            assert!(drawn, "bin {b} faces the current camera but is not drawn");
        }
    }
    assert!(
        p.bins_culled > 0 && p.bins_single > 0 && p.bins_blended > 0,
        "{p:?}"
    );
}

#[test]
fn blend_ramps_follow_time_and_view_direction() {
    let mesh = generate::icosphere(3, 1.0);
    let bins = NormalBins::build(&mesh, 8).unwrap();
    let refs = [Vec3::new(-1.0, 0.0, 4.0), Vec3::new(1.0, 0.0, 4.0)];
    let settings = PlanSettings {
        blend_band: 1.0,
        ..Default::default()
    };
    // At s = 0 every drawn bin uses reference 0 alone; at s = 1 reference 1.
    let at0 = plan(&bins, refs[0], refs, 0.0, &settings);
    assert!(
        at0.draws.iter().all(|d| d.kind == DrawKind::Single0),
        "{:?}",
        at0.draws
    );
    let at1 = plan(&bins, refs[1], refs, 1.0, &settings);
    assert!(at1.draws.iter().all(|d| d.kind == DrawKind::Single1));
    // Halfway, weights sum to one, and bins turned towards reference 0 weight it more.
    let mid = plan(&bins, Vec3::new(0.0, 0.0, 4.0), refs, 0.5, &settings);
    for d in mid.draws.iter().filter(|d| d.kind == DrawKind::Blend) {
        let w = mid.weights[d.instance as usize];
        assert!((w[0] + w[1] - 1.0).abs() < 1e-6);
        let n = bins.bins[d.instance as usize].normal;
        let towards0 = n.dot(refs[0].normalize()) > n.dot(refs[1].normalize()) + 0.05;
        if towards0 {
            assert!(w[0] > 0.5, "bin {} normal {n} weight {w:?}", d.instance);
        }
    }
    // A narrower band turns more bins into single-reference draws.
    let narrow = plan(
        &bins,
        Vec3::new(0.0, 0.0, 4.0),
        refs,
        0.5,
        &PlanSettings {
            blend_band: 0.2,
            ..Default::default()
        },
    );
    assert!(narrow.bins_blended < mid.bins_blended);
}

#[test]
fn the_papers_plan_culls_by_representative_vector_and_ramps_linearly() {
    let mesh = generate::icosphere(3, 1.0);
    let bins = NormalBins::build(&mesh, 8).unwrap();
    let refs = [Vec3::new(-2.0, 0.0, 4.0), Vec3::new(2.0, 0.0, 4.0)];
    let eye_now = Vec3::new(0.0, 0.0, 4.5);
    let paper = PlanSettings::paper();
    let at = |s: f32| plan(&bins, eye_now, refs, s, &paper);
    let p = at(0.5);
    let faces = |b: usize, eye: Vec3| bins.bins[b].cell_normal.dot(eye - bins.centre) > 0.0;
    let elevation = |b: usize, eye: Vec3| {
        let v = (eye - bins.centre).normalize();
        bins.bins[b]
            .cell_normal
            .dot(v)
            .clamp(-1.0, 1.0)
            .asin()
            .max(0.0)
    };
    let mut checked = 0;
    for (b, bin) in bins.bins.iter().enumerate() {
        if bin.indices.is_empty() {
            continue;
        }
        let drawn = p
            .draws
            .iter()
            .any(|d| d.indices.start <= bin.indices.start && bin.indices.end <= d.indices.end);
        let (f0, f1) = (faces(b, refs[0]), faces(b, refs[1]));
        let facing_now = bins.facing(b, eye_now) != Facing::Back;
        // §3.3.2: a bin is drawn exactly when its representative vector faces a reference
        // (and the bin is not certainly back-facing now); bins neither sees are culled.
        assert_eq!(drawn, (f0 || f1) && facing_now, "bin {b}");
        if !drawn {
            continue;
        }
        // §3.3.3: the linear ramp from boundary to boundary, no time term.
        let w0 = p.weights[b][0];
        let want = match (f0, f1) {
            (true, false) => 1.0,
            (false, true) => 0.0,
            _ => {
                let (a0, a1) = (elevation(b, refs[0]), elevation(b, refs[1]));
                a0 / (a0 + a1)
            }
        };
        assert!((w0 - want).abs() < 1e-5, "bin {b}: {w0} vs {want}");
        checked += 1;
    }
    assert!(
        checked > 10 && p.bins_blended > 0 && p.bins_culled > 0,
        "{p:?}"
    );
    // No time term: the weights do not depend on s.
    assert_eq!(at(0.1).weights, p.weights);
    // Ours differs: the time term moves the weights.
    let ours = PlanSettings::default();
    assert_ne!(
        plan(&bins, eye_now, refs, 0.1, &ours).weights,
        plan(&bins, eye_now, refs, 0.9, &ours).weights
    );
}

#[test]
fn settings_out_of_range_are_typed_errors() {
    for band in [0.0, -0.5, 1.5, f32::NAN] {
        let settings = PlanSettings {
            blend_band: band,
            ..Default::default()
        };
        assert!(
            matches!(settings.validate(), Err(WarpError::InvalidSetting(_))),
            "band {band}"
        );
    }
    assert!(PlanSettings::paper().validate().is_ok());
    let mut warp = npr_warp::WarpSettings::default();
    assert!(warp.validate().is_ok());
    warp.depth_tolerance_world = f32::NAN;
    let e = warp.validate().unwrap_err();
    assert!(e.to_string().contains("depth_tolerance_world"), "{e}");
    warp.depth_tolerance_world = 0.01;
    warp.surface_slack_world = -1.0;
    assert!(matches!(warp.validate(), Err(WarpError::InvalidSetting(_))));
}

#[test]
fn schedule_places_references_every_k_frames() {
    let s = WarpSchedule::new(10, false).unwrap();
    let r = s.role(23);
    assert_eq!((r.segment, r.first_frame, r.step), (2, 20, 3));
    assert!((r.s - 0.3).abs() < 1e-6);
    assert_eq!(s.role(0).s, 0.0);
    assert!((s.amortized_ms(50.0, 2.0) - 7.0).abs() < 1e-12);
    assert!(matches!(
        WarpSchedule::new(0, true),
        Err(WarpError::ZeroPeriod)
    ));
}

#[test]
fn bad_input_gives_typed_errors() {
    let empty = Mesh::default();
    assert!(matches!(
        Proxy::simplify(&empty, 0.5),
        Err(WarpError::EmptyMesh(_))
    ));
    assert!(matches!(
        NormalBins::build(&empty, 4),
        Err(WarpError::EmptyMesh(_))
    ));
    let mesh = generate::icosphere(2, 1.0);
    for ratio in [0.0, -0.1, 1.5, f32::NAN, f32::INFINITY] {
        assert!(
            matches!(
                Proxy::simplify(&mesh, ratio),
                Err(WarpError::RatioOutOfRange(_))
            ),
            "ratio {ratio}"
        );
    }
    assert!(matches!(
        NormalBins::build(&mesh, 0),
        Err(WarpError::ZeroBins(0))
    ));
    assert!(matches!(
        NormalBins::build(&mesh, 100_000),
        Err(WarpError::TooManyBins(_))
    ));
    let mut broken = mesh.clone();
    broken.indices.push(9999);
    broken.indices.push(0);
    broken.indices.push(1);
    assert!(matches!(
        Proxy::simplify(&broken, 0.5),
        Err(WarpError::InvalidMesh(_))
    ));
    let mut nan = mesh.clone();
    nan.positions[0] = Vec3::NAN;
    assert!(Proxy::simplify(&nan, 0.5).is_err());
    // Every error explains itself.
    let e = Proxy::simplify(&mesh, 5.0).unwrap_err();
    assert!(e.to_string().contains("(0, 1]"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random small meshes, valid or not, never panic: they simplify and bin, or return a
    /// typed error.
    #[test]
    fn random_meshes_never_panic(
        positions in prop::collection::vec((-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0), 0..24),
        indices in prop::collection::vec(0u32..30, 0..60),
        ratio in -0.5f32..1.5,
        n in 0u32..6,
    ) {
        let positions: Vec<Vec3> = positions.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect();
        let mesh = Mesh {
            normals: vec![Vec3::Z; positions.len()],
            uvs: vec![Vec2::ZERO; positions.len()],
            positions,
            indices,
        };
        if let Ok(proxy) = Proxy::simplify(&mesh, ratio) {
            prop_assert!(proxy.triangles() >= 1);
        }
        if let Ok(bins) = NormalBins::build(&mesh, n) {
            let p = plan(&bins, Vec3::new(0.0, 0.0, 5.0), [Vec3::X * 5.0, Vec3::Y * 5.0], 0.3, &PlanSettings::default());
            prop_assert!(p.weights.len() == bins.len());
        }
    }
}
