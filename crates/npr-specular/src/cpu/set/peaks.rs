//! Highlights of bright regions that hold no `N = H` point (beyond the paper).
//!
//! §3.1 places a highlight at the maximum of the specular term, Eq. (2), and finds it
//! where `N = H`, Eq. (3). On a smooth closed surface the Gauss map reaches every
//! direction somewhere, but not inside every bright region: a limb, an ear or a panel
//! whose normals come within `arccos σ` of `H` without reaching it has a region
//! `N·H ≥ σ` whose maximum is below 1, and no `N = H` point to stylize it. On scanned
//! characters such regions are a large share of the light (on Spot, 13 % of the
//! `N·H ≥ σ` pixels over the fidelity views). Here each connected part of the vertices
//! with `N·H ≥ σ` that no `N = H` centre lies in gets one centre at its own maximum of
//! `N·H` (the vertex of largest specular term, Eq. (2)), whose region is then grown and
//! fitted like any other ([`crate::cpu::region`]).

use super::HighlightSet;
use glam::{Mat3, Mat4, Vec3};
use npr_geometry::{HighlightCentre, LightEye, Topology};

/// Per-vertex scratch of [`HighlightSet::peak_centres`], kept across frames: `N·H` of
/// the bright vertices and whether a part's fill has reached them (outside a call −2 and
/// false), the vertices reached and the fill's stack, so a frame costs the candidate
/// vertices, not the mesh; and each vertex's neighbours (the other corners of its faces,
/// `neighbours[offsets[v]..offsets[v + 1]]`), built once.
#[derive(Clone, Debug, Default)]
pub(super) struct PeakScratch {
    nh: Vec<f32>,
    visited: Vec<bool>,
    seen: Vec<u32>,
    stack: Vec<u32>,
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl PeakScratch {
    /// Clean scratch for `topo`, with its vertices' neighbours.
    fn new(topo: &Topology) -> Self {
        let nv = topo.vertex_count();
        let (offsets, neighbours) = vertex_neighbours(topo);
        Self {
            nh: vec![UNSET; nv],
            visited: vec![false; nv],
            offsets,
            neighbours,
            ..Self::default()
        }
    }
}

/// Each vertex's neighbours (the other corners of its faces, sorted, once each):
/// `neighbours[offsets[v]..offsets[v + 1]]`, the parts' adjacency here and in the GPU's
/// peaks (`cs_peaks`).
pub(crate) fn vertex_neighbours(topo: &Topology) -> (Vec<u32>, Vec<u32>) {
    let nv = topo.vertex_count();
    let mut offsets = Vec::with_capacity(nv + 1);
    let mut neighbours = Vec::new();
    offsets.push(0);
    for v in 0..nv {
        let start = neighbours.len();
        for &f in topo.vertex_faces(v) {
            let t = topo.triangles[f as usize];
            neighbours.extend(t.iter().copied().filter(|&u| u as usize != v));
        }
        neighbours[start..].sort_unstable();
        let mut end = start;
        for k in start..neighbours.len() {
            if k == start || neighbours[k] != neighbours[end - 1] {
                neighbours[end] = neighbours[k];
                end += 1;
            }
        }
        neighbours.truncate(end);
        offsets.push(end as u32);
    }
    (offsets, neighbours)
}

/// Not measured this frame (below every σ).
const UNSET: f32 = -2.0;

/// Visits the part of the bright vertices (`N·H ≥ σ`, sharing a face) that holds `start`,
/// marking each vertex reached; its lowest vertex and its brightest (the lowest index on
/// ties).
fn fill_part(sigma: f32, start: u32, s: &mut PeakScratch) -> (u32, u32) {
    let PeakScratch {
        nh,
        visited,
        seen,
        stack,
        offsets,
        neighbours,
    } = s;
    visited[start as usize] = true;
    seen.push(start);
    stack.clear();
    stack.push(start);
    let (mut low, mut best) = (start, start);
    while let Some(v) = stack.pop() {
        low = low.min(v);
        let (d, db) = (nh[v as usize], nh[best as usize]);
        if d > db || (d == db && v < best) {
            best = v;
        }
        let around = offsets[v as usize] as usize..offsets[v as usize + 1] as usize;
        for &u in &neighbours[around] {
            if !visited[u as usize] && nh[u as usize] >= sigma {
                visited[u as usize] = true;
                seen.push(u);
                stack.push(u);
            }
        }
    }
    (low, best)
}

impl HighlightSet {
    /// The centres of the bright regions without an `N = H` point (see the module docs),
    /// at σ (the global controls'), for `centres` found by the search this frame.
    pub(super) fn peak_centres(
        &mut self,
        centres: &[HighlightCentre],
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        let nv = self.topology.vertex_count();
        let normal_from_object = Mat3::from_mat4(world_from_object).inverse().transpose();
        if self.search.normals().len() != nv || !normal_from_object.is_finite() {
            return Vec::new();
        }
        let sigma = self.tuning.controls.sigma;
        let mut scratch = std::mem::take(&mut self.peak_scratch);
        if scratch.nh.len() != nv {
            scratch = PeakScratch::new(&self.topology);
        }
        let bright = self.bright_vertices(
            light_eye,
            world_from_object,
            normal_from_object,
            &mut scratch,
        );
        let topo = &self.topology;
        // The parts an `N = H` centre lies in (through its face's bright vertices) are
        // filled first: they need no peak.
        for c in centres {
            let Some(t) = topo.triangles.get(c.face as usize) else {
                continue;
            };
            for &v in t {
                if !scratch.visited[v as usize] && scratch.nh[v as usize] >= sigma {
                    fill_part(sigma, v, &mut scratch);
                }
            }
        }
        // Each other part's brightest vertex, the parts in order of their lowest vertex.
        let mut parts = Vec::new();
        for &v in &bright {
            if !scratch.visited[v as usize] {
                parts.push(fill_part(sigma, v, &mut scratch));
            }
        }
        parts.sort_unstable();
        let peaks = parts
            .iter()
            .filter_map(|&(_, best)| {
                self.centre_at_vertex(
                    best as usize,
                    light_eye,
                    world_from_object,
                    normal_from_object,
                )
            })
            .collect();
        // Leave the scratch clean for the next frame.
        for &v in &bright {
            scratch.nh[v as usize] = UNSET;
        }
        for &v in &scratch.seen {
            scratch.visited[v as usize] = false;
        }
        scratch.seen.clear();
        self.peak_scratch = scratch;
        peaks
    }

