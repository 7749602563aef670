//! Measuring temporal coherence of hatched frames (beyond the paper: its §5 names the
//! shower-door effect of image-space strokes as a limit): how far the stroke pattern moves
//! between two frames (phase correlation of image tiles), how dense the strokes are on
//! the screen, and how much a frame changes beyond what motion explains. Used by
//! `cargo xtask bench hatching-coherence` and the coherence tests; plain CPU code.

/// Ink of an sRGB pixel: 0 = paper white, 1 = black (the red channel, normalised; the
/// hatching frames are grey).
pub fn ink(pixel: &image::Rgba<u8>) -> f32 {
    1.0 - f32::from(pixel.0[0]) / 255.0
}

/// The ink image of a hatched frame, row-major ([`ink`] per pixel).
pub fn ink_image(image: &image::RgbaImage) -> Vec<f32> {
    image.pixels().map(ink).collect()
}

/// In-place iterative radix-2 FFT of `re`/`im` (length a power of two); `inverse` flips
/// the sign of the exponent (no 1/n scaling).
fn fft(re: &mut [f32], im: &mut [f32], inverse: bool) {
    let n = re.len();
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let ang = sign * 2.0 * std::f32::consts::PI / len as f32;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (s, c) = (ang * k as f32).sin_cos();
                let (a, b) = (start + k, start + k + len / 2);
                let (xr, xi) = (re[b] * c - im[b] * s, re[b] * s + im[b] * c);
                re[b] = re[a] - xr;
                im[b] = im[a] - xi;
                re[a] += xr;
                im[a] += xi;
            }
        }
        len <<= 1;
    }
}

/// 2-D FFT of an `n × n` row-major image (rows, then columns).
fn fft2(re: &mut [f32], im: &mut [f32], n: usize, inverse: bool) {
    for r in 0..n {
        fft(
            &mut re[r * n..(r + 1) * n],
            &mut im[r * n..(r + 1) * n],
            inverse,
        );
    }
    let (mut cr, mut ci) = (vec![0.0; n], vec![0.0; n]);
    for c in 0..n {
        for r in 0..n {
            cr[r] = re[r * n + c];
            ci[r] = im[r * n + c];
        }
        fft(&mut cr, &mut ci, inverse);
        for r in 0..n {
            re[r * n + c] = cr[r];
            im[r * n + c] = ci[r];
        }
    }
}

/// The shift `d` (pixels, x right, y down) with `b(p) ≈ a(p − d)` between two `n × n`
/// row-major tiles, by phase correlation (Kuglin & Hines 1975): the peak of the inverse
/// transform of the normalised cross-power spectrum, refined to sub-pixel precision by a
/// parabola through the peak and its neighbours on each axis. The tiles are windowed
/// (Hann) and their means removed first. `None` when `n` is not a power of two ≥ 4, the
/// tiles are not `n × n`, or either tile is flat.
pub fn phase_correlation(a: &[f32], b: &[f32], n: usize) -> Option<[f32; 2]> {
    if !n.is_power_of_two() || n < 4 || a.len() != n * n || b.len() != n * n {
        return None;
    }
    let window: Vec<f32> = (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f32::consts::PI * (i as f32 + 0.5) / n as f32).cos())
        .collect();
    let prep = |t: &[f32]| -> Option<Vec<f32>> {
        let mean = t.iter().sum::<f32>() / t.len() as f32;
        let v: Vec<f32> = t
            .iter()
            .enumerate()
            .map(|(i, x)| (x - mean) * window[i % n] * window[i / n])
            .collect();
        (v.iter().map(|x| x * x).sum::<f32>() > 1e-6).then_some(v)
    };
    let (mut ar, mut br) = (prep(a)?, prep(b)?);
    let (mut ai, mut bi) = (vec![0.0; n * n], vec![0.0; n * n]);
    fft2(&mut ar, &mut ai, n, false);
    fft2(&mut br, &mut bi, n, false);
    // B · conj(A) / |B · conj(A)|.
    let (mut cr, mut ci) = (vec![0.0; n * n], vec![0.0; n * n]);
    for i in 0..n * n {
        let re = br[i] * ar[i] + bi[i] * ai[i];
        let im = bi[i] * ar[i] - br[i] * ai[i];
        let m = (re * re + im * im).sqrt().max(1e-12);
        cr[i] = re / m;
        ci[i] = im / m;
    }
    fft2(&mut cr, &mut ci, n, true);
    let (mut best, mut bx, mut by) = (f32::MIN, 0usize, 0usize);
    for y in 0..n {
        for x in 0..n {
            if cr[y * n + x] > best {
                best = cr[y * n + x];
                (bx, by) = (x, y);
            }
        }
    }
    let at = |x: usize, y: usize| cr[(y % n) * n + (x % n)];
    let refine = |l: f32, c: f32, r: f32| {
        let d = l - 2.0 * c + r;
        if d.abs() > 1e-12 {
            (0.5 * (l - r) / d).clamp(-0.5, 0.5)
        } else {
            0.0
        }
    };
    let dx = refine(at(bx + n - 1, by), best, at(bx + 1, by));
    let dy = refine(at(bx, by + n - 1), best, at(bx, by + 1));
    let wrap = |i: usize| {
        if i > n / 2 {
            i as f32 - n as f32
        } else {
            i as f32
        }
    };
    Some([wrap(bx) + dx, wrap(by) + dy])
}

