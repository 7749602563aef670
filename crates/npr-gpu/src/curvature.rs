//! Curvature on the GPU: the per-vertex tensor of Lee & Choi §2.2, Eq. (1), in the
//! corrected form ([`npr_geometry::CurvatureMethod::Corrected`], the default), with its
//! principal curvatures and directions, as two compute passes over the mesh's own vertex
//! buffer, so a mesh posed on the GPU ([`crate::posing`]) is measured every frame without
//! a copy (after Griffin, Wang, Berrios and Olano, "Real-time GPU surface curvature
//! estimation on deforming meshes and volumetric data sets", IEEE TVCG 18(10), 2012:
//! per-vertex tensors gathered on the GPU).
//!
//! It speaks the pass contract ([`crate::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let curvature = CurvaturePass::new(device);
//! let mut object = curvature.create_object(device, &gpu_mesh, &mesh, CurvatureRadius::default())?;
//! // per frame, after the pass that poses `gpu_mesh` (if any)
//! let prepared = curvature.prepare(queue, &mut object, &CurvatureInput { frame })?;
//! curvature.record(&mut encoder, &object, &prepared)?;
//! // `object.output()` now holds the field, per welded vertex (`CurvatureObject::decode`)
//! ```
//!
//! What is fixed at [`CurvaturePass::create_object`], from the mesh it is given: the weld
//! (render vertex → welded vertex, and one render vertex read per welded vertex), each
//! face's neighbours across its edges, the ball radius (in world units, from the mesh's
//! mean edge length for [`CurvatureRadius::EdgeLengths`]), and each vertex's ball as a
//! list of faces ([`npr_geometry::CurvatureField::corrected_balls`]: the faces the CPU's
//! walk visits, those inside and the ring around them). What is measured every frame from
//! the current positions: face normals, areas, centroids, dihedral angles, the edges'
//! tensors, which listed faces are inside the ball and their weights, the vertex normals
//! and the eigen-analysis. So on the mesh given to `create_object` the field is the CPU's
//! ([`npr_geometry::CurvatureField::compute`]); on a pose of it, the ball keeps that
//! mesh's connectivity (a face that moves into the ball from beyond the listed ring is not
//! seen, and the radius does not follow the pose's edge lengths).
//!
//! The WGSL is `shaders/curvature.wgsl` (`cs_faces`, `cs_vertices`), whose functions name
//! their Rust twins; the 2×2 eigen solve is `sym2_eigen`, the twin of the CPU's closed
//! form. WGSL has no `f64`: the GPU sums in `f32` where the CPU builds faces in `f64`
//! (it sums the ball in `f32` too). Meshes far from unit size, which the CPU measures on a
//! copy scaled by a power of two, are measured as they are (the scaling is exact, so only
//! the `f32` range differs).

use crate::compute::{
    buffer_init as buffer, check_bindings, dispatch_size, group_entry as entry,
    layout_entry as compute_entry, pipeline, storage_layout_entry as storage_entry,
};
use crate::pass::{FrameId, PassId, Prepared, Slots};
use crate::{GpuError, GpuMesh};
use glam::Vec3;
use npr_geometry::{CurvatureField, CurvatureMethod, CurvatureRadius, EdgeKind, Mesh, Topology};

/// `NONE` of `curvature.wgsl`: a face corner whose edge has no dihedral angle.
const NONE: u32 = u32::MAX;
/// `f32`s per welded vertex in [`CurvatureObject::output`].
pub const OUTPUT_FLOATS: usize = 12;

/// The reach [`CurvaturePass::create_object_with_reach`] suits a moving mesh's poses
/// with: each ball listed half as far again as its radius, so a pose that brings faces
/// up to a third closer (a stretched or bent limb) is still measured as the CPU measures
/// it at the same radius.
pub const POSE_REACH: f32 = 1.5;

/// The two compute pipelines of curvature: one per device, shared by every object.
#[derive(Debug)]
pub struct CurvaturePass {
    id: PassId,
    device: wgpu::Device,
    faces_pipeline: wgpu::ComputePipeline,
    vertices_pipeline: wgpu::ComputePipeline,
    faces_layout: wgpu::BindGroupLayout,
    vertices_layout: wgpu::BindGroupLayout,
    /// A list binding limit below the device's, to split small meshes in tests.
    max_list_binding: Option<u64>,
}

