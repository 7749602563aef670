//! The stylized highlights (Lee & Choi) in the engine: the highlight set, specialised by
//! its curvature smoothing and abstraction, and the highlight pass, specialised by its
//! texture shape. A new shape keeps the set (and its tracked highlights); new smoothing
//! keeps the pass.

use super::FrameStats;
use super::inputs::{anchor_reach, apply_controls, builtin_shape};
use super::receivers::ReceiverSetup;
use super::search::SearchSetup;
use super::specialized::Specialized;
use crate::AppError;
use crate::model::Model;
use crate::preset::{Preset, SearchPreset};
use crate::view::View;
use npr_geometry::{CurvatureOptions, CurvatureRadius};
use npr_gpu::{FrameId, FrameUniforms, GpuMesh, ObjectUniforms, Prepared, TargetFormats};
use npr_specular::{HighlightObject, HighlightPass, HighlightSet, HighlightShape};
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// What the highlight set is built for: the curvature smoothing (edge lengths) and the
/// abstraction scale, as bit patterns so that the key hashes.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct SetKey {
    smoothing_edges: u32,
    abstraction: u32,
}

impl SetKey {
    fn of(preset: &Preset) -> Self {
        Self {
            smoothing_edges: preset.specular.smoothing_edges.to_bits(),
            abstraction: preset.specular.abstraction.to_bits(),
        }
    }
}

/// The highlight pass of one texture shape (a built-in name or a PNG path), the model's
/// object in it and the shape's texture layer.
struct ShapePass {
    pass: HighlightPass,
    object: HighlightObject,
    layer: u32,
}

/// The highlight set and pass (see the module docs).
#[derive(Default)]
pub(crate) struct SpecularEffect {
    set: Specialized<SetKey, HighlightSet>,
    shape: Specialized<String, ShapePass>,
    /// The model moved since the set was built or last reposed.
    moved: bool,
    /// The set's geometry lags the model's pose (a pose made on the GPU only), and the
    /// GPU frame's tables lag it (the next GPU frame makes them).
    cpu_lags: bool,
    gpu_lags: bool,
    /// The curvature of the model's poses on the GPU, for `frame_gpu`'s poses
    /// (`FrameOnGpu::pose_on_gpu`); whether they could not be made there (the set is
    /// reposed on the CPU then).
    curvature: Option<(npr_gpu::CurvaturePass, npr_gpu::CurvatureObject, FrameId)>,
    pose_failed: bool,
    /// Where the `N = H` search runs, and the GPU search of the current set.
    search: SearchSetup,
    /// The GPU walk of the §4.2 receivers, where the search runs on the GPU.
    receivers: ReceiverSetup,
    /// The whole frame on the GPU (`search = "gpu-frame"`) for the current set; whether
    /// it could not be made for it (then the `gpu` path runs), and whether its next frame
    /// starts again from the set (a reset).
    frame_gpu: Option<npr_specular::FrameOnGpu>,
    frame_gpu_failed: bool,
    restart: bool,
    /// Frames read back that the set has adopted.
    adopted: u64,
}

impl SpecularEffect {
    /// The model moved to a new pose (same triangles): the next frame reposes the set
    /// ([`HighlightSet::repose`]), keeping its highlights' ids, fades and edits.
    pub(crate) fn repose(&mut self) {
        self.moved = true;
    }

    /// The highlight set, once a specular frame has been prepared.
    pub(crate) fn set(&self) -> Option<&HighlightSet> {
        self.set.get()
    }

    /// Forgets highlight tracking (the next frame starts a new sequence).
    pub(crate) fn reset(&mut self) {
        if let Some(set) = self.set.get_mut() {
            set.reset();
        }
        self.restart = true;
    }

    /// Drops everything (a new model).
    pub(crate) fn clear(&mut self) {
        self.set.clear();
        self.shape.clear();
        self.search.forget();
        self.receivers.forget();
        self.forget_frame_gpu();
    }

    fn forget_frame_gpu(&mut self) {
        self.frame_gpu = None;
        self.curvature = None;
        self.pose_failed = false;
        self.adopted = 0;
        self.frame_gpu_failed = false;
        self.restart = false;
    }

