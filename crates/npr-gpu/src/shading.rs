//! Base shading passes shared by all techniques: per-pixel Phong (Blinn-Phong, Lee & Choi
//! Eq. (2)–(3)), per-vertex Gouraud, and cel/toon shading with a 1-D ramp texture
//! (Lake, Marshall, Harris, Blackstein, "Stylized Rendering Techniques for Scalable
//! Real-Time 3D Animation", NPAR 2000). WGSL: `shaders/base_shading.wgsl`.

use crate::pass::{FrameId, PassError, PassId, Prepared, Slots};
use crate::render::{self, PipelineBuilder};
use crate::{FrameUniforms, GpuMesh, ObjectUniforms, TargetFormats, Vertex, shaders};
use wgpu::util::DeviceExt;

/// Which base shading model to draw with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShadingModel {
    /// Blinn-Phong evaluated per pixel.
    Phong,
    /// Blinn-Phong evaluated per vertex and interpolated.
    Gouraud,
    /// Cel shading: the ramp indexed by `max(N·L, 0)`, nearest filtering.
    Cel,
}

impl ShadingModel {
    /// All models, in a fixed order.
    pub const ALL: [ShadingModel; 3] = [Self::Phong, Self::Gouraud, Self::Cel];

    /// Lower-case name (for file names).
    pub fn name(self) -> &'static str {
        match self {
            Self::Phong => "phong",
            Self::Gouraud => "gouraud",
            Self::Cel => "cel",
        }
    }
}

/// A banded toon ramp as RGBA8 sRGB texels, `width` texels wide: `shades` split the
/// `N·L` range 0..1 into equal bands, darkest first (Lake et al. 2000).
pub fn toon_ramp(width: u32, shades: &[[u8; 4]]) -> Vec<[u8; 4]> {
    let bands = shades.len().max(1) as u32;
    (0..width)
        .map(|i| {
            let b = ((i * bands) / width.max(1)).min(bands - 1) as usize;
            shades.get(b).copied().unwrap_or([255; 4])
        })
        .collect()
}

/// Uploads ramp texels as a `width × 1` `Rgba8UnormSrgb` texture and returns its view.
pub fn upload_ramp(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texels: &[[u8; 4]],
) -> wgpu::TextureView {
    let width = texels.len().max(1) as u32;
    let mut data: Vec<u8> = texels.iter().flatten().copied().collect();
    if data.is_empty() {
        data = vec![255; 4];
    }
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("npr toon ramp"),
            size: wgpu::Extent3d {
                width,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &data,
    );
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// The default ramp: three shades (0.35, 0.65, 1.0 in sRGB) over 256 texels.
pub fn default_ramp() -> Vec<[u8; 4]> {
    toon_ramp(
        256,
        &[
            [89, 89, 89, 255],
            [166, 166, 166, 255],
            [255, 255, 255, 255],
        ],
    )
}

/// The base shading's settings: plain data, keyed by value (a change builds a new pass).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BaseSettings {
    /// The cel ramp's texels, darkest first (see [`toon_ramp`]).
    pub ramp: Vec<[u8; 4]>,
}

impl Default for BaseSettings {
    fn default() -> Self {
        Self {
            ramp: default_ramp(),
        }
    }
}

/// One draw's per-frame input to [`BaseShading::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct BaseInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// Camera and light.
    pub view: &'a FrameUniforms,
    /// Object transform and material.
    pub object: &'a ObjectUniforms,
    /// The shading model to draw with.
    pub model: ShadingModel,
}

/// One prepare's GPU state: frame (group 0) and object (group 1) uniforms.
#[derive(Debug)]
struct BaseSlot {
    frame: wgpu::Buffer,
    object: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    object_group: wgpu::BindGroup,
    model: ShadingModel,
}

/// One mesh drawn by [`BaseShading`]: the caller's buffers (shared, not copied) and the
/// per-frame slots.
#[derive(Debug)]
pub struct BaseObject {
    mesh: GpuMesh,
    slots: Slots<BaseSlot>,
}

impl BaseObject {
    /// The mesh this object draws.
    pub fn mesh(&self) -> &GpuMesh {
        &self.mesh
    }
}

/// The base shading passes (Phong, Gouraud, cel), following the pass contract
/// ([`crate::pass`]): [`BaseShading::new`], [`BaseShading::create_object`],
/// [`BaseShading::prepare`], [`BaseShading::draw`].
///
/// Bind groups: 0 = frame ([`FrameUniforms`]), 1 = object ([`ObjectUniforms`]), 2 = ramp
/// texture + nearest sampler.
#[derive(Debug)]
pub struct BaseShading {
    id: PassId,
    device: wgpu::Device,
    phong: wgpu::RenderPipeline,
    gouraud: wgpu::RenderPipeline,
    cel: wgpu::RenderPipeline,
    frame_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    ramp_bind_group: wgpu::BindGroup,
    formats: TargetFormats,
}

