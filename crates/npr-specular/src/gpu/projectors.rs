//! The frame's highlights made into projectors on the GPU (`shaders/projectors.wgsl`),
//! so that nothing is read back on the frame's path: after the search
//! ([`crate::gpu::CentreSearchPass`]) and the regions seeded on the GPU
//! ([`crate::gpu::RegionPass::prepare_tracked`]) in the same submission, `cs_project` makes
//! this frame's highlights as [`HighlightSet::update`] makes them (matching's ids, fades,
//! suppression, the change limit, the pieces of bent regions, the user's §3.4 controls,
//! Eq. (7)–(9)'s projectors, the falloff and who shares a region), writes the highlight
//! pass's records ([`ProjectorObject::projectors`], in [`crate::gpu::ProjectorGpu`]'s layout)
//! and keeps the highlights as the table the next frame's matching reads
//! ([`crate::gpu::RegionPass::prepare_tracked_on_table`] with [`ProjectorObject::table`]).
//! The CPU reads a frame's highlights one frame late ([`ProjectorObject::map_frame`]),
//! for picking or a panel.
//!
//! It speaks the pass contract ([`npr_gpu::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let pass = ProjectorPass::new(device);
//! let mut object = pass.create_object(device);
//! // per frame, after the search's and the tracked regions' prepares
//! let grown = regions.prepare_tracked_on_table(queue, &mut region_object, &tracked, object.table())?;
//! let input = ProjectorInput { frame, set: &set, world_from_object, regions: (&region_object, &grown), normal_maps: &[false] };
//! let projected = pass.prepare(queue, &mut object, &input)?;
//! search.record(..); regions.record(..); pass.record(&mut encoder, &object, &projected)?;
//! ```
//!
//! The CPU update is the reference: `tests/gpu_projectors.rs` compares the two on the
//! same frames. Ids are `u32` on the GPU.

use crate::gpu::regions::{MAX_TRACKED, TRACKED_SEEDS, TrackParams, TrackedRecord};
use crate::gpu::tables::{ControlsRecord, ProjectParams};
use crate::pass::ProjectorGpu;
use crate::{Footprint, HighlightSet, SpecularError, gpu::RegionObject};
use glam::{Mat4, Vec2};
use npr_geometry::HighlightCentre;
use npr_gpu::compute::{buffer_init, group_entry, layout_entry, pipeline};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};

/// Projectors one frame draws at most, pieces included (`MAX_DRAWN` of
/// `projectors.wgsl`); past them the frame says so ([`GpuFrameStatus::TooMany`]).
pub const MAX_DRAWN: usize = 384;

const PARAMS_BYTES: usize = std::mem::size_of::<ProjectParams>();
const TABLE_HEAD: usize = std::mem::size_of::<TrackParams>();
const RECORD_BYTES: usize = std::mem::size_of::<TrackedRecord>();
const PROJECTOR_BYTES: usize = std::mem::size_of::<ProjectorGpu>();
/// Where the §4.2 walk's frame starts in the projectors' buffer (`ProjectOutput`).
pub(crate) const RECEIVERS_AT: u64 = (PROJECTOR_BYTES * MAX_DRAWN) as u64;

/// The projectors' compute pipeline: one per device, shared by every object.
#[derive(Debug)]
pub struct ProjectorPass {
    id: PassId,
    device: wgpu::Device,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// One frame's projectors: the set (its settings and the user's controls), the
/// transform, the regions seeded on the GPU in the same submission (with the search
/// they were seeded from), and which texture layers are normal maps.
#[derive(Clone, Copy, Debug)]
pub struct ProjectorInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The highlight set: its settings and per-highlight controls.
    pub set: &'a HighlightSet,
    /// The object's transform.
    pub world_from_object: Mat4,
    /// The tracked regions' object and prepare for this frame
    /// ([`crate::gpu::RegionPass::prepare_tracked`] or `prepare_tracked_on_table`).
    pub regions: (&'a RegionObject, &'a Prepared),
    /// The search whose centres seeded them, and its prepare for this frame.
    pub search: (&'a crate::gpu::SearchObject, &'a Prepared),
    /// Per texture layer, whether it is a normal map ([`crate::HighlightPass`]'s
    /// layers; at most 32 are told apart).
    pub normal_maps: &'a [bool],
}

/// The GPU's highlights from frame to frame: two tables (the last frame's, read, and this
/// frame's, written) and the highlight pass's records.
#[derive(Debug)]
pub struct ProjectorObject {
    tables: [wgpu::Buffer; 2],
    /// The table the last prepare writes.
    written: usize,
    projectors: wgpu::Buffer,
    /// The highlight draw's normals of a pose made on the GPU
    /// ([`crate::gpu::FrameOnGpu::pose_on_gpu`]), in place of the set's.
    pub(crate) posed_normals: Option<wgpu::Buffer>,
    slots: Slots<ProjectorSlot>,
}