    /// Updates the highlights for `view` (the setup: the `N = H` search, matching,
    /// regions, visibility; timed into `stats`) and writes this draw's per-frame data.
    /// Where the search runs on the GPU the receivers are walked there too, recorded
    /// into `encoder` ahead of the frame's render pass.
    ///
    /// # Errors
    /// A highlight texture that cannot be loaded, or a mesh the set cannot use.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn prepare(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (model, mesh): (&Model, &GpuMesh),
        preset: &Preset,
        view: &View,
        (frame, uniforms, object): (FrameId, &FrameUniforms, &ObjectUniforms),
        stats: &mut FrameStats,
    ) -> Result<Prepared, AppError> {
        let sp = &preset.specular;
        let shape = self.shape.get_or_build(&sp.shape, |shape| {
            ShapePass::new(device, queue, mesh, shape)
        })?;
        let options = CurvatureOptions {
            radius: CurvatureRadius::EdgeLengths(sp.smoothing_edges),
            ..CurvatureOptions::default()
        };
        let mut built = false;
        let set = self.set.get_or_build(&SetKey::of(preset), |_| {
            built = true;
            HighlightSet::with_abstraction(&model.mesh, &options, sp.abstraction)
        })?;
        if built {
            self.search.forget();
            self.receivers.forget();
            self.frame_gpu = None;
            self.adopted = 0;
            self.frame_gpu_failed = false;
        }
        if built {
            (self.cpu_lags, self.gpu_lags) = (false, false);
        }
        if std::mem::take(&mut self.moved) && !built {
            // Reposed on the CPU when the frame is not made on the GPU (below).
            (self.cpu_lags, self.gpu_lags) = (true, true);
        }
        let started = Instant::now();
        if set.highlights().is_empty() && sp.edits.iter().any(|e| e.anchor.is_some()) {
            if std::mem::take(&mut self.cpu_lags) {
                set.repose(&model.mesh, &options)?;
            }
            // A fresh sequence: find the highlights once so that anchored edits can be
            // matched to their ids. Updating again with the same light and eye matches
            // every highlight to itself (same ids, full opacity), now with the edits
            // applied.
            set.update(view.light_eye(), view.world_from_object);
        }
        apply_controls(set, preset, shape.layer, anchor_reach(&model.framing));
        // `auto`'s first frame times the whole frame on the GPU too.
        let whole_frame = match sp.search {
            SearchPreset::GpuFrame => true,
            SearchPreset::Auto => self.search.untimed() || self.search.chose_frame(),
            _ => false,
        };
        if whole_frame && !self.frame_gpu_failed {
            if self.frame_gpu.is_none() {
                match npr_specular::FrameOnGpu::new(device, set, &model.mesh.indices) {
                    Ok(mut made) => {
                        made.set_normal_maps(shape.pass.normal_map_layers());
                        made.start_from(queue, set, view.world_from_object);
                        self.frame_gpu = Some(made);
                        self.adopted = 0;
                        self.restart = false;
                        self.curvature = None;
                        self.pose_failed = false;
                        // Made from the set's geometry: the pose, if the set lags it.
                        self.gpu_lags = self.cpu_lags;
                    }
                    Err(npr_specular::SpecularError::Gpu(npr_gpu::GpuError::MeshTooLarge {
                        ..
                    })) => self.frame_gpu_failed = true,
                    Err(e) => return Err(e.into()),
                }
            }
            if let Some(on_gpu) = self
                .frame_gpu
                .as_mut()
                .filter(|_| !(sp.search == SearchPreset::Auto && self.search.untimed()))
            {
                let recording = Instant::now();
                if std::mem::take(&mut self.gpu_lags) {
                    // A new pose: its tables made on the GPU from its curvature there,
                    // else the set reposed on the CPU (the frame's objects take its
                    // tables).
                    if !on_gpu.poses_on_gpu()
                        && !self.pose_failed
                        && std::env::var("NO_GPU_POSE").is_err()
                    {
                        let curvature = npr_gpu::CurvaturePass::new(device);
                        let made = curvature
                            .create_object_with_reach(
                                device,
                                mesh,
                                &model.mesh,
                                options.radius,
                                npr_gpu::POSE_REACH,
                            )
                            .map_err(npr_specular::SpecularError::from)
                            .and_then(|object| {
                                on_gpu.pose_on_gpu(device, set, (&model.mesh, mesh), &object)?;
                                Ok(object)
                            });
                        match made {
                            Ok(object) => {
                                self.curvature = Some((curvature, object, FrameId::default()))
                            }
                            Err(_) => self.pose_failed = true,
                        }
                    }
                    match self.curvature.as_mut().filter(|_| on_gpu.poses_on_gpu()) {
                        Some((pass, object, at)) => {
                            stats.pose_on_gpu = true;
                            *at = at.next();
                            let input = npr_gpu::CurvatureInput { frame: *at };
                            let measured = pass.prepare(queue, object, &input)?;
                            pass.record(encoder, object, &measured)?;
                            on_gpu.record_pose(queue, encoder, frame)?;
                        }
                        None => {
                            if std::mem::take(&mut self.cpu_lags) {
                                set.repose(&model.mesh, &options)?;
                            }
                        }
                    }
                }
                if std::mem::take(&mut self.restart) {
                    on_gpu.start_from(queue, set, view.world_from_object);
                } else if on_gpu.frames_read() > self.adopted {
                    // A frame newly read back is the set's highlights: the panel and
                    // picking, one frame late.
                    self.adopted = on_gpu.frames_read();
                    if let Some(latest) = on_gpu.latest() {
                        set.adopt_gpu_frame(latest);
                    }
                }
                let frame_of = (view.light_eye(), view.world_from_object);
                let walked = on_gpu.record(queue, encoder, set, frame_of, frame)?;
                // Recording the pose's tables (if any) and the frame's work.
                stats.setup_us = recording.elapsed().as_secs_f64() * 1e6;
                stats.search_on_gpu = true;
                stats.regions_on_gpu = true;
                stats.receivers_on_gpu = true;
                stats.gpu_waits = 0;
                stats.highlights = set.highlights().len();
                stats.receiver_faces = 0;
                let input = highlight_input(frame, model, set, (uniforms, object));
                return Ok(shape.pass.prepare_with_gpu_projectors(
                    queue,
                    &mut shape.object,
                    &input,
                    (on_gpu.receivers(), &walked),
                    on_gpu.projectors(),
                )?);
            }
        }
        // A frame not made on the GPU: the next one that is starts again from the set.
        self.restart |= self.frame_gpu.is_some();
        if std::mem::take(&mut self.cpu_lags) {
            set.repose(&model.mesh, &options)?;
        }
        let walk_on_gpu = match sp.search {
            SearchPreset::Cpu => false,
            SearchPreset::Gpu | SearchPreset::GpuFrame => true,
            SearchPreset::Auto => self.search.chose_gpu(),
        } && self.receivers.ready(device, set, &model.mesh.indices)?;
        set.receivers_on_gpu = walk_on_gpu;
        stats.search_on_gpu = self.search.update(
            (device, queue),
            set,
            sp.search,
            (view.light_eye(), view.world_from_object),
            self.frame_gpu.as_mut(),
        )?;
        let gpu_faces = self.receivers.faces();
        let walked = if walk_on_gpu {
            self.receivers
                .record(queue, encoder, set, (frame, view.world_from_object))?
        } else {
            None
        };
        stats.setup_us = started.elapsed().as_secs_f64() * 1e6;
        let st = set.stats();
        stats.highlights = st.highlights;
        stats.receivers_on_gpu = walked.is_some();
        stats.regions_on_gpu = st.regions_on_gpu;
        stats.gpu_waits = self.search.waits();
        stats.receiver_faces = if walked.is_some() {
            gpu_faces
        } else {
            st.receiver_faces
        };
        let input = highlight_input(frame, model, set, (uniforms, object));
        Ok(match walked {
            Some((receivers, walked)) => shape.pass.prepare_with_receivers(
                queue,
                &mut shape.object,
                &input,
                receivers,
                &walked,
            )?,
            None => shape.pass.prepare(queue, &mut shape.object, &input)?,
        })
    }

    /// After the frame's submission: asks for the counts of its GPU walk (the panel's
    /// receiver count, one frame late).
    ///
    /// # Errors
    /// A readback that cannot be set up.
    pub(crate) fn after_submit(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(), AppError> {
        if let Some(on_gpu) = self.frame_gpu.as_mut() {
            on_gpu.read_after_submit(device, queue);
            // Lets the map complete between frames (never waits).
            #[cfg(not(target_arch = "wasm32"))]
            let _ = device.poll(wgpu::PollType::Poll);
        }
        self.receivers.after_submit(device, queue)
    }

    /// Draws the highlights prepared as `prepared`.
    ///
    /// # Errors
    /// A [`npr_gpu::PassError`] for a stale ticket.
    pub(crate) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        prepared: &Prepared,
    ) -> Result<(), AppError> {
        if let Some(shape) = self.shape.get() {
            shape.pass.draw(pass, &shape.object, prepared)?;
        }
        Ok(())
    }
}

