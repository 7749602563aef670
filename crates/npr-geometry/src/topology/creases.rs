//! Cutting a [`Topology`] along its creases (vertices split per fan of faces between
//! crease edges), and the union-find both that and the stroke field use.

use glam::Vec3;

use super::{CreaseSplit, NO_EDGE, Topology};

/// The fewest edges of a closed crease loop that [`Topology::crease_edges`] takes as a
/// rim at any length: a hole tessellated with 8 segments or more.
const MIN_RIM_EDGES: u32 = 8;

impl Topology {
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
    /// their vertices whose total length is at least `min_line_length`, or that closes
    /// into one loop of at least 8 edges (the rim of a small hole or boss).
    /// Isolated sharp edges of a noisy scan (a folded sliver, a spike) form short open
    /// sets and are kept.
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
        // A set that is one closed loop of at least `MIN_RIM_EDGES` edges (every vertex
        // on two of its edges) is a rim, a hole's or a boss's, however short: noise gives
        // open sets, stars around a spike and loops of a few edges.
        let mut degree = vec![0u32; nv];
        let mut edges = vec![0u32; nv];
        for (e, &[a, b]) in self.edges.iter().enumerate() {
            if cut[e] {
                degree[a as usize] += 1;
                degree[b as usize] += 1;
                edges[find_set(&mut parent, a) as usize] += 1;
            }
        }
        let mut open = vec![false; nv];
        for v in 0..nv {
            if degree[v] > 0 && degree[v] != 2 {
                open[find_set(&mut parent, v as u32) as usize] = true;
            }
        }
        for (e, &[a, _]) in self.edges.iter().enumerate() {
            let r = find_set(&mut parent, a) as usize;
            let rim = !open[r] && edges[r] >= MIN_RIM_EDGES;
            if cut[e] && !rim && length[r] < f64::from(min_line_length) {
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
