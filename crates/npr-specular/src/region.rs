//! The region `N·H ≥ σ` a highlight stylizes, measured on the mesh (beyond the paper).
//!
//! Eq. (8) sizes a projector from the principal curvatures at the centre: exact on a
//! sphere, but on a real mesh κ is noisy and the region is not an ellipse, so the paper's
//! footprint misses most of it (recall 0.37–0.80 measured by `cargo xtask bench
//! specular-fidelity`). Here the region itself is grown over the mesh from the centre's
//! face, on the normals the `N = H` search uses (the shaded ones), with `H` per vertex
//! from the light and eye: each face is clipped to the linear interpolant of
//! `N·H − σ ≥ 0`, projected onto the projector's plane (e_max, e_min) and its area
//! moments summed. The footprint is the ellipse with the same moments: centred at the
//! region's centroid, half extent `2·sqrt(variance)` along each axis (a uniform ellipse of
//! half axis `a` has variance `a²/4`), turned towards the moments' own axes when the
//! region is clearly anisotropic.

use glam::{Mat3, Mat4, Vec2, Vec3};
use npr_geometry::{HighlightCentre, LightEye, Topology};
use std::collections::VecDeque;

/// A projector's footprint before the §3.4 controls: the ellipse inscribed in its square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Half extents along the (rotated) `e_max` and `e_min` axes, world units.
    pub half_extent: Vec2,
    /// Offset of the footprint's centre from the `N = H` point along (`e_max`, `e_min`),
    /// world units (zero for Eq. (8)).
    pub offset: Vec2,
    /// Rotation of the footprint's axes about the normal from (`e_max`, `e_min`), radians
    /// (zero for Eq. (8)).
    pub rotate_rad: f32,
    /// Area of the region measured (projected onto the projector plane), world units²;
    /// zero for Eq. (8).
    pub region_area: f32,
    /// Smallest `cos` between the region's normals and the projector's axis (the
    /// region's normal cone; receivers beyond it cannot be in the region); −1 when not
    /// measured (Eq. (8)).
    pub normal_cone_cos: f32,
}

impl Default for Footprint {
    fn default() -> Self {
        Self {
            half_extent: Vec2::ZERO,
            offset: Vec2::ZERO,
            rotate_rad: 0.0,
            region_area: 0.0,
            normal_cone_cos: -1.0,
        }
    }
}

/// What growing a centre's region found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// The centre's face is an earlier centre's: the highlight would stylize a region
    /// another one covers.
    Covered,
    /// The linear interpolant of `N·H − σ` is negative at every vertex of the centre's
    /// face: the region is smaller than a triangle (or absent).
    Empty,
    /// The fitted footprint and the number of faces the region touches.
    Fit(Footprint, usize),
}

/// Reusable per-mesh scratch of [`RegionGrower`]: per-frame vertex values and face
/// ownership, generation-stamped so nothing is cleared per frame.
#[derive(Clone, Debug, Default)]
pub struct RegionGrower {
    frame: u32,
    vertex_frame: Vec<u32>,
    vertex_world: Vec<Vec3>,
    vertex_normal: Vec<Vec3>,
    /// Unit `H(p_v)` at the vertex (world frame).
    vertex_h: Vec<Vec3>,
    /// `N_v·H(p_v)` at the vertex.
    vertex_nh: Vec<f32>,
    /// Distances to the light and the eye and `|L̂ + V̂|` at the vertex (point light and
    /// eye; zero for directions).
    vertex_dist: Vec<[f32; 3]>,
    face_visit: Vec<u32>,
    queue: VecDeque<(u32, u32)>,
    /// Faces classified whole (inside or outside) and on the sub-grid, last frame.
    counts: RegionCounts,
    /// Per face taken this frame: its seed and its share of that seed's moments.
    face_moments: Vec<(u32, Moments)>,
    /// Pieces of bent regions ([`RegionGrower::pieces`]), and each seed's range of them.
    pieces: Vec<Footprint>,
    piece_ranges: Vec<std::ops::Range<usize>>,
    /// Tests: sample every face on the finest sub-grid with `H` computed at each point
    /// (the reference the classification is compared with).
    #[cfg(test)]
    exact: bool,
}

