//! Presets: every parameter the crates expose, as one TOML file shared by `npr render` and
//! `npr view` (a preset saved by the viewer renders the same image in batch).
//!
//! Every section and field is optional; what a file leaves out keeps its default, so a
//! preset can be as short as `effect = "hatching-pen"`. Unknown keys are errors (a typo must
//! not be silently ignored). See `fixtures/presets/example.toml` for a full file.

use crate::AppError;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

mod specular;
pub use specular::{
    BackendPreset, BoundaryPreset, HighlightEdit, MAX_ABSTRACTION, SpecularPreset, UpPreset,
};

/// What `npr render` draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(not(target_arch = "wasm32"), derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Effect {
    /// Per-pixel Blinn-Phong.
    #[default]
    Phong,
    /// Per-vertex Blinn-Phong.
    Gouraud,
    /// Cel shading with a 1-D ramp.
    Cel,
    /// Stylized specular highlights (Lee & Choi) over the base shading.
    Specular,
    /// Image-space hatching (Kim & Lee), pen tonal art map.
    HatchingPen,
    /// Image-space hatching, pencil tonal art map.
    HatchingPencil,
    /// Post-rendering 3-D warping (Park & Ihm) of the base shading.
    Warp,
}

impl Effect {
    /// Every effect, in CLI order.
    pub const ALL: [Effect; 7] = [
        Self::Phong,
        Self::Gouraud,
        Self::Cel,
        Self::Specular,
        Self::HatchingPen,
        Self::HatchingPencil,
        Self::Warp,
    ];

    /// The CLI / preset name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Phong => "phong",
            Self::Gouraud => "gouraud",
            Self::Cel => "cel",
            Self::Specular => "specular",
            Self::HatchingPen => "hatching-pen",
            Self::HatchingPencil => "hatching-pencil",
            Self::Warp => "warp",
        }
    }

    /// Parses a CLI / preset name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }

    /// Whether the effect hatches.
    pub fn is_hatching(self) -> bool {
        matches!(self, Self::HatchingPen | Self::HatchingPencil)
    }
}

/// The base shading model under every technique.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BaseModel {
    /// Per-pixel Blinn-Phong.
    #[default]
    Phong,
    /// Per-vertex Blinn-Phong.
    Gouraud,
    /// Cel shading.
    Cel,
}

impl From<BaseModel> for npr_gpu::ShadingModel {
    fn from(m: BaseModel) -> Self {
        match m {
            BaseModel::Phong => Self::Phong,
            BaseModel::Gouraud => Self::Gouraud,
            BaseModel::Cel => Self::Cel,
        }
    }
}

/// Orbit camera around the framed model. Distances are in bounding radii, so a preset
/// works for a model at any scale.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraPreset {
    /// Rotation about the vertical axis, degrees (0 looks from +z).
    pub yaw_deg: f32,
    /// Elevation, degrees (positive looks down on the model).
    pub pitch_deg: f32,
    /// Eye distance from the model's centre, in bounding radii.
    pub distance: f32,
    /// Vertical field of view, degrees.
    pub fov_deg: f32,
    /// Pan of the look-at point, in bounding radii (camera right, camera up).
    pub pan: [f32; 2],
}

impl Default for CameraPreset {
    fn default() -> Self {
        Self {
            yaw_deg: 25.0,
            pitch_deg: 15.0,
            distance: 3.0,
            fov_deg: 40.0,
            pan: [0.0, 0.0],
        }
    }
}

/// A directional light, fixed in the world (the model turns under it).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LightPreset {
    /// Direction towards the light, world space (normalised on use).
    pub direction: [f32; 3],
    /// Linear light colour.
    pub color: [f32; 3],
    /// Linear ambient colour.
    pub ambient: [f32; 3],
}

impl Default for LightPreset {
    fn default() -> Self {
        Self {
            direction: [-0.5, 0.8, 1.0],
            color: [1.0, 1.0, 1.0],
            ambient: [0.08, 0.08, 0.08],
        }
    }
}

/// Base shading and material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BasePreset {
    /// Shading model under `specular` and `warp` (the `phong`/`gouraud`/`cel` effects
    /// choose their own).
    pub model: BaseModel,
    /// Linear diffuse albedo.
    pub diffuse: [f32; 3],
    /// Specular weight k_s of the base shading.
    pub ks: f32,
    /// Blinn exponent.
    pub shininess: f32,
    /// Cel ramp: sRGB grey levels 0..255 of its bands, darkest first.
    pub cel_bands: Vec<u8>,
    /// Linear background colour.
    pub background: [f32; 3],
}

impl Default for BasePreset {
    fn default() -> Self {
        Self {
            model: BaseModel::Phong,
            diffuse: [0.8, 0.8, 0.8],
            ks: 0.5,
            shininess: 32.0,
            cel_bands: vec![89, 166, 255],
            background: [1.0, 1.0, 1.0],
        }
    }
}

