//! The coarsest rejection of the per-frame search: vertices in clusters of 16 along a
//! Morton curve, each with the cone of its normals, skipped whole when no half vector
//! its faces can see comes near that cone (a one-level normal-cone hierarchy).

use glam::Vec3;

use super::coherence::Budget;
use super::search::{FrameKind, FrameSetup, turn_bound};
use super::{ANGLE_MARGIN, HighlightSearch};
/// Vertices per [`Cluster`].
pub(super) const CLUSTER_SIZE: usize = 16;

/// A cluster of nearby vertices and bounds over them, for a normal-cone rejection of
/// whole clusters before the per-vertex tests (a one-level normal-cone hierarchy).
#[derive(Clone, Debug)]
pub(super) struct Cluster {
    /// Range of [`HighlightSearch::cluster_vertices`].
    pub(super) start: u32,
    pub(super) end: u32,
    /// Centre of the vertices' bounding box.
    pub(super) centre: Vec3,
    /// Largest `|p_v − centre| + reach_v`: every point of every face around the
    /// cluster's vertices lies within it.
    pub(super) radius: f32,
    /// Cone axis of the vertex normals (unit; zero when they span no cone).
    pub(super) axis: Vec3,
    /// Largest angle between `axis` and a vertex normal (π without a cone).
    pub(super) spread: f32,
    /// Smallest `cos_spread_v − ANGLE_MARGIN` over the vertices.
    pub(super) cmin_linear: f32,
    /// Smallest `cos_spread_v − ANGLE_MARGIN − curvature_margin_v`.
    pub(super) cmin_curved: f32,
}

/// Vertices grouped in clusters of [`CLUSTER_SIZE`] along a Morton (Z-order) curve of
/// their positions, so each cluster is compact in space.
pub(super) fn build_clusters(
    positions: &[Vec3],
    normals: &[Vec3],
    cos_spread: &[f32],
    reach: &[f32],
    curvature_margin: &[f32],
) -> (Vec<Cluster>, Vec<u32>) {
    let nv = positions.len();
    let codes = crate::locality::morton_codes(positions);
    let mut order: Vec<u32> = (0..nv as u32).collect();
    order.sort_by_key(|&v| codes[v as usize]);
    let clusters = order
        .chunks(CLUSTER_SIZE)
        .enumerate()
        .map(|(i, chunk)| {
            let vs = || chunk.iter().map(|&v| v as usize);
            let (clo, chi) = vs().fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), v| (lo.min(positions[v]), hi.max(positions[v])),
            );
            let centre = (clo + chi) * 0.5;
            let radius = vs()
                .map(|v| positions[v].distance(centre) + reach[v])
                .fold(0f32, f32::max);
            let sum: Vec3 = vs().map(|v| normals[v]).sum();
            let axis = sum.normalize_or_zero();
            let spread = if axis == Vec3::ZERO {
                std::f32::consts::PI
            } else {
                vs().map(|v| normals[v].dot(axis).clamp(-1.0, 1.0).acos())
                    .fold(0f32, f32::max)
            };
            let cmin_linear = vs()
                .map(|v| cos_spread[v] - ANGLE_MARGIN)
                .fold(f32::MAX, f32::min);
            let cmin_curved = vs()
                .map(|v| cos_spread[v] - ANGLE_MARGIN - curvature_margin[v])
                .fold(f32::MAX, f32::min);
            let finite = radius.is_finite() && spread.is_finite() && centre.is_finite();
            Cluster {
                start: (i * CLUSTER_SIZE) as u32,
                end: (i * CLUSTER_SIZE + chunk.len()) as u32,
                centre,
                radius: if finite { radius } else { f32::INFINITY },
                axis: if finite { axis } else { Vec3::ZERO },
                spread: if finite { spread } else { std::f32::consts::PI },
                cmin_linear,
                cmin_curved,
            }
        })
        .collect();
    (clusters, order)
}

impl HighlightSearch {
    /// The vertices of the clusters that can hold a centre (the coarsest rejection): a
    /// cluster whose normals all lie more than the per-vertex test's largest allowance
    /// away from every half vector its faces can see is skipped whole. Conservative: a
    /// skipped vertex would have failed its own test (see [`HighlightSearch::find`]).
    /// With a motion `budget`, a skipped vertex also fails it after the light and eye
    /// move by up to the budget (see [`SearchCoherence`]).
    pub(super) fn active_vertices(&self, frame: &FrameSetup, budget: Budget) -> Vec<u32> {
        self.cluster_vertices_within(frame, budget, None)
    }

