//! Mesh topology built once from a welded triangle mesh: vertex → faces, edge → faces
//! with the signed dihedral angle, face adjacency across edges, and the special cases
//! (boundary, non-manifold, inconsistently oriented edges, degenerate triangles, isolated
//! vertices) as values rather than panics.
//!
//! Supports the curvature tensor of §2.2, Eq. (1), of Lee & Choi, "Stylized Specular
//! Reflections Using Projective Textures based on Principal Curvature Analysis" (Journal
//! of the Korea Computer Graphics Society): β(e) is [`Topology::dihedral`].
//!
//! Layout: compressed sparse rows (one offsets array plus one flat array per relation),
//! edges found per vertex from its faces (the half-edges to larger vertices, sorted), so
//! building is linear in the mesh size apart from tiny per-vertex sorts, and runs in
//! parallel over vertex chunks with the same result for any thread count.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::Welded;

/// Marker for "no edge" in [`Topology::face_edges`] (a corner pair of a triangle with a
/// repeated vertex index, which is not an edge).
pub const NO_EDGE: u32 = u32::MAX;

/// What kind of edge an undirected edge is, by the faces that use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// One face: a hole or open border. Dihedral angle 0 (no bend is measurable).
    Boundary,
    /// Two faces traversing it in opposite directions: the normal case. Dihedral angle
    /// signed, convex positive (0 if one face is degenerate).
    Interior,
    /// Two faces traversing it in the same direction (the mesh's orientation flips
    /// here, e.g. a Möbius strip or a badly exported part). Dihedral angle 0.
    Inconsistent,
    /// Three or more faces (a fin, duplicate faces). Dihedral angle 0.
    NonManifold,
}

/// A [`Topology`] cut along its creases ([`Topology::split_creases`]).
#[derive(Clone, Debug, Default)]
pub struct CreaseSplit {
    /// The split mesh: same faces, vertices copied once per fan between creases.
    pub topology: Topology,
    /// For each vertex of `topology`, the vertex it copies.
    pub original: Vec<u32>,
}

/// Topology and per-element geometry of a welded triangle mesh.
///
/// Never panics on bad input: degenerate triangles (zero area or a repeated vertex) get a
/// zero normal and zero area and contribute nothing to curvature; isolated vertices have
/// no faces (curvature marks them invalid); triangles with an out-of-range index are
/// treated as degenerate and left out of every relation.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// Welded vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles over `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// Unit face normals (right-hand rule); zero for degenerate faces.
    pub face_normals: Vec<Vec3>,
    /// Face areas; zero for degenerate faces.
    pub face_areas: Vec<f32>,
    /// Undirected edges, `[a, b]` with `a < b`, sorted.
    pub edges: Vec<[u32; 2]>,
    /// For each face, its edges: `face_edges[f][k]` joins corners `k` and `(k+1) % 3`;
    /// [`NO_EDGE`] where those corners are the same vertex.
    pub face_edges: Vec<[u32; 3]>,
    /// Signed dihedral angle β(e) per edge in radians: the angle between the two face
    /// normals, positive where the surface is convex (bends away from its normals), 0
    /// for every edge kind other than [`EdgeKind::Interior`].
    pub dihedral: Vec<f32>,
    /// Area-weighted unit vertex normals from the faces (`Vec3::Z` for isolated
    /// vertices and fans of degenerate faces).
    pub vertex_normals: Vec<Vec3>,
    /// Mean length of the edges with finite length (0 for a mesh without any).
    pub mean_edge_length: f32,
    edge_face_offsets: Vec<u32>,
    edge_faces: Vec<u32>,
    vertex_face_offsets: Vec<u32>,
    vertex_faces: Vec<u32>,
    face_adj_offsets: Vec<u32>,
    face_adj: Vec<u32>,
}

impl Topology {
    /// Builds the topology of a welded mesh.
    pub fn new(welded: &Welded) -> Self {
        Self::from_parts(welded.positions.clone(), welded.indices.clone())
    }

