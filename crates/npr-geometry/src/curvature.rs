//! Per-vertex curvature tensor, principal curvatures and principal directions: Eq. (1),
//! §2.2 of Hwan-Jik Lee and Jung-Ju Choi, "Stylized Specular Reflections Using Projective
//! Textures based on Principal Curvature Analysis" (Journal of the Korea Computer
//! Graphics Society), which takes the tensor from P. Alliez, D. Cohen-Steiner,
//! O. Devillers, B. Lévy, M. Desbrun, "Anisotropic polygonal remeshing", ACM Trans.
//! Graph. 22(3), 2003, after D. Cohen-Steiner and J.-M. Morvan, "Restricted Delaunay
//! triangulations and normal cycle", SoCG 2003.
//!
//! Eq. (1): `T(v) = 1/|B| Σ_e β(e) |e ∩ B| ē ēᵀ`. Paper symbols → our names: `B` the
//! ball of radius [`CurvatureField::radius_world`] around `v`, `β(e)`
//! [`Topology::dihedral`] (signed here, convex positive — the paper uses the unsigned
//! angle and only needs `|κ|`), `ē` the unit edge vector.
//!
//! The eigenvector of `T` with the *larger* of the two tangent eigenvalues is the
//! direction of *minimum* curvature (the tensor swaps them, §2.2): a cylinder's bending
//! edges run along its axis. So `kappa_max` = larger eigenvalue, `dir_kappa_max` = the
//! eigenvector of the smaller one.
//!
//! Three forms ([`CurvatureMethod`]); [`CurvatureMethod::Corrected`] is the default
//! because it measures best (see its doc and `cargo xtask bench curvature`).

use std::cell::RefCell;

use glam::{DVec3, Vec3};
use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use crate::topology::{NO_EDGE, Topology};
use crate::{Mesh, weld};

/// Which form of Eq. (1) to evaluate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CurvatureMethod {
    /// The paper's approximation (§2.2): `B` = every whole triangle with at least one
    /// vertex inside the sphere of radius r, `|e ∩ B| = |e|` for each of their edges
    /// (each edge once), `|B|` = their area sum. The normal is the eigenvector with the
    /// smallest |eigenvalue|, as in the paper. Biased high (boundary edges of the patch
    /// count in full, 9–33 % on a sphere, Lee & Choi §2.2), and the normal choice can swap with a
    /// principal direction where one curvature is near zero.
    Paper,
    /// Cohen-Steiner & Morvan's clipped form: `|e ∩ B|` is the exact length of each edge
    /// inside the ball, `|B|` the area of the triangles inside the ball (boundary
    /// triangles clipped by recursive subdivision, 1/64 of a triangle resolution). Normal
    /// as in [`CurvatureMethod::Paper`]. Its error swings with the radius (Lee & Choi §2.2).
    Clipped,
    /// The corrected form (default): each face owns its area-proportional share of each
    /// of its edges (`A_f / (A_f + A_g)`, so edge content and area agree), faces are
    /// weighted by the smooth kernel `w = (1 − d²/r²)²` of their centroid distance `d`
    /// (no hard cut-off aliasing, no face-size bias on irregular meshes), and `T` is
    /// projected onto the tangent plane of the mesh vertex normal before the eigen-
    /// analysis (the normal cannot leak into the principal directions):
    /// `T(v) = Σ_f w_f T_f / Σ_f w_f A_f`, `T_f = Σ_{e∈f} share_f(e) β(e) |e| ē ēᵀ`.
    #[default]
    Corrected,
}

impl CurvatureMethod {
    /// Lower-case name (`paper`, `clipped`, `corrected`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Clipped => "clipped",
            Self::Corrected => "corrected",
        }
    }
}

/// Radius r of the ball `B` of Eq. (1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurvatureRadius {
    /// In world (object) units.
    World(f32),
    /// As a multiple of the mesh's mean edge length ([`Topology::mean_edge_length`]):
    /// scale-free, so it follows the mesh's resolution. Default: 3 edge lengths, where
    /// the corrected form measures best on regular, jittered and noisy tori (larger
    /// balls smooth noise but pull `kappa_max` down and `kappa_min` up, Lee & Choi §2.2).
    EdgeLengths(f32),
}

impl Default for CurvatureRadius {
    fn default() -> Self {
        Self::EdgeLengths(3.0)
    }
}

/// Settings of the curvature computation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CurvatureOptions {
    /// Which form of Eq. (1).
    pub method: CurvatureMethod,
    /// Ball radius.
    pub radius: CurvatureRadius,
}

/// Principal curvatures and directions, one entry per vertex (struct of arrays).
///
/// Conventions: curvatures are pointwise (per unit length, not integrated), convex
/// positive with respect to `normal` (a sphere has `+1/R`), `kappa_max ≥ kappa_min`;
/// `dir_kappa_max`, `dir_kappa_min`, `normal` are unit and right-handed:
/// `dir_kappa_max × dir_kappa_min = normal`. Directions are defined up to sign (only
/// the frame's handedness is fixed). Where `valid[v]` is false (isolated vertex,
/// neighbourhood without area, non-finite input) the curvatures are 0, the directions
/// zero vectors and the normal the mesh normal: never NaN.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CurvatureField {
    /// Unit normal: the mesh vertex normal for [`CurvatureMethod::Corrected`], the
    /// tensor's normal eigenvector (oriented to agree with the mesh normal) otherwise.
    pub normal: Vec<Vec3>,
    /// Unit direction of maximum curvature.
    pub dir_kappa_max: Vec<Vec3>,
    /// Unit direction of minimum curvature.
    pub dir_kappa_min: Vec<Vec3>,
    /// Maximum principal curvature (1/world unit).
    pub kappa_max: Vec<f32>,
    /// Minimum principal curvature (1/world unit).
    pub kappa_min: Vec<f32>,
    /// Whether the method defined this vertex.
    pub valid: Vec<bool>,
    /// The ball radius used, in world units.
    pub radius_world: f32,
    /// The method used.
    pub method: CurvatureMethod,
}

