//! Welding render vertices into a topological mesh: render vertices that share a
//! position (UV seams, hard-edge splits, per-face normals as in many OBJ exports) become
//! one welded vertex, so that edges, dihedral angles and curvature see one surface.

use glam::Vec3;

use crate::Mesh;

/// A welded mesh: unique positions, triangles over them, and the map back to the render
/// vertices of the [`Mesh`] it came from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Welded {
    /// One position per welded vertex, in order of first appearance among the render
    /// vertices.
    pub positions: Vec<Vec3>,
    /// Triangles over welded vertices (same order and winding as the render triangles).
    pub indices: Vec<[u32; 3]>,
    /// For each render vertex, its welded vertex.
    pub render_to_welded: Vec<u32>,
}

/// The bit pattern used as a weld key: exact position equality, with `-0.0` read as
/// `0.0` so mirrored exporters still weld.
pub(crate) fn position_key(p: Vec3) -> [u32; 3] {
    let f = |x: f32| if x == 0.0 { 0u32 } else { x.to_bits() };
    [f(p.x), f(p.y), f(p.z)]
}

/// Merges render vertices with bit-identical positions (`-0.0 == 0.0`).
///
/// Exact equality is deliberate: exporters write seam duplicates from the same number,
/// and an epsilon would silently fuse genuinely distinct nearby vertices (thin shells).
/// Procedural generators in [`crate::generate`] evaluate seam vertices from the same
/// wrapped parameter, so their seams weld exactly. An out-of-range render index maps to
/// `u32::MAX`, which [`crate::Topology`] treats as a degenerate face; call
/// [`Mesh::validate`] first for untrusted meshes (it also rejects NaN positions, which
/// here weld only with bit-identical NaNs).
pub fn weld(mesh: &Mesh) -> Welded {
    let n = mesh.positions.len();
    // Sort render vertices by key: O(n log n), no hashing, deterministic.
    let mut order: Vec<u32> = (0..n as u32).collect();
    let keys: Vec<[u32; 3]> = mesh.positions.iter().map(|&p| position_key(p)).collect();
    order.sort_unstable_by_key(|&i| (keys[i as usize], i));
    // Representative of each run = the smallest render index (first appearance).
    let mut rep = vec![0u32; n];
    let mut k = 0;
    while k < n {
        let first = order[k];
        let mut e = k;
        while e < n && keys[order[e] as usize] == keys[first as usize] {
            rep[order[e] as usize] = first;
            e += 1;
        }
        k = e;
    }
    let mut render_to_welded = vec![u32::MAX; n];
    let mut positions = Vec::new();
    for i in 0..n {
        let r = rep[i] as usize;
        if r == i {
            render_to_welded[i] = positions.len() as u32;
            positions.push(mesh.positions[i]);
        } else {
            render_to_welded[i] = render_to_welded[r];
        }
    }
    let indices = mesh
        .triangles()
        .map(|t| {
            t.map(|i| {
                render_to_welded
                    .get(i as usize)
                    .copied()
                    .unwrap_or(u32::MAX)
            })
        })
        .collect();
    Welded {
        positions,
        indices,
        render_to_welded,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn seam_duplicates_merge_and_map_back() {
        let p = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::new(-0.0, 0.0, 0.0),
        ];
        let mesh = Mesh {
            positions: p.to_vec(),
            normals: vec![Vec3::Z; 5],
            uvs: vec![Vec2::ZERO; 5],
            indices: vec![0, 1, 2, 4, 2, 3],
        };
        let w = weld(&mesh);
        assert_eq!(w.positions.len(), 3);
        assert_eq!(w.render_to_welded, vec![0, 1, 2, 1, 0]);
        assert_eq!(w.indices, vec![[0, 1, 2], [0, 2, 1]]);
    }
}
