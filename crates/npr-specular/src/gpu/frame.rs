//! A frame's highlights wholly on the GPU, nothing read back on the frame's path: the
//! `N = H` search with its peaks ([`CentreSearchPass`]), the regions seeded from its
//! centres matched with the last frame's highlights as the GPU kept them
//! ([`RegionPass::prepare_tracked_on_table`]), the highlights made into projectors
//! ([`ProjectorPass`]) and their §4.2 receivers ([`ReceiverPass::prepare_on_projectors`]),
//! recorded into the caller's encoder before the highlight draw
//! ([`FrameOnGpu::highlight_frame`]). [`crate::HighlightSetup`] drives it for
//! [`crate::Backend::Gpu`]. The CPU sees each frame's
//! highlights one frame late ([`FrameOnGpu::latest`]), for picking or a panel; the
//! user's edits ([`HighlightSet::controls_mut`]) and settings reach the GPU the frame they
//! are made.
//!
//! ```ignore
//! let mut highlights = FrameOnGpu::new(device, &set, &mesh.indices)?;
//! // per frame
//! let walked = highlights.record(queue, &mut encoder, &set, (light_eye, world), frame)?;
//! let frame_product = highlights.highlight_frame(&set, &walked)?;
//! let drawn = pass.prepare(queue, &mut object, &HighlightInput { highlights: &frame_product, .. })?;
//! // draw, submit, then:
//! highlights.read_after_submit(device, queue);
//! ```

use crate::{
    HighlightSet, SpecularError, gpu::CentreSearchPass, gpu::GpuFrame, gpu::PendingFrame,
    gpu::ProjectorInput, gpu::ProjectorObject, gpu::ProjectorPass, gpu::ReceiverInput,
    gpu::ReceiverObject, gpu::ReceiverPass, gpu::RegionObject, gpu::RegionPass, gpu::ReposeInput,
    gpu::ReposeObject, gpu::ReposePass, gpu::ReposeTargets, gpu::SearchObject, gpu::TrackedInput,
};
use glam::Mat4;
use npr_geometry::LightEye;
use npr_gpu::pass::{FrameId, Prepared};
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// The prepares of one frame's stages ([`FrameOnGpu::prepare`]), for their records.
#[derive(Debug)]
pub(crate) struct FramePrepared {
    searched: Prepared,
    grown: Prepared,
    projected: Prepared,
    pub(crate) walked: Prepared,
}

/// The passes and objects of one mesh's frames on the GPU, and the last frame read back.
#[derive(Debug)]
pub struct FrameOnGpu {
    search_pass: CentreSearchPass,
    region_pass: RegionPass,
    projector_pass: ProjectorPass,
    receiver_pass: ReceiverPass,
    search: SearchObject,
    regions: RegionObject,
    projectors: ProjectorObject,
    receivers: ReceiverObject,
    pending: Option<PendingFrame>,
    latest: Option<GpuFrame>,
    /// Which texture layers are normal maps (the highlight pass's).
    normal_maps: Vec<bool>,
    /// The last frame's receivers prepare and the CPU time its `record` took (µs).
    walked: Option<Prepared>,
    record_us: f64,
    /// Frames read back so far.
    reads: u64,
    /// Seeds the next frame's regions have room for.
    room: usize,
    /// A pose's tables made on the GPU ([`FrameOnGpu::pose_on_gpu`]).
    pose: Option<(ReposePass, ReposeObject)>,
}

