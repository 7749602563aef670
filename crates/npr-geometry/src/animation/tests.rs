//! Sampler tests against values worked out by hand (glTF 2.0 Appendix C), not by
//! re-running the sampler's formulas.

use glam::{Quat, Vec3};

use super::*;

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-6
}

fn scalar(i: Interpolation, times: &[f32], values: &[f32]) -> Sampler {
    Sampler::new(i, times.to_vec(), values.to_vec(), 1).unwrap()
}

#[test]
fn step_holds_the_key_at_or_before_t() {
    let s = scalar(Interpolation::Step, &[0.0, 1.0, 2.0], &[1.0, 2.0, 4.0]);
    for (t, want) in [
        (-1.0, 1.0),
        (0.0, 1.0),
        (0.5, 1.0),
        (0.999, 1.0),
        (1.0, 2.0),
        (1.99, 2.0),
        (2.0, 4.0),
        (7.0, 4.0),
    ] {
        assert_eq!(s.sample(t), vec![want], "t = {t}");
    }
}

#[test]
fn linear_interpolates_and_clamps() {
    let s = scalar(Interpolation::Linear, &[0.0, 2.0], &[0.0, 10.0]);
    assert!(close(s.sample(0.5)[0], 2.5));
    assert!(close(s.sample(1.5)[0], 7.5));
    assert_eq!(s.sample(-3.0), vec![0.0]);
    assert_eq!(s.sample(9.0), vec![10.0]);
    assert_eq!(s.sample(f32::NAN), vec![0.0]);
    // Vec3 over [1, 3]: t = 2.5 is 3/4 of the way from (0, 0, 0) to (4, -2, 8).
    let v = Sampler::new(
        Interpolation::Linear,
        vec![1.0, 3.0],
        vec![0.0, 0.0, 0.0, 4.0, -2.0, 8.0],
        3,
    )
    .unwrap();
    let got = v.sample(2.5);
    for (g, w) in got.iter().zip([3.0, -1.5, 6.0]) {
        assert!(close(*g, w), "{got:?}");
    }
}

fn rot(i: Interpolation, times: &[f32], qs: &[Quat]) -> Sampler {
    let v = qs.iter().flat_map(|q| q.to_array()).collect();
    Sampler::new(i, times.to_vec(), v, 4).unwrap()
}

fn same_rotation(a: Quat, b: Quat) -> bool {
    a.dot(b).abs() > 1.0 - 1e-6
}

#[test]
fn linear_rotation_is_slerp_on_the_short_arc() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    // Identity to 90° about z: halfway is 45° about z = (0, 0, sin 22.5°, cos 22.5°).
    let q90 = Quat::from_xyzw(0.0, 0.0, h, h);
    let s = rot(Interpolation::Linear, &[0.0, 1.0], &[Quat::IDENTITY, q90]);
    let half = s.sample_rotation(0.5);
    assert!(same_rotation(
        half,
        Quat::from_xyzw(0.0, 0.0, 0.382_683_43, 0.923_879_5)
    ));
    // A third of the way: 30° about z = (0, 0, sin 15°, cos 15°); a normalised lerp
    // would give (0, 0, 0.2559, 0.9667) instead.
    let third = s.sample_rotation(1.0 / 3.0);
    assert!(same_rotation(
        third,
        Quat::from_xyzw(0.0, 0.0, 0.258_819_04, 0.965_925_8)
    ));
    // The same key written as -q90: the shorter arc still gives 45°, not 135°.
    let neg = rot(Interpolation::Linear, &[0.0, 1.0], &[Quat::IDENTITY, -q90]);
    assert!(same_rotation(
        neg.sample_rotation(0.5),
        Quat::from_xyzw(0.0, 0.0, 0.382_683_43, 0.923_879_5)
    ));
    // Clamped at both ends.
    assert!(same_rotation(s.sample_rotation(-1.0), Quat::IDENTITY));
    assert!(same_rotation(s.sample_rotation(4.0), q90));
}

