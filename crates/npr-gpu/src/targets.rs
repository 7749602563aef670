//! Offscreen colour + depth render targets.

use crate::GpuError;

/// Colour format of offscreen targets: 8-bit sRGB, so passes write linear colour and the
/// hardware encodes it, and readback yields PNG-ready sRGB bytes.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format of offscreen targets (WebGPU depth range 0..1, cleared to 1).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A single-mip, single-sample 2-D texture of `width × height` texels.
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&texture_2d_descriptor(
        label, width, height, format, usage, 1,
    ))
}

/// The descriptor of a single-mip 2-D texture of `width × height` texels with `samples`
/// samples per texel (at least one), e.g. for `create_texture_with_data` or a
/// multisampled render attachment.
pub fn texture_2d_descriptor(
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
    samples: u32,
) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples.max(1),
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    }
}

/// `Ok` when a `width × height` 2-D target fits the device: each side in
/// `1..=max_texture_dimension_2d`.
///
/// # Errors
/// [`GpuError::InvalidSize`] otherwise.
pub fn check_size(device: &wgpu::Device, width: u32, height: u32) -> Result<(), GpuError> {
    let max = device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(GpuError::InvalidSize {
            width,
            height,
            reason: format!("each side must be in 1..={max}"),
        });
    }
    Ok(())
}

/// A headless colour + depth target pair of one size.
#[derive(Debug)]
pub struct OffscreenTarget {
    /// Colour texture ([`COLOR_FORMAT`]), renderable, copyable and sampleable.
    pub color: wgpu::Texture,
    /// Default view of `color`.
    pub color_view: wgpu::TextureView,
    /// Depth texture ([`DEPTH_FORMAT`]), renderable and sampleable.
    pub depth: wgpu::Texture,
    /// Default view of `depth`.
    pub depth_view: wgpu::TextureView,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl OffscreenTarget {
    /// Creates a target of `width` × `height` pixels.
    ///
    /// # Errors
    /// [`GpuError::InvalidSize`] for a zero size or one past the device's 2-D limit.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Result<Self, GpuError> {
        check_size(device, width, height)?;
        let make = |label, format, usage| texture_2d(device, label, width, height, format, usage);
        let color = make(
            "npr offscreen color",
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let depth = make(
            "npr offscreen depth",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
        let depth_view = depth.create_view(&wgpu::TextureViewDescriptor::default());
        Ok(Self {
            color,
            color_view,
            depth,
            depth_view,
            width,
            height,
        })
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Begins a render pass on this target that clears colour to `clear` (linear RGBA) and
    /// depth to 1.
    pub fn begin_clear_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        clear: [f64; 4],
    ) -> wgpu::RenderPass<'e> {
        let [r, g, b, a] = clear;
        self.begin_pass(
            encoder,
            wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
            wgpu::LoadOp::Clear(1.0),
        )
    }

    /// Begins a render pass on this target that keeps its colour and depth (to draw over
    /// an earlier pass, e.g. highlights over base shading).
    pub fn begin_load_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
    ) -> wgpu::RenderPass<'e> {
        self.begin_pass(encoder, wgpu::LoadOp::Load, wgpu::LoadOp::Load)
    }

    fn begin_pass<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        color: wgpu::LoadOp<wgpu::Color>,
        depth: wgpu::LoadOp<f32>,
    ) -> wgpu::RenderPass<'e> {
        begin_views_pass(encoder, &self.color_view, &self.depth_view, color, depth)
    }
}

/// Begins a render pass over any colour and depth views (a caller's targets, whatever
/// their formats) with the given load operations; both are stored.
pub fn begin_views_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    color_view: &wgpu::TextureView,
    depth_view: &wgpu::TextureView,
    color: wgpu::LoadOp<wgpu::Color>,
    depth: wgpu::LoadOp<f32>,
) -> wgpu::RenderPass<'e> {
    crate::render::begin_pass(
        encoder,
        "npr offscreen pass",
        &[Some(crate::render::color_attachment(color_view, color))],
        Some(crate::render::depth_attachment(depth_view, depth)),
    )
}
