//! The GPU rig shared by the warping figures (`examples/fig8_10.rs`, ...) and
//! `cargo xtask bench warp`: the full-detail renderer, the reference frames (drawn by the
//! default Phong base pass) and the warp pass, drawing into one square target; the
//! turntable path; the paper's and our warp variants; the warping models.

use crate::{
    Antialiasing, Departures, FrameReport, FullInput, FullRenderer, MsaaTarget, PhongBase, Proxy,
    ReferenceDraw, ReferenceFrame, SceneView, SequenceFrame, Turntable, WarpError, WarpInput,
    WarpMode, WarpObject, WarpPass, WarpPassSettings, WarpSequence, WarpSettings,
};
use glam::{Mat4, Vec3};
use npr_geometry::Mesh;
use npr_gpu::{
    COLOR_FORMAT, Camera, DEPTH_FORMAT, FrameId, GpuContext, GpuMesh, Light, ObjectUniforms,
    OffscreenTarget, TargetFormats, readback_rgba,
};

#[derive(Debug)]
/// A warping test model and the three proxy ratios the warping paper's Fig. 8–10 and
/// Table 1 show for it (the shape starts to read; good enough; hard to tell apart).
pub struct WarpModel {
    /// Name in tables and printouts.
    pub name: String,
    /// Name in file names (`warp-ratios-{slug}.png`).
    pub slug: &'static str,
    /// The full-detail mesh.
    pub mesh: Mesh,
    /// Proxy ratios, in the order of the paper's columns.
    pub ratios: [f32; 3],
}

/// The warping models: the bunny from `fixtures/meshes/` (the paper's own Bunny, Fig. 8),
/// and two smooth torus-knot tubes standing in for the paper's Dragon (871,414 triangles,
/// Fig. 9) and Buddha (1,085,634, Fig. 10), which the project does not ship.
pub fn warp_models() -> Result<Vec<WarpModel>, WarpError> {
    Ok(vec![
        WarpModel {
            name: "bunny".into(),
            slug: "bunny",
            mesh: npr_geometry::load_obj(npr_gpu::figures::fixture_mesh("stanford-bunny.obj"))?,
            ratios: [0.05, 0.02, 0.01],
        },
        WarpModel {
            name: "knot-3-5 (870k)".into(),
            slug: "knot-870k",
            mesh: npr_geometry::generate::torus_knot(&npr_geometry::generate::TorusKnot {
                p: 3,
                q: 5,
                major_radius: 1.0,
                minor_radius: 0.45,
                tube_radius: 0.14,
                segments: 2175,
                tube_segments: 200,
            }),
            ratios: [0.01, 0.004, 0.0009],
        },
        WarpModel {
            name: "knot-2-3 (1.1M)".into(),
            slug: "knot-1100k",
            mesh: npr_geometry::generate::benchmark_knot(),
            ratios: [0.006, 0.002, 0.0007],
        },
    ])
}

/// Clear colour of every warping image (transparent black: the object's pixels are the
/// ones with alpha).
pub const CLEAR: [f64; 4] = [0.0; 4];

/// Rotation per frame of every warping path (degrees).
pub const DEG_PER_FRAME: f32 = 1.0;

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

/// The turntable framing `mesh` (scaled to a unit bounding sphere at the origin) with one
/// copy per offset, seen from `distance` with a 34° field of view, at [`DEG_PER_FRAME`]:
/// with `orbit_camera` the camera orbits the fixed objects, else the objects turn before a
/// fixed camera. Returns the path and the world units per object unit.
pub fn path_for(
    mesh: &Mesh,
    offsets: Vec<Vec3>,
    distance: f32,
    orbit_camera: bool,
) -> (Turntable, f32) {
    let (centre, radius) = crate::proxy::bounding_sphere(&mesh.positions);
    let scale = 1.0 / radius.max(1e-6);
    let normalize = Mat4::from_scale(Vec3::splat(scale)) * Mat4::from_translation(-centre);
    let eye = Vec3::new(0.0, 0.35, 1.0).normalize() * distance;
    let mut camera = Camera::look_at(eye, Vec3::ZERO, 1.0);
    camera.fov_y_rad = 34f32.to_radians();
    (
        Turntable {
            camera,
            normalize,
            deg_per_frame: DEG_PER_FRAME,
            offsets,
            orbit_camera,
        },
        scale,
    )
}

#[derive(Debug)]
/// One warp variant of a proxy: the object (binned, inflated per the departures), its
/// settings and fragment shader.
pub struct Variant {
    /// The proxy on the GPU.
    pub object: WarpObject,
    /// Plan and tolerances.
    pub settings: WarpSettings,
    /// Fragment shader.
    pub mode: WarpMode,
}