impl FrameOnGpu {
    /// Uploads `set`'s tables (`indices`: the render mesh's triangles, faces in the set's
    /// order), with the built-in textures' layers (none a normal map but the last,
    /// [`crate::HighlightShape::ALL`]).
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] where a table exceeds the device's bindings (set
    /// the frame up on the CPU there).
    pub fn new(
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
    ) -> Result<Self, SpecularError> {
        let search_pass = CentreSearchPass::new(device);
        let region_pass = RegionPass::new(device);
        let projector_pass = ProjectorPass::new(device);
        let receiver_pass = ReceiverPass::new(device);
        let longest = (4 * crate::gpu::DEFAULT_WALK_CAPACITY).min(set.topology().face_count());
        Ok(Self {
            search: search_pass.create_object_with_peaks(device, set)?,
            regions: region_pass.create_object(device, set)?,
            projectors: projector_pass.create_object(device),
            receivers: receiver_pass.create_object_with_capacity(device, set, indices, longest)?,
            search_pass,
            region_pass,
            projector_pass,
            receiver_pass,
            pending: None,
            latest: None,
            normal_maps: crate::HighlightShape::ALL
                .iter()
                .map(|s| s.is_normal_map())
                .collect(),
            walked: None,
            record_us: 0.0,
            reads: 0,
            room: crate::gpu::TRACKED_SEEDS,
            pose: None,
        })
    }

    /// Makes this mesh's poses on the GPU from now on: each [`FrameOnGpu::record_pose`]
    /// writes the tables of the pose in `gpu`'s vertex buffer (the search's, the
    /// regions', the receivers' and the highlight draw's normals) from it and from
    /// `curvature`'s field measured on it, as [`HighlightSet::repose`] would on the CPU,
    /// so `set` need not be reposed (its settings and controls are still read every
    /// frame). `mesh` is the render mesh `set` was built from, `gpu` its upload;
    /// `curvature` is best made with
    /// [`npr_gpu::CurvaturePass::create_object_with_reach`] at [`npr_gpu::POSE_REACH`],
    /// so that parts a pose brings closer are measured as the CPU measures them.
    ///
    /// # Errors
    /// As [`ReposePass::create_object`].
    pub fn pose_on_gpu(
        &mut self,
        device: &wgpu::Device,
        set: &HighlightSet,
        (mesh, gpu): (&npr_geometry::Mesh, &npr_gpu::GpuMesh),
        curvature: &npr_gpu::CurvatureObject,
    ) -> Result<(), SpecularError> {
        let pass = ReposePass::new(device);
        let targets = ReposeTargets {
            search: &self.search,
            regions: &self.regions,
            receivers: &self.receivers,
        };
        let object = pass.create_object(device, set, (mesh, gpu), curvature, targets)?;
        self.projectors.posed_normals = Some(object.render_normals().clone());
        self.pose = Some((pass, object));
        Ok(())
    }

    /// Records the tables of the pose now in the mesh's vertex buffer into `encoder`:
    /// after the posing and the curvature, before [`FrameOnGpu::record`] (once a pose; a
    /// frame of the same pose needs none). Nothing without [`FrameOnGpu::pose_on_gpu`].
    ///
    /// # Errors
    /// As [`ReposePass::record`].
    pub fn record_pose(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameId,
    ) -> Result<(), SpecularError> {
        let prepared = self.prepare_pose(queue, frame)?;
        self.record_prepared_pose(encoder, prepared.as_ref())
    }

    /// The queue writes of [`FrameOnGpu::record_pose`]; `None` without a pose on the GPU.
    pub(crate) fn prepare_pose(
        &mut self,
        queue: &wgpu::Queue,
        frame: FrameId,
    ) -> Result<Option<Prepared>, SpecularError> {
        match self.pose.as_mut() {
            Some((pass, object)) => {
                Ok(Some(pass.prepare(queue, object, &ReposeInput { frame })?))
            }
            None => Ok(None),
        }
    }

    /// The commands of [`FrameOnGpu::record_pose`].
    pub(crate) fn record_prepared_pose(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        prepared: Option<&Prepared>,
    ) -> Result<(), SpecularError> {
        if let (Some((pass, object)), Some(prepared)) = (self.pose.as_ref(), prepared) {
            pass.record(encoder, object, prepared)?;
        }
        Ok(())
    }

    /// Whether poses are made on the GPU ([`FrameOnGpu::pose_on_gpu`]).
    pub fn poses_on_gpu(&self) -> bool {
        self.pose.is_some()
    }

    /// Records `frame`'s highlight work into `encoder` for this light, eye and transform:
    /// the search, the regions, the projectors and their receivers, in that order. `set`
    /// gives the mesh, the settings and the user's controls; its own highlights are not
    /// touched. Returns the receivers' prepare, for [`FrameOnGpu::highlight_frame`] in the
    /// same submission.
    ///
    /// # Errors
    /// A pass's (a set of another mesh, too many prepares in one frame).
    pub fn record(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        set: &HighlightSet,
        frame_of: (LightEye, Mat4),
        frame: FrameId,
    ) -> Result<Prepared, SpecularError> {
        let prepared = self.prepare(queue, set, frame_of, frame)?;
        self.record_prepared(encoder, &prepared)
    }

    /// The queue writes of [`FrameOnGpu::record`]: each stage's prepare, in order.
    pub(crate) fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        set: &HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
        frame: FrameId,
    ) -> Result<FramePrepared, SpecularError> {
        let start = Instant::now();
        let frame_of = (light_eye, world_from_object);
        let searched =
            self.search_pass
                .prepare_for_set(queue, &mut self.search, (set, frame), frame_of)?;
        let tracked = TrackedInput {
            frame,
            set,
            light_eye,
            world_from_object,
            search: (&self.search, &searched),
        };
        // Room for twice the highlights last read back and 8 more (at least
        // `TRACKED_SEEDS`); twice the last room after a frame held for want of it.
        self.room = match &self.latest {
            Some(f) if f.status == crate::gpu::GpuFrameStatus::Held => 2 * self.room,
            Some(f) => (2 * f.highlights.len() + 8).next_power_of_two(),
            None => self.room,
        }
        .clamp(crate::gpu::TRACKED_SEEDS, crate::gpu::MAX_TRACKED);
        let table = self.projectors.table().clone();
        let grown = self.region_pass.prepare_tracked_on_table(
            queue,
            &mut self.regions,
            &tracked,
            (&table, self.room),
        )?;
        let projected = self.projector_pass.prepare(
            queue,
            &mut self.projectors,
            &ProjectorInput {
                frame,
                set,
                world_from_object,
                regions: (&self.regions, &grown),
                search: (&self.search, &searched),
                normal_maps: &self.normal_maps,
            },
        )?;
        // Room for twice the projectors the last frame read back drew, and 8 more.
        let drawn = self.latest.as_ref().map_or(24, |f| f.projectors.len());
        let room = (2 * drawn + 8)
            .next_power_of_two()
            .min(crate::gpu::MAX_DRAWN);
        let walk = ReceiverInput {
            frame,
            set,
            world_from_object,
        };
        let walked = self.receiver_pass.prepare_on_projectors(
            queue,
            &mut self.receivers,
            &walk,
            (&self.projectors, room),
        )?;
        self.walked = Some(walked);
        self.record_us = start.elapsed().as_secs_f64() * 1e6;
        Ok(FramePrepared {
            searched,
            grown,
            projected,
            walked,
        })
    }

    /// The commands of [`FrameOnGpu::record`]: search, regions, projectors, receivers.
    pub(crate) fn record_prepared(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        prepared: &FramePrepared,
    ) -> Result<Prepared, SpecularError> {
        let start = Instant::now();
        self.search_pass
            .record_on_gpu(encoder, &self.search, &prepared.searched)?;
        self.region_pass
            .record(encoder, &self.regions, &prepared.grown)?;
        self.projector_pass
            .record(encoder, &self.projectors, &prepared.projected)?;
        self.receiver_pass
            .record(encoder, &self.receivers, &prepared.walked)?;
        self.record_us += start.elapsed().as_secs_f64() * 1e6;
        Ok(prepared.walked)
    }

    /// The frame `walked` (a [`FrameOnGpu::record`]'s return) made, for the highlight
    /// draw; `set` is the one recorded with.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `walked` of another object or pass.
    pub fn highlight_frame<'a>(
        &'a self,
        set: &'a HighlightSet,
        walked: &Prepared,
    ) -> Result<crate::HighlightFrame<'a>, SpecularError> {
        let stream = self.receivers.stream(walked)?;
        Ok(crate::HighlightFrame::on_gpu(
            walked.frame(),
            set,
            stream,
            &self.projectors,
        ))
    }

    /// Makes the next [`FrameOnGpu::record`] start from the table the last one started
    /// from: for a measure that draws the last frame again (with other tints) without
    /// advancing its fades. Call only after that frame's submission.
    #[cfg(any(test, feature = "test-support"))]
    pub(crate) fn repeat_last_frame(&mut self) {
        self.projectors.rewind();
    }

    /// Waits until no frame is on its way back (the last one asked for has arrived, or
    /// none was asked for): for a measure that reads each frame it made. Polling the
    /// device alone is not enough where other threads poll it too (tests run in
    /// parallel on one device): another thread's poll may run the map's callback after
    /// this one's returns.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::Readback`] for a failed poll, or a read that never arrives.
    #[cfg(any(test, feature = "test-support"))]
    pub(crate) fn wait_for_read(&mut self, device: &wgpu::Device) -> Result<(), SpecularError> {
        for _ in 0..10_000 {
            self.poll();
            if self.pending.is_none() {
                return Ok(());
            }
            device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| npr_gpu::GpuError::Readback(e.to_string()))?;
            std::thread::yield_now();
        }
        Err(npr_gpu::GpuError::Readback("the frame's read never arrived".into()).into())
    }

    /// The CPU time the last [`FrameOnGpu::record`] took, µs: all the CPU does for a
    /// frame's highlights.
    pub fn record_us(&self) -> f64 {
        self.record_us
    }

    /// The last recorded frame's receivers prepare (to read its counts, one frame late:
    /// [`ReceiverObject::map_counts`]).
    pub fn walked(&self) -> Option<&Prepared> {
        self.walked.as_ref()
    }

    /// Starts the next frame from `set`'s last update (its highlights keep their ids, fades
    /// and edits on the GPU): [`ProjectorObject::start_from`].
    pub fn start_from(&self, queue: &wgpu::Queue, set: &HighlightSet, world_from_object: Mat4) {
        self.projectors
            .start_from(queue, (set, &self.search), world_from_object);
    }

    /// Which texture layers of the highlight pass are normal maps
    /// ([`crate::HighlightPass::normal_map_layers`]; the built-in textures' by default).
    pub fn set_normal_maps(&mut self, layers: &[bool]) {
        self.normal_maps = layers.to_vec();
    }

    /// The projectors the last recorded frame builds (the highlight pass draws them).
    pub fn projectors(&self) -> &ProjectorObject {
        &self.projectors
    }

    /// The receivers the last recorded frame walks (the highlight pass draws their
    /// stream).
    pub fn receivers(&self) -> &ReceiverObject {
        &self.receivers
    }

    /// After the frame's submission: asks for its highlights, which
    /// [`FrameOnGpu::latest`] gives once they arrive (a frame still on its way is
    /// dropped for the newer one).
    pub fn read_after_submit(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        self.poll();
        if self.pending.is_none() {
            self.pending = Some(self.projectors.map_frame(device, queue));
        }
    }

    /// The last frame read back, if any has arrived (never waits).
    pub fn latest(&mut self) -> Option<&GpuFrame> {
        self.poll();
        self.latest.as_ref()
    }

    /// How many frames have been read back so far ([`FrameOnGpu::latest`] is the last).
    pub fn frames_read(&mut self) -> u64 {
        self.poll();
        self.reads
    }

    fn poll(&mut self) {
        if let Some(pending) = &self.pending {
            if let Some(result) = pending.try_take() {
                if let Ok(frame) = result {
                    self.latest = Some(frame);
                    self.reads += 1;
                }
                self.pending = None;
            }
        }
    }
}