    /// Builds the topology from welded positions and triangles.
    pub fn from_parts(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        let nv = positions.len();
        let nf = triangles.len();
        let valid = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < nv);

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
            let ctx = EdgeCtx {
                positions: &positions,
                triangles: &triangles,
                face_normals: &face_normals,
                face_areas: &face_areas,
                vertex_face_offsets: &vertex_face_offsets,
                vertex_faces: &vertex_faces,
            };
            let lens = bounds.iter().map(|&(s, e)| e - s);
            split_lens(&mut vertex_normals, lens.clone())
                .into_iter()
                .zip(split_lens(&mut vertex_edges[..nv], lens))
                .zip(&bounds)
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(|((vn, ve), &(sv, ev))| ctx.chunk(sv, ev, vn, ve))
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

        // Each face corner's edge (looked up among its smaller vertex's edges) and each
        // face's neighbour count, in parallel, while one thread sums the edge lengths in
        // edge order (the same sum as before: serial, bit for bit).
        let (efo, efs) = (&edge_face_offsets, &edge_faces);
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
                            let fe = corner_edges(t, &vertex_edges, &edges);
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

    /// This mesh with every vertex split into one copy per fan of its faces that are
    /// joined around it by edges bending by at most `crease_angle_deg` (|β(e)|), so the
    /// creases become boundaries (hatching must not smooth across them).
    ///
    /// Face order and winding are kept: corner `k` of face `f` of the result is a copy
    /// of corner `k` of face `f` here. The copies of vertex `v` are numbered
    /// consecutively in vertex order (an isolated vertex keeps one copy), so a mesh
    /// without creases comes back with the same numbering. Edges with more than two
    /// faces (non-manifold) never split; out-of-range corners stay out of range.
    pub fn split_creases(&self, crease_angle_deg: f32) -> CreaseSplit {
        self.split_creases_longer_than(crease_angle_deg, 0.0)
    }

    /// The crease edges of [`Topology::split_creases`] (two faces, `|β(e)|` above
    /// `crease_angle_deg`) that belong to a crease line: a set of crease edges joined at
    /// their vertices whose total length is at least `min_line_length`. Isolated sharp
    /// edges of a noisy scan (a folded sliver, a spike) form short sets and are kept.
    pub fn crease_edges(&self, crease_angle_deg: f32, min_line_length: f32) -> Vec<bool> {
        let limit = crease_angle_deg.to_radians();
        let mut cut: Vec<bool> = (0..self.edges.len())
            .map(|e| self.edge_faces(e).len() == 2 && !(self.dihedral[e].abs() <= limit))
            .collect();
        if !(min_line_length > 0.0) {
            return cut;
        }
        // Components of crease edges through shared vertices, and their lengths.
        let nv = self.vertex_count();
        let mut parent: Vec<u32> = (0..nv as u32).collect();
        for (e, &[a, b]) in self.edges.iter().enumerate() {
            if cut[e] {
                union_sets(&mut parent, a, b);
            }
        }
        let mut length = vec![0.0f64; nv];
        for (e, &[a, b]) in self.edges.iter().enumerate() {
            if cut[e] {
                let r = find_set(&mut parent, a) as usize;
                let l =
                    f64::from((self.positions[b as usize] - self.positions[a as usize]).length());
                if l.is_finite() {
                    length[r] += l;
                }
            }
        }
        for (e, &[a, _]) in self.edges.iter().enumerate() {
            if cut[e] && length[find_set(&mut parent, a) as usize] < f64::from(min_line_length) {
                cut[e] = false;
            }
        }
        cut
    }

