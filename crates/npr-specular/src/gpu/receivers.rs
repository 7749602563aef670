//! The receivers of §4.2 as a compute pass (`shaders/receivers.wgsl`): each highlight's
//! breadth-first walk from the face holding its centre, one workgroup per highlight, and
//! the received faces laid out as the highlight pass's vertex stream with the indirect
//! draw's count. Nothing mesh-sized is read back: the CPU writes one small record per
//! highlight (its projector's map, facing rule and start face), and the highlight pass
//! draws the stream where it lies (a [`crate::HighlightFrame`] of [`crate::Backend::Gpu`],
//! whose frames walk the projectors [`crate::gpu::ProjectorPass`] built:
//! [`ReceiverPass::prepare_on_projectors`]).
//!
//! It speaks the pass contract ([`npr_gpu::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let receivers = ReceiverPass::new(device);
//! let mut walk = receivers.create_object(device, &set, &mesh.indices)?;
//! // per frame, after set.update(..)
//! let input = ReceiverInput { frame, set: &set, world_from_object };
//! let walked = receivers.prepare(queue, &mut walk, &input)?;
//! receivers.record(&mut encoder, &walk, &walked)?;
//! let read = walk.read(device, queue, &walked)?; // a test's or a panel's readback
//! ```
//!
//! The CPU walk ([`crate::cpu::visibility::receivers_within`]) is the reference:
//! `tests/gpu_receivers.rs` compares the two on the same frame. A walk longer than the
//! object's capacity stops there and says so ([`ReceiverCounts::overflowed`]).

use crate::cpu::set::ReceiverRule;
use crate::cpu::visibility::{is_similarity, object_space, walk_box};
use crate::{HighlightSet, SpecularError};
use glam::{Mat3, Mat4};
use npr_gpu::compute::{buffer_init, check_bindings, group_entry, layout_entry, pipeline};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};

/// Faces one highlight's walk may cross by default (its queue's length).
pub const DEFAULT_WALK_CAPACITY: usize = 16_384;

/// The walk's compute pipelines: one set per device, shared by every object.
#[derive(Debug)]
pub struct ReceiverPass {
    id: PassId,
    device: wgpu::Device,
    layout: wgpu::BindGroupLayout,
    walk: wgpu::ComputePipeline,
    offsets: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
}

/// One frame's walk: the set, updated for the frame, and the object's transform (the one
/// the update was given).
#[derive(Clone, Copy, Debug)]
pub struct ReceiverInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The highlight set, updated for this frame.
    pub set: &'a HighlightSet,
    /// The object's transform.
    pub world_from_object: Mat4,
}

/// One mesh's tables on the GPU (positions, faces, adjacency) and the walks' scratch.
#[derive(Debug)]
pub struct ReceiverObject {
    normals_id: u64,
    faces: usize,
    vertices: usize,
    capacity: usize,
    render: Vec<[u32; 3]>,
    positions: wgpu::Buffer,
    face_records: wgpu::Buffer,
    adjacency: wgpu::Buffer,
    /// Per face one bit per highlight; `words` per face.
    visited: wgpu::Buffer,
    words: usize,
    /// Per highlight its queue and its received faces; room for `work_highlights`.
    work: wgpu::Buffer,
    work_highlights: usize,
    slots: Slots<Slot>,
}

/// One prepare's params and queries (one buffer: `ReceiverFrame`), counts (with the
/// indirect draw's arguments) and stream.
#[derive(Debug)]
struct Slot {
    queries: wgpu::Buffer,
    meta: wgpu::Buffer,
    list: wgpu::Buffer,
    list_faces: usize,
    group: Option<wgpu::BindGroup>,
    /// The groups of earlier frames.
    groups: npr_gpu::compute::GroupCache,
    /// Highlights the buffers have room for.
    room: usize,
    /// Highlights this frame walks.
    count: usize,
}

/// One highlight's walk as [`ReceiverObject::read`] gives it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReceiverCounts {
    /// Faces the walk crossed (received or not).
    pub crossed: u32,
    /// Faces it received (drawn).
    pub received: u32,
    /// Whether the walk stopped at the object's capacity, or the stream had no room for
    /// all its faces: then it is incomplete.
    pub overflowed: bool,
    /// Its first face in the stream.
    pub first: u32,
}

