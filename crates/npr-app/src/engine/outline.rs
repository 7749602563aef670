//! Outlines in the engine (`npr_gpu::outline`): the normal + depth prepass and the
//! full-screen line pass over the frame, specialised by the target size.

use super::specialized::Specialized;
use crate::AppError;
use crate::preset::Preset;
use crate::view::View;
use npr_gpu::outline::{
    NormalDepthInput, NormalDepthPass, NormalDepthTarget, OutlineInput, OutlineObject, OutlinePass,
    OutlineSource,
};
use npr_gpu::{FrameId, GpuMesh, TargetFormats};

/// The prepass, its target and object, and the line pass reading that target.
struct OutlineState {
    target: NormalDepthTarget,
    prepass: NormalDepthPass,
    object: OutlineObject,
    pass: OutlinePass,
    source: OutlineSource,
}

/// The outline effect (see the module docs), keyed by the target size.
#[derive(Default)]
pub(crate) struct OutlineEffect {
    state: Specialized<(u32, u32), OutlineState>,
}

impl OutlineEffect {
    /// Drops everything (a new model).
    pub(crate) fn clear(&mut self) {
        self.state.clear();
    }

    /// Records the prepass and the lines over `color` (loaded, not cleared).
    ///
    /// # Errors
    /// A target size past the device's limits, or a stale ticket.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        mesh: &GpuMesh,
        encoder: &mut wgpu::CommandEncoder,
        (color, size): (&wgpu::TextureView, (u32, u32)),
        preset: &Preset,
        view: &View,
        frame: FrameId,
    ) -> Result<(), AppError> {
        let o = self
            .state
            .get_or_build(&size, |&(w, h)| -> Result<_, AppError> {
                let prepass = NormalDepthPass::new(device, queue);
                let object = prepass.create_object(device, mesh);
                let target = NormalDepthTarget::new(device, w, h)?;
                let pass = OutlinePass::new(device, queue, TargetFormats::default());
                let source = pass.create_object(device, &target);
                Ok(OutlineState {
                    target,
                    prepass,
                    object,
                    pass,
                    source,
                })
            })?;
        let input = NormalDepthInput {
            frame,
            camera: &view.camera,
            world_from_object: view.world_from_object,
        };
        let prepared = o.prepass.prepare(queue, &mut o.object, &input)?;
        let settings = preset.outline.settings();
        let input = OutlineInput {
            frame,
            settings: &settings,
        };
        let lines = o.pass.prepare(queue, &mut o.source, &input)?;
        o.prepass
            .record(encoder, &o.target, &[(&o.object, &prepared)])?;
        let mut pass = npr_gpu::render::begin_color_pass(
            encoder,
            "npr app outline",
            color,
            wgpu::LoadOp::Load,
        );
        o.pass.draw(&mut pass, &o.source, &lines)?;
        Ok(())
    }
}
