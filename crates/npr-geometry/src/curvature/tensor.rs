//! The curvature tensor of Eq. (1) at one vertex: the ball grown over face adjacency,
//! the per-face and per-edge tensors it sums, and the clipped edge lengths and areas of
//! the clipped form. The corrected form's loop is the hot one, over packed face records.

use std::cell::RefCell;

use glam::{DVec3, Vec3};
use nalgebra::Matrix3;
use rayon::prelude::*;

use super::eigen::{full_axes, tangent_axes};
use super::{CurvatureMethod, PrincipalAxes, invalid};
use crate::topology::{NO_EDGE, Topology};
/// Per-face data for the hot loop, packed for cache: centroid, bounding radius, area,
/// and the face's share of edge tensor `T_f` (xx, xy, xz, yy, yz, zz).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FaceData {
    c: [f32; 3],
    rad: f32,
    area: f32,
    t: [f32; 6],
}

/// One face of the corrected form's hot loop, in one 64-byte cache line: bounding
/// sphere (centroid, radius), the weights `T_f` (xx, xy, xz, yy | yz, zz) and area
/// `A_f`, and the face's neighbours across its edges, in [`Topology::face_neighbours`]
/// order. A face with fewer than three neighbours (a boundary) pads with itself, which
/// the walk has always marked already; `many` is set where it has more than three
/// (a non-manifold edge), and the walk then reads [`Topology::face_neighbours`].
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct FaceRec {
    sphere: [f32; 4],
    t0: glam::Vec4,
    t1: glam::Vec4,
    adj: [u32; 3],
    many: u32,
}

/// The corrected form's per-face records ([`FaceRec`]), indexed by face.
pub(super) struct Packed {
    faces: Vec<FaceRec>,
}

impl Packed {
    pub(super) fn build(topo: &Topology) -> Self {
        let totals = edge_area_totals(topo);
        let faces = topo
            .triangles
            .par_iter()
            .enumerate()
            .map(|(f, t)| {
                let d = face_record(topo, f, t, &totals);
                let nb = topo.face_neighbours(f);
                let mut adj = [f as u32; 3];
                for (a, &g) in adj.iter_mut().zip(nb) {
                    *a = g;
                }
                FaceRec {
                    sphere: [d.c[0], d.c[1], d.c[2], d.rad],
                    t0: glam::Vec4::new(d.t[0], d.t[1], d.t[2], d.t[3]),
                    t1: glam::Vec4::new(d.t[4], d.t[5], d.area, 0.0),
                    adj,
                    many: u32::from(nb.len() > 3),
                }
            })
            .collect();
        Self { faces }
    }
}

pub(super) struct Scratch {
    face_mark: Vec<u32>,
    edge_mark: Vec<u32>,
    stamp: u32,
    stack: Vec<u32>,
}

thread_local! {
    // Reused visit marks (stamp-based, never cleared per vertex) and the DFS stack.
    pub(super) static SCRATCH: RefCell<Scratch> =
        const { RefCell::new(Scratch { face_mark: Vec::new(), edge_mark: Vec::new(), stamp: 0, stack: Vec::new() }) };
}

fn sym6(d: DVec3, s: f64) -> [f64; 6] {
    [
        s * d.x * d.x,
        s * d.x * d.y,
        s * d.x * d.z,
        s * d.y * d.y,
        s * d.y * d.z,
        s * d.z * d.z,
    ]
}

/// β(e) |e| ē ēᵀ per edge (= β d dᵀ / |d| with d the edge vector).
pub(super) fn edge_tensors(topo: &Topology) -> Vec<[f64; 6]> {
    topo.edges
        .iter()
        .zip(&topo.dihedral)
        .map(|(&[a, b], &beta)| {
            let d = topo.positions[b as usize].as_dvec3() - topo.positions[a as usize].as_dvec3();
            let l = d.length();
            if l > 0.0 && beta != 0.0 {
                sym6(d, f64::from(beta) / l)
            } else {
                [0.0; 6]
            }
        })
        .collect()
}

/// Centroid, bounding radius and area per face, for the paper's and the clipped forms.
pub(super) fn face_data(topo: &Topology) -> Vec<FaceData> {
    topo.triangles
        .par_iter()
        .enumerate()
        .map(|(f, t)| face_record(topo, f, t, &[]))
        .collect()
}

