//! Building a [`Topology`]: face normals and areas, vertex → faces, the edges found per
//! vertex chunk in parallel with their faces and dihedral angles, each face corner's
//! edge and face adjacency, all in compressed sparse rows.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::{NO_EDGE, Topology};
use crate::Welded;

impl Topology {
    /// Builds the topology of a welded mesh.
    pub fn new(welded: &Welded) -> Self {
        Self::from_parts(welded.positions.clone(), welded.indices.clone())
    }

    /// Builds the topology from welded positions and triangles.
    pub fn from_parts(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        let nv = positions.len();

        // Face normals and areas (f64 cross products, in parallel) while one thread
        // builds vertex → faces (a serial counting sort); neither needs the other.
        let ((face_normals, face_areas), (vertex_face_offsets, vertex_faces)): (
            (Vec<Vec3>, Vec<f32>),
            _,
        ) = rayon::join(
            || {
                triangles
                    .par_iter()
                    .map(|t| face_normal_area(t, &positions))
                    .unzip()
            },
            || vertex_face_csr(&triangles, nv),
        );
        let ctx = EdgeCtx {
            positions: &positions,
            triangles: &triangles,
            face_normals: &face_normals,
            face_areas: &face_areas,
            vertex_face_offsets: &vertex_face_offsets,
            vertex_faces: &vertex_faces,
        };
        let found = ctx.edges();
        let (face_edges, counts, mean_edge_length) = found.corner_edges(&triangles);
        let (face_adj_offsets, face_adj) = face_adjacency(
            &face_edges,
            counts,
            &found.edge_face_offsets,
            &found.edge_faces,
        );
        let Edges {
            vertex_normals,
            edges,
            edge_face_offsets,
            edge_faces,
            dihedral,
            ..
        } = found;

        Self {
            positions,
            triangles,
            face_normals,
            face_areas,
            edges,
            face_edges,
            dihedral,
            vertex_normals,
            mean_edge_length,
            edge_face_offsets,
            edge_faces,
            vertex_face_offsets,
            vertex_faces,
            face_adj_offsets,
            face_adj,
        }
    }
}

/// The edges of a mesh and what is found with them ([`EdgeCtx::edges`]).
struct Edges {
    /// Area-weighted unit vertex normals.
    vertex_normals: Vec<Vec3>,
    /// Each vertex's first edge, then the edge count.
    vertex_edges: Vec<u32>,
    edges: Vec<[u32; 2]>,
    edge_face_offsets: Vec<u32>,
    edge_faces: Vec<u32>,
    dihedral: Vec<f32>,
    /// The chunks the edges were found in (their lengths are summed from them).
    parts: Vec<EdgeChunk>,
}

impl EdgeCtx<'_> {
    /// The edges and vertex normals, found per vertex chunk in parallel and joined.
    fn edges(&self) -> Edges {
        let nv = self.positions.len();
        // Per vertex chunk, in parallel: the area-weighted vertex normals, and the edges
        // whose smaller vertex is in the chunk, found from each vertex's faces (each
        // vertex's half-edges to larger vertices, sorted by that vertex and face corner,
        // equal runs grouped into edges) with their faces, dihedral angles and lengths.
        let chunks = 64.min(nv.max(1));
        let bounds: Vec<(usize, usize)> = (0..chunks)
            .map(|c| (nv * c / chunks, nv * (c + 1) / chunks))
            .collect();
        let mut vertex_normals = vec![Vec3::ZERO; nv];
        // Each vertex's first edge (chunk-local until the chunks are joined), then `ne`.
        let mut vertex_edges = vec![0u32; nv + 1];
        let parts: Vec<EdgeChunk> = {
            let lens = bounds.iter().map(|&(s, e)| e - s);
            split_lens(&mut vertex_normals, lens.clone())
                .into_iter()
                .zip(split_lens(&mut vertex_edges[..nv], lens))
                .zip(&bounds)
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(|((vn, ve), &(sv, ev))| self.chunk(sv, ev, vn, ve))
                .collect()
        };
        let ne: usize = parts.iter().map(|c| c.edges.len()).sum();
        let nh: usize = parts.iter().map(|c| c.edge_faces.len()).sum();
        vertex_edges[nv] = ne as u32;
        // Join the chunks' lists in parallel, each chunk copying into its own slices.
        let mut edges = vec![[0u32; 2]; ne];
        let mut edge_face_offsets = vec![0u32; ne + 1];
        let mut edge_faces = vec![0u32; nh];
        let mut dihedral = vec![0f32; ne];
        {
            let e_lens = parts.iter().map(|c| c.edges.len());
            let h_lens = parts.iter().map(|c| c.edge_faces.len());
            let v_lens = bounds.iter().map(|&(s, e)| e - s);
            let mut e_base = 0u32;
            let mut h_base = 0u32;
            let bases: Vec<(u32, u32)> = parts
                .iter()
                .map(|c| {
                    let b = (e_base, h_base);
                    e_base += c.edges.len() as u32;
                    h_base += c.edge_faces.len() as u32;
                    b
                })
                .collect();
            split_lens(&mut edges, e_lens.clone())
                .into_iter()
                .zip(split_lens(&mut edge_face_offsets[1..], e_lens.clone()))
                .zip(split_lens(&mut edge_faces, h_lens))
                .zip(split_lens(&mut dihedral, e_lens))
                .zip(split_lens(&mut vertex_edges[..nv], v_lens))
                .zip(parts.iter().zip(bases))
                .collect::<Vec<_>>()
                .into_par_iter()
                .for_each(|(((((e, o), h), d), ve), (part, (eb, hb)))| {
                    e.copy_from_slice(&part.edges);
                    for (o, &end) in o.iter_mut().zip(&part.ends) {
                        *o = end + hb;
                    }
                    h.copy_from_slice(&part.edge_faces);
                    d.copy_from_slice(&part.dihedral);
                    for x in ve {
                        *x += eb;
                    }
                });
        }

        Edges {
            vertex_normals,
            vertex_edges,
            edges,
            edge_face_offsets,
            edge_faces,
            dihedral,
            parts,
        }
    }
}

