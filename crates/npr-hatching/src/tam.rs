//! Tonal art maps generated in code: a stack of stroke textures sorted by tone, each
//! slice tileable, with the nesting property of
//! E. Praun, H. Hoppe, M. Webb, A. Finkelstein, "Real-Time Hatching", ACM SIGGRAPH 2001,
//! pp. 579–584 (the hatching paper's reference \[1\]), in the slice-stack layout without
//! mipmaps of H. Lee, S. Kwon, S. Lee, "Real-Time Pencil Rendering", NPAR 2006, pp. 37–45
//! (reference \[3\]), as used by §2 of Kim & Lee, "Real-time Image-space Hatching".
//!
//! Slice `i` of `n` has ink coverage `max_coverage · i / (n − 1)`: slice 0 is blank paper,
//! slice `n − 1` the darkest. Strokes are only ever *added* going from a lighter slice to
//! a darker one (Praun et al. §4.1), so every stroke of a lighter slice is in every darker
//! slice: texel by texel, ink never decreases with the slice index. Strokes run along the
//! texture's u axis (rows); pen maps add strokes along v (cross-hatching) in the dark
//! tones. Strokes wrap around the edges, so every slice tiles.
//!
//! Stroke placement follows Praun et al.'s "best of several candidates": each new stroke is
//! the one of `candidates` random strokes that covers the least existing ink, which keeps
//! the tone even across the tile.

use crate::HatchError;

/// The stroke style of a tonal art map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TamStyle {
    /// Pen and ink: crisp, nearly straight lines of full ink; cross-hatching (strokes along
    /// the v axis as well) once the tone passes `cross_hatch_from`.
    Pen,
    /// Pencil: soft, grainy strokes whose pressure varies along their length; graphite
    /// accumulates where strokes overlap.
    Pencil,
}

impl TamStyle {
    /// Lower-case name, for file names and tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::Pen => "pen",
            Self::Pencil => "pencil",
        }
    }
}

/// Parameters of [`TonalArtMap::generate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TamParams {
    /// Stroke style.
    pub style: TamStyle,
    /// Side of each square slice in texels: a power of two in 16..=2048.
    pub size: u32,
    /// Number of tones (slices), 6..=32; slice 0 is blank paper.
    pub tones: u32,
    /// Ink coverage of the darkest slice, in (0, 1].
    pub max_coverage: f32,
    /// Stroke width in texels (pen: line width; pencil: the soft core's width).
    pub stroke_width: f32,
    /// Stroke length as a fraction of `size`, (min, max); at most 1.
    pub stroke_length: (f32, f32),
    /// Pen only: coverage from which strokes along v are added (cross-hatching).
    pub cross_hatch_from: f32,
    /// Random candidates per placed stroke (≥ 1); more gives a more even tone.
    pub candidates: u32,
    /// Seed of the stroke placement; the same seed gives the same map.
    pub seed: u64,
}

impl TamParams {
    /// A pen-and-ink map: 256², 8 tones up to 92 % ink, cross-hatching from 45 %.
    pub fn pen() -> Self {
        Self {
            style: TamStyle::Pen,
            size: 256,
            tones: 8,
            max_coverage: 0.92,
            stroke_width: 1.3,
            stroke_length: (0.25, 0.6),
            cross_hatch_from: 0.45,
            candidates: 8,
            seed: 0x5eed_0001,
        }
    }

    /// A pencil map: 256², 8 tones up to 85 % graphite, grainy strokes.
    pub fn pencil() -> Self {
        Self {
            style: TamStyle::Pencil,
            size: 256,
            tones: 8,
            max_coverage: 0.85,
            stroke_width: 1.6,
            stroke_length: (0.15, 0.45),
            cross_hatch_from: 2.0,
            candidates: 8,
            seed: 0x5eed_0002,
        }
    }

    /// The defaults of a style ([`TamParams::pen`] or [`TamParams::pencil`]).
    pub fn for_style(style: TamStyle) -> Self {
        match style {
            TamStyle::Pen => Self::pen(),
            TamStyle::Pencil => Self::pencil(),
        }
    }

