//! A search's lists on their way back: the readback's layout and its decoding.

use super::{MAX_MERGED, NO_MERGE, SearchSolutions};
use glam::Vec3;
use npr_geometry::{FaceSolution, HighlightCentre};

/// `CentreRecord` of `centre_search.wgsl`: one centre `cs_centres` computed.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct CentreRecord {
    /// w: 1 where the CPU has a centre there, 0 where not.
    pub(super) position_object: [f32; 4],
    pub(super) position_world: [f32; 4],
    pub(super) normal_object: [f32; 4],
    pub(super) normal_world: [f32; 4],
    pub(super) dir_kappa_max: [f32; 4],
    /// (κmax, κmin, 1 for a peak, 0).
    pub(super) curvature: [f32; 4],
    /// (face, α and β as bits, the face's visiting slot).
    pub(super) solution: [u32; 4],
}

/// Bytes of one [`CentreRecord`].
pub(super) const CENTRE_RECORD_BYTES: usize = std::mem::size_of::<CentreRecord>();

/// Bytes of a readback: the 16-byte header, the `capacity` accepted faces, then the
/// [`MAX_MERGED`] centre records.
pub(super) fn readback_bytes(capacity: usize) -> u64 {
    (16 + 16 * capacity + CENTRE_RECORD_BYTES * MAX_MERGED) as u64
}

/// A search's list on its way to the CPU ([`super::SearchObject::map`]).
#[derive(Debug)]
pub struct PendingSolutions {
    pub(super) map: npr_gpu::BufferReadback,
    pub(super) capacity: usize,
    /// The σ the search looked for peaks at.
    pub(super) peaks: Option<f32>,
}

impl PendingSolutions {
    /// The accepted faces once the map has completed; `None` while it has not.
    pub fn try_take(&self) -> Option<Result<SearchSolutions, npr_gpu::GpuError>> {
        Some(
            self.map
                .try_take()?
                .map(|b| decode(&b, self.capacity, self.peaks)),
        )
    }

    /// Blocks until the map has completed (native: polls `device`) and decodes the list.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::Readback`] when polling or mapping fails.
    pub fn wait(self, device: &wgpu::Device) -> Result<SearchSolutions, npr_gpu::GpuError> {
        let (capacity, peaks) = (self.capacity, self.peaks);
        Ok(decode(&self.map.wait(device)?, capacity, peaks))
    }
}

/// Entries of the solutions buffer: the list, `cs_merge`'s ranks and ordered copy, and
/// the merged list (`solutions` of `centre_search.wgsl`).
pub(super) fn solution_entries(capacity: usize) -> usize {
    3 * capacity + MAX_MERGED
}

/// Per visiting slot, its face and that face's place in the CPU's merge order (`order`
/// of `centre_search.wgsl`).
pub(super) fn slot_records(face_order: &[u32], ranks: &[u32]) -> Vec<[u32; 2]> {
    face_order
        .iter()
        .map(|&f| [f, ranks.get(f as usize).copied().unwrap_or(u32::MAX)])
        .collect()
}

/// The counters (accepted faces, clusters solved, centres merged, peaks), the `capacity`
/// accepted faces after the 16-byte header, then the [`MAX_MERGED`] centre records (those
/// the CPU would not have, `HighlightSearch::centre_at` giving none, left out): the
/// merged centres, then the peaks where the search `looked` for them.
pub(super) fn decode(bytes: &[u8], capacity: usize, looked: Option<f32>) -> SearchSolutions {
    let word = |i: usize| {
        bytes
            .get(4 * i..4 * i + 4)
            .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let accepted = word(0) as usize;
    let clusters_solved = word(1) as usize;
    let merged = word(2);
    let entry = |at: usize| FaceSolution {
        face: word(at),
        alpha: f32::from_bits(word(at + 1)),
        beta: f32::from_bits(word(at + 2)),
    };
    let faces = (0..accepted.min(capacity))
        .map(|k| entry(4 + 4 * k))
        .collect();
    let record = |k: usize| {
        let at = 16 + 16 * capacity + k * CENTRE_RECORD_BYTES;
        let r: CentreRecord =
            bytemuck::pod_read_unaligned(bytes.get(at..at + CENTRE_RECORD_BYTES)?);
        if r.position_object[3] != 1.0 {
            return None;
        }
        let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
        let (normal_world, dir_kappa_max) = (v(r.normal_world), v(r.dir_kappa_max));
        Some(HighlightCentre {
            face: r.solution[0],
            alpha: f32::from_bits(r.solution[1]),
            beta: f32::from_bits(r.solution[2]),
            position_object: v(r.position_object),
            position_world: v(r.position_world),
            normal_object: v(r.normal_object),
            normal_world,
            dir_kappa_max,
            dir_kappa_min: normal_world.cross(dir_kappa_max),
            kappa_max: r.curvature[0],
            kappa_min: r.curvature[1],
        })
    };
    let merged_ok = accepted <= capacity && merged != NO_MERGE && merged as usize <= MAX_MERGED;
    let centres = merged_ok.then(|| (0..merged as usize).filter_map(record).collect());
    let peaks = word(3);
    let (first, count) = (merged as usize, peaks as usize);
    let peaks = (looked.is_some() && merged_ok && peaks != NO_MERGE && count <= MAX_MERGED - first)
        .then(|| (first..first + count).filter_map(record).collect());
    SearchSolutions {
        faces,
        accepted,
        clusters_solved,
        centres,
        peaks,
        peak_sigma: looked,
    }
}
