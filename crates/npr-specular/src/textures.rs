//! Highlight textures generated in code (§5, Fig. 6 of the specular paper: a disc, a
//! star, a normal-map style texture), plus PNG loading.
//!
//! Every texture is square RGBA8 (straight alpha) with a transparent border texel ring,
//! so clamped sampling outside the projector frustum gives nothing. The texture's u axis
//! maps to the projector's `e_max`, v to `e_min` (Eq. (7), (9)).

use crate::SpecularError;
use std::f32::consts::{PI, TAU};
use std::path::Path;

/// The built-in highlight shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HighlightShape {
    /// A hard-edged white disc (Fig. 6b).
    Disc,
    /// A disc with a smooth falloff.
    SoftDisc,
    /// A five-pointed star.
    Star,
    /// A four-point sparkle (thin cross with a bright core).
    Sparkle,
    /// A ring.
    Ring,
    /// A normal map of a hemispherical bump (Fig. 6c): RGB = `(n + 1)/2` in the projector
    /// frame, alpha = footprint. The highlight pass shades it with Blinn's `(N·H)^n`.
    NormalMap,
    /// An elongated ellipse along u (`e_max`): a directional shape whose orientation a
    /// test can measure.
    Streak,
}

impl HighlightShape {
    /// Every built-in shape, in texture-layer order of [`builtin_set`].
    pub const ALL: [HighlightShape; 7] = [
        Self::Disc,
        Self::SoftDisc,
        Self::Star,
        Self::Sparkle,
        Self::Ring,
        Self::NormalMap,
        Self::Streak,
    ];

    /// Lower-case name, used for fixture file names.
    pub fn name(self) -> &'static str {
        match self {
            Self::Disc => "disc",
            Self::SoftDisc => "soft-disc",
            Self::Star => "star",
            Self::Sparkle => "sparkle",
            Self::Ring => "ring",
            Self::NormalMap => "normal-map",
            Self::Streak => "streak",
        }
    }

    /// Whether the texture is a normal map that the pass shades rather than a colour.
    pub fn is_normal_map(self) -> bool {
        self == Self::NormalMap
    }

    /// The layer of this shape in [`builtin_set`].
    pub fn layer(self) -> u32 {
        Self::ALL.iter().position(|s| *s == self).unwrap_or(0) as u32
    }
}

