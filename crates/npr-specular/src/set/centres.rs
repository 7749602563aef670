//! Where a frame's `N = H` centres come from: the CPU search, coherent from frame to
//! frame, or the faces a solve elsewhere accepted (the GPU search,
//! [`crate::CentreSearchPass`]).

use super::{Highlight, HighlightSet, valid_input};
use glam::Mat4;
use npr_geometry::{HighlightCentre, HighlightSearch, LightEye};
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

impl HighlightSet {
    /// [`HighlightSet::update`] on the faces an `N = H` solve elsewhere accepted (the GPU
    /// search, [`crate::CentreSearchPass`], for this light, eye and transform) in place of
    /// the CPU search: the same centres once merged
    /// ([`HighlightSearch::centres_from_solutions`]), then the same matching, fades,
    /// projectors and receivers.
    pub fn update_from_solutions(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        solutions: &[npr_geometry::FaceSolution],
    ) -> &[Highlight] {
        let centres = self.solution_centres(light_eye, world_from_object, solutions);
        self.update_with(light_eye, world_from_object, centres, None, None)
    }

    /// [`HighlightSet::update`] on centres found elsewhere (the GPU's, merged and computed
    /// there: [`crate::SearchSolutions::centres`]) for this light, eye and transform, in
    /// the order the CPU's merge gives them ([`HighlightSearch::centres_from_solutions`]).
    pub fn update_from_centres(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        centres: &[HighlightCentre],
    ) -> &[Highlight] {
        let centres = given_centres(light_eye, world_from_object, centres);
        self.update_with(light_eye, world_from_object, centres, None, None)
    }

    /// [`HighlightSet::update_from_centres`] with the regions grown by `regions`, as
    /// [`HighlightSet::update_from_solutions_and_regions`].
    pub fn update_from_centres_and_regions(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        centres: &[HighlightCentre],
        regions: super::RegionsOnGpu<'_>,
    ) -> &[Highlight] {
        let centres = given_centres(light_eye, world_from_object, centres);
        self.update_with(light_eye, world_from_object, centres, Some(regions), None)
    }

    /// [`HighlightSet::update_from_solutions`] with the regions grown by `regions` (the
    /// GPU: [`crate::RegionPass`] on the seeds it is given) in place of the CPU's grower:
    /// the same matching, fades and controls, the footprints, overlap scales and pieces
    /// of its regions. Where `regions` gives `None` (or not one region per seed), the
    /// CPU grows them for that frame.
    pub fn update_from_solutions_and_regions(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        solutions: &[npr_geometry::FaceSolution],
        regions: super::RegionsOnGpu<'_>,
    ) -> &[Highlight] {
        let centres = self.solution_centres(light_eye, world_from_object, solutions);
        self.update_with(light_eye, world_from_object, centres, Some(regions), None)
    }

    /// The update a GPU search's list (`solved`; one that overflowed, see
    /// [`crate::SearchSolutions::complete`], is searched again on the CPU) asks for: on
    /// its centres merged on the GPU
    /// where it has them ([`HighlightSet::update_from_centres`]), with its peaks where it
    /// found them ([`crate::SearchSolutions::peaks`], in place of the update's own search
    /// for them), else on its accepted faces merged here
    /// ([`HighlightSet::update_from_solutions`]); with the regions of `regions` where
    /// given (the `_and_regions` forms).
    pub fn update_from_search(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        solved: &crate::SearchSolutions,
        regions: Option<super::RegionsOnGpu<'_>>,
    ) -> &[Highlight] {
        if !solved.complete() {
            // An overflowed list: the CPU's own search for the frame.
            let centres = self.search_centres(light_eye, world_from_object);
            return self.update_with(light_eye, world_from_object, centres, regions, None);
        }
        // The GPU's peaks where found at this set's σ.
        let peaks = solved
            .peaks
            .as_deref()
            .filter(|_| solved.peak_sigma == Some(self.global.sigma));
        let (centres, peaks) = match &solved.centres {
            Some(centres) => (given_centres(light_eye, world_from_object, centres), peaks),
            None => (
                self.solution_centres(light_eye, world_from_object, &solved.faces),
                None,
            ),
        };
        self.update_with(light_eye, world_from_object, centres, regions, peaks)
    }

    /// The centres of `solutions` ([`HighlightSearch::centres_from_solutions`]) and the
    /// time the merge took, microseconds: none for non-finite or zero light/eye input.
    fn solution_centres(
        &self,
        light_eye: LightEye,
        world_from_object: Mat4,
        solutions: &[npr_geometry::FaceSolution],
    ) -> (Vec<HighlightCentre>, f64) {
        let start = Instant::now();
        let centres = if valid_input(light_eye, world_from_object) {
            self.search
                .centres_from_solutions(solutions, world_from_object)
        } else {
            Vec::new()
        };
        (centres, start.elapsed().as_secs_f64() * 1e6)
    }

    /// The search of this set's mesh: what [`crate::CentreSearchPass`] uploads and solves.
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

/// Centres found elsewhere, as an update takes them (none for non-finite or zero
/// light/eye input, as the CPU search finds), with no search time of the CPU's own.
fn given_centres(
    light_eye: LightEye,
    world_from_object: Mat4,
    centres: &[HighlightCentre],
) -> (Vec<HighlightCentre>, f64) {
    if valid_input(light_eye, world_from_object) {
        (centres.to_vec(), 0.0)
    } else {
        (Vec::new(), 0.0)
    }
}