/// One vertex's result.
#[derive(Clone, Copy, Debug, Default)]
struct Frame {
    n: Vec3,
    dmax: Vec3,
    dmin: Vec3,
    kmax: f32,
    kmin: f32,
    valid: bool,
}

/// Per-face data for the hot loop, packed for cache: centroid, bounding radius, area,
/// and the face's share of edge tensor `T_f` (xx, xy, xz, yy, yz, zz).
#[derive(Clone, Copy, Debug, Default)]
struct FaceData {
    c: [f32; 3],
    rad: f32,
    area: f32,
    t: [f32; 6],
}

/// One face of the corrected form's hot loop, in one 64-byte cache line: bounding
/// sphere (centroid, radius), the weights `T_f` (xx, xy, xz, yy | yz, zz) and area
/// `A_f`, and the face's neighbours across its edges, in [`Topology::face_neighbours`]
/// order. A face with fewer than three neighbours (a boundary) pads with itself, which
/// the walk has always marked already; `many` is set where it has more than three
/// (a non-manifold edge), and the walk then reads [`Topology::face_neighbours`].
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct FaceRec {
    sphere: [f32; 4],
    t0: glam::Vec4,
    t1: glam::Vec4,
    adj: [u32; 3],
    many: u32,
}

/// The corrected form's per-face records ([`FaceRec`]), indexed by face.
struct Packed {
    faces: Vec<FaceRec>,
}

impl Packed {
    fn build(topo: &Topology) -> Self {
        let totals = edge_area_totals(topo);
        let faces = topo
            .triangles
            .par_iter()
            .enumerate()
            .map(|(f, t)| {
                let d = face_record(topo, f, t, &totals);
                let nb = topo.face_neighbours(f);
                let mut adj = [f as u32; 3];
                for (a, &g) in adj.iter_mut().zip(nb) {
                    *a = g;
                }
                FaceRec {
                    sphere: [d.c[0], d.c[1], d.c[2], d.rad],
                    t0: glam::Vec4::new(d.t[0], d.t[1], d.t[2], d.t[3]),
                    t1: glam::Vec4::new(d.t[4], d.t[5], d.area, 0.0),
                    adj,
                    many: u32::from(nb.len() > 3),
                }
            })
            .collect();
        Self { faces }
    }
}

struct Scratch {
    face_mark: Vec<u32>,
    edge_mark: Vec<u32>,
    stamp: u32,
    stack: Vec<u32>,
}

thread_local! {
    // Reused visit marks (stamp-based, never cleared per vertex) and the DFS stack.
    static SCRATCH: RefCell<Scratch> =
        const { RefCell::new(Scratch { face_mark: Vec::new(), edge_mark: Vec::new(), stamp: 0, stack: Vec::new() }) };
}

fn sym6(d: DVec3, s: f64) -> [f64; 6] {
    [
        s * d.x * d.x,
        s * d.x * d.y,
        s * d.x * d.z,
        s * d.y * d.y,
        s * d.y * d.z,
        s * d.z * d.z,
    ]
}

/// `2^k` as an exact `f32` (`k` in -126..=127).
fn pow2(k: i32) -> f32 {
    f32::from_bits(((k.clamp(-126, 127) + 127) as u32) << 23)
}

