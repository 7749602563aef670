//! One face measured against a seed's region: the per-frame vertex values, the face's
//! class and its moments (whole, clipped once, or sampled on a sub-grid).

use super::RegionFrame;
#[cfg(test)]
use super::classify::SUB;
use super::classify::{
    EXACT_H_TURN, FaceClass, GRID_POINTS, classify, for_sub_triangles, grid_points,
};
use super::fit::Moments;
use super::grow::{Part, RegionGrower};
use glam::{Mat3, Vec2, Vec3};
use npr_geometry::LightEye;

impl RegionGrower {
    /// World position, unit world normal and `N·H` of vertex `v` (cached for the frame).
    #[inline]
    pub(super) fn vertex(
        &mut self,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        v: usize,
    ) -> (Vec3, Vec3, f32) {
        if self.vertices[v].frame != self.frame {
            self.compute_vertex(f, normal_from_object, v);
        }
        let c = &self.vertices[v];
        (c.world, c.normal, c.nh)
    }

    #[inline(never)]
    fn compute_vertex(&mut self, f: &RegionFrame<'_>, normal_from_object: Mat3, v: usize) {
        let p = f
            .world_from_object
            .transform_point3(f.topology.positions[v]);
        let n = (normal_from_object * f.normals.get(v).copied().unwrap_or(Vec3::ZERO))
            .normalize_or_zero();
        // H and, for a point light and eye, the distances to them and |L̂ + V̂| (one
        // square root each).
        let (h, dist) = match f.light_eye {
            LightEye::Positions { light, eye } => {
                let (l, e) = (light - p, eye - p);
                let (dl, de) = (l.length(), e.length());
                let s = l / dl + e / de;
                let ds = s.length();
                let h = if dl > 0.0 && de > 0.0 && ds > 0.0 && ds.is_finite() {
                    s / ds
                } else {
                    f.light_eye.half_vector(p)
                };
                (h, [dl, de, ds])
            }
            LightEye::Directions { .. } => (f.light_eye.half_vector(p), [0.0; 3]),
        };
        let nh = n.dot(h);
        self.vertices[v] = VertexCache {
            frame: self.frame,
            nh: if nh.is_finite() { nh } else { -1.0 },
            world: p,
            normal: n,
            h,
            dist,
        };
    }

    /// Measures face `fi` against seed `part`'s region: its moments and the smallest cos
    /// of its normals (where in the region) with the axis, or `None` when the region does
    /// not take it (facing away, degenerate or outside; the growth stops there).
    pub(super) fn measure(
        &mut self,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        fi: usize,
        part: &Part,
    ) -> Option<(Moments, f32)> {
        let topo = f.topology;
        let (n, e_u, e_v) = part.frame;
        if topo.is_degenerate(fi) || (normal_from_object * topo.face_normals[fi]).dot(n) <= 0.0 {
            return None;
        }
        let tri = topo.triangles[fi];
        let vs = [
            self.vertex(f, normal_from_object, tri[0] as usize),
            self.vertex(f, normal_from_object, tri[1] as usize),
            self.vertex(f, normal_from_object, tri[2] as usize),
        ];
        let (sigma, origin) = (part.sigma, part.origin);
        let project = |p: Vec3| {
            let q = p - origin;
            Vec2::new(q.dot(e_u), q.dot(e_v))
        };
        let dists = [
            self.vertices[tri[0] as usize].dist,
            self.vertices[tri[1] as usize].dist,
            self.vertices[tri[2] as usize].dist,
        ];
        // Longest edge, world units, from the cached vertices (one square root).
        let reach = vs[0]
            .0
            .distance_squared(vs[1].0)
            .max(vs[1].0.distance_squared(vs[2].0))
            .max(vs[2].0.distance_squared(vs[0].0))
            .sqrt();
        let class = classify(f.light_eye, &vs, &dists, reach, sigma);
        #[cfg(test)]
        let class = if self.exact {
            FaceClass::Grid {
                steps: SUB,
                delta: f32::INFINITY,
            }
        } else {
            class
        };
        let mut face = Moments::default();
        let vertex_cone = || vs.iter().fold(1f32, |m, v| m.min(v.1.dot(n)));
        match class {
            FaceClass::Outside => {
                self.counts.outside += 1;
                None
            }
            FaceClass::Inside => {
                // The whole face: its moments at once; the normalised interpolant's
                // cos with the axis is at least the vertices' smallest.
                self.counts.inside += 1;
                let [a, b, c] = vs.map(|v| project(v.0));
                face.add_triangle(a, b, c);
                Some((face, vertex_cone()))
            }
            FaceClass::Linear => {
                self.counts.linear += 1;
                let tri = vs.map(|v| (project(v.0), v.2 - sigma));
                if tri.iter().all(|t| t.1 < 0.0) {
                    return None;
                }
                face.add_clipped(tri);
                Some((face, vertex_cone()))
            }
            FaceClass::Grid { steps, delta } => {
                // The face on a sub-grid of `steps` per edge, as the GPU shades it:
                // interpolated and normalised normal, H at the point (interpolated
                // from the vertices' where it turns little over the face: its
                // departure from linear is then second order); `N·H − σ` linear on
                // each sub-triangle.
                self.counts.grid += 1;
                let hs = [
                    self.vertices[tri[0] as usize].h,
                    self.vertices[tri[1] as usize].h,
                    self.vertices[tri[2] as usize].h,
                ];
                let qs = [project(vs[0].0), project(vs[1].0), project(vs[2].0)];
                sample_sub_grid(f.light_eye, &vs, hs, qs, part, steps, delta)
            }
        }
    }
}