impl Edges {
    /// Each face corner's edge and each face's neighbour count, and the mean length of
    /// the edges with finite length (0 without any).
    fn corner_edges(&self, triangles: &[[u32; 3]]) -> (Vec<[u32; 3]>, Vec<u32>, f32) {
        let nv = self.vertex_edges.len() - 1;
        let (vertex_edges, edges, parts) = (&self.vertex_edges, &self.edges, &self.parts);
        let valid = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < nv);
        // Each face corner's edge (looked up among its smaller vertex's edges) and each
        // face's neighbour count, in parallel, while one thread sums the edge lengths in
        // edge order (the same sum as before: serial, bit for bit).
        let (efo, efs) = (&self.edge_face_offsets, &self.edge_faces);
        let ((face_edges, counts), (edge_len_sum, finite_edges)): ((Vec<[u32; 3]>, Vec<u32>), _) =
            rayon::join(
                || {
                    triangles
                        .par_iter()
                        .enumerate()
                        .map(|(f, t)| {
                            if !valid(t) {
                                return ([NO_EDGE; 3], 0);
                            }
                            let fe = corner_edges(t, vertex_edges, edges);
                            let mut n = 0u32;
                            for_each_neighbour(f, &fe, efo, efs, |_| n += 1);
                            (fe, n)
                        })
                        .unzip()
                },
                || {
                    let (mut sum, mut count) = (0f64, 0usize);
                    for len in parts.iter().flat_map(|c| &c.lengths) {
                        if len.is_finite() {
                            sum += len;
                            count += 1;
                        }
                    }
                    (sum, count)
                },
            );
        let mean_edge_length = if finite_edges == 0 {
            0.0
        } else {
            (edge_len_sum / finite_edges as f64) as f32
        };

        (face_edges, counts, mean_edge_length)
    }
}

/// Face adjacency across edges (CSR) from each face's corner edges and neighbour count.
fn face_adjacency(
    face_edges: &[[u32; 3]],
    counts: Vec<u32>,
    efo: &[u32],
    efs: &[u32],
) -> (Vec<u32>, Vec<u32>) {
    let nf = face_edges.len();
    // Face adjacency across edges (CSR), filled in parallel (order preserved).
    let mut face_adj_offsets = Vec::with_capacity(nf + 1);
    face_adj_offsets.push(0u32);
    let mut acc = 0u32;
    for c in counts {
        acc += c;
        face_adj_offsets.push(acc);
    }
    let mut face_adj = vec![0u32; acc as usize];
    {
        // Fill in parallel: faces split into chunks, each owning its slice.
        let chunks = 64.min(nf.max(1));
        let mut rest: &mut [u32] = &mut face_adj;
        let mut pieces = Vec::with_capacity(chunks);
        let (mut start_f, mut consumed) = (0usize, 0usize);
        for c in 1..=chunks {
            let end_f = nf * c / chunks;
            let end = face_adj_offsets[end_f] as usize;
            let (piece, r) = std::mem::take(&mut rest).split_at_mut(end - consumed);
            pieces.push((start_f, end_f, piece));
            rest = r;
            consumed = end;
            start_f = end_f;
        }
        pieces.into_par_iter().for_each(|(sf, ef, piece)| {
            let mut k = 0;
            for (f, fe) in (sf..ef).zip(&face_edges[sf..ef]) {
                for_each_neighbour(f, fe, efo, efs, |g| {
                    piece[k] = g;
                    k += 1;
                });
            }
        });
    }
    (face_adj_offsets, face_adj)
}