/// The power of two `k` with `2^k` ≈ the bounding radius of the finite positions (about
/// their bounding-box centre), when it is outside `-8..=8`; `None` for meshes near unit
/// size (computed as they are) and for meshes without a finite extent.
fn normalising_exponent(positions: &[Vec3]) -> Option<i32> {
    let finite = positions
        .iter()
        .filter(|p| p.is_finite())
        .map(|p| p.as_dvec3());
    let (lo, hi) = finite.clone().fold(
        (glam::DVec3::splat(f64::MAX), glam::DVec3::splat(f64::MIN)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let centre = 0.5 * (lo + hi);
    // The largest distance is the square root of the largest squared distance (the
    // square root is correctly rounded and monotonic): one root instead of one a vertex.
    let radius = finite
        .map(|p| p.distance_squared(centre))
        .fold(0.0, f64::max)
        .sqrt();
    if !(radius > 0.0) || !radius.is_finite() {
        return None;
    }
    let k = radius.log2().round() as i32;
    (k.abs() > 8).then_some(k.clamp(-126, 126))
}

impl CurvatureField {
    /// Welds a render mesh, builds its topology and computes the field per welded
    /// vertex; [`CurvatureField::to_render`] maps it to render vertices.
    pub fn for_mesh(mesh: &Mesh, options: &CurvatureOptions) -> (crate::Welded, Topology, Self) {
        let welded = weld(mesh);
        let topo = Topology::new(&welded);
        let field = Self::compute(&topo, options);
        (welded, topo, field)
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.kappa_max.len()
    }

    /// Whether the field has no entries.
    pub fn is_empty(&self) -> bool {
        self.kappa_max.is_empty()
    }

    /// The field re-indexed through a map (e.g. [`crate::Welded::render_to_welded`], or
    /// an OBJ `v`-line map): entry `i` of the result is entry `map[i]` of `self`;
    /// out-of-range entries become invalid.
    pub fn to_render(&self, map: &[u32]) -> Self {
        let mut out = Self {
            radius_world: self.radius_world,
            method: self.method,
            ..Self::default()
        };
        for &w in map {
            let w = w as usize;
            if w < self.len() {
                out.normal.push(self.normal[w]);
                out.dir_kappa_max.push(self.dir_kappa_max[w]);
                out.dir_kappa_min.push(self.dir_kappa_min[w]);
                out.kappa_max.push(self.kappa_max[w]);
                out.kappa_min.push(self.kappa_min[w]);
                out.valid.push(self.valid[w]);
            } else {
                out.normal.push(Vec3::Z);
                out.dir_kappa_max.push(Vec3::ZERO);
                out.dir_kappa_min.push(Vec3::ZERO);
                out.kappa_max.push(0.0);
                out.kappa_min.push(0.0);
                out.valid.push(false);
            }
        }
        out
    }

    /// Computes Eq. (1) and its eigen-analysis at every vertex of `topo`, in parallel.
    ///
    /// The ball is grown over face adjacency from the vertex's own faces (never
    /// quadratic). Corrected form: a face passes the ball on when its centroid is inside
    /// (it has weight), or when it is large against the ball (bounding radius > r/2) and
    /// its bounding sphere reaches in; paper and clipped forms: every face whose bounding
    /// sphere can touch the ball passes it on. So `B` is the part of the surface inside
    /// the ball that is connected to `v` — another sheet passing through the ball (a
    /// thin wall's far side) is not mixed in. At boundary vertices the ball is one-sided
    /// and boundary edges carry no dihedral angle, so curvature there reads low.
    /// Vertices with a non-finite position, isolated vertices, and vertices whose ball
    /// holds no area are marked invalid; non-finite neighbours are skipped.
    ///
    /// Any scale works: when the mesh's bounding radius is far from 1 (beyond 2^±8), the
    /// field is computed on a copy scaled by a power of two to unit size (exact in
    /// floating point, so only the absolute tolerances and the `f32` range of areas see a
    /// difference) and the curvatures are scaled back: κ is reported in 1/(file unit),
    /// `radius_world` in file units.
    pub fn compute(topo: &Topology, options: &CurvatureOptions) -> Self {
        let Some(k) = normalising_exponent(&topo.positions) else {
            return Self::compute_at_scale(topo, options);
        };
        // x · 2^-k, and back with 2^k: both exact (|k| ≤ 126 keeps them normal floats).
        let (down, up) = (pow2(-k), pow2(k));
        let scaled = Topology::from_parts(
            topo.positions.iter().map(|&p| p * down).collect(),
            topo.triangles.clone(),
        );
        let radius = match options.radius {
            CurvatureRadius::World(r) => CurvatureRadius::World(r * down),
            edges => edges,
        };
        let mut field = Self::compute_at_scale(
            &scaled,
            &CurvatureOptions {
                radius,
                method: options.method,
            },
        );
        for kappa in field.kappa_max.iter_mut().chain(field.kappa_min.iter_mut()) {
            *kappa *= down;
        }
        field.radius_world *= up;
        field
    }

    fn compute_at_scale(topo: &Topology, options: &CurvatureOptions) -> Self {
        let r = match options.radius {
            CurvatureRadius::World(r) => r,
            CurvatureRadius::EdgeLengths(k) => k * topo.mean_edge_length,
        };
        let nv = topo.vertex_count();
        let method = options.method;
        let faces = if method == CurvatureMethod::Corrected {
            Vec::new()
        } else {
            face_data(topo)
        };
        let edge_t = if method == CurvatureMethod::Corrected {
            Vec::new()
        } else {
            edge_tensors(topo)
        };
        let packed = (method == CurvatureMethod::Corrected).then(|| Packed::build(topo));
        let ok_radius = r.is_finite() && r > 0.0;
        let frames: Vec<Frame> = (0..nv)
            .into_par_iter()
            .with_min_len(512)
            .map(|v| {
                if !ok_radius || topo.is_isolated(v) || !topo.positions[v].is_finite() {
                    return invalid(topo.vertex_normals[v]);
                }
                SCRATCH.with(|s| {
                    let mut s = s.borrow_mut();
                    match &packed {
                        Some(p) => corrected_frame(topo, p, v, r, &mut s),
                        None => vertex_frame(topo, &faces, &edge_t, v, r, method, &mut s),
                    }
                })
            })
            .collect();
        let mut out = Self {
            radius_world: r,
            method,
            ..Self::default()
        };
        // Struct of arrays, in two halves at once (plain loops: cheaper per element
        // than a parallel iterator).
        let ((normal, dmax), (dmin, (kmax, (kmin, valid)))) = rayon::join(
            || {
                rayon::join(
                    || frames.iter().map(|f| f.n).collect(),
                    || frames.iter().map(|f| f.dmax).collect(),
                )
            },
            || {
                rayon::join(
                    || frames.iter().map(|f| f.dmin).collect(),
                    || {
                        (
                            frames.iter().map(|f| f.kmax).collect(),
                            (
                                frames.iter().map(|f| f.kmin).collect(),
                                frames.iter().map(|f| f.valid).collect(),
                            ),
                        )
                    },
                )
            },
        );
        out.normal = normal;
        out.dir_kappa_max = dmax;
        out.dir_kappa_min = dmin;
        out.kappa_max = kmax;
        out.kappa_min = kmin;
        out.valid = valid;
        out
    }

    /// Principal frame and curvatures at barycentric point `(alpha, beta)` of triangle
    /// `[i0, i1, i2]` (`p = (1-α-β) p0 + α p1 + β p2`, Eq. (4)), interpolated "the same
    /// way" as the paper's §3.1: curvatures linearly, the normal linearly then
    /// normalised, `dir_kappa_max` linearly after flipping the vertex directions to agree
    /// with vertex 0's, then projected onto the tangent plane; `dir_kappa_min` completes
    /// the right-handed frame. Invalid vertices are left out (`None` if all are).
    pub fn interpolate(&self, tri: [u32; 3], alpha: f32, beta: f32) -> Option<InterpolatedFrame> {
        let w = [1.0 - alpha - beta, alpha, beta];
        let mut n = Vec3::ZERO;
        let mut d = Vec3::ZERO;
        let (mut kmax, mut kmin, mut wsum) = (0.0, 0.0, 0.0);
        let mut d0: Option<Vec3> = None;
        for (k, &i) in tri.iter().enumerate() {
            let i = i as usize;
            if i >= self.len() || !self.valid[i] {
                continue;
            }
            let mut di = self.dir_kappa_max[i];
            match d0 {
                None => d0 = Some(di),
                Some(r) if r.dot(di) < 0.0 => di = -di,
                _ => {}
            }
            n += w[k] * self.normal[i];
            d += w[k] * di;
            kmax += w[k] * self.kappa_max[i];
            kmin += w[k] * self.kappa_min[i];
            wsum += w[k];
        }
        if wsum.abs() < 1e-12 {
            return None;
        }
        let n = n.try_normalize()?;
        let dmax = (d - n * n.dot(d))
            .try_normalize()
            .unwrap_or_else(|| n.any_orthonormal_vector());
        Some(InterpolatedFrame {
            normal: n,
            dir_kappa_max: dmax,
            dir_kappa_min: n.cross(dmax),
            kappa_max: kmax / wsum,
            kappa_min: kmin / wsum,
        })
    }
}

/// Curvature frame at a point inside a triangle ([`CurvatureField::interpolate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolatedFrame {
    /// Unit normal.
    pub normal: Vec3,
    /// Unit direction of maximum curvature, tangent.
    pub dir_kappa_max: Vec3,
    /// Unit direction of minimum curvature: `normal × dir_kappa_max`.
    pub dir_kappa_min: Vec3,
    /// Maximum principal curvature.
    pub kappa_max: f32,
    /// Minimum principal curvature.
    pub kappa_min: f32,
}

fn invalid(n: Vec3) -> Frame {
    Frame {
        n: if n.is_finite() { n } else { Vec3::Z },
        ..Frame::default()
    }
}

/// β(e) |e| ē ēᵀ per edge (= β d dᵀ / |d| with d the edge vector).
fn edge_tensors(topo: &Topology) -> Vec<[f64; 6]> {
    topo.edges
        .iter()
        .zip(&topo.dihedral)
        .map(|(&[a, b], &beta)| {
            let d = topo.positions[b as usize].as_dvec3() - topo.positions[a as usize].as_dvec3();
            let l = d.length();
            if l > 0.0 && beta != 0.0 {
                sym6(d, f64::from(beta) / l)
            } else {
                [0.0; 6]
            }
        })
        .collect()
}

/// Centroid, bounding radius and area per face, for the paper's and the clipped forms.
fn face_data(topo: &Topology) -> Vec<FaceData> {
    topo.triangles
        .par_iter()
        .enumerate()
        .map(|(f, t)| face_record(topo, f, t, &[]))
        .collect()
}

/// Each edge's area total `Σ_g A_g` over its faces (f64, in edge-face order), the
/// denominator of the corrected form's shares; 0 where the edge has no dihedral angle
/// (no share is taken there).
fn edge_area_totals(topo: &Topology) -> Vec<f64> {
    const CHUNK: usize = 4096;
    let mut totals = vec![0f64; topo.edges.len()];
    totals
        .par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            for (i, t) in out.iter_mut().enumerate() {
                let e = c * CHUNK + i;
                if topo.dihedral[e] != 0.0 {
                    let mut s = 0f64;
                    for &g in topo.edge_faces(e) {
                        s += f64::from(topo.face_areas[g as usize]);
                    }
                    *t = s;
                }
            }
        });
    totals
}

