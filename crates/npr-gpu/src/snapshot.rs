//! One-call offscreen rendering for tests, demos and tools: draws meshes with a base
//! shading model into a new target and reads it back. It submits and waits, so it is not
//! for use inside a caller's frame.

use crate::{
    BaseShading, Camera, FrameUniforms, GpuError, GpuMesh, Light, ObjectUniforms, OffscreenTarget,
    ShadingModel, TargetFormats, readback_rgba,
};

/// What [`render_base`] draws: meshes with their object uniforms, seen by a camera.
#[derive(Debug)]
pub struct BaseScene<'a> {
    /// Meshes and their transform + material.
    pub objects: &'a [(&'a GpuMesh, ObjectUniforms)],
    /// The camera (its aspect should match the size).
    pub camera: Camera,
    /// The light.
    pub light: Light,
    /// Linear RGBA clear colour.
    pub clear: [f64; 4],
}

/// Renders `scene` with `model` at `width × height` and returns the sRGB image.
///
/// # Errors
/// [`GpuError::InvalidSize`] for a bad size, [`GpuError::Readback`] when readback fails.
pub fn render_base(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &BaseScene<'_>,
    model: ShadingModel,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage, GpuError> {
    let target = OffscreenTarget::new(device, width, height)?;
    let shading = BaseShading::new(
        device,
        queue,
        TargetFormats::default(),
        &crate::BaseSettings::default(),
    );
    let view = FrameUniforms::new(&scene.camera, &scene.light);
    let frame = crate::FrameId::default();
    let mut drawn = Vec::with_capacity(scene.objects.len());
    for (mesh, object) in scene.objects {
        let mut bound = shading.create_object(device, mesh);
        let input = crate::BaseInput {
            frame,
            view: &view,
            object,
            model,
        };
        let prepared = shading.prepare(queue, &mut bound, &input)?;
        drawn.push((bound, prepared));
    }
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("npr render_base"),
    });
    {
        let mut pass = target.begin_clear_pass(&mut encoder, scene.clear);
        for (bound, prepared) in &drawn {
            shading.draw(&mut pass, bound, prepared)?;
        }
    }
    queue.submit(Some(encoder.finish()));
    readback_rgba(device, queue, &target.color)
}
