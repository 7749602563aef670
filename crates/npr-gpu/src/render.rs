//! The wgpu boilerplate every pass of the workspace shares, written once: the formats a
//! pass draws into ([`TargetFormats`]), uniform buffers, colour and depth attachments,
//! render passes, pipeline layouts and render pipelines ([`PipelineBuilder`]).
//!
//! Each helper builds exactly the descriptor the passes wrote out before, with wgpu's
//! defaults wherever they left them, so a pass built with them draws the same pixels.

use wgpu::util::DeviceExt;

/// The formats and sample count of the targets a pass draws into: the colour attachment's
/// format, the depth attachment's format and the samples per pixel of both.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TargetFormats {
    /// Format of the colour attachment.
    pub color: wgpu::TextureFormat,
    /// Format of the depth attachment.
    pub depth: wgpu::TextureFormat,
    /// Samples per pixel of both attachments (1, or 4 for MSAA: WebGPU guarantees 4 for
    /// every depth format and the filterable 8-bit and 16-bit float colour formats).
    pub samples: u32,
}

impl TargetFormats {
    /// `color` and `depth` at one sample per pixel.
    pub const fn new(color: wgpu::TextureFormat, depth: wgpu::TextureFormat) -> Self {
        Self {
            color,
            depth,
            samples: 1,
        }
    }

    /// The same formats at `samples` samples per pixel.
    #[must_use]
    pub const fn with_samples(self, samples: u32) -> Self {
        Self { samples, ..self }
    }

    /// Whether the targets have more than one sample per pixel.
    pub const fn is_multisampled(&self) -> bool {
        self.samples > 1
    }

    /// The pipeline multisample state for these targets (at least one sample).
    pub fn multisample(&self) -> wgpu::MultisampleState {
        wgpu::MultisampleState {
            count: self.samples.max(1),
            ..Default::default()
        }
    }
}

/// [`crate::OffscreenTarget`]'s formats ([`crate::COLOR_FORMAT`], [`crate::DEPTH_FORMAT`]),
/// one sample per pixel.
impl Default for TargetFormats {
    fn default() -> Self {
        Self::new(crate::COLOR_FORMAT, crate::DEPTH_FORMAT)
    }
}

/// Usage of every uniform buffer: bound as uniform, written with `Queue::write_buffer`.
pub const UNIFORM_USAGE: wgpu::BufferUsages =
    wgpu::BufferUsages::UNIFORM.union(wgpu::BufferUsages::COPY_DST);

/// A zeroed uniform buffer of `size` bytes ([`UNIFORM_USAGE`]), to be written before use.
pub fn uniform_buffer(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: UNIFORM_USAGE,
        mapped_at_creation: false,
    })
}

/// A uniform buffer ([`UNIFORM_USAGE`]) holding `value`.
pub fn uniform_buffer_init<T: bytemuck::Pod>(
    device: &wgpu::Device,
    label: &str,
    value: &T,
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::bytes_of(value),
        usage: UNIFORM_USAGE,
    })
}

/// A bind group of `layout` with `buffer` whole at binding 0 (the layout of
/// [`crate::layout::uniform_layout`]).
pub fn uniform_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffer: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: buffer.as_entire_binding(),
        }],
    })
}

/// `LoadOp::Clear` of a linear RGBA colour.
pub fn clear_color([r, g, b, a]: [f64; 4]) -> wgpu::LoadOp<wgpu::Color> {
    wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a })
}

/// A colour attachment of `view` loaded with `load` and stored, resolving nothing.
pub fn color_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    }
}

/// A depth attachment of `view` loaded with `load` and stored, without stencil.
pub fn depth_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// Begins a render pass labelled `label` over `colors` and `depth` (see
/// [`color_attachment`], [`depth_attachment`]), without queries.
pub fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    colors: &[Option<wgpu::RenderPassColorAttachment<'_>>],
    depth: Option<wgpu::RenderPassDepthStencilAttachment<'_>>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: colors,
        depth_stencil_attachment: depth,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Begins a render pass labelled `label` over one colour attachment, `view` loaded with
/// `load` and stored, without depth (a full-screen pass).
pub fn begin_color_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPass<'e> {
    begin_pass(encoder, label, &[Some(color_attachment(view, load))], None)
}