    /// [`Topology::split_creases`] cutting only [`Topology::crease_edges`] with
    /// `min_line_length`.
    pub fn split_creases_longer_than(
        &self,
        crease_angle_deg: f32,
        min_line_length: f32,
    ) -> CreaseSplit {
        let nv = self.vertex_count();
        let cut = self.crease_edges(crease_angle_deg, min_line_length);
        let is_crease = |e: usize| cut[e];
        if !(0..self.edges.len()).any(is_crease) {
            return CreaseSplit {
                topology: self.clone(),
                original: (0..nv as u32).collect(),
            };
        }
        // Union-find over face corners (3f + k): corners of the same vertex in faces
        // joined across a non-crease edge belong together.
        let nc = self.triangles.len() * 3;
        let mut parent: Vec<u32> = (0..nc as u32).collect();
        for (f, t) in self.triangles.iter().enumerate() {
            // A repeated vertex within a face is one corner group.
            for k in 0..3 {
                for m in k + 1..3 {
                    if t[k] == t[m] {
                        union_sets(&mut parent, (3 * f + k) as u32, (3 * f + m) as u32);
                    }
                }
            }
            for k in 0..3 {
                let e = self.face_edges[f][k];
                if e == NO_EDGE || is_crease(e as usize) {
                    continue;
                }
                for &g in self.edge_faces(e as usize) {
                    let g = g as usize;
                    if g == f {
                        continue;
                    }
                    let tg = self.triangles[g];
                    for c in [k, (k + 1) % 3] {
                        if let Some(cg) = tg.iter().position(|&v| v == t[c]) {
                            union_sets(&mut parent, (3 * f + c) as u32, (3 * g + cg) as u32);
                        }
                    }
                }
            }
        }
        // (vertex, group) pairs, numbered in vertex order.
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(nc + nv);
        for (f, t) in self.triangles.iter().enumerate() {
            for (k, &v) in t.iter().enumerate() {
                if (v as usize) < nv {
                    pairs.push((v, find_set(&mut parent, (3 * f + k) as u32)));
                }
            }
        }
        // Isolated vertices keep one copy (group u32::MAX sorts after any corner group,
        // and is dropped for vertices that have corners).
        pairs.extend((0..nv as u32).map(|v| (v, u32::MAX)));
        pairs.sort_unstable();
        pairs.dedup();
        let pairs: Vec<(u32, u32)> = pairs
            .iter()
            .enumerate()
            .filter(|&(i, &(v, g))| g != u32::MAX || i == 0 || pairs[i - 1].0 != v)
            .map(|(_, &p)| p)
            .collect();
        let positions: Vec<Vec3> = pairs
            .iter()
            .map(|&(v, _)| self.positions[v as usize])
            .collect();
        let original: Vec<u32> = pairs.iter().map(|&(v, _)| v).collect();
        let triangles: Vec<[u32; 3]> = self
            .triangles
            .iter()
            .enumerate()
            .map(|(f, t)| {
                let mut out = [u32::MAX; 3];
                for (k, &v) in t.iter().enumerate() {
                    if (v as usize) < nv {
                        let g = find_set(&mut parent, (3 * f + k) as u32);
                        if let Ok(i) = pairs.binary_search(&(v, g)) {
                            out[k] = i as u32;
                        }
                    }
                }
                out
            })
            .collect();
        CreaseSplit {
            topology: Topology::from_parts(positions, triangles),
            original,
        }
    }

    /// Number of welded vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }

    /// The faces using vertex `v` (each once); empty for an isolated vertex.
    pub fn vertex_faces(&self, v: usize) -> &[u32] {
        &self.vertex_faces
            [self.vertex_face_offsets[v] as usize..self.vertex_face_offsets[v + 1] as usize]
    }

    /// The faces using edge `e` (one per use; a duplicated face appears twice).
    pub fn edge_faces(&self, e: usize) -> &[u32] {
        &self.edge_faces[self.edge_face_offsets[e] as usize..self.edge_face_offsets[e + 1] as usize]
    }

    /// The faces sharing an edge with face `f` (all of them at a non-manifold edge).
    pub fn face_neighbours(&self, f: usize) -> &[u32] {
        &self.face_adj[self.face_adj_offsets[f] as usize..self.face_adj_offsets[f + 1] as usize]
    }

