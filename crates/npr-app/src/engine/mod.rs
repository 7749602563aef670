//! The renderer behind `npr render` and `npr view`: one model, one offscreen target, and
//! one small adapter per effect over the technique crates' passes. Each adapter keeps its
//! GPU state specialised by a hashable key made of the settings that state is built for
//! (a new curvature smoothing, a new highlight texture, shadows toggled, a new size), and
//! builds it again only when that key changes.
//!
//! - [`inputs`]: what a preset means for each pass (material, shading model, controls);
//! - `base`, `specular`, `hatching`, `outline`, `warp`: the adapters;
//! - `surface`: the per-model fields (stroke directions, mean curvature) kept once
//!   computed.

mod base;
mod hatching;
pub mod inputs;
mod outline;
mod specialized;
mod specular;
mod surface;
mod warp;

pub use inputs::{
    anchor_reach, apply_controls, builtin_shape, clear_color, frame_tuning,
    full_render_antialiasing, object_uniforms, resolve_edit_ids, shading_model,
};
pub(crate) use surface::stroke_directions;
pub use warp::{MIN_PROXY_TRIANGLES, warp_view};
#[cfg(not(target_arch = "wasm32"))]
pub use warp::{render_clip_warp_frames, render_warp_frames};

use crate::AppError;
use crate::model::Model;
use crate::preset::{DirectionPreset, Effect, Preset};
use crate::view::View;
use base::{BaseEffect, BaseKey};
use glam::Vec3;
use hatching::HatchingEffect;
use npr_gpu::{BaseInput, FrameId, FrameUniforms, GpuMesh, OffscreenTarget, TargetFormats};
use npr_specular::HighlightSet;
use outline::OutlineEffect;
use serde::Serialize;
use specialized::Specialized;
use specular::SpecularEffect;
use surface::SurfaceFields;
use warp::WarpEffect;

/// Statistics of one rendered frame (`npr render --json`, the viewer's heads-up line).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameStats {
    /// Frame index in its sequence.
    pub frame: usize,
    /// The effect drawn.
    pub effect: String,
    /// CPU setup the frame waited on (N = H search, matching, BFS; warp: none), µs.
    pub setup_us: f64,
    /// The highlight backend that ran and why (specular; `[specular] backend`), as
    /// `npr_specular::BackendChoice` writes it: `"cpu (software adapter llvmpipe ...)"`.
    pub backend: Option<String>,
    /// Whether the model's pose was taken on the GPU (specular, the GPU backend on an
    /// animated model): its curvature and the highlights' tables made there from the
    /// posed vertices, the CPU's set left on an earlier pose.
    pub pose_on_gpu: bool,
    /// Highlights drawn (specular).
    pub highlights: usize,
    /// Receiver faces of all highlights (specular).
    pub receiver_faces: usize,
    /// Triangles drawn (the proxy's for a warped frame).
    pub triangles: usize,
    /// Whether the frame was warped from references rather than rendered in full.
    pub warped: bool,
    /// Warp: PSNR of this frame against a full render of the same view, dB.
    pub psnr_db: Option<f64>,
}

