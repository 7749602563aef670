//! Post-rendering 3D warping (Park & Ihm) in the engine: the proxy's warper and the base
//! pass drawing its references, specialised by the warp settings and the target, and the
//! multisampled full render that warped frames are measured against.

use super::base::{BaseEffect, BaseKey, grey_shades};
use super::inputs::{clear_color, full_render_antialiasing, object_uniforms};
use super::specialized::Specialized;
use super::{FrameStats, Renderer};
use crate::AppError;
use crate::model::Model;
use crate::preset::{Preset, WarpAntialiasing, WarpMode};
use crate::view::View;
use npr_gpu::{GpuMesh, ShadingModel, TargetFormats};

/// The fewest proxy triangles warping uses (see [`Renderer::warp_reference`]).
pub const MIN_PROXY_TRIANGLES: usize = 256;

/// What the warper and its reference pass are built for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct WarpKey {
    /// `[warp] proxy_ratio`, as bits.
    proxy_ratio: u32,
    mode: WarpMode,
    depth_test: bool,
    antialiasing: WarpAntialiasing,
    size: (u32, u32),
    model: ShadingModel,
    cel_bands: Vec<u8>,
}

impl WarpKey {
    fn of(preset: &Preset, size: (u32, u32)) -> Self {
        let w = &preset.warp;
        Self {
            proxy_ratio: w.proxy_ratio.to_bits(),
            mode: w.mode,
            depth_test: w.depth_test,
            antialiasing: w.antialiasing,
            size,
            model: preset.base.model.into(),
            cel_bands: preset.base.cel_bands.clone(),
        }
    }
}

/// The warper, the base pass of its references, and the proxy's size.
pub(crate) struct WarpState {
    warper: npr_warp::Warper,
    base: npr_warp::PhongBase,
    proxy_triangles: usize,
    /// The proxy as simplified (its source map poses it with the model).
    proxy: npr_warp::Proxy,
    /// The [`WarpEffect::poses`] count its proxy is posed at (`None`: as simplified).
    posed_at: Option<u64>,
}

/// The warping state (see the module docs).
#[derive(Default)]
pub(crate) struct WarpEffect {
    state: Specialized<WarpKey, WarpState>,
    /// The multisampled full render.
    full_msaa: Specialized<FullMsaaKey, FullMsaa>,
    /// Poses the renderer has taken ([`WarpEffect::repose`]); 0 for a rigid model.
    poses: u64,
}

/// What the multisampled full render is built for: its base shading (formats with the
/// sample count, the cel ramp) and the target size.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct FullMsaaKey {
    base: BaseKey,
    size: (u32, u32),
}

/// The multisampled full render of the warp effect: the base shading built for the sample
/// count and the multisampled textures it draws into, resolved into the renderer's target.
pub(crate) struct FullMsaa {
    pub base: BaseEffect,
    pub target: npr_warp::MsaaTarget,
}

impl WarpEffect {
    /// Drops everything (a new model).
    pub(crate) fn clear(&mut self) {
        self.state.clear();
        self.full_msaa.clear();
        self.poses = 0;
    }

    /// The model took a new pose: the proxy follows it before the next reference or warp,
    /// and the references keep the poses they were rendered at.
    pub(crate) fn repose(&mut self) {
        self.poses += 1;
    }

    /// The multisampled full render for `preset` at `size`, built or kept.
    ///
    /// # Errors
    /// A size past the device's limits.
    pub(crate) fn full_msaa(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        mesh: &GpuMesh,
        preset: &Preset,
        size: (u32, u32),
    ) -> Result<&mut FullMsaa, AppError> {
        let key = FullMsaaKey {
            base: BaseKey {
                formats: full_render_antialiasing(preset).references(TargetFormats::default()),
                cel_bands: preset.base.cel_bands.clone(),
            },
            size,
        };
        self.full_msaa
            .get_or_build(&key, |key| -> Result<_, AppError> {
                let (w, h) = key.size;
                let target = npr_warp::MsaaTarget::new(device, w, h, key.base.formats)?;
                let base = BaseEffect::new(device, queue, mesh, &key.base);
                Ok(FullMsaa { base, target })
            })
    }

    /// The warper for `preset` at `size`, built or kept.
    fn state(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        (model, mesh): (&Model, &GpuMesh),
        preset: &Preset,
        view: &View,
        size: (u32, u32),
    ) -> Result<&mut WarpState, AppError> {
        let poses = self.poses;
        let state = self.state.get_or_build(&WarpKey::of(preset, size), |key| {
            WarpState::new((device, queue), (model, mesh), preset, view, key)
        })?;
        // A model that has moved: the proxy takes the model's current pose (ours; the
        // paper's proxy is rigid).
        if poses > 0 && state.posed_at != Some(poses) {
            let posed = state.proxy.posed(&model.mesh)?;
            state.warper.set_proxy_pose(queue, &posed)?;
            state.posed_at = Some(poses);
        }
        Ok(state)
    }
}

