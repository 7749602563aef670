//! Antialiasing of the warp path (ours, beyond the paper): 4× MSAA of the references, of
//! the warped frame and of the full render it is compared with.
//!
//! A multisampled reference is drawn into [`MsaaTarget`] textures and resolved: its colour
//! by the render pass (a rim texel's alpha becomes the share the object covers, its colour
//! premultiplied by it, since references are cleared to transparent black), its depth by a
//! pass of our own that keeps the nearest sample (WebGPU resolves colour only). The warp
//! pass then draws the proxy into a multisampled target with a per-fragment sample mask
//! taken from the reference's coverage at each sample's point (`warp.wgsl`,
//! `coverage_mask`), so the warped silhouette is antialiased as the full render's is.
//! WebGPU guarantees 4 samples per pixel for every depth format and, with resolve, for the
//! filterable 8-bit and 16-bit float colour formats (e.g. `Rgba8Unorm[Srgb]`,
//! `Bgra8Unorm[Srgb]`, `Rgba16Float`), but not for every renderable colour format (not
//! for the 32-bit float ones; the integer ones multisample without resolve):
//! [`Antialiasing::check`] asks what the device enforces.

use crate::WarpError;
use npr_gpu::TargetFormats;
use npr_gpu::render::{self, PipelineBuilder};

/// Antialiasing of references, warped frames and full renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Antialiasing {
    /// One sample per pixel (as the paper, and the default).
    #[default]
    None,
    /// 4× multisampling of references, warped frames and full renders, resolved to one
    /// sample per pixel; the warp's sample mask follows the references' coverage.
    Msaa4,
    /// 4× multisampling of references and full renders; the warp draws one sample per
    /// pixel and blends its rim over the background by the references' coverage
    /// (premultiplied alpha): the multisampled look for a one-sample warp's cost.
    Msaa4Blend,
}

impl Antialiasing {
    /// Every setting, in table order.
    pub const ALL: [Antialiasing; 3] = [
        Antialiasing::None,
        Antialiasing::Msaa4,
        Antialiasing::Msaa4Blend,
    ];

    /// Samples per pixel of references and full renders.
    pub fn sample_count(self) -> u32 {
        match self {
            Antialiasing::None => 1,
            Antialiasing::Msaa4 | Antialiasing::Msaa4Blend => 4,
        }
    }

    /// Samples per pixel of the warped frame.
    pub fn warp_sample_count(self) -> u32 {
        match self {
            Antialiasing::None | Antialiasing::Msaa4Blend => 1,
            Antialiasing::Msaa4 => 4,
        }
    }

    /// A short name (table and JSON value): `none`, `msaa4`, `msaa4-blend`.
    pub fn name(self) -> &'static str {
        match self {
            Antialiasing::None => "none",
            Antialiasing::Msaa4 => "msaa4",
            Antialiasing::Msaa4Blend => "msaa4-blend",
        }
    }

    /// The setting named `name` ([`Antialiasing::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|a| a.name() == name)
    }

    /// The setting of references (and full renders) drawn with `references.samples` and a
    /// warped frame drawn with `target.samples` per pixel: 1 and 1 [`Antialiasing::None`],
    /// 4 and 4 [`Antialiasing::Msaa4`], 4 and 1 [`Antialiasing::Msaa4Blend`].
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] for any other pair.
    pub fn from_samples(references: u32, target: u32) -> Result<Self, WarpError> {
        Self::ALL
            .into_iter()
            .find(|a| a.sample_count() == references && a.warp_sample_count() == target)
            .ok_or_else(|| {
                WarpError::InvalidSetting(format!(
                    "references with {references} and a warp target with {target} samples \
                     per pixel: the warp supports 1 and 1, 4 and 4, 4 and 1"
                ))
            })
    }

    /// `formats` at the sample count of references and full renders.
    pub fn references(self, formats: TargetFormats) -> TargetFormats {
        formats.with_samples(self.sample_count())
    }

    /// `formats` at the sample count of the warped frame.
    pub fn warp_target(self, formats: TargetFormats) -> TargetFormats {
        formats.with_samples(self.warp_sample_count())
    }

    /// Whether references and full renders are multisampled.
    pub fn is_multisampled(self) -> bool {
        self.sample_count() > 1
    }

    /// Whether the warped frame is multisampled.
    pub fn warp_is_multisampled(self) -> bool {
        self.warp_sample_count() > 1
    }

    /// Checks that `device` renders (and resolves) `color_format` and renders
    /// `depth_format` at this sample count: with the format features the device enforces,
    /// WebGPU's guaranteed ones (`TextureFormat::guaranteed_format_features`) unless it was
    /// created with `Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`, then `adapter`'s
    /// (the adapter `device` was requested from).
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] naming the format that lacks it.
    pub fn check(
        self,
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        depth_format: wgpu::TextureFormat,
    ) -> Result<(), WarpError> {
        let n = self.sample_count();
        if n == 1 {
            return Ok(());
        }
        let features = device.features();
        let adapter_specific =
            features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
        for (format, resolve) in [(color_format, true), (depth_format, false)] {
            let f = if adapter_specific {
                adapter.get_texture_format_features(format)
            } else {
                format.guaranteed_format_features(features)
            };
            let ok = f.flags.sample_count_supported(n)
                && (!resolve
                    || f.flags
                        .contains(wgpu::TextureFormatFeatureFlags::MULTISAMPLE_RESOLVE));
            if !ok {
                return Err(WarpError::InvalidSetting(format!(
                    "{format:?} does not support {n}x multisampling on this device"
                )));
            }
        }
        Ok(())
    }
}