/// A frame's walks read back (tests, picking, a panel; one frame late is enough).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReceiverReadback {
    /// Per highlight, in [`HighlightSet::highlights`] order.
    pub counts: Vec<ReceiverCounts>,
    /// The vertex stream: (render vertex, highlight index), three per received face.
    pub stream: Vec<[u32; 2]>,
}

/// `ReceiverParams` of `receivers.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Params {
    normal_from_object: [[f32; 4]; 4],
    highlight_count: u32,
    face_count: u32,
    words: u32,
    capacity: u32,
    similar: u32,
    k: f32,
    list_faces: u32,
    _pad: u32,
}

/// Bytes of `ReceiverParams`: the queries follow them in `ReceiverFrame`'s buffer.
const PARAMS_BYTES: usize = std::mem::size_of::<Params>();

/// Bytes of a `ReceiverFrame` of `highlights` queries.
pub(crate) fn frame_bytes(highlights: usize) -> usize {
    PARAMS_BYTES + highlights.max(1) * std::mem::size_of::<Query>()
}

/// `ReceiverFrame` of `receivers.wgsl` with one query.
#[cfg(test)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameData {
    params: Params,
    queries: [Query; 1],
}

/// `Query` of `receivers.wgsl`: one highlight's walk.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Query {
    ndc_from_object: [[f32; 4]; 4],
    n_max: [f32; 4],
    walk_lo: [f32; 4],
    walk_hi: [f32; 4],
    rule: [u32; 4],
}

/// `Face` of `receivers.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct FaceRecord {
    tri: [u32; 4],
    render: [u32; 4],
    normal: [f32; 4],
}

const NO_WALK: u32 = u32::MAX;

pub(crate) fn face_records(set: &HighlightSet, render: &[[u32; 3]]) -> Vec<FaceRecord> {
    let topo = set.topology();
    let slack = set.face_slack();
    (0..topo.face_count())
        .map(|f| {
            let t = topo.triangles[f];
            let n = topo.face_normals[f];
            let [c, s] = slack.get(f).copied().unwrap_or([1.0, 0.0]);
            let r = render.get(f).copied().unwrap_or([0; 3]);
            FaceRecord {
                tri: [t[0], t[1], t[2], u32::from(topo.is_degenerate(f))],
                render: [r[0], r[1], r[2], s.to_bits()],
                normal: [n.x, n.y, n.z, c],
            }
        })
        .collect()
}

fn positions(set: &HighlightSet) -> Vec<[f32; 4]> {
    let p = &set.topology().positions;
    p.iter().map(|v| v.extend(1.0).to_array()).collect()
}

/// `face_count + 1` offsets, then the neighbours ([`npr_geometry::Topology::face_neighbours`]).
pub(crate) fn adjacency(set: &HighlightSet) -> Vec<u32> {
    let topo = set.topology();
    let faces = topo.face_count();
    let mut offsets = Vec::with_capacity(faces + 1);
    let mut list = Vec::new();
    offsets.push(0);
    for f in 0..faces {
        list.extend_from_slice(topo.face_neighbours(f));
        offsets.push(list.len() as u32);
    }
    offsets.extend(list);
    offsets
}

/// The frame's params and one query per highlight (in the set's order).
fn queries(
    set: &HighlightSet,
    highlights: &[crate::Highlight],
    world_from_object: Mat4,
) -> (Params, Vec<Query>) {
    let linear = Mat3::from_mat4(world_from_object);
    let normal_from_object = linear.inverse().transpose();
    let params = Params {
        normal_from_object: Mat4::from_mat3(normal_from_object).to_cols_array_2d(),
        highlight_count: highlights.len() as u32,
        face_count: set.topology().face_count() as u32,
        similar: u32::from(is_similarity(normal_from_object, 1e-6)),
        k: normal_from_object.x_axis.length(),
        ..Params::default()
    };
    let queries = highlights
        .iter()
        .map(|h| {
            let mut q = Query {
                rule: [NO_WALK, 0, 0, 0],
                ..Query::default()
            };
            let (rule, _) = set.receiver_rule(h);
            let space = object_space(world_from_object, &h.projector);
            let (Some(rule), Some((n_max, _, ndc_from_object))) = (rule, space) else {
                return q;
            };
            let affine = ndc_from_object.row(3) == glam::Vec4::W;
            let (lo, hi) = walk_box(&h.projector);
            let (sin, cos, mode, fixed) = match rule {
                ReceiverRule::Cos(c) => (0.0, 1.0, 0, c),
                ReceiverRule::Interpolated { limit_rad } => {
                    let (s, c) = limit_rad.clamp(0.0, std::f32::consts::FRAC_PI_2).sin_cos();
                    (s, c, 1, c)
                }
            };
            q.ndc_from_object = ndc_from_object.to_cols_array_2d();
            q.n_max = n_max.extend(f32::from(u8::from(affine))).to_array();
            q.walk_lo = lo.extend(sin).to_array();
            q.walk_hi = hi.extend(cos).to_array();
            q.rule = [h.centre.face, mode, fixed.to_bits(), 0];
            q
        })
        .collect();
    (params, queries)
}

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC);

