//! One search prepare's buffers and bind groups ([`Slot`]), made once per slot.

use super::{COUNTER_BYTES, MAX_MERGED, Params, Slot, readback, solution_entries};
use npr_gpu::compute::{buffer_init, group_entry};

pub(super) fn make_slot(
    device: &wgpu::Device,
    [layout, dispatch_layout]: [&wgpu::BindGroupLayout; 2],
    centres_layouts: [&wgpu::BindGroupLayout; 2],
    [
        vertices,
        triangles,
        order,
        clusters,
        field,
        adjacency,
        scratch,
    ]: [&wgpu::Buffer; 7],
    (capacity, cluster_count): (usize, usize),
) -> Slot {
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let frame = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr search frame"),
        size: COUNTER_BYTES + std::mem::size_of::<Params>() as u64,
        usage: storage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let solutions = buffer_init(
        device,
        "npr search solutions",
        &vec![[0u32; 4]; solution_entries(capacity)],
        storage,
    );
    let listed = buffer_init(
        device,
        "npr search listed clusters",
        &vec![0u32; cluster_count],
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    );
    let dispatch = buffer_init(
        device,
        "npr search dispatch",
        &[[0u32; 4]],
        storage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::INDIRECT,
    );
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr search readback"),
        size: readback::readback_bytes(capacity),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("npr centre search"),
        layout,
        entries: &[
            group_entry(0, vertices),
            group_entry(1, triangles),
            group_entry(2, &frame),
            group_entry(3, &solutions),
            group_entry(5, order),
            group_entry(6, clusters),
            group_entry(7, &listed),
        ],
    });
    let dispatch_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("npr centre search dispatch"),
        layout: dispatch_layout,
        entries: &[group_entry(0, &dispatch)],
    });
    let records = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr search centres"),
        // The search's centres, then the last frame's highlights placed again
        // (`cs_replace`).
        size: (readback::CENTRE_RECORD_BYTES * 2 * MAX_MERGED) as u64,
        usage: storage,
        mapped_at_creation: false,
    });
    let centres_groups = [
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr centre search centres tables"),
            layout: centres_layouts[0],
            entries: &[
                group_entry(0, vertices),
                group_entry(1, triangles),
                group_entry(2, &frame),
                group_entry(3, &solutions),
            ],
        }),
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr centre search centres"),
            layout: centres_layouts[1],
            entries: &[
                group_entry(1, field),
                group_entry(2, &records),
                group_entry(3, adjacency),
                group_entry(4, scratch),
            ],
        }),
    ];
    Slot {
        frame,
        solutions,
        dispatch,
        listed,
        readback,
        group,
        dispatch_group,
        records,
        centres_groups,
        active: false,
        peaks: None,
    }
}