/// Smooth step for anti-aliased edges.
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Coverage of shape `shape` at texture point (x, y) in [-1, 1]² (u = x along `e_max`,
/// v = y along `e_min`), with `aa` the width of one texel in those units. Returns
/// (rgb, alpha).
fn sample(shape: HighlightShape, x: f32, y: f32, aa: f32) -> ([f32; 3], f32) {
    let r = (x * x + y * y).sqrt();
    let white = [1.0; 3];
    match shape {
        HighlightShape::Disc => (white, 1.0 - smoothstep(0.9 - aa, 0.9 + aa, r)),
        HighlightShape::SoftDisc => {
            let a = 1.0 - smoothstep(0.0, 0.92, r);
            (white, a * a * (3.0 - 2.0 * a))
        }
        HighlightShape::Star => {
            // Five points: radius oscillates between inner and outer with the angle.
            let angle = y.atan2(x) + PI / 2.0;
            let k = (angle * 5.0 / TAU).rem_euclid(1.0);
            let tri = (2.0 * k - 1.0).abs(); // 1 at points, 0 between
            let edge = 0.38 + 0.52 * tri;
            (white, 1.0 - smoothstep(edge - aa, edge + aa, r))
        }
        HighlightShape::Sparkle => {
            let arm = |a: f32, b: f32| {
                let width = 0.09 * (1.0 - a.abs()).max(0.0);
                (1.0 - smoothstep(width - aa, width + aa, b.abs()))
                    * (1.0 - smoothstep(0.85, 0.92, a.abs()))
            };
            let core = 1.0 - smoothstep(0.18 - aa, 0.18 + aa, r);
            (white, arm(x, y).max(arm(y, x)).max(core))
        }
        HighlightShape::Ring => {
            let d = (r - 0.65).abs();
            (white, 1.0 - smoothstep(0.16 - aa, 0.16 + aa, d))
        }
        HighlightShape::NormalMap => {
            let rr = r / 0.9;
            if rr >= 1.0 {
                return ([0.5, 0.5, 1.0], 0.0);
            }
            let nz = (1.0 - rr * rr).sqrt();
            let (nx, ny) = (x / 0.9, y / 0.9);
            let a = 1.0 - smoothstep(0.9 - aa, 0.9 + aa, r);
            ([(nx + 1.0) * 0.5, (ny + 1.0) * 0.5, (nz + 1.0) * 0.5], a)
        }
        HighlightShape::Streak => {
            let e = (x / 0.9).powi(2) + (y / 0.3).powi(2);
            (white, 1.0 - smoothstep(1.0 - 3.0 * aa, 1.0 + 3.0 * aa, e))
        }
    }
}

/// Generates `shape` at `size × size` texels (size ≥ 4), supersampled 4×4 per texel.
pub fn generate(shape: HighlightShape, size: u32) -> image::RgbaImage {
    let size = size.max(4);
    let aa = 2.0 / size as f32;
    image::RgbaImage::from_fn(size, size, |i, j| {
        if i == 0 || j == 0 || i == size - 1 || j == size - 1 {
            return image::Rgba([0, 0, 0, 0]);
        }
        let (mut rgb, mut a) = ([0f32; 3], 0f32);
        for sy in 0..4 {
            for sx in 0..4 {
                let x = ((i as f32 + (sx as f32 + 0.5) / 4.0) / size as f32) * 2.0 - 1.0;
                // v grows downwards in texture space; y = +1 at the top row (Eq. (9)).
                let y = 1.0 - ((j as f32 + (sy as f32 + 0.5) / 4.0) / size as f32) * 2.0;
                let (c, al) = sample(shape, x, y, aa * 0.5);
                for k in 0..3 {
                    rgb[k] += c[k] / 16.0;
                }
                a += al / 16.0;
            }
        }
        let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        image::Rgba([q(rgb[0]), q(rgb[1]), q(rgb[2]), q(a)])
    })
}

/// The footprint texture (beyond the paper's set): the ellipse inscribed in the
/// projector's square, fully opaque white, so a projected highlight covers exactly its
/// footprint (what `cargo xtask bench specular-fidelity` measures), with no margin.
pub fn footprint(size: u32) -> image::RgbaImage {
    let size = size.max(4);
    let aa = 2.0 / size as f32;
    image::RgbaImage::from_fn(size, size, |i, j| {
        // The border ring stays clear, as in every texture (clamped sampling outside).
        if i == 0 || j == 0 || i == size - 1 || j == size - 1 {
            return image::Rgba([255, 255, 255, 0]);
        }
        let x = ((i as f32 + 0.5) / size as f32) * 2.0 - 1.0;
        let y = ((j as f32 + 0.5) / size as f32) * 2.0 - 1.0;
        let r = (x * x + y * y).sqrt();
        let a = 1.0 - smoothstep(1.0 - aa, 1.0, r);
        image::Rgba([255, 255, 255, (a * 255.0).round() as u8])
    })
}

/// Every built-in shape at `size`, in [`HighlightShape::ALL`] order (the texture-array
/// layers of the highlight pass).
pub fn builtin_set(size: u32) -> Vec<image::RgbaImage> {
    HighlightShape::ALL
        .iter()
        .map(|s| generate(*s, size))
        .collect()
}

/// Loads a user highlight texture from a PNG, resized to `size × size`, with the border
/// ring cleared so nothing leaks outside the frustum.
///
/// # Errors
/// [`SpecularError::Texture`] when the file cannot be read or decoded.
pub fn load_png(path: &Path, size: u32) -> Result<image::RgbaImage, SpecularError> {
    let img = image::open(path).map_err(|e| SpecularError::Texture {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    let size = size.max(4);
    let mut img = image::imageops::resize(
        &img.to_rgba8(),
        size,
        size,
        image::imageops::FilterType::Triangle,
    );
    for k in 0..size {
        for (x, y) in [(k, 0), (k, size - 1), (0, k), (size - 1, k)] {
            img.put_pixel(x, y, image::Rgba([0, 0, 0, 0]));
        }
    }
    Ok(img)
}

/// The built-in highlight textures as fixture files (`highlight-<name>.png`, 128²), written
/// to `fixtures/` by `cargo xtask fixtures`; a test checks the committed files match.
pub fn fixtures() -> Vec<(String, image::RgbaImage)> {
    HighlightShape::ALL
        .iter()
        .map(|s| (format!("highlight-{}.png", s.name()), generate(*s, 128)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn textures_have_clear_borders_and_content() {
        for shape in HighlightShape::ALL {
            let img = generate(shape, 64);
            let border =
                (0..64).all(|k| img.get_pixel(k, 0).0[3] == 0 && img.get_pixel(0, k).0[3] == 0);
            assert!(border, "{shape:?} border");
            let covered = img.pixels().filter(|p| p.0[3] > 128).count();
            assert!(covered > 64 * 64 / 50, "{shape:?} nearly empty: {covered}");
            assert!(
                covered < 64 * 64 * 9 / 10,
                "{shape:?} nearly full: {covered}"
            );
        }
    }

    #[test]
    fn streak_is_elongated_along_u() {
        let img = generate(HighlightShape::Streak, 64);
        let row = (0..64).filter(|&x| img.get_pixel(x, 32).0[3] > 128).count();
        let col = (0..64).filter(|&y| img.get_pixel(32, y).0[3] > 128).count();
        assert!(row > 2 * col, "row {row} col {col}");
    }
}