/// Centroid, bounding radius, area and the corrected form's `T_f` of one face, given each
/// edge's area total ([`edge_area_totals`]; empty: `T_f` is left zero).
fn face_record(topo: &Topology, f: usize, t: &[u32; 3], totals: &[f64]) -> FaceData {
    if t.iter().any(|&i| i as usize >= topo.positions.len()) {
        return FaceData {
            c: [f32::INFINITY; 3],
            ..FaceData::default()
        };
    }
    let p = t.map(|i| topo.positions[i as usize].as_dvec3());
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let rad = p.iter().map(|q| (*q - c).length()).fold(0.0, f64::max);
    let area = f64::from(topo.face_areas[f]);
    let mut tf = [0f64; 6];
    if !totals.is_empty() && area > 0.0 {
        for k in 0..3 {
            let e = topo.face_edges[f][k];
            if e == NO_EDGE {
                continue;
            }
            let beta = f64::from(topo.dihedral[e as usize]);
            if beta == 0.0 {
                continue;
            }
            let share = area / totals[e as usize];
            let d = p[(k + 1) % 3] - p[k];
            let s = sym6(d, share * beta / d.length());
            for (a, b) in tf.iter_mut().zip(s) {
                *a += b;
            }
        }
    }
    FaceData {
        c: c.as_vec3().to_array(),
        rad: rad as f32,
        area: area as f32,
        t: tf.map(|x| x as f32),
    }
}

/// Restarts the visit marks for a new vertex; returns the stamp for this vertex.
fn next_stamp(s: &mut Scratch, nf: usize, ne: usize) -> u32 {
    if s.face_mark.len() != nf {
        s.face_mark.clear();
        s.face_mark.resize(nf, 0);
        s.stamp = 0;
    }
    if s.edge_mark.len() != ne {
        s.edge_mark.clear();
        s.edge_mark.resize(ne, 0);
        s.stamp = 0;
    }
    s.stamp = s.stamp.wrapping_add(1);
    if s.stamp == 0 {
        s.face_mark.fill(0);
        s.edge_mark.fill(0);
        s.stamp = 1;
    }
    s.stamp
}

/// The corrected form's hot loop: `Σ w_f T_f` and `Σ w_f A_f` over the faces whose
/// centroid lies in the ball, grown from the vertex's faces over face adjacency.
///
/// The depth-first stack is a preallocated slice indexed by hand (a face is pushed at
/// most once per vertex, so it never outgrows the face count): no growth check or
/// reallocation call in the loop, so the accumulators and pointers stay in registers.
fn corrected_frame(topo: &Topology, p: &Packed, v: usize, r: f32, s: &mut Scratch) -> Frame {
    let stamp = next_stamp(s, p.faces.len(), 0);
    let own = topo.vertex_faces(v);
    let Scratch {
        face_mark, stack, ..
    } = s;
    let need = face_mark.len() + own.len();
    if stack.len() < need {
        stack.resize(need, 0);
    }
    let (face_mark, stack) = (face_mark.as_mut_slice(), stack.as_mut_slice());
    let pv = topo.positions[v];
    let r2 = r * r;
    let inv_r2 = 1.0 / r2;
    // Two SIMD accumulators: (xx, xy, xz, yy) and (yz, zz, area, 0).
    let (mut acc0, mut acc1) = (glam::Vec4::ZERO, glam::Vec4::ZERO);
    let mut top = 0;
    for &f in own {
        face_mark[f as usize] = stamp;
        stack[top] = f;
        top += 1;
    }
    while top > 0 {
        top -= 1;
        let f = stack[top] as usize;
        let rec = &p.faces[f];
        let [cx, cy, cz, rad] = rec.sphere;
        let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
        let d2 = dx * dx + dy * dy + dz * dz;
        if d2 < r2 {
            let q = 1.0 - d2 * inv_r2;
            let w = q * q;
            acc0 += w * rec.t0;
            acc1 += w * rec.t1;
        } else {
            // Outside: pass the ball on only if the face is large against the ball and
            // its bounding sphere reaches in (small faces outside have no inside
            // neighbour the ring does not already reach).
            let reach = r + rad;
            if !(rad > 0.5 * r && d2 < reach * reach) {
                continue;
            }
        }
        let nb = if rec.many == 0 {
            &rec.adj[..]
        } else {
            topo.face_neighbours(f)
        };
        for &g in nb {
            let m = &mut face_mark[g as usize];
            if *m != stamp {
                *m = stamp;
                stack[top] = g;
                top += 1;
            }
        }
    }
    let area = f64::from(acc1.z);
    let mesh_n = topo.vertex_normals[v];
    if !(area > 0.0) || !acc0.is_finite() || !acc1.is_finite() {
        return invalid(mesh_n);
    }
    let acc = [acc0.x, acc0.y, acc0.z, acc0.w, acc1.x, acc1.y];
    let t = acc.map(|x| f64::from(x) / area);
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
    tangent_frame(&m, mesh_n.as_dvec3()).unwrap_or_else(|| invalid(mesh_n))
}