/// Screen-space stroke density of an ink image over `mask`: the mean absolute ink change
/// between horizontally or vertically adjacent pixels, both in `mask` (the image's total
/// variation per pixel step; each stroke edge contributes its contrast). Strokes twice as
/// far apart and twice as wide halve it, at the same ink coverage. `None` when the mask
/// holds no adjacent pair.
pub fn stroke_density(ink: &[f32], mask: &[bool], width: usize) -> Option<f32> {
    if width == 0 || ink.len() != mask.len() {
        return None;
    }
    let (mut pairs, mut variation) = (0usize, 0f64);
    for i in 0..ink.len() {
        if !mask[i] {
            continue;
        }
        for j in [i + 1, i + width] {
            if (j == i + 1 && j % width == 0) || j >= ink.len() || !mask[j] {
                continue;
            }
            pairs += 1;
            variation += f64::from((ink[i] - ink[j]).abs());
        }
    }
    (pairs > 0).then(|| (variation / pairs as f64) as f32)
}

/// Bilinear sample of a row-major image at pixel-centre coordinates (`(x, y)` = centre of
/// pixel `(x − ½, y − ½)`), clamped to the edges.
pub fn sample_bilinear(img: &[f32], width: usize, height: usize, x: f32, y: f32) -> f32 {
    if width == 0 || height == 0 || img.len() < width * height {
        return 0.0;
    }
    let fx = (x - 0.5).clamp(0.0, (width - 1) as f32);
    let fy = (y - 0.5).clamp(0.0, (height - 1) as f32);
    let (x0, y0) = (fx.floor() as usize, fy.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(width - 1), (y0 + 1).min(height - 1));
    let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
    let row = |y: usize| {
        let a = img[y * width + x0];
        a + (img[y * width + x1] - a) * tx
    };
    let top = row(y0);
    top + (row(y1) - top) * ty
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Broadband value noise: hashed lattice values every 2 pixels, bilinear between.
    fn pattern(x: f32, y: f32) -> f32 {
        let h = |i: i32, j: i32| {
            let v = (i.wrapping_mul(374_761_393) ^ j.wrapping_mul(668_265_263)) as u32;
            let v = v.wrapping_mul(0x27d4_eb2d) ^ (v >> 15);
            (v % 1000) as f32 / 1000.0
        };
        let (gx, gy) = (x * 0.5 + 100.0, y * 0.5 + 100.0);
        let (i, j) = (gx.floor() as i32, gy.floor() as i32);
        let (tx, ty) = (gx - gx.floor(), gy - gy.floor());
        let top = h(i, j) + (h(i + 1, j) - h(i, j)) * tx;
        let bot = h(i, j + 1) + (h(i + 1, j + 1) - h(i, j + 1)) * tx;
        top + (bot - top) * ty
    }

    #[test]
    fn phase_correlation_finds_a_known_shift() {
        let n = 32;
        for (dx, dy) in [(0.0f32, 0.0f32), (2.0, -1.0), (1.5, 0.5), (-3.25, 2.0)] {
            let a: Vec<f32> = (0..n * n)
                .map(|i| pattern((i % n) as f32, (i / n) as f32))
                .collect();
            let b: Vec<f32> = (0..n * n)
                .map(|i| pattern((i % n) as f32 - dx, (i / n) as f32 - dy))
                .collect();
            let d = phase_correlation(&a, &b, n).unwrap();
            assert!(
                (d[0] - dx).abs() < 0.35 && (d[1] - dy).abs() < 0.35,
                "{d:?} vs ({dx}, {dy})"
            );
        }
        assert!(phase_correlation(&[0.0; 9], &[0.0; 9], 3).is_none());
        assert!(phase_correlation(&[0.5; 16], &[0.5; 16], 4).is_none());
    }

    #[test]
    fn stroke_density_halves_with_doubled_strokes() {
        let (w, h) = (64, 64);
        let lines = |period: usize| -> Vec<f32> {
            (0..w * h)
                .map(|i| {
                    if (i % w) % period < period / 2 {
                        1.0
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let mask = vec![true; w * h];
        let d4 = stroke_density(&lines(4), &mask, w).unwrap();
        let d8 = stroke_density(&lines(8), &mask, w).unwrap();
        assert!((d4 / d8 - 2.0).abs() < 0.1, "{d4} {d8}");
        assert!(stroke_density(&lines(4), &vec![false; w * h], w).is_none());
    }

    #[test]
    fn bilinear_is_exact_at_centres_and_linear_between() {
        let img = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(sample_bilinear(&img, 2, 2, 0.5, 0.5), 0.0);
        assert_eq!(sample_bilinear(&img, 2, 2, 1.5, 1.5), 3.0);
        assert!((sample_bilinear(&img, 2, 2, 1.0, 0.5) - 0.5).abs() < 1e-6);
    }
}

/// A hatching rig of one stroke space: frame passes and one object, for coherence
/// measurements and figures of a turning object. Each [`Rig::render`] is one displayed
/// frame: it advances the rig's own frame id and anchor clock, in the open.
#[derive(Debug)]
pub struct Rig {
    /// The frame passes.
    pub frame: crate::HatchFrame,
    /// The object (material of [`uniforms`]).
    pub object: crate::HatchObject,
    /// The hatching parameters (the rig's stroke space).
    pub params: crate::HatchParams,
    /// Displayed frames rendered so far (the anchors' clock of the next one).
    pub clock: u64,
}

/// The object material of the coherence sequences, at `world_from_object`.
pub fn uniforms(world_from_object: glam::Mat4) -> npr_gpu::ObjectUniforms {
    let white = glam::Vec3::splat(0.9);
    npr_gpu::ObjectUniforms::new(world_from_object, white, 0.35, glam::Vec3::ONE, 24.0)
}

/// A `width × height` rig hatching `mesh` (stroke `directions` per render vertex) with
/// `tam` in `space`, with surface anchors re-taken every `period` frames.
///
/// # Errors
/// As [`crate::HatchFrame::new`] and [`crate::ScenePasses::create_object`].
pub fn rig(
    ctx: &npr_gpu::GpuContext,
    tam: &crate::TonalArtMap,
    (space, period): (crate::StrokeSpace, u32),
    (mesh, directions): (&npr_gpu::GpuMesh, &[glam::Vec3]),
    (width, height): (u32, u32),
) -> Result<Rig, crate::HatchError> {
    let params = crate::HatchParams {
        space,
        ..Default::default()
    };
    let settings = crate::HatchFrameSettings {
        tam: tam.clone(),
        scene: crate::SceneSettings {
            anchor_period: period,
            ..Default::default()
        },
    };
    let frame = crate::HatchFrame::new(
        &ctx.device,
        &ctx.queue,
        npr_gpu::TargetFormats::default(),
        &settings,
        (width, height),
    )?;
    let object = frame.create_object(&ctx.device, mesh, directions)?;
    Ok(Rig {
        frame,
        object,
        params,
        clock: 0,
    })
}

impl Rig {
    /// Renders the next displayed frame of the object at `world_from_object` (material of
    /// [`uniforms`]) from `camera`, and reads it back.
    ///
    /// # Errors
    /// As [`crate::HatchFrame::render_hatched`].
    pub fn render(
        &mut self,
        ctx: &npr_gpu::GpuContext,
        camera: &npr_gpu::Camera,
        light: &crate::ShadowLight,
        world_from_object: glam::Mat4,
    ) -> Result<image::RgbaImage, crate::HatchError> {
        let clock = self.clock;
        self.clock += 1;
        let view = crate::HatchView {
            frame: npr_gpu::FrameId(clock),
            clock,
            camera,
            light,
            params: &self.params,
        };
        let u = uniforms(world_from_object);
        self.frame.render_hatched(
            &ctx.device,
            &ctx.queue,
            &view,
            &mut [(&mut self.object, &u)],
        )
    }
}
