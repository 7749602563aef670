//! The one settings type of a mesh's highlights ([`SpecularSettings`]): plain data, what a
//! preset or an embedder's panel maps onto. What a frame reads ([`HighlightTuning`]) lives
//! in the set ([`HighlightSet::tuning`]) and may change any frame; the curvature, the
//! abstraction and the backend are the set's build and take a new
//! [`crate::HighlightSetup::create_object`] to change.

use crate::{BackendSetting, HighlightBoundary, HighlightSet, HighlightSizing, ProjectorControls};
use npr_geometry::CurvatureOptions;

/// Everything that decides a mesh's highlights.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecularSettings {
    /// The curvature the set is built on (its ball radius: the smoothing).
    pub curvature: CurvatureOptions,
    /// The scale the highlights see the surface at, in bounding radii (0: the raw
    /// surface; [`HighlightSet::with_abstraction`]).
    pub abstraction: f32,
    /// Which backend sets the highlights up ([`crate::Backend::choose`]).
    pub backend: BackendSetting,
    /// What each frame reads.
    pub tuning: HighlightTuning,
}

impl Default for SpecularSettings {
    fn default() -> Self {
        Self {
            curvature: CurvatureOptions::default(),
            abstraction: crate::DEFAULT_ABSTRACTION,
            backend: BackendSetting::default(),
            tuning: HighlightTuning::default(),
        }
    }
}

/// The settings a frame's update reads (both backends read them every frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightTuning {
    /// Controls applied to every highlight (composed with per-highlight controls, §3.4):
    /// σ, texture, up axis, tint, transforms.
    pub controls: ProjectorControls,
    /// The `r` of Eq. (8)'s cap `s ≤ 2r`, in object units. The paper uses its curvature
    /// ball radius; ours is a few edge lengths (for accuracy), which would cap every
    /// highlight at a few triangles, so `None` (the default) uses the larger of that
    /// radius and 15 % of the mesh's bounding-sphere radius.
    pub size_cap_radius: Option<f32>,
    /// Updates over which a highlight fades in or out (0 = pop; default 6).
    pub fade_frames: u32,
    /// Matching radius as a multiple of the previous frustum's larger half-extent
    /// (default 1).
    pub match_radius: f32,
    /// Projector sizing: the measured region (default) or the paper's Eq. (8).
    pub sizing: HighlightSizing,
    /// How a highlight's edge meets the surface (default: a smooth per-pixel falloff).
    pub boundary: HighlightBoundary,
    /// [`HighlightSizing::Region`]: smallest region kept, as a fraction of the squared
    /// bounding-sphere radius (default 5·10⁻⁴: about 20 px when the mesh fills a
    /// 640×480 view).
    pub min_region_area: f32,
    /// [`HighlightSizing::Region`]: a receiver's face normal must make `cos ≥` this with
    /// the projector's axis (default 0.3, so the texture stretches at most 1/0.3 ≈ 3.3:1
    /// and never wraps onto another limb); the paper's rule is `> 0`.
    pub receiver_min_cos: f32,
    /// [`HighlightSizing::Region`]: receivers must also lie within the measured region's
    /// normal cone ([`crate::Footprint::normal_cone_cos`]) widened by this angle, radians
    /// (default 10°).
    pub receiver_cone_margin_rad: f32,
    /// Largest relative change of a found highlight's footprint area from one update to
    /// the next (default 0.25); the footprint catches up over a few updates instead of
    /// jumping when its region merges or splits. ≤ 0 disables the limit.
    pub max_area_change: f32,
}

impl Default for HighlightTuning {
    fn default() -> Self {
        Self {
            controls: ProjectorControls::default(),
            size_cap_radius: None,
            fade_frames: 6,
            match_radius: 1.0,
            sizing: HighlightSizing::default(),
            boundary: HighlightBoundary::default(),
            min_region_area: 5e-4,
            receiver_min_cos: 0.3,
            receiver_cone_margin_rad: 10f32.to_radians(),
            max_area_change: 0.25,
        }
    }
}

impl SpecularSettings {
    /// The set these settings build for `mesh` (its curvature and abstraction), tuned.
    ///
    /// # Errors
    /// As [`HighlightSet::with_abstraction`].
    pub fn build(&self, mesh: &npr_geometry::Mesh) -> Result<HighlightSet, crate::SpecularError> {
        let mut set = HighlightSet::with_abstraction(mesh, &self.curvature, self.abstraction)?;
        set.tuning = self.tuning;
        Ok(set)
    }
}