/// Each edge's area total `Σ_g A_g` over its faces (f64, in edge-face order), the
/// denominator of the corrected form's shares; 0 where the edge has no dihedral angle
/// (no share is taken there).
fn edge_area_totals(topo: &Topology) -> Vec<f64> {
    const CHUNK: usize = 4096;
    let mut totals = vec![0f64; topo.edges.len()];
    totals
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            for (i, t) in out.iter_mut().enumerate() {
                let e = c * CHUNK + i;
                if topo.dihedral[e] != 0.0 {
                    let mut s = 0f64;
                    for &g in topo.edge_faces(e) {
                        s += f64::from(topo.face_areas[g as usize]);
                    }
                    *t = s;
                }
            }
        });
    totals
}

/// Centroid, bounding radius, area and the corrected form's `T_f` of one face, given each
/// edge's area total ([`edge_area_totals`]; empty: `T_f` is left zero).
fn face_record(topo: &Topology, f: usize, t: &[u32; 3], totals: &[f64]) -> FaceData {
    if t.iter().any(|&i| i as usize >= topo.positions.len()) {
        return FaceData {
            c: [f32::INFINITY; 3],
            ..FaceData::default()
        };
    }
    let p = t.map(|i| topo.positions[i as usize].as_dvec3());
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let rad = p.iter().map(|q| (*q - c).length()).fold(0.0, f64::max);
    let area = f64::from(topo.face_areas[f]);
    let mut tf = [0f64; 6];
    if !totals.is_empty() && area > 0.0 {
        for k in 0..3 {
            let e = topo.face_edges[f][k];
            if e == NO_EDGE {
                continue;
            }
            let beta = f64::from(topo.dihedral[e as usize]);
            if beta == 0.0 {
                continue;
            }
            let share = area / totals[e as usize];
            let d = p[(k + 1) % 3] - p[k];
            let s = sym6(d, share * beta / d.length());
            for (a, b) in tf.iter_mut().zip(s) {
                *a += b;
            }
        }
    }
    FaceData {
        c: c.as_vec3().to_array(),
        rad: rad as f32,
        area: area as f32,
        t: tf.map(|x| x as f32),
    }
}

/// Restarts the visit marks for a new vertex; returns the stamp for this vertex.
fn next_stamp(s: &mut Scratch, nf: usize, ne: usize) -> u32 {
    if s.face_mark.len() != nf {
        s.face_mark.clear();
        s.face_mark.resize(nf, 0);
        s.stamp = 0;
    }
    if s.edge_mark.len() != ne {
        s.edge_mark.clear();
        s.edge_mark.resize(ne, 0);
        s.stamp = 0;
    }
    s.stamp = s.stamp.wrapping_add(1);
    if s.stamp == 0 {
        s.face_mark.fill(0);
        s.edge_mark.fill(0);
        s.stamp = 1;
    }
    s.stamp
}

