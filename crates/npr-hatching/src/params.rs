//! Parameters of the hatching pass (§3 of Kim & Lee, "Real-time Image-space Hatching") and
//! their uniform block, shared byte for byte by the GPU pass (`shaders/hatching.wgsl`,
//! struct `Hatch`) and the CPU reference, so both evaluate the same constants.

use crate::{HatchError, TonalArtMap};
use std::f32::consts::PI;

/// Which steps of §3 the pass applies (Fig. 1 shows all three).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlendMode {
    /// Eq. (1), §3.1: one texture lookup in the quantized direction θ^q (seams between
    /// partitions; Fig. 1 left).
    CutAndPaste,
    /// Eq. (2)–(3), §3.2: the two nearest bins blended with `w_k = 1 − |θ−θ_k|/Δθ`
    /// (Fig. 1 middle).
    Blended,
    /// §3.3: Eq. (2)–(3) again on bins offset by Δθ/2, mixed 50/50 with the blended result
    /// (Fig. 1 right). The paper's final method and the default.
    OffsetPartition,
}

impl BlendMode {
    /// All modes in the order of Fig. 1.
    pub const ALL: [BlendMode; 3] = [Self::CutAndPaste, Self::Blended, Self::OffsetPartition];

    /// Lower-case name, for file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::CutAndPaste => "cut-and-paste",
            Self::Blended => "blended",
            Self::OffsetPartition => "offset-partition",
        }
    }

    fn code(self) -> u32 {
        match self {
            Self::CutAndPaste => 0,
            Self::Blended => 1,
            Self::OffsetPartition => 2,
        }
    }
}

/// Where the strokes are anchored: the coordinates that Eq. (1) rotates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StrokeSpace {
    /// The paper (§3.1): Eq. (1) rotates the pixel position, so the strokes stay fixed on
    /// the screen while a moving surface slides beneath them (the "shower-door" effect the
    /// paper names as a limit, §5). Still images and 2-D inputs are the same in both
    /// spaces.
    Screen,
    /// Coherent hatching, the default: Eq. (1) rotates the pixel's *surface anchors*,
    /// where its surface point was on the screen at two reference views that the
    /// G-buffer pass re-takes in turn (every [`crate::SceneSettings::anchor_period`]
    /// frames) and cross-fades (after Breslav et al. 2007, "Dynamic 2D Patterns for
    /// Shading 3D Scenes", with per-pixel anchors instead of one similarity per object).
    /// The strokes move with the surface; θ, tone and stroke scale stay screen-space, so
    /// the density stays the paper's under dolly. Pixels stay independent (one pass).
    /// Inputs without anchors ([`crate::HatchInputs`] from images) hatch as
    /// [`StrokeSpace::Screen`].
    #[default]
    Surface,
}

impl StrokeSpace {
    /// Both spaces, the paper's first.
    pub const ALL: [StrokeSpace; 2] = [Self::Screen, Self::Surface];

    /// Lower-case name, for tables and file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::Screen => "screen",
            Self::Surface => "surface",
        }
    }

    fn code(self) -> u32 {
        match self {
            Self::Screen => 0,
            Self::Surface => 1,
        }
    }
}

/// Short strokes where the stroke direction turns fast (beyond the paper's
/// §5, which suggests short strokes where curvature varies quickly): two fixed stroke
/// lengths blended per pixel by the G-buffer's turn rate of the direction field, like the
/// direction bins of Eq. (2)–(3) (a per-pixel scale of the texture coordinates would tear
/// the texture). The strokes of the map run along its u axis; the short ones are the map
/// compressed `shorten` times along u (so cross-hatching along v gets denser there).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeLength {
    /// How many times shorter the short strokes are (> 1).
    pub shorten: f32,
    /// Turn rate (radians of stroke direction per pixel) up to which strokes are long.
    pub calm: f32,
    /// Turn rate from which strokes are all short (> `calm`).
    pub busy: f32,
}

impl Default for StrokeLength {
    /// Half-length strokes from 0.1 rad/pixel (a 6° turn per pixel); full length below
    /// 0.02 rad/pixel.
    fn default() -> Self {
        Self {
            shorten: 2.0,
            calm: 0.02,
            busy: 0.1,
        }
    }
}

