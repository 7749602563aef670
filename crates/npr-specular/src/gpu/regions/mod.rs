//! The regions `N·H ≥ σ` of [`crate::cpu::region`] grown and fitted as a compute pass
//! (`shaders/regions.wgsl`): each seed's breadth-first growth from its face, one
//! workgroup per seed; the seeds whose walks met walked again together, level by level,
//! so that the faces are shared out between seeds as the CPU's single queue shares them
//! (fewest steps, then the lower seed; a face one seed reached, taken or not, closed to
//! the others); and each seed's area moments summed and fitted with the ellipse of the
//! same moments ([`Footprint`]). Nothing mesh-sized is read back: one
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
//! The CPU growth ([`RegionGrower::grow_all`](crate::cpu::region::RegionGrower::grow_all)) is
//! the reference: `tests/gpu_regions.rs` compares the two on the same frame. The moment
//! ellipse, the scale of it that fits the region best ([`GpuRegion::overlap_scale`]) and
//! a long bent region's pieces ([`GpuRegion::pieces`]) are fitted here. A growth longer than the object's capacity stops there and
//! says so ([`GpuRegion::overflowed`]).

use crate::cpu::region::{Footprint, MAX_PIECES, Region};
use crate::gpu::receivers::{adjacency, storage};
use crate::{HighlightSet, SpecularError};
use glam::{Mat3, Mat4};
use npr_geometry::{HighlightCentre, LightEye};
use npr_gpu::compute::{buffer_init, check_bindings, group_entry, layout_entry, pipeline};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};

pub(crate) mod records;
mod tracked;
use records::{
    FIT_BYTES, PARAMS_BYTES, Params, STORAGE, SeedRecord, decode, face_records, vertex_records,
};
pub use tracked::{
    MAX_TRACKED, PendingTracked, TRACKED_SEEDS, TrackStatus, TrackedInput, TrackedRegions,
    TrackedSeed,
};
pub(crate) use tracked::{TrackParams, TrackedRecord};

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
    /// `cs_join`: the seeds whose walks met, walked again together.
    join: wgpu::ComputePipeline,
    fit: wgpu::ComputePipeline,
    /// `cs_track` of `tracking.wgsl` and its group's layout.
    track: wgpu::ComputePipeline,
    track_layout: wgpu::BindGroupLayout,
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
    /// Per face the word walks meet in and two bits per seed (`words` words each), then
    /// the joint walk's state ([`visited_words`]).
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
    /// What `group` was made for: the object's visited words, its queues' seeds, and
    /// this slot's room.
    group_key: Option<(usize, usize, usize)>,
    /// Seeds the buffers have room for.
    room: usize,
    /// Seeds this frame grows (a frame seeded on the GPU: the most it may).
    count: usize,
    /// A frame seeded on the GPU ([`RegionPass::prepare_tracked`]).
    tracked: Option<tracked::TrackedSlot>,
}

