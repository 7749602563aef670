//! The whole hatching frame of Kim & Lee, "Real-time Image-space Hatching" (2008), §2:
//! variance shadow map → G-buffer (tone, θ) → hatching pass, and the Phong + VSM frame of
//! the same scene it is compared with. A convenience over [`ScenePasses`], [`GBuffer`] and
//! [`HatchPass`] on the pass contract ([`npr_gpu::pass`]): [`HatchFrame::prepare`] writes
//! a frame's data, the `record_*` functions record into the caller's encoder; only the
//! helpers named `render_*` submit and read back.

use crate::{
    GBuffer, HatchError, HatchInput, HatchObject, HatchParams, HatchPass, HatchSettings,
    HatchSource, SceneInput, ScenePasses, SceneSettings, ShadowLight, TonalArtMap,
};
use glam::Vec3;
use npr_gpu::{Camera, FrameId, GpuMesh, ObjectUniforms, OffscreenTarget, Prepared, TargetFormats};

/// The settings of a [`HatchFrame`]: the style's tonal art map and the scene passes'.
#[derive(Clone, Debug)]
pub struct HatchFrameSettings {
    /// The tonal art map (pen or pencil style).
    pub tam: TonalArtMap,
    /// Shadow map and surface anchors.
    pub scene: SceneSettings,
}

/// One frame's input to [`HatchFrame::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct HatchView<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The displayed-frame count that schedules the surface anchors
    /// ([`SceneInput::clock`]).
    pub clock: u64,
    /// The camera.
    pub camera: &'a Camera,
    /// The light.
    pub light: &'a ShadowLight,
    /// Bin count, stroke scale, mode and colours.
    pub params: &'a HatchParams,
}

/// What [`HatchFrame::prepare`] hands back for the `record_*` calls of the same frame.
#[derive(Clone, Debug)]
pub struct HatchPrepared {
    objects: Vec<Prepared>,
    hatch: Prepared,
}

impl HatchPrepared {
    /// The objects' tickets for [`ScenePasses`], in the order they were prepared.
    pub fn objects(&self) -> &[Prepared] {
        &self.objects
    }
}

/// Shadow, G-buffer and hatching passes for one target size.
#[derive(Debug)]
pub struct HatchFrame {
    /// The shadow / G-buffer / Phong passes.
    pub scene: ScenePasses,
    /// The hatching pass.
    pub hatch: HatchPass,
    /// The G-buffer the scene is drawn into.
    pub gbuffer: GBuffer,
    source: HatchSource,
    formats: TargetFormats,
}

