//! What a long session holds: the heap in use, the process's resident memory and the GPU
//! objects that wgpu keeps alive. The soak tests compare these after a warm-up and after hundreds of frames;
//! `npr view --script` writes them with the `memory PATH` command.

use serde::Serialize;

/// The process's resident set size in bytes (`VmRSS` of `/proc/self/status`), or `None`
/// where the platform has no `/proc` (then the soak figures are not available).
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Bytes the C allocator has handed out and not yet taken back, over all its arenas
/// (glibc's `mallinfo2`: chunks in use plus blocks it mapped on its own). Rust's heap and the
/// Vulkan driver's host memory both come from it.
///
/// This is the figure a leak grows. Resident memory also moves when the allocator opens
/// another arena for a busy thread, or keeps pages it freed. `None` off glibc.
pub fn heap_in_use_bytes() -> Option<u64> {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: `mallinfo2` takes no arguments, returns a struct by value and only reads
        // the allocator's statistics under its own locks (glibc 2.33 and later; Debian 12
        // ships 2.36).
        #[allow(unsafe_code)]
        let info = unsafe { libc::mallinfo2() };
        Some((info.uordblks + info.hblkhd) as u64)
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        None
    }
}

/// GPU objects alive in a wgpu instance, by kind (wgpu-core's registries: ids handed out
/// and not yet released). A frame that creates and drops its own objects leaves these
/// unchanged once the device has been polled; one that leaks grows them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct GpuObjects {
    /// Buffers.
    pub buffers: usize,
    /// Textures.
    pub textures: usize,
    /// Texture views.
    pub texture_views: usize,
    /// Samplers.
    pub samplers: usize,
    /// Bind groups.
    pub bind_groups: usize,
    /// Bind group layouts.
    pub bind_group_layouts: usize,
    /// Pipeline layouts.
    pub pipeline_layouts: usize,
    /// Render pipelines.
    pub render_pipelines: usize,
    /// Compute pipelines.
    pub compute_pipelines: usize,
    /// Shader modules.
    pub shader_modules: usize,
    /// Query sets.
    pub query_sets: usize,
    /// Command buffers not yet submitted or dropped.
    pub command_buffers: usize,
}

impl GpuObjects {
    /// The counts of `instance`'s registries, or `None` where wgpu runs on the browser's
    /// WebGPU (no wgpu-core registries to read).
    pub fn of(instance: &wgpu::Instance) -> Option<Self> {
        let report = instance.generate_report()?;
        let hub = report.hub_report();
        Some(Self {
            buffers: hub.buffers.num_allocated,
            textures: hub.textures.num_allocated,
            texture_views: hub.texture_views.num_allocated,
            samplers: hub.samplers.num_allocated,
            bind_groups: hub.bind_groups.num_allocated,
            bind_group_layouts: hub.bind_group_layouts.num_allocated,
            pipeline_layouts: hub.pipeline_layouts.num_allocated,
            render_pipelines: hub.render_pipelines.num_allocated,
            compute_pipelines: hub.compute_pipelines.num_allocated,
            shader_modules: hub.shader_modules.num_allocated,
            query_sets: hub.query_sets.num_allocated,
            command_buffers: hub.command_buffers.num_allocated,
        })
    }
}

/// One reading: resident memory and GPU objects, after waiting for the device to finish
/// its work (so that objects dropped by the frames before are released).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct MemoryReading {
    /// [`heap_in_use_bytes`].
    pub heap_bytes: Option<u64>,
    /// [`resident_bytes`].
    pub resident_bytes: Option<u64>,
    /// [`GpuObjects::of`].
    pub gpu_objects: Option<GpuObjects>,
}

impl MemoryReading {
    /// Waits for `device` and reads both figures.
    pub fn take(instance: &wgpu::Instance, device: &wgpu::Device) -> Self {
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        Self {
            heap_bytes: heap_in_use_bytes(),
            resident_bytes: resident_bytes(),
            gpu_objects: GpuObjects::of(instance),
        }
    }

    /// Growth of resident memory from `earlier` to `self`, as a fraction of `earlier`
    /// (0.05 = 5 %), when both were read.
    pub fn resident_growth_since(&self, earlier: &MemoryReading) -> Option<f64> {
        growth(earlier.resident_bytes?, self.resident_bytes?)
    }

    /// Growth of the heap in use from `earlier` to `self`, as a fraction of `earlier`, when
    /// both were read.
    pub fn heap_growth_since(&self, earlier: &MemoryReading) -> Option<f64> {
        growth(earlier.heap_bytes?, self.heap_bytes?)
    }
}

fn growth(a: u64, b: u64) -> Option<f64> {
    (a > 0).then(|| (b as f64 - a as f64) / a as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Held by each test that allocates 64 MiB: the heap and the resident set are the
    /// process's, so one test's block must not land between another's two readings
    /// (`heap_in_use_…` once read 64 MiB still in use after its free, the other test's).
    static LARGE_BLOCKS: std::sync::Mutex<()> = std::sync::Mutex::new(());

    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[test]
    fn heap_in_use_follows_an_allocation_and_its_release() {
        let _alone = LARGE_BLOCKS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let before = heap_in_use_bytes().expect("mallinfo2 on glibc");
        // Not touched: the heap counts what was handed out, resident or not.
        // (black_box: the optimiser may otherwise elide an allocation nothing writes to.)
        let block: Vec<u8> = std::hint::black_box(Vec::with_capacity(64 << 20));
        let held = heap_in_use_bytes().expect("mallinfo2 on glibc");
        assert!(block.capacity() >= 64 << 20);
        drop(block);
        let after = heap_in_use_bytes().expect("mallinfo2 on glibc");
        assert!(
            held >= before + (64 << 20),
            "heap {before} -> {held} bytes with 64 MiB allocated"
        );
        assert!(
            after + (60 << 20) <= held,
            "heap {held} -> {after} bytes after the 64 MiB were freed"
        );
    }

    #[test]
    fn resident_memory_is_read_and_follows_a_large_allocation() {
        let _alone = LARGE_BLOCKS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let before = resident_bytes().expect("/proc/self/statm on Linux");
        // Touch 64 MiB so that it becomes resident.
        let block = vec![1u8; 64 << 20];
        let after = resident_bytes().expect("/proc/self/statm on Linux");
        assert!(block.iter().step_by(4096).all(|&b| b == 1));
        assert!(
            after >= before + (48 << 20),
            "resident {before} -> {after} bytes after touching 64 MiB"
        );
    }

    #[test]
    fn growth_is_relative_to_the_earlier_reading() {
        let a = MemoryReading {
            heap_bytes: Some(50),
            resident_bytes: Some(100),
            gpu_objects: None,
        };
        let b = MemoryReading {
            heap_bytes: Some(51),
            resident_bytes: Some(104),
            gpu_objects: None,
        };
        assert_eq!(b.resident_growth_since(&a), Some(0.04));
        assert_eq!(b.heap_growth_since(&a), Some(0.02));
        assert_eq!(a.resident_growth_since(&MemoryReading::default()), None);
        assert_eq!(a.heap_growth_since(&MemoryReading::default()), None);
    }
}
