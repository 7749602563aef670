//! The GPU rig shared by the warping demo and benchmark: the full-detail renderer, the
//! reference frames and the warp pass, drawing into one square target.

use npr_geometry::Mesh;
use npr_gpu::{GpuContext, GpuMesh, Light, ObjectUniforms, OffscreenTarget, readback_rgba};
use npr_warp::{FullRenderer, ReferenceFrame, ScenePose, WarpPass};

/// Clear colour of every warping image (transparent black: the object's pixels are the
/// ones with alpha).
pub const CLEAR: [f64; 4] = [0.0; 4];

/// The light of the warping scenes.
pub fn light() -> Light {
    Light::directional(glam::Vec3::new(1.0, 1.5, 2.0))
}

/// The material of the warping scenes.
pub fn material() -> ObjectUniforms {
    ObjectUniforms::new(
        glam::Mat4::IDENTITY,
        glam::Vec3::new(0.75, 0.6, 0.45),
        0.3,
        glam::Vec3::ONE,
        24.0,
    )
}

/// Full mesh, renderer, target and warp pass for one mesh.
pub struct Rig<'a> {
    /// The GPU.
    pub ctx: &'a GpuContext,
    /// The full-detail mesh.
    pub full: GpuMesh,
    /// Full-detail renderer (the reference and ground-truth frames).
    pub renderer: FullRenderer,
    /// The `size × size` target every frame is drawn into.
    pub target: OffscreenTarget,
    /// The warp pass.
    pub pass: WarpPass,
    size: u32,
}

impl<'a> Rig<'a> {
    /// A rig for `mesh` drawing `size × size` frames.
    pub fn new(ctx: &'a GpuContext, mesh: &Mesh, size: u32) -> anyhow::Result<Self> {
        Ok(Self {
            ctx,
            full: GpuMesh::upload(&ctx.device, mesh)?,
            renderer: FullRenderer::new(&ctx.device, &ctx.queue),
            target: OffscreenTarget::new(&ctx.device, size, size)?,
            pass: WarpPass::new(&ctx.device),
            size,
        })
    }

    /// Records (without submitting) the full render of `scene` into the target.
    pub fn record_full(&mut self, scene: &ScenePose) -> wgpu::CommandEncoder {
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        self.renderer
            .set_scene(d, q, &scene.camera, &scene.objects, &light(), &material());
        let mut enc = d.create_command_encoder(&Default::default());
        self.renderer
            .record(&mut enc, &self.target, &self.full, CLEAR);
        enc
    }

    /// The full render of `scene`, read back.
    pub fn full(&mut self, scene: &ScenePose) -> anyhow::Result<image::RgbaImage> {
        let enc = self.record_full(scene);
        self.ctx.queue.submit(Some(enc.finish()));
        self.image()
    }

    /// A reference frame of object 0 at `scene`.
    pub fn reference(&self, scene: &ScenePose) -> anyhow::Result<ReferenceFrame> {
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let mut r = ReferenceFrame::new(d, q, self.size, self.size)?;
        r.set_pose(q, &scene.object(0), &light(), &material());
        let mut enc = d.create_command_encoder(&Default::default());
        r.record(&mut enc, &self.full, CLEAR);
        q.submit(Some(enc.finish()));
        Ok(r)
    }

    /// The target's current image.
    pub fn image(&self) -> anyhow::Result<image::RgbaImage> {
        Ok(readback_rgba(
            &self.ctx.device,
            &self.ctx.queue,
            &self.target.color,
        )?)
    }
}