impl ReceiverPass {
    /// The walk's pipelines (a compute pass draws into no target).
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::RECEIVERS.module(device);
        let entries: Vec<_> = (1..9)
            .map(|b| layout_entry(b, wgpu::BufferBindingType::Storage { read_only: b < 5 }))
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr receivers"),
            entries: &entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            walk: pipeline(device, &module, &layout, "cs_walk"),
            offsets: pipeline(device, &module, &layout, "cs_offsets"),
            scatter: pipeline(device, &module, &layout, "cs_scatter"),
            layout,
        }
    }

    /// Uploads `set`'s mesh (positions 16 bytes a vertex; faces with their render
    /// triangle from `indices` and slack, 48 bytes; adjacency), each walk crossing at most
    /// [`DEFAULT_WALK_CAPACITY`] faces.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] when a table exceeds the device's storage
    /// binding limit (use the CPU walk there).
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
    ) -> Result<ReceiverObject, SpecularError> {
        self.create_object_with_capacity(device, set, indices, DEFAULT_WALK_CAPACITY)
    }

    /// [`ReceiverPass::create_object`] with walks of at most `capacity` faces (at least
    /// 1).
    ///
    /// # Errors
    /// As [`ReceiverPass::create_object`].
    pub fn create_object_with_capacity(
        &self,
        device: &wgpu::Device,
        set: &HighlightSet,
        indices: &[u32],
        capacity: usize,
    ) -> Result<ReceiverObject, SpecularError> {
        let render: Vec<[u32; 3]> = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let records = face_records(set, &render);
        let points = positions(set);
        let adjacency = adjacency(set);
        let faces = records.len();
        let capacity = capacity.clamp(1, faces.max(1));
        check_bindings(
            &[
                ("receiver faces", (faces * 48) as u64),
                ("receiver positions", (points.len() * 16) as u64),
                ("receiver adjacency", (adjacency.len() * 4) as u64),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        Ok(ReceiverObject {
            normals_id: set.normals_id(),
            faces,
            vertices: points.len(),
            capacity,
            render,
            positions: buffer_init(device, "npr receiver positions", &points, STORAGE),
            face_records: buffer_init(device, "npr receiver faces", &records, STORAGE),
            adjacency: buffer_init(device, "npr receiver adjacency", &adjacency, STORAGE),
            visited: buffer_init(device, "npr receiver visited", &vec![0u32; faces], STORAGE),
            words: 1,
            work: buffer_init(device, "npr receiver work", &[0u32; 2], STORAGE),
            work_highlights: 0,
            slots: Slots::new(self.id),
        })
    }

    /// Takes a slot for `input.frame` and writes its params and one query per highlight
    /// (growing the scratch for more highlights). A set of a new pose (its
    /// [`HighlightSet::normals_id`] changed) has its positions and faces written again.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a foreign object or too many prepares in one frame;
    /// [`SpecularError::Mismatch`] for a set of another mesh;
    /// [`SpecularError::Gpu`] when the scratch would exceed a binding.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut ReceiverObject,
        input: &ReceiverInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        self.prepare_with(queue, object, input, None)
    }

    /// [`ReceiverPass::prepare`] for the projectors the GPU builds this frame
    /// ([`crate::gpu::ProjectorPass`], recorded before the walk in the same submission): their
    /// queries are written there, so the CPU writes only the frame's values; `room` walks
    /// at most (more projectors are not drawn), dispatched over all of it.
    ///
    /// # Errors
    /// As [`ReceiverPass::prepare`].
    pub fn prepare_on_projectors(
        &self,
        queue: &wgpu::Queue,
        object: &mut ReceiverObject,
        input: &ReceiverInput<'_>,
        (projectors, room): (&crate::gpu::ProjectorObject, usize),
    ) -> Result<Prepared, SpecularError> {
        self.prepare_with(queue, object, input, Some((projectors, room)))
    }

    fn prepare_with(
        &self,
        queue: &wgpu::Queue,
        object: &mut ReceiverObject,
        input: &ReceiverInput<'_>,
        gpu: Option<(&crate::gpu::ProjectorObject, usize)>,
    ) -> Result<Prepared, SpecularError> {
        object.slots.check_pass(self.id)?;
        let set = input.set;
        let topo = set.topology();
        if topo.face_count() != object.faces || topo.vertex_count() != object.vertices {
            return Err(SpecularError::Mismatch(format!(
                "a receiver object of {} vertices and {} faces prepared with a set of {} and {}",
                object.vertices,
                object.faces,
                topo.vertex_count(),
                topo.face_count()
            )));
        }
        if set.normals_id() != object.normals_id && object.faces > 0 {
            let records = face_records(set, &object.render);
            queue.write_buffer(&object.face_records, 0, bytemuck::cast_slice(&records));
            let points = positions(set);
            queue.write_buffer(&object.positions, 0, bytemuck::cast_slice(&points));
        }
        object.normals_id = set.normals_id();
        // The projectors the GPU builds write their own queries.
        let drawn = if gpu.is_some() {
            &[][..]
        } else {
            set.highlights()
        };
        let (mut params, queries) = queries(set, drawn, input.world_from_object);
        let highlights = match gpu {
            Some((_, room)) => room.clamp(1, crate::gpu::MAX_DRAWN),
            None => queries.len(),
        };
        let device = &self.device;
        let limit = device.limits().max_storage_buffer_binding_size;
        let words = highlights.div_ceil(32).max(1);
        let (faces, capacity) = (object.faces, object.capacity);
        // Grow the shared scratch (never shrink it).
        if words > object.words {
            let bytes = (faces.max(1) * words * 4) as u64;
            check_bindings(&[("receiver visited", bytes)], limit)?;
            object.visited = storage(device, "npr receiver visited", bytes);
            object.words = words;
        }
        if highlights > object.work_highlights {
            let room = highlights.next_power_of_two();
            let bytes = (room * 2 * capacity * 4) as u64;
            check_bindings(&[("receiver work", bytes)], limit)?;
            object.work = storage(device, "npr receiver work", bytes);
            object.work_highlights = room;
        }
        let list_faces = (highlights * capacity).min((limit / 24) as usize).max(1);
        let (prepared, slot) = object
            .slots
            .next(self.id, input.frame, || make_slot(device))?;
        if highlights > slot.room || list_faces > slot.list_faces {
            let room = highlights.next_power_of_two().max(slot.room);
            slot.queries = storage(
                device,
                "npr receiver queries",
                (PARAMS_BYTES + room.max(1) * 128) as u64,
            );
            slot.meta = meta_buffer(device, room);
            slot.room = room;
            let list = list_faces.max(slot.list_faces);
            slot.list = storage(device, "npr receiver stream", (list * 24) as u64);
            slot.list_faces = list;
        }
        params.words = object.words as u32;
        params.capacity = capacity as u32;
        params.list_faces = slot.list_faces as u32;
        if gpu.is_some() {
            // The walks dispatched: the projectors take at most this many.
            params.highlight_count = highlights as u32;
        }
        let (frame_buffer, at) = match gpu {
            None => {
                npr_gpu::compute::write_head_and_records(queue, &slot.queries, &params, &queries);
                (&slot.queries, 0)
            }
            Some((projectors, _)) => {
                let (buffer, at) = projectors.receiver_frame();
                queue.write_buffer(buffer, at, bytemuck::bytes_of(&params));
                (buffer, at)
            }
        };
        let bound = [
            frame_buffer,
            &object.positions,
            &object.face_records,
            &object.adjacency,
            &object.visited,
            &object.work,
            &slot.meta,
            &slot.list,
        ];
        let layout = &self.layout;
        let group = slot.groups.get_or_make(&bound, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr receivers"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: frame_buffer,
                            offset: at,
                            size: None,
                        }),
                    },
                    group_entry(2, &object.positions),
                    group_entry(3, &object.face_records),
                    group_entry(4, &object.adjacency),
                    group_entry(5, &object.visited),
                    group_entry(6, &object.work),
                    group_entry(7, &slot.meta),
                    group_entry(8, &slot.list),
                ],
            })
        });
        slot.group = Some(group);
        slot.count = highlights;
        Ok(prepared)
    }

    /// Records the walks: visited marks cleared, one workgroup per highlight, then the
    /// stream's offsets and the scatter. The indirect draw's count is written last.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another pass, object or frame; nothing
    /// is recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &ReceiverObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        let slot = object.slots.get(self.id, prepared)?;
        let Some(group) = &slot.group else {
            return Ok(());
        };
        let highlights = slot.count;
        encoder.clear_buffer(&object.visited, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr receivers"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        if highlights > 0 {
            pass.set_pipeline(&self.walk);
            pass.dispatch_workgroups(highlights as u32, 1, 1);
        }
        pass.set_pipeline(&self.offsets);
        pass.dispatch_workgroups(1, 1, 1);
        if highlights > 0 {
            pass.set_pipeline(&self.scatter);
            pass.dispatch_workgroups(highlights as u32, 1, 1);
        }
        Ok(())
    }
}

