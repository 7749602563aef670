//! The inputs of the hatching pass for 3-D scenes (§2 of Kim & Lee, "Real-time
//! Image-space Hatching", 2008): a variance shadow map (W. Donnelly and A. Lauritzen,
//! "Variance Shadow Maps", Proc. Symposium on Interactive 3D Graphics and Games 2006,
//! pp. 161–165; the paper's reference \[4\]) for a directional or spot light, then a
//! G-buffer of per-pixel tone (Phong shading with the VSM shadows) and stroke direction θ
//! (a per-vertex surface direction, e.g. a principal curvature direction, projected to the
//! screen). WGSL: `shaders/hatching_scene.wgsl`, `shaders/vsm_blur.wgsl`.
//!
//! The same shading as colour ([`ScenePasses::draw`], the Phong + VSM baseline) is the baseline the
//! benchmark compares the hatching frame against.

//!
//! On the pass contract ([`npr_gpu::pass`]): [`ScenePasses::new`],
//! [`ScenePasses::create_object`], [`ScenePasses::prepare`] per object and frame, then
//! the stages [`ScenePasses::record_shadow`] and [`ScenePasses::record_gbuffer`] (into
//! the pass's own shadow map and the caller's [`GBuffer`]) and [`ScenePasses::draw`]
//! (the baseline, into the caller's render pass).

mod anchor;
mod light;

use anchor::{clean_direction, copy_snapshots};

pub use light::{MOMENTS_FORMAT, ShadowLight, VsmSettings};

use crate::HatchError;
use crate::pass::{ANCHOR_FORMAT, GBUFFER_FORMAT, GBuffer};
use glam::Vec3;
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};
use npr_gpu::render::{self, PipelineBuilder};
use npr_gpu::{Camera, FrameUniforms, GpuMesh, ObjectUniforms, TargetFormats, Vertex};
use wgpu::util::DeviceExt;

/// Default frames between re-takes of a surface anchor's reference view
/// ([`SceneSettings::anchor_period`]). Shorter periods track zoom more closely (the visible
/// pattern's reference view is on average one period old, so its stroke density lags the
/// screen scale by one period of zoom) but cross-fade faster. On the benchmark's 2× dolly
/// over 24 frames, 4 frames keep the stroke density within about 10 % with no more
/// flicker than the paper's mode (`cargo xtask bench hatching-coherence`).
pub const DEFAULT_ANCHOR_PERIOD: u32 = 4;

/// `Anchor` in `hatching_scene.wgsl`: the two reference views' clip-from-world, then the
/// object's world-from-object at each (written by [`ScenePasses::prepare`] when a
/// reference view is re-taken).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct AnchorUniforms {
    clip_from_world: [[[f32; 4]; 4]; 2],
    world_from_object: [[[f32; 4]; 4]; 2],
}

/// `Coherence` in `hatching_scene.wgsl`: x = weight of anchor 1 in the cross-fade.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CoherenceUniforms {
    weights: [f32; 4],
}

/// Size of one `mat4x4<f32>`.
const MAT4_BYTES: u64 = 64;

/// `Scene` in `hatching_scene.wgsl` (128 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct SceneUniforms {
    light_clip_from_world: [[f32; 4]; 4],
    light_pos: [f32; 4],
    spot: [f32; 4],
    vsm: [f32; 4],
    viewport: [f32; 4],
}

/// The scene passes' settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneSettings {
    /// The variance shadow map.
    pub vsm: VsmSettings,
    /// Frames between re-takes of each surface anchor's reference view (≥ 1; default
    /// [`DEFAULT_ANCHOR_PERIOD`]). The two anchors are re-taken in turn, each living two
    /// periods and cross-faded linearly, so a stroke pattern is never more than two
    /// periods old and never pops (its weight is 0 when it is re-taken).
    pub anchor_period: u32,
}

impl Default for SceneSettings {
    fn default() -> Self {
        Self {
            vsm: VsmSettings::default(),
            anchor_period: DEFAULT_ANCHOR_PERIOD,
        }
    }
}