/// How [`RegionGrower::grow_all`] classified the faces it looked at in its last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionCounts {
    /// Faces proved inside the region from their vertices alone (added whole).
    pub inside: usize,
    /// Faces proved outside from their vertices alone (skipped).
    pub outside: usize,
    /// Faces the boundary crosses, clipped once by their vertex values.
    pub linear: usize,
    /// Faces the boundary may cross where the field is curved, clipped on the sub-grid.
    pub grid: usize,
}

/// Everything of the current frame the growth needs.
#[derive(Clone, Copy, Debug)]
pub struct RegionFrame<'a> {
    /// The mesh (object space).
    pub topology: &'a Topology,
    /// Unit vertex normals the search uses, object space.
    pub normals: &'a [Vec3],
    /// Object → world.
    pub world_from_object: Mat4,
    /// Light and eye, world space.
    pub light_eye: LightEye,
}

/// A region is split into pieces along its length ([`RegionGrower::pieces`]) when its
/// moment ellipse is this much larger than the region (an ellipse region reads 1, a
/// rectangle 1.05; a band that bends reads more: the ellipse covers the inside of the
/// bend) ...
pub const SPLIT_AREA_RATIO: f32 = 1.3;
/// ... and the ellipse is at least this elongated.
pub const SPLIT_ELONGATION: f32 = 2.5;
/// Most pieces a region is split into.
pub const MAX_PIECES: usize = 6;

/// Largest number of faces one region may visit (a flat mesh facing the light would
/// otherwise be walked whole every frame; the fit of a truncated region is still its best).
const MAX_REGION_FACES: usize = 200_000;

impl RegionGrower {
    /// Starts a frame: forgets the vertex values and face marks of the last one.
    fn begin_frame(&mut self, topology: &Topology) {
        let (nv, nf) = (topology.vertex_count(), topology.face_count());
        if self.vertex_frame.len() != nv || self.face_visit.len() != nf {
            #[cfg(test)]
            let exact = self.exact;
            *self = Self {
                vertex_frame: vec![0; nv],
                vertex_world: vec![Vec3::ZERO; nv],
                vertex_normal: vec![Vec3::ZERO; nv],
                vertex_h: vec![Vec3::ZERO; nv],
                vertex_nh: vec![0.0; nv],
                vertex_dist: vec![[0.0; 3]; nv],
                face_visit: vec![0; nf],
                ..Self::default()
            };
            #[cfg(test)]
            {
                self.exact = exact;
            }
        }
        self.frame = self.frame.wrapping_add(1);
        if self.frame == 0 {
            self.vertex_frame.fill(0);
            self.face_visit.fill(0);
            self.frame = 1;
        }
    }

    /// World position, unit world normal and `N·H` of vertex `v` (cached for the frame).
    #[inline]
    fn vertex(
        &mut self,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        v: usize,
    ) -> (Vec3, Vec3, f32) {
        if self.vertex_frame[v] != self.frame {
            self.compute_vertex(f, normal_from_object, v);
        }
        (
            self.vertex_world[v],
            self.vertex_normal[v],
            self.vertex_nh[v],
        )
    }

    #[inline(never)]
    fn compute_vertex(&mut self, f: &RegionFrame<'_>, normal_from_object: Mat3, v: usize) {
        self.vertex_frame[v] = self.frame;
        let p = f
            .world_from_object
            .transform_point3(f.topology.positions[v]);
        let n = (normal_from_object * f.normals.get(v).copied().unwrap_or(Vec3::ZERO))
            .normalize_or_zero();
        let h = half_vector(f.light_eye, p);
        let nh = n.dot(h);
        if let LightEye::Positions { light, eye } = f.light_eye {
            let (l, e) = (light - p, eye - p);
            let (dl, de) = (l.length(), e.length());
            self.vertex_dist[v] = [dl, de, (l / dl + e / de).length()];
        }
        self.vertex_world[v] = p;
        self.vertex_h[v] = h;
        self.vertex_normal[v] = n;
        self.vertex_nh[v] = if nh.is_finite() { nh } else { -1.0 };
    }

    /// How the faces of the last [`RegionGrower::grow_all`] were classified.
    pub fn counts(&self) -> RegionCounts {
        self.counts
    }