/// Unit normal and area of one triangle (f64 cross product); zero for a degenerate or
/// out-of-range triangle.
fn face_normal_area(t: &[u32; 3], positions: &[Vec3]) -> (Vec3, f32) {
    let nv = positions.len();
    if !t.iter().all(|&i| (i as usize) < nv) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return (Vec3::ZERO, 0.0);
    }
    let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
    let cr = (b - a).cross(c - a);
    let len = cr.length();
    let scale = (b - a)
        .length_squared()
        .max((c - a).length_squared())
        .max((c - b).length_squared());
    if !(len > 1e-12 * scale) || !len.is_finite() {
        return (Vec3::ZERO, 0.0);
    }
    ((cr / len).as_vec3(), (0.5 * len) as f32)
}

/// Vertex → faces (CSR, faces ascending, each face once per vertex), by a counting sort;
/// triangles with an out-of-range index are left out.
fn vertex_face_csr(triangles: &[[u32; 3]], nv: usize) -> (Vec<u32>, Vec<u32>) {
    let valid = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < nv);
    let mut offsets = vec![0u32; nv + 1];
    for t in triangles.iter().filter(|t| valid(t)) {
        for &i in t {
            offsets[i as usize + 1] += 1;
        }
    }
    prefix_sum(&mut offsets);
    let mut fill = offsets.clone();
    let mut faces = vec![0u32; *offsets.last().unwrap_or(&0) as usize];
    for (f, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
        for (k, &i) in t.iter().enumerate() {
            // A face with a repeated vertex is listed once per vertex.
            if t[..k].contains(&i) {
                continue;
            }
            faces[fill[i as usize] as usize] = f as u32;
            fill[i as usize] += 1;
        }
    }
    // Compact away the slots left by repeated vertices (none in a clean mesh).
    if fill[..nv] == offsets[1..] {
        (offsets, faces)
    } else {
        let offsets = compact(&mut faces, &offsets, &fill);
        (offsets, faces)
    }
}

/// What the per-chunk edge build reads.
struct EdgeCtx<'a> {
    positions: &'a [Vec3],
    triangles: &'a [[u32; 3]],
    face_normals: &'a [Vec3],
    face_areas: &'a [f32],
    vertex_face_offsets: &'a [u32],
    vertex_faces: &'a [u32],
}

/// One vertex chunk's edges (`[a, b]`, `a` in the chunk), in order: the end of each
/// edge's faces in `edge_faces` (chunk-local), the faces (one per half-edge, in face
/// corner order), and each edge's dihedral angle and length.
struct EdgeChunk {
    edges: Vec<[u32; 2]>,
    ends: Vec<u32>,
    edge_faces: Vec<u32>,
    dihedral: Vec<f32>,
    lengths: Vec<f64>,
}

