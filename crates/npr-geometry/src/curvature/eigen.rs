//! The eigen-analysis of the tensor: the principal axes and curvatures at a vertex,
//! from the tensor projected onto the tangent plane (the corrected form) or from the
//! full 3×3 tensor (the paper's and the clipped forms).

use glam::DVec3;
use nalgebra::{Matrix3, SymmetricEigen};

use super::PrincipalAxes;
/// Projects T onto the tangent plane of `n` and eigen-decomposes the 2×2 restriction.
pub(super) fn tangent_axes(m: &Matrix3<f64>, n: DVec3) -> Option<PrincipalAxes> {
    let n = n.try_normalize()?;
    let (t1, t2) = n.any_orthonormal_pair();
    let mv = |a: DVec3| {
        let v = m * nalgebra::Vector3::new(a.x, a.y, a.z);
        DVec3::new(v.x, v.y, v.z)
    };
    let (m1, m2) = (mv(t1), mv(t2));
    let (lam_hi, lam_lo, u) = sym2_eigen(t1.dot(m1), 0.5 * (t1.dot(m2) + t2.dot(m1)), t2.dot(m2));
    // Larger eigenvalue ↔ direction of MINIMUM curvature (the tensor swaps them).
    let dmin = (u[0] * t1 + u[1] * t2).try_normalize()?;
    let dmax = dmin.cross(n);
    finish(n, dmax, lam_hi, lam_lo)
}

/// Closed-form eigen-decomposition of the symmetric 2×2 `[[a, b], [b, c]]`: (larger
/// eigenvalue, smaller eigenvalue, unit eigenvector of the larger). Exact and much
/// cheaper than an iterative solver; a unit test checks it against nalgebra's
/// `SymmetricEigen` (which the 3×3 forms use).
pub(super) fn sym2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, [f64; 2]) {
    let mean = 0.5 * (a + c);
    let half = 0.5 * (a - c);
    let d = (half * half + b * b).sqrt();
    let (hi, lo) = (mean + d, mean - d);
    // Eigenvector of the larger eigenvalue, from the better-conditioned row.
    let v = if half >= 0.0 {
        [half + d, b]
    } else {
        [b, d - half]
    };
    let l = (v[0] * v[0] + v[1] * v[1]).sqrt();
    let u = if l > 0.0 {
        [v[0] / l, v[1] / l]
    } else {
        [1.0, 0.0]
    };
    (hi, lo, u)
}

/// The paper's eigen-analysis of the full 3×3 T: smallest |eigenvalue| → normal.
pub(super) fn full_axes(m: &Matrix3<f64>, mesh_n: DVec3) -> Option<PrincipalAxes> {
    let eig = SymmetricEigen::try_new(*m, 1e-14, 128)?;
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| {
        eig.eigenvalues[a]
            .abs()
            .total_cmp(&eig.eigenvalues[b].abs())
    });
    let col = |i: usize| {
        let c = eig.eigenvectors.column(i);
        DVec3::new(c[0], c[1], c[2])
    };
    let mut n = col(idx[0]).try_normalize()?;
    if n.dot(mesh_n) < 0.0 {
        n = -n;
    }
    let (a, b) = (idx[1], idx[2]);
    let (hi, lo) = if eig.eigenvalues[a] >= eig.eigenvalues[b] {
        (a, b)
    } else {
        (b, a)
    };
    let dmin = col(hi);
    let dmax = dmin.cross(n).try_normalize()?;
    finish(n, dmax, eig.eigenvalues[hi], eig.eigenvalues[lo])
}

fn finish(n: DVec3, dmax: DVec3, kmax: f64, kmin: f64) -> Option<PrincipalAxes> {
    let dmin = n.cross(dmax);
    let f = PrincipalAxes {
        n: n.as_vec3(),
        dmax: dmax.as_vec3(),
        dmin: dmin.as_vec3(),
        kmax: kmax as f32,
        kmin: kmin as f32,
        valid: true,
    };
    let finite = f.n.is_finite()
        && f.dmax.is_finite()
        && f.dmin.is_finite()
        && f.kmax.is_finite()
        && f.kmin.is_finite();
    finite.then_some(f)
}