    /// Grows the regions `N·H ≥ σ` of all `seeds` (centre in world frame as the search
    /// returns it, and its σ) at once, breadth-first from their faces, so that a region
    /// holding several centres is shared between them (each face goes to the centre that
    /// reaches it first), and fits each part's footprint. A seed whose face an earlier
    /// seed already holds is [`Region::Covered`].
    pub fn grow_all(
        &mut self,
        f: &RegionFrame<'_>,
        seeds: &[(HighlightCentre, f32)],
    ) -> Vec<Region> {
        let topo = f.topology;
        self.begin_frame(topo);
        let mut out = vec![Region::Empty; seeds.len()];
        let m3 = Mat3::from_mat4(f.world_from_object);
        if m3.determinant().abs() <= f32::MIN_POSITIVE {
            return out;
        }
        let normal_from_object = m3.inverse().transpose();
        let mut parts: Vec<Part> = Vec::with_capacity(seeds.len());
        self.queue.clear();
        for (k, (centre, sigma)) in seeds.iter().enumerate() {
            let start = centre.face as usize;
            let frame = centre.normal_world.try_normalize().and_then(|n| {
                let e_u =
                    (centre.dir_kappa_max - n * n.dot(centre.dir_kappa_max)).try_normalize()?;
                Some((n, e_u, n.cross(e_u)))
            });
            parts.push(Part {
                frame: frame.unwrap_or((Vec3::Z, Vec3::X, Vec3::Y)),
                origin: centre.position_world,
                sigma: *sigma,
                moments: Moments::default(),
                faces: 0,
                cone: 1.0,
            });
            if start >= topo.face_count() || frame.is_none() {
                continue;
            }
            if self.face_visit[start] == self.frame {
                out[k] = Region::Covered;
                continue;
            }
            self.face_visit[start] = self.frame;
            self.queue.push_back((start as u32, k as u32));
        }
        let mut total = 0usize;
        self.counts = RegionCounts::default();
        self.face_moments.clear();
        self.pieces.clear();
        self.piece_ranges.clear();
        self.piece_ranges.resize(seeds.len(), 0..0);
        while let Some((face, k)) = self.queue.pop_front() {
            let fi = face as usize;
            let part = &parts[k as usize];
            let (n, e_u, e_v) = part.frame;
            if topo.is_degenerate(fi) || (normal_from_object * topo.face_normals[fi]).dot(n) <= 0.0
            {
                continue;
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
                self.vertex_dist[tri[0] as usize],
                self.vertex_dist[tri[1] as usize],
                self.vertex_dist[tri[2] as usize],
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
            let part = &mut parts[k as usize];
            let mut face = Moments::default();
            match class {
                FaceClass::Outside => {
                    self.counts.outside += 1;
                    continue;
                }
                FaceClass::Inside => {
                    // The whole face: its moments at once; the normalised interpolant's
                    // cos with the axis is at least the vertices' smallest.
                    self.counts.inside += 1;
                    let [a, b, c] = vs.map(|v| project(v.0));
                    face.add_triangle(a, b, c);
                    part.cone = vs.iter().fold(part.cone, |m, v| m.min(v.1.dot(n)));
                }
                FaceClass::Linear => {
                    self.counts.linear += 1;
                    let tri = vs.map(|v| (project(v.0), v.2 - sigma));
                    if tri.iter().all(|t| t.1 < 0.0) {
                        continue;
                    }
                    face.add_clipped(tri);
                    part.cone = vs.iter().fold(part.cone, |m, v| m.min(v.1.dot(n)));
                }
                FaceClass::Grid { steps, delta } => {
                    // The face on a sub-grid of `steps` per edge, as the GPU shades it:
                    // interpolated and normalised normal, H at the point (interpolated
                    // from the vertices' where it turns little over the face: its
                    // departure from linear is then second order); `N·H − σ` linear on
                    // each sub-triangle.
                    self.counts.grid += 1;
                    let hs = [
                        self.vertex_h[tri[0] as usize],
                        self.vertex_h[tri[1] as usize],
                        self.vertex_h[tri[2] as usize],
                    ];
                    let qs = [project(vs[0].0), project(vs[1].0), project(vs[2].0)];
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
                            u.dot(half_vector(f.light_eye, p)) * inv_len - sigma
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
                        continue;
                    }
                    part.cone = part.cone.min(cone);
                    for_sub_triangles(steps, |a, b, c| {
                        face.add_clipped([grid[a], grid[b], grid[c]]);
                    });
                }
            }
            part.moments.add(&face);
            self.face_moments.push((k, face));
            part.faces += 1;
            total += 1;
            if total >= MAX_REGION_FACES {
                break;
            }
            for &nb in topo.face_neighbours(fi) {
                let ni = nb as usize;
                if self.face_visit[ni] != self.frame {
                    self.face_visit[ni] = self.frame;
                    self.queue.push_back((nb, k));
                }
            }
        }
        for (k, part) in parts.iter().enumerate() {
            if out[k] == Region::Empty && part.faces > 0 {
                if let Some(fp) = part.moments.footprint() {
                    let fp = Footprint {
                        normal_cone_cos: part.cone,
                        ..fp
                    };
                    out[k] = Region::Fit(fp, part.faces);
                    let start = self.pieces.len();
                    split_bent(&fp, k as u32, &self.face_moments, &mut self.pieces);
                    self.piece_ranges[k] = start..self.pieces.len();
                }
            }
        }
        out
    }

