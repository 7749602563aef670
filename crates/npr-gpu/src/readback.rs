//! Reading textures back to the CPU. Row padding (`COPY_BYTES_PER_ROW_ALIGNMENT`) is
//! handled here and nowhere else.

use crate::GpuError;

/// Bytes per row of a buffer that receives a texture copy: `width * bytes_per_pixel`
/// rounded up to wgpu's 256-byte row alignment.
pub fn padded_bytes_per_row(width: u32, bytes_per_pixel: u32) -> u32 {
    let unpadded = width * bytes_per_pixel;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    unpadded.div_ceil(align) * align
}

/// Copies a whole 2-D texture (mip 0, layer 0) to the CPU, returning tightly packed rows.
/// Submits its own command buffer and waits: call it outside a frame.
///
/// # Errors
/// [`GpuError::UnsupportedFormat`] for formats without a fixed texel size (depth24,
/// compressed), [`GpuError::Readback`] when mapping fails.
pub fn readback_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, GpuError> {
    let format = texture.format();
    let bpp = format
        .block_copy_size(Some(wgpu::TextureAspect::All))
        .filter(|_| format.block_dimensions() == (1, 1))
        .ok_or(GpuError::UnsupportedFormat(format))?;
    let (width, height) = (texture.width(), texture.height());
    let padded = padded_bytes_per_row(width, bpp);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("npr readback"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit(Some(encoder.finish()));
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let row = (width * bpp) as usize;
    let mut out = Vec::with_capacity(row * height as usize);
    {
        let view = buffer
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        for y in 0..height as usize {
            let start = y * padded as usize;
            out.extend_from_slice(&view[start..start + row]);
        }
    }
    buffer.unmap();
    Ok(out)
}

/// Reads an RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`) back as an image. For an sRGB
/// texture the bytes are sRGB-encoded, ready to save as PNG.
///
/// # Errors
/// [`GpuError::UnsupportedFormat`] for other formats; [`GpuError::Readback`] on mapping
/// failure.
pub fn readback_rgba(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<image::RgbaImage, GpuError> {
    let format = texture.format();
    if !matches!(
        format,
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb
    ) {
        return Err(GpuError::UnsupportedFormat(format));
    }
    let bytes = readback_texture(device, queue, texture)?;
    image::RgbaImage::from_raw(texture.width(), texture.height(), bytes)
        .ok_or_else(|| GpuError::Readback("buffer size does not match the image".into()))
}
