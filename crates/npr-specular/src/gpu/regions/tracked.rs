//! A frame's regions seeded on the GPU (`shaders/tracking.wgsl`): the search's centres
//! ([`crate::gpu::SearchSolutions::centres`], computed by `cs_centres`) matched with the last
//! update's highlights as [`HighlightSet`]'s matching does, and written as the growth's
//! seeds in the order the CPU grows them, so that the search and the regions run in one
//! submission and the frame waits once. The centres include the peaks (bright regions
//! without an `N = H` point) where the search found them on the GPU. The CPU then
//! checks that the seeds are the ones its own matching gives
//! ([`TrackedRegions::for_seeds`]); a frame whose seeds differ is grown again in
//! a second submission: the search found no peaks for it (too many centres or bright
//! vertices), the seeds outnumber the frame's room, the σ differ, or a float tie fell
//! otherwise.

use super::records::{FIT_BYTES, PARAMS_BYTES, SeedRecord, decode};
use super::{GpuRegion, RegionObject};
use crate::{HighlightSet, SpecularError, gpu::SearchObject};
use glam::{Mat4, Vec3};
use npr_geometry::LightEye;
use npr_gpu::compute::{buffer_init, group_entry};
use npr_gpu::pass::{FrameId, Prepared};

/// Seeds a frame seeded on the GPU has room for at most: more, and it grows none
/// ([`TrackedRegions::status`]). A frame's room is twice the last update's highlights
/// and 8 more, in powers of two up to this, so that the scratch of a
/// [`RegionObject`] (a queue per seed) stays the size its frames need.
pub const TRACKED_SEEDS: usize = 64;

/// The seeds a tracked frame of `set` has room for: twice its last update's highlights
/// and 8 more (centres come and go between frames), a power of two, at most
/// [`TRACKED_SEEDS`].
pub(super) fn tracked_room(set: &HighlightSet) -> usize {
    (2 * set.highlights().len() + 8)
        .next_power_of_two()
        .min(TRACKED_SEEDS)
}

/// Highlights of the last update the GPU's matching takes at most (`MAX_TRACKED` of
/// `tracking.wgsl`); past them a frame is not seeded on the GPU.
pub const MAX_TRACKED: usize = 256;

/// `TrackedHighlight` of `highlight_table.wgsl`: one highlight of the table the GPU's
/// matching and projectors read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct TrackedRecord {
    pub(crate) position_reach: [f32; 4],
    pub(crate) sigma: [f32; 4],
    pub(crate) centre: crate::gpu::search::CentreRecord,
    pub(crate) footprint: [f32; 4],
    pub(crate) shape: [f32; 4],
    pub(crate) state: [u32; 4],
    pub(crate) fade: [f32; 4],
}

/// `TrackParams` of `highlight_table.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct TrackParams {
    pub(crate) count: u32,
    pub(crate) room: u32,
    pub(crate) sigma: f32,
    pub(crate) tracking: u32,
    pub(crate) next_id: u32,
    pub(crate) drawn: u32,
    pub(crate) merged: u32,
    pub(crate) status: u32,
}

/// `TrackData` of `tracking.wgsl` with one highlight.
#[cfg(test)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct TrackData {
    pub(super) params: TrackParams,
    pub(super) previous: [TrackedRecord; 1],
}

/// One frame's growth seeded on the GPU: the set (its mesh, normals, and the last
/// update's highlights the centres are matched with), the frame, its light, eye and
/// transform, and the search recorded before it in the same submission.
#[derive(Clone, Copy, Debug)]
pub struct TrackedInput<'a> {
    /// The caller's submission (the search's too).
    pub frame: FrameId,
    /// The highlight set, not yet updated for this frame.
    pub set: &'a HighlightSet,
    /// Light and eye, world space.
    pub light_eye: LightEye,
    /// The object's transform.
    pub world_from_object: Mat4,
    /// The search whose centres seed the growth, and its prepare for this frame.
    pub search: (&'a SearchObject, &'a Prepared),
}

/// How a frame seeded on the GPU went (`dispatch[3]` of `tracking.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackStatus {
    /// Seeded and grown.
    Seeded,
    /// More seeds than the frame's room (at most [`TRACKED_SEEDS`]): none grown.
    TooMany,
    /// The search's centres were not merged on the GPU (an overflowed list, or more than
    /// [`crate::gpu::MAX_MERGED`]): none grown.
    Unmerged,
}