    fn validate(&self) -> Result<(), HatchError> {
        let bad = |what, reason: &str| {
            Err(HatchError::InvalidTam {
                what,
                reason: reason.to_string(),
            })
        };
        if !self.size.is_power_of_two() || !(16..=2048).contains(&self.size) {
            return bad("size", "a power of two in 16..=2048");
        }
        if !(6..=32).contains(&self.tones) {
            return bad("tones", "6..=32");
        }
        if !(self.max_coverage > 0.0 && self.max_coverage <= 1.0) {
            return bad("max_coverage", "in (0, 1]");
        }
        if !(self.stroke_width.is_finite() && self.stroke_width > 0.0) {
            return bad("stroke_width", "finite and > 0");
        }
        let (lo, hi) = self.stroke_length;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi && hi <= 1.0) {
            return bad("stroke_length", "0 < min <= max <= 1");
        }
        if self.cross_hatch_from.is_nan() {
            return bad("cross_hatch_from", "a number");
        }
        if self.candidates == 0 {
            return bad("candidates", ">= 1");
        }
        Ok(())
    }
}

/// A tonal art map: `tones` slices of `size × size` ink coverages (0 = paper, 255 = full
/// ink), sorted from light to dark, nested and tileable (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct TonalArtMap {
    params: TamParams,
    /// Slice-major texels: `texels[(slice * size + y) * size + x]`.
    texels: Vec<u8>,
}

/// A tiny deterministic generator (splitmix64), so maps do not depend on a crate's RNG.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.0)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// One candidate stroke: a segment with a width and an ink profile.
#[derive(Clone, Copy, Debug)]
struct Stroke {
    /// Start, in texels (may be anywhere; drawing wraps).
    start: [f32; 2],
    /// Unit direction.
    dir: [f32; 2],
    length: f32,
    /// Peak ink (pencil pressure), 0..1.
    pressure: f32,
}

/// The texels a stroke touches with their ink, handed to `visit(index, ink)`.
fn rasterize(
    stroke: &Stroke,
    params: &TamParams,
    grain: &[f32],
    mut visit: impl FnMut(usize, f32),
) {
    let size = params.size as i32;
    let mask = size - 1;
    let half = params.stroke_width * 0.5;
    let [sx, sy] = stroke.start;
    let [dx, dy] = stroke.dir;
    let (ex, ey) = (sx + dx * stroke.length, sy + dy * stroke.length);
    let pad = half + 1.5;
    let (x0, x1) = (sx.min(ex) - pad, sx.max(ex) + pad);
    let (y0, y1) = (sy.min(ey) - pad, sy.max(ey) + pad);
    for iy in (y0.floor() as i32)..=(y1.ceil() as i32) {
        for ix in (x0.floor() as i32)..=(x1.ceil() as i32) {
            let (px, py) = (ix as f32 + 0.5 - sx, iy as f32 + 0.5 - sy);
            let t = (px * dx + py * dy).clamp(0.0, stroke.length);
            let (qx, qy) = (px - t * dx, py - t * dy);
            let dist = (qx * qx + qy * qy).sqrt();
            let idx = ((iy & mask) * size + (ix & mask)) as usize;
            let ink = match params.style {
                // Crisp line, one-texel anti-aliased edge.
                TamStyle::Pen => (half + 0.5 - dist).clamp(0.0, 1.0),
                TamStyle::Pencil => {
                    // Pressure rises and falls along the stroke; the soft core is modulated
                    // by the paper grain (a per-texel noise, so it tiles with the map).
                    let s = t / stroke.length.max(1e-6);
                    let taper = (std::f32::consts::PI * s).sin().max(0.0).powf(0.6);
                    let core = (1.0 - dist / (half + 0.75)).clamp(0.0, 1.0);
                    stroke.pressure * taper * core * grain.get(idx).copied().unwrap_or(1.0)
                }
            };
            if ink > 0.0 {
                visit(idx, ink);
            }
        }
    }
}

