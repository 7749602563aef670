//! Matching each frame's centres with the last frame's highlights, so that a highlight
//! keeps its identity, its controls and its fade (frame coherence beyond the paper).

use super::{Entry, Highlight, HighlightSet};
use glam::Mat4;
use npr_geometry::HighlightCentre;

impl HighlightSet {
    /// How far (object space) a centre may be from highlight `h` of the last update to
    /// take its identity: the footprint before controls, at most Eq. (8)'s cap (a large
    /// measured region must not let a highlight take a far centre's identity), and at
    /// least two mean edges.
    pub(crate) fn reach(&self, h: &Highlight, radius_world: f32, scale: f32) -> f32 {
        // The moment ellipse's own extent (before its fit to the region's area).
        let fit = h.footprint.fit_scale;
        let fit = if fit > 0.0 && fit <= 1.0 { fit } else { 1.0 };
        let extent = (h.footprint.half_extent.max_element() / fit).min(radius_world);
        let reach = self.tuning.match_radius * extent / scale.max(1e-12);
        reach.max(2.0 * self.topology.mean_edge_length)
    }

    /// Matches this frame's `centres` with the `previous` highlights: (id, centre, found,
    /// previous highlight index) per highlight to show, oldest first.
    pub(super) fn match_centres(
        &mut self,
        previous: &[Highlight],
        (centres, solved): (&[HighlightCentre], usize),
        radius_world: f32,
        scale: f32,
        world_from_object: Mat4,
    ) -> Vec<Entry> {
        let mut claimed = vec![false; centres.len()];
        // (id, centre, found, previous highlight index)
        let mut next: Vec<Entry> = Vec::with_capacity(centres.len() + previous.len());
        // Greedy matching, closest pairs first, in object space (rigid motion of the
        // object does not move a centre there; only lighting changes do).
        let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
        for (i, h) in previous.iter().enumerate() {
            let reach = self.reach(h, radius_world, scale);
            for (j, c) in centres.iter().enumerate() {
                let d = h.centre.position_object.distance(c.position_object);
                if d <= reach {
                    pairs.push((d, i, j));
                }
            }
        }
        // Each highlight first takes a centre of its own kind: an `N = H` centre (the
        // first `solved`) for a highlight of one, a peak of a bright region without one
        // ([`HighlightSet::peak_centres`]) for a peak's; across kinds only what is left
        // (a bright region gaining or losing its `N = H` point). So a peak near a pair of
        // `N = H` centres being born never swaps their identities, and a peak's highlight
        // never takes a nearby `N = H` centre that its region then suppresses (which
        // re-identified it every frame of a still view).
        let other_kind = |&(_, i, j): &(f32, usize, usize)| previous[i].peak != (j >= solved);
        pairs.sort_by(|a, b| other_kind(a).cmp(&other_kind(b)).then(a.0.total_cmp(&b.0)));
        let mut prev_taken = vec![false; previous.len()];
        for (_, i, j) in pairs {
            if !prev_taken[i] && !claimed[j] {
                prev_taken[i] = true;
                claimed[j] = true;
                next.push((previous[i].id, centres[j], true, Some(i)));
            }
        }
        // Lost highlights fade out at their last point on the object, re-placed with the
        // object's current transform (the projector and the receiver search both follow
        // an object that moves while the highlight fades).
        for (i, h) in previous.iter().enumerate() {
            if !prev_taken[i] {
                let c = &h.centre;
                let centre = self
                    .search
                    .centre_at(c.face, c.alpha, c.beta, world_from_object)
                    .unwrap_or(h.centre);
                next.push((h.id, centre, false, Some(i)));
            }
        }
        // New highlights fade in (appear at full opacity on the first frame).
        for (j, c) in centres.iter().enumerate() {
            if !claimed[j] {
                next.push((self.next_id, *c, true, None));
                self.next_id += 1;
            }
        }
        // Footprints, oldest highlight first: an older highlight keeps its region, and a
        // younger centre inside a region already claimed is suppressed (fades out if it
        // was shown, never appears if it is new).
        next.sort_by_key(|e| e.0);
        next
    }
}