/// One object's per-frame input to [`ScenePasses::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct SceneInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The displayed-frame count that schedules the surface anchors' reference views
    /// ([`SceneSettings::anchor_period`]): advance it by one per displayed frame, keep it
    /// for a second view of the same frame.
    pub clock: u64,
    /// The camera.
    pub camera: &'a Camera,
    /// The light and its shadow map's frustum.
    pub light: &'a ShadowLight,
    /// Pixels of the G-buffer or colour target drawn next.
    pub viewport: (u32, u32),
    /// Transform and material.
    pub object: &'a ObjectUniforms,
}

/// One prepare's GPU state: frame, scene and coherence uniforms (group 0), the object's
/// uniforms and its anchors (group 1).
#[derive(Debug)]
struct SceneSlot {
    frame: wgpu::Buffer,
    scene: wgpu::Buffer,
    coherence: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    object: wgpu::Buffer,
    anchor: wgpu::Buffer,
    object_group: wgpu::BindGroup,
    /// The clock each anchor of this slot's reference views was taken at.
    anchored: [Option<u64>; 2],
    /// The mesh's vertices as they were when each anchor was taken (`@location(4)` and
    /// `(5)`): a posed mesh's surface point is anchored where it was then, not where it
    /// is now, so strokes move with a deforming surface.
    snapshots: [wgpu::Buffer; 2],
    /// The anchors this slot's last prepare re-took, whose snapshots the next record
    /// copies from the mesh.
    copy_due: [bool; 2],
}

/// One object of a hatched scene: the caller's mesh (shared, not copied), its per-vertex
/// stroke directions as a second vertex buffer (`@location(3)`), and per-frame slots with
/// its uniforms and its two surface anchors' reference views
/// ([`crate::StrokeSpace::Surface`]).
#[derive(Debug)]
pub struct HatchObject {
    mesh: GpuMesh,
    directions: wgpu::Buffer,
    slots: Slots<SceneSlot>,
}

impl HatchObject {
    /// Number of render vertices the directions were given for.
    pub fn vertex_count(&self) -> u32 {
        self.mesh.vertex_count
    }
}

/// The shadow, G-buffer and Phong + VSM passes. Create once per device; per frame
/// [`ScenePasses::prepare`] each object, then record [`ScenePasses::record_shadow`] and
/// [`ScenePasses::record_gbuffer`] (hatching) or [`ScenePasses::draw`] (baseline).
/// Nothing here submits.
#[derive(Debug)]
pub struct ScenePasses {
    id: PassId,
    device: wgpu::Device,
    shadow_pipeline: wgpu::RenderPipeline,
    gbuffer_pipeline: wgpu::RenderPipeline,
    phong_pipeline: wgpu::RenderPipeline,
    blur_h: wgpu::RenderPipeline,
    blur_v: wgpu::RenderPipeline,
    frame_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    moments_group: wgpu::BindGroup,
    blur_from_moments: wgpu::BindGroup,
    blur_from_scratch: wgpu::BindGroup,
    moments_view: wgpu::TextureView,
    scratch_view: wgpu::TextureView,
    shadow_depth_view: wgpu::TextureView,
    settings: SceneSettings,
}

fn texture_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    npr_gpu::layout::texture_layout(
        device,
        label,
        wgpu::TextureViewDimension::D2,
        npr_gpu::layout::UNFILTERABLE,
    )
}

fn texture_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    view: &wgpu::TextureView,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("npr hatching texture"),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(view),
        }],
    })
}

/// The vertex layout of the stroke directions (`@location(3)`, one `vec3<f32>` per vertex).
const DIRECTION_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![3 => Float32x3];
/// The positions of the two anchors' vertex snapshots (`@location(4)`, `(5)`), read from
/// buffers laid out as the mesh's [`Vertex`] (position first).
const ANCHOR_POSITION_ATTRIBUTES: [[wgpu::VertexAttribute; 1]; 2] = [
    wgpu::vertex_attr_array![4 => Float32x3],
    wgpu::vertex_attr_array![5 => Float32x3],
];