impl TonalArtMap {
    /// Generates a map (deterministic for a given `params.seed`).
    ///
    /// # Errors
    /// [`HatchError::InvalidTam`] for a parameter outside its range (see [`TamParams`]).
    pub fn generate(params: &TamParams) -> Result<Self, HatchError> {
        params.validate()?;
        let size = params.size as usize;
        let area = size * size;
        let mut rng = Rng(params.seed);
        // Paper grain for pencil: per-texel noise in [0.45, 1].
        let grain: Vec<f32> = (0..area)
            .map(|i| {
                0.45 + 0.55 * ((mix64(params.seed ^ (i as u64) << 1) >> 40) as f32 / 16_777_216.0)
            })
            .collect();
        let mut canvas = vec![0f32; area];
        let mut ink_sum = 0f64;
        let mut texels = vec![0u8; area * params.tones as usize];
        let levels = params.tones - 1;
        // Guard against a target the strokes cannot reach (e.g. full coverage with pencil).
        let max_strokes = 64 * area;
        let mut placed = 0usize;
        for slice in 1..=levels {
            let target = f64::from(params.max_coverage) * f64::from(slice) / f64::from(levels);
            while ink_sum / area as f64 + 1e-4 < target && placed < max_strokes {
                let coverage = (ink_sum / area as f64) as f32;
                // Shorten strokes that would overshoot the target by much (small maps).
                let deficit = ((target - ink_sum / area as f64) * area as f64) as f32;
                let max_len = (deficit / (params.stroke_width + 0.5)).max(3.0);
                let best = (0..params.candidates)
                    .map(|_| {
                        let mut s = Self::random_stroke(params, coverage, &mut rng);
                        s.length = s.length.min(max_len);
                        let mut under = 0f32;
                        let mut n = 0f32;
                        rasterize(&s, params, &grain, |i, _| {
                            under += canvas[i];
                            n += 1.0;
                        });
                        (under / n.max(1.0), s)
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, s)| s);
                let Some(stroke) = best else { break };
                rasterize(&stroke, params, &grain, |i, ink| {
                    let old = canvas[i];
                    let new = match params.style {
                        TamStyle::Pen => old.max(ink),
                        TamStyle::Pencil => 1.0 - (1.0 - old) * (1.0 - ink),
                    };
                    canvas[i] = new;
                    ink_sum += f64::from(new - old);
                });
                placed += 1;
            }
            let out = &mut texels[slice as usize * area..(slice as usize + 1) * area];
            for (o, c) in out.iter_mut().zip(&canvas) {
                *o = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
            }
        }
        Ok(Self {
            params: *params,
            texels,
        })
    }

    fn random_stroke(params: &TamParams, coverage: f32, rng: &mut Rng) -> Stroke {
        let size = params.size as f32;
        let cross = params.style == TamStyle::Pen
            && coverage >= params.cross_hatch_from
            && rng.unit() < 0.5;
        let jitter_deg = match params.style {
            TamStyle::Pen => 1.5,
            TamStyle::Pencil => 4.0,
        };
        let angle = rng.range(-jitter_deg, jitter_deg).to_radians()
            + if cross {
                std::f32::consts::FRAC_PI_2
            } else {
                0.0
            };
        let (lo, hi) = params.stroke_length;
        Stroke {
            start: [rng.range(0.0, size), rng.range(0.0, size)],
            dir: [angle.cos(), angle.sin()],
            length: rng.range(lo, hi) * size,
            pressure: match params.style {
                TamStyle::Pen => 1.0,
                TamStyle::Pencil => rng.range(0.55, 0.95),
            },
        }
    }

    /// The parameters the map was generated with.
    pub fn params(&self) -> &TamParams {
        &self.params
    }

    /// The stroke style.
    pub fn style(&self) -> TamStyle {
        self.params.style
    }

    /// Side of a slice in texels (a power of two).
    pub fn size(&self) -> u32 {
        self.params.size
    }

    /// Number of slices (tones), light to dark.
    pub fn tones(&self) -> u32 {
        self.params.tones
    }

    /// Ink coverage of the darkest slice (the target; see [`TonalArtMap::coverage`]).
    pub fn max_coverage(&self) -> f32 {
        self.params.max_coverage
    }

    /// The target ink coverage of slice `i`: `max_coverage · i / (tones − 1)`.
    pub fn target_coverage(&self, slice: u32) -> f32 {
        self.params.max_coverage * slice as f32 / (self.params.tones - 1) as f32
    }

