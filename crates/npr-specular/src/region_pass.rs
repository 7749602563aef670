//! The regions `N·H ≥ σ` of [`crate::region`] grown and fitted as a compute pass
//! (`shaders/regions.wgsl`): each seed's breadth-first growth from its face, one
//! workgroup per seed, the faces shared out between seeds as the CPU shares them (fewest
//! steps, then the lower seed), and each seed's area moments summed and fitted with the
//! ellipse of the same moments ([`Footprint`]). Nothing mesh-sized is read back: one
//! 288-byte record per seed.
//!
//! It speaks the pass contract ([`npr_gpu::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let pass = RegionPass::new(device);
//! let mut object = pass.create_object(device, &set)?;
//! // per frame, with the frame's centres and their σ
//! let input = RegionInput { frame, set: &set, seeds: &seeds, light_eye, world_from_object };
//! let prepared = pass.prepare(queue, &mut object, &input)?;
//! pass.record(&mut encoder, &object, &prepared)?;
//! queue.submit([encoder.finish()]);
//! let fitted = object.read(device, queue, &prepared)?; // tests, a panel: one frame late
//! ```
//!
//! The CPU growth ([`RegionGrower::grow_all`](crate::region::RegionGrower::grow_all)) is
//! the reference: `tests/gpu_regions.rs` compares the two on the same frame. The moment
//! ellipse, the scale of it that fits the region best ([`GpuRegion::overlap_scale`]) and
//! a long bent region's pieces ([`GpuRegion::pieces`]) are fitted here. A growth longer than the object's capacity stops there and
//! says so ([`GpuRegion::overflowed`]).

use crate::receiver_pass::{adjacency, storage};
use crate::region::{Footprint, MAX_PIECES, Region};
use crate::{HighlightSet, SpecularError};
use glam::{Mat3, Mat4, Vec2};
use npr_geometry::{HighlightCentre, LightEye};
use npr_gpu::compute::{buffer_init, check_bindings, group_entry, layout_entry, pipeline};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};

/// Faces one seed's growth may take by default (its queue's length, 8 bytes a face); a
/// frame of more seeds than the storage binding limit holds at this length gets shorter
/// queues ([`RegionObject::capacity`]).
pub const DEFAULT_REGION_CAPACITY: usize = 65_536;

/// Most seeds one frame grows (the faces' marks hold the seed in 12 bits).
pub const MAX_REGION_SEEDS: usize = 4096;

/// The growth's compute pipelines: one pair per device, shared by every object.
#[derive(Debug)]
pub struct RegionPass {
    id: PassId,
    device: wgpu::Device,
    layout: wgpu::BindGroupLayout,
    grow: wgpu::ComputePipeline,
    fit: wgpu::ComputePipeline,
}

/// One frame's growth: the set whose mesh and normals the object holds, the seeds
/// (centre, σ) in the order the CPU would grow them, and the frame's light, eye and
/// transform.
#[derive(Clone, Copy, Debug)]
pub struct RegionInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The highlight set (its mesh and the normals its regions are measured on).
    pub set: &'a HighlightSet,
    /// Centres (world frame, as the search returns them) and their σ.
    pub seeds: &'a [(HighlightCentre, f32)],
    /// Light and eye, world space.
    pub light_eye: LightEye,
    /// The object's transform.
    pub world_from_object: Mat4,
}

/// One mesh's tables on the GPU (vertices with their normals, faces, adjacency) and the
/// growths' scratch.
#[derive(Debug)]
pub struct RegionObject {
    normals_id: u64,
    faces: usize,
    vertices: usize,
    /// The queue length asked for at creation.
    max_capacity: usize,
    vertex_records: wgpu::Buffer,
    face_records: wgpu::Buffer,
    adjacency: wgpu::Buffer,
    /// Per face one bit per seed; `words` per face.
    visited: wgpu::Buffer,
    words: usize,
    /// Per face the least mark of the seeds that took it.
    owner: wgpu::Buffer,
    /// Per seed its queue of `work_capacity` entries; room for `work_seeds`.
    work: wgpu::Buffer,
    work_seeds: usize,
    work_capacity: usize,
    slots: Slots<Slot>,
}

/// One prepare's params and seeds (one buffer: `RegionFrameData`) and results.
#[derive(Debug)]
struct Slot {
    seeds: wgpu::Buffer,
    fits: wgpu::Buffer,
    group: Option<wgpu::BindGroup>,
    /// Seeds the buffers have room for.
    room: usize,
    /// Seeds this frame grows.
    count: usize,
}