/// The paper's and the clipped-edge forms of Eq. (1) at vertex `v` (the corrected form,
/// the default, has its own loop: [`corrected_frame`]; `compute` never sends it here, and
/// a `Corrected` that did arrive is treated as the clipped form).
fn vertex_frame(
    topo: &Topology,
    faces: &[FaceData],
    edge_t: &[[f64; 6]],
    v: usize,
    r: f32,
    method: CurvatureMethod,
    s: &mut Scratch,
) -> Frame {
    let stamp = next_stamp(s, faces.len(), edge_t.len());
    let pv = topo.positions[v];
    let r2 = r * r;
    let mesh_n = topo.vertex_normals[v];
    let mut acc = [0f64; 6];
    let mut area = 0f64;
    s.stack.clear();
    for &f in topo.vertex_faces(v) {
        s.face_mark[f as usize] = stamp;
        s.stack.push(f);
    }
    while let Some(f) = s.stack.pop() {
        let fd = &faces[f as usize];
        let d = Vec3::from_array(fd.c) - pv;
        let d2 = d.length_squared();
        // Paper / clipped: pass the ball on through every face that can touch it.
        let reach = r + fd.rad;
        if !(d2 < reach * reach) {
            continue;
        }
        match method {
            CurvatureMethod::Paper => {
                let t = topo.triangles[f as usize];
                let inside = t
                    .iter()
                    .any(|&i| (topo.positions[i as usize] - pv).length_squared() < r2);
                if inside {
                    area += f64::from(fd.area);
                    for &e in &topo.face_edges[f as usize] {
                        if e != NO_EDGE && s.edge_mark[e as usize] != stamp {
                            s.edge_mark[e as usize] = stamp;
                            for (a, t) in acc.iter_mut().zip(edge_t[e as usize]) {
                                *a += t;
                            }
                        }
                    }
                }
            }
            CurvatureMethod::Clipped | CurvatureMethod::Corrected => {
                let t = topo.triangles[f as usize];
                let p = t.map(|i| topo.positions[i as usize].as_dvec3());
                area += clipped_area(p, pv.as_dvec3(), f64::from(r), 3);
                for &e in &topo.face_edges[f as usize] {
                    if e != NO_EDGE && s.edge_mark[e as usize] != stamp {
                        s.edge_mark[e as usize] = stamp;
                        let [a, b] = topo.edges[e as usize];
                        let frac = clipped_fraction(
                            topo.positions[a as usize].as_dvec3(),
                            topo.positions[b as usize].as_dvec3(),
                            pv.as_dvec3(),
                            f64::from(r),
                        );
                        for (a, t) in acc.iter_mut().zip(edge_t[e as usize]) {
                            *a += frac * t;
                        }
                    }
                }
            }
        }
        for &g in topo.face_neighbours(f as usize) {
            if s.face_mark[g as usize] != stamp {
                s.face_mark[g as usize] = stamp;
                s.stack.push(g);
            }
        }
    }
    if !(area > 0.0) || !acc.iter().all(|x| x.is_finite()) {
        return invalid(mesh_n);
    }
    let t = acc.map(|x| x / area);
    let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
    full_frame(&m, mesh_n.as_dvec3()).unwrap_or_else(|| invalid(mesh_n))
}

/// Projects T onto the tangent plane of `n` and eigen-decomposes the 2×2 restriction.
fn tangent_frame(m: &Matrix3<f64>, n: DVec3) -> Option<Frame> {
    let n = n.try_normalize()?;
    let (t1, t2) = n.any_orthonormal_pair();
    let mv = |a: DVec3| {
        let v = m * nalgebra::Vector3::new(a.x, a.y, a.z);
        DVec3::new(v.x, v.y, v.z)
    };
    let (m1, m2) = (mv(t1), mv(t2));
    let (lam_hi, lam_lo, u) = sym2_eigen(t1.dot(m1), 0.5 * (t1.dot(m2) + t2.dot(m1)), t2.dot(m2));
    // Larger eigenvalue ↔ direction of MINIMUM curvature (the tensor swaps them).
    let dmin = (u[0] * t1 + u[1] * t2).try_normalize()?;
    let dmax = dmin.cross(n);
    finish(n, dmax, lam_hi, lam_lo)
}

/// Closed-form eigen-decomposition of the symmetric 2×2 `[[a, b], [b, c]]`: (larger
/// eigenvalue, smaller eigenvalue, unit eigenvector of the larger). Exact and much
/// cheaper than an iterative solver; a unit test checks it against nalgebra's
/// `SymmetricEigen` (which the 3×3 forms use).
pub(crate) fn sym2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, [f64; 2]) {
    let mean = 0.5 * (a + c);
    let half = 0.5 * (a - c);
    let d = (half * half + b * b).sqrt();
    let (hi, lo) = (mean + d, mean - d);
    // Eigenvector of the larger eigenvalue, from the better-conditioned row.
    let v = if half >= 0.0 {
        [half + d, b]
    } else {
        [b, d - half]
    };
    let l = (v[0] * v[0] + v[1] * v[1]).sqrt();
    let u = if l > 0.0 {
        [v[0] / l, v[1] / l]
    } else {
        [1.0, 0.0]
    };
    (hi, lo, u)
}

