//! A headless wgpu context: instance, adapter, device and queue, without a window.

use crate::GpuError;

/// A headless GPU context. A convenience: every pass in the workspace only needs a
/// `&wgpu::Device` and `&wgpu::Queue`, which a caller may take from its own renderer.
#[derive(Debug)]
pub struct GpuContext {
    /// The instance the adapter came from (created with `WGPU_BACKEND` etc. honoured).
    pub instance: wgpu::Instance,
    /// The adapter in use.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// Creates a headless context on the best adapter available.
    ///
    /// The instance reads `WGPU_BACKEND`, `WGPU_ADAPTER_NAME`, `WGPU_POWER_PREF` and the
    /// debugging flags from the environment (`InstanceDescriptor::new_without_display_handle_from_env`).
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] when no adapter exists (its message says what to install),
    /// [`GpuError::RequestDevice`] when the device cannot be created.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    /// Async form of [`GpuContext::new`].
    ///
    /// # Errors
    /// As [`GpuContext::new`].
    pub async fn new_async() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Self::with_instance(instance, None).await
    }

    /// A context for a window: `descriptor` should carry the windowing system's display
    /// handle (with winit, `InstanceDescriptor::new_with_display_handle_from_env` of the
    /// event loop's `owned_display_handle()`), `make_surface` creates the window's surface
    /// from the instance, and the adapter is chosen to present to it.
    ///
    /// # Errors
    /// [`GpuError::Surface`] when the surface cannot be created, else as
    /// [`GpuContext::new`].
    pub fn for_surface(
        descriptor: wgpu::InstanceDescriptor,
        make_surface: impl FnOnce(
            &wgpu::Instance,
        ) -> Result<wgpu::Surface<'static>, wgpu::CreateSurfaceError>,
    ) -> Result<(Self, wgpu::Surface<'static>), GpuError> {
        pollster::block_on(Self::for_surface_async(descriptor, make_surface))
    }

    /// [`GpuContext::for_surface`] without blocking, for where a thread cannot wait (the
    /// browser's event loop: a canvas surface there, with `Backends::BROWSER_WEBGPU`).
    ///
    /// # Errors
    /// As [`GpuContext::for_surface`].
    pub async fn for_surface_async(
        descriptor: wgpu::InstanceDescriptor,
        make_surface: impl FnOnce(
            &wgpu::Instance,
        ) -> Result<wgpu::Surface<'static>, wgpu::CreateSurfaceError>,
    ) -> Result<(Self, wgpu::Surface<'static>), GpuError> {
        let instance = wgpu::Instance::new(descriptor);
        let surface = make_surface(&instance).map_err(|e| GpuError::Surface(e.to_string()))?;
        let ctx = Self::with_instance(instance, Some(&surface)).await?;
        Ok((ctx, surface))
    }

    async fn with_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = match wgpu::util::initialize_adapter_from_env(&instance, surface).await {
            Ok(a) => a,
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    force_fallback_adapter: false,
                    compatible_surface: surface,
                    ..Default::default()
                })
                .await
                .map_err(|e| GpuError::NoAdapter {
                    detail: e.to_string(),
                })?,
        };
        let limits = wgpu::Limits::default().using_resolution(adapter.limits());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("npr device"),
                required_features: wgpu::Features::empty(),
                required_limits: limits,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::RequestDevice(e.to_string()))?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// One line describing the adapter: name, type, backend and driver.
    pub fn adapter_summary(&self) -> String {
        let info = self.adapter.get_info();
        format!(
            "{} ({:?}, {:?}, driver {} {})",
            info.name, info.device_type, info.backend, info.driver, info.driver_info
        )
    }

    /// Whether the adapter is a software rasterizer (lavapipe, WARP, SwiftShader).
    pub fn is_software(&self) -> bool {
        self.adapter.get_info().device_type == wgpu::DeviceType::Cpu
    }
}
