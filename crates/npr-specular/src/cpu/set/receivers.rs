//! Receivers (§4.2) of each highlight with their normal limit or per-pixel falloff, and
//! which highlights split the pixels they share.

use super::{Highlight, HighlightBoundary, HighlightSet, HighlightSizing, NO_FALLOFF};
use crate::cpu::visibility::{FaceClusters, Facing, receivers_within_clustered};
use glam::{Mat4, Vec3};

/// How a highlight's §4.2 walk tests that a face faces its projector
/// ([`crate::cpu::visibility::Facing`] without the per-face slack, which the set holds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ReceiverRule {
    /// The face normal's cosine with the axis exceeds this.
    Cos(f32),
    /// [`crate::cpu::visibility::Facing::Interpolated`] at this limit.
    Interpolated { limit_rad: f32 },
}

impl HighlightSet {
    /// The receiver faces (§4.2) of each highlight in `kept` (none for one drawn as
    /// pieces) and its per-pixel falloff, into [`HighlightSet::receiver_faces`].
    pub(super) fn find_receivers(&mut self, kept: &mut [Highlight], world_from_object: Mat4) {
        // Receivers (§4.2), over the region growth's face patches (none: face by face).
        let no_clusters = FaceClusters::default();
        self.receiver_faces.clear();
        for h in kept.iter_mut() {
            let start = self.receiver_faces.len();
            h.receivers = start..start;
            let (rule, falloff) = self.receiver_rule(h);
            h.falloff_cos = falloff;
            let Some(rule) = rule else {
                continue;
            };
            let facing = match rule {
                ReceiverRule::Cos(c) => Facing::Cos(c),
                ReceiverRule::Interpolated { limit_rad } => Facing::Interpolated {
                    limit_rad,
                    slack: &self.face_slack,
                },
            };
            receivers_within_clustered(
                &self.topology,
                self.grower.patch_clusters().unwrap_or(&no_clusters),
                world_from_object,
                &h.projector,
                h.centre.face,
                facing,
                &mut self.scratch,
                &mut self.receiver_faces,
            );
            h.receivers = start..self.receiver_faces.len();
        }
    }

    /// The §4.2 facing rule of highlight `h`'s walk (`None` for one drawn as pieces,
    /// which has no receivers of its own) and its per-pixel falloff
    /// ([`Highlight::falloff_cos`]): what the CPU walk and [`crate::gpu::ReceiverPass`] share.
    pub(crate) fn receiver_rule(&self, h: &Highlight) -> (Option<ReceiverRule>, glam::Vec2) {
        if h.pieces > 0 {
            return (None, NO_FALLOFF);
        }
        let grazing = self.tuning.receiver_min_cos.clamp(-1.0, 1.0).acos();
        // Ours: also within the measured region's normal cone, widened by
        // `receiver_cone_margin_rad` (no receiver outside it can be in the region),
        // per face or as a per-pixel falloff.
        // An edit may take the texture past the grazing limit of unedited highlights
        // (onto surface the user asked it onto): then only §4.2's facing bounds it.
        let turn = edit_turn(h);
        let cap = if turn > 0.0 {
            std::f32::consts::FRAC_PI_2 - 0.5 * self.tuning.receiver_cone_margin_rad
        } else {
            grazing
        };
        let cone = (self.tuning.sizing == HighlightSizing::Region
            && self.tuning.boundary != HighlightBoundary::Unrestricted)
            .then(|| {
                let measured = h.footprint.normal_cone_cos.clamp(-1.0, 1.0).acos();
                (measured + turn + self.tuning.receiver_cone_margin_rad).min(cap)
            });
        match (cone, self.tuning.boundary) {
            (None, _) => (Some(ReceiverRule::Cos(0.0)), NO_FALLOFF),
            (Some(limit), HighlightBoundary::Smooth) => {
                // Alpha 1/2 at the limit (where the per-face rule cut), ramping over
                // half the margin either side, and at least over the normal's turn
                // across a face either side: on a coarse mesh a narrower ramp ends
                // within a triangle, as hard a step as the per-face cut.
                // The far end no further out than a margin-wide ramp reaches at the
                // cap (so the grazing limit still bounds the stretch), the ramp no
                // wider than keeps alpha 1/2 at the limit.
                let half_margin = 0.5 * self.tuning.receiver_cone_margin_rad.max(1e-3);
                let outer = (cap + half_margin).min(std::f32::consts::FRAC_PI_2);
                let band = self.face_turn.min(outer - limit).max(half_margin);
                let zero = (limit + band).min(outer);
                let falloff = glam::Vec2::new(zero.cos(), (zero - 2.0 * band).max(0.0).cos());
                (
                    Some(ReceiverRule::Interpolated { limit_rad: zero }),
                    falloff,
                )
            }
            (Some(limit), _) => (Some(ReceiverRule::Cos(limit.cos())), NO_FALLOFF),
        }
    }

