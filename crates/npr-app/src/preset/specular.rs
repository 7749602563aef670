//! The `[specular]` section of a preset: the highlights' settings, their search path
//! and the user's own edits.

use serde::{Deserialize, Serialize};

/// Up axis of the highlight projectors (Lee & Choi Eq. (7)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum UpPreset {
    /// Up = e_min (the paper's choice).
    #[default]
    EMin,
    /// Up = e_max.
    EMax,
}

impl From<UpPreset> for npr_specular::UpAxis {
    fn from(u: UpPreset) -> Self {
        match u {
            UpPreset::EMin => Self::KappaMin,
            UpPreset::EMax => Self::KappaMax,
        }
    }
}

/// One highlight's own §3.4 edit, keyed by its id (stable while it is tracked).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HighlightEdit {
    /// The highlight's id.
    pub id: u64,
    /// The found centre of the highlight when it was edited, object space (the model's own
    /// units). When set, the edit applies to the highlight found nearest to it, so a preset
    /// saved after orbiting (when ids have moved on) edits the same highlight in a fresh
    /// `npr render`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub anchor: Option<[f32; 3]>,
    /// Translation along (e_max, e_min), in bounding radii.
    pub translate: [f32; 2],
    /// Rotation about N, degrees.
    pub rotate_deg: f32,
    /// Scale along (e_max, e_min).
    pub scale: [f32; 2],
}

impl Default for HighlightEdit {
    fn default() -> Self {
        Self {
            id: 0,
            anchor: None,
            translate: [0.0, 0.0],
            rotate_deg: 0.0,
            scale: [1.0, 1.0],
        }
    }
}

/// Largest `specular.abstraction` a preset takes (a fifth of the model's radius).
pub const MAX_ABSTRACTION: f32 = 0.2;

/// Stylized specular highlights (npr-specular).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpecularPreset {
    /// Highlight threshold σ of Eq. (8), in (−1, 1).
    pub sigma: f32,
    /// A built-in shape (`disc`, `soft-disc`, `star`, `sparkle`, `ring`, `normal-map`,
    /// `streak`) or the path of a PNG.
    pub shape: String,
    /// Projector up axis.
    pub up: UpPreset,
    /// Curvature ball radius in mean edge lengths (the curvature smoothing).
    pub smoothing_edges: f32,
    /// The scale the highlights see the surface at, in units of the model's bounding
    /// radius (`npr_specular::HighlightSet::with_abstraction`): 0 is one highlight per
    /// bump of the raw surface, the default a cartoon scale (a few per form).
    pub abstraction: f32,
    /// Where a highlight's edge meets the surface: `smooth` (a per-pixel falloff) or
    /// `per-face` (whole faces, the edge steps along triangles).
    pub boundary: BoundaryPreset,
    /// k_s of the base shading under the highlights (0: the stylized highlight replaces
    /// the base's own).
    pub base_ks: f32,
    /// Where the per-frame `N = H` search runs.
    pub search: SearchPreset,
    /// Per-highlight edits.
    pub edits: Vec<HighlightEdit>,
}

impl Default for SpecularPreset {
    fn default() -> Self {
        Self {
            sigma: 0.9,
            shape: "disc".into(),
            up: UpPreset::EMin,
            smoothing_edges: 3.0,
            abstraction: npr_specular::DEFAULT_ABSTRACTION,
            boundary: BoundaryPreset::Smooth,
            base_ks: 0.0,
            search: SearchPreset::default(),
            edits: Vec::new(),
        }
    }
}

/// Where the per-frame `N = H` search of the highlights runs ([`SpecularPreset::search`]),
/// and with it the §4.2 receivers. Both give the same centres (the GPU solves in `f32`;
/// `npr-specular`'s `tests/gpu_search.rs`) and the same receivers
/// (`tests/gpu_receivers.rs`); on the GPU the regions are grown there too
/// (`tests/gpu_regions.rs`), while matching and projectors stay on the CPU either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SearchPreset {
    /// The fastest of the three for the model, timed on its first frame (the whole
    /// highlight update each way twice, the second timing kept; the whole frame on the
    /// GPU with its submission and wait) and again when the model or its highlight set
    /// changes.
    #[default]
    Auto,
    /// On the CPU (`npr_geometry::HighlightSearch`, coherent from frame to frame).
    Cpu,
    /// As a compute pass (`npr_specular::CentreSearchPass`), its list merged into centres
    /// there and read back,
    /// the regions grown and fitted by another (`npr_specular::RegionPass`, one record a
    /// highlight read back), and the receivers walked by a third
    /// (`npr_specular::ReceiverPass`) in the frame's submission, drawn from the stream it
    /// writes. In the browser, where a readback
    /// completes only between frames, the search is the CPU's and the walk the GPU's.
    Gpu,
    /// The whole frame's highlights on the GPU, nothing read back on the frame's path
    /// (`npr_specular::FrameOnGpu`: the search, the regions seeded from its centres
    /// matched with the GPU's own table of the last frame, the highlights made into
    /// projectors by `npr_specular::ProjectorPass` with the user's edits, their receivers
    /// walked and drawn where they lie). The panel and picking see each frame's
    /// highlights one frame late. Also in the browser.
    GpuFrame,
}

/// Where a highlight's edge meets the surface (`npr_specular::HighlightBoundary`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundaryPreset {
    /// A falloff on the interpolated normal, smooth per pixel; edits widen it.
    #[default]
    Smooth,
    /// Whole faces in or out (edges step along triangles).
    PerFace,
}

impl From<BoundaryPreset> for npr_specular::HighlightBoundary {
    fn from(b: BoundaryPreset) -> Self {
        match b {
            BoundaryPreset::Smooth => Self::Smooth,
            BoundaryPreset::PerFace => Self::PerFace,
        }
    }
}