/// Parameters of the hatching pass.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HatchParams {
    /// Number of direction bins over [0, π), 12..=24 (Eq. (1), §3.1); Δθ = π / bins.
    pub bins: u32,
    /// Screen pixels per texel of the tonal art map (> 0): stroke spacing and width in
    /// pixels, constant over the screen whatever the depth.
    pub stroke_scale: f32,
    /// Which steps of §3 to apply.
    pub mode: BlendMode,
    /// Linear RGB of the ink.
    pub ink: [f32; 3],
    /// Linear RGB of the paper.
    pub paper: [f32; 3],
    /// Screen (the paper) or surface-anchored (coherent) strokes.
    pub space: StrokeSpace,
    /// Short strokes where the direction field turns; `None` (the default) keeps one
    /// stroke length, as the paper.
    pub stroke_length: Option<StrokeLength>,
}

impl Default for HatchParams {
    /// 16 bins, 1 pixel per texel, offset partition, black ink on white paper,
    /// surface-anchored strokes.
    fn default() -> Self {
        Self {
            bins: 16,
            stroke_scale: 1.0,
            mode: BlendMode::OffsetPartition,
            ink: [0.0; 3],
            paper: [1.0; 3],
            space: StrokeSpace::Surface,
            stroke_length: None,
        }
    }
}

impl HatchParams {
    /// Checks the ranges documented on the fields.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), HatchError> {
        if !(MIN_BINS..=MAX_BINS).contains(&self.bins) {
            return Err(HatchError::InvalidParams {
                what: "bins",
                reason: format!("{MIN_BINS}..={MAX_BINS} (Eq. (1), §3.1), got {}", self.bins),
            });
        }
        if !(self.stroke_scale.is_finite() && self.stroke_scale > 0.0) {
            return Err(HatchError::InvalidParams {
                what: "stroke_scale",
                reason: format!("finite and > 0, got {}", self.stroke_scale),
            });
        }
        if let Some(l) = self.stroke_length
            && !(l.shorten.is_finite()
                && l.shorten > 1.0
                && l.calm.is_finite()
                && l.calm >= 0.0
                && l.busy.is_finite()
                && l.busy > l.calm)
        {
            return Err(HatchError::InvalidParams {
                what: "stroke_length",
                reason: format!("shorten > 1, 0 ≤ calm < busy, all finite; got {l:?}"),
            });
        }
        if !self.ink.iter().chain(&self.paper).all(|c| c.is_finite()) {
            return Err(HatchError::InvalidParams {
                what: "ink/paper",
                reason: "finite colours".to_string(),
            });
        }
        Ok(())
    }

    /// Δθ = π / bins, in radians.
    pub fn bin_width_rad(&self) -> f32 {
        PI / self.bins as f32
    }
}

/// The direction bin that Eq. (1) (§3.1) reads for a stroke angle: the `k` in
/// `0..bins` whose `θ_k = k·Δθ` (`Δθ = π / bins`) is nearest `theta_rad`, as a line
/// direction (θ and θ + π are the same bin, so angles just below π go to bin 0). The
/// hatching pass and [`crate::CpuHatcher`] take this bin (and, blended, its neighbour);
/// use it to show a G-buffer's bins. `bins` of 0 is taken as 1.
pub fn nearest_bin(theta_rad: f32, bins: u32) -> u32 {
    let n = bins.max(1);
    let k = (theta_rad / (PI / n as f32) + 0.5).floor();
    if !k.is_finite() {
        return 0;
    }
    (k as i64).rem_euclid(i64::from(n)) as u32
}

/// Fewest direction bins (Eq. (1), §3.1: "12~24").
pub const MIN_BINS: u32 = 12;
/// Most direction bins.
pub const MAX_BINS: u32 = 24;

