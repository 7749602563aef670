//! Reordering a mesh for memory locality: triangles in meshoptimizer's
//! vertex-cache order (each triangle shares vertices with the ones just before it, so a
//! walk over neighbouring faces, as the §4.2 visibility search and the region growth do,
//! touches nearby memory), then vertices in order of first use (meshoptimizer's fetch
//! order). The same surface: every triangle keeps its corners, their attributes and its
//! winding; only indices change (vertices no triangle uses are dropped). Also what a GPU wants for its post-transform cache.

use crate::Mesh;
use glam::Vec3;

/// The Morton (Z-order) code of each point: 10 bits an axis over the finite points'
/// bounding box, interleaved x, y, z from the lowest bit; `u32::MAX` for a non-finite
/// point. Sorting by it puts points that are near in space mostly near in the order
/// (the search's clusters of vertices and of faces are runs of it).
pub fn morton_codes(points: &[Vec3]) -> Vec<u32> {
    let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let extent = (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let spread_bits = |x: u32| {
        let mut x = x & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    };
    points
        .iter()
        .map(|&p| {
            if !p.is_finite() {
                return u32::MAX;
            }
            let q = ((p - lo) / extent * 1023.0).clamp(Vec3::ZERO, Vec3::splat(1023.0));
            spread_bits(q.x as u32)
                | (spread_bits(q.y as u32) << 1)
                | (spread_bits(q.z as u32) << 2)
        })
        .collect()
}

/// What [`reorder_for_locality`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reordered {
    /// The reordered mesh.
    pub mesh: Mesh,
    /// For each triangle of `mesh`, its index in the input.
    pub triangle_from_input: Vec<u32>,
    /// For each vertex of the input, its index in `mesh` (`u32::MAX` for a vertex no
    /// triangle uses, which is dropped).
    pub vertex_to_output: Vec<u32>,
}

/// `mesh` with triangles and vertices reordered for locality (see the module docs). A
/// mesh whose indices are not a valid triangle list (length not a multiple of three, or
/// an index past the vertices) is returned as it is, with identity maps.
pub fn reorder_for_locality(mesh: &Mesh) -> Reordered {
    let nv = mesh.positions.len();
    let identity = || Reordered {
        mesh: mesh.clone(),
        triangle_from_input: (0..(mesh.indices.len() / 3) as u32).collect(),
        vertex_to_output: (0..nv as u32).collect(),
    };
    let attributes_fit = |n: usize| n == 0 || n == nv;
    if mesh.indices.is_empty()
        || !mesh.indices.len().is_multiple_of(3)
        || mesh.indices.iter().any(|&i| i as usize >= nv)
        || !attributes_fit(mesh.normals.len())
        || !attributes_fit(mesh.uvs.len())
        || u32::try_from(nv).is_err()
    {
        return identity();
    }
    let cached = optimize_vertex_cache(&mesh.indices, nv);
    let triangle_from_input = match triangle_order(&mesh.indices, &cached) {
        Some(order) => order,
        None => return identity(),
    };
    // Vertices in order of first use (what meshoptimizer's fetch remap computes; its
    // Rust wrapper truncates the table when a vertex is unused, so it is done here).
    let mut remap = vec![u32::MAX; nv];
    let mut used = 0usize;
    for &i in &cached {
        let r = &mut remap[i as usize];
        if *r == u32::MAX {
            *r = used as u32;
            used += 1;
        }
    }
    let place = |values: &[glam::Vec3]| {
        let mut out = vec![glam::Vec3::ZERO; used];
        for (v, &r) in remap.iter().enumerate() {
            if r != u32::MAX {
                out[r as usize] = values[v];
            }
        }
        out
    };
    let mut uvs = vec![glam::Vec2::ZERO; if mesh.uvs.is_empty() { 0 } else { used }];
    for (v, &r) in remap.iter().enumerate() {
        if r != u32::MAX && !mesh.uvs.is_empty() {
            uvs[r as usize] = mesh.uvs[v];
        }
    }
    let out = Mesh {
        positions: place(&mesh.positions),
        normals: if mesh.normals.is_empty() {
            Vec::new()
        } else {
            place(&mesh.normals)
        },
        uvs,
        indices: cached.iter().map(|&i| remap[i as usize]).collect(),
    };
    Reordered {
        mesh: out,
        triangle_from_input,
        vertex_to_output: remap,
    }
}

/// For each triangle of `reordered` (a permutation of `input`'s triangles, each possibly
/// rotated), its index in `input`; `None` if it is not one.
fn triangle_order(input: &[u32], reordered: &[u32]) -> Option<Vec<u32>> {
    use std::collections::HashMap;
    // Key: the triangle rotated to start at its smallest index (winding kept).
    let key = |t: &[u32]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
    };
    let mut slots: HashMap<[u32; 3], Vec<u32>> = HashMap::with_capacity(input.len() / 3);
    for (f, t) in input.chunks_exact(3).enumerate().rev() {
        slots.entry(key(t)).or_default().push(f as u32);
    }
    reordered
        .chunks_exact(3)
        .map(|t| slots.get_mut(&key(t))?.pop())
        .collect()
}

