//! Highlight centres: the points where `N = H` (maximum specular intensity), Eq. (3)–(6),
//! §3.1 of Hwan-Jik Lee and Jung-Ju Choi, "Stylized Specular Reflections Using Projective
//! Textures based on Principal Curvature Analysis" (Journal of the Korea Computer
//! Graphics Society).
//!
//! Eq. (4)–(5): inside triangle F, `p = p0 + α Δp1 + β Δp2`, `N = N0 + α ΔN1 + β ΔN2`,
//! `H = H0 + α ΔH1 + β ΔH2`. Eq. (6): `[ΔN1−ΔH1  ΔN2−ΔH2] [α β]ᵀ = H0 − N0`, solved by
//! pseudo-inverse, accepted when `−ε ≤ α, β, α+β ≤ 1+ε`.
//!
//! Normalisation (our choice): Eq. (6) equates the *unnormalised* interpolants, three
//! equations in two unknowns, which generally has no exact solution even where the
//! interpolated normal and half vector *are* parallel (their lengths differ inside the
//! triangle). What Eq. (3) asks, `N̂ · Ĥ = 1`, is two equations on the unit sphere. So
//! [`try_solve_barycentric`] takes the Eq. (6) pseudo-inverse solution as its start and
//! refines it with Gauss–Newton on `N̂(α,β) − Ĥ(α,β) = 0`, accepting only when that
//! residual is below [`RESIDUAL_TOLERANCE`]. Where the paper's system has an exact
//! solution (`N = H` exactly), the start is already the answer.
//! [`try_solve_barycentric_eq6`] is the paper's solve alone.
//!
//! Normal field (beyond the paper): the per-frame search solves, by default, on a
//! curvature-blended normal field ([`NormalInterpolation::Curvature`]) instead of the
//! linear interpolation of Eq. (4). The linear field's gradient jumps across edges, so a
//! centre under steady rotation changes speed abruptly at each face crossing (worst step
//! 4.1× its neighbours' on the paper's knot); blending each vertex's first-order model
//! `N_i + S_i (p − p_i)` (shape operator from the curvature field) brings that to 1.9×
//! (`npr-specular`'s coherence test). [`NormalInterpolation::Linear`] keeps the paper's
//! form.
//!
//! Normal source: Eq. (4) interpolates the vertex normals the mesh is *shaded* with, so
//! [`HighlightSearch::for_mesh`] takes the render mesh's own normals (averaged over render
//! vertices that weld together) whenever the mesh has them ([`NormalSource::Mesh`]);
//! [`HighlightSearch::new`] uses the curvature field's normals ([`NormalSource::Field`],
//! area-weighted normals of the welded mesh for the default method). The two differ where
//! an exporter or artist set normals that are not the area-weighted ones, and the centre
//! must land on the shaded peak.

use glam::{DVec3, Mat3, Mat4, Vec3};
use rayon::prelude::*;

use crate::{CurvatureField, Mesh, Topology, Welded};

/// ε of the acceptance test `−ε ≤ α, β, α+β ≤ 1+ε` (§3.1).
pub const BARYCENTRIC_EPSILON: f64 = 1e-3;

/// Largest accepted `|N̂ − Ĥ|` at the solution (about 0.06°).
pub const RESIDUAL_TOLERANCE: f64 = 1e-3;

/// The paper's Eq. (6) alone: least-squares `(α, β)` by pseudo-inverse, accepted by the
/// ε test; `None` when the 3×2 system is rank-deficient (e.g. constant N and H over the
/// triangle) or the point lies outside. No residual test: the result minimises
/// `|N − H|` but need not make them parallel.
pub fn try_solve_barycentric_eq6(n: [Vec3; 3], h: [Vec3; 3]) -> Option<(f32, f32)> {
    let (n, h) = (n.map(Vec3::as_dvec3), h.map(Vec3::as_dvec3));
    let (a, b) = eq6(n, h)?;
    inside(a, b).then_some((a as f32, b as f32))
}

fn eq6(n: [DVec3; 3], h: [DVec3; 3]) -> Option<(f64, f64)> {
    let c1 = (n[1] - n[0]) - (h[1] - h[0]);
    let c2 = (n[2] - n[0]) - (h[2] - h[0]);
    let rhs = h[0] - n[0];
    let (g11, g12, g22) = (c1.dot(c1), c1.dot(c2), c2.dot(c2));
    let det = g11 * g22 - g12 * g12;
    // Rank test relative to the columns' size.
    if !(det > 1e-12 * g11 * g22) || !(g11 * g22 > 1e-30) {
        return None;
    }
    let (r1, r2) = (c1.dot(rhs), c2.dot(rhs));
    let a = (g22 * r1 - g12 * r2) / det;
    let b = (g11 * r2 - g12 * r1) / det;
    (a.is_finite() && b.is_finite()).then_some((a, b))
}

fn inside(a: f64, b: f64) -> bool {
    let e = BARYCENTRIC_EPSILON;
    a >= -e && b >= -e && a + b <= 1.0 + e && a <= 1.0 + e && b <= 1.0 + e
}

/// Eq. (6) solve with normalisation (see the module doc): `Some((α, β))` for the point
/// of the triangle where the interpolated normal `N0 + αΔN1 + βΔN2` and half vector are
/// parallel (same direction), within ε of the triangle (§3.1); `None` for degenerate
/// systems, points outside, and triangles without such a point.
pub fn try_solve_barycentric(n: [Vec3; 3], h: [Vec3; 3]) -> Option<(f32, f32)> {
    let (n, h) = (n.map(Vec3::as_dvec3), h.map(Vec3::as_dvec3));
    let (a, b) = solve_normalised(n, h)?;
    Some((a as f32, b as f32))
}

fn solve_normalised(n: [DVec3; 3], h: [DVec3; 3]) -> Option<(f64, f64)> {
    let (dn1, dn2) = (n[1] - n[0], n[2] - n[0]);
    gauss_newton(n, h, 6, |a, b| (n[0] + a * dn1 + b * dn2, dn1, dn2))
}

/// Gauss–Newton on `N̂(α,β) − Ĥ(α,β) = 0` from the Eq. (6) start, for a normal field
/// given as `normal(α, β) = (N, ∂N/∂α, ∂N/∂β)` and the linearly interpolated `H`.
/// Accepts the point when the residual is below [`RESIDUAL_TOLERANCE`] and it lies in
/// the triangle (ε test).
fn gauss_newton(
    n: [DVec3; 3],
    h: [DVec3; 3],
    iterations: usize,
    normal: impl Fn(f64, f64) -> (DVec3, DVec3, DVec3),
) -> Option<(f64, f64)> {
    let (mut a, mut b) = eq6(n, h)?;
    // Far outside: Gauss–Newton would wander; the pseudo-inverse start is good to
    // first order, so a start well outside means no centre here.
    if a < -0.5 || b < -0.5 || a + b > 1.5 {
        return None;
    }
    let (dh1, dh2) = (h[1] - h[0], h[2] - h[0]);
    let mut res = f64::INFINITY;
    for _ in 0..iterations {
        let (nv, dn1, dn2) = normal(a, b);
        let hv = h[0] + a * dh1 + b * dh2;
        let (ln, lh) = (nv.length(), hv.length());
        if !(ln > 1e-12 && lh > 1e-12) {
            return None;
        }
        let (nn, hn) = (nv / ln, hv / lh);
        let r = nn - hn;
        res = r.length();
        if res < 1e-12 {
            break;
        }
        // d(v/|v|) = (I − v̂v̂ᵀ) dv / |v|
        let proj = |u: DVec3, d: DVec3, l: f64| (d - u * u.dot(d)) / l;
        let j1 = proj(nn, dn1, ln) - proj(hn, dh1, lh);
        let j2 = proj(nn, dn2, ln) - proj(hn, dh2, lh);
        let (g11, g12, g22) = (j1.dot(j1), j1.dot(j2), j2.dot(j2));
        let det = g11 * g22 - g12 * g12;
        if !(det > 1e-14 * g11 * g22) {
            break;
        }
        let (r1, r2) = (j1.dot(r), j2.dot(r));
        let da = -(g22 * r1 - g12 * r2) / det;
        let db = -(g11 * r2 - g12 * r1) / det;
        a += da;
        b += db;
        if !(a.is_finite() && b.is_finite()) || a.abs() > 4.0 || b.abs() > 4.0 {
            return None;
        }
        if da.abs() + db.abs() < 1e-13 {
            let (nv, ..) = normal(a, b);
            let hv = h[0] + a * dh1 + b * dh2;
            res = (nv.normalize_or_zero() - hv.normalize_or_zero()).length();
            break;
        }
    }
    (res < RESIDUAL_TOLERANCE && inside(a, b)).then_some((a, b))
}

