//! The typed errors of the GPU layer.

/// Everything that can go wrong in `npr-gpu`.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No graphics adapter could be found. Cause: no GPU driver and no software Vulkan
    /// driver is installed, or `WGPU_BACKEND` names a backend that is missing. Fix: on
    /// Debian/Ubuntu install Mesa's software Vulkan driver (lavapipe) with the command in
    /// the message, or install your GPU's Vulkan driver.
    #[error(
        "no GPU adapter found ({detail}); on Debian/Ubuntu install Mesa's software Vulkan \
         driver: `apt-get install -y mesa-vulkan-drivers libvulkan1` (as root), or install \
         your GPU's Vulkan driver"
    )]
    NoAdapter {
        /// What wgpu reported.
        detail: String,
    },
    /// The adapter refused to create a device. Cause: the requested limits or features
    /// exceed what the adapter offers. Fix: use a more capable adapter or driver.
    #[error("the adapter could not create a device: {0}")]
    RequestDevice(String),
    /// A buffer could not be mapped for reading. Cause: the device was lost or the
    /// buffer was misused. Fix: check earlier wgpu validation errors.
    #[error("GPU buffer readback failed: {0}")]
    Readback(String),
    /// A texture format that the helper cannot read back.
    #[error("readback of texture format {0:?} is not supported")]
    UnsupportedFormat(wgpu::TextureFormat),
    /// A size of zero or beyond the device limits.
    #[error("invalid size {width}x{height}: {reason}")]
    InvalidSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Why it is invalid.
        reason: String,
    },
    /// The mesh cannot be uploaded. Cause: no triangles, mismatched attribute lengths or an
    /// index past the vertex count. Fix: validate the mesh with `npr_geometry`.
    #[error("mesh cannot be uploaded: {0}")]
    InvalidMesh(String),
    /// A window surface could not be created. Cause: the windowing system refused it (no
    /// display, or a backend without presentation support). Fix: check `DISPLAY` /
    /// `WAYLAND_DISPLAY`, or render offscreen instead.
    #[error("cannot create a window surface: {0}")]
    Surface(String),
    /// A mesh buffer would exceed one of the adapter's limits. Cause: the mesh is too large
    /// for this adapter (`max_buffer_size`, or `max_storage_buffer_binding_size`, since
    /// the passes bind the vertex and index buffers as storage). Fix: decimate or split
    /// the mesh, or use an adapter with larger limits.
    #[error(
        "mesh {buffer} buffer needs {size} bytes, over the adapter's {limit_name} of {limit} bytes"
    )]
    MeshTooLarge {
        /// `"vertex"` or `"index"`.
        buffer: &'static str,
        /// The buffer's size in bytes.
        size: u64,
        /// The wgpu limit exceeded (`"max_buffer_size"`, ...).
        limit_name: &'static str,
        /// The limit's value on this device.
        limit: u64,
    },
    /// A pass refused an object or its prepared state (see [`crate::PassError`]).
    #[error(transparent)]
    Pass(#[from] crate::PassError),
}