/// One model's renderer (see the module docs).
pub struct Renderer {
    model: Model,
    gpu_mesh: GpuMesh,
    target: OffscreenTarget,
    /// The base shading of full frames, keyed by its cel ramp.
    base: Specialized<BaseKey, BaseEffect>,
    /// The id of the last submission (each frame, reference or warp is one).
    submission: FrameId,
    specular: SpecularEffect,
    hatching: HatchingEffect,
    outline: OutlineEffect,
    warp: WarpEffect,
    fields: SurfaceFields,
    frame_index: usize,
    /// The posing pass and the rig's object, once a pose was set on the GPU.
    posing: Option<(npr_gpu::PosingPass, npr_gpu::PosedObject, FrameId)>,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("model", &self.model.name)
            .field("size", &(self.target.width, self.target.height))
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// Uploads `model` and creates a `width × height` target on `ctx` (whose adapter the
    /// highlight backend's rule reads, `npr_specular::Backend::choose`).
    ///
    /// # Errors
    /// [`AppError::Gpu`] for a size or mesh past the device's limits.
    pub fn new(
        ctx: &npr_gpu::GpuContext,
        model: Model,
        size: (u32, u32),
    ) -> Result<Self, AppError> {
        let device = &ctx.device;
        let gpu_mesh = GpuMesh::upload(device, &model.mesh)?;
        let target = OffscreenTarget::new(device, size.0, size.1)?;
        let mut specular = SpecularEffect::default();
        specular.set_adapter(ctx.adapter.get_info());
        Ok(Self {
            model,
            gpu_mesh,
            target,
            base: Specialized::default(),
            submission: FrameId::default(),
            specular,
            hatching: HatchingEffect::default(),
            outline: OutlineEffect::default(),
            warp: WarpEffect::default(),
            fields: SurfaceFields::default(),
            frame_index: 0,
            posing: None,
        })
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The model on the GPU.
    pub fn gpu_mesh(&self) -> &GpuMesh {
        &self.gpu_mesh
    }

    /// The target the last frame was drawn into.
    pub fn target(&self) -> &OffscreenTarget {
        &self.target
    }

    /// Target size.
    pub fn size(&self) -> (u32, u32) {
        (self.target.width, self.target.height)
    }

    /// Replaces the model; the current one stays if the upload fails.
    ///
    /// # Errors
    /// As [`GpuMesh::upload`].
    pub fn set_model(&mut self, device: &wgpu::Device, model: Model) -> Result<(), AppError> {
        let gpu_mesh = GpuMesh::upload(device, &model.mesh)?;
        self.model = model;
        self.gpu_mesh = gpu_mesh;
        self.base.clear();
        self.specular.clear();
        self.hatching.clear();
        self.outline.clear();
        self.warp.clear();
        self.fields = SurfaceFields::default();
        self.frame_index = 0;
        self.posing = None;
        Ok(())
    }

    /// Moves the model to a new pose: `model` is the same mesh (same vertex count and
    /// triangles) with moved vertices, a frame of a skinned or morphing clip. Its vertices
    /// are written into the uploaded buffers in place, so the passes' pipelines and
    /// objects stay; what depends on the surface is taken again on the posed mesh on the
    /// next frame: the stroke directions, the curvature, and the highlight set, reposed so
    /// that its highlights keep their ids, fades and the user's edits
    /// (`npr_specular::HighlightSet::repose`). Another mesh is [`Renderer::set_model`].
    ///
    /// # Errors
    /// [`AppError::Gpu`] when `model` is not a pose of the current mesh (then nothing
    /// changes).
    pub fn set_pose(&mut self, queue: &wgpu::Queue, model: Model) -> Result<(), AppError> {
        self.check_pose(&model)?;
        self.gpu_mesh.write_vertices(queue, &model.mesh)?;
        self.took_pose(model);
        Ok(())
    }

    /// [`Renderer::set_pose`] with the vertices the passes draw posed on the GPU
    /// (`npr_gpu::PosingPass`, recorded and submitted here) from `gpu`, the same pose as
    /// `model` ([`crate::animation::Animated::gpu_pose_at`]); `model` still gives the
    /// surface's geometry. `directions`, when given, are the pose's stroke directions of
    /// that preset ([`Renderer::set_pose_with_directions`]).
    ///
    /// # Errors
    /// As [`Renderer::set_pose`]; [`AppError::Gpu`] when the rig does not fit the mesh.
    pub fn set_pose_on_gpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        model: Model,
        gpu: &crate::animation::GpuPose<'_>,
        directions: Option<(DirectionPreset, Vec<Vec3>)>,
    ) -> Result<(), AppError> {
        self.check_pose(&model)?;
        if let Some((_, d)) = &directions {
            check_directions(d, &model)?;
        }
        if self.posing.is_none() {
            let pass = npr_gpu::PosingPass::new(device);
            let object = pass.create_object(device, &self.gpu_mesh, gpu.rig, Some(gpu.order))?;
            self.posing = Some((pass, object, FrameId::default()));
        }
        if let Some((pass, object, frame)) = self.posing.as_mut() {
            *frame = frame.next();
            let input = npr_gpu::PoseInput {
                frame: *frame,
                pose: &gpu.pose,
            };
            let prepared = pass.prepare(queue, object, &input)?;
            let mut encoder = device.create_command_encoder(&Default::default());
            pass.record(&mut encoder, object, &prepared)?;
            queue.submit([encoder.finish()]);
        }
        self.took_pose(model);
        if let Some((which, d)) = directions {
            self.fields.seed_directions(which, d);
        }
        Ok(())
    }

