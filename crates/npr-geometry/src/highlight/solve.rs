//! The `N = H` solve inside one triangle: the paper's Eq. (6) by pseudo-inverse, and
//! its refinement by Gauss–Newton on the normalised fields (see the module doc of
//! [`crate::highlight`]), for the linear and the curvature-blended normal fields.

use glam::{DVec3, Vec3};
/// ε of the acceptance test `−ε ≤ α, β, α+β ≤ 1+ε` (§3.1).
pub const BARYCENTRIC_EPSILON: f64 = 1e-3;

/// Largest accepted `|N̂ − Ĥ|` at the solution (about 0.06°).
pub const RESIDUAL_TOLERANCE: f64 = 1e-3;

/// The paper's Eq. (6) alone: least-squares `(α, β)` by pseudo-inverse, accepted by the
/// ε test; `None` when the 3×2 system is rank-deficient (e.g. constant N and H over the
/// triangle) or the point lies outside. No residual test: the result minimises
/// `|N − H|` but need not make them parallel.
pub fn try_solve_barycentric_eq6(n: [Vec3; 3], h: [Vec3; 3]) -> Option<(f32, f32)> {
    let (n, h) = (n.map(Vec3::as_dvec3), h.map(Vec3::as_dvec3));
    let (a, b) = eq6(n, h)?;
    inside(a, b).then_some((a as f32, b as f32))
}

pub(super) fn eq6(n: [DVec3; 3], h: [DVec3; 3]) -> Option<(f64, f64)> {
    let c1 = (n[1] - n[0]) - (h[1] - h[0]);
    let c2 = (n[2] - n[0]) - (h[2] - h[0]);
    let rhs = h[0] - n[0];
    let (g11, g12, g22) = (c1.dot(c1), c1.dot(c2), c2.dot(c2));
    let det = g11 * g22 - g12 * g12;
    // Rank test relative to the columns' size.
    if !(det > 1e-12 * g11 * g22) || !(g11 * g22 > 1e-30) {
        return None;
    }
    let (r1, r2) = (c1.dot(rhs), c2.dot(rhs));
    let a = (g22 * r1 - g12 * r2) / det;
    let b = (g11 * r2 - g12 * r1) / det;
    (a.is_finite() && b.is_finite()).then_some((a, b))
}

fn inside(a: f64, b: f64) -> bool {
    let e = BARYCENTRIC_EPSILON;
    a >= -e && b >= -e && a + b <= 1.0 + e && a <= 1.0 + e && b <= 1.0 + e
}

/// Eq. (6) solve with normalisation (see the module doc): `Some((α, β))` for the point
/// of the triangle where the interpolated normal `N0 + αΔN1 + βΔN2` and half vector are
/// parallel (same direction), within ε of the triangle (§3.1); `None` for degenerate
/// systems, points outside, and triangles without such a point.
pub fn try_solve_barycentric(n: [Vec3; 3], h: [Vec3; 3]) -> Option<(f32, f32)> {
    let (n, h) = (n.map(Vec3::as_dvec3), h.map(Vec3::as_dvec3));
    let (a, b) = solve_normalised(n, h)?;
    Some((a as f32, b as f32))
}

pub(super) fn solve_normalised(n: [DVec3; 3], h: [DVec3; 3]) -> Option<(f64, f64)> {
    let (dn1, dn2) = (n[1] - n[0], n[2] - n[0]);
    gauss_newton(n, h, 6, |a, b| (n[0] + a * dn1 + b * dn2, dn1, dn2))
}

