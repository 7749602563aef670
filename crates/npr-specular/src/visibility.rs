//! Receiver faces of a projector, §4.2 of the specular paper: a triangle receives the
//! highlight only if it is reachable by breadth-first search from the triangle holding
//! the centre, lies at least partly inside the projector's frustum, and its face normal
//! satisfies `N·N_max > 0`.
//!
//! The paper names this search its bottleneck. Here it costs time proportional to the
//! region it visits: visited marks are generation-stamped in a reused buffer (no clearing
//! per search), and the frontier never leaves the accepted faces.

use crate::Projector;
use glam::{Mat3, Mat4, Vec3};
use npr_geometry::Topology;
use std::collections::VecDeque;

/// Reusable scratch space for [`receivers`]; keep one per mesh.
#[derive(Clone, Debug, Default)]
pub struct VisibilityScratch {
    stamp: Vec<u32>,
    generation: u32,
    queue: VecDeque<u32>,
    /// Per-vertex cache of projector coordinates, valid where `vertex_stamp` equals the
    /// current generation (a vertex is shared by about six faces).
    vertex_stamp: Vec<u32>,
    vertex_ndc: Vec<Vec3>,
}

impl VisibilityScratch {
    fn begin(&mut self, faces: usize, vertices: usize) -> u32 {
        if self.stamp.len() != faces || self.vertex_stamp.len() != vertices {
            self.stamp = vec![0; faces];
            self.vertex_stamp = vec![0; vertices];
            self.vertex_ndc = vec![Vec3::ZERO; vertices];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.fill(0);
            self.vertex_stamp.fill(0);
            self.generation = 1;
        }
        self.queue.clear();
        self.generation
    }
}

/// Whether the triangle with projector coordinates `q` can overlap the box
/// `lo..hi` (the frustum is x, y in [−1, 1], z in [0, 1]): false only when all three
/// vertices lie outside the same face of the box (a conservative separating-plane test:
/// the triangle's bounding box misses the box along some axis).
fn overlaps_box(q: [Vec3; 3], lo: Vec3, hi: Vec3) -> bool {
    // A triangle with a non-finite coordinate (a vertex at the projector's plane at
    // infinity, or bad data) is not received.
    if !(q[0].is_finite() && q[1].is_finite() && q[2].is_finite()) {
        return false;
    }
    let q_lo = q[0].min(q[1]).min(q[2]);
    let q_hi = q[0].max(q[1]).max(q[2]);
    q_hi.cmpge(lo).all() && q_lo.cmple(hi).all()
}

const FRUSTUM_LO: Vec3 = Vec3::new(-1.0, -1.0, 0.0);
const FRUSTUM_HI: Vec3 = Vec3::new(1.0, 1.0, 1.0);

fn overlaps_frustum(q: [Vec3; 3]) -> bool {
    overlaps_box(q, FRUSTUM_LO, FRUSTUM_HI)
}

/// Appends to `out` every receiver face of `projector` (§4.2), searching from
/// `start_face` over `topology`'s face adjacency, for the object placed by
/// `world_from_object`. Degenerate faces are skipped (never received, never crossed).
/// Returns the number of faces appended.
pub fn receivers(
    topology: &Topology,
    world_from_object: Mat4,
    projector: &Projector,
    start_face: u32,
    scratch: &mut VisibilityScratch,
    out: &mut Vec<u32>,
) -> usize {
    receivers_within(
        topology,
        world_from_object,
        projector,
        start_face,
        0.0,
        scratch,
        out,
    )
}