/// One seed's region as the GPU grew and fitted it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuRegion {
    /// What the growth found, as [`RegionGrower::grow_all`](crate::region::RegionGrower::grow_all)
    /// gives it: covered, empty, or the moment ellipse (with the region's normal cone;
    /// `fit_scale` 1) and the faces the seed won.
    pub region: Region,
    /// Faces its walk took, won or not.
    pub walked: u32,
    /// Whether the walk stopped at the object's capacity (then the region is cut short).
    pub overflowed: bool,
    /// The scale (≤ 1) of the moment ellipse that fits the region best
    /// ([`RegionGrower::overlap_scale`](crate::region::RegionGrower::overlap_scale),
    /// from the faces won one by one); 1 when the region is not fitted.
    pub overlap_scale: f32,
    /// How many of [`GpuRegion::pieces`] hold a piece: 0, or 2 to [`MAX_PIECES`] for a
    /// long bent region cut along its length
    /// ([`RegionGrower::pieces`](crate::region::RegionGrower::pieces)).
    pub piece_count: usize,
    /// The pieces' footprints (the whole's normal cone), the first `piece_count`.
    pub pieces: [Footprint; MAX_PIECES],
    /// Each piece's overlap scale, against all the faces the seed won.
    pub piece_scales: [f32; MAX_PIECES],
}

impl GpuRegion {
    /// The pieces of a long bent region (empty for one its ellipse fits).
    pub fn pieces(&self) -> &[Footprint] {
        &self.pieces[..self.piece_count.min(MAX_PIECES)]
    }
}

/// `RegionParams` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    world_from_object: [[f32; 4]; 4],
    normal_from_object: [[f32; 4]; 4],
    light: [f32; 4],
    eye: [f32; 4],
    seed_count: u32,
    face_count: u32,
    words: u32,
    capacity: u32,
}

/// Bytes of `RegionParams`: the seeds follow them in `RegionFrameData`'s buffer.
const PARAMS_BYTES: usize = std::mem::size_of::<Params>();

/// `RegionFrameData` of `regions.wgsl` with one seed: the frame's values and the seeds
/// in one storage buffer (see the shader for why not a uniform buffer).
#[cfg(test)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameData {
    params: Params,
    seeds: [SeedRecord; 1],
}

/// `Seed` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct SeedRecord {
    origin: [f32; 4],
    n: [f32; 4],
    e_u: [f32; 4],
    e_v: [f32; 4],
    start: [u32; 4],
}

/// `RegionVertex` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct VertexRecord {
    position: [f32; 4],
    normal: [f32; 4],
}

/// `RegionFace` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct FaceRecord {
    tri: [u32; 4],
    normal: [f32; 4],
}

/// `RegionPiece` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct PieceRecord {
    ellipse: [f32; 4],
    fit: [f32; 4],
}

/// `RegionFit` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct FitRecord {
    moments: [f32; 4],
    second: [f32; 4],
    ellipse: [f32; 4],
    fit: [f32; 4],
    flags: [u32; 4],
    piece_count: [u32; 4],
    pieces: [PieceRecord; MAX_PIECES],
}

/// Bytes of one seed's `RegionFit`.
const FIT_BYTES: usize = std::mem::size_of::<FitRecord>();

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_DST);

fn vertex_records(set: &HighlightSet) -> Vec<VertexRecord> {
    let normals = set.search().normals();
    set.topology()
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| VertexRecord {
            position: p.extend(1.0).to_array(),
            normal: normals
                .get(v)
                .copied()
                .unwrap_or_default()
                .extend(0.0)
                .to_array(),
        })
        .collect()
}

fn face_records(set: &HighlightSet) -> Vec<FaceRecord> {
    let topo = set.topology();
    (0..topo.face_count())
        .map(|f| {
            let t = topo.triangles[f];
            FaceRecord {
                tri: [t[0], t[1], t[2], u32::from(topo.is_degenerate(f))],
                normal: topo.face_normals[f].extend(0.0).to_array(),
            }
        })
        .collect()
}

