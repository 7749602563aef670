//! The watch list's invariant, checked on the search's private bounds.

use super::coherence::Budget;
use super::search::VertexScratch;
use super::*;
use crate::Topology;
use glam::Mat4;

/// The watch list's invariant itself: after the light and eye move by up to the
/// budget, every vertex that passes its exact test is on the list (the results'
/// equality alone rarely exposes a loose bound, since centres sit far from the
/// thresholds).
#[test]
fn every_vertex_that_can_pass_within_the_budget_is_watched() {
    let path = format!(
        "{}/../../fixtures/meshes/stanford-bunny.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let mesh = crate::load_obj(&path).unwrap();
    let welded = crate::weld(&mesh);
    let topo = Topology::new(&welded);
    let field = CurvatureField::compute(&topo, &crate::CurvatureOptions::default());
    let s = HighlightSearch::for_mesh(&mesh, &welded, &topo, &field);
    let nv = s.positions.len();
    let (lo, hi) = s.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let world = Mat4::from_scale_rotation_translation(
        Vec3::splat(2.5),
        glam::Quat::from_rotation_y(0.4),
        Vec3::new(0.5, 0.0, -1.0),
    );
    let w = |p: Vec3| world.transform_point3(p);
    let (light, eye) = (
        w(c + Vec3::new(6.0 * r, 8.0 * r, 10.0 * r)),
        w(c + Vec3::new(0.0, 0.5 * r, 3.0 * r)),
    );
    let key = s.setup(LightEye::Positions { light, eye }, world).unwrap();
    // Budget in object units: 0.3 r for the light and the eye.
    let budget = Budget {
        angle: 0.0,
        light: 0.3 * r,
        eye: 0.3 * r,
    };
    let active = s.active_vertices(&key, budget);
    let watch = s.watch_list(&key, &active, budget);
    let mut watched = vec![false; nv];
    for &v in &watch {
        watched[v as usize] = true;
    }
    let all: Vec<u32> = (0..nv as u32).collect();
    let mut scratch = VertexScratch::default();
    let mut rng = 0x2545_f491_u32;
    let mut unit = || {
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 17;
            rng ^= rng << 5;
            rng as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        Vec3::new(next(), next(), next()).normalize()
    };
    let mut passing = 0;
    for k in 0..24 {
        // World displacement of 0.999 × budget in object units (scale 2.5).
        let (dl, de) = (
            unit() * 0.999 * 0.3 * r * 2.5,
            unit() * 0.999 * 0.3 * r * 2.5,
        );
        let frame = s
            .setup(
                LightEye::Positions {
                    light: light + dl,
                    eye: eye + de,
                },
                world,
            )
            .unwrap();
        s.test_vertices(&frame, &all, &mut scratch);
        for (v, (&p, &w)) in scratch.pass.iter().zip(&watched).enumerate() {
            if p {
                passing += 1;
                assert!(w, "pose {k}: vertex {v} passes but is not watched");
            }
        }
        scratch.pass.fill(false);
    }
    assert!(passing > 0);
    assert!(watch.len() < nv / 2, "{} of {nv} watched", watch.len());
}