    fn check_pose(&self, model: &Model) -> Result<(), AppError> {
        if model.mesh.indices != self.model.mesh.indices {
            return Err(AppError::Gpu(npr_gpu::GpuError::InvalidMesh(format!(
                "a pose of {} triangles is not a pose of this mesh of {}",
                model.mesh.triangle_count(),
                self.model.mesh.triangle_count()
            ))));
        }
        Ok(())
    }

    /// What follows a new pose, however its vertices were written.
    fn took_pose(&mut self, model: Model) {
        self.model = model;
        self.specular.repose();
        self.hatching.repose();
        self.warp.repose();
        self.fields = SurfaceFields::default();
    }

    /// [`Renderer::set_pose`] with the stroke directions of `which` for the pose given
    /// rather than computed on it (carried through the skinning from the rest pose,
    /// `crate::animation::Animated::carried_directions`), one per vertex of `model`.
    ///
    /// # Errors
    /// As [`Renderer::set_pose`], or [`AppError::Usage`] for a direction count that is
    /// not the vertex count.
    pub fn set_pose_with_directions(
        &mut self,
        queue: &wgpu::Queue,
        model: Model,
        (which, directions): (DirectionPreset, Vec<Vec3>),
    ) -> Result<(), AppError> {
        check_directions(&directions, &model)?;
        self.set_pose(queue, model)?;
        self.fields.seed_directions(which, directions);
        Ok(())
    }

    /// Resizes the target (a zero side is refused with a typed error; the old target
    /// stays).
    ///
    /// # Errors
    /// [`AppError::Gpu`] for an invalid size.
    pub fn resize(&mut self, device: &wgpu::Device, size: (u32, u32)) -> Result<(), AppError> {
        if size != self.size() {
            self.target = OffscreenTarget::new(device, size.0, size.1)?;
        }
        Ok(())
    }

    /// The highlight set, once a specular frame has been drawn.
    pub fn highlight_set(&self) -> Option<&HighlightSet> {
        self.specular.set()
    }

    /// Forgets highlight tracking (the next frame starts a new sequence).
    pub fn reset_sequence(&mut self) {
        self.specular.reset();
        self.frame_index = 0;
    }

    /// Signed mean curvature `(κ_max + κ_min) / 2` per render vertex, times the bounding
    /// radius (so a sphere reads 1 at any scale); 0 where undefined. Computed once per
    /// model.
    pub fn mean_curvature(&mut self) -> &[f32] {
        self.fields
            .mean_curvature(&self.model.mesh, self.model.framing.radius)
    }

    /// The mean curvature of [`Renderer::mean_curvature`], if computed already.
    pub fn cached_mean_curvature(&self) -> Option<&[f32]> {
        self.fields.cached_mean_curvature()
    }

