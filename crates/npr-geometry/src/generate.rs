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
    /// The (2, 3) knot (a trefoil) in the specular paper's proportions (major radius 1,
    /// minor radius 0.4), with a tube of `tube_radius` and `segments × tube_segments`
    /// segments: [`paper_knot`], [`benchmark_knot`] and the figures' knots.
    pub fn trefoil(tube_radius: f32, segments: usize, tube_segments: usize) -> Self {
        Self {
            p: 2,
            q: 3,
            major_radius: 1.0,
            minor_radius: 0.4,
            tube_radius,
            segments,
            tube_segments,
        }
    }

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
    torus_knot(&TorusKnot::trefoil(0.15, 144, 10))
}

/// The large benchmark mesh: the same (2, 3) knot with 2,750 × 200 segments,
/// 550,000 vertices and 1,100,000 triangles (the warping paper's Buddha is 1,085,634).
pub fn benchmark_knot() -> Mesh {
    torus_knot(&TorusKnot::trefoil(0.15, 2750, 200))
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

/// `a` at `i = 0`, `b` at `i = n` (exactly, so shared boundary points of separately
/// generated patches weld), linear between.
fn lerp_ends(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == 0 {
        a
    } else if i >= n {
        b
    } else {
        a + (b - a) * (i as f64 / n as f64)
    }
}

/// Appends `src` to `dst` (indices shifted).
fn append(dst: &mut Mesh, src: Mesh) {
    let base = dst.positions.len() as u32;
    dst.positions.extend(src.positions);
    dst.normals.extend(src.normals);
    dst.uvs.extend(src.uvs);
    dst.indices
        .extend(src.indices.into_iter().map(|i| i + base));
}

/// A point of the circle of radius `radius` around the y axis at height `y`, at angle
/// `TAU · i / n`: one formula for every patch of [`stepped_shaft`], so rims weld.
fn ring_point(i: usize, n: usize, radius: f64, y: f64) -> DVec3 {
    let u = TAU * (i % n) as f64 / n as f64;
    DVec3::new(radius * u.cos(), y, radius * u.sin())
}

/// A flat annulus (or disc, `inner = 0`) around the y axis at height `y`, facing
/// `up` (+y) or down, `segments` around and `rows` from `inner` to `outer`.
fn annulus(segments: usize, rows: usize, inner: f64, outer: f64, y: f64, up: bool) -> Mesh {
    let n = if up { DVec3::Y } else { -DVec3::Y };
    param_grid(segments, rows, true, false, |i, j| {
        let r = lerp_ends(inner, outer, j, rows.max(1));
        (ring_point(i, segments.max(3), r, y), n)
    })
}

/// A CAD-style stepped shaft around the y axis (the procedural CAD parts):
/// coaxial cylinders `steps = [(radius, length), ...]` stacked from `y = −L/2` upwards
/// (L the total length), joined by flat annular shoulders, closed by flat discs. Every
/// face meets the next at a 90° crease; each flat face and each cylinder has its own
/// render vertices (hard edges), and shared rims weld exactly.
///
/// `segments` around (at least 3); rows along each cylinder and across each flat face
/// keep the triangles near square.
pub fn stepped_shaft(steps: &[(f32, f32)], segments: usize) -> Mesh {
    let nu = segments.max(3);
    let total: f64 = steps.iter().map(|s| f64::from(s.1.max(0.0))).sum();
    let mut mesh = Mesh::default();
    let mut y = -total / 2.0;
    let rows_for =
        |len: f64, r: f64| ((len / (TAU * r / nu as f64)).round() as usize).clamp(1, 256);
    let mut prev: Option<f64> = None;
    for (k, &(radius, length)) in steps.iter().enumerate() {
        let (r, len) = (f64::from(radius.max(1e-6)), f64::from(length.max(0.0)));
        let (y0, y1) = (
            y,
            if k + 1 == steps.len() {
                total / 2.0
            } else {
                y + len
            },
        );
        match prev {
            None => append(&mut mesh, annulus(nu, rows_for(r, r), 0.0, r, y0, false)),
            Some(p) if p != r => {
                let (inner, outer) = (p.min(r), p.max(r));
                // The shoulder faces up when the step below is the wider one.
                append(
                    &mut mesh,
                    annulus(nu, rows_for(outer - inner, outer), inner, outer, y0, p > r),
                );
            }
            Some(_) => {}
        }
        let rows = rows_for(len, r);
        append(
            &mut mesh,
            param_grid(nu, rows, true, false, |i, j| {
                let p = ring_point(i, nu, r, lerp_ends(y0, y1, j, rows));
                (p, DVec3::new(p.x, 0.0, p.z) / r)
            }),
        );
        if k + 1 == steps.len() {
            append(&mut mesh, annulus(nu, rows_for(r, r), 0.0, r, y1, true));
        }
        prev = Some(r);
        y = y1;
    }
    mesh
}

/// A CAD-style block with a round through-hole (the procedural CAD parts): the box
/// `[−a, a] × [−b, b] × [−c, c]` (`half_extents = (a, b, c)`) pierced along y by a
/// hole of radius `hole_radius` (clamped inside the footprint). Six flat faces (top and
/// bottom with the hole) and the hole's cylindrical wall, all meeting at 90° creases,
/// with their own render vertices.
///
/// `per_side` vertices along each side of the footprint; the hole's wall has
/// `4 · per_side` around, on the rays from the axis to the footprint's boundary points.
pub fn box_with_hole(half_extents: Vec3, hole_radius: f32, per_side: usize) -> Mesh {
    let h = half_extents.as_dvec3().abs().max(DVec3::splat(1e-6));
    let (a, b, c) = (h.x, h.y, h.z);
    let r = f64::from(hole_radius).clamp(1e-6, 0.95 * a.min(c));
    let n = per_side.max(2);
    let around = 4 * n;
    // Boundary point `g` of the footprint (xz), counter-clockwise seen from +y... in
    // order: side 0 (x = a), 1 (z = c), 2 (x = −a), 3 (z = −c).
    let square = |g: usize| {
        let (side, i) = ((g % around) / n, (g % around) % n);
        let s = lerp_ends(-1.0, 1.0, i, n);
        match side {
            0 => (a, s * c),
            1 => (-s * a, c),
            2 => (-a, -s * c),
            _ => (s * a, -c),
        }
    };
    let hole = |g: usize| {
        let (x, z) = square(g);
        let d = (x * x + z * z).sqrt();
        (r * x / d, r * z / d)
    };
    let gap = (a.min(c) - r).max(1e-6);
    let step = TAU * r / around as f64;
    let radial = ((gap / step).round() as usize).clamp(1, 64);
    let height_rows = ((2.0 * b / (2.0 * a.max(c) / n as f64)).round() as usize).clamp(1, 128);
    let mut mesh = Mesh::default();
    for (y, up) in [(b, true), (-b, false)] {
        let normal = if up { DVec3::Y } else { -DVec3::Y };
        append(
            &mut mesh,
            param_grid(around, radial, true, false, |g, j| {
                let (hx, hz) = hole(g);
                let (sx, sz) = square(g);
                let p = DVec3::new(
                    lerp_ends(hx, sx, j, radial),
                    y,
                    lerp_ends(hz, sz, j, radial),
                );
                (p, normal)
            }),
        );
    }
    append(
        &mut mesh,
        param_grid(around, height_rows, true, false, |g, j| {
            let (x, z) = hole(g);
            (
                DVec3::new(x, lerp_ends(-b, b, j, height_rows), z),
                DVec3::new(-x, 0.0, -z) / r,
            )
        }),
    );
    let side_normals = [DVec3::X, DVec3::Z, -DVec3::X, -DVec3::Z];
    for (side, normal) in side_normals.into_iter().enumerate() {
        append(
            &mut mesh,
            param_grid(n, height_rows, false, false, |i, j| {
                // i = n is the side's far corner, the next side's first point.
                let (x, z) = if i == n {
                    square((side + 1) * n)
                } else {
                    square(side * n + i)
                };
                (DVec3::new(x, lerp_ends(-b, b, j, height_rows), z), normal)
            }),
        );
    }
    mesh
}

/// Shape of a bent sheet-metal bracket; see [`filleted_bracket`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    /// Length of the vertical leg's flat part (along y).
    pub height: f32,
    /// Length of the horizontal leg's flat part (along x).
    pub length: f32,
    /// Extent along z.
    pub width: f32,
    /// Sheet thickness.
    pub thickness: f32,
    /// Inner radius of the 90° bend (the fillet).
    pub bend_radius: f32,
    /// Segments across the bend (90°).
    pub bend_segments: usize,
    /// Target edge length of the flat parts.
    pub edge: f32,
}