#[derive(Debug)]
struct ProjectorSlot {
    settings: wgpu::Buffer,
    room: usize,
    group: Option<wgpu::BindGroup>,
    /// The search's `cs_replace` over the table this frame reads.
    replace: Option<crate::gpu::search::ReplaceWork>,
    table: usize,
    /// The groups of earlier frames (`cs_project`'s, `cs_replace`'s).
    groups: npr_gpu::compute::GroupCache,
    replace_groups: npr_gpu::compute::GroupCache,
}

/// How a frame's projectors were made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuFrameStatus {
    /// Built from this frame's centres and regions.
    Built,
    /// The frame's regions were not seeded (too many centres, or none merged): its
    /// highlights were held as the last frame left them.
    Held,
    /// More than [`MAX_DRAWN`] projectors: the rest were left out.
    TooMany,
    /// A region's walk was cut short at its queue's capacity: it was fitted from the
    /// part it walked (the CPU would have grown it whole).
    CutShort,
    /// The search could not find the frame's peaks on the GPU (more bright parts
    /// without an `N = H` point than [`crate::gpu::MAX_MERGED`] centres in all): the frame
    /// was drawn without them (the CPU's update would have found them).
    NoPeaks,
}

/// One highlight of a frame built on the GPU (its piece 0), as the CPU reads it one
/// frame late.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuHighlight {
    /// Its id (the GPU counts them in `u32`).
    pub id: u64,
    /// The centre it was drawn at.
    pub centre: HighlightCentre,
    /// Its footprint before the controls.
    pub footprint: Footprint,
    /// Its opacity.
    pub opacity: f32,
    /// Whether this frame found its centre (else it fades out).
    pub found: bool,
    /// Whether it is a bright region's peak.
    pub peak: bool,
    /// Pieces drawn in its place.
    pub pieces: u8,
}

/// A frame's highlights and projectors, read back.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuFrame {
    /// How they were made.
    pub status: GpuFrameStatus,
    /// The highlights, in id order.
    pub highlights: Vec<GpuHighlight>,
    /// The highlight pass's records (pieces after their highlight).
    pub projectors: Vec<ProjectorGpu>,
    /// Centres suppressed this frame (merged away).
    pub merged: u32,
    /// The id the next new highlight takes.
    pub next_id: u64,
}

impl ProjectorPass {
    /// The projectors' pipeline.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::PROJECTORS.module(device);
        let entries: Vec<_> = (0..8)
            .map(|b| layout_entry(b, wgpu::BufferBindingType::Storage { read_only: b < 6 }))
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr projectors"),
            entries: &entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            pipeline: pipeline(device, &module, &layout, "cs_project"),
            layout,
        }
    }

    /// Two empty tables (no highlight yet: the first frame shows its highlights at once)
    /// and room for [`MAX_DRAWN`] projectors.
    pub fn create_object(&self, device: &wgpu::Device) -> ProjectorObject {
        let head = TrackParams {
            room: TRACKED_SEEDS as u32,
            ..TrackParams::default()
        };
        let mut bytes = bytemuck::bytes_of(&head).to_vec();
        bytes.resize(TABLE_HEAD + RECORD_BYTES * MAX_TRACKED, 0);
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let table = |label| buffer_init(device, label, &bytes, usage);
        ProjectorObject {
            tables: [
                table("npr projector table a"),
                table("npr projector table b"),
            ],
            written: 1,
            projectors: buffer_init(
                device,
                "npr projectors",
                &vec![0u8; RECEIVERS_AT as usize + crate::gpu::receivers::frame_bytes(MAX_DRAWN)],
                wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
            ),
            posed_normals: None,
            slots: Slots::new(self.id),
        }
    }

    /// Writes the frame's settings and controls and binds this frame's inputs (the
    /// tracked regions, their table and the search's centres) and outputs (the other
    /// table, the projectors).
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a foreign object, a regions or search prepare of
    /// another frame or one not tracked, or too many prepares in one frame.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut ProjectorObject,
        input: &ProjectorInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        object.slots.check_pass(self.id)?;
        for prepared in [input.regions.1, input.search.1] {
            if prepared.frame() != input.frame {
                return Err(SpecularError::Pass(npr_gpu::PassError::Stale {
                    prepared: prepared.frame().0,
                    current: input.frame.0,
                }));
            }
        }
        let [seeds, fits, dispatch, track] = input.regions.0.tracked_buffers(input.regions.1)?;
        let (_, centres) = input.search.0.centre_buffers(input.search.1)?;
        let (params, controls) = input
            .set
            .project_params(input.world_from_object, input.normal_maps);
        let device = &self.device;
        let table = 1 - object.written;
        let (prepared, slot) = object.slots.next(self.id, input.frame, || ProjectorSlot {
            settings: settings_buffer(device, 1),
            room: 1,
            group: None,
            replace: None,
            table,
            groups: Default::default(),
            replace_groups: Default::default(),
        })?;
        if controls.len() > slot.room {
            slot.room = controls.len().next_power_of_two();
            slot.settings = settings_buffer(device, slot.room);
        }
        let records = if controls.is_empty() {
            vec![ControlsRecord::default()]
        } else {
            controls
        };
        npr_gpu::compute::write_head_and_records(queue, &slot.settings, &params, &records);
        slot.table = table;
        let (search, searched) = input.search;
        let replace = search.replace_work(device, searched, track, &mut slot.replace_groups)?;
        slot.replace = Some(replace);
        let next = &object.tables[table];
        let bound = [seeds, fits, centres, track, dispatch, &slot.settings, next];
        let layout = &self.layout;
        let group = slot.groups.get_or_make(&bound, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr projectors"),
                layout,
                entries: &[
                    group_entry(0, seeds),
                    group_entry(1, fits),
                    group_entry(2, centres),
                    group_entry(3, track),
                    group_entry(4, dispatch),
                    group_entry(5, &slot.settings),
                    group_entry(6, next),
                    group_entry(7, &object.projectors),
                ],
            })
        });
        slot.group = Some(group);
        object.written = table;
        Ok(prepared)
    }

    /// Records the last frame's highlights placed again on this frame (the search's
    /// `cs_replace`) and `cs_project` (one workgroup), after the search and the regions in
    /// the same submission.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another pass, object or frame.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &ProjectorObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        let slot = object.slots.get(self.id, prepared)?;
        let Some(group) = &slot.group else {
            return Ok(());
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr projectors"),
            timestamp_writes: None,
        });
        if let Some(replace) = &slot.replace {
            replace.dispatch(&mut pass);
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        Ok(())
    }
}