impl HatchFrame {
    /// Passes for targets of `formats` and `size` (width, height).
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`], [`HatchError::InvalidParams`].
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &HatchFrameSettings,
        (width, height): (u32, u32),
    ) -> Result<Self, HatchError> {
        let scene = ScenePasses::new(device, queue, formats, &settings.scene)?;
        let hatch_settings = HatchSettings {
            tam: settings.tam.clone(),
        };
        let hatch = HatchPass::new(device, queue, formats, &hatch_settings)?;
        let gbuffer = GBuffer::new(device, width, height)?;
        let source = hatch.create_object(device, &gbuffer);
        Ok(Self {
            scene,
            hatch,
            gbuffer,
            source,
            formats,
        })
    }

    /// Switches the tonal art map (style): a new hatching pass over the same G-buffer.
    ///
    /// # Errors
    /// As [`HatchPass::new`]; the old map stays in force.
    pub fn set_tam(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tam: &TonalArtMap,
    ) -> Result<(), HatchError> {
        let settings = HatchSettings { tam: tam.clone() };
        self.hatch = HatchPass::new(device, queue, self.formats, &settings)?;
        self.source = self.hatch.create_object(device, &self.gbuffer);
        Ok(())
    }

    /// Width × height of the G-buffer (and of the targets to draw into).
    pub fn size(&self) -> (u32, u32) {
        (self.gbuffer.width(), self.gbuffer.height())
    }

    /// An object of the scene ([`ScenePasses::create_object`]).
    ///
    /// # Errors
    /// As [`ScenePasses::create_object`].
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        mesh: &GpuMesh,
        directions: &[Vec3],
    ) -> Result<HatchObject, HatchError> {
        self.scene.create_object(device, mesh, directions)
    }

    /// A new pose's stroke directions for `object`, its anchors kept
    /// ([`crate::ScenePasses::write_directions`]): write the pose's vertices into the mesh
    /// (`GpuMesh::write_vertices` or `npr_gpu::PosingPass`) and its directions here, and
    /// the strokes move with the deforming surface.
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] for a count that is not the vertex count.
    pub fn write_directions(
        &self,
        queue: &wgpu::Queue,
        object: &HatchObject,
        directions: &[Vec3],
    ) -> Result<(), HatchError> {
        self.scene.write_directions(queue, object, directions)
    }

    /// Writes one frame: each object's uniforms and anchors, and the hatching
    /// parameters.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] for bad parameters; [`HatchError::Pass`] for an
    /// object of another frame's passes.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        view: &HatchView<'_>,
        objects: &mut [(&mut HatchObject, &ObjectUniforms)],
    ) -> Result<HatchPrepared, HatchError> {
        let hatch = self.hatch.prepare(
            queue,
            &mut self.source,
            &HatchInput {
                frame: view.frame,
                params: view.params,
                anchor_weight: Some(self.scene.anchor_weight(view.clock)),
            },
        )?;
        let viewport = self.size();
        let objects = objects
            .iter_mut()
            .map(|(object, uniforms)| {
                let input = SceneInput {
                    frame: view.frame,
                    clock: view.clock,
                    camera: view.camera,
                    light: view.light,
                    viewport,
                    object: uniforms,
                };
                self.scene.prepare(queue, object, &input)
            })
            .collect::<Result<_, _>>()?;
        Ok(HatchPrepared { objects, hatch })
    }

    fn pairs<'o>(
        objects: &[&'o HatchObject],
        prepared: &'o HatchPrepared,
    ) -> Vec<(&'o HatchObject, &'o Prepared)> {
        objects.iter().copied().zip(&prepared.objects).collect()
    }

    /// Records the shadow map of the prepared objects.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for state of another frame.
    pub fn record_shadow(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        objects: &[&HatchObject],
        prepared: &HatchPrepared,
    ) -> Result<(), HatchError> {
        self.scene
            .record_shadow(encoder, &Self::pairs(objects, prepared))
    }

    /// Records the G-buffer of the prepared objects (after the shadow map).
    ///
    /// # Errors
    /// [`HatchError::Pass`] for state of another frame.
    pub fn record_gbuffer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        objects: &[&HatchObject],
        prepared: &HatchPrepared,
    ) -> Result<(), HatchError> {
        self.scene
            .record_gbuffer(encoder, &self.gbuffer, &Self::pairs(objects, prepared))
    }

    /// Records the frame's hatching pass alone, over the G-buffer recorded before it
    /// ([`HatchPass::record`]: the background unshaded, one anchor outside the
    /// cross-fade).
    ///
    /// # Errors
    /// [`HatchError::Pass`] for state of another frame.
    pub fn record_hatching(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        prepared: &HatchPrepared,
    ) -> Result<(), HatchError> {
        self.hatch
            .record(encoder, target, &self.source, &prepared.hatch)
    }

    /// Records the hatching frame: shadow map, G-buffer, hatching pass into `target`.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for state of another frame.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        objects: &[&HatchObject],
        prepared: &HatchPrepared,
    ) -> Result<(), HatchError> {
        self.record_shadow(encoder, objects, prepared)?;
        self.record_gbuffer(encoder, objects, prepared)?;
        self.record_hatching(encoder, target, prepared)
    }

    /// Records the comparison frame: the same shadow map, then Phong + VSM as colour
    /// over white.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for state of another frame.
    pub fn record_phong(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &OffscreenTarget,
        objects: &[&HatchObject],
        prepared: &HatchPrepared,
    ) -> Result<(), HatchError> {
        self.record_shadow(encoder, objects, prepared)?;
        let mut pass = target.begin_clear_pass(encoder, [1.0, 1.0, 1.0, 1.0]);
        for (object, p) in Self::pairs(objects, prepared) {
            self.scene.draw(&mut pass, object, p)?;
        }
        Ok(())
    }

    /// Prepares, records, submits and reads back one hatched frame (for demos and
    /// tests).
    ///
    /// # Errors
    /// As [`HatchFrame::prepare`], [`HatchError::InvalidSize`] or [`HatchError::Gpu`].
    pub fn render_hatched(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: &HatchView<'_>,
        objects: &mut [(&mut HatchObject, &ObjectUniforms)],
    ) -> Result<image::RgbaImage, HatchError> {
        let prepared = self.prepare(queue, view, objects)?;
        let refs: Vec<&HatchObject> = objects.iter().map(|(o, _)| &**o).collect();
        let (w, h) = self.size();
        let target = OffscreenTarget::new(device, w, h)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.record(&mut encoder, &target.color_view, &refs, &prepared)?;
        queue.submit(Some(encoder.finish()));
        Ok(npr_gpu::readback_rgba(device, queue, &target.color)?)
    }

    /// Prepares, records, submits and reads back one Phong + VSM frame (for demos and
    /// tests).
    ///
    /// # Errors
    /// As [`HatchFrame::render_hatched`].
    pub fn render_phong(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view: &HatchView<'_>,
        objects: &mut [(&mut HatchObject, &ObjectUniforms)],
    ) -> Result<image::RgbaImage, HatchError> {
        let prepared = self.prepare(queue, view, objects)?;
        let refs: Vec<&HatchObject> = objects.iter().map(|(o, _)| &**o).collect();
        let (w, h) = self.size();
        let target = OffscreenTarget::new(device, w, h)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.record_phong(&mut encoder, &target, &refs, &prepared)?;
        queue.submit(Some(encoder.finish()));
        Ok(npr_gpu::readback_rgba(device, queue, &target.color)?)
    }
}
