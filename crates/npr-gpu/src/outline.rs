//! Outlines for every style: silhouettes and creases found from depth and normal
//! discontinuities in a G-buffer, drawn as lines over the caller's colour target.
//!
//! Image-space edge detection on a normal + depth buffer after T. Saito and T. Takahashi,
//! "Comprehensible Rendering of 3-D Shapes", SIGGRAPH 1990, and P. Decaudin,
//! "Cartoon-looking rendering of 3D scenes", INRIA research report 2919, 1996. Not part of
//! the three papers (docs/papers.md); the figures that reproduce them are drawn without it.
//!
//! Two passes, both on the pass contract ([`crate::pass`]):
//! 1. [`NormalDepthPass`] draws meshes into a [`NormalDepthTarget`]
//!    ([`NORMAL_DEPTH_FORMAT`]: view-space unit normal in rgb, linear view depth in a,
//!    a = 0 for background), with its own depth buffer.
//! 2. [`OutlinePass`] draws one full-screen triangle over the caller's colour view,
//!    reading the G-buffer with `textureLoad`, blending the line colour over what is
//!    there and leaving other pixels untouched.
//!
//! The edge rule ([`outline_mask_cpu`] is its CPU twin): a foreground pixel `p` is an
//! edge pixel if one of its four neighbours `q` is background, or is farther by more than
//! `depth_ratio × min(d_p, d_q)` (silhouette / occlusion edge, drawn on the near side), or
//! is at a similar depth but no nearer and its normal differs by more than the crease
//! angle (crease); neighbours outside the image are ignored. A pixel is drawn when an edge pixel lies within `(width_px − 1) / 2`
//! pixels (Euclidean) of it, so widths 1, 3, 5 … draw lines that many pixels across.

use crate::pass::{FrameId, PassError, PassId, Prepared, Slots};
use crate::render::{self, PipelineBuilder};
use crate::{Camera, GpuError, GpuMesh, ObjectUniforms, TargetFormats, Vertex, texture_2d};
use glam::Mat4;
use wgpu::util::DeviceExt;

/// Format of the normal + depth G-buffer: rgb = view-space unit normal, a = linear view
/// depth (distance along the view direction, > 0), a = 0 where nothing was drawn.
pub const NORMAL_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// The outline parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineSettings {
    /// Line width in pixels, clamped to [1, 15]. Default 3.
    pub width_px: f32,
    /// Linear RGB line colour. Default black.
    pub color: [f32; 3],
    /// Opacity in [0, 1]. Default 1.
    pub opacity: f32,
    /// Neighbouring normals turned by more than this (degrees, clamped to [1, 179]) make
    /// a crease line. Default 50°.
    pub crease_angle_deg: f32,
    /// A depth step larger than this fraction of the nearer depth makes a silhouette
    /// line (clamped to [1e-4, 10]). Default 0.1: a smooth surface seen edge-on changes
    /// depth by less than that between pixels at the usual framings.
    pub depth_ratio: f32,
}

impl Default for OutlineSettings {
    fn default() -> Self {
        Self {
            width_px: 3.0,
            color: [0.0; 3],
            opacity: 1.0,
            crease_angle_deg: 50.0,
            depth_ratio: 0.1,
        }
    }
}

/// `x` clamped to `[lo, hi]`, `default` when not finite.
fn clamp_or(x: f32, lo: f32, hi: f32, default: f32) -> f32 {
    if x.is_finite() {
        x.clamp(lo, hi)
    } else {
        default
    }
}

impl OutlineSettings {
    /// The settings with every value clamped to its documented range (non-finite values
    /// take the default).
    pub fn sanitized(&self) -> Self {
        let d = Self::default();
        Self {
            width_px: clamp_or(self.width_px, 1.0, 15.0, d.width_px),
            color: self.color.map(|c| clamp_or(c, 0.0, 1.0, 0.0)),
            opacity: clamp_or(self.opacity, 0.0, 1.0, d.opacity),
            crease_angle_deg: clamp_or(self.crease_angle_deg, 1.0, 179.0, d.crease_angle_deg),
            depth_ratio: clamp_or(self.depth_ratio, 1e-4, 10.0, d.depth_ratio),
        }
    }

    /// Dilation radius `(width_px − 1) / 2` of the sanitized settings.
    pub fn radius_px(&self) -> f32 {
        (self.sanitized().width_px - 1.0) * 0.5
    }

    fn uniforms(&self) -> OutlineUniforms {
        let s = self.sanitized();
        OutlineUniforms {
            color: [s.color[0], s.color[1], s.color[2], s.opacity],
            radius_px: self.radius_px(),
            cos_crease: s.crease_angle_deg.to_radians().cos(),
            depth_ratio: s.depth_ratio,
            _pad: 0.0,
        }
    }
}