/// Where hatching strokes take their direction from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DirectionPreset {
    /// The smooth line field fitted to the direction of maximum curvature (Knöppel et al.
    /// 2013): strokes flow instead of following every bump of a scan. Cut at creases
    /// (50°) and straight on flat faces: a flat face joined smoothly to a
    /// curved one carries its direction, one bounded by creases takes `up × n`
    /// (`x × n` within 30° of facing up).
    #[default]
    Smooth,
    /// The same field without the crease cuts and the flat-face rule (the curvature-only field).
    SmoothCurvatureOnly,
    /// The raw direction of maximum curvature, vertex by vertex.
    KMax,
    /// The raw direction of minimum curvature, vertex by vertex.
    KMin,
}

/// Ink outlines: silhouettes and creases over any effect (`npr_gpu::outline`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutlinePreset {
    /// Draw outlines.
    pub enabled: bool,
    /// Line width in pixels (1..=15).
    pub width_px: f32,
    /// Linear RGB line colour.
    pub color: [f32; 3],
    /// Neighbouring normals turned by more than this make a crease line, degrees.
    pub crease_deg: f32,
}

impl Default for OutlinePreset {
    fn default() -> Self {
        let d = npr_gpu::outline::OutlineSettings::default();
        Self {
            enabled: false,
            width_px: d.width_px,
            color: d.color,
            crease_deg: d.crease_angle_deg,
        }
    }
}

impl OutlinePreset {
    /// The outline pass settings.
    pub fn settings(&self) -> npr_gpu::outline::OutlineSettings {
        npr_gpu::outline::OutlineSettings {
            width_px: self.width_px,
            color: self.color,
            crease_angle_deg: self.crease_deg,
            ..Default::default()
        }
        .sanitized()
    }
}

/// Blend of direction bins (Kim & Lee §3.2–§3.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BlendPreset {
    /// One bin per pixel.
    CutAndPaste,
    /// Neighbouring bins blended (Eq. (2)–(3)).
    Blended,
    /// Blended plus a half-bin offset partition (§3.3).
    #[default]
    Offset,
}

impl From<BlendPreset> for npr_hatching::BlendMode {
    fn from(b: BlendPreset) -> Self {
        match b {
            BlendPreset::CutAndPaste => Self::CutAndPaste,
            BlendPreset::Blended => Self::Blended,
            BlendPreset::Offset => Self::OffsetPartition,
        }
    }
}

/// Where hatching strokes live (Kim & Lee, and beyond).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpacePreset {
    /// Surface-anchored strokes that move with the object at constant screen density
    /// (the default: no shower-door sliding).
    #[default]
    Surface,
    /// The paper's screen-space strokes.
    Screen,
}

impl From<SpacePreset> for npr_hatching::StrokeSpace {
    fn from(s: SpacePreset) -> Self {
        match s {
            SpacePreset::Surface => Self::Surface,
            SpacePreset::Screen => Self::Screen,
        }
    }
}

/// Image-space hatching (npr-hatching).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HatchingPreset {
    /// Direction bins (Eq. (1)).
    pub bins: u32,
    /// Stroke scale (1 = the tonal art map's own).
    pub stroke_scale: f32,
    /// Bin blending.
    pub blend: BlendPreset,
    /// Variance shadow maps.
    pub shadows: bool,
    /// Stroke direction source.
    pub direction: DirectionPreset,
    /// Surface-anchored (coherent) or the paper's screen-space strokes.
    pub space: SpacePreset,
    /// Linear ink colour.
    pub ink: [f32; 3],
    /// Linear paper colour.
    pub paper: [f32; 3],
}

impl Default for HatchingPreset {
    fn default() -> Self {
        let p = npr_hatching::HatchParams::default();
        Self {
            bins: p.bins,
            stroke_scale: p.stroke_scale,
            blend: BlendPreset::Offset,
            shadows: true,
            direction: DirectionPreset::Smooth,
            space: SpacePreset::Surface,
            ink: p.ink,
            paper: p.paper,
        }
    }
}

/// Which warping path (npr-warp's `Departures`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WarpMode {
    /// Ours: the paper's path plus every measured departure.
    #[default]
    Ours,
    /// The paper's path as published (§3.3.1–§3.3.3).
    Paper,
}

/// Antialiasing of the warp effect's references, warped frames and frames rendered in full
/// (npr-warp's `Antialiasing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WarpAntialiasing {
    /// One sample per pixel.
    #[default]
    None,
    /// 4× MSAA references, full frames and warp.
    Msaa4,
    /// 4× MSAA references and full frames; a one-sample warp blended at the rim by the
    /// references' coverage.
    Msaa4Blend,
}

