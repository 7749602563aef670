//! Procedural meshes with exact analytic geometry: every vertex lies exactly on the
//! surface (up to `f32` rounding) and carries the surface's analytic unit normal.
//!
//! These are the test and benchmark fixtures (STYLE: procedural fixtures first): sphere,
//! cylinder, torus, ellipsoid, the (p, q) torus knot of the specular paper's Fig. 8
//! ([`paper_knot`], 2,880 faces), a plane, and [`benchmark_knot`] with about 1.1 million
//! triangles. Irregular variants ([`torus_jittered`], [`displace_along_normals`]) are
//! seeded and deterministic.
//!
//! Parametric surfaces duplicate the render vertices on their UV seams; the duplicates
//! are evaluated from the same wrapped parameter, so their positions are bit-identical
//! and [`crate::weld()`] merges them. Triangles are counter-clockwise seen from the side
//! the normals point to (outside).

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

use crate::Mesh;
use crate::rng::hashed_signed;
use crate::weld::position_key;

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

/// Torus around the y axis: major radius `major_radius` (centre of the tube to the
/// axis), minor radius `minor_radius` (the tube), `major_segments × minor_segments`
/// welded vertices, twice as many triangles.
///
/// Point at angles (u, v): `((R + r cos v) cos u, r sin v, (R + r cos v) sin u)`;
/// principal curvatures `1/r` (meridian) and `cos v / (R + r cos v)` (parallel).
pub fn torus(
    major_radius: f32,
    minor_radius: f32,
    major_segments: usize,
    minor_segments: usize,
) -> Mesh {
    torus_jittered(
        major_radius,
        minor_radius,
        major_segments,
        minor_segments,
        0.0,
        0,
    )
}

/// A torus whose vertices are moved *along the surface*: each parameter (u, v) moves by
/// up to `jitter` × its grid spacing (uniform, seeded). Positions and normals stay exact,
/// triangle shapes become irregular. `jitter = 0` or `seed = 0` gives [`torus`].
pub fn torus_jittered(
    major_radius: f32,
    minor_radius: f32,
    major_segments: usize,
    minor_segments: usize,
    jitter_fraction: f32,
    seed: u64,
) -> Mesh {
    let (big_r, r) = (f64::from(major_radius), f64::from(minor_radius));
    let (nu, nv) = (major_segments.max(3), minor_segments.max(3));
    let (du, dv) = (TAU / nu as f64, TAU / nv as f64);
    let jf = f64::from(jitter_fraction);
    param_grid(nu, nv, true, true, |i, j| {
        let u = i as f64 * du + jf * du * jitter(seed, i, j, 0);
        let v = j as f64 * dv + jf * dv * jitter(seed, i, j, 1);
        let n = DVec3::new(v.cos() * u.cos(), v.sin(), v.cos() * u.sin());
        let p = DVec3::new(big_r * u.cos(), 0.0, big_r * u.sin()) + r * n;
        (p, n)
    })
}

/// Segment counts for a torus with about `vertices` vertices and near-equilateral grid
/// cells (`major_segments / minor_segments ≈ R / r`).
pub fn torus_segments_for(major_radius: f32, minor_radius: f32, vertices: usize) -> (usize, usize) {
    let ratio = f64::from(major_radius / minor_radius).max(1.0);
    let nv = ((vertices as f64 / ratio).sqrt().round() as usize).max(3);
    let nu = ((vertices as f64 / nv as f64).round() as usize).max(3);
    (nu, nv)
}

/// Latitude–longitude sphere of radius `radius` centred at the origin, `segments`
/// around the y axis and `rings` from pole to pole. The poles are single welded
/// vertices (their degenerate triangles are dropped).
pub fn uv_sphere(radius: f32, segments: usize, rings: usize) -> Mesh {
    let r = f64::from(radius);
    let nv = rings.max(2);
    param_grid(segments.max(3), nv, true, false, |i, j| {
        if j == 0 || j == nv {
            let n = if j == 0 { DVec3::Y } else { -DVec3::Y };
            return (r * n, n);
        }
        let u = TAU * i as f64 / segments.max(3) as f64;
        let t = PI * j as f64 / nv as f64;
        let n = DVec3::new(t.sin() * u.cos(), t.cos(), t.sin() * u.sin());
        (r * n, n)
    })
}