/// `OutlineParams` of `outline.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct OutlineUniforms {
    color: [f32; 4],
    radius_px: f32,
    cos_crease: f32,
    depth_ratio: f32,
    _pad: f32,
}

/// `OutlineCamera` of `outline.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniforms {
    clip_from_world: [[f32; 4]; 4],
    view_from_world: [[f32; 4]; 4],
}

/// The normal + depth G-buffer and its depth attachment.
#[derive(Debug)]
pub struct NormalDepthTarget {
    /// [`NORMAL_DEPTH_FORMAT`] texture: renderable, sampleable, copyable.
    pub texture: wgpu::Texture,
    /// Default view of `texture`.
    pub view: wgpu::TextureView,
    /// Depth attachment ([`crate::DEPTH_FORMAT`]).
    pub depth: wgpu::Texture,
    /// Default view of `depth`.
    pub depth_view: wgpu::TextureView,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl NormalDepthTarget {
    /// A G-buffer of `width × height` pixels.
    ///
    /// # Errors
    /// [`GpuError::InvalidSize`] for a zero size or one past the device's 2-D limit.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Result<Self, GpuError> {
        crate::targets::check_size(device, width, height)?;
        let texture = texture_2d(
            device,
            "npr normal+depth",
            width,
            height,
            NORMAL_DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = texture_2d(
            device,
            "npr normal+depth depth",
            width,
            height,
            crate::DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Ok(Self {
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            texture,
            depth,
            width,
            height,
        })
    }

    /// Begins a render pass that clears this G-buffer and its depth, for
    /// [`NormalDepthPass::draw`].
    pub fn begin_pass<'e>(&self, encoder: &'e mut wgpu::CommandEncoder) -> wgpu::RenderPass<'e> {
        render::begin_pass(
            encoder,
            "npr normal+depth",
            &[Some(render::color_attachment(
                &self.view,
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            ))],
            Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
        )
    }

    /// Reads the G-buffer back (`[nx, ny, nz, depth]` per pixel, rows top to bottom).
    /// Submits and waits.
    ///
    /// # Errors
    /// [`GpuError::Readback`] when mapping fails.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let bytes = crate::readback_texture(device, queue, &self.texture)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

/// One mesh drawn by the normal + depth prepass: the caller's buffers (shared) and the
/// per-frame slots (camera at group 0, transform at group 1).
#[derive(Debug)]
pub struct OutlineObject {
    mesh: GpuMesh,
    slots: Slots<NormalDepthSlot>,
}

#[derive(Debug)]
struct NormalDepthSlot {
    camera: wgpu::Buffer,
    object: wgpu::Buffer,
    camera_group: wgpu::BindGroup,
    object_group: wgpu::BindGroup,
}

/// One draw's per-frame input to [`NormalDepthPass::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct NormalDepthInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The camera the G-buffer is drawn from.
    pub camera: &'a Camera,
    /// Object → world (must equal the colour pass's).
    pub world_from_object: Mat4,
}

fn module(device: &wgpu::Device) -> wgpu::ShaderModule {
    crate::shaders::OUTLINE_FILE.module(device)
}

/// The normal + depth prepass: any technique can run it over its meshes. Its draws go
/// into a render pass over a [`NormalDepthTarget`] ([`NormalDepthTarget::begin_pass`]),
/// or [`NormalDepthPass::record`] begins that pass and draws a list of objects.
#[derive(Debug)]
pub struct NormalDepthPass {
    id: PassId,
    device: wgpu::Device,
    pipeline: wgpu::RenderPipeline,
    camera_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
}

