//! The inputs of the hatching pass for 3-D scenes (§2 of Kim & Lee, "Real-time
//! Image-space Hatching", 2008): a variance shadow map (W. Donnelly and A. Lauritzen,
//! "Variance Shadow Maps", Proc. Symposium on Interactive 3D Graphics and Games 2006,
//! pp. 161–165; the paper's reference \[4\]) for a directional or spot light, then a
//! G-buffer of per-pixel tone (Phong shading with the VSM shadows) and stroke direction θ
//! (a per-vertex surface direction, e.g. a principal curvature direction, projected to the
//! screen). WGSL: `shaders/hatching_scene.wgsl`, `shaders/vsm_blur.wgsl`.
//!
//! The same shading as colour ([`ScenePasses::record_phong`]) is the baseline the
//! benchmark compares the hatching frame against.

use crate::HatchError;
use crate::pass::{ANCHOR_FORMAT, GBUFFER_FORMAT, GBuffer};
use glam::{Mat4, Vec3};
use npr_gpu::render::{self, PipelineBuilder};
use npr_gpu::{Camera, FrameUniforms, GpuMesh, Light, ObjectUniforms, Vertex};
use std::sync::atomic::{AtomicU64, Ordering};
use wgpu::util::DeviceExt;

/// Default frames between re-takes of a surface anchor's reference view
/// ([`ScenePasses::anchor_period`]). Shorter periods track zoom more closely (the visible
/// pattern's reference view is on average one period old, so its stroke density lags the
/// screen scale by one period of zoom) but cross-fade faster. On the benchmark's 2× dolly
/// over 24 frames, 4 frames keep the stroke density within about 10 % with no more
/// flicker than the paper's mode (`cargo xtask bench hatching-coherence`).
pub const DEFAULT_ANCHOR_PERIOD: u32 = 4;

/// Size of `Anchor` in `hatching_scene.wgsl`: two clip-from-world and two
/// world-from-object matrices.
const ANCHOR_BYTES: u64 = std::mem::size_of::<AnchorUniforms>() as u64;

/// `Anchor` in `hatching_scene.wgsl`: the two reference views' clip-from-world, then the
/// object's world-from-object at each (filled by buffer copies, see
/// [`ScenePasses::record_gbuffer`]).
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
/// Size of one `mat4x4<f32>`; both `FrameUniforms::clip_from_world` and
/// `ObjectUniforms::world_from_object` sit at offset 0 of their buffers.
const MAT4_BYTES: u64 = 64;
/// "Never anchored" in [`HatchObject`]'s reference-frame slots.
const UNANCHORED: u64 = u64::MAX;

/// Format of the variance shadow map's moments.
pub const MOMENTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The light that casts the variance shadow map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowLight {
    /// A directional light, shining from `towards_light`; the shadow map is an
    /// orthographic box around the sphere (`center`, `radius`) that holds the scene.
    Directional {
        /// Direction from the scene towards the light.
        towards_light: Vec3,
        /// Centre of the scene's bounding sphere (world).
        center: Vec3,
        /// Radius of the scene's bounding sphere (world, > 0).
        radius: f32,
    },
    /// A spot light at `position` aimed at `target`, lighting a cone of half-angle
    /// `outer_angle_rad` (full strength inside `inner_angle_rad`), reaching `range`.
    Spot {
        /// Light position (world).
        position: Vec3,
        /// Point the cone's axis passes through.
        target: Vec3,
        /// Half-angle where the light falls to zero, radians in (0, π/2).
        outer_angle_rad: f32,
        /// Half-angle of full strength, radians, ≤ `outer_angle_rad`.
        inner_angle_rad: f32,
        /// Farthest lit distance (world, > 0); also the shadow map's far plane.
        range: f32,
    },
}

impl ShadowLight {
    /// The light as the shading uniforms see it (white, ambient 0.1).
    pub fn light(&self) -> Light {
        match *self {
            Self::Directional { towards_light, .. } => Light::directional(towards_light),
            Self::Spot { position, .. } => Light::point(position),
        }
    }