impl EdgeCtx<'_> {
    /// Vertices `sv..ev`: their normals into `vn`, their first (chunk-local) edge into
    /// `ve`, and the chunk's edges.
    fn chunk(&self, sv: usize, ev: usize, vn: &mut [Vec3], ve: &mut [u32]) -> EdgeChunk {
        let guess = 3 * (ev - sv) / 2 + 4;
        let mut out = EdgeChunk {
            edges: Vec::with_capacity(guess),
            ends: Vec::with_capacity(guess),
            edge_faces: Vec::with_capacity(2 * guess),
            dihedral: Vec::with_capacity(guess),
            lengths: Vec::with_capacity(guess),
        };
        // (larger vertex, face * 3 + corner) of one vertex's half-edges.
        let mut hs: Vec<(u32, u32)> = Vec::with_capacity(32);
        for v in sv..ev {
            let fs = &self.vertex_faces
                [self.vertex_face_offsets[v] as usize..self.vertex_face_offsets[v + 1] as usize];
            let n: DVec3 = fs
                .iter()
                .map(|&f| {
                    self.face_normals[f as usize].as_dvec3()
                        * f64::from(self.face_areas[f as usize])
                })
                .sum();
            vn[v - sv] = n.try_normalize().map_or(Vec3::Z, |n| n.as_vec3());
            ve[v - sv] = out.edges.len() as u32;
            hs.clear();
            for &f in fs {
                let t = self.triangles[f as usize];
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    if a != b && a.min(b) == v as u32 {
                        hs.push((a.max(b), f * 3 + k as u32));
                    }
                }
            }
            hs.sort_unstable();
            let mut i = 0;
            while i < hs.len() {
                let hi = hs[i].0;
                let mut j = i;
                while j < hs.len() && hs[j].0 == hi {
                    out.edge_faces.push(hs[j].1 / 3);
                    j += 1;
                }
                out.edges.push([v as u32, hi]);
                out.ends.push(out.edge_faces.len() as u32);
                out.dihedral.push(self.dihedral(v as u32, hi, &hs[i..j]));
                out.lengths.push(
                    (self.positions[hi as usize].as_dvec3() - self.positions[v].as_dvec3())
                        .length(),
                );
                i = j;
            }
        }
        out
    }

    /// Signed dihedral angle of edge `lo`–`hi` from its half-edges (face * 3 + corner,
    /// ascending); 0 unless it is a consistently oriented manifold edge between two
    /// faces with area.
    fn dihedral(&self, lo: u32, hi: u32, hs: &[(u32, u32)]) -> f32 {
        // Corner k of a face starts the edge, so the face runs lo → hi iff it is at lo.
        let &[(_, h1), (_, h2)] = hs else { return 0.0 };
        let (f1, f2) = ((h1 / 3) as usize, (h2 / 3) as usize);
        if self.face_areas[f1] == 0.0 || self.face_areas[f2] == 0.0 {
            return 0.0;
        }
        let dir1 = self.triangles[f1][(h1 % 3) as usize] == lo;
        if dir1 == (self.triangles[f2][(h2 % 3) as usize] == lo) {
            return 0.0;
        }
        let (pa, pb) = (
            self.positions[lo as usize].as_dvec3(),
            self.positions[hi as usize].as_dvec3(),
        );
        let n1 = self.face_normals[f1].as_dvec3();
        let n2 = self.face_normals[f2].as_dvec3();
        // Edge direction as traversed by f1; convex ⇔ (n1 × n2)·ē > 0.
        let ev = if dir1 { pb - pa } else { pa - pb }.normalize_or_zero();
        // f32 atan2 (about 1e-7 relative) is ample and much cheaper than f64.
        (n1.cross(n2).dot(ev) as f32).atan2(n1.dot(n2) as f32)
    }
}

/// The edge of each corner pair of a valid triangle (`NO_EDGE` where the two corners are
/// the same vertex), found among the edges of its smaller vertex.
fn corner_edges(t: &[u32; 3], vertex_edges: &[u32], edges: &[[u32; 2]]) -> [u32; 3] {
    let mut fe = [NO_EDGE; 3];
    for (k, e) in fe.iter_mut().enumerate() {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        if a == b {
            continue;
        }
        let (lo, hi) = (a.min(b) as usize, a.max(b));
        let first = vertex_edges[lo] as usize;
        let own = &edges[first..vertex_edges[lo + 1] as usize];
        if let Some(i) = own.iter().position(|&[_, h]| h == hi) {
            *e = (first + i) as u32;
        }
    }
    fe
}

/// `s` cut into consecutive pieces of the given lengths (which must sum to at most
/// `s.len()`).
fn split_lens<T>(mut s: &mut [T], lens: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    for n in lens {
        let (piece, rest) = std::mem::take(&mut s).split_at_mut(n);
        out.push(piece);
        s = rest;
    }
    out
}

/// Moves each vertex's filled slots `offsets[v]..fill[v]` together; the new offsets.
fn compact(faces: &mut Vec<u32>, offsets: &[u32], fill: &[u32]) -> Vec<u32> {
    let nv = offsets.len() - 1;
    let mut out = 0usize;
    let mut new_offsets = vec![0u32; nv + 1];
    for v in 0..nv {
        for s in offsets[v]..fill[v] {
            faces[out] = faces[s as usize];
            out += 1;
        }
        new_offsets[v + 1] = out as u32;
    }
    faces.truncate(out);
    new_offsets
}

/// Calls `out` with each face sharing an edge with face `f` (whose corner edges are
/// `face_edges`), in corner order and each edge's face order, `f` itself left out (the
/// order of [`Topology::face_neighbours`]).
fn for_each_neighbour(
    f: usize,
    face_edges: &[u32; 3],
    efo: &[u32],
    efs: &[u32],
    mut out: impl FnMut(u32),
) {
    for &e in face_edges {
        if e == NO_EDGE {
            continue;
        }
        for &g in &efs[efo[e as usize] as usize..efo[e as usize + 1] as usize] {
            if g != f as u32 {
                out(g);
            }
        }
    }
}

fn prefix_sum(v: &mut [u32]) {
    for i in 1..v.len() {
        v[i] += v[i - 1];
    }
}
