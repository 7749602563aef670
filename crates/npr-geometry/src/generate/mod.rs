//! Procedural meshes with exact analytic geometry: every vertex lies exactly on the
//! surface (up to `f32` rounding) and carries the surface's analytic unit normal.
//!
//! These are the test and benchmark fixtures (STYLE: procedural fixtures first): sphere,
//! cylinder, torus, ellipsoid, the (p, q) torus knot of the specular paper's Fig. 8
//! ([`paper_knot`], 2,880 faces), a plane, and [`benchmark_knot`] with about 1.1 million
//! triangles. Irregular variants ([`torus_jittered`], [`displace_along_normals`]) are
//! seeded and deterministic. Rigged models ([`bent_tube`], [`stretched_sphere`],
//! [`twisted_bar`]) come with a [`crate::animation::Rig`] and one clip.
//!
//! Parametric surfaces duplicate the render vertices on their UV seams; the duplicates
//! are evaluated from the same wrapped parameter, so their positions are bit-identical
//! and [`crate::weld()`] merges them. Triangles are counter-clockwise seen from the side
//! the normals point to (outside).

use glam::{DVec3, Vec2, Vec3};

use crate::Mesh;
use crate::rng::hashed_signed;
use crate::weld::position_key;

mod cad;
mod knot;
mod rigged;
mod surfaces;
#[cfg(test)]
mod tests;

pub use cad::{Bracket, box_with_hole, cad_parts, filleted_bracket, stepped_shaft};
pub use knot::{TorusKnot, benchmark_knot, paper_knot, torus_knot};
pub use rigged::{Rigged, bent_tube, stretched_sphere, swaying, twisted_bar};
pub use surfaces::{
    cylinder, ellipsoid, geodesic_sphere, icosphere, plane, torus, torus_jittered,
    torus_segments_for, uv_sphere,
};
/// Builds a (nu+1)×(nv+1) vertex grid. `eval(i, j)` gets wrapped indices when the
/// direction is periodic, so seam duplicates are bit-identical. Triangles whose
/// positions coincide (poles) are dropped; each triangle is oriented to agree with the
/// analytic normals.
fn param_grid(
    nu: usize,
    nv: usize,
    wrap_u: bool,
    wrap_v: bool,
    eval: impl Fn(usize, usize) -> (DVec3, DVec3),
) -> Mesh {
    let nu = nu.max(if wrap_u { 3 } else { 1 });
    let nv = nv.max(if wrap_v { 3 } else { 1 });
    let mut mesh = Mesh::default();
    for j in 0..=nv {
        for i in 0..=nu {
            let iw = if wrap_u { i % nu } else { i };
            let jw = if wrap_v { j % nv } else { j };
            let (p, n) = eval(iw, jw);
            mesh.positions.push(p.as_vec3());
            mesh.normals.push(n.normalize_or_zero().as_vec3());
            mesh.uvs
                .push(Vec2::new(i as f32 / nu as f32, 1.0 - j as f32 / nv as f32));
        }
    }
    let id = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            push_oriented(&mut mesh, [a, b, c]);
            push_oriented(&mut mesh, [a, c, d]);
        }
    }
    mesh
}

/// Appends a triangle unless two of its corners share a position, flipped if its
/// geometric normal disagrees with the sum of its vertex normals.
fn push_oriented(mesh: &mut Mesh, t: [u32; 3]) {
    let p = t.map(|i| mesh.positions[i as usize]);
    let k = p.map(position_key);
    if k[0] == k[1] || k[1] == k[2] || k[0] == k[2] {
        return;
    }
    let g = (p[1] - p[0]).cross(p[2] - p[0]);
    let n: Vec3 = t.iter().map(|&i| mesh.normals[i as usize]).sum();
    if g.dot(n) < 0.0 {
        mesh.indices.extend([t[0], t[2], t[1]]);
    } else {
        mesh.indices.extend(t);
    }
}

fn jitter(seed: u64, i: usize, j: usize, axis: u64) -> f64 {
    if seed == 0 {
        return 0.0;
    }
    hashed_signed(seed, ((i as u64) << 32 | j as u64) ^ (axis << 62))
}

/// Moves every vertex along its normal by a seeded uniform amount in
/// `[-amplitude, amplitude]` (world units), keyed by position so seam duplicates move
/// together, then recomputes normals from the new geometry (as a scan's would be).
pub fn displace_along_normals(mesh: &Mesh, amplitude: f32, seed: u64) -> Mesh {
    let mut out = mesh.clone();
    for (p, n) in out.positions.iter_mut().zip(&mesh.normals) {
        let k = position_key(*p);
        let key = (u64::from(k[0]) << 32 | u64::from(k[1])) ^ u64::from(k[2]).rotate_left(17);
        *p += *n * (amplitude * hashed_signed(seed, key) as f32);
    }
    out.recompute_normals();
    out
}
