//! Reference frames (§3.3, Fig. 4): the full-detail scene rendered at a reference pose into
//! colour and depth textures, keeping the reference camera's `clip_from_world` and the
//! object's pose so the image can be projected back (§3.3.1).
//!
//! What a reference shows is the caller's: a [`BasePass`] records the draws into the
//! reference's render pass (targets of the caller's colour and depth formats), given the
//! reference camera ([`ReferenceDraw`]). [`PhongBase`] is the default: npr-gpu's full Phong.
//! A reference can be rendered at once ([`ReferenceFrame::record`]) or in slices spread
//! over the intermediate frames (a [`ReferenceDraw`] of several slices), as the paper's §3.4
//! suggests for hiding the reference cost behind a third off-screen buffer.

use crate::WarpError;
use crate::msaa::{DepthResolve, MsaaTarget};
use glam::{Mat4, Vec3};
use npr_gpu::render::clear_color;
use npr_gpu::{
    BaseInput, BaseObject, BaseSettings, BaseShading, Camera, FrameId, FrameUniforms, GpuMesh,
    Light, ObjectUniforms, Prepared, ShadingModel, TargetFormats,
};
use std::ops::Range;

/// Where and how a reference (or a full frame) is rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectView {
    /// The camera.
    pub camera: Camera,
    /// Object → world of the (prototype) object.
    pub world_from_object: Mat4,
}

impl ObjectView {
    /// The camera's eye in the object's space.
    pub fn eye_object(&self) -> Vec3 {
        self.world_from_object
            .inverse()
            .transform_point3(self.camera.eye)
    }
}

/// What a [`BasePass`] is asked to draw: one reference, or one slice of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceDraw<'a> {
    /// The caller's submission this draw is recorded for: references recorded before one
    /// submit share it, so a base pass keeps each one's state apart.
    pub frame: FrameId,
    /// The reference camera and the object's pose.
    pub pose: &'a ObjectView,
    /// The reference slot (0, 1, 2 in a [`crate::WarpSequence`]; 0, 1 in a
    /// [`crate::Warper`]): references alive at once have different slots, so a base pass
    /// that keeps its camera uniforms per slot may record several references before one
    /// submit (`queue.write_buffer` lands at the submit, before any command).
    pub slot: usize,
    /// This slice, `0..slices`.
    pub slice: u32,
    /// Slices the reference is split into (1: whole).
    pub slices: u32,
}

impl<'a> ReferenceDraw<'a> {
    /// The whole reference at `pose` as slot `slot` (one slice), for submission `frame`.
    pub fn whole(frame: FrameId, pose: &'a ObjectView, slot: usize) -> Self {
        Self {
            frame,
            pose,
            slot,
            slice: 0,
            slices: 1,
        }
    }

    /// The range of a `count`-long triangle-list index buffer this slice draws: the
    /// triangles `[slice/slices, (slice+1)/slices)`, whole triangles only.
    pub fn index_range(&self, count: u32) -> Range<u32> {
        let slices = self.slices.max(1);
        let slice = self.slice.min(slices - 1);
        let triangles = u64::from(count / 3);
        let at = |k: u32| (triangles * u64::from(k) / u64::from(slices)) as u32 * 3;
        at(slice)..at(slice + 1)
    }
}

/// The caller's base pass: what a reference (and a full frame) shows.
///
/// [`BasePass::prepare`] is called before each [`BasePass::draw`] of a reference (per slice),
/// outside any render pass; `draw` records into a render pass whose colour and depth
/// targets have the formats the [`crate::WarpPass`] was built for and the reference's
/// sample count ([`ReferenceFrame::sample_count`]: 1, or 4 for a multisampled reference),
/// cleared (slice 0) or loaded (later slices). The base pass's pipelines must be built for
/// both: a reference checks [`BasePass::sample_count`] before recording and returns
/// [`WarpError::SampleCountMismatch`] instead of drawing (the formats are the caller's to
/// match). Keep per-slot uniforms: two references may be recorded into one encoder.
pub trait BasePass {
    /// Samples per pixel the pipelines of `draw` are built for (1 unless overridden).
    fn sample_count(&self) -> u32 {
        1
    }
    /// Writes what `draw` needs (camera, transforms) for `target`.
    fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, target: &ReferenceDraw<'_>);
    /// Records the draws of `target` (for a slice, only its share of the work, e.g.
    /// [`ReferenceDraw::index_range`] of the index buffer).
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, target: &ReferenceDraw<'_>);
}

