//! Closed-form principal curvatures and directions of the procedural surfaces in
//! [`crate::generate`], for tests and benchmarks (do Carmo, "Differential Geometry of
//! Curves and Surfaces", 1976 — the specular paper's reference \[9\]).
//!
//! Conventions as [`crate::CurvatureField`]: convex positive with the outward normal,
//! `kappa_max ≥ kappa_min`, directions unit and tangent.

use glam::{DVec3, Vec3};

/// Exact principal curvatures and the direction of maximum curvature at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principal {
    /// Maximum principal curvature.
    pub kappa_max: f64,
    /// Minimum principal curvature.
    pub kappa_min: f64,
    /// Unit direction of maximum curvature (undefined at umbilics: any tangent).
    pub dir_kappa_max: DVec3,
}

/// Torus around the y axis (as [`crate::generate::torus`]) at the surface point nearest
/// to `p`: `1/r` along the meridian, `cos v / (R + r cos v)` along the parallel.
pub fn torus(p: Vec3, major_radius: f64, minor_radius: f64) -> Principal {
    let p = p.as_dvec3();
    let rho = (p.x * p.x + p.z * p.z).sqrt();
    let v = p.y.atan2(rho - major_radius);
    let kmin = v.cos() / (major_radius + minor_radius * v.cos());
    let parallel = DVec3::new(-p.z, 0.0, p.x).normalize_or_zero();
    let normal = DVec3::new(v.cos() * p.x / rho, v.sin(), v.cos() * p.z / rho);
    Principal {
        kappa_max: 1.0 / minor_radius,
        kappa_min: kmin,
        dir_kappa_max: normal.cross(parallel),
    }
}

/// Ellipsoid `x²/a² + y²/b² + z²/c² = 1` at the point `p` (projected radially onto the
/// surface), from the shape operator of the implicit function: `S = P ∇²F P / |∇F|` on
/// the tangent plane.
pub fn ellipsoid(p: Vec3, a: f64, b: f64, c: f64) -> Principal {
    let p = p.as_dvec3();
    let s = ((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2)).sqrt();
    let p = p / s;
    let g = DVec3::new(
        2.0 * p.x / (a * a),
        2.0 * p.y / (b * b),
        2.0 * p.z / (c * c),
    );
    let n = g.normalize();
    let hess = DVec3::new(2.0 / (a * a), 2.0 / (b * b), 2.0 / (c * c));
    let (t1, t2) = n.any_orthonormal_pair();
    let q = |u: DVec3, w: DVec3| (u * hess).dot(w) / g.length();
    let (m11, m12, m22) = (q(t1, t1), q(t1, t2), q(t2, t2));
    let mean = 0.5 * (m11 + m22);
    let d = (0.25 * (m11 - m22).powi(2) + m12 * m12).sqrt();
    let (kmax, kmin) = (mean + d, mean - d);
    // Eigenvector of [[m11, m12], [m12, m22]] for kmax.
    let (x, y) = if m12.abs() > 1e-15 {
        (m12, kmax - m11)
    } else if m11 >= m22 {
        (1.0, 0.0)
    } else {
        (0.0, 1.0)
    };
    let dir = (x * t1 + y * t2).normalize_or_zero();
    Principal {
        kappa_max: kmax,
        kappa_min: kmin,
        dir_kappa_max: dir,
    }
}

/// Cylinder of radius `r` around the y axis: `1/r` around the axis, 0 along it.
pub fn cylinder(p: Vec3, radius: f64) -> Principal {
    let p = p.as_dvec3();
    Principal {
        kappa_max: 1.0 / radius,
        kappa_min: 0.0,
        dir_kappa_max: DVec3::new(-p.z, 0.0, p.x).normalize_or_zero(),
    }
}

/// Angle in degrees between two directions taken up to sign (0..90).
pub fn axis_angle_deg(a: DVec3, b: DVec3) -> f64 {
    let c = a
        .normalize_or_zero()
        .dot(b.normalize_or_zero())
        .abs()
        .min(1.0);
    c.acos().to_degrees()
}