fn settings_buffer(device: &wgpu::Device, room: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("npr projector settings"),
        size: (PARAMS_BYTES + room.max(1) * std::mem::size_of::<ControlsRecord>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl ProjectorObject {
    /// Makes the next prepare read the table the last one read (and write the one it
    /// wrote): the last frame made again, its fades not advanced.
    pub(crate) fn rewind(&mut self) {
        self.written = 1 - self.written;
    }

    /// The table the last prepare writes: the next frame's matching reads it
    /// ([`crate::gpu::RegionPass::prepare_tracked_on_table`]).
    pub fn table(&self) -> &wgpu::Buffer {
        &self.tables[self.written]
    }

    /// The highlight pass's records the last recorded frame wrote
    /// ([`crate::gpu::ProjectorGpu`]'s layout, at most [`MAX_DRAWN`]; their count is in the
    /// table, [`GpuFrame::projectors`]).
    pub fn projectors(&self) -> &wgpu::Buffer {
        &self.projectors
    }

    /// The highlight pass's records as a binding ([`MAX_DRAWN`] of them).
    pub(crate) fn projector_binding(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.projectors,
            offset: 0,
            size: std::num::NonZeroU64::new(RECEIVERS_AT),
        })
    }

    /// The §4.2 walk's frame (`ReceiverFrame`: values, then [`MAX_DRAWN`] queries) as a
    /// binding, and its buffer and offset (the CPU writes the values).
    pub(crate) fn receiver_frame(&self) -> (&wgpu::Buffer, u64) {
        (&self.projectors, RECEIVERS_AT)
    }

    /// Starts the next frame from `set`'s last update (its highlights, ids, fades and next
    /// id) placed under `world_from_object`, in place of the table the GPU kept: a set
    /// updated on the CPU so far goes on on the GPU with the same highlights.
    /// `search` is the GPU search the frames run (`cs_replace` places the highlights it
    /// loses again through its faces' slots).
    pub fn start_from(
        &self,
        queue: &wgpu::Queue,
        (set, search): (&HighlightSet, &crate::gpu::SearchObject),
        world_from_object: Mat4,
    ) {
        let slots = search.slots_of_faces();
        let (mut head, table) = set.gpu_table(world_from_object, Some(&slots));
        head.room = TRACKED_SEEDS as u32;
        let count = table.len().min(MAX_TRACKED);
        head.count = count as u32;
        let mut bytes = bytemuck::bytes_of(&head).to_vec();
        bytes.extend_from_slice(bytemuck::cast_slice(&table[..count]));
        queue.write_buffer(self.table(), 0, &bytes);
    }

    /// Copies the frame's table and projectors, after the submission that holds its
    /// [`ProjectorPass::record`], and asks for the map without waiting: the CPU's view of
    /// a frame, one frame late.
    pub fn map_frame(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> PendingFrame {
        let table = (TABLE_HEAD + RECORD_BYTES * MAX_TRACKED) as u64;
        let projectors = (PROJECTOR_BYTES * MAX_DRAWN) as u64;
        let to = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr projector readback"),
            size: table + projectors,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(self.table(), 0, &to, 0, table);
        encoder.copy_buffer_to_buffer(&self.projectors, 0, &to, table, projectors);
        queue.submit([encoder.finish()]);
        PendingFrame {
            map: npr_gpu::BufferReadback::map(to),
        }
    }
}

/// A frame's highlights on their way to the CPU ([`ProjectorObject::map_frame`]).
#[derive(Debug)]
pub struct PendingFrame {
    map: npr_gpu::BufferReadback,
}

impl PendingFrame {
    /// The frame once the map has completed; `None` while it has not.
    pub fn try_take(&self) -> Option<Result<GpuFrame, npr_gpu::GpuError>> {
        Some(self.map.try_take()?.map(|b| decode(&b)))
    }

    /// Blocks until the map has completed (native: polls `device`) and decodes.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::Readback`] when polling or mapping fails.
    pub fn wait(self, device: &wgpu::Device) -> Result<GpuFrame, npr_gpu::GpuError> {
        self.map.wait(device).map(|b| decode(&b))
    }
}

fn decode(bytes: &[u8]) -> GpuFrame {
    let head: TrackParams = bytes
        .get(..TABLE_HEAD)
        .map(bytemuck::pod_read_unaligned)
        .unwrap_or_default();
    let records = (head.count as usize).min(MAX_TRACKED);
    let highlights = (0..records)
        .filter_map(|k| {
            let at = TABLE_HEAD + k * RECORD_BYTES;
            let r: TrackedRecord = bytemuck::pod_read_unaligned(bytes.get(at..at + RECORD_BYTES)?);
            Some(GpuHighlight {
                id: u64::from(r.state[0]),
                centre: r.centre.centre(),
                footprint: Footprint {
                    half_extent: Vec2::new(r.footprint[0], r.footprint[1]),
                    offset: Vec2::new(r.footprint[2], r.footprint[3]),
                    rotate_rad: r.shape[0],
                    region_area: r.shape[1],
                    normal_cone_cos: r.shape[2],
                    fit_scale: r.shape[3],
                },
                opacity: r.fade[0],
                found: r.state[1] != 0,
                peak: r.state[2] != 0,
                pieces: r.state[3].min(255) as u8,
            })
        })
        .collect();
    let base = TABLE_HEAD + RECORD_BYTES * MAX_TRACKED;
    let projectors = (0..(head.drawn as usize).min(MAX_DRAWN))
        .filter_map(|k| {
            let at = base + k * PROJECTOR_BYTES;
            Some(bytemuck::pod_read_unaligned(
                bytes.get(at..at + PROJECTOR_BYTES)?,
            ))
        })
        .collect();
    GpuFrame {
        status: match head.status {
            0 => GpuFrameStatus::Built,
            1 => GpuFrameStatus::Held,
            2 => GpuFrameStatus::TooMany,
            3 => GpuFrameStatus::CutShort,
            _ => GpuFrameStatus::NoPeaks,
        },
        highlights,
        projectors,
        merged: head.merged,
        next_id: u64::from(head.next_id),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ProjectData` of `projectors.wgsl` with one control.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
    struct ProjectData {
        params: ProjectParams,
        controls: [ControlsRecord; 1],
    }

    /// `ProjectOutput` of `projectors.wgsl` with one query.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
    struct ProjectOutput {
        records: [ProjectorGpu; MAX_DRAWN],
        receiver_params: crate::gpu::receivers::Params,
        queries: [crate::gpu::receivers::Query; 1],
    }

    #[test]
    fn records_match_wgsl() {
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            ProjectOutput,
            "ProjectOutput",
            [records, receiver_params, queries]
        );
        assert_eq!(
            std::mem::offset_of!(ProjectOutput, receiver_params) as u64,
            RECEIVERS_AT
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            ProjectData,
            "ProjectData",
            [params, controls]
        );
        // `ProjectorRecord` is `ProjectorGpu` (checked against the highlight pass's
        // `Projector` in `pass.rs`), bound inside `ProjectOutput`.
        assert_eq!(std::mem::size_of::<ProjectorGpu>(), 160);
        // `ProjectParams` and `ControlsRecord` are bound inside `ProjectData`.
        assert_eq!(
            [
                std::mem::offset_of!(ProjectParams, sizes),
                std::mem::offset_of!(ProjectParams, modes),
                std::mem::size_of::<ProjectParams>(),
                std::mem::offset_of!(ControlsRecord, tint),
                std::mem::size_of::<ControlsRecord>(),
            ],
            [48, 80, 112, 48, 64]
        );
    }
}