/// The hatching pass's uniform block (`Hatch` in `shaders/hatching.wgsl`, 496 bytes),
/// also read by the CPU reference so both use the very same constants.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct HatchUniforms {
    /// Per bin k: (cos θ_k, sin θ_k) of the partition (θ_k = kΔθ) and of the offset
    /// partition (θ_k = (k + ½)Δθ, §3.3), each pre-multiplied by 1 / stroke_scale so that
    /// Eq. (1)'s rotated coordinates come out in texels.
    pub bins: [[f32; 4]; MAX_BINS as usize],
    /// rgb = ink (linear), a = 1 / Δθ.
    pub ink: [f32; 4],
    /// rgb = paper (linear), a = max coverage of the map.
    pub paper: [f32; 4],
    /// x = (tones − 1) / max coverage (coverage → slice), y..w unused.
    pub tone: [f32; 4],
    /// x = bins, y = mode (0 cut-and-paste, 1 blended, 2 offset partition),
    /// z = map size − 1 (texel mask), w = tones.
    pub config: [u32; 4],
    /// x = stroke space (0 screen, 1 surface), y..w unused.
    pub space: [u32; 4],
    /// Short strokes ([`StrokeLength`]): x = shorten, y = calm, z = 1 / (busy − calm),
    /// w = 1 when on, 0 off.
    pub length: [f32; 4],
}

impl HatchUniforms {
    /// The uniforms for `params` and `tam`.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] when `params` fails [`HatchParams::validate`].
    pub fn new(params: &HatchParams, tam: &TonalArtMap) -> Result<Self, HatchError> {
        params.validate()?;
        let dtheta = params.bin_width_rad();
        let inv_scale = 1.0 / params.stroke_scale;
        let mut bins = [[0.0; 4]; MAX_BINS as usize];
        for (k, b) in bins.iter_mut().enumerate().take(params.bins as usize) {
            let (s0, c0) = (k as f32 * dtheta).sin_cos();
            let (s1, c1) = ((k as f32 + 0.5) * dtheta).sin_cos();
            *b = [
                c0 * inv_scale,
                s0 * inv_scale,
                c1 * inv_scale,
                s1 * inv_scale,
            ];
        }
        let [ir, ig, ib] = params.ink;
        let [pr, pg, pb] = params.paper;
        Ok(Self {
            bins,
            ink: [ir, ig, ib, 1.0 / dtheta],
            paper: [pr, pg, pb, tam.max_coverage()],
            tone: [(tam.tones() - 1) as f32 / tam.max_coverage(), 0.0, 0.0, 0.0],
            config: [params.bins, params.mode.code(), tam.size() - 1, tam.tones()],
            space: [params.space.code(), 0, 0, 0],
            length: match params.stroke_length {
                Some(l) => [l.shorten, l.calm, 1.0 / (l.busy - l.calm), 1.0],
                None => [1.0, 0.0, 0.0, 0.0],
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_bin_is_the_closest_line_direction() {
        for bins in [1u32, 12, 18, 24] {
            let dt = PI / bins as f32;
            for i in 0..1000 {
                let theta = PI * i as f32 / 1000.0;
                let k = nearest_bin(theta, bins);
                assert!(k < bins);
                // The distance between lines (mod π) to θ_k is the least of all bins.
                let line_dist = |a: f32| {
                    let d = (theta - a).rem_euclid(PI);
                    d.min(PI - d)
                };
                let best = (0..bins)
                    .map(|j| line_dist(j as f32 * dt))
                    .fold(f32::INFINITY, f32::min);
                assert!(
                    line_dist(k as f32 * dt) <= best + 1e-5,
                    "θ {theta}, {bins} bins: bin {k}"
                );
            }
        }
        assert_eq!(nearest_bin(f32::NAN, 12), 0);
        assert_eq!(nearest_bin(0.49 * PI / 12.0, 12), 0);
        assert_eq!(nearest_bin(0.51 * PI / 12.0, 12), 1);
    }

    #[test]
    fn uniform_layout_matches_wgsl() {
        // Size and member offsets read from `hatching.wgsl` by naga.
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            HatchUniforms,
            "Hatch",
            [bins, ink, paper, tone, config, space, length]
        );
    }

    #[test]
    fn bad_params_are_errors() {
        for p in [
            HatchParams {
                bins: 11,
                ..Default::default()
            },
            HatchParams {
                bins: 25,
                ..Default::default()
            },
            HatchParams {
                stroke_scale: 0.0,
                ..Default::default()
            },
            HatchParams {
                stroke_scale: f32::NAN,
                ..Default::default()
            },
            HatchParams {
                ink: [f32::INFINITY, 0.0, 0.0],
                ..Default::default()
            },
        ] {
            assert!(matches!(
                p.validate(),
                Err(HatchError::InvalidParams { .. })
            ));
        }
    }
}
