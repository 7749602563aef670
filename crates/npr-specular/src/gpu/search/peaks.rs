//! The search's peaks on the GPU (`cs_bright`, `cs_join_bright`, `cs_part_best`,
//! `cs_part_brightest` and `cs_peaks` of `centre_search.wgsl`): the
//! bright regions `N·H ≥ σ` without an `N = H` point, each given a centre at its maximum
//! of `N̂·Ĥ` as `HighlightSet`'s update gives it (`set::peaks`), so that the frame's
//! regions can be seeded on the GPU with them.

use crate::HighlightSet;
use glam::{Mat3, Mat4};
use npr_geometry::LightEye;
use npr_gpu::compute::buffer_init;

/// The tables the peaks read and their scratch, for one mesh.
#[derive(Debug)]
pub(super) struct PeakTables {
    /// Per vertex its neighbours and its faces (`peak_adjacency` of the shader).
    pub(super) adjacency: wgpu::Buffer,
    /// `PeakScratch` of the shader: a header, per vertex `N·H`, its parent in the parts'
    /// union-find and its part's greatest `N·H` and brightest vertex, and the list of the
    /// parts' roots.
    pub(super) scratch: wgpu::Buffer,
    /// Welded vertices.
    pub(super) vertices: usize,
}

/// Parts of bright vertices a frame lists at most (one invocation reads the list; a
/// frame with more than [`crate::gpu::MAX_MERGED`] parts without a centre leaves its peaks to
/// the CPU anyway).
const LIST_ROOM: usize = 8192;

/// `set`'s vertex neighbours (the other corners of its faces, sorted, once each) and
/// faces (in `Topology::vertex_faces`'s order, each with its visiting slot and its
/// corner at the vertex), as `peak_adjacency` of the shader reads them: `nv + 1`
/// absolute offsets, the neighbours, `nv + 1` absolute offsets, the faces' pairs.
pub(super) fn adjacency_words(set: &HighlightSet, slot_of: &[u32]) -> Vec<u32> {
    let topo = set.topology();
    let nv = topo.vertex_count();
    let (offsets, neighbours) = crate::cpu::set::vertex_neighbours(topo);
    let mut faces: Vec<u32> = Vec::new();
    let mut face_offsets = Vec::with_capacity(nv + 1);
    for v in 0..nv {
        face_offsets.push(faces.len() as u32);
        for &f in topo.vertex_faces(v) {
            let t = topo.triangles[f as usize];
            let corner = t.iter().position(|&u| u as usize == v).unwrap_or(0) as u32;
            let slot = slot_of.get(f as usize).copied().unwrap_or(0) & 0x1fff_ffff;
            faces.extend([f, slot | (corner << 29)]);
        }
    }
    face_offsets.push(faces.len() as u32);
    let base = (nv + 1) as u32;
    let faces_base = base + neighbours.len() as u32 + base;
    let mut data: Vec<u32> = offsets.iter().map(|o| o + base).collect();
    data.extend(&neighbours);
    data.extend(face_offsets.iter().map(|o| o + faces_base));
    data.extend(&faces);
    data
}

/// Words of the scratch for `nv` vertices: the header, four per vertex, the list.
pub(super) fn scratch_words(nv: usize) -> usize {
    4 + 4 * nv + LIST_ROOM.min(nv.max(1))
}

impl PeakTables {
    /// The tables of `adjacency_words` and a scratch for `nv` vertices.
    pub(super) fn new(device: &wgpu::Device, adjacency: &[u32], nv: usize) -> Self {
        let mut scratch = vec![0u32; scratch_words(nv)];
        scratch[2] = LIST_ROOM.min(nv.max(1)) as u32;
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        Self {
            adjacency: buffer_init(device, "npr search peak adjacency", adjacency, usage),
            scratch: buffer_init(device, "npr search peak scratch", &scratch, usage),
            vertices: nv,
        }
    }

    /// Clears the frame's part of the scratch: the header's counts and the per-vertex
    /// words.
    pub(super) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.scratch, 0, Some(8));
        encoder.clear_buffer(&self.scratch, 16, Some((16 * self.vertices.max(1)) as u64));
    }
}

/// The peaks' parameters: σ, whether the transform is a similarity (then `N·H` is tested
/// in object space, with the light and eye there, as the CPU tests it), and the light
/// and eye in world and object space (w = 1 positions, w = 0 directions).
pub(super) struct PeakParams {
    pub(super) sigma: f32,
    pub(super) similar: u32,
    pub(super) light: [f32; 4],
    pub(super) eye: [f32; 4],
    pub(super) object_light: [f32; 4],
    pub(super) object_eye: [f32; 4],
}

/// The peaks' parameters for σ, this light, eye and transform (`object_light_eye` of
/// `set::peaks`).
pub(super) fn peak_params(sigma: f32, light_eye: LightEye, world_from_object: Mat4) -> PeakParams {
    let m3 = Mat3::from_mat4(world_from_object);
    let object_from_world = world_from_object.inverse();
    let similar = crate::cpu::visibility::is_similarity(m3, 1e-6) && object_from_world.is_finite();
    let (light, eye, object_light, object_eye) = match light_eye {
        LightEye::Directions { to_light, to_eye } => (
            to_light.extend(0.0),
            to_eye.extend(0.0),
            (m3.transpose() * to_light).extend(0.0),
            (m3.transpose() * to_eye).extend(0.0),
        ),
        LightEye::Positions { light, eye } => (
            light.extend(1.0),
            eye.extend(1.0),
            object_from_world.transform_point3(light).extend(1.0),
            object_from_world.transform_point3(eye).extend(1.0),
        ),
    };
    PeakParams {
        sigma,
        similar: u32::from(similar),
        light: light.to_array(),
        eye: eye.to_array(),
        object_light: object_light.to_array(),
        object_eye: object_eye.to_array(),
    }
}

/// `PeakScratch` of `centre_search.wgsl` with one word of data: its header.
#[cfg(test)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ScratchLayout {
    pub(super) listed: u32,
    pub(super) overflowed: u32,
    pub(super) list_room: u32,
    pub(super) pad: u32,
    pub(super) data: [u32; 1],
}
