//! The highlight setup: one [`HighlightSetup`] on the pass contract, whichever
//! [`Backend`] runs it, whose product is one [`HighlightFrame`] a frame for
//! [`crate::HighlightPass`] to draw. The backend is chosen once per mesh
//! ([`HighlightSetup::create_object`], by [`Backend::choose`]'s rule); the per-frame
//! orchestration (a moving model's pose, the GPU frame's restarts and the CPU's view of
//! its highlights) lives here, so an embedder writes none of it.
//!
//! ```ignore
//! let setup = HighlightSetup::new(device, queue, &SetupSettings::default());
//! let settings = SpecularSettings::default(); // or a preset's
//! let mut object = setup.create_object(device, queue, &mesh, &settings, &adapter.get_info())?;
//! // per frame
//! let prepared = setup.prepare(device, queue, &mut object, &SetupInput { frame, light_eye, world_from_object, mesh: &mesh, gpu: &gpu_mesh })?;
//! let highlights = setup.record(&mut encoder, &mut object, &prepared)?;
//! let drawn = pass.prepare(queue, &mut pass_object, &HighlightInput { frame, highlights: &highlights, view, object })?;
//! // base shading, then pass.draw(...), submit, then:
//! setup.after_submit(device, queue, &mut object);
//! ```
//!
//! The GPU stages of one [`Backend::Gpu`] frame, in the order they are recorded:
//! 1. a new pose's curvature ([`npr_gpu::CurvaturePass`]) and tables
//!    ([`crate::gpu::ReposePass`]), only on the frame after [`SetupObject::repose`];
//! 2. the `N = H` search with its peaks ([`crate::gpu::CentreSearchPass`]);
//! 3. the regions `N·H ≥ σ` seeded from its centres and matched with the last frame's
//!    highlights ([`crate::gpu::RegionPass`]);
//! 4. the projectors, with fades, edits and the area-change limit
//!    ([`crate::gpu::ProjectorPass`]);
//! 5. the §4.2 receivers and the draw's indirect arguments ([`crate::gpu::ReceiverPass`]).

pub mod backend;
pub mod frame;

pub use backend::{Backend, BackendChoice, BackendSetting, ChoiceReason};
pub use frame::HighlightFrame;

use crate::{HighlightSet, SpecularError, gpu::FrameOnGpu};
use glam::Mat4;
use npr_geometry::{CurvatureOptions, LightEye, Mesh};
use npr_gpu::pass::{FrameId, PassError, PassId};
use npr_gpu::{CurvatureInput, CurvatureObject, CurvaturePass, GpuError, GpuMesh};
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// The setup's settings: plain data.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SetupSettings {
    /// Per texture layer of the highlight pass, whether it is a normal map
    /// ([`crate::HighlightPass::normal_map_layers`]); the built-in textures' by default.
    pub normal_maps: Vec<bool>,
}

impl Default for SetupSettings {
    fn default() -> Self {
        Self {
            normal_maps: crate::HighlightShape::ALL
                .iter()
                .map(|s| s.is_normal_map())
                .collect(),
        }
    }
}

/// One frame's input to [`HighlightSetup::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct SetupInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// Light and eye, in world space.
    pub light_eye: LightEye,
    /// The object's transform.
    pub world_from_object: Mat4,
    /// The render mesh in its current pose (the triangles the object was made with).
    pub mesh: &'a Mesh,
    /// Its upload (the vertex buffer the base shading draws).
    pub gpu: &'a GpuMesh,
}

/// What one frame's setup cost and made, for panels and benches.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SetupStats {
    /// CPU time of the frame's prepare and record, µs (the CPU backend's whole update;
    /// the GPU backend's recording).
    pub cpu_us: f64,
    /// Highlights the CPU knows of this frame (the GPU backend's: the last frame read
    /// back, one frame late).
    pub highlights: usize,
    /// Receiver faces of the CPU backend's highlights (0 on the GPU backend, whose walk
    /// stays there).
    pub receiver_faces: usize,
    /// Whether this frame's pose was taken on the GPU (curvature and tables).
    pub pose_on_gpu: bool,
}

/// The highlight setup's pipelines and settings; create once per device.
#[derive(Debug)]
pub struct HighlightSetup {
    id: PassId,
    settings: SetupSettings,
}

