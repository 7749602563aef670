#![doc = include_str!("../README.md")]
//!
//! Real-time image-space hatching with tonal art maps.
//!
//! Implements Yongjin Kim (김용진) and Seungyong Lee (이승용), "Real-time Image-space
//! Hatching" (실시간 영상 공간 해칭, "GPU 기반 실시간 픽셀 단위 영상공간 해칭"), Journal of
//! the Korea Computer Graphics Society, POSTECH, 2008: given a tone and a stroke direction
//! θ ∈ [0, π) per pixel, one fragment shader draws strokes from a tonal art map by
//! rotating the pixel coordinates into the quantized direction (Eq. (1), §3.1), blending
//! the neighbouring direction bins (Eq. (2)–(3), §3.2) and mixing in a second partition
//! offset by half a bin (§3.3). Each pixel is independent of its neighbours.
//!
//! - [`tam`]: tonal art maps generated in code (Praun et al. 2001), pen and pencil,
//!   nested and tileable.
//! - [`params`]: bin count, stroke scale, [`BlendMode`], colours; the uniform block
//!   shared by GPU and CPU.
//! - [`inputs`]: tone/θ images from the caller ([`HatchInputs`]), including 2-D flow
//!   fields (§5's "flow visualisation").
//! - [`mod@cpu`]: the CPU reference of the per-pixel function ([`CpuHatcher`], rayon).
//! - [`pass`]: the GPU hatching pass ([`HatchPass`]) and its G-buffer ([`GBuffer`]).
//! - [`directions`]: per-vertex stroke directions ([`stroke_directions`]): by default a
//!   smooth line field fitted to the principal curvature directions
//!   ([`DirectionSource::Smooth`]), or the raw principal field ([`principal_directions`]).
//!   On the Stanford bunny the stroke line turns by more than 30° across 1.7 % of the
//!   edges with the smooth field against 9.8 % with the raw one (`cargo xtask bench
//!   hatching-directions`).
//! - [`scene`]: variance shadow maps (Donnelly & Lauritzen 2006) and the G-buffer pass
//!   for 3-D scenes, with per-vertex stroke directions from the caller.
//! - [`frame`]: the whole frame (shadow → G-buffer → hatching) and its Phong baseline.
//! - Coherent hatching (beyond the paper, whose §5 names the "shower-door" effect as a
//!   limit): with [`StrokeSpace::Surface`] (the default) the G-buffer pass also writes
//!   per-pixel *surface anchors*, where the pixel's surface point was on the screen at two
//!   reference views re-taken in turn and cross-faded ([`SceneSettings::anchor_period`]);
//!   Eq. (1) rotates those instead of the pixel position, so strokes move with the
//!   surface while their screen-space density stays the paper's. `coherence` (feature
//!   `test-support`) holds the
//!   measurements (`cargo xtask bench hatching-coherence`).
//!
//! Passes record into the caller's `wgpu::CommandEncoder` and views; only the helpers
//! named for it ([`hatch_image_gpu`], [`HatchFrame::render_hatched`]) submit and read back.
//!
//! Hatching an image on the CPU, no GPU needed:
//! ```
//! use npr_hatching::{CpuHatcher, HatchInputs, HatchParams, TamParams, TonalArtMap};
//! # fn main() -> Result<(), npr_hatching::HatchError> {
//! let tam = TonalArtMap::generate(&TamParams::pen())?;
//! // A tone ramp from black (left) to white, strokes turning with the row.
//! let inputs = HatchInputs::from_fn(64, 48, |x, y| (x / 64.0, 0.02 * y))?;
//! let image = CpuHatcher::new(&tam, &HatchParams::default())?.hatch_rgba8(&inputs)?;
//! assert_eq!(image.dimensions(), (64, 48));
//! # Ok(())
//! # }
//! ```
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

#[cfg(any(test, feature = "test-support"))]
pub mod coherence;
pub mod cpu;
pub mod directions;
mod error;
#[cfg(any(test, feature = "test-support"))]
pub mod figures;
pub mod frame;
pub mod inputs;
pub mod params;
pub mod pass;
pub mod pen;
pub mod scene;
pub mod shaders;
pub mod tam;

pub use cpu::{CpuHatcher, hatch_cpu};
pub use directions::{
    DirectionSource, StrokeDirection, principal_directions, second_axis, stroke_directions,
};
pub use error::HatchError;
pub use frame::{HatchFrame, HatchFrameSettings, HatchPrepared, HatchView};
pub use inputs::{Anchor, HatchInputs};
pub use params::{
    BlendMode, HatchParams, HatchUniforms, MAX_BINS, MIN_BINS, StrokeLength, StrokeSpace,
    nearest_bin,
};
pub use pass::{
    ANCHOR_FORMAT, GBUFFER_FORMAT, GBuffer, GBufferContents, GBufferReadback, HatchInput,
    HatchPass, HatchSettings, HatchSource, hatch_image_gpu,
};
pub use scene::{
    DEFAULT_ANCHOR_PERIOD, HatchObject, MOMENTS_FORMAT, SceneInput, ScenePasses, SceneSettings,
    ShadowLight, VsmSettings,
};
pub use tam::{TamParams, TamStyle, TonalArtMap};
