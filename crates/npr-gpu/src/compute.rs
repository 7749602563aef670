//! What the compute passes share (`PosingPass`, `CurvaturePass` here, and the technique
//! crates' own): their layout entries, pipelines, buffers, dispatch sizes and the check of
//! a buffer against the storage binding limit.

use crate::GpuError;
use wgpu::util::DeviceExt;

/// Invocations per workgroup of every compute entry point (`@workgroup_size(64)`).
pub const WORKGROUP: u32 = 64;

/// A buffer binding of type `ty` at `binding`, visible to the compute stage.
pub fn layout_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A storage buffer at `binding`, compute stage.
pub fn storage_layout_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    layout_entry(binding, wgpu::BufferBindingType::Storage { read_only })
}

/// The compute pipeline of `entry` in `module`, over one bind group of `layout`.
pub fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    entry: &str,
) -> wgpu::ComputePipeline {
    pipeline_over(device, module, &[layout], entry)
}

/// The compute pipeline of `entry` in `module`, over bind groups `0..layouts.len()` of
/// `layouts`.
pub fn pipeline_over(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    entry: &str,
) -> wgpu::ComputePipeline {
    let layout = crate::render::pipeline_layout(device, entry, layouts);
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    })
}

/// Writes a frame's values `head` at the start of `buffer` and its `records` right after
/// them: the layout of a storage buffer that leads with the frame's values and ends in a
/// runtime array (frame values kept out of uniform buffers, which some drivers compile
/// into the shader, compiling it again whenever they change).
pub fn write_head_and_records<H: bytemuck::Pod, R: bytemuck::Pod>(
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    head: &H,
    records: &[R],
) {
    // One write: each write is a staging upload of its own at the next submission.
    if records.is_empty() {
        queue.write_buffer(buffer, 0, bytemuck::bytes_of(head));
    } else {
        let mut bytes = bytemuck::bytes_of(head).to_vec();
        bytes.extend_from_slice(bytemuck::cast_slice(records));
        queue.write_buffer(buffer, 0, &bytes);
    }
}

/// A buffer of `data`, at least one element long (a binding may not be empty).
pub fn buffer_init<T: bytemuck::Pod + Default>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let one = [T::default()];
    let contents: &[T] = if data.is_empty() { &one } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(contents),
        usage,
    })
}

/// `buffer` whole at `binding`.
pub fn group_entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// Workgroup counts covering `n` invocations within the per-dimension limit (the shaders
/// fold `y` back into one index).
pub fn dispatch_size(n: usize, max_per_dimension: u32) -> (u32, u32) {
    let groups = n.div_ceil(WORKGROUP as usize).max(1) as u64;
    let max = u64::from(max_per_dimension.max(1));
    let y = groups.div_ceil(max);
    let x = groups.div_ceil(y);
    (x as u32, y as u32)
}

/// [`GpuError::MeshTooLarge`] for the first buffer (name, bytes) over the storage
/// binding limit.
pub fn check_bindings(buffers: &[(&'static str, u64)], limit: u64) -> Result<(), GpuError> {
    match buffers.iter().find(|(_, bytes)| *bytes > limit) {
        Some(&(buffer, size)) => Err(GpuError::MeshTooLarge {
            buffer,
            size,
            limit_name: "max_storage_buffer_binding_size",
            limit,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispatch_folds_past_the_per_dimension_limit() {
        assert_eq!(dispatch_size(0, 65_535), (1, 1));
        assert_eq!(dispatch_size(64 * 65_535, 65_535), (65_535, 1));
        let (x, y) = dispatch_size(64 * 65_536, 65_535);
        assert!(x <= 65_535 && y == 2 && u64::from(x) * u64::from(y) * 64 >= 64 * 65_536);
    }

    #[test]
    fn a_list_over_the_binding_limit_is_a_typed_error() {
        let limit = 128 << 20;
        assert!(check_bindings(&[("a", limit), ("b", 16)], limit).is_ok());
        let e = check_bindings(&[("a", 16), ("curvature ball list", limit + 4)], limit);
        assert!(matches!(
            e,
            Err(GpuError::MeshTooLarge {
                buffer: "curvature ball list",
                limit_name: "max_storage_buffer_binding_size",
                ..
            })
        ));
    }
}

/// Bind groups kept for the buffers they bind: a pass whose frame binds the same buffers
/// as an earlier one (a slot's own, a table that alternates between two) takes that
/// frame's group instead of making one, which costs the CPU tens of microseconds a
/// group. Holds the last few.
#[derive(Debug, Default)]
pub struct GroupCache {
    entries: Vec<(Vec<wgpu::Buffer>, wgpu::BindGroup)>,
}

impl GroupCache {
    /// Groups kept at most.
    const KEEP: usize = 4;

    /// The group made for `buffers` (in binding order), made by `make` the first time.
    pub fn get_or_make(
        &mut self,
        buffers: &[&wgpu::Buffer],
        make: impl FnOnce() -> wgpu::BindGroup,
    ) -> wgpu::BindGroup {
        let same = |kept: &[wgpu::Buffer]| {
            kept.len() == buffers.len() && kept.iter().zip(buffers).all(|(a, b)| a == *b)
        };
        if let Some((_, group)) = self.entries.iter().find(|(kept, _)| same(kept)) {
            return group.clone();
        }
        let group = make();
        if self.entries.len() == Self::KEEP {
            self.entries.remove(0);
        }
        let kept = buffers.iter().map(|b| (*b).clone()).collect();
        self.entries.push((kept, group.clone()));
        group
    }
}