impl WarpState {
    fn new(
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        (model, mesh): (&Model, &GpuMesh),
        preset: &Preset,
        view: &View,
        key: &WarpKey,
    ) -> Result<Self, AppError> {
        let w = &preset.warp;
        // A proxy needs some triangles to carry the references: keep at least
        // MIN_PROXY_TRIANGLES (all of a smaller mesh) whatever the ratio.
        let tris = model.mesh.triangle_count().max(1);
        let ratio = w
            .proxy_ratio
            .max((MIN_PROXY_TRIANGLES as f32 / tris as f32).min(1.0));
        let proxy = npr_warp::Proxy::simplify(&model.mesh, ratio)?;
        let antialiasing = npr_warp::Antialiasing::from(key.antialiasing);
        let references = antialiasing.references(TargetFormats::default());
        let warper = npr_warp::Warper::new(
            device,
            queue,
            &proxy,
            w.departures(),
            1.0 / model.framing.radius,
            key.size,
            (
                references,
                antialiasing.warp_target(TargetFormats::default()),
            ),
        )?;
        let base = npr_warp::PhongBase::new(
            mesh,
            view.light,
            object_uniforms(preset, view.world_from_object),
            references,
        )
        .with_model(
            key.model,
            Some(npr_gpu::toon_ramp(256, &grey_shades(&key.cel_bands))),
        );
        Ok(Self {
            warper,
            base,
            proxy_triangles: proxy.mesh.triangle_count(),
            proxy,
            posed_at: None,
        })
    }
}

impl Renderer {
    /// Warping (Park & Ihm): records a reference of the full model at `view` (its base
    /// shading per the preset) and submits it. From then on warps interpolate between the
    /// previous newest reference (s = 0) and this one (s = 1).
    ///
    /// # Errors
    /// [`AppError::Warp`] for a proxy or setting the warp cannot use.
    pub fn warp_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
    ) -> Result<(), AppError> {
        let size = self.size();
        let frame = self.next_submission();
        let w = self.warp.state(
            (device, queue),
            (&self.model, &self.gpu_mesh),
            preset,
            view,
            size,
        )?;
        w.base
            .set_lighting(view.light, object_uniforms(preset, view.world_from_object));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app warp reference"),
        });
        let object_view = warp_view(view);
        w.warper.record_reference(
            device,
            queue,
            &mut encoder,
            &mut w.base,
            frame,
            &object_view,
        )?;
        queue.submit(Some(encoder.finish()));
        Ok(())
    }

    /// References recorded so far.
    pub fn warp_references(&self) -> u64 {
        self.warp
            .state
            .get()
            .map_or(0, |w| w.warper.references_recorded())
    }

    /// Warping (Park & Ihm): draws the proxy textured by the two newest references at
    /// `view`, at position `s` between them (`None`: estimated from the eye, as for an
    /// unknown path), over the preset's background, into the target, and submits it.
    ///
    /// # Errors
    /// As [`Renderer::warp_reference`].
    pub fn warp_frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        preset: &Preset,
        view: &View,
        s: Option<f32>,
    ) -> Result<FrameStats, AppError> {
        let size = self.size();
        let mut stats = FrameStats {
            frame: self.frame_index,
            effect: preset.effect.name().to_string(),
            warped: true,
            ..FrameStats::default()
        };
        self.frame_index += 1;
        let submission = self.next_submission();
        let w = self.warp.state(
            (device, queue),
            (&self.model, &self.gpu_mesh),
            preset,
            view,
            size,
        )?;
        stats.triangles = w.proxy_triangles;
        let object_view = warp_view(view);
        let s = s.unwrap_or_else(|| w.warper.position(&object_view));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr app warp"),
        });
        if w.warper.antialiasing().warp_is_multisampled() {
            // The warper's own multisampled pass, resolved into the target.
            let (color, depth) = (&self.target.color_view, &self.target.depth_view);
            w.warper.clear = clear_color(preset);
            w.warper.record_warp(
                queue,
                &mut encoder,
                (color, depth),
                submission,
                &object_view,
                s,
            )?;
        } else {
            let prepared = w.warper.prepare(queue, submission, &object_view, s)?;
            let mut pass = self
                .target
                .begin_clear_pass(&mut encoder, clear_color(preset));
            if let Some(prepared) = &prepared {
                w.warper.draw(&mut pass, prepared)?;
            }
        }
        self.record_outline(device, queue, &mut encoder, preset, view, submission)?;
        queue.submit(Some(encoder.finish()));
        Ok(stats)
    }
}

