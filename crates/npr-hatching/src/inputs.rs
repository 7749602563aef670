//! The per-pixel inputs of the hatching pass (§2 of Kim & Lee, "Real-time Image-space
//! Hatching"): a tone and a stroke direction θ ∈ [0, π) per pixel, as plain arrays. They
//! come from the G-buffer pass ([`crate::ScenePasses`]) or from the caller: any 2-D
//! source, such as the flow fields of §5 ([`HatchInputs::from_flow`]).
//!
//! Conventions: rows top to bottom, pixel (x, y) at index `y * width + x`. Tone is the
//! linear reflectance the hatching should reproduce, 1 = paper white, 0 = black. θ is the
//! stroke's angle as seen on screen, counter-clockwise from +x (y up), so a stroke in
//! direction θ runs along pixel offsets `(cos θ, −sin θ)` in the y-down pixel grid.

use crate::HatchError;
use std::f32::consts::PI;

/// A pixel's surface anchors ([`crate::StrokeSpace::Surface`]): where its surface point
/// was on the screen (pixels, y down) at the two reference views, and the cross-fade
/// weight of the second.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Anchor {
    /// Position at reference view 0.
    pub a: [f32; 2],
    /// Position at reference view 1.
    pub b: [f32; 2],
    /// Weight of `b` in [0, 1] (`a` gets `1 − weight_b`).
    pub weight_b: f32,
}

impl Anchor {
    /// The anchor of a pixel that does not move: its own centre, twice.
    pub fn fixed(x: f32, y: f32) -> Self {
        Self {
            a: [x, y],
            b: [x, y],
            weight_b: 0.0,
        }
    }
}

/// Tone and direction images of one size, sanitized: tone in [0, 1] (NaN → 1, paper),
/// θ in [0, π) (NaN or infinite → 0); optionally surface anchors per pixel (from the
/// G-buffer pass, [`crate::GBuffer::read`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HatchInputs {
    width: u32,
    height: u32,
    tone: Vec<f32>,
    theta: Vec<f32>,
    anchors: Option<Vec<Anchor>>,
    turn: Option<Vec<f32>>,
}

/// Reduces an angle to [0, π); non-finite angles become 0.
pub fn wrap_theta(theta: f32) -> f32 {
    if !theta.is_finite() {
        return 0.0;
    }
    let t = theta.rem_euclid(PI);
    // rem_euclid can round up to exactly π.
    if t >= PI { 0.0 } else { t }
}

/// Clamps a tone to [0, 1]; NaN becomes 1 (paper).
pub fn sanitize_tone(tone: f32) -> f32 {
    if tone.is_nan() {
        1.0
    } else {
        tone.clamp(0.0, 1.0)
    }
}

pub(crate) fn pixel_count(width: u32, height: u32) -> Result<usize, HatchError> {
    if width == 0 || height == 0 {
        return Err(HatchError::InvalidSize {
            width,
            height,
            reason: "each side must be at least 1",
        });
    }
    (width as usize)
        .checked_mul(height as usize)
        .filter(|n| *n <= (i32::MAX as usize))
        .ok_or(HatchError::InvalidSize {
            width,
            height,
            reason: "too many pixels",
        })
}

impl HatchInputs {
    /// Inputs from a tone image and a θ image (radians, any range: wrapped to [0, π)).
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a zero size, [`HatchError::LengthMismatch`] when an
    /// image does not have `width × height` values.
    pub fn new(width: u32, height: u32, tone: &[f32], theta: &[f32]) -> Result<Self, HatchError> {
        let n = pixel_count(width, height)?;
        for (what, len) in [("tone image", tone.len()), ("direction image", theta.len())] {
            if len != n {
                return Err(HatchError::LengthMismatch {
                    what,
                    expected: n,
                    actual: len,
                });
            }
        }
        Ok(Self {
            width,
            height,
            tone: tone.iter().map(|&t| sanitize_tone(t)).collect(),
            theta: theta.iter().map(|&t| wrap_theta(t)).collect(),
            anchors: None,
            turn: None,
        })
    }

