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
    BaseShading, Camera, FrameUniforms, GpuMesh, Light, ObjectUniforms, ShadingModel, TargetFormats,
};
use npr_specular::{FrameInput, HighlightDraw, HighlightPass, HighlightSet, SpecularError};

/// One mesh with stylized highlights over Phong (your own base shading works the same).
pub struct Highlights {
    base: BaseShading,
    object: npr_gpu::ObjectBinding,
    pass: HighlightPass,
    draw: HighlightDraw,
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
        (color_format, depth_format): (wgpu::TextureFormat, wgpu::TextureFormat),
    ) -> Result<Self, SpecularError> {
        let formats = TargetFormats::new(color_format, depth_format);
        let base = BaseShading::new(device, queue, formats);
        let object = base.create_object(device, &ObjectUniforms::default_material(Mat4::IDENTITY));
        let pass = HighlightPass::new(device, queue, color_format, depth_format)?;
        let draw = pass.create_draw(device, gpu_mesh);
        let set = HighlightSet::new(mesh, &CurvatureOptions::default())?;
        Ok(Self {
            base,
            object,
            pass,
            draw,
            set,
        })
    }

    /// Per frame, before recording: the CPU update and the uploads.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &Mesh,
        gpu_mesh: &GpuMesh,
        camera: &Camera,
        light: &Light,
    ) {
        let frame = FrameUniforms::new(camera, light);
        let object = ObjectUniforms::default_material(Mat4::IDENTITY);
        let light_eye = LightEye::Positions {
            light: light.position_or_direction,
            eye: camera.eye,
        };
        self.set.update(light_eye, Mat4::IDENTITY);
        self.base.set_frame(queue, &frame);
        let input = FrameInput {
            mesh: gpu_mesh,
            indices: &mesh.indices,
            set: &self.set,
            frame: &frame,
            object: &object,
        };
        self.pass.prepare(device, queue, &mut self.draw, &input);
    }

    /// Per frame, inside your render pass (it has your depth attachment).
    pub fn draw(&self, rpass: &mut wgpu::RenderPass<'_>, gpu_mesh: &GpuMesh, highlights: bool) {
        self.base
            .draw(rpass, ShadingModel::Phong, &self.object, gpu_mesh);
        if highlights {
            self.pass.draw(rpass, &self.draw);
        }
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
    let mut hl = Highlights::new(device, queue, &mesh, &gpu_mesh, (COLOR, DEPTH))?;
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let camera = Camera::look_at(eye, Vec3::ZERO, 1.0);
    hl.prepare(device, queue, &mesh, &gpu_mesh, &camera, &Light::point(eye));
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
        hl.draw(&mut rpass, &gpu_mesh, highlights);
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
