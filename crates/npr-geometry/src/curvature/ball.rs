//! The ball `B` of Eq. (1) as lists: per vertex, the faces the corrected form's walk
//! visits, for an evaluator that gathers per vertex over a fixed list (a GPU pass) rather
//! than walking the mesh.

use rayon::prelude::*;

use super::tensor::{Packed, SCRATCH, corrected_walk};
use super::{CurvatureField, CurvatureRadius};
use crate::topology::Topology;

/// Per vertex, the faces of its ball (compressed sparse rows): vertex `v`'s faces are
/// `faces[offsets[v]..offsets[v + 1]]`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BallFaces {
    /// `vertex_count + 1` offsets into `faces`.
    pub offsets: Vec<u32>,
    /// The faces, vertex after vertex.
    pub faces: Vec<u32>,
}

impl BallFaces {
    /// Vertex `v`'s faces (empty past the end).
    pub fn of(&self, v: usize) -> &[u32] {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&a), Some(&b)) => self.faces.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }
}

impl CurvatureRadius {
    /// The radius in world units on `topo` (what [`CurvatureField::radius_world`]
    /// reports for a mesh near unit size).
    pub fn world(self, topo: &Topology) -> f32 {
        match self {
            Self::World(r) => r,
            Self::EdgeLengths(k) => k * topo.mean_edge_length,
        }
    }
}

impl CurvatureField {
    /// The faces that [`CurvatureMethod::Corrected`](super::CurvatureMethod::Corrected)'s
    /// walk visits at each vertex with ball radius `radius_world` (grown from the vertex's
    /// faces over face adjacency, passed on as [`CurvatureField::compute`] says), in the
    /// order it sums them. Every face whose centroid lies in the ball is listed, and the
    /// ring of faces around it the walk looked at; summing `w_f T_f` and `w_f A_f` over the
    /// listed faces whose centroid is inside (`w = (1 − d²/r²)²`) gives the corrected
    /// form's tensor. The lists depend on the positions only through which faces are
    /// inside: a pass that keeps them while the mesh moves recomputes `T_f`, `A_f` and
    /// `d` from the current positions and sees a ball of the first pose's connectivity.
    pub fn corrected_balls(topo: &Topology, radius_world: f32) -> BallFaces {
        let packed = Packed::build(topo);
        let nv = topo.vertex_count();
        let ok = radius_world.is_finite() && radius_world > 0.0;
        const CHUNK: usize = 1024;
        let parts: Vec<(Vec<u32>, Vec<u32>)> = (0..nv.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut ends = Vec::with_capacity(CHUNK);
                let mut faces = Vec::new();
                SCRATCH.with(|s| {
                    let mut s = s.borrow_mut();
                    for v in c * CHUNK..((c + 1) * CHUNK).min(nv) {
                        if ok && topo.positions[v].is_finite() {
                            corrected_walk(topo, &packed, v, radius_world, &mut s, &mut faces);
                        }
                        ends.push(faces.len() as u32);
                    }
                });
                (ends, faces)
            })
            .collect();
        let mut out = BallFaces {
            offsets: Vec::with_capacity(nv + 1),
            faces: Vec::with_capacity(parts.iter().map(|p| p.1.len()).sum()),
        };
        out.offsets.push(0);
        for (ends, faces) in parts {
            let base = out.faces.len() as u32;
            out.offsets.extend(ends.iter().map(|e| e + base));
            out.faces.extend(faces);
        }
        out
    }
}
