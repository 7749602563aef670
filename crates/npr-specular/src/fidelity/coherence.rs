//! Frame coherence of a highlight sequence: pops without their fade and footprint
//! changes, over a rigid turn or a moving mesh's poses, on the CPU or with each frame made
//! by a caller (the GPU setups of [`super::GpuSetup`]).

use crate::{HighlightSet, SpecularError};
use glam::Mat4;
use npr_geometry::{CurvatureOptions, LightEye, Mesh};

/// Frame coherence of a highlight sequence (see [`Coherence::step`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coherence {
    /// Highlights that appeared above one fade step of opacity (popped in).
    pub pops_in: usize,
    /// Highlights that vanished while above one fade step (popped out).
    pub pops_out: usize,
    /// Largest relative change `|A − A_prev| / A_prev` of a footprint's area (projector
    /// half extents' product) of a highlight present in consecutive frames.
    pub area_change_max: f32,
    /// Frames seen.
    pub frames: usize,
    fade_step: f32,
    previous: Vec<(u64, f32, f32)>,
}

impl Coherence {
    /// Checks a sequence against fades over `fade_frames` updates (0: no fade required).
    pub fn new(fade_frames: u32) -> Self {
        Self {
            fade_step: if fade_frames == 0 {
                1.0
            } else {
                1.0 / fade_frames as f32
            },
            ..Self::default()
        }
    }

    /// Records the set's highlights after one update. The first frame may show anything
    /// at full opacity; afterwards a highlight must appear with an opacity of at most one
    /// fade step, and disappear only after fading to it.
    pub fn step(&mut self, set: &HighlightSet) {
        let step = self.fade_step + 1e-4;
        let now: Vec<(u64, f32, f32)> = set
            .highlights()
            .iter()
            .filter(|h| h.piece == 0)
            .map(|h| {
                let e = h.projector.half_extent;
                (h.id, h.opacity, e.x * e.y)
            })
            .collect();
        if self.frames > 0 {
            for &(id, opacity, area) in &now {
                match self.previous.iter().find(|p| p.0 == id) {
                    None if opacity > step => self.pops_in += 1,
                    None => {}
                    Some(&(_, _, before)) => {
                        let change = (area - before).abs() / before.max(f32::MIN_POSITIVE);
                        self.area_change_max = self.area_change_max.max(change);
                    }
                }
            }
            for &(id, opacity, _) in &self.previous {
                if opacity > step && !now.iter().any(|n| n.0 == id) {
                    self.pops_out += 1;
                }
            }
        }
        self.previous = now;
        self.frames += 1;
    }
}

/// The set tracked over a rigid turn about y under a fixed light and eye: `frames`
/// updates, update `k` at `k × step_deg` degrees applied before `world_from_normalized`.
/// The set starts a new sequence first ([`HighlightSet::reset`]).
pub fn turntable_coherence(
    set: &mut HighlightSet,
    light_eye: LightEye,
    world_from_normalized: Mat4,
    frames: usize,
    step_deg: f32,
) -> Coherence {
    let cpu = |set: &mut HighlightSet, (le, w): (LightEye, Mat4)| {
        set.update(le, w);
        Ok::<(), std::convert::Infallible>(())
    };
    match turntable_coherence_with(
        set,
        (light_eye, world_from_normalized),
        (frames, step_deg),
        cpu,
    ) {
        Ok(c) => c,
        Err(e) => match e {},
    }
}

/// [`turntable_coherence`] with each frame's update done by `update` (for instance
/// [`super::GpuSetup::update`]).
///
/// # Errors
/// The first error of `update`.
pub fn turntable_coherence_with<E>(
    set: &mut HighlightSet,
    (light_eye, world_from_normalized): (LightEye, Mat4),
    (frames, step_deg): (usize, f32),
    mut update: impl FnMut(&mut HighlightSet, (LightEye, Mat4)) -> Result<(), E>,
) -> Result<Coherence, E> {
    set.reset();
    let mut c = Coherence::new(set.tuning.fade_frames);
    for k in 0..frames {
        let turn = Mat4::from_rotation_y((k as f32 * step_deg).to_radians());
        update(set, (light_eye, turn * world_from_normalized))?;
        c.step(set);
    }
    Ok(c)
}

/// The set tracked over the poses of a moving mesh (a clip's frames, same triangles):
/// per pose one [`HighlightSet::repose`] and one update, light, eye and object transform
/// still. The set starts a new sequence first.
///
/// # Errors
/// As [`HighlightSet::repose`], for a pose it cannot be built on.
pub fn pose_coherence(
    set: &mut HighlightSet,
    light_eye: LightEye,
    world_from_object: Mat4,
    poses: impl IntoIterator<Item = Mesh>,
    options: &CurvatureOptions,
) -> Result<Coherence, SpecularError> {
    let cpu = |set: &mut HighlightSet, pose: &Mesh, (le, w): (LightEye, Mat4)| {
        set.repose(pose, options)?;
        set.update(le, w);
        Ok(())
    };
    pose_coherence_with(set, (light_eye, world_from_object), poses, cpu)
}

/// [`pose_coherence`] with each pose's frame made by `update` (for instance
/// [`super::GpuSetup::update_pose`], which leaves the set at its built pose).
///
/// # Errors
/// The first error of `update`.
pub fn pose_coherence_with<E>(
    set: &mut HighlightSet,
    frame: (LightEye, Mat4),
    poses: impl IntoIterator<Item = Mesh>,
    mut update: impl FnMut(&mut HighlightSet, &Mesh, (LightEye, Mat4)) -> Result<(), E>,
) -> Result<Coherence, E> {
    set.reset();
    let mut c = Coherence::new(set.tuning.fade_frames);
    for pose in poses {
        update(set, &pose, frame)?;
        c.step(set);
    }
    Ok(c)
}