/// How the normal field inside a triangle is interpolated for the `N = H` solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalInterpolation {
    /// The paper's Eq. (4): `N = N0 + αΔN1 + βΔN2`, linear in the barycentric
    /// coordinates. Its gradient is constant per face and jumps across edges, so a
    /// centre's speed under steady rotation jumps where it crosses a face (up to 4× on the
    /// paper's knot).
    Linear,
    /// Beyond the paper (default): each vertex contributes its own first-order model of
    /// the surface normal, `N_i + S_i (p − p_i)`, with `S_i = κ_max e_max e_maxᵀ +
    /// κ_min e_min e_minᵀ` its shape operator from the curvature field, blended with the
    /// barycentric weights. The models agree where the curvature is right, so the blend's
    /// gradient is the interpolated shape operator, continuous across edges, and centres
    /// glide at a steady speed. On an edge only that edge's two vertices count, so the
    /// field is continuous across faces.
    #[default]
    Curvature,
}

/// Gauss–Newton on `N̂(α,β) − Ĥ(α,β) = 0` for the curvature-blended normal field of
/// [`NormalInterpolation::Curvature`]: `N(α,β) = Σ w_i (N_i + S_i (p(α,β) − p_i))`,
/// `w = (1−α−β, α, β)`. Starts from the Eq. (6) solution of the linear field.
fn solve_curvature(
    n: [DVec3; 3],
    h: [DVec3; 3],
    p: [DVec3; 3],
    shape: [glam::DMat3; 3],
) -> Option<(f64, f64)> {
    let (dp1, dp2) = (p[1] - p[0], p[2] - p[0]);
    gauss_newton(n, h, 10, |a, b| {
        let w = [1.0 - a - b, a, b];
        let x = p[0] + a * dp1 + b * dp2;
        let model = [0, 1, 2].map(|i| n[i] + shape[i] * (x - p[i]));
        let nv = w[0] * model[0] + w[1] * model[1] + w[2] * model[2];
        let blended_shape = shape[0] * w[0] + shape[1] * w[1] + shape[2] * w[2];
        (
            nv,
            model[1] - model[0] + blended_shape * dp1,
            model[2] - model[0] + blended_shape * dp2,
        )
    })
}

/// Where the light and the eye are, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightEye {
    /// Point light and perspective eye: `L` and `V` vary over the surface.
    Positions {
        /// Light position.
        light: Vec3,
        /// Eye position.
        eye: Vec3,
    },
    /// Directional light and orthographic (infinitely far) eye: `H` is constant.
    Directions {
        /// Unit-or-not direction from the surface towards the light.
        to_light: Vec3,
        /// Direction from the surface towards the eye.
        to_eye: Vec3,
    },
}

/// One highlight centre (maximum specular intensity point, §3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightCentre {
    /// Triangle holding the point (index into [`Topology::triangles`]).
    pub face: u32,
    /// Barycentric α of Eq. (4) (weight of the triangle's vertex 1).
    pub alpha: f32,
    /// Barycentric β of Eq. (4) (weight of vertex 2).
    pub beta: f32,
    /// Point in object space.
    pub position_object: Vec3,
    /// Point in world space.
    pub position_world: Vec3,
    /// Interpolated unit normal, object space.
    pub normal_object: Vec3,
    /// Unit normal in world space (transformed by the inverse transpose).
    pub normal_world: Vec3,
    /// Unit direction of maximum curvature, world space, tangent.
    pub dir_kappa_max: Vec3,
    /// Unit direction of minimum curvature, world space: `normal_world × dir_kappa_max`.
    pub dir_kappa_min: Vec3,
    /// Maximum principal curvature in 1/world unit (object value divided by the
    /// transform's mean scale `|det|^(1/3)`; exact for rotations with uniform scale).
    pub kappa_max: f32,
    /// Minimum principal curvature in 1/world unit (same scaling).
    pub kappa_min: f32,
}

/// Per-mesh data for the per-frame centre search, built once from the topology and the
/// curvature field.
#[derive(Clone, Debug)]
pub struct HighlightSearch {
    /// Unique per built search (clones share it: same data), what [`SearchCoherence`]
    /// keys on so that its state is never used for another mesh.
    id: u64,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    field: CurvatureField,
    vf_offsets: Vec<u32>,
    vf: Vec<u32>,
    /// Per vertex: cos of the largest angle between two vertex normals of any face
    /// around it (the normal spread a centre in those faces can be away from N_v).
    cos_spread: Vec<f32>,
    /// Per vertex: longest incident edge, object space.
    reach: Vec<f32>,
    merge_distance: f32,
    /// Per-vertex shape operators `S = κ_max e_max e_maxᵀ + κ_min e_min e_minᵀ` (object
    /// space; zero where the field is invalid), for [`NormalInterpolation::Curvature`].
    shape: Vec<Mat3>,
    /// Per-vertex extra slack of the rejection tests for the curvature-blended field,
    /// whose normals can leave the cone of the three vertex normals (bound in
    /// `with_normals`): the largest over the vertex's faces.
    curvature_margin: Vec<f32>,
    /// The same per face (the per-vertex value is the largest over the vertex's faces).
    face_curvature_margin: Vec<f32>,
    /// Which normal field the solve uses.
    pub interpolation: NormalInterpolation,
    normal_source: NormalSource,
    /// Vertex clusters with bounds on their normals: the coarsest rejection.
    clusters: Vec<Cluster>,
    /// Vertices in cluster order (each cluster is a range of this).
    cluster_vertices: Vec<u32>,
}

/// Vertices per [`Cluster`].
const CLUSTER_SIZE: usize = 16;

/// A cluster of nearby vertices and bounds over them, for a normal-cone rejection of
/// whole clusters before the per-vertex tests (a one-level normal-cone hierarchy).
#[derive(Clone, Debug)]
struct Cluster {
    /// Range of [`HighlightSearch::cluster_vertices`].
    start: u32,
    end: u32,
    /// Centre of the vertices' bounding box.
    centre: Vec3,
    /// Largest `|p_v − centre| + reach_v`: every point of every face around the
    /// cluster's vertices lies within it.
    radius: f32,
    /// Cone axis of the vertex normals (unit; zero when they span no cone).
    axis: Vec3,
    /// Largest angle between `axis` and a vertex normal (π without a cone).
    spread: f32,
    /// Smallest `cos_spread_v − ANGLE_MARGIN` over the vertices.
    cmin_linear: f32,
    /// Smallest `cos_spread_v − ANGLE_MARGIN − curvature_margin_v`.
    cmin_curved: f32,
}

