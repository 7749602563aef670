//! The `[specular]` section of a preset: the highlights' settings, their backend
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
    /// Which highlight backend runs (`search` in older presets).
    #[serde(alias = "search")]
    pub backend: BackendPreset,
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
            backend: BackendPreset::default(),
            edits: Vec::new(),
        }
    }
}

impl From<&SpecularPreset> for npr_specular::SpecularSettings {
    /// The preset's highlight settings (the texture layer of a shape the highlight pass
    /// holds is the pass's to set: `controls.texture_layer`).
    fn from(p: &SpecularPreset) -> Self {
        use npr_geometry::{CurvatureOptions, CurvatureRadius};
        Self {
            curvature: CurvatureOptions {
                radius: CurvatureRadius::EdgeLengths(p.smoothing_edges),
                ..CurvatureOptions::default()
            },
            abstraction: p.abstraction,
            backend: p.backend.into(),
            tuning: npr_specular::HighlightTuning {
                controls: npr_specular::ProjectorControls {
                    sigma: p.sigma,
                    up: p.up.into(),
                    ..Default::default()
                },
                boundary: p.boundary.into(),
                ..Default::default()
            },
        }
    }
}

/// Which highlight backend sets up a model's highlights ([`SpecularPreset::backend`]):
/// `npr_specular::Backend::choose`'s rule, or one backend. Both give the same highlights
/// (`npr-specular`'s twin tests). Presets written before this key had `search = "auto" |
/// "cpu" | "gpu" | "gpu-frame"`; they still load, `"gpu"` and `"gpu-frame"` both meaning
/// the GPU backend.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BackendPreset {
    /// The rule: the CPU on a software adapter or one of unknown type (most browsers),
    /// the GPU frame on a real GPU; the CPU wherever the mesh's GPU tables exceed the
    /// device's limits.
    #[default]
    Auto,
    /// The CPU (`npr_specular::HighlightSet::update`).
    Cpu,
    /// The whole frame as compute passes, nothing read back on the frame's path: the
    /// search, the regions, the projectors with the user's edits and their receivers,
    /// and an animated model's pose. The panel and picking see each frame's highlights
    /// one frame late.
    #[serde(alias = "gpu-frame")]
    Gpu,
}

impl From<BackendPreset> for npr_specular::BackendSetting {
    fn from(b: BackendPreset) -> Self {
        match b {
            BackendPreset::Auto => Self::Auto,
            BackendPreset::Cpu => Self::Cpu,
            BackendPreset::Gpu => Self::Gpu,
        }
    }
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