/// The seeds' records: a seed whose start face an earlier seed (with a frame) starts on
/// is covered, as the CPU's growth finds it.
fn seed_records(seeds: &[(HighlightCentre, f32)], faces: usize) -> Vec<SeedRecord> {
    let mut started = std::collections::HashSet::new();
    seeds
        .iter()
        .map(|(centre, sigma)| {
            let n = centre.normal_world;
            let frame = n.try_normalize().and_then(|n| {
                let e_u =
                    (centre.dir_kappa_max - n * n.dot(centre.dir_kappa_max)).try_normalize()?;
                Some((n, e_u, n.cross(e_u)))
            });
            let Some((n, e_u, e_v)) = frame else {
                return SeedRecord {
                    start: [u32::MAX, 0, 0, 0],
                    ..SeedRecord::default()
                };
            };
            let face = centre.face;
            let covered = (face as usize) < faces && !started.insert(face);
            SeedRecord {
                origin: centre.position_world.extend(*sigma).to_array(),
                n: n.extend(1.0).to_array(),
                e_u: e_u.extend(0.0).to_array(),
                e_v: e_v.extend(0.0).to_array(),
                start: [face, u32::from(covered), 0, 0],
            }
        })
        .collect()
}

fn params_of(input: &RegionInput<'_>, faces: usize) -> Params {
    let linear = Mat3::from_mat4(input.world_from_object);
    let normal_from_object = if linear.determinant().abs() > f32::MIN_POSITIVE {
        linear.inverse().transpose()
    } else {
        Mat3::ZERO
    };
    let (light, eye) = match input.light_eye {
        LightEye::Positions { light, eye } => (light.extend(1.0), eye.extend(1.0)),
        LightEye::Directions { to_light, to_eye } => (to_light.extend(0.0), to_eye.extend(0.0)),
    };
    Params {
        world_from_object: input.world_from_object.to_cols_array_2d(),
        normal_from_object: Mat4::from_mat3(normal_from_object).to_cols_array_2d(),
        light: light.to_array(),
        eye: eye.to_array(),
        seed_count: input.seeds.len() as u32,
        face_count: faces as u32,
        ..Params::default()
    }
}