impl BaseShading {
    /// Builds the three pipelines for render passes over targets of `formats` (colour,
    /// depth tested less and written, samples per pixel: 1, or 4 for MSAA, which WebGPU
    /// guarantees for renderable formats), and uploads the settings' cel ramp.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &BaseSettings,
    ) -> Self {
        let module = shaders::BASE_SHADING_FILE.module(device);
        let frame_layout = crate::layout::uniform_layout(device, "npr frame");
        let object_layout = crate::layout::uniform_layout(device, "npr object");
        let ramp_layout = crate::layout::texture_sampler_layout(
            device,
            "npr ramp",
            wgpu::TextureViewDimension::D2,
        );
        let layout = render::pipeline_layout(
            device,
            "npr base shading",
            &[&frame_layout, &object_layout, &ramp_layout],
        );
        let pipeline = |vs: &str, fs: &str| {
            PipelineBuilder::new(fs, &layout, &module, vs, fs)
                .buffers(&[Some(Vertex::layout())])
                .cull(Some(wgpu::Face::Back))
                .depth(formats.depth, true, wgpu::CompareFunction::Less)
                .samples(formats.samples)
                .targets(&[Some(formats.color.into())])
                .build(device)
        };
        let ramp_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("npr ramp sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let ramp_view = upload_ramp(device, queue, &settings.ramp);
        let ramp_bind_group = Self::ramp_group(device, &ramp_layout, &ramp_sampler, &ramp_view);
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            phong: pipeline("vs_pixel", "fs_phong"),
            gouraud: pipeline("vs_gouraud", "fs_gouraud"),
            cel: pipeline("vs_pixel", "fs_cel"),
            frame_layout,
            object_layout,
            ramp_bind_group,
            formats,
        }
    }

    fn ramp_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        sampler: &wgpu::Sampler,
        view: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr ramp"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        })
    }

    /// The target formats the pipelines were built for.
    pub fn formats(&self) -> TargetFormats {
        self.formats
    }

    /// An object drawing `mesh` (its buffers are shared with the caller, not copied).
    pub fn create_object(&self, _device: &wgpu::Device, mesh: &GpuMesh) -> BaseObject {
        BaseObject {
            mesh: mesh.clone(),
            slots: Slots::new(self.id),
        }
    }

    /// Writes one draw's camera, light, transform and material into a fresh slot of
    /// `object`.
    ///
    /// # Errors
    /// [`PassError::ForeignObject`] or [`PassError::SlotsExhausted`].
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut BaseObject,
        input: &BaseInput<'_>,
    ) -> Result<Prepared, PassError> {
        let device = &self.device;
        let (prepared, slot) = object.slots.next(self.id, input.frame, || {
            let frame = render::uniform_buffer(
                device,
                "npr frame uniforms",
                std::mem::size_of::<FrameUniforms>(),
            );
            let object = render::uniform_buffer(
                device,
                "npr object uniforms",
                std::mem::size_of::<ObjectUniforms>(),
            );
            BaseSlot {
                frame_group: render::uniform_group(device, "npr frame", &self.frame_layout, &frame),
                object_group: render::uniform_group(
                    device,
                    "npr object",
                    &self.object_layout,
                    &object,
                ),
                frame,
                object,
                model: input.model,
            }
        })?;
        queue.write_buffer(&slot.frame, 0, bytemuck::bytes_of(input.view));
        queue.write_buffer(&slot.object, 0, bytemuck::bytes_of(input.object));
        slot.model = input.model;
        Ok(prepared)
    }

    /// Records the draw of `object` as `prepared` into the caller's render pass (whose
    /// colour target has the formats given to [`BaseShading::new`] and a depth
    /// attachment).
    ///
    /// # Errors
    /// [`PassError`] for a `prepared` of another object, pass or frame; nothing is
    /// recorded then.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &BaseObject,
        prepared: &Prepared,
    ) -> Result<(), PassError> {
        self.draw_range(pass, object, prepared, 0..object.mesh.index_count)
    }

    /// As [`BaseShading::draw`], drawing only `indices` of the mesh's index buffer (a
    /// slice of a reference spread over frames, for example).
    ///
    /// # Errors
    /// As [`BaseShading::draw`].
    pub fn draw_range(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &BaseObject,
        prepared: &Prepared,
        indices: std::ops::Range<u32>,
    ) -> Result<(), PassError> {
        let slot = object.slots.get(self.id, prepared)?;
        pass.set_pipeline(match slot.model {
            ShadingModel::Phong => &self.phong,
            ShadingModel::Gouraud => &self.gouraud,
            ShadingModel::Cel => &self.cel,
        });
        pass.set_bind_group(0, &slot.frame_group, &[]);
        pass.set_bind_group(1, &slot.object_group, &[]);
        pass.set_bind_group(2, &self.ramp_bind_group, &[]);
        let mesh = &object.mesh;
        pass.set_vertex_buffer(0, mesh.vertex_buffer.slice(..));
        pass.set_index_buffer(mesh.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(indices, 0, 0..1);
        Ok(())
    }
}

crate::impl_pass!(BaseShading, BaseObject, BaseInput, PassError);
