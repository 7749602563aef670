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

// Unit normal (right-hand rule) and area of triangle (a, b, c); zero for a degenerate
// one (|cross| ≤ 1e-12 × the longest edge², or not finite). Rust twin:
// `npr_geometry::topology::build::face_normal_area`.
fn normal_area(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec4<f32> {
    let cr = cross(b - a, c - a);
    let len = length(cr);
    let scale = max(max(dot(b - a, b - a), dot(c - a, c - a)), dot(c - b, c - b));
    if !(len > 1e-12 * scale) || !finite(len) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(cr / len, 0.5 * len);
}

// Two unit tangents completing unit `n` to an orthonormal frame (Duff et al. 2017, as
// glam's `any_orthonormal_pair`). Rust twin: `glam::DVec3::any_orthonormal_pair`.
fn orthonormal_pair(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// Closed-form eigen-decomposition of the symmetric 2×2 [[a, b], [b, c]]: (larger
// eigenvalue, smaller eigenvalue, unit eigenvector of the larger). Rust twin:
// `npr_geometry::curvature::eigen::sym2_eigen`.
fn sym2_eigen(a: f32, b: f32, c: f32) -> vec4<f32> {
    let mean = 0.5 * (a + c);
    let half = 0.5 * (a - c);
    let d = sqrt(half * half + b * b);
    var v = vec2<f32>(b, d - half);
    if half >= 0.0 {
        v = vec2<f32>(half + d, b);
    }
    let l = length(v);
    var u = vec2<f32>(1.0, 0.0);
    if l > 0.0 {
        u = v / l;
    }
    return vec4<f32>(mean + d, mean - d, u);
}