/// One seed's region as the GPU grew and fitted it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuRegion {
    /// What the growth found, as [`RegionGrower::grow_all`](crate::cpu::region::RegionGrower::grow_all)
    /// gives it: covered, empty, or the moment ellipse (with the region's normal cone;
    /// `fit_scale` 1) and the faces the seed won.
    pub region: Region,
    /// Faces its walk took, won or not.
    pub walked: u32,
    /// Whether the walk stopped at the object's capacity (then the region is cut short).
    pub overflowed: bool,
    /// The scale (≤ 1) of the moment ellipse that fits the region best
    /// ([`RegionGrower::overlap_scale`](crate::cpu::region::RegionGrower::overlap_scale),
    /// from the faces won one by one); 1 when the region is not fitted.
    pub overlap_scale: f32,
    /// How many of [`GpuRegion::pieces`] hold a piece: 0, or 2 to [`MAX_PIECES`] for a
    /// long bent region cut along its length
    /// ([`RegionGrower::pieces`](crate::cpu::region::RegionGrower::pieces)).
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
        let track_module = crate::shaders::TRACKING.module(device);
        let track_entries: Vec<_> = (0..6)
            .map(|b| {
                let read_only = b != 0 && b != 4;
                layout_entry(b, wgpu::BufferBindingType::Storage { read_only })
            })
            .collect();
        let track_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr region track"),
            entries: &track_entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            grow: pipeline(device, &module, &layout, "cs_grow"),
            join: pipeline(device, &module, &layout, "cs_join"),
            fit: pipeline(device, &module, &layout, "cs_fit"),
            layout,
            track: pipeline(device, &track_module, &track_layout, "cs_track"),
            track_layout,
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
                &vec![0u32; visited_words(faces.len(), 1)],
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
        self.prepare_with(queue, object, input, None)
    }

    /// [`RegionPass::prepare`] for a frame whose seeds the GPU writes (`tracking.wgsl`)
    /// from the centres of `input.search`, recorded before this growth in the same
    /// submission, matched with `input.set`'s last update as its matching does: the
    /// growth is dispatched over them indirectly, with room for twice the last update's
    /// highlights and 8 more (at most [`TRACKED_SEEDS`]). Read it
    /// with [`RegionObject::map_tracked`].
    ///
    /// # Errors
    /// As [`RegionPass::prepare`]; [`SpecularError::Pass`] for a search prepare of
    /// another pass, object or frame; [`SpecularError::Mismatch`] when the set has more
    /// than [`MAX_TRACKED`] highlights.
    pub fn prepare_tracked(
        &self,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &TrackedInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        let room = tracked::tracked_room(input.set);
        let table =
            tracked::track_data(input.set, input.world_from_object, room).ok_or_else(|| {
                SpecularError::Mismatch(format!(
                    "more than {MAX_TRACKED} highlights to match on the GPU"
                ))
            })?;
        let table = tracked::TableSource::Bytes(&table);
        self.prepare_tracked_with(queue, object, input, (room, table))
    }

    /// [`RegionPass::prepare_tracked`] matching the centres with a table of highlights the
    /// GPU wrote (a [`crate::gpu::ProjectorObject`]'s, [`crate::gpu::ProjectorObject::table`]) in
    /// place of `input.set`'s last update, with room for `room` seeds (at most
    /// [`MAX_TRACKED`]; a frame of more is not seeded): a frame that reads nothing back.
    ///
    /// # Errors
    /// As [`RegionPass::prepare_tracked`].
    pub fn prepare_tracked_on_table(
        &self,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &TrackedInput<'_>,
        (table, room): (&wgpu::Buffer, usize),
    ) -> Result<Prepared, SpecularError> {
        let room = room.clamp(1, MAX_TRACKED);
        let table = tracked::TableSource::Gpu(table);
        self.prepare_tracked_with(queue, object, input, (room, table))
    }

    /// A tracked frame's prepare (`room` seeds at most, matched with `table`), after the
    /// search's of the same frame.
    fn prepare_tracked_with(
        &self,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &TrackedInput<'_>,
        (room, table): (usize, tracked::TableSource<'_>),
    ) -> Result<Prepared, SpecularError> {
        let (search, searched) = input.search;
        if searched.frame() != input.frame {
            return Err(SpecularError::Pass(npr_gpu::PassError::Stale {
                prepared: searched.frame().0,
                current: input.frame.0,
            }));
        }
        let outputs = search.centre_buffers(searched)?;
        let cpu_input = RegionInput {
            frame: input.frame,
            set: input.set,
            seeds: &[],
            light_eye: input.light_eye,
            world_from_object: input.world_from_object,
        };
        self.prepare_with(queue, object, &cpu_input, Some((room, table, outputs)))
    }

    /// [`RegionPass::prepare`], its seeds written by the CPU (`tracked` `None`) or by
    /// `cs_track` from the table and the search's counter and centres.
    fn prepare_with(
        &self,
        queue: &wgpu::Queue,
        object: &mut RegionObject,
        input: &RegionInput<'_>,
        tracked: Option<(
            usize,
            tracked::TableSource<'_>,
            (&wgpu::Buffer, &wgpu::Buffer),
        )>,
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
        let count = match tracked {
            Some((room, ..)) => room,
            None => input.seeds.len(),
        };
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
            let bytes = (visited_words(faces, words) * 4) as u64;
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
        if tracked.is_some() {
            // A new highlight's σ is the set's global one now, as the CPU's matching
            // takes it; `cs_track` reads it and the room here, not in the table.
            let fresh = set
                .tuning
                .controls
                .compose(&crate::HighlightControls::default());
            params.track_room = count as u32;
            params.track_sigma = fresh.sigma;
        }
        let seeds = seed_records(input.seeds, faces);
        npr_gpu::compute::write_head_and_records(queue, &slot.seeds, &params, &seeds);
        // The group changes only with the buffers it binds.
        let key = (object.words, object.work_seeds, slot.room);
        if slot.group_key != Some(key) || slot.group.is_none() {
            slot.group_key = Some(key);
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
        }
        slot.count = count;
        let own_sigma = set.own_sigmas();
        let last = slot.tracked.take();
        slot.tracked = tracked.map(|(_, table, outputs)| {
            let inputs = (&slot.seeds, table, own_sigma.as_slice());
            tracked::tracked_slot((device, queue), &self.track_layout, inputs, outputs, last)
        });
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

    /// Records the growth: the faces' marks cleared, one workgroup per seed walking its
    /// region, one walking again together the seeds whose walks met, then one per seed
    /// summing and fitting the faces it won.
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
        if let Some(tracked) = &slot.tracked {
            // Two passes: the dispatch buffer is written as storage by the first and read
            // as the second's indirect arguments.
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("npr region track"),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, &tracked.group, &[]);
                pass.set_pipeline(&self.track);
                pass.dispatch_workgroups(1, 1, 1);
            }
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("npr regions"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, group, &[]);
            pass.set_pipeline(&self.grow);
            pass.dispatch_workgroups_indirect(&tracked.dispatch, 0);
            pass.set_pipeline(&self.join);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&self.fit);
            pass.dispatch_workgroups_indirect(&tracked.dispatch, 0);
            return Ok(());
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr regions"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        pass.set_pipeline(&self.grow);
        pass.dispatch_workgroups(slot.count as u32, 1, 1);
        pass.set_pipeline(&self.join);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.fit);
        pass.dispatch_workgroups(slot.count as u32, 1, 1);
        Ok(())
    }
}

/// Words of the `visited` scratch for `faces` faces and `words` bit words a face: per
/// face the word walks meet in and the seeds' bits (reached, taken), then a head of four
/// and per seed (32 a bit word) four words of `cs_join`'s state.
fn visited_words(faces: usize, words: usize) -> usize {
    faces.max(1) * (2 * words + 1) + 4 + 4 * 32 * words
}

fn make_slot(device: &wgpu::Device) -> Slot {
    Slot {
        seeds: storage(device, "npr region seeds", (PARAMS_BYTES + 80) as u64),
        fits: storage(device, "npr region fits", FIT_BYTES as u64),
        group: None,
        group_key: None,
        room: 0,
        count: 0,
        tracked: None,
    }
}

impl RegionObject {
    /// The buffers a pose's tables go to ([`crate::gpu::ReposePass`]): the vertices and the
    /// faces.
    pub(crate) fn pose_tables(&self) -> [&wgpu::Buffer; 2] {
        [&self.vertex_records, &self.face_records]
    }

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

#[cfg(test)]
mod tests;
