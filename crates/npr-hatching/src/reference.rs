//! The CPU reference of the hatching pass: exactly the per-pixel function of
//! `shaders/hatching.wgsl` (`hatch_coverage`), evaluated with rayon. Used by the tests to
//! check the GPU, and usable on its own to hatch images without a GPU.
//!
//! Implements §3 of Yongjin Kim and Seungyong Lee, "Real-time Image-space Hatching"
//! (실시간 영상 공간 해칭), Journal of the Korea Computer Graphics Society (POSTECH, 2008):
//! Eq. (1) (§3.1 cut-and-paste), Eq. (2)–(3) (§3.2 blending of neighbouring bins) and
//! §3.3 (offset partition mixed 50/50), with the tone interpolated between the two nearest
//! slices of the tonal art map. Each pixel depends only on its own tone and θ.
//!
//! Both sides read the same [`HatchUniforms`]; texels are fetched nearest, with
//! wrap-around, so the only CPU/GPU differences are float rounding (fused multiply-adds)
//! deciding which texel a coordinate lands in.

use crate::inputs::pixel_count;
use crate::{HatchError, HatchInputs, HatchParams, HatchUniforms, TonalArtMap};
use rayon::prelude::*;

/// Entries of the coverage → sRGB lookup table of [`CpuHatcher::hatch_rgba8`].
const LUT_SIZE: usize = 4096;

/// `floor(x)` as an integer without a libm call (exact for |x| < 2³¹), the same value as
/// WGSL `i32(floor(x))`.
#[inline(always)]
fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    if (i as f32) > x { i - 1 } else { i }
}

/// A prepared CPU hatcher: the map's texels interleaved by slice (the two slices a pixel
/// blends sit side by side in memory), the uniforms, and an sRGB lookup table.
#[derive(Clone, Debug)]
pub struct CpuHatcher {
    uniforms: HatchUniforms,
    /// `texels[(y * size + x) * tones + slice]`, ink 0..255.
    texels: Vec<u8>,
    size_log2: u32,
    mask: i32,
    tones: usize,
    bins: i32,
    /// Coverage (quantized to `LUT_SIZE` steps) → sRGB8 of `paper + (ink − paper)·c`.
    lut: Vec<[u8; 4]>,
}

impl CpuHatcher {
    /// Prepares a hatcher for `tam` and `params`.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] when `params` fails [`HatchParams::validate`].
    pub fn new(tam: &TonalArtMap, params: &HatchParams) -> Result<Self, HatchError> {
        let uniforms = HatchUniforms::new(params, tam)?;
        let size = tam.size() as usize;
        let area = size * size;
        let tones = tam.tones() as usize;
        let src = tam.texels();
        let mut texels = vec![0u8; area * tones];
        for (t, chunk) in texels.chunks_exact_mut(tones).enumerate() {
            for (s, v) in chunk.iter_mut().enumerate() {
                *v = src.get(s * area + t).copied().unwrap_or(0);
            }
        }
        let q = |c: f32| (npr_gpu::reference::linear_to_srgb(c) * 255.0).round() as u8;
        let lut = (0..LUT_SIZE)
            .map(|i| {
                let c = i as f32 / (LUT_SIZE - 1) as f32;
                let ch = |k: usize| params.paper[k] + (params.ink[k] - params.paper[k]) * c;
                [q(ch(0)), q(ch(1)), q(ch(2)), 255]
            })
            .collect();
        Ok(Self {
            uniforms,
            texels,
            size_log2: tam.size().trailing_zeros(),
            mask: tam.size() as i32 - 1,
            tones,
            bins: params.bins as i32,
            lut,
        })
    }

    /// The uniforms shared with the GPU pass.
    pub fn uniforms(&self) -> &HatchUniforms {
        &self.uniforms
    }

    /// `f(u_k, v_k)` of Eq. (2): the map at the rotated pixel (Eq. (1)), nearest texel with
    /// wrap-around, blended between slices `slice` and `slice + 1` by `a`. `cs` = (cos θ_k,
    /// sin θ_k) / stroke_scale. Mirrors WGSL `stroke_texel`.
    #[inline(always)]
    fn stroke_texel(&self, cs: (f32, f32), x: f32, y: f32, slice: usize, a: f32) -> f32 {
        let u = cs.0 * x - cs.1 * y;
        let v = cs.1 * x + cs.0 * y;
        let tx = (floor_i32(u) & self.mask) as usize;
        let ty = (floor_i32(v) & self.mask) as usize;
        let base = ((ty << self.size_log2) + tx) * self.tones + slice;
        let t0 = f32::from(self.texels.get(base).copied().unwrap_or(0)) * (1.0 / 255.0);
        let t1 = f32::from(self.texels.get(base + 1).copied().unwrap_or(0)) * (1.0 / 255.0);
        t0 + (t1 - t0) * a
    }

    #[inline(always)]
    fn bin_cs(&self, k: i32, offset: bool) -> (f32, f32) {
        let b = self.uniforms.bins[k.rem_euclid(self.bins) as usize];
        if offset { (b[2], b[3]) } else { (b[0], b[1]) }
    }