/// The GPU backend's state for one mesh.
#[derive(Debug)]
struct OnGpu {
    frame: FrameOnGpu,
    /// The curvature of the model's poses, made on the first pose; `None` before, or
    /// where it could not be made (the set is reposed on the CPU then).
    curvature: Option<(CurvaturePass, CurvatureObject)>,
    pose_failed: bool,
    /// The next frame starts again from the set (a new sequence, or after a reset).
    restart: bool,
    /// Frames read back that the set has taken as its highlights.
    adopted: u64,
}

/// One mesh's setup: its highlight set, the backend chosen for it, and the GPU frame's
/// objects where that backend is [`Backend::Gpu`].
#[derive(Debug)]
pub struct SetupObject {
    pass: PassId,
    set: HighlightSet,
    options: CurvatureOptions,
    indices: Vec<u32>,
    choice: BackendChoice,
    gpu: Option<OnGpu>,
    /// The set's geometry lags the model's pose; the GPU frame's tables lag it.
    cpu_lags: bool,
    gpu_lags: bool,
    stats: SetupStats,
}

/// A prepared frame's ticket, for [`HighlightSetup::record`].
#[derive(Debug)]
pub struct SetupPrepared {
    pass: PassId,
    frame: FrameId,
    /// The GPU backend's stages: the pose's (curvature, tables) and the frame's.
    gpu: Option<GpuPrepared>,
    started: Instant,
}

#[derive(Debug)]
struct GpuPrepared {
    pose: Option<(npr_gpu::Prepared, Option<npr_gpu::Prepared>)>,
    frame: crate::gpu::frame::FramePrepared,
}

impl HighlightSetup {
    /// The setup for `settings` (the passes' pipelines are made with each object).
    pub fn new(_device: &wgpu::Device, _queue: &wgpu::Queue, settings: &SetupSettings) -> Self {
        Self {
            id: PassId::fresh(),
            settings: settings.clone(),
        }
    }