/// Geodesic sphere: an icosahedron with each face split into `frequency²` triangles,
/// vertices projected onto the sphere. `10·f² + 2` vertices, `20·f²` triangles.
pub fn geodesic_sphere(frequency: usize, radius: f32) -> Mesh {
    let mut m = unit_geodesic(frequency);
    for p in &mut m.positions {
        *p *= radius;
    }
    m
}

/// Icosphere with `subdivisions` levels of 1→4 splitting (frequency `2^subdivisions`):
/// `10·4^s + 2` vertices (s = 5: 10,242). Normals are the exact radial directions.
pub fn icosphere(subdivisions: u32, radius: f32) -> Mesh {
    geodesic_sphere(1usize << subdivisions.min(12), radius)
}

/// Ellipsoid `x²/a² + y²/b² + z²/c² = 1` made by stretching a geodesic sphere of
/// `frequency` (about `10·f²` vertices), with the exact normals `∇F / |∇F|`.
pub fn ellipsoid(a: f32, b: f32, c: f32, frequency: usize) -> Mesh {
    let mut m = unit_geodesic(frequency);
    let s = Vec3::new(a, b, c);
    for (p, n) in m.positions.iter_mut().zip(&mut m.normals) {
        let u = *p;
        *p = u * s;
        *n = (u / s).normalize_or_zero();
    }
    m
}

fn unit_geodesic(frequency: usize) -> Mesh {
    let f = frequency.max(1);
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let v: [DVec3; 12] = [
        DVec3::new(-1.0, t, 0.0),
        DVec3::new(1.0, t, 0.0),
        DVec3::new(-1.0, -t, 0.0),
        DVec3::new(1.0, -t, 0.0),
        DVec3::new(0.0, -1.0, t),
        DVec3::new(0.0, 1.0, t),
        DVec3::new(0.0, -1.0, -t),
        DVec3::new(0.0, 1.0, -t),
        DVec3::new(t, 0.0, -1.0),
        DVec3::new(t, 0.0, 1.0),
        DVec3::new(-t, 0.0, -1.0),
        DVec3::new(-t, 0.0, 1.0),
    ]
    .map(|p| p.normalize());
    const FACES: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mesh = Mesh::default();
    let mut ids: HashMap<u64, u32> = HashMap::new();
    let mut vertex = |mesh: &mut Mesh, w: [(usize, usize); 3]| -> u32 {
        // Canonical key: (corner id, weight) pairs sorted by corner id, zero weights out.
        let mut e: Vec<(usize, usize)> = w.into_iter().filter(|x| x.1 > 0).collect();
        e.sort_unstable();
        let key = e.iter().fold(0u64, |k, &(id, wt)| {
            (k << 21) | ((id as u64) << 16) | wt as u64
        });
        *ids.entry(key).or_insert_with(|| {
            let p: DVec3 = e.iter().map(|&(id, wt)| v[id] * wt as f64).sum::<DVec3>() / f as f64;
            let n = p.normalize();
            mesh.positions.push(n.as_vec3());
            mesh.normals.push(n.as_vec3());
            let uv = Vec2::new(
                (0.5 + n.z.atan2(n.x) / TAU) as f32,
                (n.y.clamp(-1.0, 1.0).acos() / PI) as f32,
            );
            mesh.uvs.push(uv);
            (mesh.positions.len() - 1) as u32
        })
    };
    for [a, b, c] in FACES {
        let mut at =
            |mesh: &mut Mesh, i: usize, j: usize| vertex(mesh, [(a, f - i - j), (b, i), (c, j)]);
        for i in 0..f {
            for j in 0..f - i {
                let t0 = [
                    at(&mut mesh, i, j),
                    at(&mut mesh, i + 1, j),
                    at(&mut mesh, i, j + 1),
                ];
                push_oriented(&mut mesh, t0);
                if i + j + 1 < f {
                    let t1 = [
                        at(&mut mesh, i + 1, j),
                        at(&mut mesh, i + 1, j + 1),
                        at(&mut mesh, i, j + 1),
                    ];
                    push_oriented(&mut mesh, t1);
                }
            }
        }
    }
    mesh
}

