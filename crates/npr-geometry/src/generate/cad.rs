//! CAD-like parts with creases and flat faces (procedural fixtures for hard edges): a
//! stepped shaft, a block with a through-hole, a bent bracket, and all three together.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3};

use super::param_grid;
use crate::Mesh;
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