impl NormalDepthPass {
    /// Builds the pipeline (back faces culled, depth test less) for a
    /// [`NormalDepthTarget`] (its formats are fixed: [`NORMAL_DEPTH_FORMAT`] and
    /// [`crate::DEPTH_FORMAT`]).
    pub fn new(device: &wgpu::Device, _queue: &wgpu::Queue) -> Self {
        let module = module(device);
        let camera_layout = crate::layout::uniform_layout(device, "npr outline camera");
        let object_layout = crate::layout::uniform_layout(device, "npr outline object");
        let layout = render::pipeline_layout(
            device,
            "npr normal+depth",
            &[&camera_layout, &object_layout],
        );
        let pipeline = PipelineBuilder::new(
            "npr normal+depth",
            &layout,
            &module,
            "vs_normal_depth",
            "fs_normal_depth",
        )
        .buffers(&[Some(Vertex::layout())])
        .cull(Some(wgpu::Face::Back))
        .depth(crate::DEPTH_FORMAT, true, wgpu::CompareFunction::Less)
        .targets(&[Some(NORMAL_DEPTH_FORMAT.into())])
        .build(device);
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            pipeline,
            camera_layout,
            object_layout,
        }
    }

    /// An object drawing `mesh` (its buffers are shared with the caller, not copied).
    pub fn create_object(&self, _device: &wgpu::Device, mesh: &GpuMesh) -> OutlineObject {
        OutlineObject {
            mesh: mesh.clone(),
            slots: Slots::new(self.id),
        }
    }

    /// Writes one draw's camera and transform into a fresh slot of `object`.
    ///
    /// # Errors
    /// [`PassError::ForeignObject`] or [`PassError::SlotsExhausted`].
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut OutlineObject,
        input: &NormalDepthInput<'_>,
    ) -> Result<Prepared, PassError> {
        let device = &self.device;
        let (prepared, slot) = object.slots.next(self.id, input.frame, || {
            let camera = render::uniform_buffer(
                device,
                "npr outline camera",
                std::mem::size_of::<CameraUniforms>(),
            );
            let object = render::uniform_buffer(
                device,
                "npr outline object",
                std::mem::size_of::<ObjectUniforms>(),
            );
            NormalDepthSlot {
                camera_group: render::uniform_group(
                    device,
                    "npr outline camera",
                    &self.camera_layout,
                    &camera,
                ),
                object_group: render::uniform_group(
                    device,
                    "npr outline object",
                    &self.object_layout,
                    &object,
                ),
                camera,
                object,
            }
        })?;
        let c = CameraUniforms {
            clip_from_world: input.camera.clip_from_world().to_cols_array_2d(),
            view_from_world: input.camera.view_from_world().to_cols_array_2d(),
        };
        queue.write_buffer(&slot.camera, 0, bytemuck::bytes_of(&c));
        let u = ObjectUniforms::default_material(input.world_from_object);
        queue.write_buffer(&slot.object, 0, bytemuck::bytes_of(&u));
        Ok(prepared)
    }

    /// Records the draw of `object` as `prepared` into a render pass over a
    /// [`NormalDepthTarget`].
    ///
    /// # Errors
    /// [`PassError`] for a `prepared` of another object, pass or frame.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &OutlineObject,
        prepared: &Prepared,
    ) -> Result<(), PassError> {
        let slot = object.slots.get(self.id, prepared)?;
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &slot.camera_group, &[]);
        pass.set_bind_group(1, &slot.object_group, &[]);
        object.mesh.draw(pass);
        Ok(())
    }

    /// Clears `target` and draws the prepared `objects` into it.
    ///
    /// # Errors
    /// As [`NormalDepthPass::draw`].
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &NormalDepthTarget,
        objects: &[(&OutlineObject, &Prepared)],
    ) -> Result<(), PassError> {
        let mut pass = target.begin_pass(encoder);
        for (object, prepared) in objects {
            self.draw(&mut pass, object, prepared)?;
        }
        Ok(())
    }
}

crate::impl_pass!(NormalDepthPass, OutlineObject, NormalDepthInput, PassError);

/// The G-buffer the outline pass reads, bound once ([`OutlinePass::create_object`]).
#[derive(Debug)]
pub struct OutlineSource {
    gbuffer: wgpu::TextureView,
    slots: Slots<OutlineSlot>,
}

#[derive(Debug)]
struct OutlineSlot {
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// One draw's per-frame input to [`OutlinePass::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct OutlineInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// Line width, colour and thresholds (sanitized, see [`OutlineSettings::sanitized`]).
    pub settings: &'a OutlineSettings,
}