    /// The vertices of the clusters that can hold a vertex whose normal makes
    /// `cos ≥ min_cos` with its own half vector (beyond the paper: the bright regions
    /// `N·H ≥ σ` that hold no `N = H` point are found among them). Conservative: a
    /// vertex left out has `N·H < min_cos` (angles measured in world space, so all
    /// vertices for a transform that is not a similarity).
    pub fn bright_candidates(
        &self,
        light_eye: crate::LightEye,
        world_from_object: glam::Mat4,
        min_cos: f32,
    ) -> Vec<u32> {
        match self.setup(light_eye, world_from_object) {
            Some(frame) if frame.similarity && min_cos.is_finite() => {
                self.cluster_vertices_within(&frame, Budget::NONE, Some(min_cos))
            }
            _ => (0..self.positions.len() as u32).collect(),
        }
    }

    /// [`HighlightSearch::active_vertices`], or with `min_cos` the clusters whose normal
    /// cone comes within `arccos(min_cos)` of a half vector its faces see.
    fn cluster_vertices_within(
        &self,
        frame: &FrameSetup,
        budget: Budget,
        min_cos: Option<f32>,
    ) -> Vec<u32> {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let keep = |c: &Cluster| -> bool {
            if c.axis == Vec3::ZERO || !c.radius.is_finite() {
                return true;
            }
            let cmin = if frame.curved {
                c.cmin_curved
            } else {
                c.cmin_linear
            };
            // H at the centre, how far the per-vertex allowance b_v can grow (b), how far
            // H itself turns over the cluster (b_h), and how far the budgeted motion can
            // turn it (phi).
            let (hc, b, b_h, phi) = match frame.kind {
                FrameKind::Direction(h) => (h, 0.0, 0.0, budget.angle),
                FrameKind::Positions { light_o, eye_o, .. } => {
                    let (l, e) = (light_o - c.centre, eye_o - c.centre);
                    let (ll, le) = (l.length(), e.length());
                    let s = l / ll + e / le;
                    let sl = s.length();
                    if !(sl > 1e-6) || !s.is_finite() {
                        return true;
                    }
                    let r = c.radius;
                    // Turn of L̂ (V̂) between the centre and any point within r of it, and
                    // the per-vertex turn bound at any vertex (its reach ≤ r, its distance
                    // ≥ d − r): both ≤ turn(d − r) with the vertex formula.
                    let turn = |d: f32| turn_bound(r, d - r);
                    let t = turn(ll) + turn(le);
                    // The same after the light and eye move by their budgets.
                    let t_moved = turn(ll - budget.light) + turn(le - budget.eye);
                    if t_moved >= half_pi {
                        return true;
                    }
                    let Some(tau) = budget.direction_turn(ll - r, le - r) else {
                        return true;
                    };
                    if sl - t <= tau {
                        return true;
                    }
                    let b = (t_moved / (sl - t - tau - t_moved).max(1e-3)).min(4.0);
                    let b_h = (t / (sl - t).max(1e-3)).min(std::f32::consts::PI);
                    (s / sl, b, b_h, (tau / (sl - t)).min(1.0).asin())
                }
            };
            // A vertex's own N·H ≥ min_cos: its normal within arccos(min_cos) of its H,
            // which is within b_h of the centre's.
            let allowance = match min_cos {
                Some(c) => c.clamp(-1.0, 1.0).acos(),
                None => (cmin - b).clamp(-1.0, 1.0).acos(),
            };
            let angle = c.axis.dot(hc).clamp(-1.0, 1.0).acos();
            angle <= c.spread + b_h + allowance + phi + ANGLE_MARGIN
        };
        let mut out = Vec::new();
        for c in &self.clusters {
            if keep(c) {
                out.extend_from_slice(&self.cluster_vertices[c.start as usize..c.end as usize]);
            }
        }
        out
    }

    /// Radius of the vertices' bounding box, object units (the floor of motion budgets).
    pub(super) fn extent(&self) -> f32 {
        self.clusters
            .iter()
            .filter(|c| c.radius.is_finite())
            .fold(0f32, |m, c| m.max(c.centre.abs().max_element() + c.radius))
    }
}
