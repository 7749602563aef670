//! npr-specular inside your own wgpu renderer: your device and queue, your command
//! encoder and render pass, your colour and depth formats. The README's example; run it
//! with `cargo run --release -p npr-specular --example embed -- out.png`.
//!
//! `Highlights` is what a renderer keeps per mesh; `main` plays the renderer: it makes its
//! own targets (`Rgba8UnormSrgb` colour, `Depth24Plus` depth), records one frame and writes
//! the PNG. `tests/embed.rs` renders through the same code and checks the highlight lies
//! where `N = H`.

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, Mesh};
use npr_gpu::{
    BaseInput, BaseObject, BaseShading, Camera, FrameId, FrameUniforms, GpuMesh, Light,
    ObjectUniforms, Prepared, ShadingModel, TargetFormats,
};
use npr_specular::{HighlightInput, HighlightObject, HighlightPass, HighlightSet, SpecularError};

/// One mesh with stylized highlights over Phong (your own base shading works the same).
pub struct Highlights {
    base: BaseShading,
    base_object: BaseObject,
    pass: HighlightPass,
    object: HighlightObject,
    /// The CPU side: N = H centres, projectors, receiver faces (§3, §4.2).
    pub set: HighlightSet,
}

impl Highlights {
    /// Once per mesh, in the formats of the targets you will draw into.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &Mesh,
        gpu_mesh: &GpuMesh,
        formats: TargetFormats,
    ) -> Result<Self, SpecularError> {
        let base = BaseShading::new(device, queue, formats, &Default::default());
        let pass = HighlightPass::new(device, queue, formats, &Default::default())?;
        Ok(Self {
            base_object: base.create_object(device, gpu_mesh),
            object: pass.create_object(device, gpu_mesh),
            set: HighlightSet::new(mesh, &CurvatureOptions::default())?,
            base,
            pass,
        })
    }

    /// Per frame, before recording: the CPU update and the uploads (the only queue
    /// writes). Returns the tickets `draw` takes.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        frame: FrameId,
        mesh: &Mesh,
        camera: &Camera,
        light: &Light,
    ) -> Result<[Prepared; 2], SpecularError> {
        let view = FrameUniforms::new(camera, light);
        let object = ObjectUniforms::default_material(Mat4::IDENTITY);
        let light_eye = LightEye::Positions {
            light: light.position_or_direction,
            eye: camera.eye,
        };
        self.set.update(light_eye, Mat4::IDENTITY);
        let model = ShadingModel::Phong;
        let base = BaseInput {
            frame,
            view: &view,
            object: &object,
            model,
        };
        let base = self.base.prepare(queue, &mut self.base_object, &base)?;
        let input = HighlightInput {
            frame,
            indices: &mesh.indices,
            set: &self.set,
            view: &view,
            object: &object,
            list: None,
        };
        let highlights = self.pass.prepare(queue, &mut self.object, &input)?;
        Ok([base, highlights])
    }

    /// Per frame, inside your render pass (it has your depth attachment).
    pub fn draw(
        &self,
        rpass: &mut wgpu::RenderPass<'_>,
        [base, highlights]: &[Prepared; 2],
        with_highlights: bool,
    ) -> Result<(), SpecularError> {
        self.base.draw(rpass, &self.base_object, base)?;
        if with_highlights {
            self.pass.draw(rpass, &self.object, highlights)?;
        }
        Ok(())
    }
}

/// The renderer's colour format in this example.
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The renderer's depth format in this example.
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// A unit sphere seen from +z at distance 4 with the point light at the eye, `size²`
/// pixels, with or without the highlight pass; the image and the highlight set.
///
/// # Errors
/// A GPU or highlight-set error.
pub fn render_sphere(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    size: u32,
    highlights: bool,
) -> Result<(image::RgbaImage, HighlightSet), Box<dyn std::error::Error>> {
    let mesh = npr_geometry::generate::icosphere(5, 1.0);
    let gpu_mesh = GpuMesh::upload(device, &mesh)?;
    let formats = TargetFormats::new(COLOR, DEPTH);
    let mut hl = Highlights::new(device, queue, &mesh, &gpu_mesh, formats)?;
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let camera = Camera::look_at(eye, Vec3::ZERO, 1.0);
    let frame = FrameId::default();
    let prepared = hl.prepare(queue, frame, &mesh, &camera, &Light::point(eye))?;
    let target = |format, usage| {
        npr_gpu::texture_2d(device, "my renderer target", size, size, format, usage)
    };
    let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = target(COLOR, attach | wgpu::TextureUsages::COPY_SRC);
    let depth = target(DEPTH, attach);
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut rpass = npr_gpu::begin_views_pass(
            &mut encoder,
            &color_view,
            &depth_view,
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            wgpu::LoadOp::Clear(1.0),
        );
        hl.draw(&mut rpass, &prepared, highlights)?;
    }
    queue.submit(Some(encoder.finish()));
    Ok((npr_gpu::readback_rgba(device, queue, &color)?, hl.set))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed-specular.png".into());
    // Your renderer's device and queue; here a headless one.
    let ctx = npr_gpu::GpuContext::new()?;
    let (image, set) = render_sphere(&ctx.device, &ctx.queue, 256, true)?;
    image.save(&out)?;
    println!("{} highlight(s); wrote {out}", set.highlights().len());
    Ok(())
}