    /// The pieces seed `k`'s region was split into by the last [`RegionGrower::grow_all`]
    /// (beyond the paper): empty for a region its moment ellipse fits; for a long bent
    /// band (ellipse [`SPLIT_AREA_RATIO`] × larger than the region, [`SPLIT_ELONGATION`]
    /// × longer than wide), up to [`MAX_PIECES`] footprints of equal area along its
    /// length, each fitted to its own faces, in the same frame as the whole's, so that
    /// several projectors follow the band where one ellipse cannot.
    pub fn pieces(&self, k: usize) -> &[Footprint] {
        self.piece_ranges
            .get(k)
            .and_then(|r| self.pieces.get(r.clone()))
            .unwrap_or(&[])
    }
}

/// Appends to `out` the pieces of the region of seed `k` fitted by `whole` (see
/// [`RegionGrower::pieces`]), from its faces' moments; nothing when it needs none.
fn split_bent(whole: &Footprint, k: u32, faces: &[(u32, Moments)], out: &mut Vec<Footprint>) {
    let h = whole.half_extent;
    let ellipse = std::f32::consts::PI * h.x * h.y;
    let elongation = h.max_element() / h.min_element().max(f32::MIN_POSITIVE);
    if !(ellipse > SPLIT_AREA_RATIO * whole.region_area && elongation >= SPLIT_ELONGATION) {
        return;
    }
    let count = ((elongation / 1.5).round() as usize).clamp(2, MAX_PIECES);
    let (s, c) = whole.rotate_rad.sin_cos();
    let axis = if h.x >= h.y {
        Vec2::new(c, s)
    } else {
        Vec2::new(-s, c)
    };
    let mut along: Vec<(f32, Moments)> = faces
        .iter()
        .filter(|(seed, m)| *seed == k && m.area > 0.0)
        .map(|(_, m)| {
            let centroid = Vec2::new((m.first[0] / m.area) as f32, (m.first[1] / m.area) as f32);
            ((centroid - whole.offset).dot(axis), *m)
        })
        .collect();
    along.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = along.iter().map(|(_, m)| m.area).sum();
    let start = out.len();
    let mut piece = Moments::default();
    let mut cut = 1;
    for (_, m) in &along {
        piece.add(m);
        if piece.area >= total * cut as f64 / count as f64 - 1e-12 * total && cut < count {
            out.extend(piece.footprint());
            piece = Moments::default();
            cut += 1;
        }
    }
    out.extend(piece.footprint());
    for p in &mut out[start..] {
        p.normal_cone_cos = whole.normal_cone_cos;
    }
    if out.len() - start < 2 {
        out.truncate(start);
    }
}

/// One seed's growing region: its projector frame (n, e_max, e_min), origin, σ, moments.
struct Part {
    frame: (Vec3, Vec3, Vec3),
    origin: Vec3,
    sigma: f32,
    moments: Moments,
    faces: usize,
    cone: f32,
}

/// Sub-grid of a face: `SUB` steps per edge.
const SUB: usize = 4;
const GRID_POINTS: usize = (SUB + 1) * (SUB + 2) / 2;

/// Index of grid point (i, j) (i + j ≤ `steps`) in the order of [`grid_points`].
const fn grid_index(steps: usize, i: usize, j: usize) -> usize {
    // Row i starts after rows 0..i of steps + 1 − r points each.
    i * (2 * steps + 3 - i) / 2 + j
}

/// The points (i, j), i + j ≤ `steps`, of a face's sub-grid, row by row.
fn grid_points(steps: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..=steps).flat_map(move |i| (0..=steps - i).map(move |j| (i, j)))
}