/// `material` with its transforms replaced by `world_from_object`'s.
fn posed(material: &ObjectUniforms, world_from_object: Mat4) -> ObjectUniforms {
    let fresh = ObjectUniforms::new(world_from_object, Vec3::ZERO, 0.0, Vec3::ZERO, 1.0);
    ObjectUniforms {
        world_from_object: fresh.world_from_object,
        normal_from_object: fresh.normal_from_object,
        ..*material
    }
}

/// The default [`BasePass`]: one mesh with npr-gpu's base shading (full Phong unless
/// [`PhongBase::with_model`] picks Gouraud or cel) under one light, its shading state kept
/// per reference slot.
#[derive(Debug)]
pub struct PhongBase {
    mesh: GpuMesh,
    light: Light,
    material: ObjectUniforms,
    formats: TargetFormats,
    model: ShadingModel,
    ramp: Option<Vec<[u8; 4]>>,
    /// The shading pass and its object, built on first use.
    shading: Option<(BaseShading, BaseObject)>,
    /// What each reference slot was last prepared with.
    prepared: Vec<Option<Prepared>>,
}

impl PhongBase {
    /// Full Phong of `mesh` (its buffers are shared, not copied) lit by `light` with
    /// `material` (whose transform is replaced by each pose's), into references of
    /// `formats` (the references' formats and sample count, see [`ReferenceFrame::new`]).
    pub fn new(
        mesh: &GpuMesh,
        light: Light,
        material: ObjectUniforms,
        formats: TargetFormats,
    ) -> Self {
        Self {
            mesh: mesh.clone(),
            light,
            material,
            formats,
            model: ShadingModel::Phong,
            ramp: None,
            shading: None,
            prepared: Vec::new(),
        }
    }

    /// The same base with another shading model and, for cel shading, its ramp texels
    /// (`npr_gpu::toon_ramp`; `None` keeps npr-gpu's default ramp).
    pub fn with_model(mut self, model: ShadingModel, ramp: Option<Vec<[u8; 4]>>) -> Self {
        self.model = model;
        self.ramp = ramp;
        self.shading = None;
        self.prepared.clear();
        self
    }

    /// Changes the light and material of the references recorded from now on (CPU
    /// state: each reference's `prepare` writes them).
    pub fn set_lighting(&mut self, light: Light, material: ObjectUniforms) {
        self.light = light;
        self.material = material;
    }
}

impl BasePass for PhongBase {
    fn sample_count(&self) -> u32 {
        self.formats.samples
    }

    fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, target: &ReferenceDraw<'_>) {
        let (shading, object) = self.shading.get_or_insert_with(|| {
            let settings = match &self.ramp {
                Some(ramp) => BaseSettings { ramp: ramp.clone() },
                None => BaseSettings::default(),
            };
            let shading = BaseShading::new(device, queue, self.formats, &settings);
            let object = shading.create_object(device, &self.mesh);
            (shading, object)
        });
        let view = FrameUniforms::new(&target.pose.camera, &self.light);
        let object_uniforms = posed(&self.material, target.pose.world_from_object);
        let input = BaseInput {
            frame: target.frame,
            view: &view,
            object: &object_uniforms,
            model: self.model,
        };
        if self.prepared.len() <= target.slot {
            self.prepared.resize(target.slot + 1, None);
        }
        // A failed prepare (more than 64 references in one submission) draws nothing.
        self.prepared[target.slot] = shading.prepare(queue, object, &input).ok();
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>, target: &ReferenceDraw<'_>) {
        let Some((shading, object)) = &self.shading else {
            return;
        };
        if let Some(Some(prepared)) = self.prepared.get(target.slot) {
            let range = target.index_range(self.mesh.index_count);
            // A ticket of another frame is refused: nothing is drawn.
            let _ = shading.draw_range(pass, object, prepared, range);
        }
    }
}