    /// The kind of edge `e`.
    pub fn edge_kind(&self, e: usize) -> EdgeKind {
        match self.edge_faces(e).len() {
            0 | 1 => EdgeKind::Boundary,
            2 if self.edge_consistent(e) => EdgeKind::Interior,
            2 => EdgeKind::Inconsistent,
            _ => EdgeKind::NonManifold,
        }
    }

    fn edge_consistent(&self, e: usize) -> bool {
        let [a, _] = self.edges[e];
        let dir = |f: u32| {
            let t = self.triangles[f as usize];
            let k = self.face_edges[f as usize]
                .iter()
                .position(|&x| x == e as u32)
                .unwrap_or(0);
            t[k] == a
        };
        let fs = self.edge_faces(e);
        dir(fs[0]) != dir(fs[1])
    }

    /// The two face normals of an edge with two faces (`None` for other edge kinds).
    pub fn edge_face_normals(&self, e: usize) -> Option<[Vec3; 2]> {
        match self.edge_faces(e) {
            &[f, g] => Some([self.face_normals[f as usize], self.face_normals[g as usize]]),
            _ => None,
        }
    }

    /// Whether face `f` is degenerate (zero area, repeated or out-of-range vertex).
    pub fn is_degenerate(&self, f: usize) -> bool {
        self.face_areas[f] == 0.0
    }

    /// Whether vertex `v` is used by no triangle.
    pub fn is_isolated(&self, v: usize) -> bool {
        self.vertex_faces(v).is_empty()
    }

    /// Per-vertex flag: does a boundary edge touch the vertex?
    pub fn boundary_vertices(&self) -> Vec<bool> {
        let mut b = vec![false; self.positions.len()];
        for (e, &[x, y]) in self.edges.iter().enumerate() {
            if self.edge_faces(e).len() == 1 {
                b[x as usize] = true;
                b[y as usize] = true;
            }
        }
        b
    }

    /// Euler characteristic `χ = V − E + F` (isolated vertices count in V).
    pub fn euler_characteristic(&self) -> i64 {
        self.positions.len() as i64 - self.edges.len() as i64 + self.triangles.len() as i64
    }