/// Gauss–Newton on `N̂(α,β) − Ĥ(α,β) = 0` from the Eq. (6) start, for a normal field
/// given as `normal(α, β) = (N, ∂N/∂α, ∂N/∂β)` and the linearly interpolated `H`.
/// Accepts the point when the residual is below [`RESIDUAL_TOLERANCE`] and it lies in
/// the triangle (ε test).
fn gauss_newton(
    n: [DVec3; 3],
    h: [DVec3; 3],
    iterations: usize,
    normal: impl Fn(f64, f64) -> (DVec3, DVec3, DVec3),
) -> Option<(f64, f64)> {
    let (mut a, mut b) = eq6(n, h)?;
    // Far outside: Gauss–Newton would wander; the pseudo-inverse start is good to
    // first order, so a start well outside means no centre here.
    if a < -0.5 || b < -0.5 || a + b > 1.5 {
        return None;
    }
    let (dh1, dh2) = (h[1] - h[0], h[2] - h[0]);
    let mut res = f64::INFINITY;
    for _ in 0..iterations {
        let (nv, dn1, dn2) = normal(a, b);
        let hv = h[0] + a * dh1 + b * dh2;
        let (ln, lh) = (nv.length(), hv.length());
        if !(ln > 1e-12 && lh > 1e-12) {
            return None;
        }
        let (nn, hn) = (nv / ln, hv / lh);
        let r = nn - hn;
        res = r.length();
        if res < 1e-12 {
            break;
        }
        // d(v/|v|) = (I − v̂v̂ᵀ) dv / |v|
        let proj = |u: DVec3, d: DVec3, l: f64| (d - u * u.dot(d)) / l;
        let j1 = proj(nn, dn1, ln) - proj(hn, dh1, lh);
        let j2 = proj(nn, dn2, ln) - proj(hn, dh2, lh);
        let (g11, g12, g22) = (j1.dot(j1), j1.dot(j2), j2.dot(j2));
        let det = g11 * g22 - g12 * g12;
        if !(det > 1e-14 * g11 * g22) {
            break;
        }
        let (r1, r2) = (j1.dot(r), j2.dot(r));
        let da = -(g22 * r1 - g12 * r2) / det;
        let db = -(g11 * r2 - g12 * r1) / det;
        a += da;
        b += db;
        if !(a.is_finite() && b.is_finite()) || a.abs() > 4.0 || b.abs() > 4.0 {
            return None;
        }
        if da.abs() + db.abs() < 1e-13 {
            let (nv, ..) = normal(a, b);
            let hv = h[0] + a * dh1 + b * dh2;
            res = (nv.normalize_or_zero() - hv.normalize_or_zero()).length();
            break;
        }
    }
    (res < RESIDUAL_TOLERANCE && inside(a, b)).then_some((a, b))
}

/// How the normal field inside a triangle is interpolated for the `N = H` solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalInterpolation {
    /// The paper's Eq. (4): `N = N0 + αΔN1 + βΔN2`, linear in the barycentric
    /// coordinates. Its gradient is constant per face and jumps across edges, so a
    /// centre's speed under steady rotation jumps where it crosses a face (up to 4× on the
    /// paper's knot).
    Linear,
    /// Beyond the paper (default): each vertex contributes its own first-order model of
    /// the surface normal, `N_i + S_i (p − p_i)`, with `S_i = κ_max e_max e_maxᵀ +
    /// κ_min e_min e_minᵀ` its shape operator from the curvature field, blended with the
    /// barycentric weights. The models agree where the curvature is right, so the blend's
    /// gradient is the interpolated shape operator, continuous across edges, and centres
    /// glide at a steady speed. On an edge only that edge's two vertices count, so the
    /// field is continuous across faces.
    #[default]
    Curvature,
}

/// Gauss–Newton on `N̂(α,β) − Ĥ(α,β) = 0` for the curvature-blended normal field of
/// [`NormalInterpolation::Curvature`]: `N(α,β) = Σ w_i (N_i + S_i (p(α,β) − p_i))`,
/// `w = (1−α−β, α, β)`. Starts from the Eq. (6) solution of the linear field.
pub(super) fn solve_curvature(
    n: [DVec3; 3],
    h: [DVec3; 3],
    p: [DVec3; 3],
    shape: [glam::DMat3; 3],
) -> Option<(f64, f64)> {
    let (dp1, dp2) = (p[1] - p[0], p[2] - p[0]);
    gauss_newton(n, h, 10, |a, b| {
        let w = [1.0 - a - b, a, b];
        let x = p[0] + a * dp1 + b * dp2;
        let model = [0, 1, 2].map(|i| n[i] + shape[i] * (x - p[i]));
        let nv = w[0] * model[0] + w[1] * model[1] + w[2] * model[2];
        let blended_shape = shape[0] * w[0] + shape[1] * w[1] + shape[2] * w[2];
        (
            nv,
            model[1] - model[0] + blended_shape * dp1,
            model[2] - model[0] + blended_shape * dp2,
        )
    })
}
