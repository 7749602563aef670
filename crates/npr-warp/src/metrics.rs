//! Image quality of a warped frame against the full render at the same pose, over the
//! object's pixels: PSNR and SSIM (Z. Wang, A. C. Bovik, H. R. Sheikh, E. P. Simoncelli,
//! "Image quality assessment: from error visibility to structural similarity", IEEE TIP
//! 13(4), 2004). The paper (§4) compares its figures by eye only; these numbers are ours.
//!
//! Object pixels: those with alpha > 0 in either image (render with a clear alpha of 0;
//! every pass of the workspace writes alpha 1), so holes and spills both count.
//!
//! PSNR and SSIM are pure Rust and always built: the `npr` binary and the browser report
//! them. With the `test-support` feature, `flip_mean` is FLIP (P. Andersson, J. Nilsson,
//! T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild, "FLIP: A Difference
//! Evaluator for Alternating Images", HPG 2020; NVIDIA's C++ library through the `nv-flip`
//! crate, which wgpu's own image tests use): a perceptual difference in 0..1 per pixel,
//! weighing edges and colour as a viewer does, so a silhouette that moves scores far above
//! the same energy spread evenly.

/// PSNR and SSIM of a test image against a reference image over the object's pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// Peak signal-to-noise ratio in dB over the RGB channels of the object's pixels (8-bit
    /// sRGB values, peak 255); [`PSNR_CAP_DB`] when identical.
    pub psnr_db: f64,
    /// Mean SSIM of the luma (Rec. 601 weights on sRGB values) over windows centred on
    /// object pixels: 7 × 7 box windows, `C1 = (0.01·255)²`, `C2 = (0.03·255)²`.
    pub ssim: f64,
    /// Object pixels compared.
    pub pixels: usize,
    /// Largest per-channel absolute difference over the object's pixels.
    pub max_abs_diff: u8,
}

/// The PSNR reported for identical images (instead of infinity).
pub const PSNR_CAP_DB: f64 = 100.0;

/// Compares `test` with `reference` (same size) over the object's pixels. Images of
/// different sizes, or without object pixels, give `pixels = 0`, PSNR 0 and SSIM 0.
pub fn compare(reference: &image::RgbaImage, test: &image::RgbaImage) -> Quality {
    let empty = Quality {
        psnr_db: 0.0,
        ssim: 0.0,
        pixels: 0,
        max_abs_diff: 255,
    };
    if reference.dimensions() != test.dimensions() {
        return empty;
    }
    let (w, h) = (reference.width() as usize, reference.height() as usize);
    let (a, b) = (reference.as_raw(), test.as_raw());
    let mask: Vec<bool> = (0..w * h)
        .map(|i| a[4 * i + 3] > 0 || b[4 * i + 3] > 0)
        .collect();
    let pixels = mask.iter().filter(|m| **m).count();
    if pixels == 0 {
        return empty;
    }
    // Transparent pixels count as black (the clear colour), as in `difference_image`.
    let rgb = |img: &[u8], i: usize, c: usize| {
        if img[4 * i + 3] > 0 {
            img[4 * i + c]
        } else {
            0
        }
    };
    let mut sq = 0.0f64;
    let mut max_abs_diff = 0u8;
    for i in (0..w * h).filter(|&i| mask[i]) {
        for c in 0..3 {
            let d = rgb(a, i, c).abs_diff(rgb(b, i, c));
            max_abs_diff = max_abs_diff.max(d);
            sq += f64::from(d) * f64::from(d);
        }
    }
    let mse = sq / (pixels * 3) as f64;
    let psnr_db = if mse > 0.0 {
        (10.0 * (255.0 * 255.0 / mse).log10()).min(PSNR_CAP_DB)
    } else {
        PSNR_CAP_DB
    };
    let luma = |img: &[u8]| -> Vec<f64> {
        (0..w * h)
            .map(|i| {
                0.299 * f64::from(rgb(img, i, 0))
                    + 0.587 * f64::from(rgb(img, i, 1))
                    + 0.114 * f64::from(rgb(img, i, 2))
            })
            .collect()
    };
    let ssim = ssim_masked(&luma(a), &luma(b), w, h, &mask);
    Quality {
        psnr_db,
        ssim,
        pixels,
        max_abs_diff,
    }
}