/// The corrected form's hot loop: `Σ w_f T_f` and `Σ w_f A_f` over the faces whose
/// centroid lies in the ball, grown from the vertex's faces over face adjacency.
///
/// The depth-first stack is a preallocated slice indexed by hand (a face is pushed at
/// most once per vertex, so it never outgrows the face count): no growth check or
/// reallocation call in the loop, so the accumulators and pointers stay in registers.
pub(super) fn corrected_axes(
    topo: &Topology,
    p: &Packed,
    v: usize,
    r: f32,
    s: &mut Scratch,
) -> PrincipalAxes {
    let stamp = next_stamp(s, p.faces.len(), 0);
    let own = topo.vertex_faces(v);
    let Scratch {
        face_mark, stack, ..
    } = s;
    let need = face_mark.len() + own.len();
    if stack.len() < need {
        stack.resize(need, 0);
    }
    let (face_mark, stack) = (face_mark.as_mut_slice(), stack.as_mut_slice());
    let pv = topo.positions[v];
    let r2 = r * r;
    let inv_r2 = 1.0 / r2;
    // Two SIMD accumulators: (xx, xy, xz, yy) and (yz, zz, area, 0).
    let (mut acc0, mut acc1) = (glam::Vec4::ZERO, glam::Vec4::ZERO);
    let mut top = 0;
    for &f in own {
        face_mark[f as usize] = stamp;
        stack[top] = f;
        top += 1;
    }
    while top > 0 {
        top -= 1;
        let f = stack[top] as usize;
        let rec = &p.faces[f];
        let [cx, cy, cz, rad] = rec.sphere;
        let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
        let d2 = dx * dx + dy * dy + dz * dz;
        if d2 < r2 {
            let q = 1.0 - d2 * inv_r2;
            let w = q * q;
            acc0 += w * rec.t0;
            acc1 += w * rec.t1;
        } else {
            // Outside: pass the ball on only if the face is large against the ball and
            // its bounding sphere reaches in (small faces outside have no inside
            // neighbour the ring does not already reach).
            let reach = r + rad;
            if !(rad > 0.5 * r && d2 < reach * reach) {
                continue;
            }
        }
        let nb = if rec.many == 0 {
            &rec.adj[..]
        } else {
            topo.face_neighbours(f)
        };
        for &g in nb {
            let m = &mut face_mark[g as usize];
            if *m != stamp {
                *m = stamp;
                stack[top] = g;
                top += 1;
            }
        }
    }
    let area = f64::from(acc1.z);
    let mesh_n = topo.vertex_normals[v];
    if !(area > 0.0) || !acc0.is_finite() || !acc1.is_finite() {
        return invalid(mesh_n);
    }
    let acc = [acc0.x, acc0.y, acc0.z, acc0.w, acc1.x, acc1.y];
    let t = acc.map(|x| f64::from(x) / area);
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
    tangent_axes(&m, mesh_n.as_dvec3()).unwrap_or_else(|| invalid(mesh_n))
}

/// Every face the corrected form's walk ([`corrected_axes`]) pops at vertex `v`, in the
/// order it pops them, appended to `out`: the same stack, the same pass-on test, no sums.
/// The faces with their centroid in the ball are among them (those carry weight); the
/// others are the ring around the ball that the walk looked at and let go.
pub(super) fn corrected_walk(
    topo: &Topology,
    p: &Packed,
    v: usize,
    r: f32,
    s: &mut Scratch,
    out: &mut Vec<u32>,
) {
    let stamp = next_stamp(s, p.faces.len(), 0);
    let Scratch {
        face_mark, stack, ..
    } = s;
    stack.clear();
    let pv = topo.positions[v];
    let r2 = r * r;
    for &f in topo.vertex_faces(v) {
        face_mark[f as usize] = stamp;
        stack.push(f);
    }
    while let Some(f) = stack.pop() {
        out.push(f);
        let f = f as usize;
        let rec = &p.faces[f];
        let [cx, cy, cz, rad] = rec.sphere;
        let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
        let d2 = dx * dx + dy * dy + dz * dz;
        if !(d2 < r2) {
            let reach = r + rad;
            if !(rad > 0.5 * r && d2 < reach * reach) {
                continue;
            }
        }
        for &g in topo.face_neighbours(f) {
            let m = &mut face_mark[g as usize];
            if *m != stamp {
                *m = stamp;
                stack.push(g);
            }
        }
    }
}

