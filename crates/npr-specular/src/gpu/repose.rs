//! A new pose's tables made on the GPU (`shaders/repose.wgsl`): what
//! [`HighlightSet::repose`] rebuilds on the CPU for a skinned or morphed character's next
//! frame, written straight into the buffers the search, the regions, the receivers and the
//! highlight draw read, from the posed vertex buffer and the curvature
//! [`npr_gpu::CurvaturePass`] measured on it. Nothing is read back, so an animated model's
//! whole frame (pose, curvature, tables, search, regions, projectors, receivers, draw)
//! stays on the GPU: [`crate::gpu::FrameOnGpu::pose_on_gpu`].
//!
//! ```ignore
//! let repose = ReposePass::new(device);
//! let mut object = repose.create_object(device, &set, (&mesh, &gpu_mesh), &curvature, targets)?;
//! // per pose, after the posing and the curvature in the same encoder
//! let prepared = repose.prepare(queue, &mut object, &ReposeInput { frame })?;
//! repose.record(&mut encoder, &object, &prepared)?;
//! ```
//!
//! What is kept from the set (the pose it was built on) rather than measured per pose:
//! the weld and the connectivity, the search's face order and merge distance, and the
//! abstraction's number of diffusion steps (from the built pose's mean edge length and
//! radius; the CPU's repose measures them again, which a skinned pose barely changes).

use crate::{
    HighlightSet, SpecularError, gpu::ReceiverObject, gpu::RegionObject, gpu::SearchObject,
};
use npr_geometry::Mesh;
use npr_gpu::compute::{
    buffer_init, check_bindings, dispatch_size, group_entry, pipeline,
    storage_layout_entry as entry,
};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};
use npr_gpu::{CurvatureObject, GpuMesh};

/// The six pipelines of a pose's tables: one per device, shared by every object.
#[derive(Debug)]
pub struct ReposePass {
    id: PassId,
    device: wgpu::Device,
    /// `cs_weld`, `cs_diffuse`, `cs_finish`, `cs_faces`, `cs_clusters`,
    /// `cs_render_normals`, with their layouts.
    stages: Vec<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
}

/// What one pose's tables need: the frame (the positions and the field are the buffers
/// as the GPU has them when [`ReposePass::record`]'s work runs).
#[derive(Clone, Copy, Debug)]
pub struct ReposeInput {
    /// The caller's submission.
    pub frame: FrameId,
}

/// The buffers a pose's tables go to: those of one mesh's search, regions and receivers.
#[derive(Clone, Copy, Debug)]
pub struct ReposeTargets<'a> {
    /// The search's vertices, faces in its order, clusters and field.
    pub search: &'a SearchObject,
    /// The regions' vertices and faces.
    pub regions: &'a RegionObject,
    /// The receivers' positions and faces.
    pub receivers: &'a ReceiverObject,
}

/// One mesh's fixed lists for its poses, its bind groups and the highlight draw's normals.
#[derive(Debug)]
pub struct ReposeObject {
    welded: usize,
    faces: usize,
    render: usize,
    steps: usize,
    /// Bind groups: weld, diffuse (a → b, b → a), finish (from a, from b), faces,
    /// clusters, render normals.
    groups: Vec<wgpu::BindGroup>,
    render_normals: wgpu::Buffer,
    slots: Slots<()>,
}

/// `(binding, read only)` of each stage, in `stages` order.
const LAYOUTS: [&[(u32, bool)]; 6] = [
    &[
        (0, true),
        (1, true),
        (2, true),
        (3, false),
        (4, false),
        (5, true),
    ],
    &[(5, true), (6, true), (7, false), (8, true)],
    &[
        (1, true),
        (5, true),
        (9, true),
        (10, true),
        (11, false),
        (12, false),
        (13, false),
    ],
    &[
        (0, true),
        (5, true),
        (14, true),
        (15, true),
        (16, false),
        (17, false),
        (18, false),
    ],
    &[
        (5, true),
        (14, true),
        (15, true),
        (19, true),
        (20, true),
        (21, false),
        (22, false),
    ],
    &[(5, true), (15, true), (23, true), (24, false)],
];

const ENTRIES: [&str; 6] = [
    "cs_weld",
    "cs_diffuse",
    "cs_finish",
    "cs_faces",
    "cs_clusters",
    "cs_render_normals",
];

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE;

/// `offsets (n + 1)` then the lists, flat.
fn csr(lists: &[Vec<u32>]) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(lists.len() + 1);
    let mut flat = Vec::new();
    offsets.push(0u32);
    for l in lists {
        flat.extend_from_slice(l);
        offsets.push(flat.len() as u32);
    }
    offsets.extend(flat);
    offsets
}

