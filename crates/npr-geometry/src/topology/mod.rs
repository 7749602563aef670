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

use glam::Vec3;

mod build;
mod creases;
#[cfg(test)]
mod tests;

pub(crate) use creases::{find_set, union_sets};
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
    /// Number of welded vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The square root of the total (finite) face area: a length that scales with the
    /// mesh, for tolerances given as a share of its size.
    pub fn area_scale(&self) -> f32 {
        self.face_areas
            .iter()
            .map(|&a| f64::from(a))
            .filter(|a| a.is_finite())
            .sum::<f64>()
            .sqrt() as f32
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

    /// Each vertex's neighbours along the edges, as `vertex_count + 1` offsets and one
    /// list (vertex `v`'s are `list[offsets[v]..offsets[v + 1]]`, in edge order): the
    /// graph a diffusion over the vertices walks.
    pub fn vertex_neighbours(&self) -> (Vec<u32>, Vec<u32>) {
        let n = self.vertex_count();
        let mut offsets = vec![0u32; n + 1];
        for e in &self.edges {
            offsets[e[0] as usize + 1] += 1;
            offsets[e[1] as usize + 1] += 1;
        }
        for v in 0..n {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut list = vec![0u32; offsets[n] as usize];
        for e in &self.edges {
            for (a, b) in [(e[0], e[1]), (e[1], e[0])] {
                list[fill[a as usize] as usize] = b;
                fill[a as usize] += 1;
            }
        }
        (offsets, list)
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
