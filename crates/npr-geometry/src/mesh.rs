//! The CPU triangle mesh shared by every crate: render vertices (position, normal, uv)
//! and `u32` triangle indices.

use glam::{Vec2, Vec3};

use crate::GeometryError;

/// An indexed triangle mesh as it is rendered: one entry per render vertex in
/// `positions`, `normals` and `uvs` (all the same length), three indices per triangle.
///
/// Render vertices may share a position (UV seams, hard edges); [`crate::weld()`] merges
/// them for topology and curvature while keeping this layout for drawing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Object-space positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals (outward for closed meshes).
    pub normals: Vec<Vec3>,
    /// Texture coordinates (zero where the source has none).
    pub uvs: Vec<Vec2>,
    /// Triangle list, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Number of render vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The triangles as index triples.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]])
    }

    /// Checks the invariants every consumer relies on: arrays of equal length, an index
    /// count divisible by 3, every index in range, every position and normal finite.
    ///
    /// # Errors
    /// [`GeometryError::Inconsistent`], [`GeometryError::IndexOutOfRange`] or
    /// [`GeometryError::NonFinite`] naming the first offender.
    pub fn validate(&self) -> Result<(), GeometryError> {
        let n = self.positions.len();
        if self.normals.len() != n || self.uvs.len() != n {
            return Err(GeometryError::Inconsistent(format!(
                "{n} positions, {} normals, {} uvs",
                self.normals.len(),
                self.uvs.len()
            )));
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(GeometryError::Inconsistent(format!(
                "{} indices is not a multiple of 3",
                self.indices.len()
            )));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NonFinite {
                vertex: i,
                what: "position",
            });
        }
        if let Some(i) = self.normals.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NonFinite {
                vertex: i,
                what: "normal",
            });
        }
        if let Some(k) = self.indices.iter().position(|&i| i as usize >= n) {
            return Err(GeometryError::IndexOutOfRange {
                triangle: k / 3,
                index: self.indices[k],
                vertex_count: n,
            });
        }
        Ok(())
    }

    /// Replaces `normals` by smooth area-weighted vertex normals computed from the
    /// triangles of the *welded* mesh, so render vertices split by a UV seam still get
    /// the same normal. Vertices without a non-degenerate triangle get `Vec3::Z`, so the
    /// array stays unit length.
    pub fn recompute_normals(&mut self) {
        let welded = crate::weld(self);
        let normals = welded_area_normals(&welded.positions, &welded.indices);
        self.normals = welded
            .render_to_welded
            .iter()
            .map(|&w| normals.get(w as usize).copied().unwrap_or(Vec3::Z))
            .collect();
    }

    /// This mesh with its render vertices split along its crease lines, each side
    /// with its own smooth normal ("auto-smooth"): a file without normals shares one
    /// vertex, and so one normal and one stroke direction, between the faces on either
    /// side of a sharp edge. The crease lines are [`crate::Topology::crease_edges`] of the
    /// welded mesh: edges bending by more than `crease_angle_deg` in lines at least
    /// `min_line_share · √(total area)` long (the stroke field's own cut,
    /// [`crate::StrokeFieldOptions::crease_angle_deg`] and
    /// [`crate::StrokeFieldOptions::min_crease_length`]), so a scan's isolated sharp
    /// edges stay smooth.
    ///
    /// Normals are the area-weighted normals of [`Mesh::recompute_normals`] over each
    /// fan of faces between creases: a vertex away from every crease line gets exactly the
    /// normal `recompute_normals` gives it. The first `vertex_count()` vertices are this
    /// mesh's (the copy on the side of each one's first face, uvs kept); the other sides'
    /// copies follow. Returns `None` when there is no crease line (the mesh stays as it
    /// is), else the split mesh and, per vertex of it, the vertex of `self` it copies.
    pub fn split_at_creases(
        &self,
        crease_angle_deg: f32,
        min_line_share: f32,
    ) -> Option<(Mesh, Vec<u32>)> {
        let welded = crate::weld(self);
        let topo = crate::Topology::new(&welded);
        let size = topo.area_scale();
        let split =
            topo.split_creases_longer_than(crease_angle_deg, min_line_share.max(0.0) * size);
        if split.topology.vertex_count() == topo.vertex_count() {
            return None;
        }
        let normals = welded_area_normals(&split.topology.positions, &split.topology.triangles);
        let n = self.vertex_count();
        // Per render vertex, the split vertex of its first face corner; other sides'
        // (render vertex, split vertex) pairs get new copies.
        let mut first = vec![u32::MAX; n];
        let mut extra: std::collections::HashMap<(u32, u32), u32> =
            std::collections::HashMap::new();
        let mut out = self.clone();
        let mut source: Vec<u32> = (0..n as u32).collect();
        for (c, index) in out.indices.iter_mut().enumerate() {
            let r = *index;
            let Some(&s) = split.topology.triangles.get(c / 3).map(|t| &t[c % 3]) else {
                continue;
            };
            if (r as usize) >= n || (s as usize) >= normals.len() {
                continue;
            }
            if first[r as usize] == u32::MAX {
                first[r as usize] = s;
                out.normals[r as usize] = normals[s as usize];
            } else if first[r as usize] != s {
                *index = *extra.entry((r, s)).or_insert_with(|| {
                    source.push(r);
                    out.positions.push(self.positions[r as usize]);
                    out.normals.push(normals[s as usize]);
                    out.uvs.push(self.uvs[r as usize]);
                    (source.len() - 1) as u32
                });
            }
        }
        Some((out, source))
    }
}

/// Area-weighted vertex normals (sum of unnormalised face cross products, normalised);
/// `Vec3::Z` where the sum vanishes (isolated vertex, degenerate fan). Triangles with an
/// index past `positions` are skipped.
pub fn welded_area_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut acc = vec![glam::DVec3::ZERO; positions.len()];
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i as usize] += n;
        }
    }
    acc.into_iter()
        .map(|n| n.try_normalize().map_or(Vec3::Z, |n| n.as_vec3()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recompute_normals_skips_out_of_range_indices() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::ZERO; 3],
            uvs: vec![],
            indices: vec![0, 1, 2, 0, 1, 99],
        };
        m.recompute_normals();
        assert_eq!(m.normals, vec![Vec3::Z; 3]);
    }
}