impl ReposePass {
    /// Compiles `repose.wgsl`'s six entry points.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::REPOSE.module(device);
        let stages = LAYOUTS
            .iter()
            .zip(ENTRIES)
            .map(|(bindings, name)| {
                let entries: Vec<_> = bindings.iter().map(|&(b, ro)| entry(b, ro)).collect();
                let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(name),
                    entries: &entries,
                });
                (pipeline(device, &module, &layout, name), layout)
            })
            .collect();
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            stages,
        }
    }

    /// The fixed lists of `set`'s mesh (`mesh`, the render mesh `set` was built from, and
    /// `gpu`, its upload, whose vertex buffer holds each pose) and the bind groups that
    /// write its poses' tables into `targets` from `gpu`'s vertices and `curvature`'s
    /// field (measured on `gpu`).
    ///
    /// # Errors
    /// [`SpecularError::Mismatch`] when `mesh`, `gpu`, `curvature` and `set` are not one
    /// mesh (vertex, face or weld counts, or triangles that differ);
    /// [`npr_gpu::GpuError::MeshTooLarge`] when a list exceeds a storage binding.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        set: &HighlightSet,
        (mesh, gpu): (&Mesh, &GpuMesh),
        curvature: &CurvatureObject,
        targets: ReposeTargets<'_>,
    ) -> Result<ReposeObject, SpecularError> {
        let topo = set.topology();
        let (welded, faces, render) =
            (topo.vertex_count(), topo.face_count(), mesh.positions.len());
        let map = curvature.render_to_welded();
        let same = gpu.vertex_count as usize == render
            && gpu.index_count as usize == mesh.indices.len()
            && map.len() == render
            && curvature.welded_vertex_count() == welded
            && mesh.indices.len() == 3 * faces
            && (0..faces).all(|f| {
                (0..3).all(|k| {
                    let r = mesh.indices[3 * f + k] as usize;
                    map.get(r).copied() == Some(topo.triangles[f][k])
                })
            });
        if !same {
            return Err(SpecularError::Mismatch(format!(
                "a pose's tables for a set of {welded} vertices and {faces} faces from a mesh of {render} vertices, an upload of {} and a curvature of {}",
                gpu.vertex_count,
                curvature.welded_vertex_count()
            )));
        }
        let mut weld_lists = vec![Vec::new(); welded];
        for (r, &w) in map.iter().enumerate() {
            weld_lists[w as usize].push(r as u32);
        }
        let weld = csr(&weld_lists);
        // The diffusion's graph, as `CurvatureField::at_scale` walks it.
        let (mut neighbours, list) = topo.vertex_neighbours();
        neighbours.extend(list);
        let triangles: Vec<[u32; 4]> = (0..faces)
            .flat_map(|f| {
                let t = topo.triangles[f];
                let twice = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
                let r = &mesh.indices[3 * f..3 * f + 3];
                [[t[0], t[1], t[2], u32::from(twice)], [r[0], r[1], r[2], 0]]
            })
            .collect();
        check_bindings(
            &[
                ("repose weld", weld.len() as u64 * 4),
                ("repose neighbours", neighbours.len() as u64 * 4),
                ("repose triangles", triangles.len() as u64 * 16),
                ("repose values", welded as u64 * 48),
                ("repose render normals", render as u64 * 16),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        let steps = set.diffusion_steps();
        let params: [u32; 8] = [
            welded as u32,
            faces as u32,
            render as u32,
            u32::from(set.abstraction() > 0.0),
            u32::from(mesh.normals.len() == render),
            faces.div_ceil(crate::cpu::clusters::CLUSTER_FACES) as u32,
            npr_geometry::HighlightSearch::angle_margin().to_bits(),
            crate::cpu::clusters::SAFETY.to_bits(),
        ];
        let buffer = |label: &str, data: &[u32]| buffer_init(device, label, data, STORAGE);
        let params = buffer("npr repose params", &params);
        let weld = buffer("npr repose weld", &weld);
        let neighbours = buffer("npr repose neighbours", &neighbours);
        let triangles = buffer_init(device, "npr repose triangles", &triangles, STORAGE);
        let (order, margins) = (
            buffer("npr repose order", targets.search.face_order()),
            buffer("npr repose margins", &vec![0u32; faces]),
        );
        let map = buffer("npr repose render to welded", map);
        let values = |label| buffer_init(device, label, &vec![[0f32; 4]; 3 * welded], STORAGE);
        let (a, b) = (values("npr repose values a"), values("npr repose values b"));
        let render_normals = buffer_init(
            device,
            "npr repose render normals",
            &vec![[0f32; 4]; render],
            STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let [s_vertices, s_ordered, s_clusters, s_field] = targets.search.pose_tables();
        let [r_vertices, r_faces] = targets.regions.pose_tables();
        let [positions, receiver_faces] = targets.receivers.pose_tables();
        let (vertices, field) = (&gpu.vertex_buffer, curvature.output());
        let bound: [Vec<(u32, &wgpu::Buffer)>; 8] = [
            vec![
                (0, vertices),
                (1, field),
                (2, &weld),
                (3, &a),
                (4, positions),
                (5, &params),
            ],
            vec![(5, &params), (6, &a), (7, &b), (8, &neighbours)],
            vec![(5, &params), (6, &b), (7, &a), (8, &neighbours)],
            finish_entries(
                field,
                &params,
                &a,
                positions,
                [s_vertices, s_field, r_vertices],
            ),
            finish_entries(
                field,
                &params,
                &b,
                positions,
                [s_vertices, s_field, r_vertices],
            ),
            vec![
                (0, vertices),
                (5, &params),
                (14, &triangles),
                (15, s_vertices),
                (16, &margins),
                (17, r_faces),
                (18, receiver_faces),
            ],
            vec![
                (5, &params),
                (14, &triangles),
                (15, s_vertices),
                (19, &order),
                (20, &margins),
                (21, s_ordered),
                (22, s_clusters),
            ],
            vec![
                (5, &params),
                (15, s_vertices),
                (23, &map),
                (24, &render_normals),
            ],
        ];
        let stage_of = [0, 1, 1, 2, 2, 3, 4, 5];
        let groups = bound
            .iter()
            .zip(stage_of)
            .map(|(entries, stage)| {
                let entries: Vec<_> = entries
                    .iter()
                    .map(|&(b, buf)| group_entry(b, buf))
                    .collect();
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(ENTRIES[stage]),
                    layout: &self.stages[stage].1,
                    entries: &entries,
                })
            })
            .collect();
        Ok(ReposeObject {
            welded,
            faces,
            render,
            steps,
            groups,
            render_normals,
            slots: Slots::new(self.id),
        })
    }

    /// Takes a slot of `object` for `input.frame`. The tables have no per-frame values
    /// of their own (the pose is already on the GPU), so nothing is written.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a foreign object or too many prepares in one frame.
    pub fn prepare(
        &self,
        _queue: &wgpu::Queue,
        object: &mut ReposeObject,
        input: &ReposeInput,
    ) -> Result<Prepared, SpecularError> {
        let (prepared, _) = object.slots.next(self.id, input.frame, || ())?;
        Ok(prepared)
    }

    /// Records the pose's tables into `encoder`: after the passes that write the
    /// positions (posing) and the field (curvature), before the search.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another pass, object or frame; nothing
    /// is recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &ReposeObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        object.slots.get(self.id, prepared)?;
        let max = self.device.limits().max_compute_workgroups_per_dimension;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr repose"),
            timestamp_writes: None,
        });
        let mut run = |stage: usize, group: usize, n: usize| {
            let (x, y) = dispatch_size(n, max);
            pass.set_pipeline(&self.stages[stage].0);
            pass.set_bind_group(0, &object.groups[group], &[]);
            pass.dispatch_workgroups(x, y, 1);
        };
        run(0, 0, object.welded);
        for step in 0..object.steps {
            run(1, 1 + step % 2, object.welded);
        }
        // After an odd number of steps the values are in `b`.
        run(2, 3 + object.steps % 2, object.welded);
        run(3, 5, object.faces);
        let clusters = object.faces.div_ceil(crate::cpu::clusters::CLUSTER_FACES);
        run(4, 6, clusters * crate::cpu::clusters::CLUSTER_FACES);
        run(5, 7, object.render);
        Ok(())
    }
}

/// `cs_finish`'s bindings reading the values from `values`.
fn finish_entries<'a>(
    field: &'a wgpu::Buffer,
    params: &'a wgpu::Buffer,
    values: &'a wgpu::Buffer,
    positions: &'a wgpu::Buffer,
    [solve, field_out, region_vertices]: [&'a wgpu::Buffer; 3],
) -> Vec<(u32, &'a wgpu::Buffer)> {
    vec![
        (1, field),
        (5, params),
        (9, values),
        (10, positions),
        (11, solve),
        (12, field_out),
        (13, region_vertices),
    ]
}

impl ReposeObject {
    /// The highlight draw's normals of the last pose, one per render vertex (`w` = 0
    /// where the draw keeps the vertex buffer's own).
    pub fn render_normals(&self) -> &wgpu::Buffer {
        &self.render_normals
    }

    /// The abstraction's diffusion steps each pose runs.
    pub fn diffusion_steps(&self) -> usize {
        self.steps
    }
}

#[cfg(test)]
#[path = "repose_tests.rs"]
mod tests;
