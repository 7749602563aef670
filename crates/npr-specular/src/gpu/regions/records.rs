//! The region pass's GPU records (`regions.wgsl`, `region_frame.wgsl`) and their
//! decoding.

use super::GpuRegion;
use crate::HighlightSet;
use crate::cpu::region::{Footprint, MAX_PIECES, Region};
use glam::Vec2;

/// `RegionParams` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Params {
    pub(super) world_from_object: [[f32; 4]; 4],
    pub(super) normal_from_object: [[f32; 4]; 4],
    pub(super) light: [f32; 4],
    pub(super) eye: [f32; 4],
    pub(super) seed_count: u32,
    pub(super) face_count: u32,
    pub(super) words: u32,
    pub(super) capacity: u32,
    pub(super) track_room: u32,
    pub(super) track_sigma: f32,
    pub(super) pad: [u32; 2],
}

/// Bytes of `RegionParams`: the seeds follow them in `RegionFrameData`'s buffer.
pub(super) const PARAMS_BYTES: usize = std::mem::size_of::<Params>();

/// `RegionFrameData` of `regions.wgsl` with one seed: the frame's values and the seeds
/// in one storage buffer (see the shader for why not a uniform buffer).
#[cfg(test)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FrameData {
    pub(super) params: Params,
    pub(super) seeds: [SeedRecord; 1],
}

/// `Seed` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SeedRecord {
    pub(super) origin: [f32; 4],
    pub(super) n: [f32; 4],
    pub(super) e_u: [f32; 4],
    pub(super) e_v: [f32; 4],
    pub(super) start: [u32; 4],
}

/// `RegionVertex` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct VertexRecord {
    pub(crate) position: [f32; 4],
    pub(crate) normal: [f32; 4],
}

/// `RegionFace` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct FaceRecord {
    pub(crate) tri: [u32; 4],
    pub(crate) normal: [f32; 4],
}

/// `RegionPiece` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct PieceRecord {
    pub(super) ellipse: [f32; 4],
    pub(super) fit: [f32; 4],
}

/// `RegionFit` of `regions.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FitRecord {
    pub(super) moments: [f32; 4],
    pub(super) second: [f32; 4],
    pub(super) ellipse: [f32; 4],
    pub(super) fit: [f32; 4],
    pub(super) flags: [u32; 4],
    pub(super) piece_count: [u32; 4],
    pub(super) pieces: [PieceRecord; MAX_PIECES],
}

/// Bytes of one seed's `RegionFit`.
pub(super) const FIT_BYTES: usize = std::mem::size_of::<FitRecord>();

pub(super) const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC);

pub(crate) fn vertex_records(set: &HighlightSet) -> Vec<VertexRecord> {
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

pub(crate) fn face_records(set: &HighlightSet) -> Vec<FaceRecord> {
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

/// The seeds' `RegionFit` records.
pub(super) fn decode(bytes: &[u8], seeds: usize) -> Vec<GpuRegion> {
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