/// The highlight draw's input for `model` and `set` this frame.
fn highlight_input<'a>(
    frame: FrameId,
    model: &'a Model,
    set: &'a HighlightSet,
    (uniforms, object): (&'a FrameUniforms, &'a ObjectUniforms),
) -> npr_specular::HighlightInput<'a> {
    npr_specular::HighlightInput {
        frame,
        indices: &model.mesh.indices,
        set,
        view: uniforms,
        object,
        list: None,
    }
}

impl ShapePass {
    /// The pass for a built-in shape name, or for a PNG (then an extra layer after the
    /// built-in ones, at 128 × 128).
    fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        shape: &str,
    ) -> Result<Self, AppError> {
        let formats = TargetFormats::default();
        let (pass, layer) = if let Some(builtin) = builtin_shape(shape) {
            let pass = HighlightPass::new(device, queue, formats, &Default::default())?;
            (pass, builtin.layer())
        } else {
            let size = 128;
            let mut layers = npr_specular::textures::builtin_set(size);
            let mut normal: Vec<bool> = HighlightShape::ALL
                .iter()
                .map(|s| s.is_normal_map())
                .collect();
            layers.push(npr_specular::textures::load_png(
                std::path::Path::new(shape),
                size,
            )?);
            normal.push(false);
            let layer = (layers.len() - 1) as u32;
            let pass = HighlightPass::with_textures(device, queue, formats, &layers, &normal)?;
            (pass, layer)
        };
        let object = pass.create_object(device, mesh);
        Ok(Self {
            pass,
            object,
            layer,
        })
    }
}