/// A pipeline layout of `groups` (group `i` is `groups[i]`), without immediates.
pub fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().copied().map(Some).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}

/// A render pipeline of one shader module, vertex and fragment entry points in it: the
/// shape of every pipeline of the workspace. Starts as a full-screen pass (no vertex
/// buffer, no culling, no depth, one sample, no colour target); each method changes one
/// part.
///
/// ```ignore
/// let pipeline = PipelineBuilder::new("outline", &layout, &module, "vs_fullscreen", "fs_outline")
///     .targets(&[Some(color_format.into())])
///     .build(device);
/// ```
#[derive(Clone, Debug)]
pub struct PipelineBuilder<'a> {
    label: &'a str,
    layout: &'a wgpu::PipelineLayout,
    module: &'a wgpu::ShaderModule,
    vertex: &'a str,
    fragment: &'a str,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    targets: &'a [Option<wgpu::ColorTargetState>],
    constants: &'a [(&'a str, f64)],
    primitive: wgpu::PrimitiveState,
    depth_stencil: Option<wgpu::DepthStencilState>,
    multisample: wgpu::MultisampleState,
}

impl<'a> PipelineBuilder<'a> {
    /// A pipeline labelled `label` with `layout`, running `vertex` and `fragment` of
    /// `module`.
    pub fn new(
        label: &'a str,
        layout: &'a wgpu::PipelineLayout,
        module: &'a wgpu::ShaderModule,
        vertex: &'a str,
        fragment: &'a str,
    ) -> Self {
        Self {
            label,
            layout,
            module,
            vertex,
            fragment,
            buffers: &[],
            targets: &[],
            constants: &[],
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
        }
    }

    /// The vertex buffers the vertex stage reads.
    #[must_use]
    pub fn buffers(mut self, buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>]) -> Self {
        self.buffers = buffers;
        self
    }

    /// The colour targets the fragment stage writes.
    #[must_use]
    pub fn targets(mut self, targets: &'a [Option<wgpu::ColorTargetState>]) -> Self {
        self.targets = targets;
        self
    }

    /// Pipeline-overridable constants of the fragment stage.
    #[must_use]
    pub fn constants(mut self, constants: &'a [(&'a str, f64)]) -> Self {
        self.constants = constants;
        self
    }

    /// Faces culled (`None`: none).
    #[must_use]
    pub fn cull(mut self, face: Option<wgpu::Face>) -> Self {
        self.primitive.cull_mode = face;
        self
    }

    /// The primitive topology (triangle list by default).
    #[must_use]
    pub fn topology(mut self, topology: wgpu::PrimitiveTopology) -> Self {
        self.primitive.topology = topology;
        self
    }

    /// A depth attachment of `format`, tested with `compare`, written when `write`.
    #[must_use]
    pub fn depth(
        mut self,
        format: wgpu::TextureFormat,
        write: bool,
        compare: wgpu::CompareFunction,
    ) -> Self {
        self.depth_stencil = Some(wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        });
        self
    }

    /// `samples` samples per pixel (1 by default).
    #[must_use]
    pub fn samples(mut self, samples: u32) -> Self {
        self.multisample.count = samples.max(1);
        self
    }

    /// Creates the pipeline.
    pub fn build(&self, device: &wgpu::Device) -> wgpu::RenderPipeline {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: Some(self.layout),
            vertex: wgpu::VertexState {
                module: self.module,
                entry_point: Some(self.vertex),
                compilation_options: Default::default(),
                buffers: self.buffers,
            },
            primitive: self.primitive,
            depth_stencil: self.depth_stencil.clone(),
            multisample: self.multisample,
            fragment: Some(wgpu::FragmentState {
                module: self.module,
                entry_point: Some(self.fragment),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: self.constants,
                    ..Default::default()
                },
                targets: self.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}