/// A reference image: colour + depth of the scene at one pose (§3.3), in the caller's
/// formats.
#[derive(Debug)]
pub struct ReferenceFrame {
    /// Colour texture (renderable, sampleable, copyable).
    pub color: wgpu::Texture,
    /// Default view of `color`.
    pub color_view: wgpu::TextureView,
    /// Depth texture (renderable, sampleable).
    pub depth: wgpu::Texture,
    /// Default view of `depth` (the attachment).
    pub depth_view: wgpu::TextureView,
    pub(crate) depth_sample_view: wgpu::TextureView,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// The pose the reference shows (valid after a complete record).
    pub pose: ObjectView,
    /// `pose.camera.clip_from_world()`, kept for the projective texture matrix.
    pub clip_from_world: Mat4,
    /// The formats and samples per pixel the base pass draws into.
    formats: TargetFormats,
    /// Multisampled: the textures drawn into, the depth resolve and its source binding.
    msaa: Option<ReferenceMsaa>,
    /// The proxy's vertices at this reference's pose, for a deforming object
    /// ([`crate::deform`]), with the object they are of; kept for reuse, valid only when
    /// taken since the last record.
    pub(crate) proxy_pose: Option<crate::deform::Snapshot>,
    pub(crate) proxy_pose_valid: bool,
}

/// The multisampled side of a [`ReferenceFrame`].
#[derive(Debug)]
struct ReferenceMsaa {
    target: MsaaTarget,
    resolve: DepthResolve,
    source: wgpu::BindGroup,
}

