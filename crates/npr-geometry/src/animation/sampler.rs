//! The animation sampler: key times, output values and the three glTF interpolations
//! (glTF 2.0, §3.11 Animations, and Appendix C, Interpolation).

use glam::{DQuat, Quat};

use super::AnimationError;

/// How a sampler interpolates between its keys (glTF 2.0, §3.11,
/// `animation.sampler.interpolation`; Appendix C, Interpolation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Interpolation {
    /// The value of the key at or before `t` holds until the next key.
    Step,
    /// Linear interpolation; rotations by spherical linear interpolation along the
    /// shorter arc (Appendix C, "Spherical Linear Interpolation").
    #[default]
    Linear,
    /// Cubic Hermite spline: each key stores an in-tangent, a value and an out-tangent,
    /// and the tangents are scaled by the key interval (Appendix C, "Cubic Spline
    /// Interpolation").
    CubicSpline,
}

/// One animation sampler: strictly increasing, finite key times, and `width` output
/// components per key (three times as many for [`Interpolation::CubicSpline`]: the
/// in-tangent, value and out-tangent of each key, in that order, as glTF stores them).
///
/// Before the first key the first value holds, after the last key the last value holds
/// (glTF 2.0, §3.11 Animations: outside the keyed range the end values are held); for
/// CUBICSPLINE these are the keys' values, not their tangents.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    interpolation: Interpolation,
    times: Vec<f32>,
    values: Vec<f32>,
    width: usize,
}