    /// The setup of one mesh: its set, built from `mesh` with `settings`' curvature and
    /// abstraction and tuned by them, on the backend [`Backend::choose`] gives for
    /// `adapter` and `settings.backend`. A [`Backend::Gpu`] choice whose tables exceed
    /// the device's storage bindings runs [`Backend::Cpu`] ([`ChoiceReason::MeshTooLarge`]):
    /// the one place that decides it.
    ///
    /// # Errors
    /// A mesh the set cannot use ([`SpecularError::EmptyMesh`]); a GPU failure other than
    /// a mesh too large for the device.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        _queue: &wgpu::Queue,
        mesh: &Mesh,
        settings: &crate::SpecularSettings,
        adapter: &wgpu::AdapterInfo,
    ) -> Result<SetupObject, SpecularError> {
        let set = settings.build(mesh)?;
        let options = &settings.curvature;
        let choice = Backend::choose(adapter, settings.backend);
        let mut choice = choice;
        let gpu = match choice.backend {
            Backend::Cpu => None,
            Backend::Gpu => match FrameOnGpu::new(device, &set, &mesh.indices) {
                Ok(mut frame) => {
                    frame.set_normal_maps(&self.settings.normal_maps);
                    Some(OnGpu {
                        frame,
                        curvature: None,
                        pose_failed: false,
                        restart: true,
                        adopted: 0,
                    })
                }
                Err(SpecularError::Gpu(e @ GpuError::MeshTooLarge { .. })) => {
                    choice = choice.too_large(e.to_string());
                    None
                }
                Err(e) => return Err(e),
            },
        };
        Ok(SetupObject {
            pass: self.id,
            set,
            options: *options,
            indices: mesh.indices.clone(),
            choice,
            gpu,
            cpu_lags: false,
            gpu_lags: false,
            stats: SetupStats::default(),
        })
    }

    /// The frame's setup up to its commands: the CPU backend updates the set (reposed
    /// first after [`SetupObject::repose`]); the GPU backend writes its stages' inputs
    /// (and, after a repose, prepares the pose's curvature and tables). The only place
    /// that writes the queue.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for an object of another setup; a repose's or a pass's.
    pub fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        object: &mut SetupObject,
        input: &SetupInput<'_>,
    ) -> Result<SetupPrepared, SpecularError> {
        if object.pass != self.id {
            return Err(PassError::ForeignObject.into());
        }
        let started = Instant::now();
        object.stats.pose_on_gpu = false;
        let gpu = match object.gpu.is_some() {
            true => Some(object.prepare_gpu(device, queue, input)?),
            false => {
                object.catch_up(input.mesh)?;
                object.set.update(input.light_eye, input.world_from_object);
                None
            }
        };
        Ok(SetupPrepared {
            pass: self.id,
            frame: input.frame,
            gpu,
            started,
        })
    }

    /// Records the frame's stages into `encoder` (nothing on the CPU backend) and gives
    /// the frame's highlights for the highlight draw, in the same submission.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another setup or object.
    pub fn record<'a>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &'a mut SetupObject,
        prepared: &SetupPrepared,
    ) -> Result<HighlightFrame<'a>, SpecularError> {
        if prepared.pass != self.id || object.pass != self.id {
            return Err(PassError::ForeignObject.into());
        }
        let SetupObject {
            set,
            gpu,
            indices,
            stats,
            ..
        } = object;
        let made = match (gpu.as_mut(), &prepared.gpu) {
            (Some(on_gpu), Some(stages)) => {
                if let (Some((pass, curvature)), Some((measured, tables))) =
                    (on_gpu.curvature.as_ref(), stages.pose.as_ref())
                {
                    pass.record(encoder, curvature, measured)?;
                    on_gpu
                        .frame
                        .record_prepared_pose(encoder, tables.as_ref())?;
                }
                let walked = on_gpu.frame.record_prepared(encoder, &stages.frame)?;
                stats.highlights = set.highlights().len();
                stats.receiver_faces = 0;
                stats.cpu_us = prepared.started.elapsed().as_secs_f64() * 1e6;
                on_gpu.frame.highlight_frame(set, &walked)?
            }
            (None, None) => {
                let st = set.stats();
                stats.highlights = st.highlights;
                stats.receiver_faces = st.receiver_faces;
                stats.cpu_us = prepared.started.elapsed().as_secs_f64() * 1e6;
                HighlightFrame::of_set(prepared.frame, set, indices)
            }
            _ => return Err(PassError::ForeignObject.into()),
        };
        Ok(made)
    }

    /// After the frame's submission: asks for the GPU frame's highlights (the CPU's view
    /// of them, one frame late: [`SetupObject::set`]). Never waits.
    pub fn after_submit(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        object: &mut SetupObject,
    ) {
        if let Some(on_gpu) = object.gpu.as_mut() {
            on_gpu.frame.read_after_submit(device, queue);
            #[cfg(not(target_arch = "wasm32"))]
            let _ = device.poll(wgpu::PollType::Poll);
        }
    }
}

impl SetupObject {
    /// The backend this mesh runs, and why.
    pub fn choice(&self) -> &BackendChoice {
        &self.choice
    }

    /// The backend this mesh runs.
    pub fn backend(&self) -> Backend {
        self.choice.backend
    }

    /// The highlight set: the CPU backend's last update, or the last frame the GPU
    /// backend read back (one frame late), for picking and panels.
    pub fn set(&self) -> &HighlightSet {
        &self.set
    }

    /// The set, for its settings and the user's edits ([`HighlightSet::controls_mut`]):
    /// both backends read them every frame.
    pub fn set_mut(&mut self) -> &mut HighlightSet {
        &mut self.set
    }

    /// The GPU backend's frame (its last walk's counts for a panel, its records for a
    /// test); `None` on the CPU backend.
    pub fn gpu_frame(&self) -> Option<&FrameOnGpu> {
        self.gpu.as_ref().map(|g| &g.frame)
    }

    /// The last frame's figures.
    pub fn stats(&self) -> SetupStats {
        self.stats
    }

    /// The model moved to a new pose (same triangles, new positions in the mesh and its
    /// vertex buffer): the next frame takes it (on the GPU where the backend is the
    /// GPU's and the pose's curvature can be made there), keeping the highlights' ids,
    /// fades and edits.
    pub fn repose(&mut self) {
        (self.cpu_lags, self.gpu_lags) = (true, true);
    }

    /// Forgets highlight tracking: the next frame starts a new sequence.
    pub fn reset(&mut self) {
        self.set.reset();
        if let Some(on_gpu) = self.gpu.as_mut() {
            on_gpu.restart = true;
        }
    }