/// meshoptimizer's vertex-cache optimizer: the C++ library on native, its pure-Rust port
/// on wasm32 (the same algorithm; no C++ toolchain targets the browser).
#[cfg(not(target_arch = "wasm32"))]
fn optimize_vertex_cache(indices: &[u32], vertex_count: usize) -> Vec<u32> {
    meshopt::optimize_vertex_cache(indices, vertex_count)
}

#[cfg(target_arch = "wasm32")]
fn optimize_vertex_cache(indices: &[u32], vertex_count: usize) -> Vec<u32> {
    let mut out = vec![0; indices.len()];
    meshopt_rs::vertex::cache::optimize_vertex_cache(&mut out, indices, vertex_count);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    fn corners(m: &Mesh, f: usize) -> [(Vec3, Vec3, Vec2); 3] {
        let at = |k: usize| {
            let v = m.indices[3 * f + k] as usize;
            (
                m.positions[v],
                m.normals.get(v).copied().unwrap_or(Vec3::ZERO),
                m.uvs.get(v).copied().unwrap_or(Vec2::ZERO),
            )
        };
        [at(0), at(1), at(2)]
    }

    /// Same corners in the same cyclic order.
    fn same_triangle(a: [(Vec3, Vec3, Vec2); 3], b: [(Vec3, Vec3, Vec2); 3]) -> bool {
        (0..3).any(|r| (0..3).all(|k| a[k] == b[(k + r) % 3]))
    }

    #[test]
    fn every_triangle_keeps_its_corners_and_winding() {
        let mut mesh = crate::generate::torus(1.0, 0.4, 40, 16);
        mesh.uvs = mesh.positions.iter().map(|p| Vec2::new(p.x, p.y)).collect();
        // Scramble the triangle order so there is something to do, and add an unused
        // vertex (dropped), a duplicated triangle (kept twice) and degenerate ones.
        let tris: Vec<[u32; 3]> = mesh.triangles().collect();
        let mut order: Vec<usize> = (0..tris.len()).collect();
        order.sort_by_key(|&f| (f * 7919) % tris.len());
        mesh.indices = order.iter().flat_map(|&f| tris[f]).collect();
        mesh.indices.extend_from_slice(&tris[3]);
        // Degenerate triangles (a repeated corner, one point) are kept as they are.
        let (a, b) = (tris[5][0], tris[5][1]);
        mesh.indices.extend_from_slice(&[a, a, b, b, b, b]);
        mesh.positions.push(Vec3::splat(9.0));
        mesh.normals.push(Vec3::Z);
        mesh.uvs.push(Vec2::ONE);
        let r = reorder_for_locality(&mesh);
        assert_eq!(r.mesh.indices.len(), mesh.indices.len());
        assert_eq!(r.mesh.positions.len(), mesh.positions.len() - 1);
        assert_eq!(
            r.vertex_to_output[mesh.positions.len() - 1],
            u32::MAX,
            "the unused vertex is dropped"
        );
        let mut seen = vec![false; mesh.indices.len() / 3];
        for (f, &g) in r.triangle_from_input.iter().enumerate() {
            assert!(!seen[g as usize], "input triangle {g} used twice");
            seen[g as usize] = true;
            assert!(
                same_triangle(corners(&r.mesh, f), corners(&mesh, g as usize)),
                "triangle {f} is not input triangle {g}"
            );
        }
        assert!(seen.iter().all(|&s| s));
        // Vertices in order of first use: the first triangle uses 0, 1, 2.
        let mut first = r.mesh.indices[..3].to_vec();
        first.sort_unstable();
        assert_eq!(first, vec![0, 1, 2]);
        for (v, &o) in r.vertex_to_output.iter().enumerate() {
            if o != u32::MAX {
                assert_eq!(r.mesh.positions[o as usize], mesh.positions[v]);
            }
        }
    }

    #[test]
    fn invalid_index_lists_come_back_unchanged() {
        let mut mesh = crate::generate::icosphere(1, 1.0);
        mesh.indices.push(0);
        assert_eq!(reorder_for_locality(&mesh).mesh, mesh);
        let mut mesh = crate::generate::icosphere(1, 1.0);
        let n = mesh.positions.len() as u32;
        mesh.indices[4] = n;
        assert_eq!(reorder_for_locality(&mesh).mesh, mesh);
        let empty = Mesh::default();
        assert_eq!(reorder_for_locality(&empty).mesh, empty);
    }
}