    /// A constant tone and direction everywhere.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a zero size.
    pub fn constant(width: u32, height: u32, tone: f32, theta: f32) -> Result<Self, HatchError> {
        let n = pixel_count(width, height)?;
        Ok(Self {
            width,
            height,
            tone: vec![sanitize_tone(tone); n],
            theta: vec![wrap_theta(theta); n],
            anchors: None,
            turn: None,
        })
    }

    /// Inputs from a function of the pixel centre `(x + ½, y + ½)` giving `(tone, θ)`.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a zero size.
    pub fn from_fn(
        width: u32,
        height: u32,
        f: impl Fn(f32, f32) -> (f32, f32),
    ) -> Result<Self, HatchError> {
        let n = pixel_count(width, height)?;
        let (mut tone, mut theta) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for y in 0..height {
            for x in 0..width {
                let (t, a) = f(x as f32 + 0.5, y as f32 + 0.5);
                tone.push(sanitize_tone(t));
                theta.push(wrap_theta(a));
            }
        }
        Ok(Self {
            width,
            height,
            tone,
            theta,
            anchors: None,
            turn: None,
        })
    }

    /// 2-D flow visualisation (§5 of the paper: "2-D flow visualisation" as a further use).
    /// `direction` holds one vector `[vx, vy]` per pixel in screen axes (x right, y up);
    /// the strokes follow it (θ = atan2(vy, vx) mod π, a line field, so v and −v agree).
    /// `magnitude` holds one value per pixel; tone = `1 − magnitude / max_magnitude`
    /// clamped, so strong flow is drawn dark. A zero vector gets θ = 0.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`], [`HatchError::LengthMismatch`] as [`HatchInputs::new`];
    /// [`HatchError::InvalidParams`] when `max_magnitude` is not finite and > 0.
    pub fn from_flow(
        width: u32,
        height: u32,
        direction: &[[f32; 2]],
        magnitude: &[f32],
        max_magnitude: f32,
    ) -> Result<Self, HatchError> {
        let n = pixel_count(width, height)?;
        for (what, len) in [
            ("flow direction image", direction.len()),
            ("flow magnitude image", magnitude.len()),
        ] {
            if len != n {
                return Err(HatchError::LengthMismatch {
                    what,
                    expected: n,
                    actual: len,
                });
            }
        }
        if !(max_magnitude.is_finite() && max_magnitude > 0.0) {
            return Err(HatchError::InvalidParams {
                what: "max_magnitude",
                reason: format!("finite and > 0, got {max_magnitude}"),
            });
        }
        let theta = direction
            .iter()
            .map(|&[vx, vy]| {
                if vx * vx + vy * vy > 0.0 {
                    wrap_theta(vy.atan2(vx))
                } else {
                    0.0
                }
            })
            .collect();
        let tone = magnitude
            .iter()
            .map(|&m| sanitize_tone(1.0 - m / max_magnitude))
            .collect();
        Ok(Self {
            width,
            height,
            tone,
            theta,
            anchors: None,
            turn: None,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The tone image (row-major).
    pub fn tone(&self) -> &[f32] {
        &self.tone
    }

    /// The θ image in radians, [0, π) (row-major).
    pub fn theta(&self) -> &[f32] {
        &self.theta
    }

    /// Interleaved `(tone, θ)` pairs, the layout of the `Rg32Float` G-buffer.
    pub fn interleaved(&self) -> Vec<[f32; 2]> {
        self.tone
            .iter()
            .zip(&self.theta)
            .map(|(&t, &a)| [t, a])
            .collect()
    }

    /// Inputs from interleaved `(tone, θ)` pairs, e.g. a G-buffer read back with
    /// [`crate::GBuffer::read`].
    ///
    /// # Errors
    /// As [`HatchInputs::new`].
    pub fn from_interleaved(
        width: u32,
        height: u32,
        pairs: &[[f32; 2]],
    ) -> Result<Self, HatchError> {
        let n = pixel_count(width, height)?;
        if pairs.len() != n {
            return Err(HatchError::LengthMismatch {
                what: "G-buffer",
                expected: n,
                actual: pairs.len(),
            });
        }
        Ok(Self {
            width,
            height,
            tone: pairs.iter().map(|p| sanitize_tone(p[0])).collect(),
            theta: pairs.iter().map(|p| wrap_theta(p[1])).collect(),
            anchors: None,
            turn: None,
        })
    }

    /// These inputs with surface anchors, one per pixel (row-major); non-finite positions
    /// become the pixel's centre, weights are clamped to [0, 1] (NaN → 0).
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] when `anchors` does not have one entry per pixel.
    pub fn with_anchors(mut self, anchors: Vec<Anchor>) -> Result<Self, HatchError> {
        let n = self.tone.len();
        if anchors.len() != n {
            return Err(HatchError::LengthMismatch {
                what: "anchor image",
                expected: n,
                actual: anchors.len(),
            });
        }
        let w = self.width as usize;
        let clean = anchors
            .into_iter()
            .enumerate()
            .map(|(i, an)| {
                let centre = [(i % w) as f32 + 0.5, (i / w) as f32 + 0.5];
                let pos = |p: [f32; 2]| {
                    if p[0].is_finite() && p[1].is_finite() {
                        p
                    } else {
                        centre
                    }
                };
                Anchor {
                    a: pos(an.a),
                    b: pos(an.b),
                    weight_b: if an.weight_b.is_nan() {
                        0.0
                    } else {
                        an.weight_b.clamp(0.0, 1.0)
                    },
                }
            })
            .collect();
        self.anchors = Some(clean);
        Ok(self)
    }

    /// These inputs with the stroke direction's turn rate per pixel (radians per pixel,
    /// row-major; [`crate::StrokeLength`]); non-finite or negative values become 0.
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] when `turn` does not have one entry per pixel.
    pub fn with_turn(mut self, turn: Vec<f32>) -> Result<Self, HatchError> {
        if turn.len() != self.tone.len() {
            return Err(HatchError::LengthMismatch {
                what: "turn-rate image",
                expected: self.tone.len(),
                actual: turn.len(),
            });
        }
        self.turn = Some(
            turn.into_iter()
                .map(|t| if t.is_finite() { t.max(0.0) } else { 0.0 })
                .collect(),
        );
        Ok(self)
    }

    /// The turn rate of the stroke direction per pixel (rad/pixel), if any.
    pub fn turn(&self) -> Option<&[f32]> {
        self.turn.as_deref()
    }

    /// The surface anchors (row-major), if any.
    pub fn anchors(&self) -> Option<&[Anchor]> {
        self.anchors.as_deref()
    }

    /// Sets the tone of every pixel whose index `select` accepts to `tone` (e.g. a
    /// constant tone over an object, for measuring stroke density).
    pub fn set_tone_where(&mut self, tone: f32, mut select: impl FnMut(usize) -> bool) {
        let t = sanitize_tone(tone);
        for (i, v) in self.tone.iter_mut().enumerate() {
            if select(i) {
                *v = t;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_inputs_are_errors_not_panics() {
        assert!(matches!(
            HatchInputs::new(0, 4, &[], &[]),
            Err(HatchError::InvalidSize { .. })
        ));
        assert!(matches!(
            HatchInputs::new(2, 2, &[0.5; 4], &[0.0; 3]),
            Err(HatchError::LengthMismatch { .. })
        ));
        assert!(matches!(
            HatchInputs::from_flow(2, 1, &[[1.0, 0.0]; 2], &[1.0; 2], 0.0),
            Err(HatchError::InvalidParams { .. })
        ));
        let i = HatchInputs::new(
            3,
            1,
            &[f32::NAN, -2.0, 7.0],
            &[f32::NAN, -0.5, f32::INFINITY],
        )
        .unwrap();
        assert_eq!(i.tone(), &[1.0, 0.0, 1.0]);
        assert_eq!(i.theta()[0], 0.0);
        assert!((i.theta()[1] - (PI - 0.5)).abs() < 1e-6);
        assert_eq!(i.theta()[2], 0.0);
    }

    #[test]
    fn wrap_theta_stays_in_range() {
        for k in -1000..1000 {
            let t = wrap_theta(k as f32 * 0.0173);
            assert!((0.0..PI).contains(&t), "{t}");
        }
        assert_eq!(wrap_theta(-0.0), 0.0);
    }
}