    /// Updates the CPU's set now, for `mesh`'s pose (for a caller that needs the
    /// highlights' ids before the first frame, such as edits anchored to a point). A GPU
    /// frame after it starts from the set.
    ///
    /// # Errors
    /// A repose's.
    pub fn update_now(
        &mut self,
        mesh: &Mesh,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> Result<(), SpecularError> {
        self.catch_up(mesh)?;
        self.set.update(light_eye, world_from_object);
        if let Some(on_gpu) = self.gpu.as_mut() {
            on_gpu.restart = true;
        }
        Ok(())
    }

    /// The GPU backend's last frame read back, if one arrived since the last call, becomes
    /// the set's highlights (ids, centres, footprints, fades; pieces are not listed, their
    /// whole stands for them): what picking and panels see, one frame late. Each frame's
    /// prepare does this; call it between frames for the newest. Returns whether the set
    /// changed (never on the CPU backend). Never waits.
    pub fn adopt_read_back(&mut self) -> bool {
        let Some(on_gpu) = self.gpu.as_mut() else {
            return false;
        };
        if on_gpu.frame.frames_read() <= on_gpu.adopted {
            return false;
        }
        on_gpu.adopted = on_gpu.frame.frames_read();
        match on_gpu.frame.latest() {
            Some(latest) => {
                self.set.adopt_gpu_frame(latest);
                true
            }
            None => false,
        }
    }

    /// Reposes the CPU's set if it lags the pose.
    fn catch_up(&mut self, mesh: &Mesh) -> Result<(), SpecularError> {
        if std::mem::take(&mut self.cpu_lags) {
            self.set.repose(mesh, &self.options)?;
        }
        Ok(())
    }

    /// The GPU backend's prepare: the pose (on the GPU where it can be), the restart or
    /// the adoption of the frame read back, then the frame's stages.
    fn prepare_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: &SetupInput<'_>,
    ) -> Result<GpuPrepared, SpecularError> {
        let pose = match std::mem::take(&mut self.gpu_lags) {
            true => self.prepare_pose(device, queue, input)?,
            false => None,
        };
        self.stats.pose_on_gpu = pose.is_some();
        let Some(on_gpu) = self.gpu.as_mut() else {
            return Err(PassError::ForeignObject.into());
        };
        let frame_of = (input.light_eye, input.world_from_object);
        if std::mem::take(&mut on_gpu.restart) {
            on_gpu
                .frame
                .start_from(queue, &self.set, input.world_from_object);
        } else {
            self.adopt_read_back();
        }
        let Some(on_gpu) = self.gpu.as_mut() else {
            return Err(PassError::ForeignObject.into());
        };
        let frame = on_gpu
            .frame
            .prepare(queue, &self.set, frame_of, input.frame)?;
        Ok(GpuPrepared { pose, frame })
    }

    /// A new pose for the GPU frame: its curvature and tables prepared on the GPU (made
    /// on the first pose), else the CPU's set reposed (the frame reads its tables).
    #[allow(clippy::type_complexity)]
    fn prepare_pose(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: &SetupInput<'_>,
    ) -> Result<Option<(npr_gpu::Prepared, Option<npr_gpu::Prepared>)>, SpecularError> {
        let Some(on_gpu) = self.gpu.as_mut() else {
            return Ok(None);
        };
        if !on_gpu.frame.poses_on_gpu() && !on_gpu.pose_failed {
            let pass = CurvaturePass::new(device);
            let made = pass
                .create_object_with_reach(
                    device,
                    input.gpu,
                    input.mesh,
                    self.options.radius,
                    npr_gpu::POSE_REACH,
                )
                .map_err(SpecularError::from)
                .and_then(|curvature| {
                    on_gpu.frame.pose_on_gpu(
                        device,
                        &self.set,
                        (input.mesh, input.gpu),
                        &curvature,
                    )?;
                    Ok(curvature)
                });
            match made {
                Ok(curvature) => on_gpu.curvature = Some((pass, curvature)),
                Err(_) => on_gpu.pose_failed = true,
            }
        }
        match on_gpu
            .curvature
            .as_mut()
            .filter(|_| on_gpu.frame.poses_on_gpu())
        {
            Some((pass, curvature)) => {
                let measured =
                    pass.prepare(queue, curvature, &CurvatureInput { frame: input.frame })?;
                let tables = on_gpu.frame.prepare_pose(queue, input.frame)?;
                Ok(Some((measured, tables)))
            }
            None => {
                self.catch_up(input.mesh)?;
                Ok(None)
            }
        }
    }
}