impl Default for Bracket {
    fn default() -> Self {
        Self {
            height: 1.2,
            length: 1.4,
            width: 1.0,
            thickness: 0.16,
            bend_radius: 0.25,
            bend_segments: 16,
            edge: 0.05,
        }
    }
}

/// A CAD-style L bracket bent from a sheet (the procedural CAD parts): a vertical
/// leg (outer face at `x = 0` side, normal −x) and a horizontal leg (outer face normal
/// −y) joined by a 90° bend of inner radius `bend_radius`, whose inner and outer faces
/// are coaxial cylinder quarters (fillets) tangent to the legs; extruded along z over
/// `[−width/2, width/2]`. Flat end caps (z = ±width/2, each one L-shaped face with a
/// curved corner) and the two cut ends of the sheet meet the rest at 90° creases.
pub fn filleted_bracket(k: &Bracket) -> Mesh {
    let t = f64::from(k.thickness.max(1e-4));
    let rc = f64::from(k.bend_radius.max(0.0)) + t / 2.0; // centreline radius
    let (hh, ll) = (f64::from(k.height.max(1e-4)), f64::from(k.length.max(1e-4)));
    let w = f64::from(k.width.max(1e-4)) / 2.0;
    let edge = f64::from(k.edge.max(1e-4));
    let nb = k.bend_segments.max(2);
    let n1 = ((hh / edge).round() as usize).clamp(1, 512);
    let n2 = ((ll / edge).round() as usize).clamp(1, 512);
    let na = n1 + nb + n2;
    let nz = ((2.0 * w / edge).round() as usize).clamp(1, 512);
    let nt = ((t / edge).round() as usize).clamp(1, 16);
    // Centreline point and its outward unit normal (away from the bend's axis) at
    // station a: the vertical leg x = 0 from y = rc + height down to y = rc, the bend
    // about (rc, rc), the horizontal leg y = 0 from x = rc to rc + length.
    let centre = |a: usize| -> (DVec3, DVec3) {
        if a <= n1 {
            let y = lerp_ends(rc + hh, rc, a, n1);
            (DVec3::new(0.0, y, 0.0), -DVec3::X)
        } else if a < n1 + nb {
            let phi = PI + 0.5 * PI * (a - n1) as f64 / nb as f64;
            let n = DVec3::new(phi.cos(), phi.sin(), 0.0);
            (DVec3::new(rc, rc, 0.0) + rc * n, n)
        } else {
            let x = lerp_ends(rc, rc + ll, a - n1 - nb, n2);
            (DVec3::new(x, 0.0, 0.0), -DVec3::Y)
        }
    };
    let side = |a: usize, s: f64| {
        let (p, n) = centre(a);
        p + n * (s * t / 2.0)
    };
    let mut mesh = Mesh::default();
    for s in [1.0, -1.0] {
        append(
            &mut mesh,
            param_grid(na, nz, false, false, |a, j| {
                let p = side(a, s);
                let (_, n) = centre(a);
                (DVec3::new(p.x, p.y, lerp_ends(-w, w, j, nz)), n * s)
            }),
        );
    }
    for (z, normal) in [(w, DVec3::Z), (-w, -DVec3::Z)] {
        append(
            &mut mesh,
            param_grid(na, nt, false, false, |a, j| {
                let (p, q) = (side(a, -1.0), side(a, 1.0));
                let x = lerp_ends(p.x, q.x, j, nt);
                let y = lerp_ends(p.y, q.y, j, nt);
                (DVec3::new(x, y, z), normal)
            }),
        );
    }
    for (a, normal) in [(0, DVec3::Y), (na, DVec3::X)] {
        append(
            &mut mesh,
            param_grid(nt, nz, false, false, |j, i| {
                let (p, q) = (side(a, -1.0), side(a, 1.0));
                let x = lerp_ends(p.x, q.x, j, nt);
                let y = lerp_ends(p.y, q.y, j, nt);
                (DVec3::new(x, y, lerp_ends(-w, w, i, nz)), normal)
            }),
        );
    }
    mesh
}

