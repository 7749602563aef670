//! A frame's `N = H` centres: the CPU search, coherent from frame to frame.

use super::{HighlightSet, valid_input};
use glam::Mat4;
use npr_geometry::{HighlightCentre, HighlightSearch, LightEye};
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

impl HighlightSet {
    /// The search of this set's mesh: what [`crate::gpu::CentreSearchPass`] uploads and solves.
    pub fn search(&self) -> &HighlightSearch {
        &self.search
    }

    /// The `N = H` search (§3.1) of this frame and its wall time, microseconds: no centres
    /// for non-finite or zero light/eye input.
    pub(super) fn search_centres(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> (Vec<HighlightCentre>, f64) {
        let search_start = Instant::now();
        let centres = if valid_input(light_eye, world_from_object) {
            self.search
                .find_coherent(&mut self.coherence, light_eye, world_from_object)
        } else {
            Vec::new()
        };
        let search_us = search_start.elapsed().as_secs_f64() * 1e6;
        (centres, search_us)
    }
}