/// The paper's eigen-analysis of the full 3×3 T: smallest |eigenvalue| → normal.
fn full_frame(m: &Matrix3<f64>, mesh_n: DVec3) -> Option<Frame> {
    let eig = SymmetricEigen::try_new(*m, 1e-14, 128)?;
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| {
        eig.eigenvalues[a]
            .abs()
            .total_cmp(&eig.eigenvalues[b].abs())
    });
    let col = |i: usize| {
        let c = eig.eigenvectors.column(i);
        DVec3::new(c[0], c[1], c[2])
    };
    let mut n = col(idx[0]).try_normalize()?;
    if n.dot(mesh_n) < 0.0 {
        n = -n;
    }
    let (a, b) = (idx[1], idx[2]);
    let (hi, lo) = if eig.eigenvalues[a] >= eig.eigenvalues[b] {
        (a, b)
    } else {
        (b, a)
    };
    let dmin = col(hi);
    let dmax = dmin.cross(n).try_normalize()?;
    finish(n, dmax, eig.eigenvalues[hi], eig.eigenvalues[lo])
}

fn finish(n: DVec3, dmax: DVec3, kmax: f64, kmin: f64) -> Option<Frame> {
    let dmin = n.cross(dmax);
    let f = Frame {
        n: n.as_vec3(),
        dmax: dmax.as_vec3(),
        dmin: dmin.as_vec3(),
        kmax: kmax as f32,
        kmin: kmin as f32,
        valid: true,
    };
    let finite = f.n.is_finite()
        && f.dmax.is_finite()
        && f.dmin.is_finite()
        && f.kmax.is_finite()
        && f.kmin.is_finite();
    finite.then_some(f)
}

/// Fraction of segment [a, b] inside the ball (centre c, radius r), exact.
fn clipped_fraction(a: DVec3, b: DVec3, c: DVec3, r: f64) -> f64 {
    let d = b - a;
    let dd = d.length_squared();
    if dd == 0.0 {
        return 0.0;
    }
    let f = a - c;
    let bq = f.dot(d) / dd;
    let cq = (f.length_squared() - r * r) / dd;
    let disc = bq * bq - cq;
    if disc <= 0.0 {
        return 0.0;
    }
    let s = disc.sqrt();
    let (t0, t1) = ((-bq - s).max(0.0), (-bq + s).min(1.0));
    (t1 - t0).max(0.0)
}

/// Area of triangle ∩ ball by recursive 1→4 subdivision (`depth` levels), whole
/// sub-triangles accepted or rejected when they lie entirely inside or outside.
fn clipped_area(p: [DVec3; 3], c: DVec3, r: f64, depth: u32) -> f64 {
    let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    let inside = p.iter().all(|q| (*q - c).length_squared() <= r * r);
    if inside {
        return area;
    }
    let cen = (p[0] + p[1] + p[2]) / 3.0;
    let rad = p.iter().map(|q| (*q - cen).length()).fold(0.0, f64::max);
    if (cen - c).length() >= r + rad {
        return 0.0;
    }
    if depth == 0 {
        return if (cen - c).length_squared() < r * r {
            area
        } else {
            0.0
        };
    }
    let m = [
        (p[0] + p[1]) / 2.0,
        (p[1] + p[2]) / 2.0,
        (p[2] + p[0]) / 2.0,
    ];
    clipped_area([p[0], m[0], m[2]], c, r, depth - 1)
        + clipped_area([m[0], p[1], m[1]], c, r, depth - 1)
        + clipped_area([m[2], m[1], p[2]], c, r, depth - 1)
        + clipped_area([m[0], m[1], m[2]], c, r, depth - 1)
}

