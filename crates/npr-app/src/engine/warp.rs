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
}

/// The warping state (see the module docs).
#[derive(Default)]
pub(crate) struct WarpEffect {
    state: Specialized<WarpKey, WarpState>,
    /// The multisampled full render.
    full_msaa: Specialized<FullMsaaKey, FullMsaa>,
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
        self.state.get_or_build(&WarpKey::of(preset, size), |key| {
            WarpState::new((device, queue), (model, mesh), preset, view, key)
        })
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
    mut sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let framing = model.framing;
    let k = preset.warp.k.max(1) as usize;
    let view_at = |i: usize| {
        View::new(
            preset,
            &framing,
            size,
            360.0 * i as f32 / frames.max(1) as f32,
        )
    };
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, model, size)?;
    let bar = crate::progress::bar(u64::from(frames), "warp");
    let mut stats = Vec::new();
    for i in 0..frames as usize {
        let view = view_at(i);
        if i % k == 0 {
            if i == 0 {
                renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view)?;
            }
            renderer.warp_reference(&ctx.device, &ctx.queue, preset, &view_at(i + k))?;
        }
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
