//! Evaluating Eq. (1) at every vertex in parallel: the radius in world units, meshes far
//! from unit size scaled by a power of two first, and each vertex sent to the form the
//! options ask for.

use glam::Vec3;
use rayon::prelude::*;

use super::tensor::{Packed, SCRATCH, corrected_axes, edge_tensors, face_data, vertex_axes};
use super::{
    CurvatureField, CurvatureMethod, CurvatureOptions, CurvatureRadius, PrincipalAxes, invalid,
};
use crate::topology::Topology;

impl CurvatureField {
    /// Computes Eq. (1) and its eigen-analysis at every vertex of `topo`, in parallel.
    ///
    /// The ball is grown over face adjacency from the vertex's own faces (never
    /// quadratic). Corrected form: a face passes the ball on when its centroid is inside
    /// (it has weight), or when it is large against the ball (bounding radius > r/2) and
    /// its bounding sphere reaches in; paper and clipped forms: every face whose bounding
    /// sphere can touch the ball passes it on. So `B` is the part of the surface inside
    /// the ball that is connected to `v` — another sheet passing through the ball (a
    /// thin wall's far side) is not mixed in. At boundary vertices the ball is one-sided
    /// and boundary edges carry no dihedral angle, so curvature there reads low.
    /// Vertices with a non-finite position, isolated vertices, and vertices whose ball
    /// holds no area are marked invalid; non-finite neighbours are skipped.
    ///
    /// Any scale works: when the mesh's bounding radius is far from 1 (beyond 2^±8), the
    /// field is computed on a copy scaled by a power of two to unit size (exact in
    /// floating point, so only the absolute tolerances and the `f32` range of areas see a
    /// difference) and the curvatures are scaled back: κ is reported in 1/(file unit),
    /// `radius_world` in file units.
    pub fn compute(topo: &Topology, options: &CurvatureOptions) -> Self {
        let Some(k) = normalising_exponent(&topo.positions) else {
            return Self::compute_at_scale(topo, options);
        };
        // x · 2^-k, and back with 2^k: both exact (|k| ≤ 126 keeps them normal floats).
        let (down, up) = (pow2(-k), pow2(k));
        let scaled = Topology::from_parts(
            topo.positions.iter().map(|&p| p * down).collect(),
            topo.triangles.clone(),
        );
        let radius = match options.radius {
            CurvatureRadius::World(r) => CurvatureRadius::World(r * down),
            edges => edges,
        };
        let mut field = Self::compute_at_scale(
            &scaled,
            &CurvatureOptions {
                radius,
                method: options.method,
            },
        );
        for kappa in field.kappa_max.iter_mut().chain(field.kappa_min.iter_mut()) {
            *kappa *= down;
        }
        field.radius_world *= up;
        field
    }

    pub(super) fn compute_at_scale(topo: &Topology, options: &CurvatureOptions) -> Self {
        let r = match options.radius {
            CurvatureRadius::World(r) => r,
            CurvatureRadius::EdgeLengths(k) => k * topo.mean_edge_length,
        };
        let nv = topo.vertex_count();
        let method = options.method;
        let faces = if method == CurvatureMethod::Corrected {
            Vec::new()
        } else {
            face_data(topo)
        };
        let edge_t = if method == CurvatureMethod::Corrected {
            Vec::new()
        } else {
            edge_tensors(topo)
        };
        let packed = (method == CurvatureMethod::Corrected).then(|| Packed::build(topo));
        let ok_radius = r.is_finite() && r > 0.0;
        let axes: Vec<PrincipalAxes> = (0..nv)
            .into_par_iter()
            .with_min_len(512)
            .map(|v| {
                if !ok_radius || topo.is_isolated(v) || !topo.positions[v].is_finite() {
                    return invalid(topo.vertex_normals[v]);
                }
                SCRATCH.with(|s| {
                    let mut s = s.borrow_mut();
                    match &packed {
                        Some(p) => corrected_axes(topo, p, v, r, &mut s),
                        None => vertex_axes(topo, &faces, &edge_t, v, r, method, &mut s),
                    }
                })
            })
            .collect();
        let mut out = Self {
            radius_world: r,
            method,
            ..Self::default()
        };
        // Struct of arrays, in two halves at once (plain loops: cheaper per element
        // than a parallel iterator).
        let ((normal, dmax), (dmin, (kmax, (kmin, valid)))) = rayon::join(
            || {
                rayon::join(
                    || axes.iter().map(|f| f.n).collect(),
                    || axes.iter().map(|f| f.dmax).collect(),
                )
            },
            || {
                rayon::join(
                    || axes.iter().map(|f| f.dmin).collect(),
                    || {
                        (
                            axes.iter().map(|f| f.kmax).collect(),
                            (
                                axes.iter().map(|f| f.kmin).collect(),
                                axes.iter().map(|f| f.valid).collect(),
                            ),
                        )
                    },
                )
            },
        );
        out.normal = normal;
        out.dir_kappa_max = dmax;
        out.dir_kappa_min = dmin;
        out.kappa_max = kmax;
        out.kappa_min = kmin;
        out.valid = valid;
        out
    }
}

/// `2^k` as an exact `f32` (`k` in -126..=127).
fn pow2(k: i32) -> f32 {
    f32::from_bits(((k.clamp(-126, 127) + 127) as u32) << 23)
}

/// The power of two `k` with `2^k` ≈ the bounding radius of the finite positions (about
/// their bounding-box centre), when it is outside `-8..=8`; `None` for meshes near unit
/// size (computed as they are) and for meshes without a finite extent.
fn normalising_exponent(positions: &[Vec3]) -> Option<i32> {
    let finite = positions
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.as_dvec3());
    let (lo, hi) = finite.clone().fold(
        (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let centre = 0.5 * (lo + hi);
    // The largest distance is the square root of the largest squared distance (the
    // square root is correctly rounded and monotonic): one root instead of one a vertex.
    let radius = finite
        .map(|p| p.distance_squared(centre))
        .fold(0.0, f64::max)
        .sqrt();
    if !(radius > 0.0) || !radius.is_finite() {
        return None;
    }
    let k = radius.log2().round() as i32;
    (k.abs() > 8).then_some(k.clamp(-126, 126))
}