/// What one measurement needs: the frame it is for (the positions are the mesh's vertex
/// buffer as the GPU has it when [`CurvaturePass::record`]'s work runs).
#[derive(Clone, Copy, Debug)]
pub struct CurvatureInput {
    /// The caller's submission.
    pub frame: FrameId,
}

/// One mesh's curvature on the GPU: its fixed lists and the output buffer the later
/// passes read.
///
/// The output holds [`OUTPUT_FLOATS`] `f32` per welded vertex: `(normal, kappa_max)`,
/// `(dir_kappa_max, kappa_min)`, `(dir_kappa_min, valid ? 1 : 0)`, with the conventions of
/// [`CurvatureField`].
#[derive(Debug)]
pub struct CurvatureObject {
    welded: usize,
    faces: usize,
    ball_entries: usize,
    radius_world: f32,
    render_to_welded: Vec<u32>,
    output: wgpu::Buffer,
    faces_group: wgpu::BindGroup,
    /// One bind group and vertex count per chunk of welded vertices (see [`chunks`]).
    vertex_chunks: Vec<(wgpu::BindGroup, usize)>,
    slots: Slots<()>,
}

/// The fixed data of one mesh as the shader reads it (see `curvature.wgsl`).
struct Lists {
    /// Per face: corners, then the third vertex across each edge (render vertices).
    faces: Vec<[u32; 4]>,
    /// Per welded vertex: first own face, first ball face, end, render vertex.
    ranges: Vec<[u32; 4]>,
    /// Own faces and ball faces, vertex after vertex.
    lists: Vec<u32>,
}

/// The render vertex each welded vertex is read from (its first render vertex).
fn representatives(render_to_welded: &[u32], welded: usize) -> Vec<u32> {
    let mut rep = vec![0u32; welded];
    let mut seen = vec![false; welded];
    for (r, &w) in render_to_welded.iter().enumerate() {
        if let (Some(s), Some(x)) = (seen.get_mut(w as usize), rep.get_mut(w as usize)) {
            if !*s {
                *s = true;
                *x = r as u32;
            }
        }
    }
    rep
}

/// Per face corner `k`, the vertex of the face across edge `k → k+1` that is not on the
/// edge, where that edge has a dihedral angle (an interior edge, [`EdgeKind::Interior`]).
fn across(topo: &Topology, f: usize) -> [u32; 3] {
    let mut out = [NONE; 3];
    let Some(t) = topo.triangles.get(f) else {
        return out;
    };
    for (k, o) in out.iter_mut().enumerate() {
        let e = topo.face_edges[f][k];
        if e == npr_geometry::topology::NO_EDGE || topo.edge_kind(e as usize) != EdgeKind::Interior
        {
            continue;
        }
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let other = topo
            .edge_faces(e as usize)
            .iter()
            .copied()
            .find(|&g| g as usize != f);
        if let Some(g) = other.and_then(|g| topo.triangles.get(g as usize)) {
            if let Some(&c) = g.iter().find(|&&c| c != a && c != b) {
                *o = c;
            }
        }
    }
    out
}

/// # Errors
/// [`GpuError::MeshTooLarge`] when the lists have more entries than a `u32` counts.
fn lists(topo: &Topology, rep: &[u32], radius: f32) -> Result<Lists, GpuError> {
    let nv = topo.vertex_count();
    let to_render = |w: u32| rep.get(w as usize).copied().unwrap_or(0);
    let mut faces = Vec::with_capacity(2 * topo.face_count());
    for (f, t) in topo.triangles.iter().enumerate() {
        if t.iter().any(|&i| i as usize >= nv) {
            faces.push([0; 4]);
            faces.push([NONE, NONE, NONE, 0]);
            continue;
        }
        faces.push([to_render(t[0]), to_render(t[1]), to_render(t[2]), 0]);
        let o = across(topo, f).map(|c| if c == NONE { NONE } else { to_render(c) });
        faces.push([o[0], o[1], o[2], 0]);
    }
    let balls = CurvatureField::corrected_balls(topo, radius);
    let mut ranges = Vec::with_capacity(nv);
    let mut lists = Vec::with_capacity(balls.faces.len() + 6 * nv);
    for v in 0..nv {
        let own = lists.len() as u32;
        lists.extend_from_slice(topo.vertex_faces(v));
        let first = lists.len() as u32;
        lists.extend_from_slice(balls.of(v));
        ranges.push([own, first, lists.len() as u32, to_render(v as u32)]);
    }
    if u32::try_from(lists.len()).is_err() {
        return Err(GpuError::MeshTooLarge {
            buffer: "curvature ball list",
            size: lists.len() as u64 * 4,
            limit_name: "u32 list offsets",
            limit: u64::from(u32::MAX) * 4,
        });
    }
    Ok(Lists {
        faces,
        ranges,
        lists,
    })
}

