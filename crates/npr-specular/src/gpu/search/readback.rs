//! A search's lists on their way back: the readback's layout and its decoding.

use super::{MAX_MERGED, NO_MERGE, SearchSolutions};
use npr_geometry::FaceSolution;

/// `CentreRecord` of `centre_search.wgsl`: one centre `cs_centres` computed.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct CentreRecord {
    /// w: 1 where the CPU has a centre there, 0 where not.
    pub(crate) position_object: [f32; 4],
    pub(crate) position_world: [f32; 4],
    pub(crate) normal_object: [f32; 4],
    pub(crate) normal_world: [f32; 4],
    pub(crate) dir_kappa_max: [f32; 4],
    /// (κmax, κmin, 1 for a peak, 0).
    pub(crate) curvature: [f32; 4],
    /// (face, α and β as bits, the face's visiting slot).
    pub(crate) solution: [u32; 4],
}

impl CentreRecord {
    /// The record of a CPU centre (`peak`: a bright region's, `set::peaks`); the visiting
    /// slot is left 0 (only the search reads it).
    pub(crate) fn of(c: &npr_geometry::HighlightCentre, peak: bool) -> Self {
        Self {
            position_object: c.position_object.extend(1.0).to_array(),
            position_world: c.position_world.extend(1.0).to_array(),
            normal_object: c.normal_object.extend(0.0).to_array(),
            normal_world: c.normal_world.extend(0.0).to_array(),
            dir_kappa_max: c.dir_kappa_max.extend(0.0).to_array(),
            curvature: [c.kappa_max, c.kappa_min, f32::from(u8::from(peak)), 0.0],
            solution: [c.face, c.alpha.to_bits(), c.beta.to_bits(), 0],
        }
    }

    /// The centre it records.
    pub(crate) fn centre(&self) -> npr_geometry::HighlightCentre {
        let v = |a: [f32; 4]| glam::Vec3::new(a[0], a[1], a[2]);
        npr_geometry::HighlightCentre {
            face: self.solution[0],
            alpha: f32::from_bits(self.solution[1]),
            beta: f32::from_bits(self.solution[2]),
            position_object: v(self.position_object),
            position_world: v(self.position_world),
            normal_object: v(self.normal_object),
            normal_world: v(self.normal_world),
            dir_kappa_max: v(self.dir_kappa_max),
            dir_kappa_min: v(self.normal_world).cross(v(self.dir_kappa_max)),
            kappa_max: self.curvature[0],
            kappa_min: self.curvature[1],
        }
    }
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
        Some(r.centre())
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