/// A storage buffer of `bytes` (at least 16), written by the queue and copied out.
pub(crate) fn storage(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// The indirect draw's arguments and `highlights` counts: storage, indirect and copied
/// out by [`ReceiverObject::read`].
fn meta_buffer(device: &wgpu::Device, highlights: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr receiver counts"),
        size: (16 + 16 * highlights.max(1)) as u64,
        usage: STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::INDIRECT,
        mapped_at_creation: false,
    })
}

fn make_slot(device: &wgpu::Device) -> Slot {
    Slot {
        queries: storage(device, "npr receiver queries", (PARAMS_BYTES + 128) as u64),
        meta: meta_buffer(device, 1),
        list: storage(device, "npr receiver stream", 24),
        list_faces: 1,
        group: None,
        groups: Default::default(),
        room: 0,
        count: 0,
    }
}

impl ReceiverObject {
    /// The buffers a pose's tables go to ([`crate::gpu::ReposePass`]): the positions and the
    /// faces.
    pub(crate) fn pose_tables(&self) -> [&wgpu::Buffer; 2] {
        [&self.positions, &self.face_records]
    }

    /// Faces one highlight's walk may cross.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// The stream and the indirect draw's arguments (offset 0) of `prepared`, for the
    /// highlight pass.
    pub(crate) fn stream(
        &self,
        prepared: &Prepared,
    ) -> Result<(&wgpu::Buffer, &wgpu::Buffer), SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        Ok((&slot.list, &slot.meta))
    }

    /// Reads back the counts and the stream of `prepared`, after the submission that
    /// holds its [`ReceiverPass::record`]: copies them, waits for the GPU and decodes.
    /// Native only (in the browser use [`ReceiverObject::map`] and poll); for tests,
    /// picking or a panel, never on the frame's path.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`; [`SpecularError::Gpu`]
    /// when the map fails or the device is lost.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<ReceiverReadback, SpecularError> {
        Ok(self.map(device, queue, prepared)?.wait(device)?)
    }

    /// Copies the counts and the whole stream of `prepared` (after the submission that
    /// holds its [`ReceiverPass::record`]) and asks for their maps without waiting:
    /// [`PendingReceivers::try_take`] gives them once the maps have completed.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`.
    pub fn map(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<PendingReceivers, SpecularError> {
        self.map_impl(device, queue, prepared, true)
    }

    /// [`ReceiverObject::map`] of the counts alone (one 16-byte record per highlight,
    /// nothing mesh-sized): the panel's receiver count and whether a walk overflowed,
    /// one frame late. The readback's stream is empty.
    ///
    /// # Errors
    /// As [`ReceiverObject::map`].
    pub fn map_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<PendingReceivers, SpecularError> {
        self.map_impl(device, queue, prepared, false)
    }

    fn map_impl(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
        with_stream: bool,
    ) -> Result<PendingReceivers, SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut copy = |from: &wgpu::Buffer, bytes: u64| {
            let to = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("npr receiver readback"),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_buffer_to_buffer(from, 0, &to, 0, bytes);
            to
        };
        let meta = copy(&slot.meta, (16 + 16 * slot.count.max(1)) as u64);
        let list = with_stream.then(|| copy(&slot.list, (slot.list_faces * 24) as u64));
        queue.submit([encoder.finish()]);
        Ok(PendingReceivers {
            meta: npr_gpu::BufferReadback::map(meta),
            taken: std::sync::Mutex::new((None, list.is_none().then(Vec::new))),
            list: list.map(npr_gpu::BufferReadback::map),
            highlights: slot.count,
        })
    }
}