/// Vertices grouped in clusters of [`CLUSTER_SIZE`] along a Morton (Z-order) curve of
/// their positions, so each cluster is compact in space.
fn build_clusters(
    positions: &[Vec3],
    normals: &[Vec3],
    cos_spread: &[f32],
    reach: &[f32],
    curvature_margin: &[f32],
) -> (Vec<Cluster>, Vec<u32>) {
    let nv = positions.len();
    let (lo, hi) = positions.iter().filter(|p| p.is_finite()).fold(
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
    let morton = |p: Vec3| -> u32 {
        if !p.is_finite() {
            return u32::MAX;
        }
        let q = ((p - lo) / extent * 1023.0).clamp(Vec3::ZERO, Vec3::splat(1023.0));
        spread_bits(q.x as u32) | (spread_bits(q.y as u32) << 1) | (spread_bits(q.z as u32) << 2)
    };
    let mut order: Vec<u32> = (0..nv as u32).collect();
    order.sort_by_key(|&v| morton(positions[v as usize]));
    let clusters = order
        .chunks(CLUSTER_SIZE)
        .enumerate()
        .map(|(i, chunk)| {
            let vs = || chunk.iter().map(|&v| v as usize);
            let (clo, chi) = vs().fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), v| (lo.min(positions[v]), hi.max(positions[v])),
            );
            let centre = (clo + chi) * 0.5;
            let radius = vs()
                .map(|v| positions[v].distance(centre) + reach[v])
                .fold(0f32, f32::max);
            let sum: Vec3 = vs().map(|v| normals[v]).sum();
            let axis = sum.normalize_or_zero();
            let spread = if axis == Vec3::ZERO {
                std::f32::consts::PI
            } else {
                vs().map(|v| normals[v].dot(axis).clamp(-1.0, 1.0).acos())
                    .fold(0f32, f32::max)
            };
            let cmin_linear = vs()
                .map(|v| cos_spread[v] - ANGLE_MARGIN)
                .fold(f32::MAX, f32::min);
            let cmin_curved = vs()
                .map(|v| cos_spread[v] - ANGLE_MARGIN - curvature_margin[v])
                .fold(f32::MAX, f32::min);
            let finite = radius.is_finite() && spread.is_finite() && centre.is_finite();
            Cluster {
                start: (i * CLUSTER_SIZE) as u32,
                end: (i * CLUSTER_SIZE + chunk.len()) as u32,
                centre,
                radius: if finite { radius } else { f32::INFINITY },
                axis: if finite { axis } else { Vec3::ZERO },
                spread: if finite { spread } else { std::f32::consts::PI },
                cmin_linear,
                cmin_curved,
            }
        })
        .collect();
    (clusters, order)
}

/// Where [`HighlightSearch`] takes its vertex normals from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalSource {
    /// The curvature field's normals ([`CurvatureField::normal`]).
    #[default]
    Field,
    /// The render mesh's own normals, the ones shading interpolates (a welded vertex takes
    /// the normalised sum of its render vertices' normals).
    Mesh,
}

/// The render mesh's normals per welded vertex: the normalised sum over the render
/// vertices that weld into it. `None` when the mesh has no usable normals (count differs
/// from the positions', or the weld map does not fit the mesh); a welded vertex whose
/// normals sum to zero or are not finite gets `Vec3::ZERO` (callers fall back there).
pub fn welded_mesh_normals(mesh: &Mesh, welded: &Welded) -> Option<Vec<Vec3>> {
    let n = mesh.positions.len();
    if n == 0 || mesh.normals.len() != n || welded.render_to_welded.len() != n {
        return None;
    }
    let mut sum = vec![Vec3::ZERO; welded.positions.len()];
    for (&w, &normal) in welded.render_to_welded.iter().zip(&mesh.normals) {
        if let Some(s) = sum.get_mut(w as usize) {
            *s += normal;
        }
    }
    let out: Vec<Vec3> = sum
        .into_iter()
        .map(|s| s.try_normalize().unwrap_or(Vec3::ZERO))
        .collect();
    out.iter().any(|v| *v != Vec3::ZERO).then_some(out)
}

/// Margin (rad) added to the rejection bounds for the ε-acceptance and rounding.
const ANGLE_MARGIN: f32 = 0.01;

impl HighlightSearch {
    /// Prepares the search on the curvature field's normals ([`NormalSource::Field`]).
    /// For a render mesh prefer [`HighlightSearch::for_mesh`], which solves on the normals
    /// the mesh is shaded with.
    pub fn new(topo: &Topology, field: &CurvatureField) -> Self {
        Self::with_normals(topo, field, None)
    }

    /// Prepares the search for a render mesh and its weld (`topo` built from `welded`):
    /// on the mesh's own normals ([`NormalSource::Mesh`], see [`welded_mesh_normals`])
    /// when it has them, else on the field's. Principal directions and curvatures still
    /// come from `field`, projected onto the tangent plane of the normal used.
    pub fn for_mesh(mesh: &Mesh, welded: &Welded, topo: &Topology, field: &CurvatureField) -> Self {
        let normals = welded_mesh_normals(mesh, welded).filter(|n| n.len() == topo.vertex_count());
        Self::with_normals(topo, field, normals.as_deref())
    }

    /// The point at barycentric (`alpha`, `beta`) of `face` under `world_from_object`,
    /// with its frame: how a highlight that is no longer found (fading out) is re-placed
    /// when the object moves. `None` for an unknown face, a singular transform or a point
    /// without a normal.
    pub fn centre_at(
        &self,
        face: u32,
        alpha: f32,
        beta: f32,
        world_from_object: Mat4,
    ) -> Option<HighlightCentre> {
        let t = *self.triangles.get(face as usize)?;
        if t.iter().any(|&i| i as usize >= self.positions.len()) {
            return None;
        }
        let normal_world_from_object = Mat3::from_mat4(world_from_object).inverse().transpose();
        if !normal_world_from_object.is_finite() {
            return None;
        }
        self.centre(
            face,
            t,
            alpha,
            beta,
            world_from_object,
            normal_world_from_object,
        )
    }

    /// Which normals the search solves on.
    pub fn normal_source(&self) -> NormalSource {
        self.normal_source
    }