    /// World → light clip space (depth 0..1).
    pub fn light_clip_from_world(&self) -> Mat4 {
        match *self {
            Self::Directional {
                towards_light,
                center,
                radius,
            } => {
                let r = radius.max(1e-4);
                let dir = towards_light.normalize_or(Vec3::Y);
                let up = if dir.cross(Vec3::Y).length_squared() < 1e-6 {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                let view =
                    glam::camera::rh::view::look_at_mat4(center + dir * (2.0 * r), center, up);
                glam::camera::rh::proj::directx::orthographic(-r, r, -r, r, 0.5 * r, 3.5 * r) * view
            }
            Self::Spot {
                position,
                target,
                outer_angle_rad,
                range,
                ..
            } => {
                let dir = (target - position).normalize_or(Vec3::NEG_Y);
                let up = if dir.cross(Vec3::Y).length_squared() < 1e-6 {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                let view = glam::camera::rh::view::look_at_mat4(position, position + dir, up);
                let fov = (2.0 * outer_angle_rad).clamp(0.01, 3.0);
                let far = range.max(1e-3);
                glam::camera::rh::proj::directx::perspective(fov, 1.0, far * 1e-3, far) * view
            }
        }
    }
}

/// Variance-shadow-map settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VsmSettings {
    /// Side of the square shadow map in texels (≥ 16).
    pub size: u32,
    /// Blur the moments (5-tap binomial, separable) before shading.
    pub blur: bool,
    /// Minimum variance (Donnelly & Lauritzen §3.1), in squared light-depth units.
    pub min_variance: f32,
    /// Light-bleeding reduction in [0, 1): visibilities below it become 0.
    pub light_bleed_reduction: f32,
    /// `false` turns shadows off (visibility 1 everywhere).
    pub enabled: bool,
}

impl Default for VsmSettings {
    /// 1024², blurred, minimum variance 1e-5, bleeding reduction 0.3.
    fn default() -> Self {
        Self {
            size: 1024,
            blur: true,
            min_variance: 1e-5,
            light_bleed_reduction: 0.3,
            enabled: true,
        }
    }
}

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

/// One object of a hatched scene: its uniform buffer and bind group, its per-vertex
/// stroke directions as a second vertex buffer (`@location(3)`), and its two surface
/// anchors' reference views ([`crate::StrokeSpace::Surface`]).
#[derive(Debug)]
pub struct HatchObject {
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    directions: wgpu::Buffer,
    vertex_count: u32,
    anchor: wgpu::Buffer,
    /// The frame index each anchor slot's reference view was taken at.
    anchored: [AtomicU64; 2],
}

impl HatchObject {
    /// Writes new object uniforms (transform, material).
    pub fn update(&self, queue: &wgpu::Queue, uniforms: &ObjectUniforms) {
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
    }