/// Calls `f` with the grid indices of every sub-triangle of a `steps` sub-grid, in the
/// face's orientation.
fn for_sub_triangles(steps: usize, mut f: impl FnMut(usize, usize, usize)) {
    let at = |i, j| grid_index(steps, i, j);
    for i in 0..steps {
        for j in 0..steps - i {
            let (a, b, c) = (at(i, j), at(i + 1, j), at(i, j + 1));
            f(a, b, c);
            if i + j + 1 < steps {
                f(b, at(i + 1, j + 1), c);
            }
        }
    }
}

/// Where a face lies against the region `N·H ≥ σ`, from its vertices alone, and how it
/// must be measured.
#[derive(Clone, Copy, Debug, PartialEq)]
enum FaceClass {
    /// Every point is in the region: added whole.
    Inside,
    /// No point is: skipped.
    Outside,
    /// The boundary crosses it, and `N·H − σ` is linear in it to within
    /// [`LINEAR_TOLERANCE`] of its range: clipped once by the vertex values.
    Linear,
    /// The boundary may cross it and the field is too curved there (a region no bigger
    /// than a few faces): sampled on a sub-grid of `steps` per edge; `delta` bounds how
    /// far `H` turns over the face.
    Grid {
        /// Sub-grid steps per edge, 2 to [`SUB`].
        steps: usize,
        /// Bound on the turn of `H` over the face (radians, about).
        delta: f32,
    },
}

/// Above this bound on how far `H` turns over a face (near the light or the eye), the
/// sub-grid computes `H` at each point instead of interpolating the vertices'.
const EXACT_H_TURN: f32 = 0.05;

/// Largest deviation of `N·H` from the linear interpolant of its vertex values, as a
/// fraction of their range, for a face to be clipped by the vertex values alone: the
/// boundary is then placed within about 5 % of the face (the 4-step sub-grid's own
/// resolution is a quarter of it).
const LINEAR_TOLERANCE: f32 = 0.05;

/// Classifies a face (world position, unit normal and `N·H` per vertex) by bounds that
/// hold at every point of it. With `u = Σ bᵢ Nᵢ` the interpolated normal (`|u| ≤ 1`),
/// `c ≥ 0` the smallest `Nᵢ·Nⱼ` (so `|u|² = Σ bᵢbⱼ Nᵢ·Nⱼ ≥ c + (1 − c) Σ bᵢ² ≥
/// (1 + 2c)/3`) and `δ` a bound on how far `H` turns over the face:
/// - inside when `σ ≥ 0` and `min Nᵢ·Hᵢ − δ ≥ σ`, since then `u·H ≥ 0` and
///   `N̂·H = u·H/|u| ≥ u·H ≥ Σ bᵢ Nᵢ·Hᵢ − δ`;
/// - `N̂·H` departs from the interpolant `Σ bᵢ Nᵢ·Hᵢ` by the normalisation,
///   `≤ 1/|u| − 1`, and by `Σ bᵢ Nᵢ·(H(p) − Hᵢ)`, whose first-order part
///   `N₀·J Σ bᵢ (p − pᵢ)` vanishes, leaving `≤ max|Nᵢ − N₀| δ + 2δ²` (the second-order
///   part of `L̂` over a face, about `1.5 (r/d)²`, is within `2δ²`); so the face is
///   outside when `max Nᵢ·Hᵢ + ε < σ`, and the interpolant is trusted when that `ε` is
///   small against the vertex values' range.
fn classify(
    light_eye: LightEye,
    vs: &[(Vec3, Vec3, f32); 3],
    dists: &[[f32; 3]; 3],
    reach: f32,
    sigma: f32,
) -> FaceClass {
    let lo = vs[0].2.min(vs[1].2).min(vs[2].2);
    let hi = vs[0].2.max(vs[1].2).max(vs[2].2);
    let delta = match light_eye {
        LightEye::Directions { .. } => 0.0,
        LightEye::Positions { .. } => {
            // |ΔL̂| ≤ r/(d − r) for points within r (the longest edge) of a vertex at
            // distance d; Ĥ = S/|S| turns by at most |ΔS|/(|S| − |ΔS|).
            let r = reach;
            let turn = |d: f32| if d > 2.0 * r { r / (d - r) } else { 2.0 };
            let min = |k: usize| dists[0][k].min(dists[1][k]).min(dists[2][k]);
            let ds = turn(min(0)) + turn(min(1));
            let s = min(2);
            if s - ds > 1e-3 { ds / (s - ds) } else { 2.0 }
        }
    };
    let finest = FaceClass::Grid {
        steps: SUB,
        delta: f32::INFINITY,
    };
    if !delta.is_finite() || !lo.is_finite() || !hi.is_finite() {
        return finest;
    }
    // (u·H ≥ 0 there, which the first bound needs, since σ ≥ 0.)
    if sigma >= 0.0 && lo - delta >= sigma {
        return FaceClass::Inside;
    }
    let c = vs[0]
        .1
        .dot(vs[1].1)
        .min(vs[1].1.dot(vs[2].1))
        .min(vs[2].1.dot(vs[0].1));
    if c.is_nan() || c <= 0.0 {
        return FaceClass::Grid { steps: SUB, delta };
    }
    let eps = 1.0 / ((1.0 + 2.0 * c) / 3.0).sqrt() - 1.0
        + delta * ((2.0 * (1.0 - c)).max(0.0).sqrt() + 2.0 * delta);
    if hi + eps < sigma {
        FaceClass::Outside
    } else if eps <= LINEAR_TOLERANCE * (hi - lo) {
        FaceClass::Linear
    } else {
        // The interpolant's error falls as 1/steps² on a sub-grid.
        let need = (eps / (LINEAR_TOLERANCE * (hi - lo)).max(f32::MIN_POSITIVE)).sqrt();
        FaceClass::Grid {
            steps: if need <= 2.0 {
                2
            } else if need <= 3.0 {
                3
            } else {
                SUB
            },
            delta,
        }
    }
}