/// The CAD test part (13,864 triangles): a block with a through-hole,
/// a stepped shaft and a bent bracket side by side (three components), each with flat
/// faces, cylinders or fillets, and 90° creases. Shown in the gallery and measured by
/// `cargo xtask bench hatching-directions` and `hatching-coherence`.
pub fn cad_parts() -> Mesh {
    let mut mesh = Mesh::default();
    let place = |m: Mesh, offset: DVec3| {
        let mut m = m;
        let o = offset.as_vec3();
        m.positions.iter_mut().for_each(|p| *p += o);
        m
    };
    append(
        &mut mesh,
        place(
            box_with_hole(Vec3::new(0.7, 0.35, 0.55), 0.3, 14),
            DVec3::new(-1.5, -0.45, 0.2),
        ),
    );
    append(
        &mut mesh,
        place(
            stepped_shaft(&[(0.45, 0.35), (0.3, 0.7), (0.2, 0.5)], 48),
            DVec3::new(0.1, -0.1, -0.3),
        ),
    );
    append(
        &mut mesh,
        place(
            filleted_bracket(&Bracket {
                height: 0.9,
                length: 0.9,
                width: 0.8,
                thickness: 0.12,
                bend_radius: 0.2,
                bend_segments: 12,
                edge: 0.045,
            }),
            DVec3::new(1.0, -0.8, 0.1),
        ),
    );
    mesh
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