impl ReferenceFrame {
    /// A reference slot of `width × height` with colour `formats.color` and depth
    /// `formats.depth`, drawn with `formats.samples` samples per pixel: one, or 4
    /// (multisampled: the base pass draws into multisampled textures, its pipelines built
    /// for them, e.g. [`PhongBase::new`] with the same formats, whose colour is resolved
    /// into [`Self::color`] (alpha = coverage) and whose depth is resolved, nearest sample
    /// per texel, into [`Self::depth`] after every recorded pass).
    ///
    /// # Errors
    /// [`WarpError::Gpu`] for a zero size or one past the device's limit;
    /// [`WarpError::InvalidSetting`] for formats the warp cannot sample or a sample count
    /// other than 1 or 4.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        formats: TargetFormats,
    ) -> Result<Self, WarpError> {
        Self::with_resolve(device, width, height, formats, None)
    }

    /// As [`ReferenceFrame::new`]; multisampled, with `resolve` (built for
    /// `formats.depth`: one shared by the references of a [`crate::Warper`]) or, `None`, a
    /// depth resolve of its own.
    pub(crate) fn with_resolve(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        formats: TargetFormats,
        resolve: Option<DepthResolve>,
    ) -> Result<Self, WarpError> {
        let (color_format, depth_format) = (formats.color, formats.depth);
        if !matches!(formats.samples, 1 | 4) {
            return Err(WarpError::InvalidSetting(format!(
                "references of {} samples per pixel: the warp supports 1 or 4",
                formats.samples
            )));
        }
        crate::msaa::check_formats(color_format, depth_format)?;
        npr_gpu::check_size(device, width, height)?;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let make = |label, format| npr_gpu::texture_2d(device, label, width, height, format, usage);
        let color = make("npr-warp reference colour", color_format);
        let depth = make("npr-warp reference depth", depth_format);
        let camera = Camera::look_at(Vec3::Z * 3.0, Vec3::ZERO, width as f32 / height as f32);
        let msaa = if formats.is_multisampled() {
            let resolve = resolve.unwrap_or_else(|| DepthResolve::new(device, depth_format));
            let target = MsaaTarget::with_sampled_depth(device, width, height, formats)?;
            let source = resolve.bind(device, &target);
            Some(ReferenceMsaa {
                target,
                resolve,
                source,
            })
        } else {
            None
        };
        Ok(Self {
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            depth_sample_view: depth.create_view(&wgpu::TextureViewDescriptor {
                aspect: wgpu::TextureAspect::DepthOnly,
                ..Default::default()
            }),
            color,
            depth,
            width,
            height,
            pose: ObjectView {
                camera,
                world_from_object: Mat4::IDENTITY,
            },
            clip_from_world: camera.clip_from_world(),
            formats,
            msaa,
            proxy_pose: None,
            proxy_pose_valid: false,
        })
    }

    /// The formats and samples per pixel of the pass a base pass draws into.
    pub fn formats(&self) -> TargetFormats {
        self.formats
    }

    /// Samples per pixel of the pass a base pass draws into (1, or 4 multisampled).
    pub fn sample_count(&self) -> u32 {
        self.formats.samples
    }

    /// `Ok` when `base`'s pipelines are built for this reference's sample count.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`] otherwise.
    pub fn check_base(&self, base: &dyn BasePass) -> Result<(), WarpError> {
        WarpError::check_samples("the base pass", base.sample_count(), self.sample_count())
    }

    /// Records `base` drawing `pose` (as slot `slot`, for submission `frame`) over what the
    /// reference holds, with
    /// no clear; the reference keeps its own pose. E.g. a synthetic occluder: it is in the
    /// reference's colour and depth but not part of the warped object.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`] (recording nothing) when `base` is built for
    /// another sample count than the reference ([`ReferenceFrame::check_base`]).
    pub fn record_over(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        base: &mut dyn BasePass,
        (frame, pose, slot): (FrameId, &ObjectView, usize),
    ) -> Result<(), WarpError> {
        self.check_base(base)?;
        self.draw_base(
            device,
            queue,
            encoder,
            base,
            &ReferenceDraw::whole(frame, pose, slot),
            None,
        );
        Ok(())
    }

    /// `base.prepare`, then a pass over the reference (cleared to `clear`, or loaded)
    /// recording `base.draw`.
    fn draw_base(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        base: &mut dyn BasePass,
        draw: &ReferenceDraw<'_>,
        clear: Option<[f64; 4]>,
    ) {
        base.prepare(device, queue, draw);
        let (color, depth) = match clear {
            Some(rgba) => (clear_color(rgba), wgpu::LoadOp::Clear(1.0)),
            None => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        };
        if let Some(msaa) = &self.msaa {
            {
                let mut pass = msaa.target.begin_pass(encoder, &self.color_view, clear);
                base.draw(&mut pass, draw);
            }
            msaa.resolve.record(encoder, &msaa.source, &self.depth_view);
            return;
        }
        let mut pass =
            npr_gpu::begin_views_pass(encoder, &self.color_view, &self.depth_view, color, depth);
        base.draw(&mut pass, draw);
    }

    /// Records `draw` by `base` into `encoder`: the whole reference at `draw.pose`
    /// ([`ReferenceDraw::whole`]), or slice `draw.slice` of `draw.slices`, as slot
    /// `draw.slot` of `base`. Slice 0 clears to `clear` (use alpha 0 so the object's
    /// pixels are those with alpha) and sets the pose; later slices load what earlier ones
    /// drew, so after all slices the reference equals the whole one (§3.4: the next
    /// reference spread over the frames between). Submit the encoder before binding the
    /// reference for a warp.
    ///
    /// # Errors
    /// As [`ReferenceFrame::record_over`] (the reference is left as it was).
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        base: &mut dyn BasePass,
        draw: &ReferenceDraw<'_>,
        clear: [f64; 4],
    ) -> Result<(), WarpError> {
        let ReferenceDraw {
            frame,
            pose,
            slot,
            slice,
            slices,
        } = *draw;
        self.check_base(base)?;
        let slices = slices.max(1);
        let slice = slice.min(slices - 1);
        if slice == 0 {
            self.pose = *pose;
            self.clip_from_world = pose.camera.clip_from_world();
            // A new recording: the last one's proxy snapshot is not of it.
            self.proxy_pose_valid = false;
        }
        let draw = ReferenceDraw {
            frame,
            pose,
            slot,
            slice,
            slices,
        };
        let clear = (slice == 0).then_some(clear);
        self.draw_base(device, queue, encoder, base, &draw, clear);
        Ok(())
    }
}

/// A render pass over `color` and `depth` cleared to `clear` (linear RGBA) and depth 1.
pub fn begin_clear_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    color: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    clear: [f64; 4],
) -> wgpu::RenderPass<'e> {
    npr_gpu::begin_views_pass(
        encoder,
        color,
        depth,
        clear_color(clear),
        wgpu::LoadOp::Clear(1.0),
    )
}