    /// The texels of slice `i` (row-major, 0 = paper, 255 = ink), or `None` past the last.
    pub fn slice(&self, i: u32) -> Option<&[u8]> {
        let area = (self.params.size * self.params.size) as usize;
        self.texels.get(i as usize * area..(i as usize + 1) * area)
    }

    /// All slices, slice-major (`(slice * size + y) * size + x`), as uploaded to the GPU.
    pub fn texels(&self) -> &[u8] {
        &self.texels
    }

    /// Measured mean ink coverage of slice `i` (0..1), or `None` past the last.
    pub fn coverage(&self, i: u32) -> Option<f32> {
        self.slice(i)
            .map(|s| s.iter().map(|&t| u64::from(t)).sum::<u64>() as f32 / (255.0 * s.len() as f32))
    }

    /// The nesting property (Praun et al. 2001, §4.1): every texel's ink is at least as
    /// dark in slice `i + 1` as in slice `i`. Returns the first violation as
    /// `(lighter slice, texel index)`, or `None` when the map nests.
    pub fn nesting_violation(&self) -> Option<(u32, usize)> {
        let area = (self.params.size * self.params.size) as usize;
        (0..self.params.tones.saturating_sub(1)).find_map(|i| {
            let (a, b) = (self.slice(i)?, self.slice(i + 1)?);
            a.iter()
                .zip(b)
                .position(|(x, y)| y < x)
                .map(|p| (i, p.min(area)))
        })
    }

    /// Slice `i` as a grey image (paper white, ink black), for figures.
    pub fn slice_image(&self, i: u32) -> Option<image::GrayImage> {
        let s = self.slice(i)?;
        image::GrayImage::from_raw(
            self.params.size,
            self.params.size,
            s.iter().map(|&t| 255 - t).collect(),
        )
    }

    /// Uploads the map as a `size × size × tones` `R8Unorm` 2-D texture array (layer =
    /// slice, light to dark) and returns the texture.
    pub fn upload(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::Texture {
        use wgpu::util::DeviceExt;
        device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("npr tonal art map"),
                size: wgpu::Extent3d {
                    width: self.params.size,
                    height: self.params.size,
                    depth_or_array_layers: self.params.tones,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &self.texels,
        )
    }

    /// Uploads the map for the hatching pass as a `size × size × (tones − 1)` `Rg8Unorm`
    /// 2-D texture array: layer `s` holds slice `s` in r and slice `s + 1` in g, the two
    /// slices the pass blends for a tone between them (the volume lookup of the paper's
    /// §3.1, without mipmaps), so one fetch reads both: half the texture fetches of one
    /// `R8Unorm` layer per slice, the same texel values.
    pub fn upload_tone_pairs(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::Texture {
        use wgpu::util::DeviceExt;
        let area = (self.params.size * self.params.size) as usize;
        let layers = self.params.tones.saturating_sub(1).max(1);
        let mut pairs = Vec::with_capacity(area * 2 * layers as usize);
        for s in 0..layers {
            let (a, b) = match (self.slice(s), self.slice(s + 1)) {
                (Some(a), Some(b)) => (a, b),
                _ => break,
            };
            for (&x, &y) in a.iter().zip(b) {
                pairs.push(x);
                pairs.push(y);
            }
        }
        pairs.resize(area * 2 * layers as usize, 0);
        device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("npr tonal art map (tone pairs)"),
                size: wgpu::Extent3d {
                    width: self.params.size,
                    height: self.params.size,
                    depth_or_array_layers: layers,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rg8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &pairs,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_parameters_are_errors() {
        for p in [
            TamParams {
                size: 100,
                ..TamParams::pen()
            },
            TamParams {
                tones: 3,
                ..TamParams::pen()
            },
            TamParams {
                max_coverage: f32::NAN,
                ..TamParams::pencil()
            },
            TamParams {
                stroke_length: (0.5, 0.2),
                ..TamParams::pencil()
            },
            TamParams {
                candidates: 0,
                ..TamParams::pen()
            },
        ] {
            assert!(matches!(
                TonalArtMap::generate(&p),
                Err(HatchError::InvalidTam { .. })
            ));
        }
    }
}
