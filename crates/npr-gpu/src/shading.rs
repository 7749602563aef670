//! Base shading passes shared by all techniques: per-pixel Phong (Blinn-Phong, SPEC §2
//! Eq. (2)–(3)), per-vertex Gouraud, and cel/toon shading with a 1-D ramp texture
//! (Lake, Marshall, Harris, Blackstein, "Stylized Rendering Techniques for Scalable
//! Real-Time 3D Animation", NPAR 2000). WGSL: `shaders/base_shading.wgsl`.

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

/// Per-object GPU state: its uniform buffer and bind group (group 1).
#[derive(Debug)]
pub struct ObjectBinding {
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl ObjectBinding {
    /// Writes new object uniforms (transform, material).
    pub fn update(&self, queue: &wgpu::Queue, uniforms: &ObjectUniforms) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(uniforms));
    }

    /// The bind group to set at group 1.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }
}

/// The base shading passes. Create once per device and target format; record with
/// [`BaseShading::draw`] into a caller's render pass.
///
/// Bind groups: 0 = frame ([`FrameUniforms`], written by [`BaseShading::set_frame`]),
/// 1 = object ([`ObjectBinding`]), 2 = ramp texture + nearest sampler.
#[derive(Debug)]
pub struct BaseShading {
    phong: wgpu::RenderPipeline,
    gouraud: wgpu::RenderPipeline,
    cel: wgpu::RenderPipeline,
    frame_buffer: wgpu::Buffer,
    frame_bind_group: wgpu::BindGroup,
    object_layout: wgpu::BindGroupLayout,
    ramp_layout: wgpu::BindGroupLayout,
    ramp_sampler: wgpu::Sampler,
    ramp_bind_group: wgpu::BindGroup,
}

impl BaseShading {
    /// Builds the three pipelines for render passes over targets of `formats` (colour,
    /// depth tested less and written, samples per pixel: 1, or 4 for MSAA, which WebGPU
    /// guarantees for renderable formats), and the default three-band ramp.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, formats: TargetFormats) -> Self {
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
        let frame_buffer = render::uniform_buffer(
            device,
            "npr frame uniforms",
            std::mem::size_of::<FrameUniforms>(),
        );
        let frame_bind_group =
            render::uniform_group(device, "npr frame", &frame_layout, &frame_buffer);
        let ramp_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("npr ramp sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let ramp_view = upload_ramp(device, queue, &default_ramp());
        let ramp_bind_group = Self::ramp_group(device, &ramp_layout, &ramp_sampler, &ramp_view);
        Self {
            phong: pipeline("vs_pixel", "fs_phong"),
            gouraud: pipeline("vs_gouraud", "fs_gouraud"),
            cel: pipeline("vs_pixel", "fs_cel"),
            frame_buffer,
            frame_bind_group,
            object_layout,
            ramp_layout,
            ramp_sampler,
            ramp_bind_group,
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

    /// Replaces the cel ramp (any view of a `N × 1` filterable 2-D texture; see
    /// [`upload_ramp`]).
    pub fn set_ramp(&mut self, device: &wgpu::Device, ramp: &wgpu::TextureView) {
        self.ramp_bind_group =
            Self::ramp_group(device, &self.ramp_layout, &self.ramp_sampler, ramp);
    }

    /// Writes the frame uniforms (camera, light) used by every following draw.
    pub fn set_frame(&self, queue: &wgpu::Queue, frame: &FrameUniforms) {
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(frame));
    }

    /// The frame uniform buffer (other passes may bind it to read the same camera).
    pub fn frame_buffer(&self) -> &wgpu::Buffer {
        &self.frame_buffer
    }

    /// Creates the per-object uniform buffer and bind group, filled with `uniforms`.
    pub fn create_object(&self, device: &wgpu::Device, uniforms: &ObjectUniforms) -> ObjectBinding {
        let buffer = render::uniform_buffer_init(device, "npr object uniforms", uniforms);
        let bind_group = render::uniform_group(device, "npr object", &self.object_layout, &buffer);
        ObjectBinding { buffer, bind_group }
    }

    /// Records a draw of `mesh` with `model` into the caller's render pass (whose colour
    /// target has the format given to [`BaseShading::new`] and a depth attachment).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        model: ShadingModel,
        object: &ObjectBinding,
        mesh: &GpuMesh,
    ) {
        pass.set_pipeline(match model {
            ShadingModel::Phong => &self.phong,
            ShadingModel::Gouraud => &self.gouraud,
            ShadingModel::Cel => &self.cel,
        });
        pass.set_bind_group(0, &self.frame_bind_group, &[]);
        pass.set_bind_group(1, &object.bind_group, &[]);
        pass.set_bind_group(2, &self.ramp_bind_group, &[]);
        mesh.draw(pass);
    }
}