    /// Discrete Gaussian curvature, integrated per vertex (angle defect): `2π − Σ θ` at
    /// interior vertices, `π − Σ θ` on the boundary, `2π` at isolated vertices. By the
    /// discrete Gauss–Bonnet theorem the sum over a manifold mesh is exactly `2πχ`.
    pub fn angle_defects(&self) -> Vec<f64> {
        let boundary = self.boundary_vertices();
        let mut d: Vec<f64> = boundary.iter().map(|&b| if b { PI } else { TAU }).collect();
        for (f, t) in self.triangles.iter().enumerate() {
            if self.is_degenerate(f) {
                continue;
            }
            let p = t.map(|i| self.positions[i as usize].as_dvec3());
            for k in 0..3 {
                let a = p[(k + 1) % 3] - p[k];
                let b = p[(k + 2) % 3] - p[k];
                d[t[k] as usize] -= a.cross(b).length().atan2(a.dot(b));
            }
        }
        d
    }
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

/// Union-find over `parent` (each entry its set's parent; a root is its own): the root of
/// `x`'s set, halving the path on the way.
pub(crate) fn find_set(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins the sets of `a` and `b` under the smaller root (see [`find_set`]).
pub(crate) fn union_sets(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find_set(parent, a), find_set(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{generate, weld};

    #[test]
    fn closed_torus_is_manifold_with_chi_zero() {
        let t = Topology::new(&weld(&generate::torus(2.0, 0.7, 24, 10)));
        assert_eq!(t.euler_characteristic(), 0);
        assert!((0..t.edges.len()).all(|e| t.edge_kind(e) == EdgeKind::Interior));
        assert!(t.dihedral.iter().all(|&b| b.abs() < 1.0));
        // Outer equator bends convexly, so most dihedral angles are positive.
        let pos = t.dihedral.iter().filter(|&&b| b > 0.0).count();
        assert!(pos > t.edges.len() / 2);
        assert!((0..t.face_count()).all(|f| t.face_neighbours(f).len() == 3));
    }

    #[test]
    fn sphere_dihedrals_are_convex() {
        let t = Topology::new(&weld(&generate::icosphere(2, 1.0)));
        assert_eq!(t.euler_characteristic(), 2);
        assert!(t.dihedral.iter().all(|&b| b > 0.0));
    }

    #[test]
    fn odd_cases_are_values() {
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::NEG_Y,
            Vec3::ONE,
        ];
        // Fan of three faces on edge 0-1, a duplicate face, a degenerate face, an
        // out-of-range face, and an isolated vertex 5.
        let tris = vec![
            [0, 1, 2],
            [1, 0, 3],
            [0, 1, 4],
            [0, 1, 2],
            [2, 2, 3],
            [0, 1, 99],
        ];
        let t = Topology::from_parts(p, tris);
        let e01 = t.edges.iter().position(|&e| e == [0, 1]).unwrap();
        assert_eq!(t.edge_kind(e01), EdgeKind::NonManifold);
        assert_eq!(t.dihedral[e01], 0.0);
        assert!(t.is_degenerate(4));
        assert!(t.is_degenerate(5));
        assert!(t.is_isolated(5));
        assert!(t.edge_face_normals(e01).is_none());
    }

    /// The chunked parallel edge build against a plain ordered-map reference: same
    /// edges in the same order, same faces per edge, same edge per face corner; and the
    /// dihedral angle's orientation test on a face flipped against its neighbours.
    #[test]
    fn edges_match_ordered_map_reference() {
        use std::collections::BTreeMap;
        let mut w = weld(&generate::icosphere(3, 1.0));
        // Add odd faces: a duplicate, a repeated vertex, an out-of-range index.
        let dup = w.indices[7];
        w.indices
            .extend_from_slice(&[dup, [0, 0, 5], [1, 2, 1 << 30]]);
        let t = Topology::new(&w);
        let nv = w.positions.len() as u32;
        let mut map: BTreeMap<(u32, u32), Vec<(usize, usize)>> = BTreeMap::new();
        for (f, tri) in w.indices.iter().enumerate() {
            if tri.iter().any(|&i| i >= nv) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if a != b {
                    map.entry((a.min(b), a.max(b))).or_default().push((f, k));
                }
            }
        }
        let want: Vec<[u32; 2]> = map.keys().map(|&(a, b)| [a, b]).collect();
        assert_eq!(t.edges, want);
        for (e, uses) in map.values().enumerate() {
            let mut got = t.edge_faces(e).to_vec();
            let mut exp: Vec<u32> = uses.iter().map(|&(f, _)| f as u32).collect();
            got.sort_unstable();
            exp.sort_unstable();
            assert_eq!(got, exp, "edge {e}");
            for &(f, k) in uses {
                assert_eq!(t.face_edges[f][k], e as u32);
            }
        }
        // Direction per half-edge corner: a flipped face makes its three edges
        // inconsistent (β = 0); every other interior edge of the sphere is convex.
        let mut flipped = weld(&generate::icosphere(3, 1.0));
        let [a, b, c] = flipped.indices[11];
        flipped.indices[11] = [b, a, c];
        let tf = Topology::new(&flipped);
        assert_eq!(
            (0..tf.edges.len())
                .filter(|&e| tf.edge_kind(e) == EdgeKind::Inconsistent)
                .count(),
            3
        );
        for e in 0..tf.edges.len() {
            let interior = tf.edge_kind(e) == EdgeKind::Interior;
            let sound = tf
                .edge_faces(e)
                .iter()
                .all(|&f| !tf.is_degenerate(f as usize));
            assert_eq!(tf.dihedral[e] > 0.0, interior && sound, "edge {e}");
        }
        let lens: f64 = want
            .iter()
            .map(|&[a, b]| (w.positions[b as usize] - w.positions[a as usize]).length() as f64)
            .sum();
        let mean = lens / want.len() as f64;
        assert!((f64::from(t.mean_edge_length) - mean).abs() < 1e-6 * mean);
    }

    /// `Topology::from_parts` as it was before the per-vertex-chunk edge build (two
    /// counting sorts, a serial face-corner scatter): the reference the current build
    /// must match bit for bit.
    fn previous_from_parts(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Topology {
        let nv = positions.len();
        let nf = triangles.len();
        let valid = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < nv);

        // Face normals and areas (f64 cross products), in parallel.
        let (face_normals, face_areas): (Vec<Vec3>, Vec<f32>) = triangles
            .par_iter()
            .map(|t| {
                if !valid(t) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
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
            })
            .unzip();

        // Vertex → faces (CSR).
        let mut vertex_face_offsets = vec![0u32; nv + 1];
        for t in triangles.iter().filter(|t| valid(t)) {
            for &i in t {
                vertex_face_offsets[i as usize + 1] += 1;
            }
        }
        prefix_sum(&mut vertex_face_offsets);
        let mut fill = vertex_face_offsets.clone();
        let mut vertex_faces = vec![0u32; *vertex_face_offsets.last().unwrap_or(&0) as usize];
        for (f, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
            for (k, &i) in t.iter().enumerate() {
                // A face with a repeated vertex is listed once per vertex.
                if t[..k].contains(&i) {
                    continue;
                }
                vertex_faces[fill[i as usize] as usize] = f as u32;
                fill[i as usize] += 1;
            }
        }
        // Compact away the slots left by repeated vertices (none in a clean mesh).
        let vertex_face_offsets = if fill[..nv] == vertex_face_offsets[1..] {
            vertex_face_offsets
        } else {
            compact(&mut vertex_faces, &vertex_face_offsets, &fill)
        };

        // Area-weighted vertex normals, gathered per vertex in parallel.
        let vertex_normals: Vec<Vec3> = (0..nv)
            .into_par_iter()
            .map(|v| {
                let fs = &vertex_faces
                    [vertex_face_offsets[v] as usize..vertex_face_offsets[v + 1] as usize];
                let n: DVec3 = fs
                    .iter()
                    .map(|&f| {
                        face_normals[f as usize].as_dvec3() * f64::from(face_areas[f as usize])
                    })
                    .sum();
                n.try_normalize().map_or(Vec3::Z, |n| n.as_vec3())
            })
            .collect();

        // Half-edges bucketed by their smaller vertex (counting sort), then sorted by
        // the larger vertex inside each bucket.
        let mut bucket = vec![0u32; nv + 1];
        for t in triangles.iter().filter(|t| valid(t)) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b {
                    bucket[a.min(b) as usize + 1] += 1;
                }
            }
        }
        prefix_sum(&mut bucket);
        let nh = *bucket.last().unwrap_or(&0) as usize;
        let mut he: Vec<(u32, u32)> = vec![(0, 0); nh]; // (larger vertex, face*3+corner)
        let mut fill = bucket.clone();
        for (f, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a != b {
                    let lo = a.min(b) as usize;
                    he[fill[lo] as usize] = (a.max(b), (f * 3 + k) as u32);
                    fill[lo] += 1;
                }
            }
        }
        // Sort every bucket by its larger vertex and group equal (smaller, larger) runs
        // into edges, buckets split into chunks in parallel; each chunk lists its edges,
        // their end offsets into `he` and the chunk-local edge of each of its half-edges.
        type ChunkEdges = (Vec<[u32; 2]>, Vec<u32>, Vec<u32>);
        let chunk_edges: Vec<ChunkEdges> = {
            let chunks = 64.min(nv.max(1));
            let mut rest: &mut [(u32, u32)] = &mut he;
            let mut pieces = Vec::with_capacity(chunks);
            let (mut start_v, mut consumed) = (0usize, 0usize);
            for c in 1..=chunks {
                let end_v = nv * c / chunks;
                let end_h = bucket[end_v] as usize;
                let (piece, r) = std::mem::take(&mut rest).split_at_mut(end_h - consumed);
                pieces.push((start_v, end_v, piece));
                rest = r;
                consumed = end_h;
                start_v = end_v;
            }
            let bucket = &bucket;
            pieces
                .into_par_iter()
                .map(|(sv, ev, piece)| {
                    let base = bucket[sv] as usize;
                    let mut edges = Vec::with_capacity(piece.len() / 2 + 1);
                    let mut ends = Vec::with_capacity(piece.len() / 2 + 1);
                    let mut he_edge = Vec::with_capacity(piece.len());
                    for lo in sv..ev {
                        let (b0, b1) = (bucket[lo] as usize - base, bucket[lo + 1] as usize - base);
                        let s = &mut piece[b0..b1];
                        s.sort_unstable();
                        let mut i = 0;
                        while i < s.len() {
                            let hi = s[i].0;
                            let mut j = i;
                            while j < s.len() && s[j].0 == hi {
                                j += 1;
                            }
                            he_edge.extend(std::iter::repeat_n(edges.len() as u32, j - i));
                            edges.push([lo as u32, hi]);
                            ends.push((base + b0 + j) as u32);
                            i = j;
                        }
                    }
                    (edges, ends, he_edge)
                })
                .collect()
        };
        let ne: usize = chunk_edges.iter().map(|c| c.0.len()).sum();
        let mut edges = Vec::with_capacity(ne);
        let mut edge_face_offsets = Vec::with_capacity(ne + 1);
        edge_face_offsets.push(0u32);
        let mut he_edge = Vec::with_capacity(nh);
        for (es, ends, hes) in chunk_edges {
            let e0 = edges.len() as u32;
            he_edge.extend(hes.into_iter().map(|e| e + e0));
            edges.extend(es);
            edge_face_offsets.extend(ends);
        }
        // One face per half-edge, in half-edge order, and each face corner's edge.
        let edge_faces: Vec<u32> = he.par_iter().map(|&(_, h)| h / 3).collect();
        let mut face_edges = vec![[NO_EDGE; 3]; nf];
        for (&(_, h), &e) in he.iter().zip(&he_edge) {
            face_edges[(h / 3) as usize][(h % 3) as usize] = e;
        }
        // Edge lengths in parallel, summed in edge order (the same sum as a serial loop).
        let lengths: Vec<f64> = edges
            .par_iter()
            .map(|&[a, b]| {
                (positions[b as usize].as_dvec3() - positions[a as usize].as_dvec3()).length()
            })
            .collect();
        let (mut edge_len_sum, mut finite_edges) = (0f64, 0usize);
        for len in lengths.into_iter().filter(|l| l.is_finite()) {
            edge_len_sum += len;
            finite_edges += 1;
        }
        // Signed dihedral angle per consistently oriented manifold edge, in parallel.
        let dihedral: Vec<f32> = (0..edges.len())
            .into_par_iter()
            .map(|e| {
                // The edge's half-edges (face * 3 + corner), in edge-face order: corner k
                // of a face starts the edge, so the face runs lo → hi iff it is at lo.
                let hs = &he[edge_face_offsets[e] as usize..edge_face_offsets[e + 1] as usize];
                let &[(_, h1), (_, h2)] = hs else { return 0.0 };
                let (f1, f2) = ((h1 / 3) as usize, (h2 / 3) as usize);
                if face_areas[f1] == 0.0 || face_areas[f2] == 0.0 {
                    return 0.0;
                }
                let [lo, hi] = edges[e];
                let dir1 = triangles[f1][(h1 % 3) as usize] == lo;
                if dir1 == (triangles[f2][(h2 % 3) as usize] == lo) {
                    return 0.0;
                }
                let (pa, pb) = (
                    positions[lo as usize].as_dvec3(),
                    positions[hi as usize].as_dvec3(),
                );
                let n1 = face_normals[f1].as_dvec3();
                let n2 = face_normals[f2].as_dvec3();
                // Edge direction as traversed by f1; convex ⇔ (n1 × n2)·ē > 0.
                let ev = if dir1 { pb - pa } else { pa - pb }.normalize_or_zero();
                // f32 atan2 (about 1e-7 relative) is ample and much cheaper than f64.
                (n1.cross(n2).dot(ev) as f32).atan2(n1.dot(n2) as f32)
            })
            .collect();
        let mean_edge_length = if finite_edges == 0 {
            0.0
        } else {
            (edge_len_sum / finite_edges as f64) as f32
        };

        // Face adjacency across edges (CSR), in parallel (order preserved).
        // Plain loops, no iterator adaptors: this runs twice per face (count, fill).
        let (efo, efs) = (&edge_face_offsets, &edge_faces);
        let counts: Vec<u32> = (0..nf)
            .into_par_iter()
            .map(|f| {
                let mut n = 0u32;
                for_each_neighbour(f, &face_edges[f], efo, efs, |_| n += 1);
                n
            })
            .collect();
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

        Topology {
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

    /// Every array of two topologies, floats by their bits.
    fn assert_same(a: &Topology, b: &Topology, name: &str) {
        let v3 = |v: &[Vec3]| -> Vec<[u32; 3]> {
            v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
        };
        let f1 = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
        assert_eq!(a.triangles, b.triangles, "{name}");
        assert_eq!(v3(&a.face_normals), v3(&b.face_normals), "{name}");
        assert_eq!(f1(&a.face_areas), f1(&b.face_areas), "{name}");
        assert_eq!(a.edges, b.edges, "{name}");
        assert_eq!(a.face_edges, b.face_edges, "{name}");
        assert_eq!(f1(&a.dihedral), f1(&b.dihedral), "{name}");
        assert_eq!(v3(&a.vertex_normals), v3(&b.vertex_normals), "{name}");
        assert_eq!(
            a.mean_edge_length.to_bits(),
            b.mean_edge_length.to_bits(),
            "{name}"
        );
        assert_eq!(a.edge_face_offsets, b.edge_face_offsets, "{name}");
        assert_eq!(a.edge_faces, b.edge_faces, "{name}");
        assert_eq!(a.vertex_face_offsets, b.vertex_face_offsets, "{name}");
        assert_eq!(a.vertex_faces, b.vertex_faces, "{name}");
        assert_eq!(a.face_adj_offsets, b.face_adj_offsets, "{name}");
        assert_eq!(a.face_adj, b.face_adj, "{name}");
    }

    /// The per-vertex-chunk build against the previous one, bit for bit: a jittered,
    /// noisy torus with a hole, a fin, a duplicate face, a flipped face, faces with a
    /// repeated vertex and an out-of-range index and an isolated vertex; the scanned
    /// bunny; and a mesh smaller than the chunk count.
    #[test]
    fn matches_previous_build() {
        let mesh = generate::displace_along_normals(
            &generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5),
            0.01,
            9,
        );
        let mut w = weld(&mesh);
        w.indices
            .retain(|t| t.iter().all(|&i| !(200..260).contains(&i)));
        let [a, b, c] = w.indices[500];
        w.indices[500] = [b, a, c];
        let dup = w.indices[900];
        let fin = [w.indices[1000][0], w.indices[1000][1], 3000];
        w.indices
            .extend_from_slice(&[dup, fin, [7, 7, 8], [9, 10, 9], [1, 2, 1 << 30]]);
        w.positions.push(Vec3::splat(9.0));
        let bunny = crate::load_obj(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/meshes/stanford-bunny.obj"
        ))
        .unwrap();
        let wb = weld(&bunny);
        let tiny = (
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]],
        );
        for (name, p, t) in [
            ("torus", w.positions, w.indices),
            ("bunny", wb.positions, wb.indices),
            ("tetrahedron", tiny.0, tiny.1),
        ] {
            let got = Topology::from_parts(p.clone(), t.clone());
            let want = previous_from_parts(p, t);
            assert_same(&got, &want, name);
        }
    }
}
