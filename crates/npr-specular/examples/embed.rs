//! npr-specular inside your own wgpu renderer: your device and queue, your command
//! encoder and render pass, your colour and depth formats. The README's example; run it
//! with `cargo run --release -p npr-specular --example embed -- out.png`.
//!
//! `Highlights` is what a renderer keeps per mesh; `main` plays the renderer: it makes its
//! own targets (`Rgba8UnormSrgb` colour, `Depth24Plus` depth), records one frame and writes
//! the PNG. `tests/embed.rs` renders through the same code and checks the highlight lies
//! where `N = H`.

use glam::{Mat4, Vec3};
use npr_geometry::{LightEye, Mesh};
use npr_gpu::{
    BaseInput, BaseObject, BaseShading, Camera, FrameId, FrameUniforms, GpuMesh, Light,
    ObjectUniforms, Prepared, ShadingModel, TargetFormats,
};
use npr_specular::{
    BackendSetting, HighlightInput, HighlightObject, HighlightPass, HighlightSetup, SetupInput,
    SetupObject, SpecularError, SpecularSettings,
};

/// One mesh with stylized highlights over Phong (your own base shading works the same).
pub struct Highlights {
    base: BaseShading,
    base_object: BaseObject,
    setup: HighlightSetup,
    /// The mesh's highlight set and the backend that runs it (§3, §4.2).
    pub setup_object: SetupObject,
    pass: HighlightPass,
    object: HighlightObject,
}

impl Highlights {
    /// Once per mesh, in the formats of the targets you will draw into, with `settings`
    /// (a preset's, or the defaults) on the backend they and your `adapter` give.
    pub fn new(
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        (mesh, gpu_mesh): (&Mesh, &GpuMesh),
        formats: TargetFormats,
        (settings, adapter): (&SpecularSettings, &wgpu::AdapterInfo),
    ) -> Result<Self, SpecularError> {
        let base = BaseShading::new(device, queue, formats, &Default::default());
        let pass = HighlightPass::new(device, queue, formats, &Default::default())?;
        let setup = HighlightSetup::new(device, queue, &Default::default());
        Ok(Self {
            base_object: base.create_object(device, gpu_mesh),
            object: pass.create_object(device, gpu_mesh),
            setup_object: setup.create_object(device, queue, mesh, settings, adapter)?,
            setup,
            base,
            pass,
        })
    }

    /// Per frame, before your render pass: the highlight setup (its compute stages, on
    /// the GPU backend, recorded into your encoder) and the uploads. Returns the tickets
    /// `draw` takes.
    pub fn prepare(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (frame, mesh, gpu_mesh): (FrameId, &Mesh, &GpuMesh),
        (camera, light): (&Camera, &Light),
    ) -> Result<[Prepared; 2], SpecularError> {
        let view = FrameUniforms::new(camera, light);
        let object = ObjectUniforms::default_material(Mat4::IDENTITY);
        let light_eye = LightEye::Positions {
            light: light.position_or_direction,
            eye: camera.eye,
        };
        let input = SetupInput {
            frame,
            light_eye,
            world_from_object: Mat4::IDENTITY,
            mesh,
            gpu: gpu_mesh,
        };
        let setup = self
            .setup
            .prepare(device, queue, &mut self.setup_object, &input)?;
        let highlights = self.setup.record(encoder, &mut self.setup_object, &setup)?;
        let input = HighlightInput {
            frame,
            highlights: &highlights,
            view: &view,
            object: &object,
        };
        let highlights = self.pass.prepare(queue, &mut self.object, &input)?;
        let base = BaseInput {
            frame,
            view: &view,
            object: &object,
            model: ShadingModel::Phong,
        };
        let base = self.base.prepare(queue, &mut self.base_object, &base)?;
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

    /// After your submission (the GPU backend reads its highlights back for picking).
    pub fn after_submit(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        self.setup
            .after_submit(device, queue, &mut self.setup_object);
    }
}

/// The renderer's colour format in this example.
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The renderer's depth format in this example.
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// A unit sphere seen from +z at distance 4 with the point light at the eye, `size²`
/// pixels, on the backend `backend` and `adapter` give: the frame with its highlights,
/// the same frame's base shading alone, and the mesh's highlights.
///
/// # Errors
/// A GPU or highlight-set error.
pub fn render_sphere(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    (adapter, backend): (&wgpu::AdapterInfo, BackendSetting),
    size: u32,
) -> Result<([image::RgbaImage; 2], Highlights), Box<dyn std::error::Error>> {
    let mesh = npr_geometry::generate::icosphere(5, 1.0);
    let gpu_mesh = GpuMesh::upload(device, &mesh)?;
    let formats = TargetFormats::new(COLOR, DEPTH);
    let settings = SpecularSettings {
        backend,
        ..SpecularSettings::default()
    };
    let mut hl = Highlights::new(
        (device, queue),
        (&mesh, &gpu_mesh),
        formats,
        (&settings, adapter),
    )?;
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let camera = Camera::look_at(eye, Vec3::ZERO, 1.0);
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
    let frame = (FrameId::default(), &mesh, &gpu_mesh);
    let lit = (&camera, &Light::point(eye));
    let prepared = hl.prepare((device, queue), &mut encoder, frame, lit)?;
    let mut images = Vec::new();
    // The frame, then its base shading alone (for comparison).
    for with_highlights in [true, false] {
        {
            let mut rpass = npr_gpu::begin_views_pass(
                &mut encoder,
                &color_view,
                &depth_view,
                wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                wgpu::LoadOp::Clear(1.0),
            );
            hl.draw(&mut rpass, &prepared, with_highlights)?;
        }
        queue.submit(Some(encoder.finish()));
        encoder = device.create_command_encoder(&Default::default());
        if with_highlights {
            hl.after_submit(device, queue);
        }
        images.push(npr_gpu::readback_rgba(device, queue, &color)?);
    }
    let [with, without] = <[image::RgbaImage; 2]>::try_from(images).map_err(|_| "two images")?;
    Ok(([with, without], hl))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed-specular.png".into());
    // Your renderer's device and queue; here a headless one. The backend from its adapter.
    let ctx = npr_gpu::GpuContext::new()?;
    let adapter = ctx.adapter.get_info();
    let gpu = (&ctx.device, &ctx.queue);
    let ([image, _], hl) = render_sphere(gpu, (&adapter, BackendSetting::Auto), 256)?;
    image.save(&out)?;
    let found = hl.setup_object.set().highlights().len();
    let choice = hl.setup_object.choice();
    println!("backend {choice}; {found} highlight(s) known to the CPU; wrote {out}");
    Ok(())
}