    /// The unit vertex normals the search solves on, one per welded vertex, object space
    /// (the mesh's own where [`NormalSource::Mesh`]): what a renderer shades with, so the
    /// region `N·H ≥ σ` a highlight stylizes is measured on them.
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// `normals`: one per welded vertex (zero entries fall back to the field's), or
    /// `None` for the field's.
    fn with_normals(topo: &Topology, field: &CurvatureField, given: Option<&[Vec3]>) -> Self {
        let nv = topo.vertex_count();
        let normal_source = if given.is_some() {
            NormalSource::Mesh
        } else {
            NormalSource::Field
        };
        let normals: Vec<Vec3> = (0..nv)
            .map(|v| {
                given
                    .and_then(|n| n.get(v).copied())
                    .filter(|n| *n != Vec3::ZERO && n.is_finite())
                    .or_else(|| field.normal.get(v).copied())
                    .unwrap_or(topo.vertex_normals[v])
            })
            .collect();
        let mut vf_offsets = Vec::with_capacity(nv + 1);
        let mut vf = Vec::new();
        vf_offsets.push(0);
        for v in 0..nv {
            vf.extend_from_slice(topo.vertex_faces(v));
            vf_offsets.push(vf.len() as u32);
        }
        let mut cos_spread = vec![1f32; nv];
        let mut reach = vec![0f32; nv];
        for t in &topo.triangles {
            if t.iter().any(|&i| i as usize >= nv) {
                continue;
            }
            let mut c = 1f32;
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                c = c.min(normals[a].dot(normals[b]).clamp(-1.0, 1.0));
                let l = topo.positions[a].distance(topo.positions[b]);
                reach[a] = reach[a].max(l);
                reach[b] = reach[b].max(l);
            }
            for &i in t {
                cos_spread[i as usize] = cos_spread[i as usize].min(c);
            }
        }
        let shape: Vec<Mat3> = (0..nv)
            .map(|v| {
                if !field.valid.get(v).copied().unwrap_or(false) {
                    return Mat3::ZERO;
                }
                let outer = |d: Vec3, k: f32| Mat3::from_cols(d * d.x, d * d.y, d * d.z) * k;
                outer(field.dir_kappa_max[v], field.kappa_max[v])
                    + outer(field.dir_kappa_min[v], field.kappa_min[v])
            })
            .collect();
        // How far the blended normal can leave the cone of the vertex normals in a face:
        // N(w) − Σ wᵢNᵢ = Σᵢ wᵢSᵢ(x − pᵢ) = Σ_{i<j} wᵢwⱼ(Sᵢ − Sⱼ)(pⱼ − pᵢ), at most
        // (1/3)·max‖Sᵢ − Sⱼ‖·e_max since Σ_{i<j} wᵢwⱼ ≤ 1/3; against |Σ wᵢNᵢ| ≥
        // sqrt((1 + 2c)/3) (c the smallest Nᵢ·Nⱼ) that turns the unit normal by at most
        // the ratio, which bounds the change of any cosine. Small where the curvature is
        // consistent (Sᵢ ≈ Sⱼ), large on a noisy scan's bumps. Kept per face for the face
        // test and per vertex (largest over its faces) for the vertex and cluster tests,
        // so that rough regions do not weaken the rejection elsewhere.
        let mut curvature_margin = vec![0f32; nv];
        let mut face_curvature_margin = vec![2f32; topo.triangles.len()];
        for (f, t) in topo
            .triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.iter().all(|&i| (i as usize) < nv))
        {
            let [a, b, c] = t.map(|i| i as usize);
            let frob = |m: Mat3| {
                (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared())
                    .sqrt()
            };
            let ds = frob(shape[a] - shape[b])
                .max(frob(shape[b] - shape[c]))
                .max(frob(shape[c] - shape[a]));
            let p = &topo.positions;
            let e = p[a]
                .distance(p[b])
                .max(p[b].distance(p[c]))
                .max(p[c].distance(p[a]));
            let cmin = normals[a]
                .dot(normals[b])
                .min(normals[b].dot(normals[c]))
                .min(normals[c].dot(normals[a]));
            let u_min = ((1.0 + 2.0 * cmin) / 3.0).max(0.0).sqrt();
            let bound = ds * e / 3.0;
            // A slack of 2 in a cosine passes everything.
            let m = if u_min > 0.25 && bound.is_finite() {
                (bound / u_min).min(2.0)
            } else {
                2.0
            };
            face_curvature_margin[f] = m;
            for &i in t {
                curvature_margin[i as usize] = curvature_margin[i as usize].max(m);
            }
        }
        let (clusters, cluster_vertices) = build_clusters(
            &topo.positions,
            &normals,
            &cos_spread,
            &reach,
            &curvature_margin,
        );
        static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        Self {
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            clusters,
            cluster_vertices,
            positions: topo.positions.clone(),
            triangles: topo.triangles.clone(),
            normals,
            field: field.clone(),
            vf_offsets,
            vf,
            cos_spread,
            reach,
            merge_distance: 1e-2 * topo.mean_edge_length,
            shape,
            curvature_margin,
            face_curvature_margin,
            interpolation: NormalInterpolation::default(),
            normal_source,
        }
    }

    /// Every highlight centre on the mesh for this light, eye and object transform
    /// (`world_from_object`, affine), duplicates from neighbouring faces merged.
    ///
    /// Cheap rejection first, every test conservative (they never drop a centre):
    /// 0. per cluster of 16 nearby vertices (Morton order): the cluster's normal cone
    ///    against the half vectors its faces can see, bounded over its bounding sphere
    ///    (point light and near eye included); a cluster that fails is skipped whole, so a
    ///    frame costs about the clusters plus the vertices near highlights;
    /// 1. per vertex: a centre in a face around `v` means `angle(N_v, H_v) ≤ s_v + b_v`,
    ///    with `s_v` the normal spread of those faces (precomputed) and `b_v` a bound on
    ///    how far `H` turns across them (0 for directions; from the edge length, the
    ///    distances to light and eye and `|L̂ + V̂|` for positions). A face is solved only
    ///    if its three vertices pass.
    /// 2. per face: the averaged half vector must lie in the cone of the three vertex
    ///    normals, up to the same bound (`N(α, β)` with non-negative weights spans exactly
    ///    that cone).
    ///
    /// Then Eq. (6) and its normalised refinement ([`try_solve_barycentric`]).
    pub fn find(&self, light_eye: LightEye, world_from_object: Mat4) -> Vec<HighlightCentre> {
        self.find_with(light_eye, world_from_object, true)
    }

    /// [`HighlightSearch::find`] without the cheap rejection: every face is solved. For
    /// tests (the rejection must lose nothing) and for measuring what it saves.
    pub fn find_exhaustive(
        &self,
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        self.find_with(light_eye, world_from_object, false)
    }

    /// How many vertices survive the cluster (normal-cone) rejection of
    /// [`HighlightSearch::find`] for this light, eye and transform, out of all of them:
    /// what the per-vertex tests still look at (for measurements and tests).
    pub fn candidate_vertices(&self, light_eye: LightEye, world_from_object: Mat4) -> usize {
        match self.setup(light_eye, world_from_object) {
            Some(frame) if frame.clusters_apply() => {
                self.active_vertices(&frame, Budget::NONE).len()
            }
            _ => self.positions.len(),
        }
    }

    /// The per-frame values every test uses; `None` for a singular transform, an empty
    /// mesh or a light and eye without a half vector.
    fn setup(&self, light_eye: LightEye, world_from_object: Mat4) -> Option<FrameSetup> {
        let lin = Mat3::from_mat4(world_from_object);
        let normal_world_from_object = lin.inverse().transpose();
        if !normal_world_from_object.is_finite() || self.positions.is_empty() {
            return None;
        }
        let (sigma_max, cond) = svd_ratio(lin);
        let kind = match light_eye {
            LightEye::Directions { to_light, to_eye } => {
                let s = to_light.normalize_or_zero() + to_eye.normalize_or_zero();
                // N_w ∥ H_w ⇔ N_o ∥ Lᵀ H_w (normals transform by the inverse transpose).
                let h = (lin.transpose() * s.normalize_or_zero()).normalize_or_zero();
                if h == Vec3::ZERO {
                    return None;
                }
                FrameKind::Direction(h)
            }
            LightEye::Positions { light, eye } => {
                let object_from_world = world_from_object.inverse();
                FrameKind::Positions {
                    light,
                    eye,
                    light_o: object_from_world.transform_point3(light),
                    eye_o: object_from_world.transform_point3(eye),
                }
            }
        };
        Some(FrameSetup {
            world_from_object,
            lin,
            normal_world_from_object,
            sigma_max,
            cond,
            similarity: cond < SIMILARITY_COND,
            curved: self.interpolation == NormalInterpolation::Curvature,
            kind,
        })
    }

    /// The vertices of the clusters that can hold a centre (the coarsest rejection): a
    /// cluster whose normals all lie more than the per-vertex test's largest allowance
    /// away from every half vector its faces can see is skipped whole. Conservative: a
    /// skipped vertex would have failed its own test (see [`HighlightSearch::find`]).
    /// With a motion `budget`, a skipped vertex also fails it after the light and eye
    /// move by up to the budget (see [`SearchCoherence`]).
    fn active_vertices(&self, frame: &FrameSetup, budget: Budget) -> Vec<u32> {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let keep = |c: &Cluster| -> bool {
            if c.axis == Vec3::ZERO || !c.radius.is_finite() {
                return true;
            }
            let cmin = if frame.curved {
                c.cmin_curved
            } else {
                c.cmin_linear
            };
            // H at the centre, how far the per-vertex allowance b_v can grow (b), how far
            // H itself turns over the cluster (b_h), and how far the budgeted motion can
            // turn it (phi).
            let (hc, b, b_h, phi) = match frame.kind {
                FrameKind::Direction(h) => (h, 0.0, 0.0, budget.angle),
                FrameKind::Positions { light_o, eye_o, .. } => {
                    let (l, e) = (light_o - c.centre, eye_o - c.centre);
                    let (ll, le) = (l.length(), e.length());
                    let s = l / ll + e / le;
                    let sl = s.length();
                    if !(sl > 1e-6) || !s.is_finite() {
                        return true;
                    }
                    let r = c.radius;
                    // Turn of L̂ (V̂) between the centre and any point within r of it, and
                    // the per-vertex turn bound at any vertex (its reach ≤ r, its distance
                    // ≥ d − r): both ≤ turn(d − r) with the vertex formula.
                    let turn = |d: f32| turn_bound(r, d - r);
                    let t = turn(ll) + turn(le);
                    // The same after the light and eye move by their budgets.
                    let t_moved = turn(ll - budget.light) + turn(le - budget.eye);
                    if t_moved >= half_pi {
                        return true;
                    }
                    let Some(tau) = budget.direction_turn(ll - r, le - r) else {
                        return true;
                    };
                    if sl - t <= tau {
                        return true;
                    }
                    let b = (t_moved / (sl - t - tau - t_moved).max(1e-3)).min(4.0);
                    let b_h = (t / (sl - t).max(1e-3)).min(std::f32::consts::PI);
                    (s / sl, b, b_h, (tau / (sl - t)).min(1.0).asin())
                }
            };
            let allowance = (cmin - b).clamp(-1.0, 1.0).acos();
            let angle = c.axis.dot(hc).clamp(-1.0, 1.0).acos();
            angle <= c.spread + b_h + allowance + phi + ANGLE_MARGIN
        };
        let mut out = Vec::new();
        for c in &self.clusters {
            if keep(c) {
                out.extend_from_slice(&self.cluster_vertices[c.start as usize..c.end as usize]);
            }
        }
        out
    }

    /// The slack the per-vertex tests add for the ε-acceptance, rounding and (for the
    /// curvature-blended field) its departure from the vertex normals' cone.
    fn margin(&self, frame: &FrameSetup, v: usize) -> f32 {
        ANGLE_MARGIN
            + if frame.curved {
                self.curvature_margin.get(v).copied().unwrap_or(0.0)
            } else {
                0.0
            }
    }

    /// Which of `vertices` still pass their per-vertex test after the light and eye move
    /// by up to `budget` (object space; similarity transforms or directions only): the
    /// watch list of a [`SearchCoherence`] key frame. With `angle(N, H) ≤ acos(C_v)` the
    /// test, the motion turns `H` by at most `φ_v = asin(τ/|S|)` (`τ` the turns of `L̂`
    /// and `V̂`) and can raise the allowance to `C_v'` computed from the distances less the
    /// budgets and `|S| − τ`; a vertex is watched when `angle(N, H) ≤ acos(C_v') + φ_v`.
    fn watch_list(&self, frame: &FrameSetup, vertices: &[u32], budget: Budget) -> Vec<u32> {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let watched = |v: usize| -> bool {
            let n = self.normals[v];
            // angle(N, H) ≤ acos(c) + φ (+ margin), without trigonometry: with
            // cos φ and sin φ, compare cosines while the sum stays below π.
            let within = |h: Vec3, c: f32, sin_phi: f32| {
                let c = c.clamp(-1.0, 1.0);
                let (cos_m, sin_m) = (WATCH_MARGIN.cos(), WATCH_MARGIN.sin());
                let sin_phi = sin_phi.clamp(0.0, 1.0);
                let cos_phi = (1.0 - sin_phi * sin_phi).sqrt();
                // cos and sin of acos(c) + φ, then + margin.
                let s_c = (1.0 - c * c).max(0.0).sqrt();
                let (c1, s1) = (c * cos_phi - s_c * sin_phi, s_c * cos_phi + c * sin_phi);
                let (c2, s2) = (c1 * cos_m - s1 * sin_m, s1 * cos_m + c1 * sin_m);
                // The sum (at most 3π/2) passed π when its sine is negative.
                let past_pi = s1 < 0.0 || s2 < 0.0;
                past_pi || n.dot(h) >= c2
            };
            match frame.kind {
                FrameKind::Direction(h) => {
                    budget.angle >= half_pi
                        || within(
                            h,
                            self.cos_spread[v] - self.margin(frame, v),
                            budget.angle.sin(),
                        )
                }
                FrameKind::Positions { light_o, eye_o, .. } => {
                    let p = self.positions[v];
                    let (l, e) = (light_o - p, eye_o - p);
                    let (ll, le) = (l.length(), e.length());
                    let s = l / ll + e / le;
                    let sl = s.length();
                    let Some(tau) = budget.direction_turn(ll, le) else {
                        return true;
                    };
                    if !(sl > tau + 1e-6) || !s.is_finite() {
                        return true;
                    }
                    let r = self.reach[v];
                    let turn = |d: f32| turn_bound(r, d);
                    let t = turn(ll - budget.light) + turn(le - budget.eye);
                    let b = (t / (sl - tau - t).max(1e-3) * SIMILARITY_COND).min(4.0);
                    within(
                        s / sl,
                        self.cos_spread[v] - b - self.margin(frame, v),
                        tau / sl,
                    )
                }
            }
        };
        vertices
            .iter()
            .copied()
            .filter(|&v| watched(v as usize))
            .collect()
    }

    fn find_with(
        &self,
        light_eye: LightEye,
        world_from_object: Mat4,
        reject: bool,
    ) -> Vec<HighlightCentre> {
        let Some(frame) = self.setup(light_eye, world_from_object) else {
            return Vec::new();
        };
        // The vertices the per-vertex tests look at: those of the clusters whose normal
        // cone can hold H (all of them without the rejection or for non-similar maps).
        let active: Vec<u32> = if reject && frame.clusters_apply() {
            self.active_vertices(&frame, Budget::NONE)
        } else {
            (0..self.positions.len() as u32).collect()
        };
        let mut scratch = VertexScratch::default();
        self.search_vertices(&frame, &active, reject, &mut scratch)
    }

    /// The per-vertex tests (see [`HighlightSearch::find`]) of `vertices`: `H` in object
    /// space and whether each passes, into `scratch` (other entries untouched).
    fn test_vertices(&self, frame: &FrameSetup, vertices: &[u32], scratch: &mut VertexScratch) {
        scratch.prepare(self.positions.len());
        let VertexScratch { h: h_obj, pass } = scratch;
        match frame.kind {
            FrameKind::Direction(h) => {
                for &v in vertices {
                    let v = v as usize;
                    h_obj[v] = h;
                    pass[v] = self.normals[v].dot(h) >= self.cos_spread[v] - self.margin(frame, v);
                }
            }
            FrameKind::Positions {
                light,
                eye,
                light_o,
                eye_o,
            } => {
                let lin_t = frame.lin.transpose();
                let similarity = frame.similarity;
                let per_vertex = |v: usize| -> (Vec3, bool) {
                    let p = self.positions[v];
                    // Directions to light and eye: in object space for similarity
                    // transforms (angles are preserved), else in world space.
                    let (l, e) = if similarity {
                        (light_o - p, eye_o - p)
                    } else {
                        let pw = frame.world_from_object.transform_point3(p);
                        (light - pw, eye - pw)
                    };
                    let (ll, le) = (l.length(), e.length());
                    let s = l / ll + e / le;
                    let sl = s.length();
                    let h = if similarity {
                        s / sl
                    } else {
                        (lin_t * (s / sl)).normalize_or_zero()
                    };
                    if !(sl > 1e-6) || !h.is_finite() {
                        return (Vec3::ZERO, false);
                    }
                    // Turn of L̂ (and V̂) over the faces around v (points within r of
                    // p_v, at least d − r from the light): ≤ asin(x) ≤ x(1 + x²) for
                    // x = r/(d − r) ≤ 1/2.
                    let r = if similarity {
                        self.reach[v]
                    } else {
                        self.reach[v] * frame.sigma_max
                    };
                    let turn = |d: f32| turn_bound(r, d);
                    let (tl, te) = (turn(ll), turn(le));
                    // dĤ = (I − ĤĤᵀ)(dL̂ + dV̂)/|S|, |S| ≥ |S_v| − (θL + θE) on the way.
                    let b = ((tl + te) / (sl - tl - te).max(1e-3) * frame.cond).min(4.0);
                    (
                        h,
                        self.normals[v].dot(h) >= self.cos_spread[v] - b - self.margin(frame, v),
                    )
                };
                if vertices.len() >= 8192 {
                    let results: Vec<(Vec3, bool)> = vertices
                        .par_iter()
                        .with_min_len(2048)
                        .map(|&v| per_vertex(v as usize))
                        .collect();
                    for (&v, (h, ok)) in vertices.iter().zip(results) {
                        (h_obj[v as usize], pass[v as usize]) = (h, ok);
                    }
                } else {
                    for &v in vertices {
                        (h_obj[v as usize], pass[v as usize]) = per_vertex(v as usize);
                    }
                }
            }
        }
    }

    /// The per-vertex tests on `vertices`, then the per-face tests and solves on the
    /// faces whose three vertices pass (all faces around `vertices` without `reject`).
    fn search_vertices(
        &self,
        frame: &FrameSetup,
        vertices: &[u32],
        reject: bool,
        scratch: &mut VertexScratch,
    ) -> Vec<HighlightCentre> {
        self.test_vertices(frame, vertices, scratch);
        let VertexScratch { h: h_obj, pass } = scratch;

        if !reject {
            for &v in vertices {
                pass[v as usize] = true;
            }
        }
        let mut found: Vec<(HighlightCentre, f32)> = Vec::new();
        let mut candidates: Vec<u32> = vertices
            .iter()
            .copied()
            .filter(|&v| pass[v as usize])
            .collect();
        // Faces are solved once, at their smallest vertex index, in index order.
        candidates.sort_unstable();
        for &v in &candidates {
            let v = v as usize;
            let (s, e) = (self.vf_offsets[v] as usize, self.vf_offsets[v + 1] as usize);
            for &f in &self.vf[s..e] {
                let t = self.triangles[f as usize];
                // Solve each face once: at its smallest vertex index.
                if t.iter().copied().min() != Some(v as u32) || t.iter().any(|&i| !pass[i as usize])
                {
                    continue;
                }
                let n = t.map(|i| self.normals[i as usize]);
                let h = t.map(|i| h_obj[i as usize]);
                let face_margin = ANGLE_MARGIN
                    + if frame.curved {
                        self.face_curvature_margin
                            .get(f as usize)
                            .copied()
                            .unwrap_or(2.0)
                    } else {
                        0.0
                    };
                if reject && !in_cone(n, h, face_margin) {
                    continue;
                }
                let (nd, hd) = (n.map(Vec3::as_dvec3), h.map(Vec3::as_dvec3));
                let solved = match self.interpolation {
                    NormalInterpolation::Linear => solve_normalised(nd, hd),
                    NormalInterpolation::Curvature => solve_curvature(
                        nd,
                        hd,
                        t.map(|i| self.positions[i as usize].as_dvec3()),
                        t.map(|i| self.shape[i as usize].as_dmat3()),
                    ),
                };
                let Some((a, b)) = solved else {
                    continue;
                };
                let Some(c) = self.centre(
                    f,
                    t,
                    a as f32,
                    b as f32,
                    frame.world_from_object,
                    frame.normal_world_from_object,
                ) else {
                    continue;
                };
                let inner = (a.min(b).min(1.0 - a - b)) as f32;
                self.merge(&mut found, c, inner);
            }
        }
        // Leave the buffers clean for the next call.
        for &v in vertices {
            pass[v as usize] = false;
        }
        found.into_iter().map(|(c, _)| c).collect()
    }

    /// [`HighlightSearch::find`] with frame coherence: the same centres, at
    /// the same positions, as `find` for every input, found cheaper when the light, eye
    /// and object move a little from frame to frame. See [`SearchCoherence`].
    pub fn find_coherent(
        &self,
        state: &mut SearchCoherence,
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        let input = (light_eye, world_from_object, self.interpolation);
        if state.last_input == Some(input) && state.mesh == self.id {
            state.stats = CoherenceStats {
                reused: true,
                ..CoherenceStats::default()
            };
            return state.last_centres.clone();
        }
        let Some(frame) = self.setup(light_eye, world_from_object) else {
            state.forget();
            state.stats = CoherenceStats::default();
            return Vec::new();
        };
        let pose = Pose::of(&frame);
        let (previous, kept) = (state.pose.take(), state.key.take());
        let mut full = false;
        let key = match kept {
            Some(k) if state.mesh == self.id && k.covers(&pose, self.interpolation) => k,
            _ => {
                full = true;
                let budget = pose.budget(previous.as_ref(), state.frames_ahead, self.extent());
                let watch = match budget {
                    Some(b) if frame.clusters_apply() => {
                        let active = self.active_vertices(&frame, b);
                        self.watch_list(&frame, &active, b)
                    }
                    _ => (0..self.positions.len() as u32).collect(),
                };
                KeyFrame {
                    pose,
                    budget: budget.unwrap_or(Budget::NONE),
                    interpolation: self.interpolation,
                    watch,
                    valid: budget.is_some() && frame.clusters_apply(),
                }
            }
        };
        state.mesh = self.id;
        let centres = self.search_vertices(&frame, &key.watch, true, &mut state.scratch);
        state.stats = CoherenceStats {
            full,
            reused: false,
            tested: key.watch.len(),
        };
        state.key = Some(key);
        state.pose = Some(pose);
        state.last_input = Some(input);
        state.last_centres.clone_from(&centres);
        centres
    }

    /// Radius of the vertices' bounding box, object units (the floor of motion budgets).
    fn extent(&self) -> f32 {
        self.clusters
            .iter()
            .filter(|c| c.radius.is_finite())
            .fold(0f32, |m, c| m.max(c.centre.abs().max_element() + c.radius))
    }

    fn merge(&self, found: &mut Vec<(HighlightCentre, f32)>, c: HighlightCentre, inner: f32) {
        for (old, old_inner) in found.iter_mut() {
            if old.position_object.distance(c.position_object) <= self.merge_distance {
                if inner > *old_inner {
                    *old = c;
                    *old_inner = inner;
                }
                return;
            }
        }
        found.push((c, inner));
    }

    fn centre(
        &self,
        face: u32,
        t: [u32; 3],
        alpha: f32,
        beta: f32,
        world_from_object: Mat4,
        normal_world_from_object: Mat3,
    ) -> Option<HighlightCentre> {
        let p = t.map(|i| self.positions[i as usize]);
        let pos = p[0] + alpha * (p[1] - p[0]) + beta * (p[2] - p[0]);
        let frame = self.field.interpolate(t, alpha, beta);
        let w = [1.0 - alpha - beta, alpha, beta];
        let solved = (0..3)
            .map(|k| w[k] * self.normals[t[k] as usize])
            .sum::<Vec3>()
            .try_normalize();
        // The normal of the field the solve used (the field's frame normal equals it for
        // `NormalSource::Field`).
        let n_obj = match self.normal_source {
            NormalSource::Mesh => solved.or_else(|| frame.map(|f| f.normal)),
            NormalSource::Field => frame.map(|f| f.normal).or(solved),
        }?;
        let lin = Mat3::from_mat4(world_from_object);
        let n_w = (normal_world_from_object * n_obj).try_normalize()?;
        let (dmax, kmax, kmin) = match frame {
            Some(f) => {
                let d = lin * f.dir_kappa_max;
                let d = (d - n_w * n_w.dot(d))
                    .try_normalize()
                    .unwrap_or_else(|| n_w.any_orthonormal_vector());
                (d, f.kappa_max, f.kappa_min)
            }
            None => (n_w.any_orthonormal_vector(), 0.0, 0.0),
        };
        let scale = lin.determinant().abs().cbrt();
        let inv_s = if scale > 0.0 { 1.0 / scale } else { 1.0 };
        Some(HighlightCentre {
            face,
            alpha,
            beta,
            position_object: pos,
            position_world: world_from_object.transform_point3(pos),
            normal_object: n_obj,
            normal_world: n_w,
            dir_kappa_max: dmax,
            dir_kappa_min: n_w.cross(dmax),
            kappa_max: kmax * inv_s,
            kappa_min: kmin * inv_s,
        })
    }
}

