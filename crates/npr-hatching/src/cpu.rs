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
use crate::{Anchor, HatchError, HatchInputs, HatchParams, HatchUniforms, TonalArtMap};
use rayon::prelude::*;

/// Entries of the coverage → sRGB lookup table of [`CpuHatcher::hatch_rgba8`].
const LUT_SIZE: usize = 4096;
/// Pixels evaluated together by the batched CPU path.
const LANES: usize = 8;

/// `floor(x)` as an integer without a libm call (exact for |x| < 2³¹), the same value as
/// WGSL `i32(floor(x))`.
#[inline(always)]
fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    // Branch-free: the comparison is a coin flip per texel edge, a branch would mispredict.
    i - i32::from((i as f32) > x)
}

/// `1.5 · 2²³`: adding it to an f32 of magnitude below 2²² rounds it to an integer held
/// in the low mantissa bits.
const MAGIC: f32 = 12_582_912.0;
/// Largest |x| for which [`floor_lanes`] is exact.
const FLOOR_LANES_LIMIT: f32 = 4_194_304.0;

/// `floor(x)` as an integer for |x| < 2²², using only adds, a bit cast and a compare, so
/// that loops of it vectorize (a saturating `as i32` does not). Exact: `r` is x rounded
/// to the nearest integer; one is subtracted where that rounded up.
#[inline(always)]
fn floor_lanes(x: f32) -> i32 {
    let y = x + MAGIC;
    let r = y - MAGIC;
    let ri = (y.to_bits() as i32).wrapping_sub(MAGIC.to_bits() as i32);
    ri - i32::from(r > x)
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
    /// `uniforms.bins` extended by one bin on each side (entry `k + 1` is bin `k mod n`
    /// for k in −1..=n+1), so that the in-range case needs no integer division.
    bins_ext: Vec<[f32; 4]>,
    /// Coverage (quantized to `LUT_SIZE` steps) → sRGB8 of `paper + (ink − paper)·c`.
    lut: Vec<[u8; 4]>,
    /// Surface space: the map is read filtered ([`CpuHatcher::filtered_texel`]), as the
    /// GPU pass's surface variants read it.
    filtered: bool,
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
        let q = |c: f32| (npr_gpu::color::linear_to_srgb(c) * 255.0).round() as u8;
        let lut = (0..LUT_SIZE)
            .map(|i| {
                let c = i as f32 / (LUT_SIZE - 1) as f32;
                let ch = |k: usize| params.paper[k] + (params.ink[k] - params.paper[k]) * c;
                [q(ch(0)), q(ch(1)), q(ch(2)), 255]
            })
            .collect();
        let n = params.bins as i32;
        let bins_ext = (-1..=n + 1)
            .map(|k| uniforms.bins[k.rem_euclid(n) as usize])
            .collect();
        Ok(Self {
            uniforms,
            bins_ext,
            texels,
            size_log2: tam.size().trailing_zeros(),
            mask: tam.size() as i32 - 1,
            tones,
            bins: params.bins as i32,
            lut,
            filtered: params.space == crate::StrokeSpace::Surface,
        })
    }

    /// The uniforms shared with the GPU pass.
    pub fn uniforms(&self) -> &HatchUniforms {
        &self.uniforms
    }

    /// `f(u_k, v_k)` of Eq. (2): the map at the rotated pixel (Eq. (1)), nearest texel with
    /// wrap-around (filtered in the surface space, [`CpuHatcher::filtered_texel`]),
    /// blended between slices `slice` and `slice + 1` by `a`. `cs` = (cos θ_k, sin θ_k) /
    /// stroke_scale; `k` shortens the strokes (along u) k times. Mirrors WGSL
    /// `stroke_texel`.
    #[inline(always)]
    fn stroke_texel(&self, cs: (f32, f32), x: f32, y: f32, slice: usize, a: f32, k: f32) -> f32 {
        let u = (cs.0 * x - cs.1 * y) * k;
        let v = cs.1 * x + cs.0 * y;
        if self.filtered {
            return self.filtered_texel(u, v, slice, a);
        }
        let tx = (floor_i32(u) & self.mask) as usize;
        let ty = (floor_i32(v) & self.mask) as usize;
        let base = ((ty << self.size_log2) + tx) * self.tones + slice;
        let (t0, t1) = match self.texels.get(base..base + 2) {
            Some(&[a, b]) => (f32::from(a) * (1.0 / 255.0), f32::from(b) * (1.0 / 255.0)),
            _ => (0.0, 0.0),
        };
        t0 + (t1 - t0) * a
    }

    /// The map at texel coordinates `(u, v)` filtered with wrap-around (texel centres at
    /// `i + ½`), blended between slices `slice` and `slice + 1` by `a`: the surface
    /// space's lookup (WGSL `stroke_texel` through `tam_sampler`). Bilinear, with each
    /// axis's fraction `f` eased to `f²(3 − 2f)`: a stroke's edge slides continuously as
    /// the position moves, and stays nearly as crisp as a nearest read.
    fn filtered_texel(&self, u: f32, v: f32, slice: usize, a: f32) -> f32 {
        let (uu, vv) = (u - 0.5, v - 0.5);
        let (i0, j0) = (floor_i32(uu), floor_i32(vv));
        // Non-finite or far-off coordinates (where `floor_i32` saturates) read texel
        // (i0, j0) alone.
        let ease = |x: f32, i: i32| {
            let f = x - i as f32;
            if (0.0..=1.0).contains(&f) {
                f * f * (3.0 - 2.0 * f)
            } else {
                0.0
            }
        };
        let (fu, fv) = (ease(uu, i0), ease(vv, j0));
        let pair = |i: i32, j: i32| {
            let base = ((((j & self.mask) as usize) << self.size_log2) + (i & self.mask) as usize)
                * self.tones
                + slice;
            match self.texels.get(base..base + 2) {
                Some(&[t0, t1]) => (f32::from(t0) / 255.0, f32::from(t1) / 255.0),
                _ => (0.0, 0.0),
            }
        };
        let lerp =
            |p: (f32, f32), q: (f32, f32), t: f32| (p.0 + (q.0 - p.0) * t, p.1 + (q.1 - p.1) * t);
        // Wrapping: `floor_i32` saturates at i32::MAX far off, and the map wraps anyway.
        let (i1, j1) = (i0.wrapping_add(1), j0.wrapping_add(1));
        let top = lerp(pair(i0, j0), pair(i1, j0), fu);
        let bottom = lerp(pair(i0, j1), pair(i1, j1), fu);
        let (t0, t1) = lerp(top, bottom, fv);
        t0 + (t1 - t0) * a
    }

    /// Bin `k`'s (cos, sin) over the stroke scale, wrapped into range. Mirrors WGSL
    /// `bin_cs`.
    #[inline(always)]
    fn bin_cs(&self, k: i32, offset: bool) -> (f32, f32) {
        let b = match self.bins_ext.get(k.wrapping_add(1) as usize) {
            Some(b) => *b,
            None => self.uniforms.bins[k.rem_euclid(self.bins) as usize],
        };
        if offset { (b[2], b[3]) } else { (b[0], b[1]) }
    }

    /// Eq. (2)–(3), §3.2, on the partition with bins offset by `offset` (0 or ½, §3.3):
    /// `Σ_k w_k f(u_k, v_k)` with `w_k = 1 − |θ−θ_k|/Δθ`. With θ^0 the nearest bin only
    /// θ^0 and the neighbour on θ's side have a non-zero weight (`1 − |d|` and `|d|`, d =
    /// (θ − θ^0)/Δθ), so only those two are fetched. Mirrors WGSL `blended`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn blended(&self, t: f32, offset: bool, x: f32, y: f32, slice: usize, a: f32, k: f32) -> f32 {
        let tt = if offset { t - 0.5 } else { t };
        let q = floor_i32(tt + 0.5);
        let d = tt - q as f32;
        let (k1, w1) = if d >= 0.0 { (q + 1, d) } else { (q - 1, -d) };
        let f0 = self.stroke_texel(self.bin_cs(q, offset), x, y, slice, a, k);
        let f1 = self.stroke_texel(self.bin_cs(k1, offset), x, y, slice, a, k);
        (1.0 - w1) * f0 + w1 * f1
    }

    /// Ink coverage (0 = paper, 1 = ink) of the pixel whose centre is `(x, y)` (pixel
    /// coordinates, y down, centres at `i + ½`), for a tone in [0, 1] and θ in [0, π)
    /// (use [`crate::inputs::sanitize_tone`] / [`crate::inputs::wrap_theta`] first for raw
    /// values). Mirrors WGSL `hatch_coverage` with k = 1.
    #[inline]
    pub fn coverage(&self, x: f32, y: f32, tone: f32, theta: f32) -> f32 {
        self.coverage_k(x, y, tone, theta, 1.0)
    }

    /// [`CpuHatcher::coverage`] with strokes shortened `k` times. Mirrors WGSL
    /// `hatch_coverage`.
    #[inline]
    fn coverage_k(&self, x: f32, y: f32, tone: f32, theta: f32, k: f32) -> f32 {
        // Tone → the two nearest slices: coverage c = 1 − tone, slice position c·(n−1)/c_max.
        let max_cov = self.uniforms.paper[3];
        let c = (1.0 - tone).clamp(0.0, max_cov);
        // Slice 0 is blank paper: no ink, whatever the direction (the lookups would all
        // read 0). Not just a shortcut: the WGSL does the same.
        if c <= 0.0 {
            return 0.0;
        }
        let s = c * self.uniforms.tone[0];
        let slice = (floor_i32(s).max(0) as usize).min(self.tones - 2);
        let a = s - slice as f32;
        // θ in units of Δθ.
        let t = theta * self.uniforms.ink[3];
        match self.uniforms.config[1] {
            // Eq. (1), §3.1: the nearest bin only.
            0 => {
                let q = floor_i32(t + 0.5);
                self.stroke_texel(self.bin_cs(q, false), x, y, slice, a, k)
            }
            // Eq. (2)–(3), §3.2.
            1 => self.blended(t, false, x, y, slice, a, k),
            // §3.3: the offset partition, mixed 50/50.
            _ => {
                0.5 * self.blended(t, false, x, y, slice, a, k)
                    + 0.5 * self.blended(t, true, x, y, slice, a, k)
            }
        }
    }

    /// Ink coverage at `(x, y)` with two stroke lengths blended by the direction field's
    /// `turn` rate (rad/pixel, [`crate::StrokeLength`]; one length when it is off).
    /// Mirrors WGSL `length_blended`.
    #[inline]
    pub fn length_blended(&self, x: f32, y: f32, tone: f32, theta: f32, turn: f32) -> f32 {
        let l = self.uniforms.length;
        let w = if l[3] > 0.0 {
            ((turn - l[1]) * l[2]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c0 = if w < 1.0 {
            self.coverage_k(x, y, tone, theta, 1.0)
        } else {
            0.0
        };
        let c1 = if w > 0.0 {
            self.coverage_k(x, y, tone, theta, l[0])
        } else {
            0.0
        };
        c0 + (c1 - c0) * w
    }

    /// Ink coverage of a pixel with surface anchors ([`crate::StrokeSpace::Surface`]):
    /// [`CpuHatcher::length_blended`] at the two anchors, cross-faded by
    /// `anchor.weight_b`. Mirrors WGSL `anchored_coverage`.
    #[inline]
    pub fn anchored_coverage(&self, anchor: &Anchor, tone: f32, theta: f32, turn: f32) -> f32 {
        let w = anchor.weight_b;
        let c0 = if w < 1.0 {
            self.length_blended(anchor.a[0], anchor.a[1], tone, theta, turn)
        } else {
            0.0
        };
        let c1 = if w > 0.0 {
            self.length_blended(anchor.b[0], anchor.b[1], tone, theta, turn)
        } else {
            0.0
        };
        c0 + (c1 - c0) * w
    }

    /// [`CpuHatcher::coverage`] for `LANES` consecutive pixels of row `py` starting at
    /// pixel `x0`: the same operations in the same order (so bit-identical results), laid
    /// out lane by lane so that the arithmetic vectorizes; only the lookups stay scalar.
    #[inline(always)]
    fn coverage_lanes(
        &self,
        x0: usize,
        py: f32,
        tone: &[f32; LANES],
        theta: &[f32; LANES],
    ) -> [f32; LANES] {
        let max_cov = self.uniforms.paper[3];
        let mut slice = [0usize; LANES];
        let mut a = [0f32; LANES];
        let mut t = [0f32; LANES];
        let mut px = [0f32; LANES];
        let mut paper = [false; LANES];
        for l in 0..LANES {
            let c = (1.0 - tone[l]).clamp(0.0, max_cov);
            paper[l] = c <= 0.0;
            let s = c * self.uniforms.tone[0];
            slice[l] = (floor_lanes(s).max(0) as usize).min(self.tones - 2);
            a[l] = s - slice[l] as f32;
            t[l] = theta[l] * self.uniforms.ink[3];
            px[l] = (x0 + l) as f32 + 0.5;
        }
        let mut out = match self.uniforms.config[1] {
            0 => {
                let mut cs = [(0f32, 0f32); LANES];
                for l in 0..LANES {
                    cs[l] = self.bin_cs(floor_lanes(t[l] + 0.5), false);
                }
                self.stroke_texels(&cs, &px, py, &slice, &a)
            }
            1 => self.blended_lanes(&t, false, &px, py, &slice, &a),
            _ => {
                let b0 = self.blended_lanes(&t, false, &px, py, &slice, &a);
                let b1 = self.blended_lanes(&t, true, &px, py, &slice, &a);
                let mut o = [0f32; LANES];
                for l in 0..LANES {
                    o[l] = 0.5 * b0[l] + 0.5 * b1[l];
                }
                o
            }
        };
        for l in 0..LANES {
            if paper[l] {
                out[l] = 0.0;
            }
        }
        out
    }

    /// [`CpuHatcher::blended`] lane by lane.
    #[inline(always)]
    fn blended_lanes(
        &self,
        t: &[f32; LANES],
        offset: bool,
        px: &[f32; LANES],
        py: f32,
        slice: &[usize; LANES],
        a: &[f32; LANES],
    ) -> [f32; LANES] {
        let mut cs0 = [(0f32, 0f32); LANES];
        let mut cs1 = [(0f32, 0f32); LANES];
        let mut w1 = [0f32; LANES];
        for l in 0..LANES {
            let tt = if offset { t[l] - 0.5 } else { t[l] };
            let q = floor_lanes(tt + 0.5);
            let d = tt - q as f32;
            let (k1, w) = if d >= 0.0 { (q + 1, d) } else { (q - 1, -d) };
            cs0[l] = self.bin_cs(q, offset);
            cs1[l] = self.bin_cs(k1, offset);
            w1[l] = w;
        }
        let f0 = self.stroke_texels(&cs0, px, py, slice, a);
        let f1 = self.stroke_texels(&cs1, px, py, slice, a);
        let mut o = [0f32; LANES];
        for l in 0..LANES {
            o[l] = (1.0 - w1[l]) * f0[l] + w1[l] * f1[l];
        }
        o
    }

    /// [`CpuHatcher::stroke_texel`] lane by lane: rotation and texel index first, in
    /// 32-bit lanes (they vectorize), then the lookups.
    #[inline(always)]
    fn stroke_texels(
        &self,
        cs: &[(f32, f32); LANES],
        px: &[f32; LANES],
        py: f32,
        slice: &[usize; LANES],
        a: &[f32; LANES],
    ) -> [f32; LANES] {
        let (mut c, mut sn) = ([0f32; LANES], [0f32; LANES]);
        for l in 0..LANES {
            c[l] = cs[l].0;
            sn[l] = cs[l].1;
        }
        let mut base = [0u32; LANES];
        let (mask, log2, tones) = (self.mask, self.size_log2, self.tones as u32);
        for l in 0..LANES {
            let u = c[l] * px[l] - sn[l] * py;
            let v = sn[l] * px[l] + c[l] * py;
            let tx = (floor_lanes(u) & mask) as u32;
            let ty = (floor_lanes(v) & mask) as u32;
            base[l] = ((ty << log2) + tx) * tones + slice[l] as u32;
        }
        let mut o = [0f32; LANES];
        for l in 0..LANES {
            let b = base[l] as usize;
            let (t0, t1) = match self.texels.get(b..b + 2) {
                Some(&[x, y]) => (f32::from(x) * (1.0 / 255.0), f32::from(y) * (1.0 / 255.0)),
                _ => (0.0, 0.0),
            };
            o[l] = t0 + (t1 - t0) * a[l];
        }
        o
    }

    /// One row of coverages, handed to `emit(x, coverage)`: with surface anchors (and
    /// the surface space) pixel by pixel through [`CpuHatcher::anchored_coverage`];
    /// otherwise runs of `LANES` pixels through the batched path, the remainder one by one.
    fn coverage_row(
        &self,
        y: usize,
        tone: &[f32],
        theta: &[f32],
        (anchors, turn): (Option<&[Anchor]>, Option<&[f32]>),
        mut emit: impl FnMut(usize, f32),
    ) {
        let py = y as f32 + 0.5;
        let n = tone.len().min(theta.len());
        let anchors = anchors.filter(|_| self.uniforms.space[0] == 1);
        if anchors.is_some() || self.filtered || self.uniforms.length[3] > 0.0 {
            for i in 0..n {
                let tr = turn.and_then(|t| t.get(i)).copied().unwrap_or(0.0);
                let c = match anchors.and_then(|a| a.get(i)) {
                    Some(an) => self.anchored_coverage(an, tone[i], theta[i], tr),
                    None => self.length_blended(i as f32 + 0.5, py, tone[i], theta[i], tr),
                };
                emit(i, c);
            }
            return;
        }
        // The batched path's floor is exact below 2²² texels from the origin; beyond
        // (absurd sizes or scales) every pixel takes the scalar path.
        let reach = (n as f32 + py)
            * self.uniforms.bins[0][0]
                .abs()
                .max(self.uniforms.bins[0][1].abs())
            * 2.0;
        let mut x = if reach < FLOOR_LANES_LIMIT { 0 } else { n };
        while x + LANES <= n {
            let (Ok(t), Ok(a)) = (
                <&[f32; LANES]>::try_from(&tone[x..x + LANES]),
                <&[f32; LANES]>::try_from(&theta[x..x + LANES]),
            ) else {
                break;
            };
            for (l, c) in self.coverage_lanes(x, py, t, a).into_iter().enumerate() {
                emit(x + l, c);
            }
            x += LANES;
        }
        let x = if reach < FLOOR_LANES_LIMIT { x } else { 0 };
        for i in x..n {
            emit(i, self.coverage(i as f32 + 0.5, py, tone[i], theta[i]));
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
            let anchors = inputs.anchors().map(|a| &a[y * w..(y + 1) * w]);
            let turn = inputs.turn().map(|t| &t[y * w..(y + 1) * w]);
            self.coverage_row(y, tone, theta, (anchors, turn), |x, c| {
                if let Some(o) = row.get_mut(x) {
                    *o = c;
                }
            });
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
                let anchors = inputs.anchors().map(|a| &a[y * w..(y + 1) * w]);
                let turn = inputs.turn().map(|t| &t[y * w..(y + 1) * w]);
                self.coverage_row(y, tone, theta, (anchors, turn), |x, c| {
                    let i = ((c * scale + 0.5) as usize).min(LUT_SIZE - 1);
                    if let (Some(o), Some(rgba)) = (row.get_mut(4 * x..4 * x + 4), self.lut.get(i))
                    {
                        o.copy_from_slice(rgba);
                    }
                });
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
    fn batched_rows_equal_the_per_pixel_function() {
        let tam = crate::TonalArtMap::generate(&crate::TamParams {
            size: 64,
            ..crate::TamParams::pen()
        })
        .unwrap();
        for mode in crate::BlendMode::ALL {
            let h = CpuHatcher::new(
                &tam,
                &HatchParams {
                    mode,
                    ..Default::default()
                },
            )
            .unwrap();
            let inputs = HatchInputs::from_fn(37, 5, |x, y| (x / 37.0, 0.1 * x + 0.3 * y)).unwrap();
            let rows = h.hatch_coverage(&inputs).unwrap();
            for y in 0..5 {
                for x in 0..37 {
                    let i = y * 37 + x;
                    let c = h.coverage(
                        x as f32 + 0.5,
                        y as f32 + 0.5,
                        inputs.tone()[i],
                        inputs.theta()[i],
                    );
                    assert_eq!(rows[i].to_bits(), c.to_bits(), "{mode:?} ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn floor_matches_std() {
        for i in -2000..2000 {
            let x = i as f32 * 0.37 + 0.001;
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
            assert_eq!(floor_lanes(x), x.floor() as i32, "{x}");
        }
        for x in [
            -0.5f32,
            0.5,
            1.5,
            2.5,
            -1.5,
            -1.0,
            0.0,
            -0.0,
            4_194_303.5,
            -4_194_303.5,
            1e-30,
            -1e-30,
        ] {
            assert_eq!(floor_lanes(x), x.floor() as i32, "{x}");
        }
        assert_eq!(floor_i32(-1.0), -1);
        assert_eq!(floor_i32(-0.5), -1);
    }
}