impl RegionPass {
    /// The growth's pipelines (a compute pass draws into no target).
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::REGIONS.module(device);
        let entries: Vec<_> = [0, 2, 3, 4, 5, 6, 7, 8]
            .into_iter()
            .map(|b| layout_entry(b, wgpu::BufferBindingType::Storage { read_only: b < 5 }))
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr regions"),
            entries: &entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            grow: pipeline(device, &module, &layout, "cs_grow"),
            fit: pipeline(device, &module, &layout, "cs_fit"),
            layout,
        }
    }

    /// Uploads `set`'s mesh (vertices with their normals, 32 bytes each; faces, 32 bytes;
    /// adjacency), each growth taking at most [`DEFAULT_REGION_CAPACITY`] faces.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] when a table exceeds the device's storage
    /// binding limit (grow on the CPU there).
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        set: &HighlightSet,
    ) -> Result<RegionObject, SpecularError> {
        self.create_object_with_capacity(device, set, DEFAULT_REGION_CAPACITY)
    }

    /// [`RegionPass::create_object`] with growths of at most `capacity` faces (at least
    /// 1).
    ///
    /// # Errors
    /// As [`RegionPass::create_object`].
    pub fn create_object_with_capacity(
        &self,
        device: &wgpu::Device,
        set: &HighlightSet,
        capacity: usize,
    ) -> Result<RegionObject, SpecularError> {
        let vertices = vertex_records(set);
        let faces = face_records(set);
        let adjacency = adjacency(set);
        // The faces' marks hold a walk's steps in 20 bits.
        let capacity = capacity.clamp(1, faces.len().clamp(1, 1 << 20));
        check_bindings(
            &[
                ("region vertices", (vertices.len() * 32) as u64),
                ("region faces", (faces.len() * 32) as u64),
                ("region adjacency", (adjacency.len() * 4) as u64),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        Ok(RegionObject {
            normals_id: set.normals_id(),
            faces: faces.len(),
            vertices: vertices.len(),
            max_capacity: capacity,
            vertex_records: buffer_init(device, "npr region vertices", &vertices, STORAGE),
            face_records: buffer_init(device, "npr region faces", &faces, STORAGE),
            adjacency: buffer_init(device, "npr region adjacency", &adjacency, STORAGE),
            visited: buffer_init(
                device,
                "npr region visited",
                &vec![0u32; faces.len()],
                STORAGE,
            ),
            words: 1,
            owner: buffer_init(
                device,
                "npr region owner",
                &vec![0u32; faces.len()],
                STORAGE,
            ),
            work: buffer_init(device, "npr region work", &[0u32; 2], STORAGE),
            work_seeds: 0,
            work_capacity: capacity,
            slots: Slots::new(self.id),
        })
    }

    /// Takes a slot for `input.frame` and writes its params and seeds (growing the
    /// scratch for more seeds). A set of a new pose (its [`HighlightSet::normals_id`]
    /// changed) has its vertices and faces written again.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a foreign object or too many prepares in one frame;
    /// [`SpecularError::Mismatch`] for a set of another mesh or more than
    /// [`MAX_REGION_SEEDS`] seeds; [`SpecularError::Gpu`] when the scratch would exceed
    /// a binding.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &RegionInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        object.slots.check_pass(self.id)?;
        let set = input.set;
        let topo = set.topology();
        if topo.face_count() != object.faces || topo.vertex_count() != object.vertices {
            return Err(SpecularError::Mismatch(format!(
                "a region object of {} vertices and {} faces prepared with a set of {} and {}",
                object.vertices,
                object.faces,
                topo.vertex_count(),
                topo.face_count()
            )));
        }
        let count = input.seeds.len();
        if count > MAX_REGION_SEEDS {
            return Err(SpecularError::Mismatch(format!(
                "{count} seeds in one frame (at most {MAX_REGION_SEEDS})"
            )));
        }
        if set.normals_id() != object.normals_id && object.faces > 0 {
            let vertices = vertex_records(set);
            queue.write_buffer(&object.vertex_records, 0, bytemuck::cast_slice(&vertices));
            let faces = face_records(set);
            queue.write_buffer(&object.face_records, 0, bytemuck::cast_slice(&faces));
        }
        object.normals_id = set.normals_id();
        let device = &self.device;
        let limit = device.limits().max_storage_buffer_binding_size;
        let words = count.div_ceil(32).max(1);
        let (faces, capacity) = (object.faces, object.max_capacity);
        if words > object.words {
            let bytes = (faces.max(1) * words * 4) as u64;
            check_bindings(&[("region visited", bytes)], limit)?;
            object.visited = storage(device, "npr region visited", bytes);
            object.words = words;
        }
        if count > object.work_seeds {
            // As long a queue per seed as the binding holds, at most the capacity.
            let room = count.next_power_of_two();
            let per_seed = capacity.min((limit / (8 * room as u64)) as usize).max(1);
            let bytes = (room * per_seed * 8) as u64;
            check_bindings(&[("region work", bytes)], limit)?;
            object.work = storage(device, "npr region work", bytes);
            object.work_seeds = room;
            object.work_capacity = per_seed;
        }
        let (prepared, slot) = object
            .slots
            .next(self.id, input.frame, || make_slot(device))?;
        if count > slot.room {
            let room = count.next_power_of_two();
            slot.seeds = storage(
                device,
                "npr region seeds",
                (PARAMS_BYTES + room * 80) as u64,
            );
            slot.fits = storage(device, "npr region fits", (room * FIT_BYTES) as u64);
            slot.room = room;
        }
        let mut params = params_of(input, faces);
        params.words = object.words as u32;
        params.capacity = object.work_capacity as u32;
        queue.write_buffer(&slot.seeds, 0, bytemuck::bytes_of(&params));
        let seeds = seed_records(input.seeds, faces);
        if !seeds.is_empty() {
            queue.write_buffer(
                &slot.seeds,
                PARAMS_BYTES as u64,
                bytemuck::cast_slice(&seeds),
            );
        }
        slot.group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr regions"),
            layout: &self.layout,
            entries: &[
                group_entry(0, &slot.seeds),
                group_entry(2, &object.vertex_records),
                group_entry(3, &object.face_records),
                group_entry(4, &object.adjacency),
                group_entry(5, &object.visited),
                group_entry(6, &object.owner),
                group_entry(7, &object.work),
                group_entry(8, &slot.fits),
            ],
        }));
        slot.count = count;
        Ok(prepared)
    }

    /// One frame's growth at once (native; the browser maps and polls instead): prepare,
    /// record in an encoder of its own, submit, and read the seeds' regions back, waiting
    /// for the GPU. For callers whose frame waits on the regions anyway (the app's GPU
    /// setup, benches, measures).
    ///
    /// # Errors
    /// As [`RegionPass::prepare`] and [`RegionObject::read`].
    pub fn grow_now(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &RegionInput<'_>,
    ) -> Result<Vec<GpuRegion>, SpecularError> {
        let prepared = self.prepare(queue, object, input)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr regions"),
        });
        self.record(&mut encoder, object, &prepared)?;
        queue.submit([encoder.finish()]);
        object.read(device, queue, &prepared)
    }

    /// A [`crate::RegionsOnGpu`] callback for
    /// [`HighlightSet::update_from_solutions_and_regions`]: each update's regions grown
    /// at once with this pass ([`RegionPass::grow_now`]) for `frame` and this light, eye
    /// and transform; `None` (the CPU grows that frame's) where a step fails or a growth
    /// overflowed.
    pub fn grower<'a>(
        &'a self,
        (device, queue): (&'a wgpu::Device, &'a wgpu::Queue),
        object: &'a mut RegionObject,
        frame: FrameId,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> impl FnMut(&HighlightSet, &[(HighlightCentre, f32)]) -> Option<Vec<GpuRegion>> + 'a {
        move |set, seeds| {
            let input = RegionInput {
                frame,
                set,
                seeds,
                light_eye,
                world_from_object,
            };
            let grown = self.grow_now(device, queue, object, &input).ok()?;
            grown.iter().all(|g| !g.overflowed).then_some(grown)
        }
    }

    /// Records the growth: the faces' marks cleared, one workgroup per seed walking its
    /// region, then one per seed summing and fitting the faces it won.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another pass, object or frame; nothing
    /// is recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &RegionObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        let slot = object.slots.get(self.id, prepared)?;
        let Some(group) = &slot.group else {
            return Ok(());
        };
        if slot.count == 0 {
            return Ok(());
        }
        encoder.clear_buffer(&object.visited, 0, None);
        encoder.clear_buffer(&object.owner, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr regions"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        pass.set_pipeline(&self.grow);
        pass.dispatch_workgroups(slot.count as u32, 1, 1);
        pass.set_pipeline(&self.fit);
        pass.dispatch_workgroups(slot.count as u32, 1, 1);
        Ok(())
    }
}