#[derive(Debug)]
/// Full mesh, renderer, target and warp pass for one mesh.
pub struct Rig<'a> {
    /// The GPU.
    pub ctx: &'a GpuContext,
    /// The full-detail mesh.
    pub full: GpuMesh,
    /// Full-detail renderer (the ground-truth frames).
    pub renderer: FullRenderer,
    /// The base pass of the references (full Phong of the mesh).
    pub base: PhongBase,
    /// The `size × size` target every frame is drawn into.
    pub target: OffscreenTarget,
    /// The warp pass.
    pub pass: WarpPass,
    /// Antialiasing of full renders, references and warps.
    pub antialiasing: Antialiasing,
    /// Multisampled: what full renders and warps draw into before the resolve into
    /// `target`.
    msaa: Option<MsaaTarget>,
    size: u32,
    /// The rig's submissions so far: each method that submits takes the next id.
    frame: FrameId,
}

impl<'a> Rig<'a> {
    /// The id of the rig's next submission.
    fn next_frame(&mut self) -> FrameId {
        self.frame = self.frame.next();
        self.frame
    }

    /// A rig for `mesh` drawing `size × size` frames.
    pub fn new(ctx: &'a GpuContext, mesh: &Mesh, size: u32) -> Result<Self, WarpError> {
        Self::with_antialiasing(ctx, mesh, size, Antialiasing::None)
    }

    /// A rig for `mesh` drawing `size × size` frames, full renders, references and warps
    /// all with `antialiasing` (its resolves inside every recorded pass).
    pub fn with_antialiasing(
        ctx: &'a GpuContext,
        mesh: &Mesh,
        size: u32,
        antialiasing: Antialiasing,
    ) -> Result<Self, WarpError> {
        let (d, q) = (&ctx.device, &ctx.queue);
        antialiasing.check(&ctx.adapter, &ctx.device, COLOR_FORMAT, DEPTH_FORMAT)?;
        let full = GpuMesh::upload(d, mesh)?;
        let msaa = if antialiasing.is_multisampled() {
            Some(MsaaTarget::new(
                d,
                size,
                size,
                antialiasing.references(TargetFormats::default()),
            )?)
        } else {
            None
        };
        Ok(Self {
            ctx,
            base: PhongBase::new(
                &full,
                light(),
                material(),
                antialiasing.references(TargetFormats::default()),
            ),
            full,
            renderer: FullRenderer::new(d, q, antialiasing.references(TargetFormats::default())),
            target: OffscreenTarget::new(d, size, size)?,
            pass: WarpPass::new(
                d,
                q,
                antialiasing.warp_target(TargetFormats::default()),
                &WarpPassSettings { antialiasing },
            )?,
            antialiasing,
            msaa,
            size,
            frame: FrameId::default(),
        })
    }