/// Multisampled colour and depth textures of one size: what a multisampled pass draws
/// into before its colour is resolved into a single-sample texture.
#[derive(Debug)]
pub struct MsaaTarget {
    /// Multisampled colour (render attachment).
    pub color: wgpu::Texture,
    /// Default view of `color`.
    pub color_view: wgpu::TextureView,
    /// Multisampled depth (render attachment; sampleable too for a reference's depth
    /// resolve).
    pub depth: wgpu::Texture,
    /// Default view of `depth` (the attachment).
    pub depth_view: wgpu::TextureView,
}

impl MsaaTarget {
    /// Textures of `width × height` in `formats` (colour, depth, samples per pixel;
    /// render attachments only).
    ///
    /// # Errors
    /// [`WarpError::Gpu`] for a zero size or one past the device's limit.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        formats: TargetFormats,
    ) -> Result<Self, WarpError> {
        Self::create(device, width, height, formats, false)
    }

    /// As [`MsaaTarget::new`], its depth sampleable too (for [`DepthResolve`]).
    pub(crate) fn with_sampled_depth(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        formats: TargetFormats,
    ) -> Result<Self, WarpError> {
        Self::create(device, width, height, formats, true)
    }

    fn create(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        formats: TargetFormats,
        sampled_depth: bool,
    ) -> Result<Self, WarpError> {
        npr_gpu::check_size(device, width, height)?;
        let make = |label, format, usage| {
            let samples = formats.samples;
            device.create_texture(&npr_gpu::texture_2d_descriptor(
                label, width, height, format, usage, samples,
            ))
        };
        let color = make(
            "npr-warp msaa colour",
            formats.color,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let depth_usage = if sampled_depth {
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING
        } else {
            wgpu::TextureUsages::RENDER_ATTACHMENT
        };
        let depth = make("npr-warp msaa depth", formats.depth, depth_usage);
        Ok(Self {
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            color,
            depth,
        })
    }

    /// A render pass over the multisampled textures, cleared to `clear` (linear RGBA) and
    /// depth 1, or loaded (`None`), its colour resolved into `resolve` at the end.
    pub fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        resolve: &wgpu::TextureView,
        clear: Option<[f64; 4]>,
    ) -> wgpu::RenderPass<'e> {
        let (color, depth) = match clear {
            Some(rgba) => (render::clear_color(rgba), wgpu::LoadOp::Clear(1.0)),
            None => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        };
        render::begin_pass(
            encoder,
            "npr-warp msaa pass",
            &[Some(wgpu::RenderPassColorAttachment {
                resolve_target: Some(resolve),
                ..render::color_attachment(&self.color_view, color)
            })],
            Some(render::depth_attachment(&self.depth_view, depth)),
        )
    }
}

/// The depth resolve of a multisampled reference: the nearest sample per texel, written
/// into a single-sample depth texture (`warp.wgsl`, `fs_resolve_depth`). One per device and
/// depth format: clones share the pipeline.
#[derive(Clone, Debug)]
pub(crate) struct DepthResolve {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl DepthResolve {
    pub(crate) fn new(device: &wgpu::Device, depth_format: wgpu::TextureFormat) -> Self {
        let module = crate::shaders::WARP.module(device);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr-warp depth resolve"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: true,
                },
                count: None,
            }],
        });
        let pipeline_layout = render::pipeline_layout(device, "npr-warp depth resolve", &[&layout]);
        let pipeline = PipelineBuilder::new(
            "npr-warp depth resolve",
            &pipeline_layout,
            &module,
            "vs_fullscreen",
            "fs_resolve_depth",
        )
        .depth(depth_format, true, wgpu::CompareFunction::Always)
        .build(device);
        Self { pipeline, layout }
    }

    /// A bind group reading `source`'s multisampled depth (built
    /// [`MsaaTarget::with_sampled_depth`]).
    pub(crate) fn bind(&self, device: &wgpu::Device, source: &MsaaTarget) -> wgpu::BindGroup {
        let view = source.depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr-warp depth resolve"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(&view),
            }],
        })
    }

    /// Records the resolve of the bound source into `target` (single-sample depth).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        source: &wgpu::BindGroup,
        target: &wgpu::TextureView,
    ) {
        let mut pass = render::begin_pass(
            encoder,
            "npr-warp depth resolve",
            &[],
            Some(render::depth_attachment(target, wgpu::LoadOp::Clear(1.0))),
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, source, &[]);
        pass.draw(0..3, 0..1);
    }
}
/// Checks that `color_format` is a filterable colour format (the references are sampled) and
/// `depth_format` has a depth aspect that can be sampled.
pub(crate) fn check_formats(
    color_format: wgpu::TextureFormat,
    depth_format: wgpu::TextureFormat,
) -> Result<(), WarpError> {
    if color_format.has_depth_aspect()
        || color_format.has_stencil_aspect()
        || color_format.is_compressed()
        || !matches!(
            color_format.sample_type(None, None),
            Some(wgpu::TextureSampleType::Float { filterable: true })
        )
    {
        return Err(WarpError::InvalidSetting(format!(
            "colour format {color_format:?} is not a filterable colour format"
        )));
    }
    if !depth_format.has_depth_aspect() {
        return Err(WarpError::InvalidSetting(format!(
            "depth format {depth_format:?} has no depth aspect"
        )));
    }
    Ok(())
}
