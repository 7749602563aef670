//! Where the engine's §4.2 receivers are walked: on the CPU in the highlight update, or as
//! a compute pass (`npr_specular::ReceiverPass`) recorded into the frame's own submission,
//! whose stream the highlight pass draws indirectly (`HighlightPass::prepare_with_receivers`).
//! Nothing is read back on the frame's path: the panel's receiver count and whether a
//! walk overflowed come from the counts alone (`ReceiverObject::map_counts`), one frame
//! late. A walk that overflowed its capacity has it grown for the next frame. The GPU walk
//! runs where the search does (`[specular] search`: `gpu`, or `auto` once it chose the
//! GPU), and in the browser too with `gpu`, since it needs no readback; where the
//! device's limits are too small for the mesh, the CPU walks.

use crate::AppError;
use glam::Mat4;
use npr_gpu::{FrameId, Prepared};
use npr_specular::{
    HighlightSet, PendingReceivers, ReceiverInput, ReceiverObject, ReceiverPass, SpecularError,
};

/// The GPU walk of the current set and its last counts.
#[derive(Default)]
pub(crate) struct ReceiverSetup {
    gpu: Option<GpuWalk>,
    /// The counts of the last walk on their way back.
    pending: Option<PendingReceivers>,
    /// Receiver faces of the last walk read back.
    faces: usize,
    /// Whether the last walk read back overflowed (grow before the next walk).
    overflowed: bool,
}

/// The compute pass, the set's tables on the GPU (`None` where the device's limits are too
/// small for the mesh) and this frame's walk.
struct GpuWalk {
    pass: ReceiverPass,
    object: Option<ReceiverObject>,
    walked: Option<Prepared>,
}

impl ReceiverSetup {
    /// Forgets the GPU object and the counts (a new set or model).
    pub(crate) fn forget(&mut self) {
        *self = Self::default();
    }

    /// Receiver faces of the last GPU walk read back (one frame late; 0 before the
    /// first).
    pub(crate) fn faces(&self) -> usize {
        self.faces
    }

    /// Takes the last walk's counts if they have arrived (native: polls `device` without
    /// blocking first).
    fn collect(&mut self, device: &wgpu::Device) -> Result<(), AppError> {
        let Some(pending) = &self.pending else {
            return Ok(());
        };
        #[cfg(not(target_arch = "wasm32"))]
        let _ = device.poll(wgpu::PollType::Poll);
        #[cfg(target_arch = "wasm32")]
        let _ = device;
        if let Some(read) = pending.try_take() {
            let read = read?;
            self.faces = read.counts.iter().map(|c| c.received as usize).sum();
            self.overflowed = read.counts.iter().any(|c| c.overflowed);
            self.pending = None;
        }
        Ok(())
    }

    /// Whether this frame's walk can run on the GPU for `set` (creating or growing its
    /// object first); `false` where the mesh does not fit the device's limits.
    ///
    /// # Errors
    /// A GPU failure other than a mesh too large, or a readback that failed.
    pub(crate) fn ready(
        &mut self,
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
    ) -> Result<bool, AppError> {
        self.collect(device)?;
        let gpu = self.gpu.get_or_insert_with(|| GpuWalk {
            pass: ReceiverPass::new(device),
            object: None,
            walked: None,
        });
        gpu.walked = None;
        let capacity = match &gpu.object {
            // Twice the longest walk the CPU last made, where it made one.
            None => set
                .highlights()
                .iter()
                .map(|h| 2 * h.receivers.len())
                .fold(npr_specular::DEFAULT_WALK_CAPACITY, usize::max),
            Some(o) if self.overflowed && o.capacity() < set.topology().face_count() => {
                o.capacity() * 4
            }
            Some(_) => return Ok(true),
        };
        self.overflowed = false;
        gpu.object = match gpu
            .pass
            .create_object_with_capacity(device, set, indices, capacity)
        {
            Ok(o) => Some(o),
            Err(SpecularError::Gpu(npr_gpu::GpuError::MeshTooLarge { .. })) => None,
            Err(e) => return Err(e.into()),
        };
        Ok(gpu.object.is_some())
    }

    /// Prepares and records this frame's walk into `encoder` (after [`Self::ready`]
    /// said yes); the object and the walk for `HighlightPass::prepare_with_receivers`.
    ///
    /// # Errors
    /// The receiver pass's (a stale frame, a set of another mesh, scratch too large).
    pub(crate) fn record(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        set: &HighlightSet,
        (frame, world_from_object): (FrameId, Mat4),
    ) -> Result<Option<(&ReceiverObject, Prepared)>, AppError> {
        let Some(GpuWalk {
            pass,
            object: Some(object),
            walked,
        }) = self.gpu.as_mut()
        else {
            return Ok(None);
        };
        let input = ReceiverInput {
            frame,
            set,
            world_from_object,
        };
        let prepared = pass.prepare(queue, object, &input)?;
        pass.record(encoder, object, &prepared)?;
        *walked = Some(prepared);
        Ok(Some((object, prepared)))
    }

    /// After the frame's submission: asks for the counts of its walk, unless the last
    /// ones are still on their way.
    ///
    /// # Errors
    /// A stale walk (a frame without a new one after it).
    pub(crate) fn after_submit(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(), AppError> {
        if self.pending.is_some() {
            return Ok(());
        }
        if let Some(gpu) = self.gpu.as_mut()
            && let (Some(object), Some(walked)) = (&gpu.object, gpu.walked.take())
        {
            self.pending = Some(object.map_counts(device, queue, &walked)?);
        }
        Ok(())
    }
}
