//! A set on a new pose of its mesh: the CPU's repose, and what a repose made elsewhere
//! (the GPU's, `crate::gpu::ReposePass`) keeps from the built pose.

use super::HighlightSet;
use crate::SpecularError;
use npr_geometry::{CurvatureField, CurvatureOptions, CurvatureRadius, Mesh};

impl HighlightSet {
    /// The same set on a new pose of its mesh (a skinned or morphed character's next
    /// frame: the same triangles, moved vertices): the topology, curvature, search and
    /// regions are rebuilt on `mesh` at the set's abstraction, while the settings, the
    /// per-highlight controls (the user's edits), the last update's highlights and the id
    /// counter carry over, so the next [`HighlightSet::update`] matches its highlights to
    /// the last ones and keeps their ids, fades and edits.
    ///
    /// The pose is measured at the scales of the pose the set was built on: the
    /// curvature's ball radius in world units (`options`' radius is taken there: a part
    /// the pose stretches keeps its ball) and the abstraction's diffusion steps (its
    /// smoothing follows the surface as it stretches) and the falloff's floor (the typical
    /// turn of the normal across a face), as a pose made on the GPU keeps
    /// them ([`crate::gpu::FrameOnGpu::pose_on_gpu`]); its principal directions at that scale
    /// are signed as the measured field's ([`CurvatureField::at_steps`]), as the GPU's.
    ///
    /// # Errors
    /// As [`HighlightSet::with_abstraction`]; [`SpecularError::Mismatch`] when `mesh` has
    /// another face count (then the set is unchanged).
    pub fn repose(&mut self, mesh: &Mesh, options: &CurvatureOptions) -> Result<(), SpecularError> {
        let built = CurvatureOptions {
            radius: CurvatureRadius::World(self.ball_radius),
            ..*options
        };
        let (welded, topology, field) = CurvatureField::for_mesh(mesh, &built);
        let steps = (self.abstraction, Some(self.diffusion_steps));
        let mut next = Self::from_field(mesh, (&welded, topology), &field, steps)?;
        if next.topology.face_count() != self.topology.face_count() {
            return Err(SpecularError::Mismatch(format!(
                "a pose of {} faces for a set of {}",
                next.topology.face_count(),
                self.topology.face_count()
            )));
        }
        // The falloff's floor is a scale of the built mesh too (the GPU's poses keep it).
        next.face_turn = self.face_turn;
        next.tuning.controls = self.tuning.controls;
        next.per_highlight = std::mem::take(&mut self.per_highlight);
        next.tuning.size_cap_radius = self.tuning.size_cap_radius;
        next.tuning.fade_frames = self.tuning.fade_frames;
        next.tuning.match_radius = self.tuning.match_radius;
        next.tuning.sizing = self.tuning.sizing;
        next.tuning.boundary = self.tuning.boundary;
        next.tuning.min_region_area = self.tuning.min_region_area;
        next.tuning.receiver_min_cos = self.tuning.receiver_min_cos;
        next.tuning.receiver_cone_margin_rad = self.tuning.receiver_cone_margin_rad;
        next.tuning.max_area_change = self.tuning.max_area_change;
        next.highlights = std::mem::take(&mut self.highlights);
        next.next_id = self.next_id;
        next.tracking = self.tracking;
        next.search.interpolation = self.search.interpolation;
        *self = next;
        Ok(())
    }

    /// The abstraction's diffusion steps, fixed when the set was built (0 without an
    /// abstraction).
    pub(crate) fn diffusion_steps(&self) -> usize {
        self.diffusion_steps
    }
}