/// The counts' and the stream's bytes, each once its map has completed.
type TakenBytes = (Option<Vec<u8>>, Option<Vec<u8>>);

/// A frame's walks on their way to the CPU ([`ReceiverObject::map`]).
#[derive(Debug)]
pub struct PendingReceivers {
    meta: npr_gpu::BufferReadback,
    /// `None` for [`ReceiverObject::map_counts`].
    list: Option<npr_gpu::BufferReadback>,
    /// The bytes of each map once taken.
    taken: std::sync::Mutex<TakenBytes>,
    highlights: usize,
}

impl PendingReceivers {
    /// The counts and stream once both maps have completed; `None` while they have not.
    pub fn try_take(&self) -> Option<Result<ReceiverReadback, npr_gpu::GpuError>> {
        let mut guard = self.taken.lock().ok()?;
        let taken = &mut *guard;
        for (slot, map) in [
            (&mut taken.0, Some(&self.meta)),
            (&mut taken.1, self.list.as_ref()),
        ] {
            if slot.is_none()
                && let Some(map) = map
            {
                match map.try_take()? {
                    Ok(bytes) => *slot = Some(bytes),
                    Err(e) => return Some(Err(e)),
                }
            }
        }
        match taken {
            (Some(meta), Some(list)) => Some(Ok(decode(meta, list, self.highlights))),
            _ => None,
        }
    }

