//! A highlight whose centre changes kind keeps its place (frame coherence beyond the
//! paper).
//!
//! A tracked highlight's centre is either an `N = H` point (§3.1, Eq. (3)) or, while its
//! bright region holds none, the region's maximum of Eq. (2) (`set::peaks`). When the
//! region starts or stops holding an `N = H` point, matching hands the highlight from one
//! kind of centre to the other, and the two need not coincide: the peak is the maximum of
//! the linearly interpolated `N̂·Ĥ` around the brightest vertex, the `N = H` point a root
//! of the search's own normal field (Eq. (4)–(6)), and a pair of `N = H` points is born
//! (or annihilates) at a fold of the Gauss map, where the points move at a speed that
//! diverges; and a region's maximum can pass from one of its local maxima to another.
//! So on such a change of kind, and wherever a found centre moves more than twice its
//! last step, the drawn centre (the projector's anchor and axis, the pivot of the §3.4
//! edits) blends from where it was drawn to the new centre over at least
//! [`HighlightSet::fade_frames`] updates (more for a long jump, so that the blend adds at
//! most the last drawn step per update), in object space so that it
//! follows the object's motion; the footprint stays on the region measured for the new
//! centre (re-expressed in the blended frame), so only the anchor moves smoothly.

use super::{Highlight, HighlightSet, group_edit};
use crate::Projector;
use crate::region::Footprint;
use glam::{Mat3, Mat4, Vec2, Vec3};
use npr_geometry::HighlightCentre;
use std::collections::HashMap;

/// A centre's point, normal and principal frame in object space (curvatures as found).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ObjectCentre {
    position: Vec3,
    normal: Vec3,
    dir_kappa_max: Vec3,
    kappa_max: f32,
    kappa_min: f32,
}

/// A found highlight's centre as found and as drawn last frame (object space), how far
/// each moved then (`None` on its first frame), and its handover in progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Track {
    found_at: Vec3,
    step: Option<f32>,
    drawn_at: Vec3,
    drawn_step: Option<f32>,
    handover: Option<Handover>,
}

/// A handover in progress: where it started, where the centre was drawn last, how many
/// updates it has run and how many it takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Handover {
    from: ObjectCentre,
    drawn: ObjectCentre,
    frames: u32,
    length: u32,
}

impl ObjectCentre {
    /// `c` in object space (`object_from_world` the inverse of the linear part of the
    /// object's transform).
    fn of(c: &HighlightCentre, object_from_world: Mat3) -> Self {
        Self {
            position: c.position_object,
            normal: c.normal_object,
            dir_kappa_max: (object_from_world * c.dir_kappa_max).normalize_or_zero(),
            kappa_max: c.kappa_max,
            kappa_min: c.kappa_min,
        }
    }

    /// The blend `(1 − w)·a + w·b`: the point linearly, the normal and the principal
    /// direction (taken with `b`'s sign, as a principal direction has none) renormalised.
    fn blend(a: &Self, b: &Self, w: f32) -> Self {
        let dir_a = if a.dir_kappa_max.dot(b.dir_kappa_max) < 0.0 {
            -a.dir_kappa_max
        } else {
            a.dir_kappa_max
        };
        let normal = a
            .normal
            .lerp(b.normal, w)
            .try_normalize()
            .unwrap_or(b.normal);
        Self {
            position: a.position.lerp(b.position, w),
            normal,
            dir_kappa_max: dir_a.lerp(b.dir_kappa_max, w),
            kappa_max: a.kappa_max + w * (b.kappa_max - a.kappa_max),
            kappa_min: a.kappa_min + w * (b.kappa_min - a.kappa_min),
        }
    }

    /// This centre drawn on `to`'s face (its face and barycentrics stay the found
    /// centre's), in the world of `world_from_object`; `None` when its frame degenerates.
    fn placed(&self, to: &HighlightCentre, world_from_object: Mat4) -> Option<HighlightCentre> {
        let m3 = Mat3::from_mat4(world_from_object);
        let normal_world = (m3.inverse().transpose() * self.normal).try_normalize()?;
        let d = m3 * self.dir_kappa_max;
        let dir_kappa_max = (d - normal_world * normal_world.dot(d)).try_normalize()?;
        let position_world = world_from_object.transform_point3(self.position);
        position_world.is_finite().then_some(HighlightCentre {
            position_object: self.position,
            position_world,
            normal_object: self.normal,
            normal_world,
            dir_kappa_max,
            dir_kappa_min: normal_world.cross(dir_kappa_max),
            kappa_max: self.kappa_max,
            kappa_min: self.kappa_min,
            ..*to
        })
    }
}

/// The projector's orthonormal tangent frame at `c`, as [`Projector::with_footprint`]
/// builds it.
fn tangent_frame(c: &HighlightCentre) -> Option<(Vec3, Vec3, Vec3)> {
    let n = c.normal_world.try_normalize()?;
    let e_max = (c.dir_kappa_max - n * n.dot(c.dir_kappa_max)).try_normalize()?;
    Some((n, e_max, n.cross(e_max)))
}