    /// Fills [`Highlight::shared_with`]: for each highlight the (up to four) nearest
    /// whose footprint can overlap its own (centres closer than the sum of their larger
    /// half extents), when neither carries the user's own edits.
    pub(super) fn share_regions(&self, kept: &mut [Highlight]) {
        let edited = |id: u64| {
            self.per_highlight.get(&id).is_some_and(|c| {
                c.translate != glam::Vec2::ZERO || c.rotate_rad != 0.0 || c.scale != glam::Vec2::ONE
            })
        };
        // (centre, reach, edited, id, drawn)
        let reach: Vec<(Vec3, f32, bool, u64, bool)> = kept
            .iter()
            .map(|h| {
                let p = &h.projector;
                let drawn = h.pieces == 0;
                (
                    p.centre_world,
                    p.half_extent.max_element(),
                    edited(h.id),
                    h.id,
                    drawn,
                )
            })
            .collect();
        for (i, h) in kept.iter_mut().enumerate() {
            h.shared_with = [u32::MAX; 4];
            let (ci, ri, ei, idi, drawn) = reach[i];
            if !drawn {
                continue;
            }
            // Pieces of one highlight always share; others when neither is edited. The
            // four nearest, nearer first, ties in index order (no list per highlight).
            let mut near = [(f32::INFINITY, u32::MAX); 4];
            for (j, &(cj, rj, ej, idj, dj)) in reach.iter().enumerate() {
                let shares = idi == idj || (!ei && !ej);
                if j == i || !dj || !shares {
                    continue;
                }
                let d = ci.distance(cj);
                let overlaps = d < ri + rj; // false for NaN
                if let Some(slot) = near.iter().position(|&(e, _)| overlaps && d < e) {
                    near.copy_within(slot..3, slot + 1);
                    near[slot] = (d, j as u32);
                }
            }
            for (slot, (_, j)) in h.shared_with.iter_mut().zip(near) {
                *slot = j;
            }
        }
    }
}

/// How far a highlight's §3.4 edits turn the surface normal under its footprint beyond
/// what the unedited footprint spans (radians, ≥ 0). On the local quadric of the centre
/// (its principal curvatures), a point at tangent offset `q` seen along the axis has a
/// normal turned by `asin(min(1, |q| · |κ(q̂)|))`, `κ(d) = κ_max cos²φ + κ_min sin²φ` the
/// normal curvature along `d` (exact on a sphere under the orthographic projector). The
/// largest such turn over the drawn ellipse's rim, less the largest over the unedited
/// footprint's rim: what a translation, rotation or scale adds to the measured cone.
fn edit_turn(h: &Highlight) -> f32 {
    // Unedited, the drawn ellipse is the footprint's own: no turn (and no rims sampled).
    let k = &h.controls;
    if k.translate == glam::Vec2::ZERO && k.rotate_rad == 0.0 && k.scale == glam::Vec2::ONE {
        return 0.0;
    }
    let c = &h.centre;
    let e_max = c.dir_kappa_max;
    let e_min = c.normal_world.cross(e_max);
    let turn_at = |q: Vec3| {
        let len = q.length();
        if len <= 0.0 {
            return 0.0;
        }
        let cos = q.dot(e_max) / len;
        let kappa = (c.kappa_max * cos * cos + c.kappa_min * (1.0 - cos * cos)).abs();
        (len * kappa).min(1.0).asin()
    };
    // Largest turn over the rim of the ellipse centred `centre` (tangent offset from
    // the N = H point) with half axes `a·u`, `b·v`.
    let rim = |centre: Vec3, u: Vec3, v: Vec3, half: glam::Vec2| {
        (0..24)
            .map(|k| {
                let (s, co) = (k as f32 * std::f32::consts::TAU / 24.0).sin_cos();
                turn_at(centre + u * (half.x * co) + v * (half.y * s))
            })
            .fold(0f32, f32::max)
    };
    let p = &h.projector;
    let drawn = rim(
        p.centre_world - c.position_world,
        p.axis_u,
        p.axis_v,
        p.half_extent,
    );
    let fp = &h.footprint;
    let (s, co) = fp.rotate_rad.sin_cos();
    let own = rim(
        e_max * fp.offset.x + e_min * fp.offset.y,
        e_max * co + e_min * s,
        e_min * co - e_max * s,
        fp.half_extent,
    );
    let turn = drawn - own;
    if turn.is_finite() { turn.max(0.0) } else { 0.0 }
}