/// Keys at t = 0 and t = 2 (Δt = 2); key 0: in 0, value 1, out 3; key 1: in -1,
/// value 2, out 0.
fn spline() -> Sampler {
    scalar(
        Interpolation::CubicSpline,
        &[0.0, 2.0],
        &[0.0, 1.0, 3.0, -1.0, 2.0, 0.0],
    )
}

#[test]
fn cubic_spline_scales_tangents_by_the_key_interval() {
    let s = spline();
    // s = 1/2: h00 = 1/2, h10 = 1/8, h01 = 1/2, h11 = -1/8;
    // p = 1/2·1 + 1/8·2·3 + 1/2·2 + (-1/8)·2·(-1) = 0.5 + 0.75 + 1 + 0.25 = 2.5
    // (2.0 if the tangents were not multiplied by Δt).
    assert!(close(s.sample(1.0)[0], 2.5), "{:?}", s.sample(1.0));
    // s = 1/4: h00 = 27/32, h10 = 9/64, h01 = 5/32, h11 = -3/64;
    // p = 27/32 + 9/64·6 + 5/32·2 + 3/64·2 = 2.09375.
    assert!(close(s.sample(0.5)[0], 2.093_75), "{:?}", s.sample(0.5));
    // Outside the keys: the values, not the tangents.
    assert_eq!(s.sample(-1.0), vec![1.0]);
    assert_eq!(s.sample(2.0), vec![2.0]);
    assert_eq!(s.sample(3.0), vec![2.0]);
}

#[test]
fn cubic_spline_rotation_is_normalised() {
    // Values identity and 180° about z, zero tangents: at s = 1/2 the spline gives
    // (0, 0, 1/2, 1/2), which normalised is 90° about z.
    let z = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let s = rot(
        Interpolation::CubicSpline,
        &[0.0, 1.0],
        &[
            z,
            Quat::IDENTITY,
            z,
            z,
            Quat::from_xyzw(0.0, 0.0, 1.0, 0.0),
            z,
        ],
    );
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let q = s.sample_rotation(0.5);
    assert!(close(q.length(), 1.0));
    assert!(same_rotation(q, Quat::from_xyzw(0.0, 0.0, h, h)), "{q:?}");
}

#[test]
fn bad_samplers_are_typed_errors() {
    let e = |i, t: &[f32], v: &[f32], w| Sampler::new(i, t.to_vec(), v.to_vec(), w).unwrap_err();
    assert_eq!(
        e(Interpolation::Linear, &[], &[], 1),
        AnimationError::NoKeys
    );
    assert_eq!(
        e(Interpolation::Linear, &[0.0, 1.0, 1.0], &[0.0; 3], 1).kind(),
        "times-not-increasing"
    );
    assert_eq!(
        e(Interpolation::Linear, &[1.0, 0.5], &[0.0; 2], 1).kind(),
        "times-not-increasing"
    );
    assert_eq!(
        e(Interpolation::Step, &[0.0, f32::NAN], &[0.0; 2], 1),
        AnimationError::NonFiniteKey {
            what: "time",
            key: 1
        }
    );
    assert_eq!(
        e(
            Interpolation::Linear,
            &[0.0, 1.0],
            &[0.0, 0.0, 0.0, 0.0, f32::NAN, 0.0],
            3
        ),
        AnimationError::NonFiniteKey {
            what: "value",
            key: 1
        }
    );
    assert_eq!(
        e(Interpolation::CubicSpline, &[0.0, 1.0], &[0.0; 4], 1).kind(),
        "cubic-spline-outputs"
    );
    assert_eq!(
        e(Interpolation::Linear, &[0.0, 1.0], &[0.0; 5], 3).kind(),
        "output-count"
    );
}

#[test]
fn trs_matrix_is_t_r_s() {
    let t = Trs {
        translation: Vec3::new(1.0, 2.0, 3.0),
        rotation: Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
        scale: Vec3::new(2.0, 1.0, 1.0),
    };
    // x scaled to 2, rotated to +y, moved by (1, 2, 3).
    let p = t.matrix().transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-6, "{p}");
}