/// `CurvatureParams` of `curvature.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    radius: f32,
    vertex_count: u32,
    face_count: u32,
    first_vertex: u32,
}

/// Splits the welded vertices into runs whose face lists (each vertex's own faces, then
/// its ball's: `ranges[v].x .. ranges[v].z` of one list) and ranges (16 bytes a vertex)
/// each fit `limit` bytes, so a mesh whose lists exceed one storage binding is measured
/// in several dispatches.
///
/// # Errors
/// [`GpuError::MeshTooLarge`] when one vertex's lists alone exceed `limit`.
fn chunks(ranges: &[[u32; 4]], limit: u64) -> Result<Vec<std::ops::Range<usize>>, GpuError> {
    let mut out = Vec::new();
    let mut start = 0;
    for (v, r) in ranges.iter().enumerate() {
        let own = u64::from(r[2] - r[0]) * 4;
        check_bindings(&[("curvature ball list", own)], limit)?;
        let first = u64::from(ranges[start][0]);
        let lists = (u64::from(r[2]) - first) * 4;
        let count = (v + 1 - start) as u64 * 16;
        if lists > limit || count > limit {
            out.push(start..v);
            start = v;
        }
    }
    if start < ranges.len() || out.is_empty() {
        out.push(start..ranges.len());
    }
    Ok(out)
}