impl Sampler {
    /// A sampler over `times` (seconds) and the flat output `values`, `width`
    /// components per output element.
    ///
    /// # Errors
    /// [`AnimationError::NoKeys`] for no key or `width == 0`,
    /// [`AnimationError::NonFiniteKey`] for a NaN or infinite time or value,
    /// [`AnimationError::TimesNotIncreasing`], and [`AnimationError::CubicSplineOutputs`]
    /// or [`AnimationError::OutputCount`] when `values` does not hold one element (three
    /// for CUBICSPLINE) per key.
    pub fn new(
        interpolation: Interpolation,
        times: Vec<f32>,
        values: Vec<f32>,
        width: usize,
    ) -> Result<Self, AnimationError> {
        if times.is_empty() || width == 0 {
            return Err(AnimationError::NoKeys);
        }
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(AnimationError::NonFiniteKey {
                what: "time",
                key: k,
            });
        }
        if let Some(k) = (1..times.len()).find(|&k| !(times[k] > times[k - 1])) {
            return Err(AnimationError::TimesNotIncreasing {
                key: k,
                time: times[k],
                previous: times[k - 1],
            });
        }
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let outputs = values.len() / width;
        if !values.len().is_multiple_of(width) || outputs != per_key * times.len() {
            return Err(if per_key == 3 {
                AnimationError::CubicSplineOutputs {
                    keys: times.len(),
                    outputs,
                    width,
                }
            } else {
                AnimationError::OutputCount {
                    keys: times.len(),
                    outputs,
                    width,
                }
            });
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(AnimationError::NonFiniteKey {
                what: "value",
                key: i / width / per_key,
            });
        }
        Ok(Self {
            interpolation,
            times,
            values,
            width,
        })
    }

    /// The interpolation.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// The key times, strictly increasing.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// Components per output element (3, 4, or the morph target count).
    pub fn width(&self) -> usize {
        self.width
    }

    /// The first key's time.
    pub fn start(&self) -> f32 {
        self.times.first().copied().unwrap_or(0.0)
    }

    /// The last key's time.
    pub fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Component `d` of output element `e` (for CUBICSPLINE, element `3k` is key `k`'s
    /// in-tangent, `3k + 1` its value, `3k + 2` its out-tangent).
    fn at(&self, e: usize, d: usize) -> f64 {
        f64::from(self.values.get(e * self.width + d).copied().unwrap_or(0.0))
    }

    /// Key `k`'s value element.
    fn value_element(&self, k: usize) -> usize {
        if self.interpolation == Interpolation::CubicSpline {
            3 * k + 1
        } else {
            k
        }
    }

    /// Where `t` falls: `Err(k)` when key `k`'s value holds (before the first key, after
    /// the last, exactly on a key for STEP), `Ok((k, s, dt))` for `t` in key interval
    /// `[t_k, t_k+1)` with `s = (t - t_k) / dt` in `[0, 1)`.
    fn locate(&self, t: f32) -> Result<(usize, f64, f64), usize> {
        let n = self.times.len();
        // `!(t > t0)` also catches NaN: it holds the first value.
        if !(t > self.times[0]) {
            return Err(0);
        }
        if t >= self.times[n - 1] {
            return Err(n - 1);
        }
        // The last key with time <= t (exists: t > times[0]).
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (f64::from(self.times[k]), f64::from(self.times[k + 1]));
        let dt = t1 - t0;
        Ok((k, (f64::from(t) - t0) / dt, dt))
    }

    /// The output at time `t`, component-wise (translation, scale, morph weights; for a
    /// rotation use [`Sampler::sample_rotation`]). `width` values.
    pub fn sample(&self, t: f32) -> Vec<f32> {
        let w = self.width;
        let (k, s, dt) = match self.locate(t) {
            Err(k) => {
                let e = self.value_element(k);
                return (0..w).map(|d| self.at(e, d) as f32).collect();
            }
            Ok(x) => x,
        };
        match self.interpolation {
            Interpolation::Step => (0..w).map(|d| self.at(k, d) as f32).collect(),
            Interpolation::Linear => (0..w)
                .map(|d| {
                    let (a, b) = (self.at(k, d), self.at(k + 1, d));
                    (a + s * (b - a)) as f32
                })
                .collect(),
            Interpolation::CubicSpline => {
                (0..w).map(|d| self.hermite(k, s, dt, d) as f32).collect()
            }
        }
    }

    /// glTF 2.0 Appendix C, "Cubic Spline Interpolation": with `s` the normalised time in
    /// the interval and `dt = t_k+1 - t_k`,
    /// `p(s) = (2s³ - 3s² + 1) v_k + (s³ - 2s² + s) dt b_k + (-2s³ + 3s²) v_k+1
    /// + (s³ - s²) dt a_k+1`, where `b_k` is key `k`'s out-tangent and `a_k+1` key
    /// `k + 1`'s in-tangent.
    fn hermite(&self, k: usize, s: f64, dt: f64, d: usize) -> f64 {
        let v0 = self.at(3 * k + 1, d);
        let b0 = self.at(3 * k + 2, d);
        let a1 = self.at(3 * (k + 1), d);
        let v1 = self.at(3 * (k + 1) + 1, d);
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * v0
            + (s3 - 2.0 * s2 + s) * dt * b0
            + (-2.0 * s3 + 3.0 * s2) * v1
            + (s3 - s2) * dt * a1
    }

    /// The rotation at time `t` (`width` must be 4: `x, y, z, w`), a unit quaternion.
    /// LINEAR is spherical linear interpolation along the shorter arc (glTF 2.0,
    /// Appendix C, "Spherical Linear Interpolation"); CUBICSPLINE is the component-wise
    /// spline, normalised, as the specification requires; STEP is the key's value,
    /// normalised. A zero quaternion gives the identity.
    pub fn sample_rotation(&self, t: f32) -> Quat {
        let q =
            |e: usize| DQuat::from_xyzw(self.at(e, 0), self.at(e, 1), self.at(e, 2), self.at(e, 3));
        let r = match (self.locate(t), self.interpolation) {
            (Err(k), _) => q(self.value_element(k)),
            (Ok((k, _, _)), Interpolation::Step) => q(k),
            (Ok((k, s, _)), Interpolation::Linear) => slerp(q(k), q(k + 1), s),
            (Ok((k, s, dt)), Interpolation::CubicSpline) => DQuat::from_xyzw(
                self.hermite(k, s, dt, 0),
                self.hermite(k, s, dt, 1),
                self.hermite(k, s, dt, 2),
                self.hermite(k, s, dt, 3),
            ),
        };
        let len = r.length();
        if len > 0.0 && len.is_finite() {
            (r / len).as_quat()
        } else {
            Quat::IDENTITY
        }
    }
}

/// Spherical linear interpolation of unit quaternions along the shorter arc, as glTF
/// 2.0 Appendix C writes it: `a = acos(|q0·q1|)`, `s = sign(q0·q1)`,
/// `slerp = sin(a(1-t))/sin(a) q0 + s sin(a t)/sin(a) q1`; nearly parallel keys (where
/// `sin(a)` vanishes) interpolate linearly and normalise.
fn slerp(q0: DQuat, q1: DQuat, t: f64) -> DQuat {
    let (q0, q1) = (q0.normalize(), q1.normalize());
    let d = q0.dot(q1);
    let s = if d < 0.0 { -1.0 } else { 1.0 };
    let c = d.abs().min(1.0);
    if c > 1.0 - 1e-9 {
        return (q0 * (1.0 - t) + q1 * (s * t)).normalize();
    }
    let a = c.acos();
    let sa = a.sin();
    q0 * ((a * (1.0 - t)).sin() / sa) + q1 * (s * (a * t).sin() / sa)
}