/// The unit half vector `H` at world point `p`.
fn half_vector(light_eye: LightEye, p: Vec3) -> Vec3 {
    match light_eye {
        LightEye::Positions { light, eye } => {
            (light - p).normalize_or_zero() + (eye - p).normalize_or_zero()
        }
        LightEye::Directions { to_light, to_eye } => {
            to_light.normalize_or_zero() + to_eye.normalize_or_zero()
        }
    }
    .normalize_or_zero()
}

/// Area moments of a planar region (area, first and second moments about the origin).
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    area: f64,
    first: [f64; 2],
    /// (xx, xy, yy)
    second: [f64; 3],
}

impl Moments {
    /// Adds another region's moments (disjoint regions).
    fn add(&mut self, other: &Moments) {
        self.area += other.area;
        for (a, b) in self.first.iter_mut().zip(&other.first) {
            *a += b;
        }
        for (a, b) in self.second.iter_mut().zip(&other.second) {
            *a += b;
        }
    }

    /// Adds a triangle (counter-clockwise seen from the normal for positive area).
    fn add_triangle(&mut self, a: Vec2, b: Vec2, c: Vec2) {
        let (a, b, c) = (a.as_dvec2(), b.as_dvec2(), c.as_dvec2());
        let area = 0.5 * (b - a).perp_dot(c - a);
        let s = a + b + c;
        self.area += area;
        self.first[0] += area * s.x / 3.0;
        self.first[1] += area * s.y / 3.0;
        // ∫ x xᵀ dA = A/12 · (Σ vᵢvᵢᵀ + s sᵀ) over a triangle.
        let k = area / 12.0;
        self.second[0] += k * (a.x * a.x + b.x * b.x + c.x * c.x + s.x * s.x);
        self.second[1] += k * (a.x * a.y + b.x * b.y + c.x * c.y + s.x * s.y);
        self.second[2] += k * (a.y * a.y + b.y * b.y + c.y * c.y + s.y * s.y);
    }

    /// Adds the part of the triangle where the linear interpolant of the values `≥ 0`.
    fn add_clipped(&mut self, tri: [(Vec2, f32); 3]) {
        let mut poly: [Vec2; 4] = [Vec2::ZERO; 4];
        let mut len = 0;
        for k in 0..3 {
            let (p, dp) = tri[k];
            let (q, dq) = tri[(k + 1) % 3];
            if dp >= 0.0 {
                poly[len] = p;
                len += 1;
            }
            if (dp >= 0.0) != (dq >= 0.0) && len < 4 {
                let t = dp / (dp - dq);
                poly[len] = p + (q - p) * t;
                len += 1;
            }
        }
        for k in 1..len.saturating_sub(1) {
            self.add_triangle(poly[0], poly[k], poly[k + 1]);
        }
    }