impl CurvaturePass {
    /// The two compute pipelines (per face, per welded vertex). A compute pass draws into
    /// no target, so it takes no [`crate::TargetFormats`].
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::CURVATURE_FILE.module(device);
        let mut faces_entries: Vec<_> = (0..3).map(|b| storage_entry(b, b != 2)).collect();
        faces_entries.push(compute_entry(13, wgpu::BufferBindingType::Uniform));
        let faces_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr curvature faces"),
            entries: &faces_entries,
        });
        let mut vertices_entries: Vec<_> = (8..13).map(|b| storage_entry(b, b != 12)).collect();
        vertices_entries.push(compute_entry(13, wgpu::BufferBindingType::Uniform));
        let vertices_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr curvature vertices"),
            entries: &vertices_entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            faces_pipeline: pipeline(device, &module, &faces_layout, "cs_faces"),
            vertices_pipeline: pipeline(device, &module, &vertices_layout, "cs_vertices"),
            faces_layout,
            vertices_layout,
            max_list_binding: None,
        }
    }

    /// Builds `mesh`'s fixed lists (weld, topology, each vertex's ball at `radius`) and
    /// the output buffer; `gpu` is `mesh` as uploaded (the same render vertices and
    /// triangles, in the same order), whose vertex buffer the object keeps and reads in
    /// [`CurvaturePass::record`]. The method is [`CurvatureMethod::Corrected`].
    ///
    /// # Errors
    /// [`GpuError::InvalidMesh`] when `gpu` and `mesh` differ in vertex or index count;
    /// [`GpuError::MeshTooLarge`] when a buffer would exceed the device's storage binding
    /// limit. The per-vertex face lists (about 100 faces a vertex at the default radius,
    /// over 128 MiB on a 1.1M-face mesh) are split into chunks of vertices that each fit one
    /// binding, measured in one dispatch each ([`CurvatureObject::chunk_count`]); the
    /// per-face records and the output are not split (64 and 48 bytes per face and
    /// vertex: 2M faces fit the default 128 MiB).
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        gpu: &GpuMesh,
        mesh: &Mesh,
        radius: CurvatureRadius,
    ) -> Result<CurvatureObject, GpuError> {
        self.create_object_with_reach(device, gpu, mesh, radius, 1.0)
    }

    /// [`CurvaturePass::create_object`] for the poses of a moving mesh: each vertex's
    /// ball is listed as the walk at `reach × radius` finds it on `mesh` (`reach` at least
    /// 1), and measured every frame at the radius, so a pose that brings faces closer
    /// (a stretched or bent part) still finds those within the radius, up to a shrink of
    /// `1 / reach`. The lists grow as `reach²` (and with them the memory and each frame's
    /// work). Where a face lies within the radius only through faces beyond it (the other
    /// side of a narrow fold) the field differs from the CPU's walk even on `mesh`.
    ///
    /// # Errors
    /// As [`CurvaturePass::create_object`].
    pub fn create_object_with_reach(
        &self,
        device: &wgpu::Device,
        gpu: &GpuMesh,
        mesh: &Mesh,
        radius: CurvatureRadius,
        reach: f32,
    ) -> Result<CurvatureObject, GpuError> {
        if gpu.vertex_count as usize != mesh.positions.len()
            || gpu.index_count as usize != mesh.indices.len()
        {
            return Err(GpuError::InvalidMesh(format!(
                "curvature of a mesh of {} vertices and {} indices measured on an upload of {} and {}",
                mesh.positions.len(),
                mesh.indices.len(),
                gpu.vertex_count,
                gpu.index_count
            )));
        }
        let welded = npr_geometry::weld(mesh);
        let topo = Topology::new(&welded);
        let radius_world = radius.world(&topo);
        let nv = topo.vertex_count();
        let nf = topo.face_count();
        // The ball lists are the big one (about 100 faces a vertex at the default radius).
        let rep = representatives(&welded.render_to_welded, nv);
        let reach = if reach.is_finite() {
            reach.max(1.0)
        } else {
            1.0
        };
        let data = lists(&topo, &rep, reach * radius_world)?;
        let limit = device.limits().max_storage_buffer_binding_size;
        let runs = chunks(
            &data.ranges,
            self.max_list_binding.unwrap_or(limit).min(limit),
        )?;
        check_bindings(
            &[
                ("curvature face", data.faces.len() as u64 * 16),
                ("curvature face record", nf as u64 * 64),
                ("curvature output", (nv * OUTPUT_FLOATS * 4) as u64),
            ],
            limit,
        )?;
        let storage = wgpu::BufferUsages::STORAGE;
        let faces = buffer(device, "npr curvature faces", &data.faces, storage);
        let records = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr curvature face records"),
            size: (nf.max(1) * 64) as u64,
            usage: storage,
            mapped_at_creation: false,
        });
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr curvature output"),
            size: (nv.max(1) * OUTPUT_FLOATS * 4) as u64,
            usage: storage | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let params = |vertex_count: usize, first_vertex: usize| {
            let params = Params {
                radius: radius_world,
                vertex_count: vertex_count as u32,
                face_count: nf as u32,
                first_vertex: first_vertex as u32,
            };
            buffer(
                device,
                "npr curvature params",
                &[params],
                wgpu::BufferUsages::UNIFORM,
            )
        };
        let faces_params = params(nv, 0);
        let faces_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr curvature faces"),
            layout: &self.faces_layout,
            entries: &[
                entry(0, &gpu.vertex_buffer),
                entry(1, &faces),
                entry(2, &records),
                entry(13, &faces_params),
            ],
        });
        let vertex_chunks = runs
            .into_iter()
            .map(|run| {
                let params = params(run.len(), run.start);
                let group = self.chunk_group(
                    device,
                    &data,
                    &run,
                    [&gpu.vertex_buffer, &records, &output, &params],
                );
                (group, run.len())
            })
            .collect();
        Ok(CurvatureObject {
            welded: nv,
            faces: nf,
            ball_entries: data.lists.len(),
            radius_world,
            render_to_welded: welded.render_to_welded,
            output,
            faces_group,
            vertex_chunks,
            slots: Slots::new(self.id),
        })
    }

    /// The per-vertex bind group of the welded vertices `run`: their ranges rebased on
    /// their own slice of the lists, with the mesh's `vertices`, the face `records`, the
    /// `output` and the chunk's `params`.
    fn chunk_group(
        &self,
        device: &wgpu::Device,
        data: &Lists,
        run: &std::ops::Range<usize>,
        [vertices, records, output, params]: [&wgpu::Buffer; 4],
    ) -> wgpu::BindGroup {
        let storage = wgpu::BufferUsages::STORAGE;
        let first = data.ranges.get(run.start).map_or(0, |r| r[0]);
        let end = run
            .end
            .checked_sub(1)
            .and_then(|l| data.ranges.get(l))
            .map_or(first, |r| r[2]);
        let local: Vec<[u32; 4]> = data.ranges[run.clone()]
            .iter()
            .map(|r| [r[0] - first, r[1] - first, r[2] - first, r[3]])
            .collect();
        let slice = &data.lists[first as usize..end as usize];
        let ranges = buffer(device, "npr curvature ranges", &local, storage);
        let balls = buffer(device, "npr curvature balls", slice, storage);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr curvature vertices"),
            layout: &self.vertices_layout,
            entries: &[
                entry(8, vertices),
                entry(9, &ranges),
                entry(10, records),
                entry(11, &balls),
                entry(12, output),
                entry(13, params),
            ],
        })
    }

    /// Takes a slot of `object` for `input.frame`. Curvature has no per-frame data of its
    /// own (the positions are already on the GPU), so it writes nothing to the queue.
    ///
    /// # Errors
    /// [`GpuError::Pass`] for a foreign object or too many prepares in one frame.
    pub fn prepare(
        &self,
        _queue: &wgpu::Queue,
        object: &mut CurvatureObject,
        input: &CurvatureInput,
    ) -> Result<Prepared, GpuError> {
        let (prepared, _) = object.slots.next(self.id, input.frame, || ())?;
        Ok(prepared)
    }

    /// Records the measurement into `encoder`: per face, then per welded vertex, into
    /// [`CurvatureObject::output`]. Record it after the pass that writes the positions
    /// (posing) and before the passes that read the field.
    ///
    /// # Errors
    /// [`GpuError::Pass`] for a `prepared` of another pass, object or frame; nothing is
    /// recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &CurvatureObject,
        prepared: &Prepared,
    ) -> Result<(), GpuError> {
        object.slots.get(self.id, prepared)?;
        let max = self.device.limits().max_compute_workgroups_per_dimension;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr curvature"),
            timestamp_writes: None,
        });
        let (x, y) = dispatch_size(object.faces, max);
        pass.set_pipeline(&self.faces_pipeline);
        pass.set_bind_group(0, &object.faces_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
        pass.set_pipeline(&self.vertices_pipeline);
        for (group, count) in &object.vertex_chunks {
            let (x, y) = dispatch_size(*count, max);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        Ok(())
    }
}