/// Renders `frames` turntable frames with warping (Park & Ihm): along the known path, a
/// reference every `k` frames (rendered one interval ahead), the frames between warped
/// from the two around them at the path's own fraction, and each warped frame compared
/// with a full render of the same view (PSNR in the stats). Reference frames are the full
/// render itself. Full renders use the warp's antialiasing (see
/// [`full_render_antialiasing`]), so with `msaa4` or `msaa4-blend` every frame of the
/// turntable is antialiased and the PSNR is against the multisampled full render.
///
/// # Errors
/// GPU or technique errors, or what `sink` returns.
// Batch only (a progress bar): native only.
#[cfg(not(target_arch = "wasm32"))]
pub fn render_warp_frames(
    ctx: &npr_gpu::GpuContext,
    model: Model,
    preset: &Preset,
    frames: u32,
    sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let framing = model.framing;
    let renderer = Renderer::new(ctx, model, size)?;
    let frames_of = WarpFrames {
        framing,
        frames,
        turntable: true,
    };
    warp_frames(ctx, renderer, preset, frames_of, |_, _| Ok(()), sink)
}

/// [`render_warp_frames`] of a model playing its clip (`frames` frames at the playback's
/// rate; with `turntable`, during one camera turn, else with the camera still). The full
/// mesh is posed at each reference's moment before the reference is rendered and at each
/// frame's before it is warped; the proxy follows the same pose (ours, see
/// `npr_warp::deform`).
///
/// # Errors
/// As [`render_warp_frames`].
#[cfg(not(target_arch = "wasm32"))]
pub fn render_clip_warp_frames(
    ctx: &npr_gpu::GpuContext,
    animated: &crate::animation::Animated,
    preset: &Preset,
    (frames, turntable): (u32, bool),
    sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let renderer = Renderer::new(ctx, animated.frame(0), size)?;
    let frames_of = WarpFrames {
        framing: animated.framing(),
        frames,
        turntable,
    };
    let pose = |renderer: &mut Renderer, i: usize| {
        crate::animation::set_pose_at(
            renderer,
            (&ctx.device, &ctx.queue),
            animated,
            animated.time_of(i),
            preset,
            None,
        )
    };
    warp_frames(ctx, renderer, preset, frames_of, pose, sink)
}

/// The path of a warped sequence: its framing, frame count and whether the camera turns.
#[cfg(not(target_arch = "wasm32"))]
struct WarpFrames {
    framing: crate::view::Framing,
    frames: u32,
    turntable: bool,
}

/// The loop of [`render_warp_frames`], with `pose` setting the model's pose of frame `i`
/// (nothing for a rigid model) before each reference, full render and warp.
#[cfg(not(target_arch = "wasm32"))]
fn warp_frames(
    ctx: &npr_gpu::GpuContext,
    mut renderer: Renderer,
    preset: &Preset,
    path: WarpFrames,
    mut pose: impl FnMut(&mut Renderer, usize) -> Result<(), AppError>,
    mut sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let WarpFrames {
        framing,
        frames,
        turntable,
    } = path;
    let k = preset.warp.k.max(1) as usize;
    let view_at = |i: usize| {
        let turn = if turntable {
            360.0 * i as f32 / frames.max(1) as f32
        } else {
            0.0
        };
        View::new(preset, &framing, size, turn)
    };
    let bar = crate::progress::bar(u64::from(frames), "warp");
    let mut stats = Vec::new();
    for i in 0..frames as usize {
        let view = view_at(i);
        if i % k == 0 {
            if i == 0 {
                pose(&mut renderer, 0)?;
                renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view)?;
            }
            pose(&mut renderer, i + k)?;
            renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view_at(i + k))?;
        }
        pose(&mut renderer, i)?;
        let full_stats = renderer.render(&ctx.device, &ctx.queue, preset, &view)?;
        let full = renderer.read(&ctx.device, &ctx.queue)?;
        if i % k == 0 {
            sink(i, full, &full_stats)?;
            stats.push(FrameStats {
                frame: i,
                ..full_stats
            });
        } else {
            let s = (i % k) as f32 / k as f32;
            let mut st = renderer.warp_frame(&ctx.device, &ctx.queue, preset, &view, Some(s))?;
            let warped = renderer.read(&ctx.device, &ctx.queue)?;
            st.frame = i;
            st.psnr_db = Some(npr_warp::metrics::compare(&full, &warped).psnr_db);
            sink(i, warped, &st)?;
            stats.push(st);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// The warp's object view of a view.
pub fn warp_view(view: &View) -> npr_warp::ObjectView {
    npr_warp::ObjectView {
        camera: view.camera,
        world_from_object: view.world_from_object,
    }
}