impl CurvatureField {
    /// The field seen at scale `sigma` (object units; the "abstraction" of a stylized
    /// highlight, beyond the paper): normals and shape operators
    /// `S = κ_max e_max e_maxᵀ + κ_min e_min e_minᵀ` diffused over the mesh's edge graph
    /// (lazy random-walk averaging, `x ← (x + mean of neighbours) / 2`, as many steps as
    /// make a Gaussian of standard deviation `sigma` on edges of the mean length: `4σ²/h²`,
    /// at most [`MAX_SCALE_STEPS`]), then re-analysed: the normal is the averaged normal,
    /// the principal pair the eigen-pairs of the averaged `S` projected onto its tangent
    /// plane. Averaging `S = dN` is, to first order, the shape operator of the surface whose
    /// normals are the averaged ones, so small bumps cancel while the shape of a limb stays
    /// (a sphere or a cylinder keeps its normals exactly). `sigma ≤ 0` (or non-finite)
    /// returns the field as it is. Invalid vertices take no part and stay invalid.
    pub fn at_scale(&self, topology: &Topology, sigma: f32) -> CurvatureField {
        let n = self.len();
        let h = topology.mean_edge_length;
        if !(sigma > 0.0 && sigma.is_finite() && h > 0.0) || topology.vertex_count() != n {
            return self.clone();
        }
        let steps = ((4.0 * sigma * sigma / (h * h)).ceil() as usize).min(MAX_SCALE_STEPS);
        // Vertex neighbours from the edge list (CSR).
        let mut degree = vec![0u32; n + 1];
        for e in &topology.edges {
            degree[e[0] as usize + 1] += 1;
            degree[e[1] as usize + 1] += 1;
        }
        for v in 0..n {
            degree[v + 1] += degree[v];
        }
        let mut fill = degree.clone();
        let mut neighbours = vec![0u32; degree[n] as usize];
        for e in &topology.edges {
            for (a, b) in [(e[0], e[1]), (e[1], e[0])] {
                neighbours[fill[a as usize] as usize] = b;
                fill[a as usize] += 1;
            }
        }
        // Per vertex: normal (3) and the upper triangle of S (6); weight 0 when invalid.
        type Value = [f32; 9];
        let value = |v: usize| -> Value {
            if !self.valid[v] {
                return [0.0; 9];
            }
            let (a, b) = (self.dir_kappa_max[v], self.dir_kappa_min[v]);
            let (ka, kb) = (self.kappa_max[v], self.kappa_min[v]);
            let s = |i: usize, j: usize| ka * a[i] * a[j] + kb * b[i] * b[j];
            let nv = self.normal[v];
            [
                nv.x,
                nv.y,
                nv.z,
                s(0, 0),
                s(0, 1),
                s(0, 2),
                s(1, 1),
                s(1, 2),
                s(2, 2),
            ]
        };
        let mut x: Vec<Value> = (0..n).map(value).collect();
        let mut next = x.clone();
        for _ in 0..steps {
            next.par_iter_mut().enumerate().for_each(|(v, out)| {
                if !self.valid[v] {
                    return;
                }
                let around = &neighbours[degree[v] as usize..degree[v + 1] as usize];
                let mut sum = [0f32; 9];
                let mut count = 0;
                for &w in around {
                    if self.valid[w as usize] {
                        for (s, y) in sum.iter_mut().zip(&x[w as usize]) {
                            *s += y;
                        }
                        count += 1;
                    }
                }
                if count == 0 {
                    *out = x[v];
                    return;
                }
                let inv = 1.0 / count as f32;
                for ((o, own), s) in out.iter_mut().zip(&x[v]).zip(&sum) {
                    *o = 0.5 * own + 0.5 * s * inv;
                }
            });
            std::mem::swap(&mut x, &mut next);
        }
        let mut out = self.clone();
        for (v, &[nx, ny, nz, s00, s01, s02, s11, s12, s22]) in x.iter().enumerate() {
            if !self.valid[v] {
                continue;
            }
            let Some(normal) = Vec3::new(nx, ny, nz).try_normalize() else {
                continue;
            };
            let s = Matrix3::new(s00, s01, s02, s01, s11, s12, s02, s12, s22);
            let nn = nalgebra::Vector3::new(normal.x, normal.y, normal.z);
            let p = Matrix3::identity() - nn * nn.transpose();
            let tangent = p * s * p;
            let eig = SymmetricEigen::new(tangent);
            // The two eigenvectors least along the normal are the principal pair.
            let mut order = [0usize, 1, 2];
            order.sort_by(|&i, &j| {
                let along = |k: usize| eig.eigenvectors.column(k).dot(&nn).abs();
                along(i).total_cmp(&along(j))
            });
            let (i, j) = (order[0], order[1]);
            let (i, j) = if eig.eigenvalues[i] >= eig.eigenvalues[j] {
                (i, j)
            } else {
                (j, i)
            };
            let c = eig.eigenvectors.column(i);
            let Some(e_max) = Vec3::new(c[0], c[1], c[2])
                .reject_from_normalized(normal)
                .try_normalize()
            else {
                continue;
            };
            out.normal[v] = normal;
            out.dir_kappa_max[v] = e_max;
            out.dir_kappa_min[v] = normal.cross(e_max);
            out.kappa_max[v] = eig.eigenvalues[i];
            out.kappa_min[v] = eig.eigenvalues[j];
        }
        out
    }
}