    /// The vertices with `N·H ≥ σ` (world space, `H` per vertex), in the clusters' order,
    /// among the search's candidates ([`npr_geometry::HighlightSearch::bright_candidates`]);
    /// their `N·H` into the scratch.
    fn bright_vertices(
        &self,
        light_eye: LightEye,
        world_from_object: Mat4,
        normal_from_object: Mat3,
        scratch: &mut PeakScratch,
    ) -> Vec<u32> {
        let sigma = self.tuning.controls.sigma;
        let normals = self.search.normals();
        let mut candidates = self
            .search
            .bright_candidates(light_eye, world_from_object, sigma);
        // Under a similarity the angle between N and H is the same in object space: test
        // there, without transforming each normal and position.
        let object = object_light_eye(light_eye, world_from_object);
        candidates.retain(|&v| {
            let v = v as usize;
            let (n, h) = match object {
                Some(le) => (
                    normals[v].normalize_or_zero(),
                    le.half_vector(self.topology.positions[v]),
                ),
                None => (
                    (normal_from_object * normals[v]).normalize_or_zero(),
                    light_eye.half_vector(
                        world_from_object.transform_point3(self.topology.positions[v]),
                    ),
                ),
            };
            let d = n.dot(h);
            let bright = d >= sigma && n != Vec3::ZERO && h != Vec3::ZERO;
            if bright {
                scratch.nh[v] = d;
            }
            bright
        });
        candidates
    }

