// Numeric helpers the compute passes share (composed before `curvature.wgsl` and the
// technique crates' compute shaders that name it in their prelude).

// Whether `x` is neither infinite nor NaN, from its bits: a compiler may assume no NaN
// in float comparisons.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// atan2(y, x) from `atan` of a ratio of magnitude at most 1, then the quadrant. WGSL's
// own `atan2` is only bounded to 4096 ULP, and Chromium's software adapter (SwiftShader)
// returns dihedral angles far outside that on a few edges of a plain torus (curvature up
// to 1.5× the CPU's around them); this form agrees with the CPU's `f64::atan2` on every
// adapter the tests run.
fn atan2_reduced(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    if !(ax > 0.0 || ay > 0.0) {
        return 0.0;
    }
    var a = 0.0;
    if ay <= ax {
        a = atan(ay / ax);
    } else {
        a = 1.5707963267948966 - atan(ax / ay);
    }
    if x < 0.0 {
        a = 3.141592653589793 - a;
    }
    return select(a, -a, y < 0.0);
}

// glam's `Vec3::try_normalize`: the unit vector, w = 1, or w = 0 where the length's
// reciprocal is not finite and positive.
fn try_normalize(v: vec3<f32>) -> vec4<f32> {
    let r = 1.0 / length(v);
    if !finite(r) || r <= 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(v * r, 1.0);
}