/// The full-screen outline pass over a caller's colour target.
#[derive(Debug)]
pub struct OutlinePass {
    id: PassId,
    device: wgpu::Device,
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl OutlinePass {
    /// Builds the pass for colour targets of `formats.color` (single-sampled; the outline
    /// is drawn after resolve).
    pub fn new(device: &wgpu::Device, _queue: &wgpu::Queue, formats: TargetFormats) -> Self {
        let module = module(device);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr outline"),
            entries: &[
                crate::layout::uniform_entry(1),
                crate::layout::texture_entry(
                    2,
                    wgpu::TextureViewDimension::D2,
                    crate::layout::UNFILTERABLE,
                ),
            ],
        });
        let pipeline_layout = render::pipeline_layout(device, "npr outline", &[&layout]);
        let pipeline = PipelineBuilder::new(
            "npr outline",
            &pipeline_layout,
            &module,
            "vs_fullscreen",
            "fs_outline",
        )
        .targets(&[Some(wgpu::ColorTargetState {
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            ..formats.color.into()
        })])
        .build(device);
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            pipeline,
            layout,
        }
    }

    /// The source that reads `gbuffer` (of the colour target's size).
    pub fn create_object(
        &self,
        _device: &wgpu::Device,
        gbuffer: &NormalDepthTarget,
    ) -> OutlineSource {
        OutlineSource {
            gbuffer: gbuffer.view.clone(),
            slots: Slots::new(self.id),
        }
    }

    /// Writes one draw's settings into a fresh slot of `source`.
    ///
    /// # Errors
    /// [`PassError::ForeignObject`] or [`PassError::SlotsExhausted`].
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        source: &mut OutlineSource,
        input: &OutlineInput<'_>,
    ) -> Result<Prepared, PassError> {
        let device = &self.device;
        let gbuffer = source.gbuffer.clone();
        let (prepared, slot) = source.slots.next(self.id, input.frame, || {
            let params = render::uniform_buffer(
                device,
                "npr outline params",
                std::mem::size_of::<OutlineUniforms>(),
            );
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr outline"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&gbuffer),
                    },
                ],
            });
            OutlineSlot { params, group }
        })?;
        queue.write_buffer(
            &slot.params,
            0,
            bytemuck::bytes_of(&input.settings.uniforms()),
        );
        Ok(prepared)
    }

    /// Draws the outlines of the source's G-buffer into the caller's render pass over a
    /// colour target of the same size, blending over its contents.
    ///
    /// # Errors
    /// [`PassError`] for a `prepared` of another source, pass or frame.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        source: &OutlineSource,
        prepared: &Prepared,
    ) -> Result<(), PassError> {
        let slot = source.slots.get(self.id, prepared)?;
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &slot.group, &[]);
        pass.draw(0..3, 0..1);
        Ok(())
    }
}

crate::impl_pass!(OutlinePass, OutlineSource, OutlineInput, PassError);

/// CPU twin of `is_edge` in `outline.wgsl` for a read-back G-buffer (`[nx, ny, nz, depth]`
/// per pixel, row-major).
fn is_edge(
    gbuffer: &[[f32; 4]],
    width: i64,
    height: i64,
    x: i64,
    y: i64,
    u: &OutlineUniforms,
) -> bool {
    let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < width && y < height;
    let at = |x: i64, y: i64| gbuffer[(y * width + x) as usize];
    if !inside(x, y) {
        return false;
    }
    let c = at(x, y);
    if c[3].is_nan() || c[3] <= 0.0 {
        return false;
    }
    [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dx, dy)| {
        if !inside(x + dx, y + dy) {
            return false;
        }
        let q = at(x + dx, y + dy);
        if q[3].is_nan() || q[3] <= 0.0 {
            return true;
        }
        let step = q[3] - c[3];
        let limit = u.depth_ratio * c[3].min(q[3]);
        let dot = c[0] * q[0] + c[1] * q[1] + c[2] * q[2];
        step > limit || (step.abs() <= limit && step >= 0.0 && dot < u.cos_crease)
    })
}

/// The outline mask the GPU pass draws (`true` = line pixel), computed on the CPU from a
/// read-back G-buffer ([`NormalDepthTarget::read`]) with the same rule (see the module
/// docs). Returns `None` when `gbuffer` does not hold `width × height` pixels.
pub fn outline_mask_cpu(
    width: u32,
    height: u32,
    gbuffer: &[[f32; 4]],
    settings: &OutlineSettings,
) -> Option<Vec<bool>> {
    if gbuffer.len() != (width as usize) * (height as usize) {
        return None;
    }
    let u = settings.uniforms();
    let (w, h) = (i64::from(width), i64::from(height));
    let edges: Vec<bool> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| is_edge(gbuffer, w, h, x, y, &u))
        .collect();
    let r = u.radius_px.floor() as i64;
    let r2 = u.radius_px * u.radius_px;
    let edge = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && edges[(y * w + x) as usize];
    Some(
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                (-r..=r).any(|dy| {
                    (-r..=r).any(|dx| ((dx * dx + dy * dy) as f32) <= r2 && edge(x + dx, y + dy))
                })
            })
            .collect(),
    )
}