    /// The centre of the part whose brightest vertex is `v`: the maximum of `N̂·Ĥ` over
    /// the faces around `v` (both interpolated linearly, as Eq. (4)–(5) interpolate
    /// them), so that it glides over the surface as the light moves instead of jumping
    /// from vertex to vertex, with the principal frame there.
    fn centre_at_vertex(
        &self,
        v: usize,
        light_eye: LightEye,
        world_from_object: Mat4,
        normal_from_object: Mat3,
    ) -> Option<HighlightCentre> {
        let topo = &self.topology;
        let normals = self.search.normals();
        let world = |i: u32| {
            let p = world_from_object.transform_point3(topo.positions[i as usize]);
            let n = (normal_from_object * normals[i as usize]).normalize_or_zero();
            (n, light_eye.half_vector(p))
        };
        let mut best: Option<(f32, u32, f32, f32)> = None;
        for &f in topo.vertex_faces(v) {
            if topo.is_degenerate(f as usize) {
                continue;
            }
            let t = topo.triangles[f as usize];
            let Some(corner) = t.iter().position(|&i| i as usize == v) else {
                continue;
            };
            let [(n0, h0), (n1, h1), (n2, h2)] = t.map(world);
            let value = |a: f32, b: f32| {
                let n = n0 + a * (n1 - n0) + b * (n2 - n0);
                let h = h0 + a * (h1 - h0) + b * (h2 - h0);
                n.normalize_or_zero().dot(h.normalize_or_zero())
            };
            let start = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)][corner];
            let (a, b, g) = ascend(value, start);
            if best.is_none_or(|(bg, ..)| g > bg) {
                best = Some((g, f, a, b));
            }
        }
        let (_, f, a, b) = best?;
        self.search.centre_at(f, a, b, world_from_object)
    }
}

/// The light and eye in object space where `world_from_object` is a similarity (angles
/// kept, so `N·H` is the same there); `None` otherwise.
fn object_light_eye(light_eye: LightEye, world_from_object: Mat4) -> Option<LightEye> {
    let m3 = Mat3::from_mat4(world_from_object);
    if !crate::cpu::visibility::is_similarity(m3, 1e-6) {
        return None;
    }
    let object_from_world = world_from_object.inverse();
    let le = match light_eye {
        LightEye::Directions { to_light, to_eye } => LightEye::Directions {
            to_light: m3.transpose() * to_light,
            to_eye: m3.transpose() * to_eye,
        },
        LightEye::Positions { light, eye } => LightEye::Positions {
            light: object_from_world.transform_point3(light),
            eye: object_from_world.transform_point3(eye),
        },
    };
    object_from_world.is_finite().then_some(le)
}

/// The barycentric point of a triangle (α, β ≥ 0, α + β ≤ 1) where `value` is largest,
/// by projected gradient ascent from `start` (central differences, step halved when it
/// does not climb), and the value there.
fn ascend(value: impl Fn(f32, f32) -> f32, start: (f32, f32)) -> (f32, f32, f32) {
    let project = |a: f32, b: f32| {
        let (a, b) = (a.max(0.0), b.max(0.0));
        let over = a + b - 1.0;
        if over > 0.0 {
            (
                (a - 0.5 * over).clamp(0.0, 1.0),
                (b - 0.5 * over).clamp(0.0, 1.0),
            )
        } else {
            (a, b)
        }
    };
    let (mut a, mut b) = start;
    let mut g = value(a, b);
    let mut step = 0.25f32;
    let e = 1e-3;
    for _ in 0..40 {
        let da = value(a + e, b) - value(a - e, b);
        let db = value(a, b + e) - value(a, b - e);
        let len = (da * da + db * db).sqrt();
        if len.is_nan() || len <= 1e-9 || step < 1e-4 {
            break;
        }
        let (na, nb) = project(a + step * da / len, b + step * db / len);
        let ng = value(na, nb);
        if ng > g {
            (a, b, g) = (na, nb, ng);
        } else {
            step *= 0.5;
        }
    }
    (a, b, g)
}