/// Whether the interpolated half vector can lie in the cone spanned by the vertex
/// normals `n`: tests the averaged half vector `h̄` with a slack of the largest chord
/// from `h̄` to the vertex half vectors (every normalised interpolation of `h` lies in
/// that cap), plus [`ANGLE_MARGIN`]. A flat cone (normals nearly coplanar) passes.
fn in_cone(n: [Vec3; 3], h: [Vec3; 3], margin: f32) -> bool {
    let Some(hb) = (h[0] + h[1] + h[2]).try_normalize() else {
        return true;
    };
    let det = n[0].cross(n[1]).dot(n[2]);
    if det.abs() < 1e-6 {
        return true;
    }
    let min_dot = h.iter().map(|x| x.dot(hb)).fold(1.0, f32::min);
    // |c·(h̄ − Ĥ)| ≤ |c| |h̄ − Ĥ| ≤ |c| · chord.
    let slack = (2.0 * (1.0 - min_dot)).max(0.0).sqrt() + margin;
    let sign = det.signum();
    (0..3).all(|k| {
        let c = n[k].cross(n[(k + 1) % 3]);
        sign * c.dot(hb) >= -c.length() * slack
    })
}

/// Largest condition number of a transform treated as a similarity (angles preserved).
const SIMILARITY_COND: f32 = 1.0 + 1e-4;