impl CurvatureObject {
    /// The output buffer: [`OUTPUT_FLOATS`] `f32` per welded vertex (see the type's doc).
    pub fn output(&self) -> &wgpu::Buffer {
        &self.output
    }

    /// Number of welded vertices (entries of the output).
    pub fn welded_vertex_count(&self) -> usize {
        self.welded
    }

    /// Dispatches of the per-vertex pass: the welded vertices split so that each chunk's
    /// face lists fit one storage binding (1 for a mesh whose lists fit whole).
    pub fn chunk_count(&self) -> usize {
        self.vertex_chunks.len()
    }

    /// Entries of the per-vertex face lists (each vertex's own faces, then its ball's):
    /// the largest buffer of the object, 4 bytes each.
    pub fn ball_entries(&self) -> usize {
        self.ball_entries
    }

    /// For each render vertex of the mesh, its welded vertex (its entry of the output).
    pub fn render_to_welded(&self) -> &[u32] {
        &self.render_to_welded
    }

    /// The ball radius in world units, fixed at `create_object`.
    pub fn radius_world(&self) -> f32 {
        self.radius_world
    }

    /// The field from the bytes of a readback of [`CurvatureObject::output`] (for tests
    /// and tools; nothing on a frame's path reads it back). Entries past the bytes given
    /// are invalid.
    pub fn decode(&self, bytes: &[u8]) -> CurvatureField {
        let mut field = CurvatureField {
            radius_world: self.radius_world,
            method: CurvatureMethod::Corrected,
            ..CurvatureField::default()
        };
        let floats: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        for v in 0..self.welded {
            let c = floats
                .get(v * OUTPUT_FLOATS..(v + 1) * OUTPUT_FLOATS)
                .unwrap_or(&[0.0; OUTPUT_FLOATS]);
            field.normal.push(Vec3::new(c[0], c[1], c[2]));
            field.kappa_max.push(c[3]);
            field.dir_kappa_max.push(Vec3::new(c[4], c[5], c[6]));
            field.kappa_min.push(c[7]);
            field.dir_kappa_min.push(Vec3::new(c[8], c[9], c[10]));
            field.valid.push(c[11] == 1.0);
        }
        field
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_layout_matches_wgsl() {
        crate::assert_wgsl_layout!(
            crate::shaders::ALL,
            Params,
            "CurvatureParams",
            [radius, vertex_count, face_count, first_vertex]
        );
    }

    /// The ranges of vertices with `sizes[v]` list entries each.
    fn ranges_of(sizes: &[u32]) -> Vec<[u32; 4]> {
        let mut at = 0;
        sizes
            .iter()
            .map(|&n| {
                let r = [at, at + 1, at + n, 0];
                at += n;
                r
            })
            .collect()
    }

    #[test]
    fn vertices_split_where_their_lists_would_exceed_a_binding() {
        // 10 entries (40 bytes) a vertex, 100 bytes a binding: two vertices a chunk.
        let ranges = ranges_of(&[10; 5]);
        let runs = chunks(&ranges, 100).unwrap();
        assert_eq!(runs, vec![0..2, 2..4, 4..5]);
        assert_eq!(chunks(&ranges, 1 << 20).unwrap(), vec![0..5]);
        // One vertex whose lists alone exceed the binding: a typed error.
        assert!(matches!(
            chunks(&ranges_of(&[10, 40]), 100),
            Err(GpuError::MeshTooLarge { .. })
        ));
        assert_eq!(chunks(&[], 100).unwrap(), vec![0..0]);
    }

    #[test]
    fn a_mesh_measured_in_chunks_equals_it_measured_whole() {
        let Some(ctx) =
            crate::testing::context_or_skip("a_mesh_measured_in_chunks_equals_it_measured_whole")
        else {
            return;
        };
        let (device, queue) = (&ctx.device, &ctx.queue);
        let mesh = npr_geometry::generate::torus(1.0, 0.35, 48, 24);
        let gpu = GpuMesh::upload(device, &mesh).unwrap();
        let measure = |pass: &CurvaturePass| {
            let mut object = pass
                .create_object(device, &gpu, &mesh, CurvatureRadius::default())
                .unwrap();
            let prepared = pass
                .prepare(queue, &mut object, &CurvatureInput { frame: FrameId(1) })
                .unwrap();
            let mut encoder = device.create_command_encoder(&Default::default());
            pass.record(&mut encoder, &object, &prepared).unwrap();
            let read = crate::testing::copy_for_readback(device, &mut encoder, object.output());
            queue.submit([encoder.finish()]);
            (
                object.chunk_count(),
                object.ball_entries(),
                crate::testing::read_mapped(device, &read),
            )
        };
        let whole = CurvaturePass::new(device);
        let (one, entries, expected) = measure(&whole);
        assert_eq!(one, 1);
        // A binding a seventh of the lists: at least seven chunks.
        let mut split = CurvaturePass::new(device);
        split.max_list_binding = Some(entries as u64 * 4 / 7);
        let (many, _, got) = measure(&split);
        assert!(many >= 7, "{many} chunks");
        assert_eq!(got, expected, "chunked output differs from the whole");
        let field = whole.create_object(device, &gpu, &mesh, CurvatureRadius::default());
        let valid = field
            .unwrap()
            .decode(&got)
            .valid
            .iter()
            .filter(|v| **v)
            .count();
        assert!(valid > mesh.positions.len() / 2, "{valid} valid vertices");
    }

    #[test]
    fn representatives_are_first_render_vertices() {
        assert_eq!(representatives(&[0, 1, 0, 2, 1], 3), vec![0, 1, 3]);
        // An out-of-range entry (a bad weld) is ignored, not a panic.
        assert_eq!(representatives(&[0, u32::MAX], 1), vec![0]);
    }
}