    /// The ellipse with these moments (see the module docs); `None` for an empty or
    /// degenerate region.
    fn footprint(&self) -> Option<Footprint> {
        if self.area.is_nan() || self.area <= 1e-20 {
            return None;
        }
        let mx = self.first[0] / self.area;
        let my = self.first[1] / self.area;
        let cxx = (self.second[0] / self.area - mx * mx).max(0.0);
        let cxy = self.second[1] / self.area - mx * my;
        let cyy = (self.second[2] / self.area - my * my).max(0.0);
        // The moments' axis nearest to e_max, within ±45°.
        let mut theta = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        let quarter = std::f64::consts::FRAC_PI_2;
        if theta > quarter / 2.0 {
            theta -= quarter;
        } else if theta < -quarter / 2.0 {
            theta += quarter;
        }
        // Turn only for a clearly anisotropic region: near-isotropic moments have unstable
        // axes, and a turning texture would flicker.
        let spread = ((cxx - cyy).powi(2) + 4.0 * cxy * cxy).sqrt() / (cxx + cyy).max(1e-30);
        let t = ((spread - 0.05) / 0.15).clamp(0.0, 1.0);
        let theta = theta * t * t * (3.0 - 2.0 * t);
        let (s, c) = theta.sin_cos();
        let var_u = cxx * c * c + 2.0 * cxy * s * c + cyy * s * s;
        let var_v = cxx * s * s - 2.0 * cxy * s * c + cyy * c * c;
        let offset = glam::DVec2::new(mx, my);
        let half = Vec2::new(
            (2.0 * var_u.max(0.0).sqrt()) as f32,
            (2.0 * var_v.max(0.0).sqrt()) as f32,
        );
        let fp = Footprint {
            half_extent: half,
            offset: offset.as_vec2(),
            rotate_rad: theta as f32,
            region_area: self.area as f32,
            normal_cone_cos: -1.0,
        };
        (half.min_element() > 0.0 && fp.offset.is_finite() && half.is_finite()).then_some(fp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_of_a_square_and_its_clipped_half() {
        let mut m = Moments::default();
        let (a, b, c, d) = (
            Vec2::new(-1.0, -1.0),
            Vec2::new(1.0, -1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, 1.0),
        );
        m.add_triangle(a, b, c);
        m.add_triangle(a, c, d);
        assert!((m.area - 4.0).abs() < 1e-9);
        // Var of a uniform [−1, 1] is 1/3.
        assert!((m.second[0] / m.area - 1.0 / 3.0).abs() < 1e-9);
        assert!(m.second[1].abs() < 1e-9);
        // Clip by x ≥ 0: values = x.
        let mut h = Moments::default();
        h.add_clipped([(a, a.x), (b, b.x), (c, c.x)]);
        h.add_clipped([(a, a.x), (c, c.x), (d, d.x)]);
        assert!((h.area - 2.0).abs() < 1e-6, "{}", h.area);
        assert!((h.first[0] / h.area - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_sub_grid_tiles_the_face_once() {
        for steps in 1..=SUB {
            let mut area = 0.0;
            let mut count = 0;
            let pts: Vec<Vec2> = grid_points(steps)
                .map(|(i, j)| Vec2::new(i as f32, j as f32))
                .collect();
            assert_eq!(pts.len(), (steps + 1) * (steps + 2) / 2);
            for (g, (i, j)) in grid_points(steps).enumerate() {
                assert_eq!(grid_index(steps, i, j), g);
            }
            for_sub_triangles(steps, |a, b, c| {
                let t = 0.5 * (pts[b] - pts[a]).perp_dot(pts[c] - pts[a]);
                assert!(t > 0.0, "orientation");
                area += t;
                count += 1;
            });
            assert_eq!(count, steps * steps);
            assert!((area - 0.5 * (steps * steps) as f32).abs() < 1e-4);
        }
    }

    #[test]
    fn an_ellipse_gets_its_own_half_axes() {
        // A polygonal ellipse of half axes 3 × 1, turned by 0.5 rad.
        let mut m = Moments::default();
        let k = 720;
        let (s, c) = 0.5f32.sin_cos();
        let pt = |i: usize| {
            let t = i as f32 / k as f32 * std::f32::consts::TAU;
            let (x, y) = (3.0 * t.cos(), t.sin());
            Vec2::new(x * c - y * s, x * s + y * c) + Vec2::new(0.2, -0.1)
        };
        for i in 0..k {
            m.add_triangle(Vec2::new(0.2, -0.1), pt(i), pt(i + 1));
        }
        let fp = m.footprint().unwrap();
        assert!((fp.rotate_rad - 0.5).abs() < 1e-3, "{fp:?}");
        assert!(
            (fp.half_extent - Vec2::new(3.0, 1.0)).length() < 1e-2,
            "{fp:?}"
        );
        assert!((fp.offset - Vec2::new(0.2, -0.1)).length() < 1e-4, "{fp:?}");
    }

    #[test]
    fn classified_growth_fits_what_the_exact_sub_grid_fits() {
        // The fast path (faces proved inside/outside from their vertices, linear clips,
        // coarser sub-grids, interpolated H) against every face on the finest sub-grid
        // with H at each point: the same footprints within a few percent, on a noisy
        // scan (the bunny) and a sphere, point light and near eye, several views.
        use npr_geometry::{CurvatureField, CurvatureOptions, HighlightSearch};
        let path = format!(
            "{}/../../fixtures/meshes/stanford-bunny.obj",
            env!("CARGO_MANIFEST_DIR")
        );
        let bunny = npr_geometry::load_obj(&path).unwrap();
        let sphere = npr_geometry::generate::icosphere(4, 1.0);
        let mut fits = 0;
        for mesh in [bunny, sphere] {
            let (welded, topo, field) =
                CurvatureField::for_mesh(&mesh, &CurvatureOptions::default());
            let search = HighlightSearch::for_mesh(&mesh, &welded, &topo, &field);
            let (lo, hi) = topo.positions.iter().fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
            let world = Mat4::from_scale(Vec3::splat(1.0 / r)) * Mat4::from_translation(-c);
            let mut fast = RegionGrower::default();
            let mut exact = RegionGrower {
                exact: true,
                ..RegionGrower::default()
            };
            for k in 0..6 {
                let a = k as f32 * 1.1;
                let light_eye = LightEye::Positions {
                    light: Vec3::new(20.0 * a.cos(), 30.0, 20.0 * a.sin()),
                    eye: Vec3::new(3.0 * (a + 0.4).sin(), 0.5, 3.0 * (a + 0.4).cos()),
                };
                let seeds: Vec<(HighlightCentre, f32)> = search
                    .find(light_eye, world)
                    .into_iter()
                    .map(|c| (c, 0.9))
                    .collect();
                let frame = RegionFrame {
                    topology: &topo,
                    normals: search.normals(),
                    world_from_object: world,
                    light_eye,
                };
                let a = fast.grow_all(&frame, &seeds);
                let b = exact.grow_all(&frame, &seeds);
                let e = exact.counts();
                assert_eq!(e.inside + e.outside + e.linear, 0, "{e:?}");
                for (x, y) in a.iter().zip(&b) {
                    match (x, y) {
                        (Region::Fit(p, _), Region::Fit(q, _)) => {
                            // Regions of a face or two are where the sub-grid itself is
                            // coarse; compare the ones that count (~20 px and up).
                            if q.region_area < 5e-4 {
                                continue;
                            }
                            fits += 1;
                            let rel = (p.region_area - q.region_area).abs() / q.region_area;
                            assert!(rel < 0.03, "area {p:?} vs {q:?}");
                            let size = q.half_extent.max_element();
                            assert!(
                                (p.half_extent - q.half_extent).abs().max_element() < 0.03 * size,
                                "extent {p:?} vs {q:?}"
                            );
                            assert!(
                                (p.offset - q.offset).length() < 0.03 * size,
                                "offset {p:?} vs {q:?}"
                            );
                            // Coarser sub-grids sample fewer normals: the cone may be
                            // narrower by a degree or two (receivers add 10°).
                            assert!(
                                p.normal_cone_cos <= q.normal_cone_cos + 0.02,
                                "cone {} vs {}",
                                p.normal_cone_cos,
                                q.normal_cone_cos
                            );
                        }
                        (Region::Fit(_, _), _) | (_, Region::Fit(_, _)) => {
                            panic!("one path fitted, the other did not: {x:?} / {y:?}")
                        }
                        _ => assert_eq!(x, y),
                    }
                }
            }
            assert!(fast.counts().inside + fast.counts().outside > 0);
        }
        assert!(fits >= 10, "{fits} regions compared");
    }
}