impl ScenePasses {
    /// Builds the passes: the G-buffer pass writes [`GBUFFER_FORMAT`], the Phong pass
    /// `formats.color`, both with [`npr_gpu::DEPTH_FORMAT`] depth; and the shadow map.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a shadow map size below 16 or above the device
    /// limit; [`HatchError::InvalidParams`] for an anchor period of 0.
    pub fn new(
        device: &wgpu::Device,
        _queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &SceneSettings,
    ) -> Result<Self, HatchError> {
        let vsm = settings.vsm;
        let max = device.limits().max_texture_dimension_2d;
        if vsm.size < 16 || vsm.size > max {
            return Err(HatchError::InvalidSize {
                width: vsm.size,
                height: vsm.size,
                reason: "shadow map side must be in 16..=max_texture_dimension_2d",
            });
        }
        if settings.anchor_period == 0 {
            return Err(HatchError::InvalidParams {
                what: "anchor_period",
                reason: "at least 1 frame".to_string(),
            });
        }
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr hatching frame"),
            entries: &[
                npr_gpu::layout::uniform_entry(0),
                npr_gpu::layout::uniform_entry(1),
                npr_gpu::layout::uniform_entry(2),
            ],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr hatching object"),
            entries: &[
                npr_gpu::layout::uniform_entry(0),
                npr_gpu::layout::uniform_entry(1),
            ],
        });
        let moments_layout = texture_layout(device, "npr vsm moments");
        let pipelines = Pipelines::new(
            device,
            formats.color,
            [&frame_layout, &object_layout, &moments_layout],
        );
        let map = |label, format, usage| {
            npr_gpu::texture_2d(device, label, vsm.size, vsm.size, format, usage)
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let moments_view = map("npr vsm moments", MOMENTS_FORMAT, rt);
        let scratch_view = map("npr vsm blur scratch", MOMENTS_FORMAT, rt);
        let shadow_depth_view = map(
            "npr vsm depth",
            npr_gpu::DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        Ok(Self {
            id: PassId::fresh(),
            device: device.clone(),
            shadow_pipeline: pipelines.shadow,
            gbuffer_pipeline: pipelines.gbuffer,
            phong_pipeline: pipelines.phong,
            blur_h: pipelines.blur_h,
            blur_v: pipelines.blur_v,
            moments_group: texture_group(device, &moments_layout, &moments_view),
            blur_from_moments: texture_group(device, &moments_layout, &moments_view),
            blur_from_scratch: texture_group(device, &moments_layout, &scratch_view),
            frame_layout,
            object_layout,
            moments_view,
            scratch_view,
            shadow_depth_view,
            settings: *settings,
        })
    }

    /// The settings the passes were built with.
    pub fn settings(&self) -> &SceneSettings {
        &self.settings
    }

    /// Creates an object: one stroke direction per render vertex of `mesh`, in object
    /// space (e.g. `dir_kappa_max` of a curvature field mapped to render vertices).
    /// Directions need not be unit length or consistently signed (θ is a line field); a
    /// non-finite direction becomes zero and its pixels get θ = 0. The mesh's buffers are
    /// shared with the caller, not copied.
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] when `directions.len()` differs from the mesh's
    /// vertex count.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        mesh: &GpuMesh,
        directions: &[Vec3],
    ) -> Result<HatchObject, HatchError> {
        if directions.len() != mesh.vertex_count as usize {
            return Err(HatchError::LengthMismatch {
                what: "stroke directions (one per render vertex)",
                expected: mesh.vertex_count as usize,
                actual: directions.len(),
            });
        }
        let clean: Vec<[f32; 3]> = directions.iter().map(|d| clean_direction(*d)).collect();
        let directions = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("npr hatching directions"),
            contents: bytemuck::cast_slice(&clean),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        });
        Ok(HatchObject {
            mesh: mesh.clone(),
            directions,
            slots: Slots::new(self.id),
        })
    }

    fn create_slot(&self, vertex_bytes: u64) -> SceneSlot {
        let device = &self.device;
        let uniform = |label, size| render::uniform_buffer(device, label, size);
        let frame = uniform("npr hatching frame", std::mem::size_of::<FrameUniforms>());
        let scene = uniform("npr hatching scene", std::mem::size_of::<SceneUniforms>());
        let coherence = uniform(
            "npr hatching coherence",
            std::mem::size_of::<CoherenceUniforms>(),
        );
        let object = uniform("npr hatching object", std::mem::size_of::<ObjectUniforms>());
        let anchor = uniform("npr hatching anchor", std::mem::size_of::<AnchorUniforms>());
        let group = |label, layout, buffers: &[&wgpu::Buffer]| {
            let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: b.as_entire_binding(),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries: &entries,
            })
        };
        SceneSlot {
            frame_group: group(
                "npr hatching frame",
                &self.frame_layout,
                &[&frame, &scene, &coherence],
            ),
            object_group: group(
                "npr hatching object",
                &self.object_layout,
                &[&object, &anchor],
            ),
            frame,
            scene,
            coherence,
            object,
            anchor,
            anchored: [None; 2],
            snapshots: [0, 1].map(|_| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("npr hatching anchor vertices"),
                    size: vertex_bytes,
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            }),
            copy_due: [false; 2],
        }
    }

    /// Writes one object's camera, light, viewport, transform and material into a fresh
    /// slot, and re-takes the reference views that the slot's anchors need at
    /// `input.clock` and do not hold yet (this frame's camera and transform).
    ///
    /// # Errors
    /// [`HatchError::Pass`] for an object of another pass or too many prepares in one
    /// frame.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut HatchObject,
        input: &SceneInput<'_>,
    ) -> Result<Prepared, HatchError> {
        let vertex_bytes = object.mesh.vertex_buffer.size();
        let (prepared, slot) = object
            .slots
            .next(self.id, input.frame, || self.create_slot(vertex_bytes))?;
        let c = input.clock;
        let coherence = CoherenceUniforms {
            weights: [self.anchor_weight(c), 0.0, 0.0, 0.0],
        };
        queue.write_buffer(&slot.coherence, 0, bytemuck::bytes_of(&coherence));
        let view = FrameUniforms::new(input.camera, &input.light.light());
        queue.write_buffer(&slot.frame, 0, bytemuck::bytes_of(&view));
        let scene = scene_uniforms(input.light, &self.settings.vsm, input.viewport);
        queue.write_buffer(&slot.scene, 0, bytemuck::bytes_of(&scene));
        queue.write_buffer(&slot.object, 0, bytemuck::bytes_of(input.object));
        slot.copy_due = [false; 2];
        self.retake_anchors(queue, slot, c, &view, input.object);
        Ok(prepared)
    }

    /// Records the variance shadow map: the moments of light depth of every prepared
    /// object (cleared to the far plane), then the optional separable blur.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for a `prepared` of another object, pass or frame.
    pub fn record_shadow(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        objects: &[(&HatchObject, &Prepared)],
    ) -> Result<(), HatchError> {
        let slots = self.slots(objects)?;
        copy_snapshots(encoder, objects, &slots);
        let vsm = &self.settings.vsm;
        if !vsm.enabled {
            return Ok(());
        }
        {
            let mut pass = render::begin_pass(
                encoder,
                "npr vsm shadow",
                &[Some(render::color_attachment(
                    &self.moments_view,
                    render::clear_color([1.0, 1.0, 0.0, 0.0]),
                ))],
                Some(depth_attachment(&self.shadow_depth_view)),
            );
            pass.set_pipeline(&self.shadow_pipeline);
            for (object, slot) in objects.iter().zip(&slots) {
                pass.set_bind_group(0, &slot.frame_group, &[]);
                pass.set_bind_group(1, &slot.object_group, &[]);
                object.0.mesh.draw(&mut pass);
            }
        }
        if vsm.blur {
            for (target, pipeline, source) in [
                (&self.scratch_view, &self.blur_h, &self.blur_from_moments),
                (&self.moments_view, &self.blur_v, &self.blur_from_scratch),
            ] {
                let mut pass = render::begin_color_pass(
                    encoder,
                    "npr vsm blur",
                    target,
                    wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                );
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, source, &[]);
                pass.draw(0..3, 0..1);
            }
        }
        Ok(())
    }

    fn slots<'o>(
        &self,
        objects: &[(&'o HatchObject, &Prepared)],
    ) -> Result<Vec<&'o SceneSlot>, HatchError> {
        objects
            .iter()
            .map(|(o, p)| o.slots.get(self.id, p).map_err(HatchError::from))
            .collect()
    }

    fn draw_slot(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        object: &HatchObject,
        slot: &SceneSlot,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &slot.frame_group, &[]);
        pass.set_bind_group(1, &slot.object_group, &[]);
        pass.set_bind_group(2, &self.moments_group, &[]);
        pass.set_vertex_buffer(1, object.directions.slice(..));
        pass.set_vertex_buffer(2, slot.snapshots[0].slice(..));
        pass.set_vertex_buffer(3, slot.snapshots[1].slice(..));
        object.mesh.draw(pass);
    }

    /// Records the G-buffer pass: tone, θ and surface anchors of every prepared object
    /// into `gbuffer`, cleared to tone 1 (paper), θ 0, no surface. Record
    /// [`ScenePasses::record_shadow`] first.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for a `prepared` of another object, pass or frame.
    pub fn record_gbuffer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        objects: &[(&HatchObject, &Prepared)],
    ) -> Result<(), HatchError> {
        let slots = self.slots(objects)?;
        copy_snapshots(encoder, objects, &slots);
        let mut pass = render::begin_pass(
            encoder,
            "npr hatching g-buffer",
            &[
                Some(render::color_attachment(
                    &gbuffer.view,
                    render::clear_color([1.0, 0.0, 0.0, 0.0]),
                )),
                Some(render::color_attachment(
                    &gbuffer.anchors_view,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )),
            ],
            Some(depth_attachment(&gbuffer.depth_view)),
        );
        for ((object, _), slot) in objects.iter().zip(slots) {
            self.draw_slot(&mut pass, &self.gbuffer_pipeline, object, slot);
        }
        Ok(())
    }

    /// Draws the baseline, the same Phong shading with the same VSM as colour, into the
    /// caller's render pass (colour of the `formats` given to [`ScenePasses::new`], with
    /// [`npr_gpu::DEPTH_FORMAT`] depth). Record [`ScenePasses::record_shadow`] first.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for a `prepared` of another object, pass or frame.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &HatchObject,
        prepared: &Prepared,
    ) -> Result<(), HatchError> {
        let slot = object.slots.get(self.id, prepared)?;
        self.draw_slot(pass, &self.phong_pipeline, object, slot);
        Ok(())
    }
}