fn make_slot(device: &wgpu::Device) -> Slot {
    Slot {
        seeds: storage(device, "npr region seeds", (PARAMS_BYTES + 80) as u64),
        fits: storage(device, "npr region fits", FIT_BYTES as u64),
        group: None,
        room: 0,
        count: 0,
    }
}

impl RegionObject {
    /// Faces one seed's growth may take: the object's capacity, or less once a frame
    /// has had so many seeds that their queues at that length would exceed the storage
    /// binding limit.
    pub fn capacity(&self) -> usize {
        self.work_capacity
    }

    /// Reads back the seeds' regions of `prepared`, after the submission that holds its
    /// [`RegionPass::record`]: copies them (288 bytes a seed), waits for the GPU and
    /// decodes. Native only (in the browser use [`RegionObject::map`] and poll); for
    /// tests, picking or a panel, never on the frame's path.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`; [`SpecularError::Gpu`]
    /// when the map fails or the device is lost.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<Vec<GpuRegion>, SpecularError> {
        let pending = self.map(device, queue, prepared)?;
        let bytes = pending.map.wait(device)?;
        Ok(decode(&bytes, pending.seeds))
    }

    /// Copies the seeds' regions of `prepared` and asks for the map without waiting:
    /// [`PendingRegions::try_take`] gives them once it has completed.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`.
    pub fn map(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<PendingRegions, SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        let bytes = (FIT_BYTES * slot.count.max(1)) as u64;
        let to = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr region readback"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&slot.fits, 0, &to, 0, bytes);
        queue.submit([encoder.finish()]);
        Ok(PendingRegions {
            map: npr_gpu::BufferReadback::map(to),
            seeds: slot.count,
        })
    }
}

/// A frame's regions on their way to the CPU ([`RegionObject::map`]).
#[derive(Debug)]
pub struct PendingRegions {
    map: npr_gpu::BufferReadback,
    seeds: usize,
}

impl PendingRegions {
    /// The regions once the map has completed; `None` while it has not.
    pub fn try_take(&self) -> Option<Result<Vec<GpuRegion>, npr_gpu::GpuError>> {
        Some(self.map.try_take()?.map(|bytes| decode(&bytes, self.seeds)))
    }
}