/// FLIP of two frames (moved to the GPU crate's test support, which every technique
/// crate's tests share).
#[cfg(any(test, feature = "test-support"))]
pub use npr_gpu::testing::{flip_mean, flip_stats};

/// A picture of the per-pixel difference: `gain × |a − b|` per RGB channel over the
/// object's pixels (alpha > 0 in either), opaque black elsewhere. Mismatched sizes give
/// an empty image.
pub fn difference_image(a: &image::RgbaImage, b: &image::RgbaImage, gain: f32) -> image::RgbaImage {
    if a.dimensions() != b.dimensions() {
        return image::RgbaImage::new(0, 0);
    }
    image::RgbaImage::from_fn(a.width(), a.height(), |x, y| {
        let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
        if p[3] == 0 && q[3] == 0 {
            return image::Rgba([0, 0, 0, 255]);
        }
        // Transparent pixels count as black (the clear colour).
        let c = |i: usize| {
            let u = if p[3] > 0 { f32::from(p[i]) } else { 0.0 };
            let v = if q[3] > 0 { f32::from(q[i]) } else { 0.0 };
            ((u - v).abs() * gain).min(255.0) as u8
        };
        image::Rgba([c(0), c(1), c(2), 255])
    })
}

/// Summed-area table with a zero row and column in front: `(w+1) × (h+1)`.
fn integral(v: &[f64], w: usize, h: usize) -> Vec<f64> {
    let mut s = vec![0.0; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = 0.0;
        for x in 0..w {
            row += v[y * w + x];
            s[(y + 1) * (w + 1) + x + 1] = s[y * (w + 1) + x + 1] + row;
        }
    }
    s
}