npr_gpu::impl_pass!(ScenePasses, HatchObject, SceneInput, HatchError);

/// The `Scene` uniforms of a light, shadow map settings and viewport.
fn scene_uniforms(light: &ShadowLight, vsm: &VsmSettings, viewport: (u32, u32)) -> SceneUniforms {
    let (light_pos, spot, inner) = match *light {
        ShadowLight::Directional { .. } => ([0.0; 4], [0.0, 0.0, 0.0, -2.0], -1.0),
        ShadowLight::Spot {
            position,
            target,
            outer_angle_rad,
            inner_angle_rad,
            range,
        } => {
            let axis = (target - position).normalize_or(Vec3::NEG_Y);
            let outer = outer_angle_rad.cos();
            let inner = inner_angle_rad.min(outer_angle_rad).cos();
            (
                position.extend(1.0 / range.max(1e-6)).to_array(),
                axis.extend(outer).to_array(),
                // smoothstep needs edge0 < edge1.
                inner.max(outer + 1e-4),
            )
        }
    };
    SceneUniforms {
        light_clip_from_world: light.light_clip_from_world().to_cols_array_2d(),
        light_pos,
        spot,
        vsm: [
            vsm.min_variance,
            vsm.light_bleed_reduction.clamp(0.0, 0.999),
            vsm.size as f32,
            if vsm.enabled { 1.0 } else { 0.0 },
        ],
        viewport: [viewport.0 as f32, viewport.1 as f32, inner, 0.0],
    }
}