/// The seeds' `RegionFit` records.
fn decode(bytes: &[u8], seeds: usize) -> Vec<GpuRegion> {
    let records: Vec<FitRecord> = bytes
        .chunks_exact(FIT_BYTES)
        .take(seeds)
        .map(bytemuck::pod_read_unaligned)
        .collect();
    records
        .iter()
        .map(|r| {
            let region = match r.flags[0] {
                0 => Region::Fit(
                    Footprint {
                        half_extent: Vec2::new(r.ellipse[0], r.ellipse[1]),
                        offset: Vec2::new(r.ellipse[2], r.ellipse[3]),
                        rotate_rad: r.fit[0],
                        region_area: r.fit[1],
                        normal_cone_cos: r.fit[2],
                        fit_scale: 1.0,
                    },
                    r.flags[1] as usize,
                ),
                1 => Region::Covered,
                _ => Region::Empty,
            };
            let scale = |s: f32| if s > 0.0 && s <= 1.0 { s } else { 1.0 };
            let (overlap_scale, cone, piece_count) = match region {
                Region::Fit(fp, _) => (
                    scale(r.fit[3]),
                    fp.normal_cone_cos,
                    (r.piece_count[0] as usize).min(MAX_PIECES),
                ),
                _ => (1.0, -1.0, 0),
            };
            let mut pieces = [Footprint::default(); MAX_PIECES];
            let mut piece_scales = [1.0; MAX_PIECES];
            for (i, p) in r.pieces.iter().take(piece_count).enumerate() {
                pieces[i] = Footprint {
                    half_extent: Vec2::new(p.ellipse[0], p.ellipse[1]),
                    offset: Vec2::new(p.ellipse[2], p.ellipse[3]),
                    rotate_rad: p.fit[0],
                    region_area: p.fit[1],
                    normal_cone_cos: cone,
                    fit_scale: 1.0,
                };
                piece_scales[i] = scale(p.fit[2]);
            }
            GpuRegion {
                region,
                walked: r.flags[2],
                overflowed: r.flags[3] != 0,
                overlap_scale,
                piece_count,
                pieces,
                piece_scales,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_match_wgsl() {
        // `RegionParams` and `Seed` are bound inside `RegionFrameData`: their sizes and
        // the seeds' offset are checked there, their fields here.
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FrameData,
            "RegionFrameData",
            [params, seeds]
        );
        assert_eq!(
            [
                std::mem::offset_of!(Params, normal_from_object),
                std::mem::offset_of!(Params, light),
                std::mem::offset_of!(Params, eye),
                std::mem::offset_of!(Params, seed_count),
                std::mem::offset_of!(Params, capacity),
            ],
            [64, 128, 144, 160, 172]
        );
        assert_eq!(
            [
                std::mem::offset_of!(SeedRecord, n),
                std::mem::offset_of!(SeedRecord, start),
                std::mem::size_of::<SeedRecord>(),
            ],
            [16, 64, 80]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            VertexRecord,
            "RegionVertex",
            [position, normal]
        );
        npr_gpu::assert_wgsl_layout!(crate::shaders::ALL, FaceRecord, "RegionFace", [tri, normal]);
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FitRecord,
            "RegionFit",
            [moments, second, ellipse, fit, flags, piece_count, pieces]
        );
        // `RegionPiece` is bound only inside `RegionFit`: its array's offset and size are
        // checked there, its two fields here.
        assert_eq!(std::mem::size_of::<PieceRecord>(), 32);
    }

    #[test]
    fn a_seed_on_an_earlier_seeds_face_is_covered() {
        use glam::Vec3;
        let centre = |face| HighlightCentre {
            face,
            alpha: 0.3,
            beta: 0.3,
            position_object: Vec3::ZERO,
            position_world: Vec3::ZERO,
            normal_object: Vec3::Z,
            normal_world: Vec3::Z,
            dir_kappa_max: Vec3::X,
            dir_kappa_min: Vec3::Y,
            kappa_max: 1.0,
            kappa_min: 0.5,
        };
        let seeds = [(centre(3), 0.9), (centre(5), 0.9), (centre(3), 0.9)];
        let records = seed_records(&seeds, 10);
        let covered: Vec<u32> = records.iter().map(|r| r.start[1]).collect();
        assert_eq!(covered, [0, 0, 1]);
        // A seed with no frame grows nothing and covers nothing.
        let flat = HighlightCentre {
            normal_world: Vec3::ZERO,
            ..centre(7)
        };
        let records = seed_records(&[(flat, 0.9), (centre(7), 0.9)], 10);
        assert_eq!(records[0].start[0], u32::MAX);
        assert_eq!(records[1].start[1], 0);
    }
}