/// Mean SSIM over 7 × 7 box windows (clipped at the border) centred on masked pixels.
fn ssim_masked(x: &[f64], y: &[f64], w: usize, h: usize, mask: &[bool]) -> f64 {
    const R: usize = 3;
    let c1 = (0.01f64 * 255.0).powi(2);
    let c2 = (0.03f64 * 255.0).powi(2);
    let xx: Vec<f64> = x.iter().map(|v| v * v).collect();
    let yy: Vec<f64> = y.iter().map(|v| v * v).collect();
    let xy: Vec<f64> = x.iter().zip(y).map(|(a, b)| a * b).collect();
    let [sx, sy, sxx, syy, sxy] = [x, y, &xx[..], &yy[..], &xy[..]].map(|v| integral(v, w, h));
    let mut total = 0.0;
    let mut count = 0usize;
    for py in 0..h {
        for px in 0..w {
            if !mask[py * w + px] {
                continue;
            }
            let (x0, x1) = (px.saturating_sub(R), (px + R + 1).min(w));
            let (y0, y1) = (py.saturating_sub(R), (py + R + 1).min(h));
            let n = ((x1 - x0) * (y1 - y0)) as f64;
            let sum = |s: &[f64]| {
                s[y1 * (w + 1) + x1] - s[y0 * (w + 1) + x1] - s[y1 * (w + 1) + x0]
                    + s[y0 * (w + 1) + x0]
            };
            let (mx, my) = (sum(&sx) / n, sum(&sy) / n);
            let vx = (sum(&sxx) / n - mx * mx).max(0.0);
            let vy = (sum(&syy) / n - my * my).max(0.0);
            let cxy = sum(&sxy) / n - mx * my;
            total += ((2.0 * mx * my + c1) * (2.0 * cxy + c2))
                / ((mx * mx + my * my + c1) * (vx + vy + c2));
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        total / count as f64
    }
}

/// Reads an 8-bit RGBA or BGRA colour texture (`Rgba8Unorm[Srgb]`, `Bgra8Unorm[Srgb]`)
/// back as an RGBA image (BGRA swizzled), to [`compare`] a warped frame of an application's
/// target with a full render. Submits and waits: call it outside a frame.
///
/// # Errors
/// [`crate::WarpError::Gpu`] for another format or a failed readback.
pub fn read_rgba(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<image::RgbaImage, crate::WarpError> {
    use wgpu::TextureFormat as F;
    let format = texture.format();
    let bgra = match format {
        F::Rgba8Unorm | F::Rgba8UnormSrgb => false,
        F::Bgra8Unorm | F::Bgra8UnormSrgb => true,
        _ => return Err(npr_gpu::GpuError::UnsupportedFormat(format).into()),
    };
    let mut bytes = npr_gpu::readback_texture(device, queue, texture)?;
    if bgra {
        for p in bytes.chunks_exact_mut(4) {
            p.swap(0, 2);
        }
    }
    image::RgbaImage::from_raw(texture.width(), texture.height(), bytes).ok_or_else(|| {
        npr_gpu::GpuError::Readback("buffer size does not match the image".into()).into()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(shift: u8) -> image::RgbaImage {
        image::RgbaImage::from_fn(64, 48, |x, y| {
            let dx = x as i32 - 32;
            let dy = y as i32 - 24;
            if dx * dx + dy * dy < 300 {
                image::Rgba([(x * 3) as u8 + shift, (y * 4) as u8, 90, 255])
            } else {
                image::Rgba([0, 0, 0, 0])
            }
        })
    }

    #[test]
    fn identical_images_are_perfect() {
        let q = compare(&disc(0), &disc(0));
        assert_eq!(q.psnr_db, PSNR_CAP_DB);
        assert!((q.ssim - 1.0).abs() < 1e-12);
        assert_eq!(q.max_abs_diff, 0);
        assert!(q.pixels > 800);
    }

    #[test]
    fn psnr_of_a_constant_offset_is_analytic() {
        // Every object pixel off by 4 in red only: MSE = 16 / 3.
        let q = compare(&disc(0), &disc(4));
        let expected = 10.0 * (255.0f64 * 255.0 / (16.0 / 3.0)).log10();
        assert!((q.psnr_db - expected).abs() < 1e-9, "{}", q.psnr_db);
        assert!(q.ssim < 1.0 && q.ssim > 0.9);
    }

    /// A disc of radius `r` centred at `cx` in a constant colour, as `compare`'s object.
    fn flat_disc(cx: f32, r: f32, red: u8) -> image::RgbaImage {
        image::RgbaImage::from_fn(64, 48, |x, y| {
            let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - 24.0);
            if dx * dx + dy * dy < r * r {
                image::Rgba([red, 140, 90, 255])
            } else {
                image::Rgba([0, 0, 0, 0])
            }
        })
    }

    #[test]
    fn flip_is_zero_for_identical_images_and_weighs_silhouettes() {
        let a = flat_disc(32.0, 15.0, 200);
        let same = flip_mean(&a, &a.clone()).unwrap();
        assert!(same.abs() < 1e-6, "{same}");
        // Every object pixel 1/255 off: barely visible.
        let uniform = flip_mean(&a, &flat_disc(32.0, 15.0, 201)).unwrap();
        // The silhouette shifted by two pixels: a visible edge.
        let shifted = flip_mean(&a, &flat_disc(34.0, 15.0, 200)).unwrap();
        eprintln!("FLIP: 1/255 everywhere {uniform}, silhouette moved 2 px {shifted}");
        assert!(uniform > 0.0 && uniform < 0.1, "{uniform}");
        assert!(shifted > 2.0 * uniform, "{shifted} vs {uniform}");
        // Larger shifts score higher.
        let further = flip_mean(&a, &flat_disc(37.0, 15.0, 200)).unwrap();
        assert!(further > shifted, "{further} vs {shifted}");
        let (mean, max) = flip_stats(&a, &flat_disc(34.0, 15.0, 200)).unwrap();
        assert!((mean - shifted).abs() < 1e-12 && max >= mean && max <= 1.0);
        assert_eq!(flip_mean(&a, &image::RgbaImage::new(3, 3)), None);
    }

    #[test]
    fn mismatched_sizes_give_no_pixels() {
        let q = compare(&disc(0), &image::RgbaImage::new(3, 3));
        assert_eq!(q.pixels, 0);
    }
}