/// The five pipelines of the scene passes.
struct Pipelines {
    shadow: wgpu::RenderPipeline,
    gbuffer: wgpu::RenderPipeline,
    phong: wgpu::RenderPipeline,
    blur_h: wgpu::RenderPipeline,
    blur_v: wgpu::RenderPipeline,
}

impl Pipelines {
    fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        [frame_layout, object_layout, moments_layout]: [&wgpu::BindGroupLayout; 3],
    ) -> Self {
        let module = crate::shaders::HATCHING_SCENE.module(device);
        let blur_module = crate::shaders::VSM_BLUR.module(device);
        let shadow_layout =
            render::pipeline_layout(device, "npr vsm shadow", &[frame_layout, object_layout]);
        let shade_layout = render::pipeline_layout(
            device,
            "npr hatching shade",
            &[frame_layout, object_layout, moments_layout],
        );
        let blur_layout = render::pipeline_layout(device, "npr vsm blur", &[moments_layout]);
        let direction_layout = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &DIRECTION_ATTRIBUTES,
        };
        let mesh_pipeline = |label: &str,
                             layout: &wgpu::PipelineLayout,
                             (vs, fs): (&str, &str),
                             targets: &[Option<wgpu::ColorTargetState>],
                             buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                             cull: Option<wgpu::Face>| {
            PipelineBuilder::new(label, layout, &module, vs, fs)
                .buffers(buffers)
                .cull(cull)
                .depth(npr_gpu::DEPTH_FORMAT, true, wgpu::CompareFunction::Less)
                .targets(targets)
                .build(device)
        };
        let anchor_layout = |attributes| wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes,
        };
        let scene_buffers = [
            Some(Vertex::layout()),
            Some(direction_layout),
            Some(anchor_layout(&ANCHOR_POSITION_ATTRIBUTES[0])),
            Some(anchor_layout(&ANCHOR_POSITION_ATTRIBUTES[1])),
        ];
        // The shadow pass draws both faces so thin or open meshes still cast shadows.
        let shadow_pipeline = mesh_pipeline(
            "npr vsm shadow",
            &shadow_layout,
            ("vs_shadow", "fs_shadow"),
            &[Some(MOMENTS_FORMAT.into())],
            &[Some(Vertex::layout())],
            None,
        );
        let gbuffer_pipeline = mesh_pipeline(
            "npr hatching g-buffer",
            &shade_layout,
            ("vs_scene", "fs_gbuffer"),
            &[Some(GBUFFER_FORMAT.into()), Some(ANCHOR_FORMAT.into())],
            &scene_buffers,
            Some(wgpu::Face::Back),
        );
        let phong_pipeline = mesh_pipeline(
            "npr phong + vsm",
            &shade_layout,
            ("vs_scene", "fs_phong_vsm"),
            &[Some(color_format.into())],
            &scene_buffers,
            Some(wgpu::Face::Back),
        );
        let blur = |fs: &str| {
            PipelineBuilder::new(fs, &blur_layout, &blur_module, "vs_fullscreen", fs)
                .targets(&[Some(MOMENTS_FORMAT.into())])
                .build(device)
        };
        Self {
            shadow: shadow_pipeline,
            gbuffer: gbuffer_pipeline,
            phong: phong_pipeline,
            blur_h: blur("fs_blur_h"),
            blur_v: blur("fs_blur_v"),
        }
    }
}

fn depth_attachment(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    render::depth_attachment(view, wgpu::LoadOp::Clear(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_uniforms_match_wgsl() {
        // Size and member offsets read from `hatching_scene.wgsl` by naga.
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            SceneUniforms,
            "Scene",
            [light_clip_from_world, light_pos, spot, vsm, viewport]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            AnchorUniforms,
            "Anchor",
            [clip_from_world, world_from_object]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            CoherenceUniforms,
            "Coherence",
            [weights]
        );
    }
}
