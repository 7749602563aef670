//! The (p, q) torus knot tube: the specular paper's test knot and the large benchmark
//! mesh.

use std::f64::consts::TAU;

use glam::DVec3;

use super::param_grid;
use crate::Mesh;
/// Shape of a (p, q) torus knot tube; see [`torus_knot`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorusKnot {
    /// Windings around the y axis.
    pub p: u32,
    /// Windings through the hole.
    pub q: u32,
    /// Radius of the torus the curve winds on (axis to tube centre line).
    pub major_radius: f32,
    /// Radius of the curve's winding around that torus' core circle.
    pub minor_radius: f32,
    /// Radius of the tube around the curve.
    pub tube_radius: f32,
    /// Segments along the curve.
    pub segments: usize,
    /// Segments around the tube.
    pub tube_segments: usize,
}

impl TorusKnot {
    /// The (2, 3) knot (a trefoil) in the specular paper's proportions (major radius 1,
    /// minor radius 0.4), with a tube of `tube_radius` and `segments × tube_segments`
    /// segments: [`paper_knot`], [`benchmark_knot`] and the figures' knots.
    pub fn trefoil(tube_radius: f32, segments: usize, tube_segments: usize) -> Self {
        Self {
            p: 2,
            q: 3,
            major_radius: 1.0,
            minor_radius: 0.4,
            tube_radius,
            segments,
            tube_segments,
        }
    }

    /// Centre line `c(t)`, its first and second derivatives, t ∈ [0, 2π).
    fn curve(&self, t: f64) -> [DVec3; 3] {
        let (p, q) = (f64::from(self.p), f64::from(self.q));
        let (big_r, a) = (f64::from(self.major_radius), f64::from(self.minor_radius));
        let (sq, cq) = (q * t).sin_cos();
        let (sp, cp) = (p * t).sin_cos();
        let rho = big_r + a * cq;
        let d_rho = -a * q * sq;
        let dd_rho = -a * q * q * cq;
        let c = DVec3::new(rho * cp, a * sq, rho * sp);
        let d = DVec3::new(
            d_rho * cp - rho * p * sp,
            a * q * cq,
            d_rho * sp + rho * p * cp,
        );
        let dd = DVec3::new(
            dd_rho * cp - 2.0 * d_rho * p * sp - rho * p * p * cp,
            -a * q * q * sq,
            dd_rho * sp + 2.0 * d_rho * p * cp - rho * p * p * sp,
        );
        [c, d, dd]
    }
}

/// A tube of constant radius around a (p, q) torus knot, on the curve's Frenet basis
/// (tangent, normal, binormal; periodic, so the tube closes without a twist seam). The normal of a constant-radius
/// tube is exactly the offset direction, so normals are analytic.
/// `segments × tube_segments` vertices, twice as many triangles.
pub fn torus_knot(k: &TorusKnot) -> Mesh {
    let nu = k.segments.max(3);
    let nv = k.tube_segments.max(3);
    let tube = f64::from(k.tube_radius);
    param_grid(nu, nv, true, true, |i, j| {
        let t = TAU * i as f64 / nu as f64;
        let [c, d, dd] = k.curve(t);
        let tan = d.normalize();
        let b = d
            .cross(dd)
            .try_normalize()
            .unwrap_or_else(|| tan.any_orthonormal_vector());
        let n = b.cross(tan);
        let th = TAU * j as f64 / nv as f64;
        let dir = th.cos() * n + th.sin() * b;
        (c + tube * dir, dir)
    })
}

/// The specular paper's test knot (§5, Fig. 8, Table 1: 2,880 faces): a (2, 3) torus
/// knot tube with 144 segments along the curve and 10 around, 1,440 vertices.
pub fn paper_knot() -> Mesh {
    torus_knot(&TorusKnot::trefoil(0.15, 144, 10))
}

/// The large benchmark mesh: the same (2, 3) knot with 2,750 × 200 segments,
/// 550,000 vertices and 1,100,000 triangles (the warping paper's Buddha is 1,085,634).
pub fn benchmark_knot() -> Mesh {
    torus_knot(&TorusKnot::trefoil(0.15, 2750, 200))
}
