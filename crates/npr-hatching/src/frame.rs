//! The whole hatching frame of Kim & Lee, "Real-time Image-space Hatching" (2008), §2:
//! variance shadow map → G-buffer (tone, θ) → hatching pass, and the Phong + VSM frame of
//! the same scene it is compared with. A convenience over [`ScenePasses`], [`GBuffer`] and
//! [`HatchPass`]; it records into the caller's encoder, except the helpers named
//! `render_*`, which submit and read back.

use crate::{
    GBuffer, HatchError, HatchObject, HatchParams, HatchPass, ScenePasses, ShadowLight,
    TonalArtMap, VsmSettings,
};
use npr_gpu::{Camera, GpuMesh, OffscreenTarget};

/// Shadow, G-buffer and hatching passes for one target size.
#[derive(Debug)]
pub struct HatchFrame {
    /// The shadow / G-buffer / Phong passes.
    pub scene: ScenePasses,
    /// The hatching pass.
    pub hatch: HatchPass,
    /// The G-buffer the scene is drawn into.
    pub gbuffer: GBuffer,
    hatch_group: wgpu::BindGroup,
}

impl HatchFrame {
    /// Passes for targets of `color_format` and `size` (width, height).
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`], [`HatchError::InvalidParams`].
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tam: &TonalArtMap,
        params: &HatchParams,
        vsm: VsmSettings,
        color_format: wgpu::TextureFormat,
        (width, height): (u32, u32),
    ) -> Result<Self, HatchError> {
        let scene = ScenePasses::new(device, color_format, vsm)?;
        let hatch = HatchPass::new(device, queue, tam, params, color_format)?;
        let gbuffer = GBuffer::new(device, width, height)?;
        let hatch_group = hatch.bind(device, &gbuffer);
        Ok(Self {
            scene,
            hatch,
            gbuffer,
            hatch_group,
        })
    }

    /// Switches the tonal art map (style) and rebinds the hatching pass.
    ///
    /// # Errors
    /// As [`HatchPass::set_tam`].
    pub fn set_tam(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tam: &TonalArtMap,
    ) -> Result<(), HatchError> {
        self.hatch.set_tam(device, queue, tam)?;
        self.hatch_group = self.hatch.bind(device, &self.gbuffer);
        Ok(())
    }

    /// Width × height of the G-buffer (and of the targets to draw into).
    pub fn size(&self) -> (u32, u32) {
        (self.gbuffer.width(), self.gbuffer.height())
    }

    /// Writes camera and light for the next recorded frame.
    pub fn set_view(&self, queue: &wgpu::Queue, camera: &Camera, light: &ShadowLight) {
        self.scene.set_frame(queue, camera, light, self.size());
    }

    /// Records the hatching frame: shadow map, G-buffer, hatching pass into `target`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        self.scene.record_shadow(encoder, objects);
        self.scene.record_gbuffer(encoder, &self.gbuffer, objects);
        self.record_hatching(encoder, target);
    }

    /// Records the frame's hatching pass alone, over the G-buffer recorded before it
    /// ([`HatchPass::record_scene`]: the background unshaded, one anchor outside the
    /// cross-fade).
    pub fn record_hatching(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        self.hatch.record_scene(
            encoder,
            target,
            &self.hatch_group,
            &self.gbuffer,
            self.scene.anchor_weight(),
        );
    }

    /// Records the comparison frame: the same shadow map, then Phong + VSM as colour.
    pub fn record_phong(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &OffscreenTarget,
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        self.scene.record_shadow(encoder, objects);
        self.scene.record_phong(
            encoder,
            &target.color_view,
            &target.depth_view,
            [1.0, 1.0, 1.0, 1.0],
            objects,
        );
    }

    /// Records, submits and reads back one hatched frame (for demos and tests).
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] or [`HatchError::Gpu`].
    pub fn render_hatched(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        objects: &[(&GpuMesh, &HatchObject)],
    ) -> Result<image::RgbaImage, HatchError> {
        let (w, h) = self.size();
        let target = OffscreenTarget::new(device, w, h)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.record(&mut encoder, &target.color_view, objects);
        queue.submit(Some(encoder.finish()));
        Ok(npr_gpu::readback_rgba(device, queue, &target.color)?)
    }

    /// Records, submits and reads back one Phong + VSM frame (for demos and tests).
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] or [`HatchError::Gpu`].
    pub fn render_phong(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        objects: &[(&GpuMesh, &HatchObject)],
    ) -> Result<image::RgbaImage, HatchError> {
        let (w, h) = self.size();
        let target = OffscreenTarget::new(device, w, h)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.record_phong(&mut encoder, &target, objects);
        queue.submit(Some(encoder.finish()));
        Ok(npr_gpu::readback_rgba(device, queue, &target.color)?)
    }
}