/// Face `vs` (world position, unit normal and `N·H` per vertex; unit `H` per vertex in
/// `hs`, positions projected onto the plane in `qs`) on a sub-grid of `steps` per edge,
/// against `part`'s region: its moments and the smallest cos of its normals in the
/// region with the axis, or `None` when no grid point is in the region. `delta` bounds
/// how far `H` turns over the face.
fn sample_sub_grid(
    light_eye: LightEye,
    vs: &[(Vec3, Vec3, f32); 3],
    hs: [Vec3; 3],
    qs: [Vec2; 3],
    part: &Part,
    steps: usize,
    delta: f32,
) -> Option<(Moments, f32)> {
    let (n, sigma) = (part.frame.0, part.sigma);
    let mut face = Moments::default();
    let exact_h = delta > EXACT_H_TURN;
    // With H interpolated, u = Σ bᵢNᵢ and h = Σ bⱼHⱼ give
    // u·h = bᵀ(Nᵢ·Hⱼ)b and |u|² = bᵀ(Nᵢ·Nⱼ)b: nine and six dots per face
    // instead of vector work per point.
    let (n0, n1, n2) = (vs[0].1, vs[1].1, vs[2].1);
    let nh = [
        [n0.dot(hs[0]), n0.dot(hs[1]), n0.dot(hs[2])],
        [n1.dot(hs[0]), n1.dot(hs[1]), n1.dot(hs[2])],
        [n2.dot(hs[0]), n2.dot(hs[1]), n2.dot(hs[2])],
    ];
    let (g01, g12, g20) = (n0.dot(n1), n1.dot(n2), n2.dot(n0));
    let nn = [
        [n0.length_squared(), g01, g20],
        [g01, n1.length_squared(), g12],
        [g20, g12, n2.length_squared()],
    ];
    let na = [n0.dot(n), n1.dot(n), n2.dot(n)];
    let mut grid = [(Vec2::ZERO, 0f32); GRID_POINTS];
    let mut any = false;
    let mut cone = 1f32;
    let inv = 1.0 / steps as f32;
    for (g, (i, j)) in grid_points(steps).enumerate() {
        let (b1, b2) = (i as f32 * inv, j as f32 * inv);
        let b = [1.0 - b1 - b2, b1, b2];
        let quad = |m: &[[f32; 3]; 3]| {
            b[0] * (b[0] * m[0][0] + b[1] * m[0][1] + b[2] * m[0][2])
                + b[1] * (b[0] * m[1][0] + b[1] * m[1][1] + b[2] * m[1][2])
                + b[2] * (b[0] * m[2][0] + b[1] * m[2][1] + b[2] * m[2][2])
        };
        let len2 = quad(&nn);
        let inv_len = if len2 > 0.0 { len2.sqrt().recip() } else { 0.0 };
        let d = if exact_h {
            let p = vs[0].0 * b[0] + vs[1].0 * b[1] + vs[2].0 * b[2];
            let u = vs[0].1 * b[0] + vs[1].1 * b[1] + vs[2].1 * b[2];
            u.dot(light_eye.half_vector(p)) * inv_len - sigma
        } else {
            quad(&nh) * inv_len - sigma
        };
        let d = if d.is_finite() { d } else { -1.0 };
        if d >= 0.0 {
            any = true;
            cone = cone.min((b[0] * na[0] + b[1] * na[1] + b[2] * na[2]) * inv_len);
        }
        grid[g] = (qs[0] * b[0] + qs[1] * b[1] + qs[2] * b[2], d);
    }
    if !any {
        return None;
    }
    for_sub_triangles(steps, |a, b, c| {
        face.add_clipped([grid[a], grid[b], grid[c]]);
    });
    Some((face, cone))
}

/// A vertex's values in one frame of [`RegionGrower`].
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct VertexCache {
    /// The frame they belong to.
    frame: u32,
    /// `N_v·H(p_v)`.
    nh: f32,
    /// World position, unit world normal and unit `H(p_v)`.
    world: Vec3,
    normal: Vec3,
    h: Vec3,
    /// Distances to the light and the eye and `|L̂ + V̂|` (point light and eye; zero for
    /// directions).
    dist: [f32; 3],
}