/// One seed the GPU wrote: its centre (world), σ, and whether it has a frame to grow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedSeed {
    /// The centre, world space (bit for bit the search's [`npr_geometry::HighlightCentre::position_world`]).
    pub position_world: Vec3,
    /// The σ it was grown at.
    pub sigma: f32,
    /// Its face ([`npr_geometry::HighlightCentre::face`]).
    pub face: u32,
}

/// A frame's regions seeded on the GPU, read back with its seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedRegions {
    /// How the seeding went.
    pub status: TrackStatus,
    /// The seeds, in the order grown.
    pub seeds: Vec<TrackedSeed>,
    /// One region per seed.
    pub regions: Vec<GpuRegion>,
}

/// A frame's tracked regions on their way to the CPU ([`RegionObject::map_tracked`]).
#[derive(Debug)]
pub struct PendingTracked {
    map: npr_gpu::BufferReadback,
    room: usize,
}

impl PendingTracked {
    /// The regions once the map has completed; `None` while it has not.
    pub fn try_take(&self) -> Option<Result<TrackedRegions, npr_gpu::GpuError>> {
        Some(self.map.try_take()?.map(|b| decode_tracked(&b, self.room)))
    }

    /// Blocks until the map has completed (native: polls `device`) and decodes.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::Readback`] when polling or mapping fails.
    pub fn wait(self, device: &wgpu::Device) -> Result<TrackedRegions, npr_gpu::GpuError> {
        let room = self.room;
        Ok(decode_tracked(&self.map.wait(device)?, room))
    }
}

/// A tracked frame's own buffers: the table of the last update's highlights, the
/// growth's indirect dispatch (and status, and the matching), the σ the user set, and
/// `cs_track`'s group. A slot keeps them from frame to frame (written again, grown where
/// too small).
#[derive(Debug)]
pub(super) struct TrackedSlot {
    pub(super) dispatch: wgpu::Buffer,
    pub(super) track: wgpu::Buffer,
    /// The table this slot uploads (a table the GPU wrote is bound as it is).
    own_track: Option<wgpu::Buffer>,
    sigmas: wgpu::Buffer,
    /// What `sigmas` holds (written again only when it changes).
    sigma_words: Vec<[u32; 2]>,
    pub(super) group: wgpu::BindGroup,
    groups: npr_gpu::compute::GroupCache,
}

/// Where a tracked frame's table of last highlights comes from: the set's last update
/// (`TrackData` bytes), or a table the GPU wrote (`projectors.wgsl`'s next table).
pub(super) enum TableSource<'a> {
    Bytes(&'a [u8]),
    Gpu(&'a wgpu::Buffer),
}

/// Words of a tracked frame's dispatch buffer: (x, y, z, status), the counts, then per
/// highlight of the last update the centre it took (`MATCH_AT` of `tracking.wgsl`).
const DISPATCH_WORDS: usize = 8 + MAX_TRACKED;

/// The table `cs_track` reads (`TrackData`): the last update's highlights of `set` for
/// this transform, and `room` seeds; `None` when there are more than [`MAX_TRACKED`].
pub(super) fn track_data(
    set: &HighlightSet,
    world_from_object: Mat4,
    room: usize,
) -> Option<Vec<u8>> {
    // Made again every frame: each centre placed here already.
    let (mut params, table) = set.gpu_table(world_from_object, None);
    if table.len() > MAX_TRACKED {
        return None;
    }
    params.room = room as u32;
    let mut bytes = bytemuck::bytes_of(&params).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&table));
    if table.is_empty() {
        bytes.extend_from_slice(bytemuck::bytes_of(&TrackedRecord::default()));
    }
    Some(bytes)
}