    /// Number of render vertices the directions were given for.
    pub fn vertex_count(&self) -> u32 {
        self.vertex_count
    }
}

/// The shadow, G-buffer and Phong + VSM passes. Create once per device; per frame call
/// [`ScenePasses::set_frame`], then record [`ScenePasses::record_shadow`] and
/// [`ScenePasses::record_gbuffer`] (hatching) or [`ScenePasses::record_phong`]
/// (baseline). Nothing here submits.
#[derive(Debug)]
pub struct ScenePasses {
    shadow_pipeline: wgpu::RenderPipeline,
    gbuffer_pipeline: wgpu::RenderPipeline,
    phong_pipeline: wgpu::RenderPipeline,
    blur_h: wgpu::RenderPipeline,
    blur_v: wgpu::RenderPipeline,
    object_layout: wgpu::BindGroupLayout,
    frame_buffer: wgpu::Buffer,
    scene_buffer: wgpu::Buffer,
    coherence_buffer: wgpu::Buffer,
    /// Frames set so far ([`ScenePasses::set_frame`] calls).
    frames: AtomicU64,
    anchor_period: u32,
    frame_group: wgpu::BindGroup,
    moments_group: wgpu::BindGroup,
    blur_from_moments: wgpu::BindGroup,
    blur_from_scratch: wgpu::BindGroup,
    moments_view: wgpu::TextureView,
    scratch_view: wgpu::TextureView,
    shadow_depth_view: wgpu::TextureView,
    vsm: VsmSettings,
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

impl ScenePasses {
    /// Builds the passes: the G-buffer pass writes [`GBUFFER_FORMAT`], the Phong pass
    /// `color_format`, both with [`npr_gpu::DEPTH_FORMAT`] depth.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a shadow map size below 16 or above the device
    /// limit.
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        vsm: VsmSettings,
    ) -> Result<Self, HatchError> {
        let max = device.limits().max_texture_dimension_2d;
        if vsm.size < 16 || vsm.size > max {
            return Err(HatchError::InvalidSize {
                width: vsm.size,
                height: vsm.size,
                reason: "shadow map side must be in 16..=max_texture_dimension_2d",
            });
        }
        let module = crate::shaders::HATCHING_SCENE.module(device);
        let blur_module = crate::shaders::VSM_BLUR.module(device);
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
        let shadow_layout =
            render::pipeline_layout(device, "npr vsm shadow", &[&frame_layout, &object_layout]);
        let shade_layout = render::pipeline_layout(
            device,
            "npr hatching shade",
            &[&frame_layout, &object_layout, &moments_layout],
        );
        let blur_layout = render::pipeline_layout(device, "npr vsm blur", &[&moments_layout]);
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
        let scene_buffers = [Some(Vertex::layout()), Some(direction_layout)];
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
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr hatching frame"),
            size: std::mem::size_of::<FrameUniforms>() as u64,
            usage: render::UNIFORM_USAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let scene_buffer = render::uniform_buffer(
            device,
            "npr hatching scene",
            std::mem::size_of::<SceneUniforms>(),
        );
        let coherence_buffer = render::uniform_buffer(
            device,
            "npr hatching coherence",
            std::mem::size_of::<CoherenceUniforms>(),
        );
        let frame_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr hatching frame"),
            layout: &frame_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: scene_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: coherence_buffer.as_entire_binding(),
                },
            ],
        });
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
            shadow_pipeline,
            gbuffer_pipeline,
            phong_pipeline,
            blur_h: blur("fs_blur_h"),
            blur_v: blur("fs_blur_v"),
            frame_group,
            moments_group: texture_group(device, &moments_layout, &moments_view),
            blur_from_moments: texture_group(device, &moments_layout, &moments_view),
            blur_from_scratch: texture_group(device, &moments_layout, &scratch_view),
            object_layout,
            frame_buffer,
            scene_buffer,
            coherence_buffer,
            frames: AtomicU64::new(0),
            anchor_period: DEFAULT_ANCHOR_PERIOD,
            moments_view,
            scratch_view,
            shadow_depth_view,
            vsm,
        })
    }

    /// Creates an object: `uniforms` (transform, material) and one stroke direction per
    /// render vertex of `mesh`, in object space (e.g. `dir_kappa_max` of a curvature
    /// field mapped to render vertices). Directions need not be unit length or
    /// consistently signed (θ is a line field); a non-finite direction becomes zero and
    /// its pixels get θ = 0.
    ///
    /// # Errors
    /// [`HatchError::LengthMismatch`] when `directions.len()` differs from the mesh's
    /// vertex count.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        mesh: &GpuMesh,
        uniforms: &ObjectUniforms,
        directions: &[Vec3],
    ) -> Result<HatchObject, HatchError> {
        if directions.len() != mesh.vertex_count as usize {
            return Err(HatchError::LengthMismatch {
                what: "stroke directions (one per render vertex)",
                expected: mesh.vertex_count as usize,
                actual: directions.len(),
            });
        }
        let clean: Vec<[f32; 3]> = directions
            .iter()
            .map(|d| {
                if d.is_finite() {
                    d.to_array()
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        let directions = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("npr hatching directions"),
            contents: bytemuck::cast_slice(&clean),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("npr hatching object"),
            contents: bytemuck::bytes_of(uniforms),
            usage: render::UNIFORM_USAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let anchor = render::uniform_buffer(device, "npr hatching anchor", ANCHOR_BYTES as usize);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr hatching object"),
            layout: &self.object_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: anchor.as_entire_binding(),
                },
            ],
        });
        Ok(HatchObject {
            uniforms: buffer,
            bind_group,
            directions,
            vertex_count: mesh.vertex_count,
            anchor,
            anchored: [AtomicU64::new(UNANCHORED), AtomicU64::new(UNANCHORED)],
        })
    }

    /// Frames between re-takes of each surface anchor's reference view (default
    /// [`DEFAULT_ANCHOR_PERIOD`]). The two anchors are re-taken in turn, each living two
    /// periods and cross-faded linearly, so a stroke pattern is never more than two periods
    /// old and never pops (its weight is 0 when it is re-taken).
    pub fn anchor_period(&self) -> u32 {
        self.anchor_period
    }

    /// Sets [`ScenePasses::anchor_period`].
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] for 0.
    pub fn set_anchor_period(&mut self, frames: u32) -> Result<(), HatchError> {
        if frames == 0 {
            return Err(HatchError::InvalidParams {
                what: "anchor_period",
                reason: "at least 1 frame".to_string(),
            });
        }
        self.anchor_period = frames;
        Ok(())
    }

    /// Index of the frame last set by [`ScenePasses::set_frame`] (0 for the first).
    pub fn frame_index(&self) -> u64 {
        self.frames.load(Ordering::Relaxed).saturating_sub(1)
    }

    /// The anchor slot re-taken most recently at frame `c`, the frame it was taken at, and
    /// its weight (the other slot, taken one period earlier, gets 1 − weight).
    fn anchor_phase(&self, c: u64) -> (usize, u64, f32) {
        let n = u64::from(self.anchor_period);
        let slot = ((c / n) % 2) as usize;
        let taken = c - c % n;
        (slot, taken, (c % n) as f32 / n as f32)
    }

    /// The weight of anchor 1 at frame `c` (anchor 0 gets 1 − it).
    fn weight_b(&self, c: u64) -> f32 {
        let (slot, _, w) = self.anchor_phase(c);
        if slot == 1 { w } else { 1.0 - w }
    }

    /// The weight of anchor 1 that [`ScenePasses::record_gbuffer`] writes on every
    /// surface pixel of the frame last set by [`ScenePasses::set_frame`] (0 before the
    /// first): 0 or 1 outside the anchors' cross-fade, where the hatching pass reads one
    /// anchor only ([`crate::HatchPass::record_scene`]).
    pub fn anchor_weight(&self) -> f32 {
        match self.frames.load(Ordering::Relaxed).checked_sub(1) {
            Some(c) => self.weight_b(c),
            None => 0.0,
        }
    }

    /// Writes the frame's camera, light and viewport size (pixels of the G-buffer or
    /// colour target drawn next), and advances the frame counter that schedules the
    /// surface anchors' reference views ([`ScenePasses::anchor_period`]): call once per
    /// displayed frame.
    pub fn set_frame(
        &self,
        queue: &wgpu::Queue,
        camera: &Camera,
        light: &ShadowLight,
        viewport: (u32, u32),
    ) {
        let c = self.frames.fetch_add(1, Ordering::Relaxed);
        let weight_b = self.weight_b(c);
        queue.write_buffer(
            &self.coherence_buffer,
            0,
            bytemuck::bytes_of(&CoherenceUniforms {
                weights: [weight_b, 0.0, 0.0, 0.0],
            }),
        );
        let frame = FrameUniforms::new(camera, &light.light());
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
        let scene = SceneUniforms {
            light_clip_from_world: light.light_clip_from_world().to_cols_array_2d(),
            light_pos,
            spot,
            vsm: [
                self.vsm.min_variance,
                self.vsm.light_bleed_reduction.clamp(0.0, 0.999),
                self.vsm.size as f32,
                if self.vsm.enabled { 1.0 } else { 0.0 },
            ],
            viewport: [viewport.0 as f32, viewport.1 as f32, inner, 0.0],
        };
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
        queue.write_buffer(&self.scene_buffer, 0, bytemuck::bytes_of(&scene));
    }

    /// Records the variance shadow map: the moments of light depth of every object
    /// (cleared to the far plane), then the optional separable blur.
    pub fn record_shadow(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        if !self.vsm.enabled {
            return;
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
            pass.set_bind_group(0, &self.frame_group, &[]);
            for (mesh, object) in objects {
                pass.set_bind_group(1, &object.bind_group, &[]);
                mesh.draw(&mut pass);
            }
        }
        if self.vsm.blur {
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
    }

    fn draw_objects(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipeline: &wgpu::RenderPipeline,
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.frame_group, &[]);
        pass.set_bind_group(2, &self.moments_group, &[]);
        for (mesh, object) in objects {
            pass.set_bind_group(1, &object.bind_group, &[]);
            pass.set_vertex_buffer(1, object.directions.slice(..));
            mesh.draw(pass);
        }
    }

    /// Re-takes the reference views that the current frame's anchor slots need and do
    /// not hold yet: copies of this frame's camera and the object's transform (buffer
    /// copies recorded into `encoder`, so they see the values written for this frame).
    fn record_anchors(&self, encoder: &mut wgpu::CommandEncoder, object: &HatchObject) {
        let c = self.frame_index();
        let (slot, taken, _) = self.anchor_phase(c);
        let n = u64::from(self.anchor_period);
        // The other slot was taken one period earlier (none before the first period: it
        // is then taken now, once).
        let other_taken = taken.checked_sub(n);
        for (s, want) in [(slot, Some(taken)), (1 - slot, other_taken)] {
            let have = object.anchored[s].load(Ordering::Relaxed);
            let stale = match want {
                Some(t) => have != t,
                None => have == UNANCHORED,
            };
            if !stale {
                continue;
            }
            let o = s as u64 * MAT4_BYTES;
            let clip = std::mem::offset_of!(AnchorUniforms, clip_from_world) as u64;
            let world = std::mem::offset_of!(AnchorUniforms, world_from_object) as u64;
            encoder.copy_buffer_to_buffer(
                &self.frame_buffer,
                0,
                &object.anchor,
                clip + o,
                MAT4_BYTES,
            );
            encoder.copy_buffer_to_buffer(
                &object.uniforms,
                0,
                &object.anchor,
                world + o,
                MAT4_BYTES,
            );
            object.anchored[s].store(want.unwrap_or(c), Ordering::Relaxed);
        }
    }

    /// Records the G-buffer pass: tone, θ and surface anchors of every object into
    /// `gbuffer`, cleared to tone 1 (paper), θ 0, no surface. Record
    /// [`ScenePasses::record_shadow`] first.
    pub fn record_gbuffer(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        gbuffer: &GBuffer,
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        for (_, object) in objects {
            self.record_anchors(encoder, object);
        }
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
        self.draw_objects(&mut pass, &self.gbuffer_pipeline, objects);
    }

    /// Records the baseline: the same Phong shading with the same VSM, as colour, into
    /// `color` (the `color_format` of [`ScenePasses::new`]) with `depth`, cleared to
    /// `clear` (linear RGBA). Record [`ScenePasses::record_shadow`] first.
    pub fn record_phong(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        clear: [f64; 4],
        objects: &[(&GpuMesh, &HatchObject)],
    ) {
        let mut pass = render::begin_pass(
            encoder,
            "npr phong + vsm",
            &[Some(render::color_attachment(
                color,
                render::clear_color(clear),
            ))],
            Some(depth_attachment(depth)),
        );
        self.draw_objects(&mut pass, &self.phong_pipeline, objects);
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

    #[test]
    fn light_matrices_are_finite_for_degenerate_lights() {
        for l in [
            ShadowLight::Directional {
                towards_light: Vec3::ZERO,
                center: Vec3::ZERO,
                radius: 0.0,
            },
            ShadowLight::Directional {
                towards_light: Vec3::Y,
                center: Vec3::ONE,
                radius: 2.0,
            },
            ShadowLight::Spot {
                position: Vec3::ZERO,
                target: Vec3::ZERO,
                outer_angle_rad: 0.0,
                inner_angle_rad: 0.0,
                range: 0.0,
            },
        ] {
            assert!(l.light_clip_from_world().is_finite(), "{l:?}");
        }
    }
}