    /// The hatching G-buffer of the last hatched frame (tone and stroke angle per pixel),
    /// read back (submits and waits).
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails.
    pub fn hatch_inputs(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<npr_hatching::HatchInputs>, AppError> {
        self.hatching.read_inputs(device, queue)
    }

    /// Which pixels the model covers in the last hatched frame, read back (submits and
    /// waits); `None` before a hatched frame.
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails.
    pub fn hatch_coverage(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<Vec<bool>>, AppError> {
        self.hatching.read_mask(device, queue)
    }

    /// The last hatched frame traced for a pen plotter (see `npr_hatching::pen`): its
    /// strokes and the model's visible outlines at `view`, with a pen `pen_px` wide and
    /// strokes of at least 1 mm at `mm_per_px`. `None` before a hatched frame. Submits and
    /// waits (native); the browser uses [`Renderer::start_pen_readback`] and
    /// [`Renderer::pen_drawing_from`].
    ///
    /// # Errors
    /// [`AppError::Hatching`] when readback fails or the settings are out of range.
    pub fn pen_drawing(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
        pen: (f32, f32),
    ) -> Result<Option<npr_hatching::pen::PenDrawing>, AppError> {
        let Some(readback) = self.start_pen_readback(device, queue)? else {
            return Ok(None);
        };
        let contents = readback.wait(device)?;
        self.pen_drawing_from(&contents, preset, view, pen)
            .map(Some)
    }

    /// Starts reading back what the pen plotter traces from, for the last hatched frame:
    /// poll the readback ([`npr_hatching::GBufferReadback::try_take`]) from frame to frame
    /// and hand its contents to [`Renderer::pen_drawing_from`]. `None` before a hatched
    /// frame.
    ///
    /// # Errors
    /// [`AppError::Hatching`] when a copy cannot be set up.
    pub fn start_pen_readback(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Option<npr_hatching::GBufferReadback>, AppError> {
        self.hatching.start_pen_read(device, queue)
    }

    /// Traces `contents` (a hatched frame read back at `view`) for a pen plotter: the
    /// strokes and this model's visible outlines, with a pen `pen_px` wide and strokes of
    /// at least 1 mm at `mm_per_px`.
    ///
    /// # Errors
    /// [`AppError::Hatching`] when the settings are out of range or the contents do not
    /// fit the view.
    pub fn pen_drawing_from(
        &self,
        contents: &npr_hatching::GBufferContents,
        preset: &Preset,
        view: &View,
        (pen_px, mm_per_px): (f32, f32),
    ) -> Result<npr_hatching::pen::PenDrawing, AppError> {
        let outline = npr_hatching::pen::OutlineView {
            camera: &view.camera,
            world_from_object: view.world_from_object,
            size: (contents.inputs.width(), contents.inputs.height()),
            depth: &contents.depth,
            crease_deg: preset.outline.crease_deg,
        };
        let settings = npr_hatching::pen::PenSettings::for_pen(pen_px, mm_per_px);
        Ok(npr_hatching::pen::trace(
            &contents.inputs,
            &contents.mask,
            Some((&self.model.mesh, &outline)),
            &settings,
        )?)
    }

    /// The per-vertex stroke directions of `which`, if computed already (see
    /// [`Renderer::directions`]).
    pub fn cached_directions(&self, which: DirectionPreset) -> Option<&[Vec3]> {
        self.fields.cached_directions(which)
    }

    /// The per-vertex stroke directions of `which` (computed once per model).
    pub fn directions(&mut self, which: DirectionPreset) -> &[Vec3] {
        self.fields.directions(&self.model.mesh, which)
    }

    /// Renders one frame of `preset` seen from `view` into the target and submits it. The
    /// warp effect's full render is multisampled as its `[warp] antialiasing` says (see
    /// [`full_render_antialiasing`]), resolved into the target.
    ///
    /// # Errors
    /// A technique's typed error (bad texture, bad parameters, ...).
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
    ) -> Result<FrameStats, AppError> {
        let mut stats = FrameStats {
            frame: self.frame_index,
            effect: preset.effect.name().to_string(),
            triangles: self.model.mesh.triangle_count(),
            ..FrameStats::default()
        };
        let clock = self.frame_index as u64;
        self.frame_index += 1;
        let submission = self.next_submission();
        let object = object_uniforms(preset, view.world_from_object);
        let frame = FrameUniforms::new(&view.camera, &view.light);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app frame"),
        });
        let base_input = BaseInput {
            frame: submission,
            view: &frame,
            object: &object,
            model: shading_model(preset),
        };
        let size = self.size();
        let gpu = (device, queue);
        match preset.effect {
            Effect::HatchingPen | Effect::HatchingPencil => {
                self.hatching.record(
                    gpu,
                    (&self.model, &self.gpu_mesh, &mut self.fields),
                    preset,
                    view,
                    (submission, clock, &object),
                    &mut encoder,
                    (&self.target.color_view, size),
                )?;
            }
            Effect::Warp if full_render_antialiasing(preset).is_multisampled() => {
                let m = self.warp.full_msaa(gpu, &self.gpu_mesh, preset, size)?;
                let prepared = m
                    .base
                    .pass
                    .prepare(queue, &mut m.base.object, &base_input)?;
                let mut pass = m.target.begin_pass(
                    &mut encoder,
                    &self.target.color_view,
                    Some(clear_color(preset)),
                );
                m.base.pass.draw(&mut pass, &m.base.object, &prepared)?;
            }
            effect => {
                let key = BaseKey {
                    formats: TargetFormats::default(),
                    cel_bands: preset.base.cel_bands.clone(),
                };
                let mesh = &self.gpu_mesh;
                let base = self.base.get_or_build(&key, |key| -> Result<_, AppError> {
                    Ok(BaseEffect::new(device, queue, mesh, key))
                })?;
                let base_prepared = base.pass.prepare(queue, &mut base.object, &base_input)?;
                let highlights = if effect == Effect::Specular {
                    Some(self.specular.prepare(
                        gpu,
                        &mut encoder,
                        (&self.model, &self.gpu_mesh),
                        preset,
                        view,
                        (submission, &frame, &object),
                        &mut stats,
                    )?)
                } else {
                    None
                };
                let mut pass = self
                    .target
                    .begin_clear_pass(&mut encoder, clear_color(preset));
                if let Some(base) = self.base.get() {
                    base.pass.draw(&mut pass, &base.object, &base_prepared)?;
                }
                if let Some(prepared) = &highlights {
                    self.specular.draw(&mut pass, prepared)?;
                }
            }
        }
        self.record_outline(device, queue, &mut encoder, preset, view, submission)?;
        queue.submit(Some(encoder.finish()));
        if preset.effect == Effect::Specular {
            self.specular.after_submit(device, queue);
        }
        Ok(stats)
    }