/// Most diffusion steps of [`CurvatureField::at_scale`]: a standard deviation of about 12
/// mean edge lengths. A larger scale is capped there, which bounds the cost at that many
/// passes over the vertices (about 2 s on a million faces on two cores). The bunny at the
/// default abstraction takes 72 steps, Spot 32; a million-face scan would want about
/// 1,600 (a multiresolution smoothing would lift the cap).
pub const MAX_SCALE_STEPS: usize = 600;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift64;
    use nalgebra::Matrix2;

    /// Largest angle (degrees) between a field's normal and the exact sphere normal.
    fn worst_normal_deg(field: &CurvatureField, topo: &Topology) -> f32 {
        field
            .normal
            .iter()
            .zip(&topo.positions)
            .map(|(n, p)| n.dot(p.normalize()).clamp(-1.0, 1.0).acos().to_degrees())
            .fold(0.0, f32::max)
    }

    #[test]
    fn a_scale_smooths_bumps_and_keeps_a_sphere() {
        let (_, topo, field) =
            CurvatureField::for_mesh(&crate::generate::icosphere(4, 1.0), &Default::default());
        // A sphere keeps its normals and its curvature (1/R) at a tenth of its radius.
        let scaled = field.at_scale(&topo, 0.1);
        assert!(worst_normal_deg(&scaled, &topo) < 0.5);
        let mean = scaled.kappa_max.iter().sum::<f32>() / scaled.len() as f32;
        assert!((mean - 1.0).abs() < 0.05, "κ_max {mean}");
        // Bumps of 1 % of the radius: their normals turn by degrees, and the scale takes
        // most of that away.
        let bumpy =
            crate::generate::displace_along_normals(&crate::generate::icosphere(4, 1.0), 0.01, 3);
        let (_, topo, field) = CurvatureField::for_mesh(&bumpy, &Default::default());
        let raw = worst_normal_deg(&field, &topo);
        let smooth = worst_normal_deg(&field.at_scale(&topo, 0.1), &topo);
        assert!(
            raw > 5.0 && smooth < 0.4 * raw,
            "raw {raw}°, at scale {smooth}°"
        );
        // Scale 0 is the field itself.
        assert_eq!(field.at_scale(&topo, 0.0), field);
    }

    #[test]
    fn closed_form_2x2_matches_nalgebra() {
        let mut rng = XorShift64::new(3);
        for k in 0..2000 {
            let (a, mut b, c) = (rng.next_signed(), rng.next_signed(), rng.next_signed());
            if k % 10 == 0 {
                b = 0.0;
            }
            let (hi, lo, u) = sym2_eigen(a, b, c);
            let e = SymmetricEigen::new(Matrix2::new(a, b, b, c));
            let (nh, nl) = (e.eigenvalues.max(), e.eigenvalues.min());
            assert!((hi - nh).abs() < 1e-12 && (lo - nl).abs() < 1e-12);
            // u is an eigenvector of hi.
            let m = Matrix2::new(a, b, b, c) * nalgebra::Vector2::new(u[0], u[1]);
            assert!((m[0] - hi * u[0]).abs() < 1e-12 && (m[1] - hi * u[1]).abs() < 1e-12);
            assert!((u[0].hypot(u[1]) - 1.0).abs() < 1e-12);
        }
    }

    /// The corrected form written plainly, as a reference for the optimised hot loop:
    /// `T_f` in f64 straight from the definition (share `A_f / Σ A_g` of each edge's
    /// `β |e| ē ēᵀ`), a depth-first ball growth with a `Vec` stack and a `HashSet` of
    /// visited faces (same push order as [`corrected_frame`]), and the same f32
    /// accumulation order, so the results should agree to the bit.
    fn corrected_reference(topo: &Topology, r: f32) -> Vec<Frame> {
        use std::collections::HashSet;
        let tf: Vec<([f32; 4], [f32; 6], f32)> = topo
            .triangles
            .iter()
            .enumerate()
            .map(|(f, t)| {
                let p = t.map(|i| topo.positions[i as usize].as_dvec3());
                let c = (p[0] + p[1] + p[2]) / 3.0;
                let rad = p.iter().map(|q| (*q - c).length()).fold(0.0, f64::max);
                let area = f64::from(topo.face_areas[f]);
                let mut m = [0f64; 6];
                for k in 0..3 {
                    let e = topo.face_edges[f][k];
                    if area == 0.0 || e == NO_EDGE || topo.dihedral[e as usize] == 0.0 {
                        continue;
                    }
                    let beta = f64::from(topo.dihedral[e as usize]);
                    let total: f64 = topo
                        .edge_faces(e as usize)
                        .iter()
                        .map(|&g| f64::from(topo.face_areas[g as usize]))
                        .sum();
                    let d = p[(k + 1) % 3] - p[k];
                    let s = area / total * beta / d.length();
                    let dd = [
                        d.x * d.x,
                        d.x * d.y,
                        d.x * d.z,
                        d.y * d.y,
                        d.y * d.z,
                        d.z * d.z,
                    ];
                    for (a, q) in m.iter_mut().zip(dd) {
                        *a += s * q;
                    }
                }
                let c = c.as_vec3();
                (
                    [c.x, c.y, c.z, rad as f32],
                    m.map(|x| x as f32),
                    area as f32,
                )
            })
            .collect();
        (0..topo.vertex_count())
            .map(|v| {
                let pv = topo.positions[v];
                let n = topo.vertex_normals[v];
                if topo.is_isolated(v) {
                    return invalid(n);
                }
                let (mut acc, mut area) = ([0f32; 6], 0f32);
                let mut seen: HashSet<u32> = topo.vertex_faces(v).iter().copied().collect();
                let mut stack = topo.vertex_faces(v).to_vec();
                while let Some(f) = stack.pop() {
                    let ([cx, cy, cz, rad], t, a) = tf[f as usize];
                    let (dx, dy, dz) = (cx - pv.x, cy - pv.y, cz - pv.z);
                    let d2 = dx * dx + dy * dy + dz * dz;
                    if d2 < r * r {
                        let q = 1.0 - d2 * (1.0 / (r * r));
                        let w = q * q;
                        for (x, y) in acc.iter_mut().zip(t) {
                            *x += w * y;
                        }
                        area += w * a;
                    } else if !(rad > 0.5 * r && d2 < (r + rad) * (r + rad)) {
                        continue;
                    }
                    for &g in topo.face_neighbours(f as usize) {
                        if seen.insert(g) {
                            stack.push(g);
                        }
                    }
                }
                let area = f64::from(area);
                if !(area > 0.0) {
                    return invalid(n);
                }
                let t = acc.map(|x| f64::from(x) / area);
                let m = Matrix3::new(t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]);
                tangent_frame(&m, n.as_dvec3()).unwrap_or_else(|| invalid(n))
            })
            .collect()
    }

    /// The optimised corrected form against [`corrected_reference`] on irregular meshes:
    /// a jittered, noisy torus with a hole cut out, a few large faces (the "large
    /// against the ball" path), a fin and a duplicate face (non-manifold edges), and the
    /// scanned bunny (holes, uneven triangles).
    #[test]
    fn corrected_matches_plain_reference() {
        use crate::generate;
        let mut mesh = generate::torus_jittered(2.0, 0.7, 90, 40, 0.3, 5);
        mesh = generate::displace_along_normals(&mesh, 0.01, 9);
        let mut w = weld(&mesh);
        w.indices
            .retain(|t| t.iter().all(|&i| !(200..260).contains(&i)));
        // Large triangles spanning the torus, sharing vertices with it.
        w.indices
            .extend_from_slice(&[[0, 1500, 3000], [10, 2000, 3500]]);
        let bunny = crate::load_obj(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/meshes/stanford-bunny.obj"
        ))
        .unwrap();
        for (name, topo) in [
            ("torus", Topology::new(&w)),
            ("bunny", Topology::new(&weld(&bunny))),
        ] {
            let opts = CurvatureOptions::default();
            let got = CurvatureField::compute_at_scale(&topo, &opts);
            let want = corrected_reference(&topo, got.radius_world);
            let mut valid = 0;
            for (v, f) in want.iter().enumerate() {
                let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
                let close3 = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-6;
                assert_eq!(got.valid[v], f.valid, "{name} vertex {v}");
                assert!(close(got.kappa_max[v], f.kmax), "{name} vertex {v}");
                assert!(close(got.kappa_min[v], f.kmin), "{name} vertex {v}");
                assert!(close3(got.normal[v], f.n), "{name} vertex {v}");
                assert!(close3(got.dir_kappa_max[v], f.dmax), "{name} vertex {v}");
                assert!(close3(got.dir_kappa_min[v], f.dmin), "{name} vertex {v}");
                valid += usize::from(f.valid);
            }
            assert!(valid > want.len() * 9 / 10, "{name}: {valid} valid");
        }
    }
}
