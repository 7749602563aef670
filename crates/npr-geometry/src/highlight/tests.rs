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

/// `visit_ranks` and `merge_distance` are all a merge elsewhere needs: solutions sorted by
/// rank and merged one by one (a later one within the distance of a kept one replaces it
/// when deeper inside its face, else is dropped) give `centres_from_solutions`, on a list
/// shuffled so that its own order says nothing, and full of pairs that merge.
#[test]
fn ranks_and_the_merge_distance_reproduce_the_merge() {
    let mesh = crate::generate::torus(1.0, 0.4, 24, 12);
    let welded = crate::weld(&mesh);
    let topo = Topology::new(&welded);
    let field = CurvatureField::compute(&topo, &crate::CurvatureOptions::default());
    let s = HighlightSearch::for_mesh(&mesh, &welded, &topo, &field);
    let ranks = s.visit_ranks();
    let mut seen = ranks.clone();
    seen.sort_unstable();
    assert!(
        seen.iter().enumerate().all(|(i, &r)| r == i as u32),
        "a permutation"
    );
    // Points near each face's first corner: the faces around a vertex merge into one.
    let mut solutions: Vec<FaceSolution> = (0..s.triangles.len() as u32)
        .map(|f| FaceSolution {
            face: f,
            alpha: 1e-4 * (1 + f % 7) as f32,
            beta: 1e-4 * (1 + f % 5) as f32,
        })
        .collect();
    // A fixed shuffle (multiplicative stride, coprime with the length).
    let n = solutions.len();
    let stride = (1..n)
        .rev()
        .find(|k| gcd(*k, n) == 1 && *k < n / 2 + 7)
        .unwrap();
    solutions = (0..n).map(|i| solutions[i * stride % n]).collect();
    let world = Mat4::from_rotation_x(0.3);
    let expected = s.centres_from_solutions(&solutions, world);
    let mut sorted = solutions.clone();
    sorted.sort_by_key(|x| ranks[x.face as usize]);
    let mut kept: Vec<(FaceSolution, Vec3, f32)> = Vec::new();
    let d = s.merge_distance();
    for x in sorted {
        let t = s.triangles[x.face as usize].map(|i| s.positions[i as usize]);
        let p = t[0] + x.alpha * (t[1] - t[0]) + x.beta * (t[2] - t[0]);
        let inner = x.alpha.min(x.beta).min(1.0 - x.alpha - x.beta);
        match kept.iter_mut().find(|k| k.1.distance(p) <= d) {
            Some(k) if inner > k.2 => *k = (x, p, inner),
            Some(_) => {}
            None => kept.push((x, p, inner)),
        }
    }
    assert!(
        kept.len() * 5 < n * 3,
        "{} of {n} kept: the list merges",
        kept.len()
    );
    let merged: Vec<FaceSolution> = kept.iter().map(|k| k.0).collect();
    let got = s.centres_at_solutions(&merged, world);
    assert_eq!(got.len(), expected.len());
    for (g, e) in got.iter().zip(&expected) {
        assert_eq!((g.face, g.alpha, g.beta), (e.face, e.alpha, e.beta));
    }
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}
