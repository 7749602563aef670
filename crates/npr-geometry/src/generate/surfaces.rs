//! Smooth analytic surfaces: tori (regular and jittered along the surface), spheres
//! (latitude–longitude and geodesic), an ellipsoid, a cylinder and a plane.

use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

use super::{jitter, param_grid, push_oriented};
use crate::Mesh;
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