/// Open or capped cylinder around the y axis, from `y = -height/2` to `height/2`:
/// `segments` around, `rings` rows of quads along the axis.
///
/// Open (`capped = false`): only the side, with boundary loops at both ends (curvature
/// there is one-sided; test interior vertices). Capped: each end is closed by a flat
/// disc fan with its own vertices and normals `±y`, which weld to the side ring and form
/// a 90° crease.
pub fn cylinder(radius: f32, height: f32, segments: usize, rings: usize, capped: bool) -> Mesh {
    let (r, h) = (f64::from(radius), f64::from(height));
    let nu = segments.max(3);
    let nv = rings.max(1);
    let mut mesh = param_grid(nu, nv, true, false, |i, j| {
        let u = TAU * i as f64 / nu as f64;
        let n = DVec3::new(u.cos(), 0.0, u.sin());
        (
            DVec3::new(0.0, -h / 2.0 + h * j as f64 / nv as f64, 0.0) + r * n,
            n,
        )
    });
    if capped {
        for (y, n) in [(-h / 2.0, -Vec3::Y), (h / 2.0, Vec3::Y)] {
            let centre = mesh.positions.len() as u32;
            mesh.positions.push(Vec3::new(0.0, y as f32, 0.0));
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::splat(0.5));
            for i in 0..nu {
                let u = TAU * i as f64 / nu as f64;
                // Same arithmetic as the side ring so the rims weld exactly.
                let p = DVec3::new(0.0, y, 0.0) + r * DVec3::new(u.cos(), 0.0, u.sin());
                mesh.positions.push(p.as_vec3());
                mesh.normals.push(n);
                mesh.uvs.push(Vec2::new(
                    0.5 + 0.5 * u.cos() as f32,
                    0.5 + 0.5 * u.sin() as f32,
                ));
            }
            for i in 0..nu as u32 {
                let a = centre + 1 + i;
                let b = centre + 1 + (i + 1) % nu as u32;
                push_oriented(&mut mesh, [centre, a, b]);
            }
        }
    }
    mesh
}

/// Square grid in the xz plane (y = 0, normal +y), centred at the origin,
/// `size_x × size_z`, with `nx × nz` cells (two triangles each).
pub fn plane(size_x: f32, size_z: f32, nx: usize, nz: usize) -> Mesh {
    let (sx, sz) = (f64::from(size_x), f64::from(size_z));
    let (nx, nz) = (nx.max(1), nz.max(1));
    param_grid(nx, nz, false, false, |i, j| {
        let p = DVec3::new(
            sx * (i as f64 / nx as f64 - 0.5),
            0.0,
            sz * (0.5 - j as f64 / nz as f64),
        );
        (p, DVec3::Y)
    })
}

/// Shape of a (p, q) torus knot tube; see [`torus_knot`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorusKnot {
    /// Windings around the y axis.
    pub p: u32,
    /// Windings through the hole.
    pub q: u32,
    /// Radius of the torus the curve winds on (axis to tube centre line).
    pub major_radius: f32,
    /// Radius of the curve's winding around that torus' core circle.
    pub minor_radius: f32,
    /// Radius of the tube around the curve.
    pub tube_radius: f32,
    /// Segments along the curve.
    pub segments: usize,
    /// Segments around the tube.
    pub tube_segments: usize,
}

impl TorusKnot {
    /// Centre line `c(t)`, its first and second derivatives, t ∈ [0, 2π).
    fn curve(&self, t: f64) -> [DVec3; 3] {
        let (p, q) = (f64::from(self.p), f64::from(self.q));
        let (big_r, a) = (f64::from(self.major_radius), f64::from(self.minor_radius));
        let (sq, cq) = (q * t).sin_cos();
        let (sp, cp) = (p * t).sin_cos();
        let rho = big_r + a * cq;
        let d_rho = -a * q * sq;
        let dd_rho = -a * q * q * cq;
        let c = DVec3::new(rho * cp, a * sq, rho * sp);
        let d = DVec3::new(
            d_rho * cp - rho * p * sp,
            a * q * cq,
            d_rho * sp + rho * p * cp,
        );
        let dd = DVec3::new(
            dd_rho * cp - 2.0 * d_rho * p * sp - rho * p * p * cp,
            -a * q * q * sq,
            dd_rho * sp + 2.0 * d_rho * p * cp - rho * p * p * sp,
        );
        [c, d, dd]
    }
}