    /// Blocks until both maps have completed (native: polls `device`) and decodes them.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::Readback`] when polling or mapping fails.
    pub fn wait(self, device: &wgpu::Device) -> Result<ReceiverReadback, npr_gpu::GpuError> {
        let meta = self.meta.wait(device)?;
        let list = match self.list {
            Some(list) => list.wait(device)?,
            None => Vec::new(),
        };
        Ok(decode(&meta, &list, self.highlights))
    }
}

/// The counts (after the indirect draw's four words) and the stream's entries.
fn decode(meta: &[u8], list: &[u8], highlights: usize) -> ReceiverReadback {
    let word = |bytes: &[u8], i: usize| {
        bytes
            .get(4 * i..4 * i + 4)
            .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let counts = (0..highlights)
        .map(|h| {
            let at = 4 + 4 * h;
            ReceiverCounts {
                crossed: word(meta, at),
                received: word(meta, at + 1),
                overflowed: word(meta, at + 2) != 0,
                first: word(meta, at + 3),
            }
        })
        .collect();
    let entries = (word(meta, 0) as usize).min(list.len() / 8);
    let stream = (0..entries)
        .map(|e| [word(list, 2 * e), word(list, 2 * e + 1)])
        .collect();
    ReceiverReadback { counts, stream }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_match_wgsl() {
        // `ReceiverParams` is bound inside `ReceiverFrame` (checked below, with the
        // queries' offset): its fields' offsets by WGSL's rules.
        assert_eq!(
            [
                std::mem::offset_of!(Params, highlight_count),
                std::mem::offset_of!(Params, words),
                std::mem::offset_of!(Params, similar),
                std::mem::offset_of!(Params, k),
                std::mem::offset_of!(Params, list_faces),
                std::mem::size_of::<Params>(),
            ],
            [64, 72, 80, 84, 88, 96]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FrameData,
            "ReceiverFrame",
            [params, queries]
        );
        // `Query` is bound inside `ReceiverFrame` (its array's offset and stride there).
        assert_eq!(
            [
                std::mem::offset_of!(Query, n_max),
                std::mem::offset_of!(Query, walk_hi),
                std::mem::offset_of!(Query, rule),
                std::mem::size_of::<Query>(),
            ],
            [64, 96, 112, 128]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FaceRecord,
            "Face",
            [tri, render, normal]
        );
    }
}