    /// Eq. (2)–(3), §3.2, on the partition with bins offset by `offset` (0 or ½, §3.3):
    /// `Σ_k w_k f(u_k, v_k)` with `w_k = 1 − |θ−θ_k|/Δθ`. With θ^0 the nearest bin only
    /// θ^0 and the neighbour on θ's side have a non-zero weight (`1 − |d|` and `|d|`, d =
    /// (θ − θ^0)/Δθ), so only those two are fetched. Mirrors WGSL `blended`.
    #[inline(always)]
    fn blended(&self, t: f32, offset: bool, x: f32, y: f32, slice: usize, a: f32) -> f32 {
        let tt = if offset { t - 0.5 } else { t };
        let q = floor_i32(tt + 0.5);
        let d = tt - q as f32;
        let (k1, w1) = if d >= 0.0 { (q + 1, d) } else { (q - 1, -d) };
        let f0 = self.stroke_texel(self.bin_cs(q, offset), x, y, slice, a);
        let f1 = self.stroke_texel(self.bin_cs(k1, offset), x, y, slice, a);
        (1.0 - w1) * f0 + w1 * f1
    }

    /// Ink coverage (0 = paper, 1 = ink) of the pixel whose centre is `(x, y)` (pixel
    /// coordinates, y down, centres at `i + ½`), for a tone in [0, 1] and θ in [0, π)
    /// (use [`crate::inputs::sanitize_tone`] / [`crate::inputs::wrap_theta`] first for raw
    /// values). Mirrors WGSL `hatch_coverage`.
    #[inline]
    pub fn coverage(&self, x: f32, y: f32, tone: f32, theta: f32) -> f32 {
        // Tone → the two nearest slices: coverage c = 1 − tone, slice position c·(n−1)/c_max.
        let max_cov = self.uniforms.paper[3];
        let c = (1.0 - tone).clamp(0.0, max_cov);
        let s = c * self.uniforms.tone[0];
        let slice = (floor_i32(s).max(0) as usize).min(self.tones - 2);
        let a = s - slice as f32;
        // θ in units of Δθ.
        let t = theta * self.uniforms.ink[3];
        match self.uniforms.config[1] {
            // Eq. (1), §3.1: the nearest bin only.
            0 => {
                let q = floor_i32(t + 0.5);
                self.stroke_texel(self.bin_cs(q, false), x, y, slice, a)
            }
            // Eq. (2)–(3), §3.2.
            1 => self.blended(t, false, x, y, slice, a),
            // §3.3: the offset partition, mixed 50/50.
            _ => {
                0.5 * self.blended(t, false, x, y, slice, a)
                    + 0.5 * self.blended(t, true, x, y, slice, a)
            }
        }
    }

    /// Ink coverage of every pixel of `inputs` (row-major), in parallel.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for an empty input (not constructible through
    /// [`HatchInputs`]' constructors).
    pub fn hatch_coverage(&self, inputs: &HatchInputs) -> Result<Vec<f32>, HatchError> {
        let n = pixel_count(inputs.width(), inputs.height())?;
        let w = inputs.width() as usize;
        let mut out = vec![0f32; n];
        out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            let (tone, theta) = (
                &inputs.tone()[y * w..(y + 1) * w],
                &inputs.theta()[y * w..(y + 1) * w],
            );
            let py = y as f32 + 0.5;
            for (x, ((o, &t), &a)) in row.iter_mut().zip(tone).zip(theta).enumerate() {
                *o = self.coverage(x as f32 + 0.5, py, t, a);
            }
        });
        Ok(out)
    }

    /// The hatched image as sRGB bytes (`paper + (ink − paper)·coverage` in linear RGB,
    /// encoded as an `Rgba8UnormSrgb` target would store it), in parallel. The encoding
    /// goes through a 4096-entry table over coverage (≤ 1 code value from exact).
    ///
    /// # Errors
    /// As [`CpuHatcher::hatch_coverage`].
    pub fn hatch_rgba8(&self, inputs: &HatchInputs) -> Result<image::RgbaImage, HatchError> {
        let n = pixel_count(inputs.width(), inputs.height())?;
        let w = inputs.width() as usize;
        let mut bytes = vec![0u8; n * 4];
        let scale = (LUT_SIZE - 1) as f32;
        bytes
            .par_chunks_mut(w * 4)
            .enumerate()
            .for_each(|(y, row)| {
                let (tone, theta) = (
                    &inputs.tone()[y * w..(y + 1) * w],
                    &inputs.theta()[y * w..(y + 1) * w],
                );
                let py = y as f32 + 0.5;
                for (x, ((o, &t), &a)) in row.chunks_exact_mut(4).zip(tone).zip(theta).enumerate() {
                    let c = self.coverage(x as f32 + 0.5, py, t, a);
                    let i = ((c * scale + 0.5) as usize).min(LUT_SIZE - 1);
                    o.copy_from_slice(&self.lut[i]);
                }
            });
        image::RgbaImage::from_raw(inputs.width(), inputs.height(), bytes).ok_or(
            HatchError::InvalidSize {
                width: inputs.width(),
                height: inputs.height(),
                reason: "too many pixels",
            },
        )
    }
}

/// One-call CPU hatching: [`CpuHatcher::new`] then [`CpuHatcher::hatch_rgba8`].
///
/// # Errors
/// As [`CpuHatcher::new`].
pub fn hatch_cpu(
    inputs: &HatchInputs,
    tam: &TonalArtMap,
    params: &HatchParams,
) -> Result<image::RgbaImage, HatchError> {
    CpuHatcher::new(tam, params)?.hatch_rgba8(inputs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_matches_std() {
        for i in -2000..2000 {
            let x = i as f32 * 0.37 + 0.001;
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
        }
        assert_eq!(floor_i32(-1.0), -1);
        assert_eq!(floor_i32(-0.5), -1);
    }
}