/// A tube of constant radius around a (p, q) torus knot, using the curve's Frenet frame
/// (periodic, so the tube closes without a twist seam). The normal of a constant-radius
/// tube is exactly the offset direction, so normals are analytic.
/// `segments × tube_segments` vertices, twice as many triangles.
pub fn torus_knot(k: &TorusKnot) -> Mesh {
    let nu = k.segments.max(3);
    let nv = k.tube_segments.max(3);
    let tube = f64::from(k.tube_radius);
    param_grid(nu, nv, true, true, |i, j| {
        let t = TAU * i as f64 / nu as f64;
        let [c, d, dd] = k.curve(t);
        let tan = d.normalize();
        let b = d
            .cross(dd)
            .try_normalize()
            .unwrap_or_else(|| tan.any_orthonormal_vector());
        let n = b.cross(tan);
        let th = TAU * j as f64 / nv as f64;
        let dir = th.cos() * n + th.sin() * b;
        (c + tube * dir, dir)
    })
}

/// The specular paper's test knot (§5, Fig. 8, Table 1: 2,880 faces): a (2, 3) torus
/// knot tube with 144 segments along the curve and 10 around, 1,440 vertices.
pub fn paper_knot() -> Mesh {
    torus_knot(&TorusKnot {
        p: 2,
        q: 3,
        major_radius: 1.0,
        minor_radius: 0.4,
        tube_radius: 0.15,
        segments: 144,
        tube_segments: 10,
    })
}

/// The large benchmark mesh: the same (2, 3) knot with 2,750 × 200 segments,
/// 550,000 vertices and 1,100,000 triangles (the warping paper's Buddha is 1,085,634).
pub fn benchmark_knot() -> Mesh {
    torus_knot(&TorusKnot {
        p: 2,
        q: 3,
        major_radius: 1.0,
        minor_radius: 0.4,
        tube_radius: 0.15,
        segments: 2750,
        tube_segments: 200,
    })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::weld;

    #[test]
    fn counts_and_seams_weld() {
        let t = torus(2.0, 0.7, 30, 12);
        assert_eq!(weld(&t).positions.len(), 360);
        assert_eq!(t.triangle_count(), 720);
        let s = icosphere(2, 1.0);
        assert_eq!(s.positions.len(), 162);
        assert_eq!(s.triangle_count(), 320);
        assert_eq!(weld(&s).positions.len(), 162);
        let k = paper_knot();
        assert_eq!(k.triangle_count(), 2880);
        assert_eq!(weld(&k).positions.len(), 1440);
        let u = uv_sphere(1.0, 16, 8);
        assert_eq!(weld(&u).positions.len(), 16 * 7 + 2);
        assert_eq!(u.triangle_count(), 16 * 7 * 2);
        let c = cylinder(1.0, 2.0, 16, 4, true);
        assert_eq!(weld(&c).positions.len(), 16 * 5 + 2);
        for m in [
            t,
            s,
            k,
            u,
            c,
            plane(1.0, 1.0, 3, 3),
            ellipsoid(2.0, 1.2, 0.8, 4),
        ] {
            m.validate().unwrap();
        }
    }

    #[test]
    fn winding_agrees_with_normals() {
        for m in [
            torus(2.0, 0.7, 30, 12),
            paper_knot(),
            ellipsoid(2.0, 1.2, 0.8, 5),
        ] {
            for t in m.triangles() {
                let p = t.map(|i| m.positions[i as usize]);
                let g = (p[1] - p[0]).cross(p[2] - p[0]);
                assert!(g.dot(m.normals[t[0] as usize]) > 0.0);
            }
        }
    }
}