    /// The id of the next submission.
    fn next_submission(&mut self) -> FrameId {
        self.submission = self.submission.next();
        self.submission
    }

    /// Records the outlines over the target when the preset has them on.
    fn record_outline(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        preset: &Preset,
        view: &View,
        frame: FrameId,
    ) -> Result<(), AppError> {
        if !preset.outline.enabled {
            return Ok(());
        }
        let size = self.size();
        self.outline.record(
            (device, queue),
            &self.gpu_mesh,
            encoder,
            (&self.target.color_view, size),
            preset,
            view,
            frame,
        )
    }

    /// Reads the target back as an sRGB image (waits for the GPU).
    ///
    /// # Errors
    /// [`AppError::Gpu`] when readback fails.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<image::RgbaImage, AppError> {
        Ok(npr_gpu::readback_rgba(device, queue, &self.target.color)?)
    }
}

/// [`AppError::Usage`] unless there is one stroke direction per vertex of `model`.
fn check_directions(directions: &[Vec3], model: &Model) -> Result<(), AppError> {
    if directions.len() != model.mesh.positions.len() {
        return Err(AppError::Usage(format!(
            "{} stroke directions for a pose of {} vertices",
            directions.len(),
            model.mesh.positions.len()
        )));
    }
    Ok(())
}