/// The paper's and the clipped-edge forms of Eq. (1) at vertex `v` (the corrected form,
/// the default, has its own loop: [`corrected_axes`]; `compute` never sends it here, and
/// a `Corrected` that did arrive is treated as the clipped form).
pub(super) fn vertex_axes(
    topo: &Topology,
    faces: &[FaceData],
    edge_t: &[[f64; 6]],
    v: usize,
    r: f32,
    method: CurvatureMethod,
    s: &mut Scratch,
) -> PrincipalAxes {
    let stamp = next_stamp(s, faces.len(), edge_t.len());
    let pv = topo.positions[v];
    let r2 = r * r;
    let mesh_n = topo.vertex_normals[v];
    let mut acc = [0f64; 6];
    let mut area = 0f64;
    s.stack.clear();
    for &f in topo.vertex_faces(v) {
        s.face_mark[f as usize] = stamp;
        s.stack.push(f);
    }
    while let Some(f) = s.stack.pop() {
        let fd = &faces[f as usize];
        let d = Vec3::from_array(fd.c) - pv;
        let d2 = d.length_squared();
        // Paper / clipped: pass the ball on through every face that can touch it.
        let reach = r + fd.rad;
        if !(d2 < reach * reach) {
            continue;
        }
        match method {
            CurvatureMethod::Paper => {
                let t = topo.triangles[f as usize];
                let inside = t
                    .iter()
                    .any(|&i| (topo.positions[i as usize] - pv).length_squared() < r2);
                if inside {
                    area += f64::from(fd.area);
                    for &e in &topo.face_edges[f as usize] {
                        if e != NO_EDGE && s.edge_mark[e as usize] != stamp {
                            s.edge_mark[e as usize] = stamp;
                            for (a, t) in acc.iter_mut().zip(edge_t[e as usize]) {
                                *a += t;
                            }
                        }
                    }
                }
            }
            CurvatureMethod::Clipped | CurvatureMethod::Corrected => {
                let t = topo.triangles[f as usize];
                let p = t.map(|i| topo.positions[i as usize].as_dvec3());
                area += clipped_area(p, pv.as_dvec3(), f64::from(r), 3);
                for &e in &topo.face_edges[f as usize] {
                    if e != NO_EDGE && s.edge_mark[e as usize] != stamp {
                        s.edge_mark[e as usize] = stamp;
                        let [a, b] = topo.edges[e as usize];
                        let frac = clipped_fraction(
                            topo.positions[a as usize].as_dvec3(),
                            topo.positions[b as usize].as_dvec3(),
                            pv.as_dvec3(),
                            f64::from(r),
                        );
                        for (a, t) in acc.iter_mut().zip(edge_t[e as usize]) {
                            *a += frac * t;
                        }
                    }
                }
            }
        }
        for &g in topo.face_neighbours(f as usize) {
            if s.face_mark[g as usize] != stamp {
                s.face_mark[g as usize] = stamp;
                s.stack.push(g);
            }
        }
    }
    if !(area > 0.0) || !acc.iter().all(|x| x.is_finite()) {
        return invalid(mesh_n);
    }
    let t = acc.map(|x| x / area);
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
    full_axes(&m, mesh_n.as_dvec3()).unwrap_or_else(|| invalid(mesh_n))
}

/// Fraction of segment [a, b] inside the ball (centre c, radius r), exact.
fn clipped_fraction(a: DVec3, b: DVec3, c: DVec3, r: f64) -> f64 {
    let d = b - a;
    let dd = d.length_squared();
    if dd == 0.0 {
        return 0.0;
    }
    let f = a - c;
    let bq = f.dot(d) / dd;
    let cq = (f.length_squared() - r * r) / dd;
    let disc = bq * bq - cq;
    if disc <= 0.0 {
        return 0.0;
    }
    let s = disc.sqrt();
    let (t0, t1) = ((-bq - s).max(0.0), (-bq + s).min(1.0));
    (t1 - t0).max(0.0)
}

/// Area of triangle ∩ ball by recursive 1→4 subdivision (`depth` levels), whole
/// sub-triangles accepted or rejected when they lie entirely inside or outside.
fn clipped_area(p: [DVec3; 3], c: DVec3, r: f64, depth: u32) -> f64 {
    let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    let inside = p.iter().all(|q| (*q - c).length_squared() <= r * r);
    if inside {
        return area;
    }
    let cen = (p[0] + p[1] + p[2]) / 3.0;
    let rad = p.iter().map(|q| (*q - cen).length()).fold(0.0, f64::max);
    if (cen - c).length() >= r + rad {
        return 0.0;
    }
    if depth == 0 {
        return if (cen - c).length_squared() < r * r {
            area
        } else {
            0.0
        };
    }
    let m = [
        (p[0] + p[1]) / 2.0,
        (p[1] + p[2]) / 2.0,
        (p[2] + p[0]) / 2.0,
    ];
    clipped_area([p[0], m[0], m[2]], c, r, depth - 1)
        + clipped_area([m[0], p[1], m[1]], c, r, depth - 1)
        + clipped_area([m[2], m[1], p[2]], c, r, depth - 1)
        + clipped_area([m[0], m[1], m[2]], c, r, depth - 1)
}