impl From<WarpAntialiasing> for npr_warp::Antialiasing {
    fn from(a: WarpAntialiasing) -> Self {
        match a {
            WarpAntialiasing::None => npr_warp::Antialiasing::None,
            WarpAntialiasing::Msaa4 => npr_warp::Antialiasing::Msaa4,
            WarpAntialiasing::Msaa4Blend => npr_warp::Antialiasing::Msaa4Blend,
        }
    }
}

/// Post-rendering warping (npr-warp).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WarpPreset {
    /// A reference every k frames.
    pub k: u32,
    /// Proxy triangles as a share of the model's (at least 256 triangles are kept).
    pub proxy_ratio: f32,
    /// The paper's path or ours.
    pub mode: WarpMode,
    /// Depth-test each reference as a shadow map (one of our departures; ignored by the
    /// paper's path).
    pub depth_test: bool,
    /// Antialiasing of references, warped frames and the frames rendered in full (shown,
    /// and compared with warped frames for their PSNR); default none.
    pub antialiasing: WarpAntialiasing,
}

impl Default for WarpPreset {
    fn default() -> Self {
        Self {
            k: 10,
            proxy_ratio: 0.05,
            mode: WarpMode::Ours,
            depth_test: true,
            antialiasing: WarpAntialiasing::None,
        }
    }
}

impl WarpPreset {
    /// The departures from the paper this preset selects.
    pub fn departures(&self) -> npr_warp::Departures {
        match self.mode {
            WarpMode::Paper => npr_warp::Departures::PAPER,
            WarpMode::Ours => npr_warp::Departures {
                depth_test: self.depth_test,
                ..npr_warp::Departures::OURS
            },
        }
    }
}

/// Output settings of `npr render`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutputPreset {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Default for OutputPreset {
    fn default() -> Self {
        Self {
            width: 800,
            height: 600,
        }
    }
}

/// How a model's glTF clip plays (`npr render`, `npr view`; the command line's
/// `--animation`, `--time` and `--no-loop` override these).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AnimationPreset {
    /// The clip: its name, its index, `none` for the bind pose, or empty for the first.
    pub clip: String,
    /// The moment of the first frame, seconds into the clip.
    pub time: f32,
    /// Clip seconds per second of frames (1: as authored).
    pub speed: f32,
    /// Whether the clip wraps past its end (else it holds its last pose).
    #[serde(rename = "loop")]
    pub looped: bool,
    /// How the stroke directions follow the moving surface.
    pub geometry: PoseGeometry,
    /// Where the vertices the passes draw are posed.
    pub posing: Posing,
}

/// Where a posed frame's vertices are computed ([`AnimationPreset::posing`]). The
/// surface's geometry (curvature, highlights, directions) is taken on the CPU pose either
/// way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Posing {
    /// Posed on the CPU and uploaded (the faster on a software adapter, where a compute
    /// pass is CPU work too: `cargo xtask bench animation`'s posing table).
    #[default]
    Cpu,
    /// Posed by a compute pass into the vertex buffer (`npr_gpu::PosingPass`).
    Gpu,
}

/// How a posed frame gets its stroke directions ([`AnimationPreset::geometry`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PoseGeometry {
    /// Computed again on every pose (exact, the smooth field's solve each frame).
    Recompute,
    /// Computed once on the rest pose and carried through the skinning: exact where a
    /// part moves rigidly, an approximation near joints; a fraction of the cost.
    #[default]
    Carried,
}

impl Default for AnimationPreset {
    fn default() -> Self {
        Self {
            clip: String::new(),
            time: 0.0,
            speed: 1.0,
            looped: true,
            geometry: PoseGeometry::default(),
            posing: Posing::default(),
        }
    }
}

/// Every parameter of every effect.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Preset {
    /// The effect.
    pub effect: Effect,
    /// Model turn about the vertical axis, degrees (the turntable's start).
    pub turn_deg: f32,
    /// Camera.
    pub camera: CameraPreset,
    /// Light.
    pub light: LightPreset,
    /// Base shading.
    pub base: BasePreset,
    /// Highlights.
    pub specular: SpecularPreset,
    /// Hatching.
    pub hatching: HatchingPreset,
    /// Warping.
    pub warp: WarpPreset,
    /// Outlines over any effect.
    pub outline: OutlinePreset,
    /// Output size.
    pub output: OutputPreset,
    /// Playing a glTF clip.
    pub animation: AnimationPreset,
}