/// `cs_track`'s buffers and group for one frame: the growth's frame data (`seeds`), the
/// search's counter and centres, the table, the σ the user set per highlight
/// (`HighlightSet::own_sigmas`) and the dispatch, reusing `last`'s buffers where they are
/// large enough.
pub(super) fn tracked_slot(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    layout: &wgpu::BindGroupLayout,
    (seeds, table, own_sigma): (&wgpu::Buffer, TableSource<'_>, &[[u32; 2]]),
    (counter, centres): (&wgpu::Buffer, &wgpu::Buffer),
    last: Option<TrackedSlot>,
) -> TrackedSlot {
    let fits = |b: &wgpu::Buffer, bytes: usize| b.size() >= bytes as u64;
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
    let reuse = |b: Option<wgpu::Buffer>, bytes: &[u8], label| match b {
        Some(b) if fits(&b, bytes.len()) => {
            queue.write_buffer(&b, 0, bytes);
            b
        }
        _ => buffer_init(device, label, bytes, usage),
    };
    let (last_track, last_sigmas, last_dispatch, mut groups) = match last {
        Some(t) => (
            t.own_track,
            Some((t.sigmas, t.sigma_words)),
            Some(t.dispatch),
            t.groups,
        ),
        None => (None, None, None, Default::default()),
    };
    let (track, own_track) = match table {
        TableSource::Bytes(bytes) => {
            let t = reuse(last_track, bytes, "npr region track");
            (t.clone(), Some(t))
        }
        TableSource::Gpu(buffer) => (buffer.clone(), last_track),
    };
    let sigmas = match last_sigmas {
        Some((b, words)) if words == own_sigma => b,
        last => reuse(
            last.map(|(b, _)| b),
            bytemuck::cast_slice(own_sigma),
            "npr region own sigma",
        ),
    };
    // `cs_track` writes every word a frame reads (the status and counts; the matching
    // where it matched).
    let dispatch = last_dispatch.unwrap_or_else(|| {
        buffer_init(
            device,
            "npr region dispatch",
            &[0u32; DISPATCH_WORDS],
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_SRC,
        )
    });
    let bound = [seeds, centres, counter, &track, &dispatch, &sigmas];
    let group = groups.get_or_make(&bound, || {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr region track"),
            layout,
            entries: &[
                group_entry(0, seeds),
                group_entry(1, centres),
                group_entry(2, counter),
                group_entry(3, &track),
                group_entry(4, &dispatch),
                group_entry(5, &sigmas),
            ],
        })
    });
    TrackedSlot {
        dispatch,
        track,
        own_track,
        sigmas,
        sigma_words: own_sigma.to_vec(),
        group,
        groups,
    }
}

impl RegionObject {
    /// A tracked frame's buffers the projectors read in the same submission: the growth's
    /// frame data (seeds), the fits, the dispatch (status and matching) and the table.
    pub(crate) fn tracked_buffers(
        &self,
        prepared: &Prepared,
    ) -> Result<[&wgpu::Buffer; 4], SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        let Some(tracked) = &slot.tracked else {
            return Err(SpecularError::Pass(npr_gpu::PassError::ForeignPrepared));
        };
        Ok([&slot.seeds, &slot.fits, &tracked.dispatch, &tracked.track])
    }

    /// Copies a frame seeded on the GPU (its status, seeds and regions: about 400 bytes a
    /// seed) and asks for the map without waiting; after the submission that holds its
    /// [`super::RegionPass::record`].
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`, or one not seeded on the
    /// GPU ([`super::RegionPass::prepare_tracked`]).
    pub fn map_tracked(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prepared: &Prepared,
    ) -> Result<PendingTracked, SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        let Some(tracked) = &slot.tracked else {
            return Err(SpecularError::Pass(npr_gpu::PassError::ForeignPrepared));
        };
        let room = slot.count;
        let frame = (PARAMS_BYTES + room * 80) as u64;
        let fits = (room * FIT_BYTES) as u64;
        let to = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr region tracked readback"),
            size: 16 + frame + fits,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&tracked.dispatch, 0, &to, 0, 16);
        encoder.copy_buffer_to_buffer(&slot.seeds, 0, &to, 16, frame);
        encoder.copy_buffer_to_buffer(&slot.fits, 0, &to, 16 + frame, fits);
        queue.submit([encoder.finish()]);
        Ok(PendingTracked {
            map: npr_gpu::BufferReadback::map(to),
            room,
        })
    }
}

/// The dispatch (count, 1, 1, status), the frame data (params, `room` seeds) and the
/// fits of a tracked frame.
fn decode_tracked(bytes: &[u8], room: usize) -> TrackedRegions {
    let word = |i: usize| {
        bytes
            .get(4 * i..4 * i + 4)
            .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let status = match word(3) {
        0 => TrackStatus::Seeded,
        1 => TrackStatus::TooMany,
        _ => TrackStatus::Unmerged,
    };
    let count = (word(0) as usize).min(room);
    let seeds_at = 16 + PARAMS_BYTES;
    let seeds = (0..count)
        .filter_map(|k| {
            let at = seeds_at + 80 * k;
            let s: SeedRecord = bytemuck::pod_read_unaligned(bytes.get(at..at + 80)?);
            Some(TrackedSeed {
                position_world: Vec3::new(s.origin[0], s.origin[1], s.origin[2]),
                sigma: s.origin[3],
                face: s.start[3],
            })
        })
        .collect();
    let fits_at = 16 + PARAMS_BYTES + 80 * room;
    let regions = decode(bytes.get(fits_at..).unwrap_or(&[]), count);
    TrackedRegions {
        status,
        seeds,
        regions,
    }
}