/// `fp`, measured about the centre `found`, expressed about `drawn` instead: the same
/// ellipse centre and axes in the world (offset and rotation in `drawn`'s tangent frame),
/// its normal cone widened by the angle between the two normals (the receivers are
/// measured against the drawn projector's axis).
fn reframe(fp: &Footprint, found: &HighlightCentre, drawn: &HighlightCentre) -> Option<Footprint> {
    let (n, e, f) = tangent_frame(found)?;
    let (n2, e2, f2) = tangent_frame(drawn)?;
    let centre = found.position_world + e * fp.offset.x + f * fp.offset.y;
    let d = centre - drawn.position_world;
    let turn = e.dot(f2).atan2(e.dot(e2));
    let tilt = n.dot(n2).clamp(-1.0, 1.0).acos();
    let cone = fp.normal_cone_cos.clamp(-1.0, 1.0).acos() + tilt;
    let normal_cone_cos = if fp.normal_cone_cos <= -1.0 {
        fp.normal_cone_cos
    } else {
        cone.min(std::f32::consts::PI).cos()
    };
    let out = Footprint {
        offset: Vec2::new(d.dot(e2), d.dot(f2)),
        rotate_rad: fp.rotate_rad + turn,
        normal_cone_cos,
        ..*fp
    };
    (out.offset.is_finite() && out.rotate_rad.is_finite()).then_some(out)
}

impl HighlightSet {
    /// Blends the drawn centre of each found highlight in `kept` whose centre changed
    /// kind since `previous` (an `N = H` point ↔ a bright region's peak), or whose peak
    /// jumped (moved more than twice its last step: the region's maximum passed to
    /// another of its local maxima), from where it was drawn to its new centre over
    /// [`HighlightSet::fade_frames`] updates (see the module docs), with its pieces; the
    /// projectors are rebuilt about the blended centre.
    pub(super) fn hand_over(
        &mut self,
        kept: &mut [Highlight],
        previous: &[Highlight],
        world_from_object: Mat4,
    ) {
        let last = std::mem::take(&mut self.handovers);
        let m3 = Mat3::from_mat4(world_from_object);
        let object_from_world = m3.inverse();
        if self.fade_frames <= 1 || !object_from_world.is_finite() {
            return;
        }
        let before: HashMap<u64, &Highlight> = previous.iter().map(|h| (h.id, h)).collect();
        for i in 0..kept.len() {
            let h = &kept[i];
            let track = last.get(&h.id).copied();
            if h.piece != 0 {
                continue;
            }
            if !h.found {
                // Fading where it was last drawn: the track waits for it to be found again.
                if let Some(t) = track {
                    let t = Track {
                        handover: None,
                        ..t
                    };
                    self.handovers.insert(h.id, t);
                }
                continue;
            }
            let found_at = h.centre.position_object;
            let mut state = track.and_then(|t| t.handover);
            let step = track.map(|t| t.found_at.distance(found_at));
            let last_step = track.and_then(|t| t.step);
            let jump = step.zip(last_step).filter(|&(s, l)| s > 2.0 * l && s > 0.0);
            let jumped = |b: &&&Highlight| b.peak != h.peak || jump.is_some();
            if let Some(b) = before.get(&h.id).filter(jumped) {
                // Start (or restart) from where the centre was drawn last.
                let from = match state {
                    Some(s) => Some(s.drawn),
                    None => self
                        .search
                        .centre_at(
                            b.centre.face,
                            b.centre.alpha,
                            b.centre.beta,
                            world_from_object,
                        )
                        .map(|c| ObjectCentre::of(&c, object_from_world)),
                };
                // Long enough that the blend adds at most the last drawn step per update.
                let gap = from.map_or(0.0, |f| f.position.distance(found_at));
                let pace = track.and_then(|t| t.drawn_step).unwrap_or(f32::INFINITY);
                let frames = (gap / pace.max(1e-12)).ceil();
                let length = (frames as u32).clamp(self.fade_frames, 4 * self.fade_frames);
                state = from.map(|from| Handover {
                    from,
                    drawn: from,
                    frames: 0,
                    length,
                });
            }
            let mut next = Track {
                found_at,
                step,
                drawn_at: found_at,
                drawn_step: None,
                handover: None,
            };
            if let Some(mut s) = state {
                s.frames += 1;
                // The last frame of the blend draws the found centre itself.
                if s.frames < s.length {
                    let w = s.frames as f32 / s.length as f32;
                    let to = ObjectCentre::of(&h.centre, object_from_world);
                    s.drawn = ObjectCentre::blend(&s.from, &to, w);
                    if self.place_blended(kept, i, &s.drawn, world_from_object) {
                        next.handover = Some(s);
                    }
                }
            }
            next.drawn_at = kept[i].centre.position_object;
            next.drawn_step = track.map(|t| t.drawn_at.distance(next.drawn_at));
            self.handovers.insert(kept[i].id, next);
        }
    }

    /// Draws highlight `kept[i]` and its pieces about `drawn` (see
    /// [`HighlightSet::hand_over`]); false (nothing changed) where a frame degenerates.
    fn place_blended(
        &self,
        kept: &mut [Highlight],
        i: usize,
        drawn: &ObjectCentre,
        world_from_object: Mat4,
    ) -> bool {
        let h = &kept[i];
        let found = h.centre;
        let Some(centre) = drawn.placed(&found, world_from_object) else {
            return false;
        };
        let Some(whole) = reframe(&h.footprint, &found, &centre) else {
            return false;
        };
        let pieces = (i + 1..kept.len()).take_while(|&j| kept[j].id == h.id && kept[j].piece > 0);
        let mut placed = Vec::new();
        for j in pieces {
            let p = &kept[j];
            let Some(piece) = reframe(&p.footprint, &found, &centre) else {
                return false;
            };
            let edited = group_edit(&whole, &piece, &p.controls);
            let Some(projector) = Projector::with_footprint(&centre, &p.controls, &edited) else {
                return false;
            };
            placed.push((j, piece, projector));
        }
        let Some(projector) = Projector::with_footprint(&centre, &h.controls, &whole) else {
            return false;
        };
        let h = &mut kept[i];
        (h.centre, h.footprint, h.projector) = (centre, whole, projector);
        for (j, piece, projector) in placed {
            let p = &mut kept[j];
            (p.centre, p.footprint, p.projector) = (centre, piece, projector);
        }
        true
    }
}