    /// A pass for warps over the rig's target cleared to `clear` (with a multisampled
    /// warp: over the rig's multisampled textures, resolved into the target when it ends).
    pub fn begin_clear_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        clear: [f64; 4],
    ) -> wgpu::RenderPass<'e> {
        match &self.msaa {
            Some(ms) if self.antialiasing.warp_is_multisampled() => {
                ms.begin_pass(encoder, &self.target.color_view, Some(clear))
            }
            _ => self.target.begin_clear_pass(encoder, clear),
        }
    }

    /// `proxy` warped with `departures` (binned with `bins` per axis, optionally with a
    /// wireframe), for a path scaling object units by `world_per_object`.
    pub fn variant(
        &self,
        proxy: &Proxy,
        departures: Departures,
        world_per_object: f32,
        bins: u32,
        wireframe: bool,
    ) -> Result<Variant, WarpError> {
        Ok(Variant {
            object: self.pass.create_object(
                &self.ctx.device,
                proxy,
                bins,
                departures.inflation(proxy),
                wireframe,
            )?,
            settings: departures.settings(proxy, world_per_object),
            mode: departures.mode(),
        })
    }

    /// Records (without submitting) the full render of `scene` into the target.
    pub fn record_full(&mut self, scene: &SceneView) -> Result<wgpu::CommandEncoder, WarpError> {
        let frame = self.next_frame();
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let input = FullInput {
            frame,
            camera: &scene.camera,
            world_from_objects: &scene.objects,
            light: &light(),
            material: &material(),
        };
        self.renderer.prepare(q, &self.full, &input)?;
        let mut enc = d.create_command_encoder(&Default::default());
        let t = &self.target;
        match &self.msaa {
            Some(ms) => self
                .renderer
                .record_msaa(&mut enc, ms, &t.color_view, CLEAR),
            None => self
                .renderer
                .record(&mut enc, &t.color_view, &t.depth_view, CLEAR),
        }?;
        Ok(enc)
    }

    /// The full render of `scene`, read back.
    pub fn full(&mut self, scene: &SceneView) -> Result<image::RgbaImage, WarpError> {
        let enc = self.record_full(scene)?;
        self.ctx.queue.submit(Some(enc.finish()));
        self.image()
    }

    /// A reference frame of object 0 at `scene`.
    pub fn reference(&mut self, scene: &SceneView) -> Result<ReferenceFrame, WarpError> {
        let mut r = self.reference_slot()?;
        let enc = self.record_reference(&mut r, scene)?;
        self.ctx.queue.submit(Some(enc.finish()));
        Ok(r)
    }

    /// An empty reference slot of the rig's size and antialiasing.
    pub fn reference_slot(&self) -> Result<ReferenceFrame, WarpError> {
        ReferenceFrame::new(
            &self.ctx.device,
            self.size,
            self.size,
            self.antialiasing.references(TargetFormats::default()),
        )
    }

    /// Records (without submitting) a reference of object 0 at `scene` into `r`,
    /// resolves included.
    pub fn record_reference(
        &mut self,
        r: &mut ReferenceFrame,
        scene: &SceneView,
    ) -> Result<wgpu::CommandEncoder, WarpError> {
        let frame = self.next_frame();
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let mut enc = d.create_command_encoder(&Default::default());
        let pose = scene.object(0);
        r.record(
            d,
            q,
            &mut enc,
            &mut self.base,
            &ReferenceDraw::whole(frame, &pose, 0),
            CLEAR,
        )?;
        Ok(enc)
    }

    /// Records and submits frame `frame` of `seq` (objects `objects` along `path`, references
    /// drawn by the rig's base pass) into the rig's target.
    pub fn sequence_frame(
        &mut self,
        seq: &mut WarpSequence,
        objects: &mut [WarpObject],
        path: &dyn Fn(u32) -> SceneView,
        frame: u32,
    ) -> Result<FrameReport, WarpError> {
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let mut enc = d.create_command_encoder(&Default::default());
        let t = &self.target;
        let report = seq.record_frame(
            d,
            q,
            &mut enc,
            SequenceFrame {
                base: &mut self.base,
                objects,
                path,
                frame,
            },
            &t.color_view,
            &t.depth_view,
        )?;
        q.submit(Some(enc.finish()));
        Ok(report)
    }

    /// `variant` warped from `refs` to object 0 at `scene` (position `s` between them)
    /// with `mode`, read back; with `wire`, the proxy filled light grey with its edges
    /// over it instead.
    ///
    /// # Errors
    /// [`WarpError::Gpu`] when the readback fails.
    pub fn warp_image(
        &mut self,
        refs: [&ReferenceFrame; 2],
        variant: &mut Variant,
        (scene, s): (&SceneView, f32),
        mode: WarpMode,
        wire: bool,
    ) -> Result<image::RgbaImage, WarpError> {
        let frame = self.next_frame();
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let pair = self.pass.bind_pair(d, refs);
        let object = &mut variant.object;
        let mut settings = variant.settings;
        if wire {
            settings.fill_color = [0.8, 0.8, 0.8, 1.0];
        }
        let now = scene.object(0);
        let mut input = WarpInput {
            frame,
            pair: &pair,
            now: &now,
            s,
            settings: &settings,
            mode,
        };
        let filled = self.pass.prepare(q, object, &input)?;
        let mut wire_settings = settings;
        wire_settings.fill_color = [0.05, 0.1, 0.3, 1.0];
        input.settings = &wire_settings;
        let edges = self.pass.prepare(q, object, &input)?;
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut rpass = self.target.begin_clear_pass(&mut enc, CLEAR);
            self.pass.draw(&mut rpass, object, &filled)?;
        }
        if wire {
            let mut rpass = self.target.begin_load_pass(&mut enc);
            self.pass.draw_wireframe(&mut rpass, object, &edges)?;
        }
        q.submit(Some(enc.finish()));
        Ok(readback_rgba(d, q, &self.target.color)?)
    }

    /// The target's current image.
    pub fn image(&self) -> Result<image::RgbaImage, WarpError> {
        Ok(readback_rgba(
            &self.ctx.device,
            &self.ctx.queue,
            &self.target.color,
        )?)
    }
}