/// Draws outlines of `objects` (meshes with their `world_from_object`) seen by `camera`
/// over `image` and returns the result: uploads the image, runs both passes, reads back.
/// A helper for demos and tools; it submits and waits.
///
/// # Errors
/// [`GpuError::InvalidSize`] for an empty or too large image, [`GpuError::Readback`]
/// when readback fails.
pub fn outline_image(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &image::RgbaImage,
    camera: &Camera,
    objects: &[(&GpuMesh, Mat4)],
    settings: &OutlineSettings,
) -> Result<image::RgbaImage, GpuError> {
    let (width, height) = image.dimensions();
    let gbuffer = NormalDepthTarget::new(device, width, height)?;
    let color = device.create_texture_with_data(
        queue,
        &crate::texture_2d_descriptor(
            "npr outline image",
            width,
            height,
            crate::COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            1,
        ),
        wgpu::util::TextureDataOrder::LayerMajor,
        image.as_raw(),
    );
    let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
    let prepass = NormalDepthPass::new(device, queue);
    let frame = FrameId::default();
    let mut bound = Vec::with_capacity(objects.len());
    for (mesh, world_from_object) in objects {
        let mut object = prepass.create_object(device, mesh);
        let input = NormalDepthInput {
            frame,
            camera,
            world_from_object: *world_from_object,
        };
        let prepared = prepass.prepare(queue, &mut object, &input)?;
        bound.push((object, prepared));
    }
    let list: Vec<_> = bound.iter().map(|(o, p)| (o, p)).collect();
    let formats = TargetFormats::new(crate::COLOR_FORMAT, crate::DEPTH_FORMAT);
    let outline = OutlinePass::new(device, queue, formats);
    let mut source = outline.create_object(device, &gbuffer);
    let lines = outline.prepare(queue, &mut source, &OutlineInput { frame, settings })?;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("npr outline_image"),
    });
    prepass.record(&mut encoder, &gbuffer, &list)?;
    {
        let mut pass =
            render::begin_color_pass(&mut encoder, "npr outline", &color_view, wgpu::LoadOp::Load);
        outline.draw(&mut pass, &source, &lines)?;
    }
    queue.submit(Some(encoder.finish()));
    crate::readback_rgba(device, queue, &color)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_layouts_match_wgsl() {
        crate::assert_wgsl_layout!(
            crate::shaders::ALL,
            CameraUniforms,
            "OutlineCamera",
            [clip_from_world, view_from_world]
        );
        crate::assert_wgsl_layout!(
            crate::shaders::ALL,
            OutlineUniforms,
            "OutlineParams",
            [color, radius_px, cos_crease, depth_ratio, _pad]
        );
    }

    #[test]
    fn settings_are_sanitized() {
        let s = OutlineSettings {
            width_px: f32::NAN,
            color: [2.0, -1.0, 0.5],
            opacity: 7.0,
            crease_angle_deg: 0.0,
            depth_ratio: -1.0,
        }
        .sanitized();
        assert_eq!(s.width_px, 3.0);
        assert_eq!(s.color, [1.0, 0.0, 0.5]);
        assert_eq!(s.opacity, 1.0);
        assert_eq!(s.crease_angle_deg, 1.0);
        assert_eq!(s.depth_ratio, 1e-4);
    }

    /// A `w × h` G-buffer whose left half is `left` and right half `right`, and its
    /// 1-pixel outline mask.
    fn halves(w: u32, h: u32, left: [f32; 4], right: [f32; 4]) -> (Vec<[f32; 4]>, Vec<bool>) {
        let g: Vec<[f32; 4]> = (0..w * h)
            .map(|i| if i % w < w / 2 { left } else { right })
            .collect();
        let s = OutlineSettings {
            width_px: 1.0,
            ..Default::default()
        };
        let m = outline_mask_cpu(w, h, &g, &s).unwrap();
        (g, m)
    }

    #[test]
    fn cpu_mask_marks_the_near_side_of_a_step() {
        // Left half at depth 1 facing the camera, right half at depth 2.
        let (w, h) = (8u32, 4u32);
        let (g, m) = halves(w, h, [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 2.0]);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(m[(y * w + x) as usize], x == 3, "({x}, {y})");
            }
        }
        assert!(outline_mask_cpu(w, h, &g[1..], &OutlineSettings::default()).is_none());
    }

    #[test]
    fn cpu_mask_marks_creases_once() {
        // Two planes at equal depth meeting at x = 4 with normals 90° apart.
        let (w, h) = (8u32, 3u32);
        let (_, m) = halves(w, h, [0.0, 0.0, 1.0, 1.0], [1.0, 0.0, 0.0, 1.0]);
        // Equal depth: both sides count as "no nearer", so both sides of the crease.
        let row: Vec<bool> = (0..w).map(|x| m[(w + x) as usize]).collect();
        assert_eq!(row, [false, false, false, true, true, false, false, false]);
    }
}
