//! The surface anchors of coherent hatching (beyond the paper's §5 shower-door limit):
//! two reference views per object, re-taken in turn, each with a snapshot of the mesh's
//! vertices at the moment it was taken, so that a surface point of a moving, deforming
//! mesh is anchored where it was on the screen then.

use super::{AnchorUniforms, HatchObject, MAT4_BYTES, ScenePasses, SceneSlot};
use crate::HatchError;
use glam::Vec3;
use npr_gpu::{FrameUniforms, ObjectUniforms, Prepared};

impl ScenePasses {
    /// The anchor slot re-taken most recently at clock `c`, the clock it was taken at, and
    /// its weight (the other slot, taken one period earlier, gets 1 − weight).
    pub(super) fn anchor_phase(&self, c: u64) -> (usize, u64, f32) {
        let n = u64::from(self.settings.anchor_period.max(1));
        let slot = ((c / n) % 2) as usize;
        let taken = c - c % n;
        (slot, taken, (c % n) as f32 / n as f32)
    }

    /// The weight of anchor 1 that [`ScenePasses::record_gbuffer`] writes on every
    /// surface pixel of a frame prepared at `clock`: 0 or 1 outside the anchors'
    /// cross-fade, where the hatching pass reads one anchor only
    /// ([`crate::HatchInput::anchor_weight`]).
    pub fn anchor_weight(&self, clock: u64) -> f32 {
        let (slot, _, w) = self.anchor_phase(clock);
        if slot == 1 { w } else { 1.0 - w }
    }

    /// Writes the reference views the slot's anchors need at clock `c` and do not hold.
    pub(super) fn retake_anchors(
        &self,
        queue: &wgpu::Queue,
        slot: &mut SceneSlot,
        c: u64,
        view: &FrameUniforms,
        object: &ObjectUniforms,
    ) {
        let (current, taken, _) = self.anchor_phase(c);
        let n = u64::from(self.settings.anchor_period.max(1));
        // The other anchor was taken one period earlier (none before the first period:
        // it is then taken now, once).
        let other_taken = taken.checked_sub(n);
        for (s, want) in [(current, Some(taken)), (1 - current, other_taken)] {
            let have = slot.anchored[s];
            let stale = match want {
                Some(t) => have != Some(t),
                None => have.is_none(),
            };
            if !stale {
                continue;
            }
            let o = s as u64 * MAT4_BYTES;
            let clip = std::mem::offset_of!(AnchorUniforms, clip_from_world) as u64;
            let world = std::mem::offset_of!(AnchorUniforms, world_from_object) as u64;
            let clip_from_world = bytemuck::bytes_of(&view.clip_from_world);
            queue.write_buffer(&slot.anchor, clip + o, clip_from_world);
            let world_from_object = bytemuck::bytes_of(&object.world_from_object);
            queue.write_buffer(&slot.anchor, world + o, world_from_object);
            slot.anchored[s] = Some(want.unwrap_or(c));
            slot.copy_due[s] = true;
        }
    }

    /// Writes a new pose's stroke directions into `object` (one per render vertex, as
    /// [`ScenePasses::create_object`] takes them), keeping its anchors, so that the
    /// strokes of a deforming mesh stay on its surface from pose to pose. Like
    /// [`npr_gpu::GpuMesh::write_vertices`], this is per object, not per prepare.
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] for a count that is not the vertex count.
    pub fn write_directions(
        &self,
        queue: &wgpu::Queue,
        object: &HatchObject,
        directions: &[Vec3],
    ) -> Result<(), HatchError> {
        if directions.len() != object.mesh.vertex_count as usize {
            return Err(HatchError::LengthMismatch {
                what: "stroke directions (one per render vertex)",
                expected: object.mesh.vertex_count as usize,
                actual: directions.len(),
            });
        }
        let clean: Vec<[f32; 3]> = directions.iter().map(|d| clean_direction(*d)).collect();
        queue.write_buffer(&object.directions, 0, bytemuck::cast_slice(&clean));
        Ok(())
    }
}

/// A direction as the vertex buffer holds it: zero where it is not finite.
pub(super) fn clean_direction(d: Vec3) -> [f32; 3] {
    if d.is_finite() {
        d.to_array()
    } else {
        [0.0; 3]
    }
}

/// Copies the mesh's vertices into the snapshot of each anchor that the objects' last
/// prepare re-took (idempotent within a frame: every stage that draws may call it).
pub(super) fn copy_snapshots(
    encoder: &mut wgpu::CommandEncoder,
    objects: &[(&HatchObject, &Prepared)],
    slots: &[&SceneSlot],
) {
    for ((object, _), slot) in objects.iter().zip(slots) {
        for (snapshot, due) in slot.snapshots.iter().zip(slot.copy_due) {
            if due {
                let size = object.mesh.vertex_buffer.size().min(snapshot.size());
                encoder.copy_buffer_to_buffer(&object.mesh.vertex_buffer, 0, snapshot, 0, size);
            }
        }
    }
}
