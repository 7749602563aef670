//! Reading textures and buffers back to the CPU. Row padding (`COPY_BYTES_PER_ROW_ALIGNMENT`) is
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
/// Submits its own command buffer and waits: call it outside a frame. Native only: in the
/// browser the map completes only once control returns to the page, so use
/// [`TextureReadback`] and poll it from frame to frame.
///
/// # Errors
/// [`GpuError::UnsupportedFormat`] for formats without a fixed texel size (depth24,
/// compressed), [`GpuError::Readback`] when mapping fails.
pub fn readback_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, GpuError> {
    TextureReadback::start(device, queue, texture)?.wait(device)
}

/// What a map callback has reported (nothing yet, or its result), and a signal for it.
type MapSlot = std::sync::Arc<(
    std::sync::Mutex<Option<Result<(), String>>>,
    std::sync::Condvar,
)>;

/// A texture copy on its way to the CPU: [`TextureReadback::start`] records and submits
/// the copy and asks for the map; [`TextureReadback::try_take`] returns the bytes once the
/// map has completed, without blocking, which is how the browser reads back (the map
/// completes between two animation frames); [`TextureReadback::wait`] blocks until then
/// (native).
#[derive(Debug)]
pub struct TextureReadback {
    map: BufferReadback,
    padded: u32,
    row: u32,
    height: u32,
}

/// A buffer on its way to the CPU: [`BufferReadback::map`] asks for the map of a
/// `MAP_READ` buffer after the submission that fills it; [`BufferReadback::try_take`]
/// returns its bytes once the map has completed, without blocking (the browser's way: the
/// map completes between two animation frames, or a frame later on native); and
/// [`BufferReadback::wait`] blocks until then (native). The buffer is unmapped once its
/// bytes are taken, so a persistent buffer can be mapped again next frame.
#[derive(Debug)]
pub struct BufferReadback {
    buffer: wgpu::Buffer,
    mapped: MapSlot,
}

impl BufferReadback {
    /// Asks for the map of the whole of `buffer` (`MAP_READ`, not mapped), after the
    /// submission that fills it.
    pub fn map(buffer: wgpu::Buffer) -> Self {
        let mapped = MapSlot::default();
        let slot = mapped.clone();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            if let Ok(mut s) = slot.0.lock() {
                *s = Some(r.map_err(|e| e.to_string()));
            }
            slot.1.notify_all();
        });
        Self { buffer, mapped }
    }

    /// The map's outcome once it has completed; `None` while it has not.
    fn done(&self) -> Option<Result<(), GpuError>> {
        let done = match self.mapped.0.lock() {
            Ok(mut s) => s.take()?,
            Err(_) => Err("the map callback panicked".to_string()),
        };
        Some(done.map_err(GpuError::Readback))
    }

    /// The buffer's bytes once the map has completed (the buffer is unmapped then);
    /// `None` while it has not. After it has returned `Some`, further calls return `None`.
    pub fn try_take(&self) -> Option<Result<Vec<u8>, GpuError>> {
        Some(self.done()?.and_then(|()| {
            let bytes = self
                .buffer
                .get_mapped_range(..)
                .map_err(|e| GpuError::Readback(e.to_string()))?
                .to_vec();
            self.buffer.unmap();
            Ok(bytes)
        }))
    }

    /// Blocks until the map has completed (native: polls `device`) and returns the bytes.
    ///
    /// # Errors
    /// [`GpuError::Readback`] when polling or mapping fails, or no callback came within
    /// a minute of the device going idle.
    pub fn wait(self, device: &wgpu::Device) -> Result<Vec<u8>, GpuError> {
        self.wait_mapped(device)?;
        self.try_take().unwrap_or_else(not_completed)
    }

    /// Polls `device` until idle, then waits for the map's callback: another thread
    /// polling the same device may be the one that runs it, a moment after this thread's
    /// poll has returned.
    fn wait_mapped(&self, device: &wgpu::Device) -> Result<(), GpuError> {
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let (lock, signal) = &*self.mapped;
        let guard = lock
            .lock()
            .map_err(|_| GpuError::Readback("the map callback panicked".into()))?;
        let (_guard, timeout) = signal
            .wait_timeout_while(guard, std::time::Duration::from_secs(60), |s| s.is_none())
            .map_err(|_| GpuError::Readback("the map callback panicked".into()))?;
        if timeout.timed_out() {
            return Err(GpuError::Readback(
                "the map had not completed a minute after the device went idle".into(),
            ));
        }
        Ok(())
    }
}

fn not_completed<T>() -> Result<T, GpuError> {
    Err(GpuError::Readback(
        "the map had not completed after the device went idle".into(),
    ))
}

impl TextureReadback {
    /// Submits a copy of `texture` (mip 0, layer 0) to a mappable buffer and asks for the
    /// map.
    ///
    /// # Errors
    /// [`GpuError::UnsupportedFormat`] for formats without a fixed texel size.
    pub fn start(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        texture: &wgpu::Texture,
    ) -> Result<Self, GpuError> {
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
        Ok(Self {
            map: BufferReadback::map(buffer),
            padded,
            row: width * bpp,
            height,
        })
    }

    /// The tightly packed rows once the map has completed; `None` while it has not. After
    /// it has returned `Some`, the buffer is unmapped and further calls fail.
    pub fn try_take(&self) -> Option<Result<Vec<u8>, GpuError>> {
        Some(self.map.done()?.and_then(|()| self.rows()))
    }

    /// Blocks until the map has completed and returns the rows (native: polls `device`).
    ///
    /// # Errors
    /// [`GpuError::Readback`] when polling or mapping fails, or no callback came within
    /// a minute of the device going idle.
    pub fn wait(self, device: &wgpu::Device) -> Result<Vec<u8>, GpuError> {
        self.map.wait_mapped(device)?;
        self.try_take().unwrap_or_else(not_completed)
    }

    fn rows(&self) -> Result<Vec<u8>, GpuError> {
        let (row, padded) = (self.row as usize, self.padded as usize);
        let buffer = &self.map.buffer;
        let mut out = Vec::with_capacity(row * self.height as usize);
        {
            let view = buffer
                .get_mapped_range(..)
                .map_err(|e| GpuError::Readback(e.to_string()))?;
            for y in 0..self.height as usize {
                let start = y * padded;
                out.extend_from_slice(&view[start..start + row]);
            }
        }
        buffer.unmap();
        Ok(out)
    }
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