/// Float slack of the watch-list tests (radians).
const WATCH_MARGIN: f32 = 1e-3;

/// The per-frame values of one search.
#[derive(Clone, Copy, Debug)]
struct FrameSetup {
    world_from_object: Mat4,
    lin: Mat3,
    normal_world_from_object: Mat3,
    sigma_max: f32,
    cond: f32,
    similarity: bool,
    curved: bool,
    kind: FrameKind,
}

#[derive(Clone, Copy, Debug)]
enum FrameKind {
    /// Directional light and eye: the one half vector, object space.
    Direction(Vec3),
    /// Point light and eye, world and object space.
    Positions {
        light: Vec3,
        eye: Vec3,
        light_o: Vec3,
        eye_o: Vec3,
    },
}

impl FrameSetup {
    /// Whether the cluster rejection (and coherence) applies: directions under any map,
    /// positions under similarity transforms (where object-space angles are the world's).
    fn clusters_apply(&self) -> bool {
        self.similarity || matches!(self.kind, FrameKind::Direction(_))
    }
}

/// How far the light and eye may move (object space) while a watch list stays valid:
/// `angle` for the half vector of directions, `light` and `eye` distances for positions.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Budget {
    angle: f32,
    light: f32,
    eye: f32,
}

impl Budget {
    const NONE: Self = Self {
        angle: 0.0,
        light: 0.0,
        eye: 0.0,
    };

