//! CPU test of frame coherence in a still view: the light, the eye and the object do not
//! move, so every highlight keeps its id and stays found from one update to the next, on
//! the scans and a CAD part, at scale 0 (where bright regions without an `N = H` point
//! sit beside small `N = H` centres) and at the default abstraction, from the fidelity
//! bench's views.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use npr_geometry::{CurvatureOptions, LightEye};
use npr_specular::HighlightSet;
use npr_specular::fidelity::{standard_views, unit_sphere_transform};

mod common;
use common::fixture;

#[test]
fn a_still_view_keeps_every_highlight() {
    let mut failures = Vec::new();
    let mut peaks = 0;
    for name in ["spot.obj", "stanford-bunny.obj", "hammer.obj"] {
        let mesh = fixture(name);
        let views = standard_views(unit_sphere_transform(&mesh), 6, 4.0 / 3.0);
        for abstraction in [0.0, 0.05] {
            let mut set =
                HighlightSet::with_abstraction(&mesh, &CurvatureOptions::default(), abstraction)
                    .unwrap();
            for (k, view) in views.iter().enumerate() {
                let le = LightEye::Positions {
                    light: view.to_light * 1e4,
                    eye: view.camera.eye,
                };
                set.reset();
                set.update(le, view.world_from_object);
                let first: Vec<u64> = set.highlights().iter().map(|h| h.id).collect();
                peaks += set.highlights().iter().filter(|h| h.peak).count();
                for step in 1..4 {
                    set.update(le, view.world_from_object);
                    let ids: Vec<u64> = set.highlights().iter().map(|h| h.id).collect();
                    let lost = set.highlights().iter().filter(|h| !h.found).count();
                    if ids != first || lost > 0 {
                        failures.push(format!(
                            "{name} at {abstraction}, view {k}, update {step}: ids {ids:?} \
                             (first {first:?}), {lost} lost"
                        ));
                        break;
                    }
                }
            }
        }
    }
    // The views must hold peaks beside N = H centres, or the test proves little.
    assert!(peaks > 20, "only {peaks} peaks in the views");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
