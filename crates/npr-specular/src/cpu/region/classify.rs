//! How a face is measured against the region `N·H ≥ σ`, decided by bounds from its
//! vertices alone ([`classify`]), and the sub-triangle grid a curved face is sampled on.

use glam::Vec3;
use npr_geometry::LightEye;

/// Sub-grid of a face: `SUB` steps per edge.
pub(super) const SUB: usize = 4;
pub(super) const GRID_POINTS: usize = (SUB + 1) * (SUB + 2) / 2;

/// Index of grid point (i, j) (i + j ≤ `steps`) in the order of [`grid_points`].
pub(super) const fn grid_index(steps: usize, i: usize, j: usize) -> usize {
    // Row i starts after rows 0..i of steps + 1 − r points each.
    i * (2 * steps + 3 - i) / 2 + j
}

/// The points (i, j), i + j ≤ `steps`, of a face's sub-grid, row by row.
pub(super) fn grid_points(steps: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..=steps).flat_map(move |i| (0..=steps - i).map(move |j| (i, j)))
}

/// Calls `f` with the grid indices of every sub-triangle of a `steps` sub-grid, in the
/// face's orientation.
pub(super) fn for_sub_triangles(steps: usize, mut f: impl FnMut(usize, usize, usize)) {
    let at = |i, j| grid_index(steps, i, j);
    for i in 0..steps {
        for j in 0..steps - i {
            let (a, b, c) = (at(i, j), at(i + 1, j), at(i, j + 1));
            f(a, b, c);
            if i + j + 1 < steps {
                f(b, at(i + 1, j + 1), c);
            }
        }
    }
}

/// Where a face lies against the region `N·H ≥ σ`, from its vertices alone, and how it
/// must be measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum FaceClass {
    /// Every point is in the region: added whole.
    Inside,
    /// No point is: skipped.
    Outside,
    /// The boundary crosses it, and `N·H − σ` is linear in it to within
    /// [`LINEAR_TOLERANCE`] of its range: clipped once by the vertex values.
    Linear,
    /// The boundary may cross it and the field is too curved there (a region no bigger
    /// than a few faces): sampled on a sub-grid of `steps` per edge; `delta` bounds how
    /// far `H` turns over the face.
    Grid {
        /// Sub-grid steps per edge, 2 to [`SUB`].
        steps: usize,
        /// Bound on the turn of `H` over the face (radians, about).
        delta: f32,
    },
}

/// Above this bound on how far `H` turns over a face (near the light or the eye), the
/// sub-grid computes `H` at each point instead of interpolating the vertices'.
pub(super) const EXACT_H_TURN: f32 = 0.05;

/// Largest deviation of `N·H` from the linear interpolant of its vertex values, as a
/// fraction of their range, for a face to be clipped by the vertex values alone: the
/// boundary is then placed within about 5 % of the face (the 4-step sub-grid's own
/// resolution is a quarter of it).
const LINEAR_TOLERANCE: f32 = 0.05;

/// Classifies a face (world position, unit normal and `N·H` per vertex) by bounds that
/// hold at every point of it. With `u = Σ bᵢ Nᵢ` the interpolated normal (`|u| ≤ 1`),
/// `c ≥ 0` the smallest `Nᵢ·Nⱼ` (so `|u|² = Σ bᵢbⱼ Nᵢ·Nⱼ ≥ c + (1 − c) Σ bᵢ² ≥
/// (1 + 2c)/3`) and `δ` a bound on how far `H` turns over the face:
/// - inside when `σ ≥ 0` and `min Nᵢ·Hᵢ − δ ≥ σ`, since then `u·H ≥ 0` and
///   `N̂·H = u·H/|u| ≥ u·H ≥ Σ bᵢ Nᵢ·Hᵢ − δ`;
/// - `N̂·H` departs from the interpolant `Σ bᵢ Nᵢ·Hᵢ` by the normalisation,
///   `≤ 1/|u| − 1`, and by `Σ bᵢ Nᵢ·(H(p) − Hᵢ)`, whose first-order part
///   `N₀·J Σ bᵢ (p − pᵢ)` vanishes, leaving `≤ max|Nᵢ − N₀| δ + 2δ²` (the second-order
///   part of `L̂` over a face, about `1.5 (r/d)²`, is within `2δ²`); so the face is
///   outside when `max Nᵢ·Hᵢ + ε < σ`, and the interpolant is trusted when that `ε` is
///   small against the vertex values' range.
pub(super) fn classify(
    light_eye: LightEye,
    vs: &[(Vec3, Vec3, f32); 3],
    dists: &[[f32; 3]; 3],
    reach: f32,
    sigma: f32,
) -> FaceClass {
    let lo = vs[0].2.min(vs[1].2).min(vs[2].2);
    let hi = vs[0].2.max(vs[1].2).max(vs[2].2);
    let delta = match light_eye {
        LightEye::Directions { .. } => 0.0,
        LightEye::Positions { .. } => {
            // |ΔL̂| ≤ r/(d − r) for points within r (the longest edge) of a vertex at
            // distance d; Ĥ = S/|S| turns by at most |ΔS|/(|S| − |ΔS|).
            let r = reach;
            let turn = |d: f32| if d > 2.0 * r { r / (d - r) } else { 2.0 };
            let min = |k: usize| dists[0][k].min(dists[1][k]).min(dists[2][k]);
            let ds = turn(min(0)) + turn(min(1));
            let s = min(2);
            if s - ds > 1e-3 { ds / (s - ds) } else { 2.0 }
        }
    };
    let finest = FaceClass::Grid {
        steps: SUB,
        delta: f32::INFINITY,
    };
    if !delta.is_finite() || !lo.is_finite() || !hi.is_finite() {
        return finest;
    }
    // (u·H ≥ 0 there, which the first bound needs, since σ ≥ 0.)
    if sigma >= 0.0 && lo - delta >= sigma {
        return FaceClass::Inside;
    }
    let c = vs[0]
        .1
        .dot(vs[1].1)
        .min(vs[1].1.dot(vs[2].1))
        .min(vs[2].1.dot(vs[0].1));
    if c.is_nan() || c <= 0.0 {
        return FaceClass::Grid { steps: SUB, delta };
    }
    let eps = 1.0 / ((1.0 + 2.0 * c) / 3.0).sqrt() - 1.0
        + delta * ((2.0 * (1.0 - c)).max(0.0).sqrt() + 2.0 * delta);
    if hi + eps < sigma {
        FaceClass::Outside
    } else if eps <= LINEAR_TOLERANCE * (hi - lo) {
        FaceClass::Linear
    } else {
        // The interpolant's error falls as 1/steps² on a sub-grid.
        let need = (eps / (LINEAR_TOLERANCE * (hi - lo)).max(f32::MIN_POSITIVE)).sqrt();
        FaceClass::Grid {
            steps: if need <= 2.0 {
                2
            } else if need <= 3.0 {
                3
            } else {
                SUB
            },
            delta,
        }
    }
}