/// One frame's input to [`FullRenderer::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct FullInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The camera.
    pub camera: &'a Camera,
    /// One transform per object (`material`'s transform is replaced by each).
    pub world_from_objects: &'a [Mat4],
    /// The light.
    pub light: &'a Light,
    /// The material.
    pub material: &'a ObjectUniforms,
}

/// The full render of every object of a scene (full Phong): what each warped frame is
/// compared with and what a reference costs. One [`BaseShading`] object for the mesh,
/// prepared once per object transform.
#[derive(Debug)]
pub struct FullRenderer {
    device: wgpu::Device,
    shading: BaseShading,
    sample_count: u32,
    object: Option<BaseObject>,
    prepared: Vec<Prepared>,
}

impl FullRenderer {
    /// A renderer for targets of `formats` (e.g. multisampled for
    /// [`MsaaTarget::begin_pass`]; see [`FullRenderer::record_msaa`]).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, formats: TargetFormats) -> Self {
        Self {
            device: device.clone(),
            shading: BaseShading::new(device, queue, formats, &BaseSettings::default()),
            sample_count: formats.samples.max(1),
            object: None,
            prepared: Vec::new(),
        }
    }

    /// Writes the camera, light and one transform per object for drawing `mesh` (its
    /// buffers are shared, not copied).
    ///
    /// # Errors
    /// [`WarpError::Pass`] for more than 64 objects in one frame.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        input: &FullInput<'_>,
    ) -> Result<(), WarpError> {
        let same = self
            .object
            .as_ref()
            .is_some_and(|o| o.mesh().vertex_buffer == mesh.vertex_buffer);
        if !same {
            self.object = Some(self.shading.create_object(&self.device, mesh));
        }
        let Some(object) = self.object.as_mut() else {
            return Ok(());
        };
        let view = FrameUniforms::new(input.camera, input.light);
        self.prepared.clear();
        for m in input.world_from_objects {
            let u = posed(input.material, *m);
            let base = BaseInput {
                frame: input.frame,
                view: &view,
                object: &u,
                model: ShadingModel::Phong,
            };
            self.prepared
                .push(self.shading.prepare(queue, object, &base)?);
        }
        Ok(())
    }

    /// Records the full render prepared last into the caller's pass.
    ///
    /// # Errors
    /// [`WarpError::Pass`] when the preparation is of an earlier frame.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) -> Result<(), WarpError> {
        if let Some(object) = &self.object {
            for prepared in &self.prepared {
                self.shading.draw(pass, object, prepared)?;
            }
        }
        Ok(())
    }

    /// Samples per pixel of the passes the renderer draws into.
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Records a pass over `color` / `depth`, cleared to `clear`, with the full render.
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`] (recording nothing) when `color` or `depth` has
    /// another sample count than the renderer ([`FullRenderer::new`]).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        clear: [f64; 4],
    ) -> Result<(), WarpError> {
        let expected = self.sample_count;
        WarpError::check_samples(
            "the colour target",
            color.texture().sample_count(),
            expected,
        )?;
        WarpError::check_samples("the depth target", depth.texture().sample_count(), expected)?;
        let mut pass = begin_clear_pass(encoder, color, depth, clear);
        self.draw(&mut pass)
    }

    /// Records a multisampled pass over `target`, cleared to `clear`, with the full
    /// render, its colour resolved into `resolve` (for a renderer built
    /// [`FullRenderer::new`] at the target's sample count).
    ///
    /// # Errors
    /// [`WarpError::SampleCountMismatch`] (recording nothing) when `target` has another
    /// sample count than the renderer or `resolve` is multisampled.
    pub fn record_msaa(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &MsaaTarget,
        resolve: &wgpu::TextureView,
        clear: [f64; 4],
    ) -> Result<(), WarpError> {
        let got = target.color.sample_count();
        WarpError::check_samples("the multisampled target", got, self.sample_count)?;
        WarpError::check_samples("the resolve target", resolve.texture().sample_count(), 1)?;
        let mut pass = target.begin_pass(encoder, resolve, Some(clear));
        self.draw(&mut pass)
    }
}