    /// Bound on the turn of `L̂` plus that of `V̂` at points at least `dl` from the light
    /// and `de` from the eye when they move by the budget (`asin(a/d) ≤ a/(d − a)`);
    /// `None` when either could pass that close.
    fn direction_turn(&self, dl: f32, de: f32) -> Option<f32> {
        let one = |budget: f32, d: f32| {
            if budget <= 0.0 {
                Some(0.0)
            } else if d > 2.0 * budget {
                Some(budget / (d - budget))
            } else {
                None
            }
        };
        Some(one(self.light, dl)? + one(self.eye, de)?)
    }
}

/// Light and eye of one frame as the search sees them (object space).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pose {
    Direction(Vec3),
    Positions {
        light: Vec3,
        eye: Vec3,
    },
    /// Positions under a non-similar map: no coherence.
    Other,
}

impl Pose {
    fn of(frame: &FrameSetup) -> Self {
        match frame.kind {
            FrameKind::Direction(h) => Pose::Direction(h),
            FrameKind::Positions { light_o, eye_o, .. } if frame.similarity => Pose::Positions {
                light: light_o,
                eye: eye_o,
            },
            FrameKind::Positions { .. } => Pose::Other,
        }
    }

    /// The budget of a new key frame: `frames_ahead` times the step from the previous
    /// pose (at least a small floor, so that a still scene keeps its key), `None` where
    /// no watch list can be kept.
    fn budget(&self, previous: Option<&Pose>, frames_ahead: f32, extent: f32) -> Option<Budget> {
        let k = if frames_ahead.is_finite() {
            frames_ahead.max(0.0)
        } else {
            0.0
        };
        match (self, previous) {
            (Pose::Other, _) => None,
            (Pose::Direction(h), previous) => {
                let step = match previous {
                    Some(Pose::Direction(p)) => angle(*h, *p),
                    _ => 0.0,
                };
                let angle = (k * step).max(1e-4);
                angle.is_finite().then_some(Budget {
                    angle,
                    ..Budget::NONE
                })
            }
            (Pose::Positions { light, eye }, previous) => {
                let (sl, se) = match previous {
                    Some(Pose::Positions { light: pl, eye: pe }) => {
                        (light.distance(*pl), eye.distance(*pe))
                    }
                    _ => (0.0, 0.0),
                };
                let floor = 1e-4 * extent.max(f32::MIN_POSITIVE);
                let b = Budget {
                    angle: 0.0,
                    light: (k * sl).max(floor),
                    eye: (k * se).max(floor),
                };
                (b.light.is_finite() && b.eye.is_finite()).then_some(b)
            }
        }
    }
}

/// A key frame of [`SearchCoherence`]: where the light and eye were, how far they may
/// move, and the vertices that can pass their test meanwhile.
#[derive(Clone, Debug)]
struct KeyFrame {
    pose: Pose,
    budget: Budget,
    interpolation: NormalInterpolation,
    watch: Vec<u32>,
    valid: bool,
}