/// [`receivers`] limited by the normal cone as well (beyond the paper): a face is crossed
/// and received only when its world normal makes `cos > min_cos` with the projector's
/// axis, so the projected texture stretches at most `1/min_cos` on any receiver and the
/// search does not wrap onto another limb. `min_cos = 0` is §4.2's `N·N_max > 0`.
pub fn receivers_within(
    topology: &Topology,
    world_from_object: Mat4,
    projector: &Projector,
    start_face: u32,
    min_cos: f32,
    scratch: &mut VisibilityScratch,
    out: &mut Vec<u32>,
) -> usize {
    let faces = topology.face_count();
    if start_face as usize >= faces {
        return 0;
    }
    let generation = scratch.begin(faces, topology.vertex_count());
    // N_world · N_max = (M⁻ᵀ n) · N_max = n · (M⁻¹ N_max): test in object space.
    let linear = Mat3::from_mat4(world_from_object);
    let n_max_object = linear.inverse() * projector.normal;
    let normal_from_object = linear.inverse().transpose();
    let ndc_from_object = projector.clip_from_world * world_from_object;
    if !n_max_object.is_finite() || !ndc_from_object.is_finite() {
        return 0;
    }
    // The projector is orthographic (Eq. (7)): an affine map needs no division by w.
    let affine = ndc_from_object.row(3) == glam::Vec4::W;
    // |M⁻ᵀ n| for a unit face normal n is the same for every face under a similarity
    // (rotation, uniform scale, translation): the facing test's right side is constant.
    let cols = [
        normal_from_object.x_axis,
        normal_from_object.y_axis,
        normal_from_object.z_axis,
    ];
    let k = cols[0].length();
    let similar = cols.iter().all(|c| (c.length() - k).abs() <= 1e-6 * k)
        && cols[0].dot(cols[1]).abs() <= 1e-6 * k * k
        && cols[1].dot(cols[2]).abs() <= 1e-6 * k * k
        && cols[2].dot(cols[0]).abs() <= 1e-6 * k * k;
    let facing_floor = similar.then_some(min_cos * k);
    let before = out.len();
    // A translated projector (§3.4) may not cover the centre's own face: the walk
    // crosses the box spanning both the frustum and the untranslated centre, and only
    // faces touching the frustum itself are received.
    let anchor = projector.ndc(projector.anchor_world);
    let walk_lo = FRUSTUM_LO.min(anchor.with_z(0.0));
    let walk_hi = FRUSTUM_HI.max(anchor.with_z(1.0));
    // `None`: not crossed; `Some(received)`: crossed, and received or not.
    let VisibilityScratch {
        stamp,
        queue,
        vertex_stamp,
        vertex_ndc,
        ..
    } = scratch;
    let mut visit = |f: usize| -> Option<bool> {
        // cos = (M⁻ᵀ n)·N_max / |M⁻ᵀ n| = n·(M⁻¹ N_max) / |M⁻ᵀ n|.
        let n = topology.face_normals[f];
        let facing = if min_cos > 0.0 {
            let floor = facing_floor.unwrap_or_else(|| min_cos * (normal_from_object * n).length());
            n.dot(n_max_object) > floor
        } else {
            n.dot(n_max_object) > 0.0 // false for NaN
        };
        if topology.is_degenerate(f) || !facing {
            return None;
        }
        let t = topology.triangles[f];
        let mut q = [Vec3::ZERO; 3];
        for (qk, &v) in q.iter_mut().zip(&t) {
            let v = v as usize;
            if vertex_stamp[v] != generation {
                vertex_stamp[v] = generation;
                let p = topology.positions[v];
                vertex_ndc[v] = if affine {
                    ndc_from_object.transform_point3(p)
                } else {
                    ndc_from_object.project_point3(p)
                };
            }
            *qk = vertex_ndc[v];
        }
        overlaps_box(q, walk_lo, walk_hi).then(|| overlaps_frustum(q))
    };
    stamp[start_face as usize] = generation;
    match visit(start_face as usize) {
        None => return 0,
        Some(received) => {
            if received {
                out.push(start_face);
            }
            queue.push_back(start_face);
        }
    }
    while let Some(f) = queue.pop_front() {
        for &g in topology.face_neighbours(f as usize) {
            let gi = g as usize;
            if stamp[gi] == generation {
                continue;
            }
            stamp[gi] = generation;
            if let Some(received) = visit(gi) {
                if received {
                    out.push(g);
                }
                queue.push_back(g);
            }
        }
    }
    out.len() - before
}

/// The frustum overlap test alone, for tests and tools: whether a world-space triangle
/// can touch the projector's frustum.
pub fn triangle_touches_frustum(projector: &Projector, tri_world: [Vec3; 3]) -> bool {
    overlaps_frustum(tri_world.map(|p| projector.ndc(p)))
}