impl Preset {
    /// Parses a preset from TOML text; `origin` names it in errors.
    ///
    /// # Errors
    /// [`AppError::Preset`] with the TOML error (line and column) or the invalid value.
    pub fn from_toml(text: &str, origin: &Path) -> Result<Self, AppError> {
        let preset: Preset = toml::from_str(text).map_err(|e| AppError::Preset {
            path: origin.to_path_buf(),
            reason: toml_reason(text, &e),
        })?;
        preset.validate().map_err(|reason| AppError::Preset {
            path: origin.to_path_buf(),
            reason,
        })?;
        Ok(preset)
    }

    /// Reads a preset file.
    ///
    /// # Errors
    /// [`AppError::Io`] when unreadable, else as [`Preset::from_toml`].
    pub fn load(path: &Path) -> Result<Self, AppError> {
        let text = std::fs::read_to_string(path).map_err(|e| AppError::io(path, e))?;
        Self::from_toml(&text, path)
    }

    /// The preset as TOML text.
    ///
    /// # Errors
    /// [`AppError::Preset`] if serialisation fails (it does not for valid presets).
    pub fn to_toml(&self) -> Result<String, AppError> {
        toml::to_string_pretty(self).map_err(|e| AppError::Preset {
            path: PathBuf::from("<memory>"),
            reason: e.to_string(),
        })
    }

    /// Writes the preset atomically (a temporary file renamed over `path`).
    ///
    /// # Errors
    /// [`AppError::Io`] or as [`Preset::to_toml`].
    pub fn save(&self, path: &Path) -> Result<(), AppError> {
        crate::output::write_atomic(path, self.to_toml()?.as_bytes())
    }

    /// Checks value ranges; returns the first problem as a sentence.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |name: &str, v: &[f32]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(format!("{name} must be finite"))
            }
        };
        finite("turn_deg", &[self.turn_deg])?;
        finite("animation", &[self.animation.time, self.animation.speed])?;
        let c = &self.camera;
        finite(
            "camera",
            &[
                c.yaw_deg,
                c.pitch_deg,
                c.distance,
                c.fov_deg,
                c.pan[0],
                c.pan[1],
            ],
        )?;
        if c.distance <= 0.0 {
            return Err(format!("camera.distance must be > 0, got {}", c.distance));
        }
        if !(1.0..=170.0).contains(&c.fov_deg) {
            return Err(format!(
                "camera.fov_deg must be in 1..=170, got {}",
                c.fov_deg
            ));
        }
        finite("light.direction", &self.light.direction)?;
        if glam::Vec3::from(self.light.direction).length_squared() == 0.0 {
            return Err("light.direction must not be zero".into());
        }
        if !(-1.0 < self.specular.sigma && self.specular.sigma < 1.0) {
            return Err(format!(
                "specular.sigma must be in (-1, 1), got {}",
                self.specular.sigma
            ));
        }
        if !(self.specular.smoothing_edges > 0.0 && self.specular.smoothing_edges.is_finite()) {
            return Err("specular.smoothing_edges must be > 0".into());
        }
        if !(0.0..=MAX_ABSTRACTION).contains(&self.specular.abstraction) {
            return Err(format!(
                "specular.abstraction must be in 0..={MAX_ABSTRACTION}, got {}",
                self.specular.abstraction
            ));
        }
        if self.base.cel_bands.is_empty() {
            return Err("base.cel_bands needs at least one band".into());
        }
        let h = &self.hatching;
        if !(npr_hatching::MIN_BINS..=npr_hatching::MAX_BINS).contains(&h.bins) {
            return Err(format!(
                "hatching.bins must be in {}..={}, got {}",
                npr_hatching::MIN_BINS,
                npr_hatching::MAX_BINS,
                h.bins
            ));
        }
        if !(h.stroke_scale > 0.0 && h.stroke_scale.is_finite()) {
            return Err("hatching.stroke_scale must be > 0".into());
        }
        if self.warp.k == 0 {
            return Err("warp.k must be at least 1".into());
        }
        if !(self.warp.proxy_ratio > 0.0 && self.warp.proxy_ratio <= 1.0) {
            return Err(format!(
                "warp.proxy_ratio must be in (0, 1], got {}",
                self.warp.proxy_ratio
            ));
        }
        let o = &self.output;
        if o.width == 0 || o.height == 0 || o.width > 16384 || o.height > 16384 {
            return Err(format!(
                "output size must be in 1..=16384 on each side, got {}x{}",
                o.width, o.height
            ));
        }
        Ok(())
    }
}

/// A TOML error in one line: where (line and column of its span) and what, without the
/// source excerpt and caret lines toml's `Display` adds.
fn toml_reason(text: &str, e: &toml::de::Error) -> String {
    let what = e.message().trim().replace('\n', " ");
    match e.span() {
        Some(span) => {
            let before = text.get(..span.start).unwrap_or(text);
            let line = before.matches('\n').count() + 1;
            let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
            format!("line {line}, column {column}: {what}")
        }
        None => what,
    }
}

#[cfg(test)]
mod tests;