impl KeyFrame {
    /// Whether the watch list still holds every vertex that can pass at `pose`.
    fn covers(&self, pose: &Pose, interpolation: NormalInterpolation) -> bool {
        if !self.valid || interpolation != self.interpolation {
            return false;
        }
        match (self.pose, pose) {
            (Pose::Direction(k), Pose::Direction(h)) => angle(*h, k) <= self.budget.angle,
            (Pose::Positions { light: kl, eye: ke }, Pose::Positions { light, eye }) => {
                light.distance(kl) <= self.budget.light && eye.distance(ke) <= self.budget.eye
            }
            _ => false,
        }
    }
}

/// Per-vertex buffers of one search, reused across frames by [`SearchCoherence`]:
/// `H` in object space and whether the vertex passes (false outside a search).
#[derive(Clone, Debug, Default)]
struct VertexScratch {
    h: Vec<Vec3>,
    pass: Vec<bool>,
}

impl VertexScratch {
    fn prepare(&mut self, nv: usize) {
        if self.pass.len() != nv {
            self.h = vec![Vec3::ZERO; nv];
            self.pass = vec![false; nv];
        }
    }
}

/// What the last [`HighlightSearch::find_coherent`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoherenceStats {
    /// It built a new key frame (a full search: the cluster rejection over the mesh).
    pub full: bool,
    /// The input was the last call's: its centres were returned as they were.
    pub reused: bool,
    /// Vertices tested one by one.
    pub tested: usize,
}

/// Frame-to-frame state of [`HighlightSearch::find_coherent`] (beyond the paper; issue
/// 13). A key frame runs the cluster rejection with a motion budget (how far the light
/// and eye may move in object space: [`SearchCoherence::frames_ahead`] times the last
/// step) and keeps a watch list: every vertex that can pass its per-vertex test while the
/// light and eye stay within that budget (the bounds are in the private `watch_list`
/// and `active_vertices`). Later frames within the budget test only the watch list, and
/// since every other vertex provably fails its test, they solve exactly the faces the
/// full search solves: the same centres at the same positions. Beyond the budget, a
/// change of normal field or a non-similar map with point light and eye, the search
/// is full again. An unchanged input returns the last centres.
#[derive(Clone, Debug)]
pub struct SearchCoherence {
    /// How many frames of the last step's motion a key frame's budget covers (default
    /// 3): larger budgets rebuild less often but watch more vertices.
    pub frames_ahead: f32,
    key: Option<KeyFrame>,
    pose: Option<Pose>,
    /// [`HighlightSearch`]'s id the state belongs to (0: none).
    mesh: u64,
    last_input: Option<(LightEye, Mat4, NormalInterpolation)>,
    last_centres: Vec<HighlightCentre>,
    scratch: VertexScratch,
    stats: CoherenceStats,
}

impl Default for SearchCoherence {
    fn default() -> Self {
        Self {
            frames_ahead: 3.0,
            key: None,
            pose: None,
            mesh: 0,
            last_input: None,
            last_centres: Vec::new(),
            scratch: VertexScratch::default(),
            stats: CoherenceStats::default(),
        }
    }
}

impl SearchCoherence {
    /// What the last search did.
    pub fn stats(&self) -> CoherenceStats {
        self.stats
    }

    /// Forgets the key frame and the last input (the next search is full).
    pub fn forget(&mut self) {
        self.key = None;
        self.pose = None;
        self.last_input = None;
        self.last_centres.clear();
    }
}

/// How far the direction from a point to a target at distance `d` can turn when the
/// point moves by up to `r`: `asin(x) ≤ x(1 + x²)` for `x = r/(d − r) ≤ 1/2`, else π/2.
fn turn_bound(r: f32, d: f32) -> f32 {
    if d > 3.0 * r {
        let x = r / (d - r);
        x * (1.0 + x * x)
    } else {
        std::f32::consts::FRAC_PI_2
    }
}

/// The angle between two vectors, accurate near zero (`atan2(|a×b|, a·b)`; an `acos` of
/// an f32 dot is off by up to ~3e-4 rad there, which the watch budgets would have to
/// absorb).
fn angle(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b))
}

/// (largest singular value, condition number) of a 3×3 matrix.
fn svd_ratio(m: Mat3) -> (f32, f32) {
    let a = nalgebra::Matrix3::from_column_slice(&m.to_cols_array().map(f64::from));
    let s = a.singular_values();
    let (mx, mn) = (s.max(), s.min());
    if mn > 0.0 && mx.is_finite() {
        (mx as f32, (mx / mn) as f32)
    } else {
        (f32::MAX, f32::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The watch list's invariant itself: after the light and eye move by up to the
    /// budget, every vertex that passes its exact test is on the list (the results'
    /// equality alone rarely exposes a loose bound, since centres sit far from the
    /// thresholds).
    #[test]
    fn every_vertex_that_can_pass_within_the_budget_is_watched() {
        let path = format!(
            "{}/../../fixtures/meshes/stanford-bunny.obj",
            env!("CARGO_MANIFEST_DIR")
        );
        let mesh = crate::load_obj(&path).unwrap();
        let welded = crate::weld(&mesh);
        let topo = Topology::new(&welded);
        let field = CurvatureField::compute(&topo, &crate::CurvatureOptions::default());
        let s = HighlightSearch::for_mesh(&mesh, &welded, &topo, &field);
        let nv = s.positions.len();
        let (lo, hi) = s.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
        let world = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.5),
            glam::Quat::from_rotation_y(0.4),
            Vec3::new(0.5, 0.0, -1.0),
        );
        let w = |p: Vec3| world.transform_point3(p);
        let (light, eye) = (
            w(c + Vec3::new(6.0 * r, 8.0 * r, 10.0 * r)),
            w(c + Vec3::new(0.0, 0.5 * r, 3.0 * r)),
        );
        let key = s.setup(LightEye::Positions { light, eye }, world).unwrap();
        // Budget in object units: 0.3 r for the light and the eye.
        let budget = Budget {
            angle: 0.0,
            light: 0.3 * r,
            eye: 0.3 * r,
        };
        let active = s.active_vertices(&key, budget);
        let watch = s.watch_list(&key, &active, budget);
        let mut watched = vec![false; nv];
        for &v in &watch {
            watched[v as usize] = true;
        }
        let all: Vec<u32> = (0..nv as u32).collect();
        let mut scratch = VertexScratch::default();
        let mut rng = 0x2545_f491_u32;
        let mut unit = || {
            let mut next = || {
                rng ^= rng << 13;
                rng ^= rng >> 17;
                rng ^= rng << 5;
                rng as f32 / u32::MAX as f32 * 2.0 - 1.0
            };
            Vec3::new(next(), next(), next()).normalize()
        };
        let mut passing = 0;
        for k in 0..24 {
            // World displacement of 0.999 × budget in object units (scale 2.5).
            let (dl, de) = (
                unit() * 0.999 * 0.3 * r * 2.5,
                unit() * 0.999 * 0.3 * r * 2.5,
            );
            let frame = s
                .setup(
                    LightEye::Positions {
                        light: light + dl,
                        eye: eye + de,
                    },
                    world,
                )
                .unwrap();
            s.test_vertices(&frame, &all, &mut scratch);
            for (v, (&p, &w)) in scratch.pass.iter().zip(&watched).enumerate() {
                if p {
                    passing += 1;
                    assert!(w, "pose {k}: vertex {v} passes but is not watched");
                }
            }
            scratch.pass.fill(false);
        }
        assert!(passing > 0);
        assert!(watch.len() < nv / 2, "{} of {nv} watched", watch.len());
    }
}
