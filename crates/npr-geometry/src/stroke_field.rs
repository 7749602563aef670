//! A globally smooth stroke-direction (line) field fitted to the principal curvature
//! directions, for hatching (Kim & Lee: "a principal curvature direction projected to the
//! screen"; the raw principal field jumps wherever curvature is nearly umbilic or noisy).
//!
//! Method: Felix Knöppel, Keenan Crane, Ulrich Pinkall, Peter Schröder, "Globally Optimal
//! Direction Fields", ACM Trans. Graph. 32(4) (SIGGRAPH 2013), §4–§6, for line fields
//! (n = 2, "2-RoSy"). A line direction at vertex `i` at angle θ in a per-vertex tangent
//! basis `(e1_i, e2_i)` is the complex number `z_i = e^{2iθ}` (doubling the angle makes
//! `d` and `−d` the same number). The discrete Levi-Civita connection of edge `ij` is the
//! rotation `r_ij = e^{2i(α_i − α_j)}`, `α_k` the angle of the edge vector `p_j − p_i`
//! projected into vertex `k`'s tangent basis, so `r_ij z_j` is `z_j` transported to `i`.
//! We minimise
//!
//! ```text
//! E(z) = Σ_edges w_ij |z_i − r_ij z_j|²  +  λ Σ_i a_i s_i |z_i − u_i|²
//! ```
//!
//! with `w_ij` the cotangent weights (clamped at 0, so the form stays positive
//! semi-definite), `a_i` the barycentric vertex area, `u_i = e^{2iθ_i}` the direction of
//! maximum curvature and `s_i = min((|κ_max − κ_min| / κ̄)², 4)` its anisotropy weight,
//! κ̄ a curvature scale of the mesh (squared, so clearly directional vertices hold the
//! field and noisy, nearly umbilic ones barely pull on it). The linear term `λ a_i s_i Re(z̄_i u_i)` is the paper's
//! curvature-alignment term with `q_i = s_i u_i` (Knöppel et al. §6.1); the quadratic
//! fit term weights isotropic vertices by their anisotropy so the smoothness term alone
//! fills them in instead of pulling them to zero. The minimiser solves the sparse
//! Hermitian positive-definite system `(L + λ A S) z = λ A S u`, here by Jacobi-
//! preconditioned conjugate gradients in `f64` (matrix-vector products in parallel).
//!
//! Scale invariance: the Dirichlet term with cotangent weights is dimensionless and the
//! fit term has units of area, so λ = 1 / ℓ², with the smoothing length ℓ a fraction of
//! the mesh size `√(total area)` ([`StrokeFieldOptions::smoothing`]), never less than
//! [`StrokeFieldOptions::min_smoothing_edges`] mean edge lengths. The anisotropy weight is
//! `|κ_max − κ_min|` over κ̄ = the median of `|κ_max| + |κ_min|`: both scale as 1/length. So a
//! uniformly scaled or refined mesh gives the same field.
//!
//! Hard edges (Kim & Lee leaves the direction undefined where the principal
//! directions are): [`StrokeField::for_mesh`] cuts the mesh along crease lines
//! ([`StrokeFieldOptions::crease_angle_deg`]) before computing curvature and the field, so
//! nothing is smoothed or averaged across a crease. In [`StrokeField::compute`] the
//! vertices of each flat patch ([`planar_patches`], flat against the mesh's scale) share
//! one unknown `z_P` in the patch's own tangent basis, so the patch is straight: where
//! the patch's part of the mesh holds curvature to follow (a fillet joins it) the solve
//! sets `z_P`; otherwise `z_P` is fixed to [`planar_direction`] and enters as a boundary
//! value.

use crate::{CreaseSplit, CurvatureField, CurvatureOptions, Mesh, Topology, Welded, weld};
use glam::{DVec3, Vec3};
use nalgebra::Complex;
use rayon::prelude::*;

type C64 = Complex<f64>;

/// Settings of [`StrokeField::compute`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeFieldOptions {
    /// Smoothing length ℓ as a fraction of the mesh size `√(total area)`: features of the
    /// principal field smaller than about ℓ are smoothed away. Default 0.02: with the
    /// anisotropy defaults, the value that keeps both direction targets on the Stanford
    /// bunny and Spot (≤ 2 % of edges turning by > 30°, ≤ 10° off the principal direction
    /// on the anisotropic half); larger is smoother and follows curvature less.
    pub smoothing: f32,
    /// Lower bound of ℓ in mean edge lengths, so coarse meshes are still smoothed over a
    /// few rings. Default 2.
    pub min_smoothing_edges: f32,
    /// `|κ_max − κ_min|` at which a vertex's fit weight is 1, as a multiple of the
    /// median `|κ_max| + |κ_min|` of the mesh (the weight grows with the square of
    /// the anisotropy). Default 1.
    pub anisotropy_scale: f32,
    /// Cap of the fit weight `s_i`. Default 4.
    pub max_anisotropy_weight: f32,
    /// Conjugate-gradient iteration cap. Default 4000.
    pub max_iterations: usize,
    /// Relative residual `|b − A z| / |b|` at which the solve stops. Default 1e-6.
    pub tolerance: f64,
    /// Creases: an edge whose faces meet at more than this dihedral angle
    /// (`|β(e)|`, degrees) is cut, so the field does not smooth across it and each side
    /// keeps its own direction ([`Topology::split_creases`], applied by
    /// [`StrokeField::for_mesh`]). Default 50°, the default crease angle of the ink
    /// outlines (`npr_gpu::outline::OutlineSettings::crease_angle_deg`), so strokes
    /// turn exactly where a crease line is drawn; 180 or more turns cuts off.
    pub crease_angle_deg: f32,
    /// Only crease lines at least this long are cut, as a fraction of the mesh size
    /// `√(total area)` ([`Topology::crease_edges`]): the sharp edges of a scan's noise
    /// (slivers, spikes) are not creases. Default 0.2: on the Stanford bunny no line of
    /// its 248 edges above 50° is that long (0.1 keeps one line of 46 edges, which moves
    /// its figures), and a CAD part's creases join into lines around whole faces. A hole
    /// whose rim is shorter than this (diameter under about 6 % of the part's size) is
    /// smoothed into its face. 0 cuts every crease edge.
    pub min_crease_length: f32,
    /// Planar patches: faces connected across non-crease edges whose normals
    /// are within this many degrees of their seed face's normal form a patch
    /// ([`planar_patches`]); a patch that is flat against the mesh's scale (see
    /// [`StrokeFieldOptions::planar_max_curvature`]) gets one constant direction. Default
    /// 1°; 0 turns the planar rule off.
    pub planar_tolerance_deg: f32,
    /// A patch is flat when the median `(|κ_max| + |κ_min|) · √(total area)` over its
    /// face corners is at most this (dimensionless, so scale-invariant). Default 0.25: a
    /// cylinder has about 2.5 and more, an exact plane 0, so a coarsely faceted cylinder
    /// is not taken for planes.
    pub planar_max_curvature: f32,
    /// The planar rule's axis (object space): a planar patch that no curved surface
    /// joins smoothly takes the direction `planar_axis × n` (the parallels of that axis,
    /// the lines the curvature direction draws around a cylinder on it). Default +y.
    pub planar_axis: Vec3,
    /// The planar rule's second axis: within 30° of facing along `planar_axis` a patch
    /// takes `planar_second_axis × n` instead. Default +x.
    pub planar_second_axis: Vec3,
}

impl Default for StrokeFieldOptions {
    fn default() -> Self {
        Self {
            smoothing: 0.02,
            min_smoothing_edges: 2.0,
            anisotropy_scale: 1.0,
            max_anisotropy_weight: 4.0,
            max_iterations: 4000,
            tolerance: 1e-6,
            crease_angle_deg: 50.0,
            min_crease_length: 0.2,
            planar_tolerance_deg: 1.0,
            planar_max_curvature: 0.25,
            planar_axis: Vec3::Y,
            planar_second_axis: Vec3::X,
        }
    }
}

impl StrokeFieldOptions {
    /// The curvature-only field alone: the curvature-fitted smooth field with neither the
    /// crease cuts nor the planar rule (it smooths across creases and lets noise turn
    /// the strokes on flat faces).
    pub fn curvature_only() -> Self {
        Self {
            crease_angle_deg: 180.0,
            planar_tolerance_deg: 0.0,
            ..Self::default()
        }
    }
}

/// No patch / no vertex.
pub const NONE: u32 = u32::MAX;

/// The planar rule (see [`StrokeFieldOptions::planar_axis`]): the unit
/// direction `axis × n`, or `second_axis × n` when `n` is within 30° of `±axis`
/// (`|axis × n| < ½`); the zero vector only if that vanishes too.
pub fn planar_direction(n: Vec3, axis: Vec3, second_axis: Vec3) -> Vec3 {
    let n = n.normalize_or_zero();
    let primary = axis.normalize_or_zero().cross(n);
    if primary.length() >= 0.5 {
        return primary.normalize_or_zero();
    }
    let second = second_axis.normalize_or_zero().cross(n).normalize_or_zero();
    if second != Vec3::ZERO {
        second
    } else {
        primary.normalize_or_zero()
    }
}

/// Faces of a mesh grouped into planar patches ([`planar_patches`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanarPatches {
    /// Patch of each face ([`NONE`] for degenerate faces).
    pub face_patch: Vec<u32>,
    /// Area-weighted unit normal of each patch.
    pub normal: Vec<Vec3>,
    /// Area of each patch.
    pub area: Vec<f64>,
}

/// Grows planar patches: from each face not yet in a patch (in face order),
/// adds the faces reached across edges with exactly two faces whose normals are within
/// `tolerance_deg` of the seed face's normal. Every non-degenerate face ends in one patch
/// (most patches of a curved mesh are single faces). On a [`Topology::split_creases`]
/// result no patch crosses a crease.
pub fn planar_patches(topo: &Topology, tolerance_deg: f32) -> PlanarPatches {
    let nf = topo.face_count();
    let cos_tol = tolerance_deg.max(0.0).to_radians().cos();
    let mut out = PlanarPatches {
        face_patch: vec![NONE; nf],
        ..PlanarPatches::default()
    };
    let mut stack = Vec::new();
    for seed in 0..nf {
        if out.face_patch[seed] != NONE || topo.is_degenerate(seed) {
            continue;
        }
        let id = out.normal.len() as u32;
        let n0 = topo.face_normals[seed];
        let (mut sum, mut area) = (DVec3::ZERO, 0.0f64);
        out.face_patch[seed] = id;
        stack.push(seed);
        while let Some(f) = stack.pop() {
            let a = f64::from(topo.face_areas[f]);
            sum += topo.face_normals[f].as_dvec3() * a;
            area += a;
            for &e in &topo.face_edges[f] {
                if e == crate::topology::NO_EDGE {
                    continue;
                }
                let faces = topo.edge_faces(e as usize);
                if faces.len() != 2 {
                    continue;
                }
                for &g in faces {
                    let g = g as usize;
                    if out.face_patch[g] == NONE
                        && !topo.is_degenerate(g)
                        && topo.face_normals[g].dot(n0) >= cos_tol
                    {
                        out.face_patch[g] = id;
                        stack.push(g);
                    }
                }
            }
        }
        out.normal
            .push(sum.try_normalize().unwrap_or(n0.as_dvec3()).as_vec3());
        out.area.push(area);
    }
    out
}

/// A smooth line field per vertex of a [`Topology`] (welded vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StrokeField {
    /// The unit normal of each vertex's tangent plane (the curvature field's normal).
    pub normal: Vec<Vec3>,
    /// Unit tangent line direction aligned with the direction of maximum curvature where
    /// the surface is anisotropic (sign arbitrary); the zero vector where the field is
    /// undefined (no anisotropic vertex in the component, isolated vertex, bad input).
    pub dir_kappa_max: Vec<Vec3>,
    /// `|z_i|` of the solution, in [0, ~1]: how strongly the field is determined there
    /// (small near singularities and on isotropic components).
    pub strength: Vec<f32>,
    /// The anisotropy weight `s_i` used in the fit, in
    /// `[0, StrokeFieldOptions::max_anisotropy_weight]`.
    pub anisotropy_weight: Vec<f32>,
    /// The planar patch (index into [`PlanarPatches`] of the topology) whose constant
    /// direction each vertex takes, or [`NONE`] where the field is solved per vertex.
    pub planar_patch: Vec<u32>,
    /// Conjugate-gradient iterations used.
    pub iterations: usize,
    /// Final relative residual of the solve (0 when there was nothing to solve).
    pub relative_residual: f64,
}

/// An orthonormal tangent basis `(e1, e2)` with `e1 × e2 = n`.
fn basis(n: DVec3) -> (DVec3, DVec3) {
    let (e1, _) = n.any_orthonormal_pair();
    (e1, n.cross(e1))
}

/// Angle of vector `v` projected into the tangent basis of `n`.
fn angle_in(v: DVec3, n: DVec3) -> f64 {
    let (e1, e2) = basis(n);
    v.dot(e2).atan2(v.dot(e1))
}

fn unit_normal(field: &CurvatureField, topo: &Topology, i: usize) -> DVec3 {
    let n = field
        .normal
        .get(i)
        .copied()
        .filter(|n| n.is_finite())
        .unwrap_or(Vec3::ZERO)
        .as_dvec3()
        .normalize_or_zero();
    if n != DVec3::ZERO {
        return n;
    }
    let m = topo
        .vertex_normals
        .get(i)
        .copied()
        .unwrap_or(Vec3::Z)
        .as_dvec3()
        .normalize_or_zero();
    if m == DVec3::ZERO { DVec3::Z } else { m }
}

/// Median of finite values (0 for none).
fn median(mut v: Vec<f32>) -> f32 {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f32::total_cmp);
    *m
}

/// Cotangent weight per edge (½ Σ cot of the opposite angles), clamped to [0, 1e3].
fn cotan_weights(topo: &Topology) -> Vec<f64> {
    let mut w = vec![0.0f64; topo.edges.len()];
    for (f, t) in topo.triangles.iter().enumerate() {
        if topo.face_areas.get(f).is_none_or(|&a| !(a > 0.0)) {
            continue;
        }
        let p = t.map(|i| topo.positions[i as usize].as_dvec3());
        for k in 0..3 {
            let e = topo.face_edges[f][k];
            if e == crate::topology::NO_EDGE {
                continue;
            }
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let (u, v) = (a - c, b - c);
            let cross = u.cross(v).length();
            if cross > 0.0 && cross.is_finite() {
                w[e as usize] += 0.5 * u.dot(v) / cross;
            }
        }
    }
    w.iter_mut().for_each(|x| {
        *x = if x.is_finite() {
            x.clamp(0.0, 1e3)
        } else {
            0.0
        }
    });
    w
}

/// The planar patches of `topo` that are flat against the mesh's scale: the
/// median `(|κ_max| + |κ_min|) · √total_area` over a patch's face corners is at most
/// [`StrokeFieldOptions::planar_max_curvature`]. Renumbered: only those patches remain,
/// `face_patch` is [`NONE`] elsewhere.
fn flat_patches(
    topo: &Topology,
    curvature: &CurvatureField,
    options: &StrokeFieldOptions,
    total_area: f64,
) -> PlanarPatches {
    if !(options.planar_tolerance_deg > 0.0) || !(total_area > 0.0) || !total_area.is_finite() {
        return PlanarPatches {
            face_patch: vec![NONE; topo.face_count()],
            ..PlanarPatches::default()
        };
    }
    let all = planar_patches(topo, options.planar_tolerance_deg);
    let scale = total_area.sqrt();
    // (patch, κ · scale) per valid face corner, grouped by patch.
    let mut corners: Vec<(u32, f32)> = Vec::new();
    for (f, t) in topo.triangles.iter().enumerate() {
        let p = all.face_patch[f];
        if p == NONE {
            continue;
        }
        for &v in t {
            let v = v as usize;
            if curvature.valid.get(v).copied().unwrap_or(false) {
                let k = f64::from(curvature.kappa_max[v].abs() + curvature.kappa_min[v].abs());
                if k.is_finite() {
                    corners.push((p, (k * scale) as f32));
                }
            }
        }
    }
    corners.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut keep = vec![NONE; all.normal.len()];
    let mut out = PlanarPatches {
        face_patch: vec![NONE; topo.face_count()],
        ..PlanarPatches::default()
    };
    let mut k = 0;
    while k < corners.len() {
        let p = corners[k].0;
        let mut e = k;
        while e < corners.len() && corners[e].0 == p {
            e += 1;
        }
        if corners[k + (e - k) / 2].1 <= options.planar_max_curvature {
            keep[p as usize] = out.normal.len() as u32;
            out.normal.push(all.normal[p as usize]);
            out.area.push(all.area[p as usize]);
        }
        k = e;
    }
    for (f, &p) in all.face_patch.iter().enumerate() {
        if p != NONE {
            out.face_patch[f] = keep[p as usize];
        }
    }
    out
}

/// The flat patch each vertex takes its direction from: that of its largest face in a
/// flat patch ([`NONE`] if none of its faces is in one).
fn vertex_patches(topo: &Topology, flat: &PlanarPatches) -> Vec<u32> {
    let nv = topo.vertex_count();
    let mut best = vec![(NONE, 0.0f32); nv];
    for (f, t) in topo.triangles.iter().enumerate() {
        let p = flat.face_patch.get(f).copied().unwrap_or(NONE);
        if p == NONE {
            continue;
        }
        let a = topo.face_areas[f];
        for &v in t {
            if let Some(slot) = best.get_mut(v as usize) {
                if slot.0 == NONE || a > slot.1 {
                    *slot = (p, a);
                }
            }
        }
    }
    best.into_iter().map(|(p, _)| p).collect()
}

/// [`StrokeField::for_mesh`]'s result: the field on the mesh cut along its creases and
/// the way back to the render vertices.
#[derive(Clone, Debug, Default)]
pub struct MeshStrokeField {
    /// The welded mesh.
    pub welded: Welded,
    /// Its topology (uncut).
    pub topology: Topology,
    /// The topology cut along creases, on which curvature and the field live.
    pub split: CreaseSplit,
    /// Curvature of the cut mesh.
    pub curvature: CurvatureField,
    /// The field, per vertex of the cut mesh.
    pub field: StrokeField,
    /// For each render vertex, the vertex of the cut mesh it reads ([`NONE`] for an
    /// out-of-range one): the copy on the side of the crease of its first face.
    pub render_to_field: Vec<u32>,
}

/// A Hermitian sparse matrix: real diagonal, complex off-diagonal rows (CSR).
struct Hermitian {
    diag: Vec<f64>,
    offsets: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<C64>,
}

impl Hermitian {
    fn mul(&self, x: &[C64], out: &mut [C64]) {
        out.par_iter_mut()
            .with_min_len(1024)
            .enumerate()
            .for_each(|(i, o)| {
                let mut s = x[i] * self.diag[i];
                for k in self.offsets[i]..self.offsets[i + 1] {
                    s += self.vals[k] * x[self.cols[k] as usize];
                }
                *o = s;
            });
    }
}

fn dot(a: &[C64], b: &[C64]) -> f64 {
    // Re⟨a, b⟩ = Σ Re(ā_i b_i).
    a.par_iter()
        .with_min_len(4096)
        .zip(b)
        .map(|(x, y)| x.re * y.re + x.im * y.im)
        .sum()
}

/// Jacobi-preconditioned conjugate gradients on a Hermitian positive-definite system.
/// Returns (iterations, relative residual).
fn solve_cg(a: &Hermitian, b: &[C64], x: &mut [C64], max_iter: usize, tol: f64) -> (usize, f64) {
    let n = b.len();
    let b_norm = dot(b, b).sqrt();
    if !(b_norm > 0.0) {
        x.iter_mut().for_each(|v| *v = C64::new(0.0, 0.0));
        return (0, 0.0);
    }
    let mut ax = vec![C64::new(0.0, 0.0); n];
    a.mul(x, &mut ax);
    let mut r: Vec<C64> = b.iter().zip(&ax).map(|(b, ax)| b - ax).collect();
    let inv: Vec<f64> = a.diag.iter().map(|d| 1.0 / d).collect();
    let mut z: Vec<C64> = r.iter().zip(&inv).map(|(r, d)| r * *d).collect();
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut ap = ax;
    let mut res = dot(&r, &r).sqrt() / b_norm;
    for it in 0..max_iter {
        if res <= tol {
            return (it, res);
        }
        a.mul(&p, &mut ap);
        let pap = dot(&p, &ap);
        if !(pap > 0.0) {
            return (it, res);
        }
        let alpha = rz / pap;
        x.par_iter_mut()
            .zip(r.par_iter_mut())
            .zip(p.par_iter().zip(ap.par_iter()))
            .for_each(|((x, r), (p, ap))| {
                *x += p * alpha;
                *r -= ap * alpha;
            });
        z.par_iter_mut()
            .zip(r.par_iter().zip(inv.par_iter()))
            .for_each(|(z, (r, d))| *z = r * *d);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        p.par_iter_mut()
            .zip(z.par_iter())
            .for_each(|(p, z)| *p = z + *p * beta);
        res = dot(&r, &r).sqrt() / b_norm;
    }
    (max_iter, res)
}

impl StrokeField {
    /// Fits the smooth line field to `curvature` (computed on `topo`) — see the module
    /// docs for the energy. Never panics: vertices without a valid curvature frame get no
    /// fit term, isolated vertices and components without any anisotropic vertex end
    /// with a zero direction, non-finite geometry contributes nothing.
    pub fn compute(
        topo: &Topology,
        curvature: &CurvatureField,
        options: &StrokeFieldOptions,
    ) -> Self {
        let nv = topo.vertex_count();
        let normals: Vec<DVec3> = (0..nv).map(|i| unit_normal(curvature, topo, i)).collect();
        let valid = |i: usize| {
            curvature.valid.get(i).copied().unwrap_or(false)
                && curvature.kappa_max[i].is_finite()
                && curvature.kappa_min[i].is_finite()
        };

        // Vertex areas and the smoothing length.
        let mut area = vec![0.0f64; nv];
        for (f, t) in topo.triangles.iter().enumerate() {
            let a = f64::from(topo.face_areas.get(f).copied().unwrap_or(0.0));
            if a > 0.0 && a.is_finite() && t.iter().all(|&i| (i as usize) < nv) {
                t.iter().for_each(|&i| area[i as usize] += a / 3.0);
            }
        }
        let total: f64 = area.iter().sum();

        // Planar patches: the vertices of a flat patch share one unknown.
        let flat = flat_patches(topo, curvature, options, total);
        let patch_of = vertex_patches(topo, &flat);
        let np = flat.normal.len();
        let patch_normal: Vec<DVec3> = flat.normal.iter().map(|n| n.as_dvec3()).collect();
        let unknown = |i: usize| match patch_of[i] {
            NONE => i,
            p => nv + p as usize,
        };

        // Anisotropy weight s_i and the target u_i = e^{2iθ_i} (free vertices only).
        let kappa_scale = median(
            (0..nv)
                .filter(|&i| valid(i) && patch_of[i] == NONE)
                .map(|i| curvature.kappa_max[i].abs() + curvature.kappa_min[i].abs())
                .collect(),
        );
        let full = f64::from(options.anisotropy_scale.max(0.0) * kappa_scale);
        let (weight, target): (Vec<f64>, Vec<C64>) = (0..nv)
            .map(|i| {
                if patch_of[i] != NONE || !valid(i) || !(full > 0.0) || !full.is_finite() {
                    return (0.0, C64::new(0.0, 0.0));
                }
                let d = curvature.dir_kappa_max[i].as_dvec3();
                let n = normals[i];
                let t = d - n * n.dot(d);
                if !(t.length_squared() > 1e-20) || !t.is_finite() {
                    return (0.0, C64::new(0.0, 0.0));
                }
                let ratio = f64::from(curvature.kappa_max[i] - curvature.kappa_min[i]).abs() / full;
                let s = (ratio * ratio).min(f64::from(options.max_anisotropy_weight.max(0.0)));
                (s, C64::from_polar(1.0, 2.0 * angle_in(t, n)))
            })
            .unzip();
        let ell = (f64::from(options.smoothing.max(0.0)) * total.sqrt()).max(f64::from(
            options.min_smoothing_edges.max(0.0) * topo.mean_edge_length,
        ));
        let lambda = if ell > 0.0 && ell.is_finite() {
            1.0 / (ell * ell)
        } else {
            1.0
        };

        // Assemble (L + λ A S + ε A) z = λ A S u over the unknowns: one per free vertex
        // (rows 0..nv; a planar vertex's own row is a dummy), one per patch (nv..).
        let nu = nv + np;
        let w = cotan_weights(topo);
        let mut diag: Vec<f64> = (0..nv)
            .map(|i| {
                if patch_of[i] == NONE {
                    lambda * area[i] * (weight[i] + 1e-6)
                } else {
                    1.0
                }
            })
            .chain((0..np).map(|p| lambda * flat.area[p] * 1e-6))
            .collect();
        let mut rows: Vec<Vec<(u32, C64)>> = vec![Vec::new(); nu];
        let mut component: Vec<u32> = (0..nu as u32).collect();
        for (e, &[i, j]) in topo.edges.iter().enumerate() {
            let (iu, ju) = (i as usize, j as usize);
            let wij = w[e];
            let d = (topo.positions[ju] - topo.positions[iu]).as_dvec3();
            if !(wij > 0.0) || iu == ju || !d.is_finite() {
                continue;
            }
            let (ui, uj) = (unknown(iu), unknown(ju));
            if ui == uj {
                continue;
            }
            let frame = |u: usize, v: usize| {
                if u >= nv {
                    patch_normal[u - nv]
                } else {
                    normals[v]
                }
            };
            let rho = angle_in(d, frame(ui, iu)) - angle_in(d, frame(uj, ju));
            let r = C64::from_polar(1.0, 2.0 * rho);
            diag[ui] += wij;
            diag[uj] += wij;
            rows[ui].push((uj as u32, -r * wij));
            rows[uj].push((ui as u32, -r.conj() * wij));
            crate::topology::union_sets(&mut component, ui as u32, uj as u32);
        }
        let mut b: Vec<C64> = (0..nu)
            .map(|i| {
                if i < nv {
                    target[i] * (lambda * area[i] * weight[i])
                } else {
                    C64::new(0.0, 0.0)
                }
            })
            .collect();

        // A patch whose connected part of the mesh holds no curvature to follow (no free
        // vertex with a fit weight: a face bounded by creases) takes the planar rule.
        let mut anchored = vec![false; nu];
        for (i, &s) in weight.iter().enumerate() {
            if s > 0.0 {
                let root = crate::topology::find_set(&mut component, i as u32) as usize;
                anchored[root] = true;
            }
        }
        let mut fixed: Vec<Option<C64>> = vec![None; nu];
        for p in 0..np {
            let root = crate::topology::find_set(&mut component, (nv + p) as u32) as usize;
            if !anchored[root] {
                let n = patch_normal[p];
                let d =
                    planar_direction(n.as_vec3(), options.planar_axis, options.planar_second_axis)
                        .as_dvec3();
                let z = if d == DVec3::ZERO {
                    C64::new(0.0, 0.0)
                } else {
                    C64::from_polar(1.0, 2.0 * angle_in(d, n))
                };
                fixed[nv + p] = Some(z);
            }
        }
        for (u, row) in rows.iter_mut().enumerate() {
            if let Some(z) = fixed[u] {
                diag[u] = 1.0;
                b[u] = z;
                row.clear();
                continue;
            }
            let mut moved = C64::new(0.0, 0.0);
            row.retain(|&(c, v)| match fixed[c as usize] {
                Some(z) => {
                    moved -= v * z;
                    false
                }
                None => true,
            });
            b[u] += moved;
        }
        for (i, d) in diag.iter_mut().enumerate() {
            if !(*d > 0.0) || !d.is_finite() {
                *d = 1.0;
                b[i] = C64::new(0.0, 0.0);
                rows[i].clear();
            }
        }
        let mut offsets = Vec::with_capacity(nu + 1);
        offsets.push(0);
        let (mut cols, mut vals) = (Vec::new(), Vec::new());
        for row in &rows {
            for &(j, v) in row {
                cols.push(j);
                vals.push(v);
            }
            offsets.push(cols.len());
        }
        let a = Hermitian {
            diag,
            offsets,
            cols,
            vals,
        };
        // Warm start from the weighted target (and the fixed patches).
        let mut z: Vec<C64> = (0..nu)
            .map(|u| match fixed[u] {
                Some(z) => z,
                None if u < nv => target[u] * weight[u],
                None => C64::new(0.0, 0.0),
            })
            .collect();
        let (iterations, relative_residual) =
            solve_cg(&a, &b, &mut z, options.max_iterations, options.tolerance);

        let mut out = Self {
            iterations,
            relative_residual,
            ..Self::default()
        };
        for i in 0..nv {
            let n = normals[i];
            let (zi, frame) = match patch_of[i] {
                NONE => (z[i], n),
                p => (z[nv + p as usize], patch_normal[p as usize]),
            };
            let strength = zi.norm();
            let dir = if strength > 1e-9 && strength.is_finite() {
                let (e1, e2) = basis(frame);
                let th = 0.5 * zi.arg();
                let d = e1 * th.cos() + e2 * th.sin();
                (d - n * n.dot(d)).normalize_or_zero().as_vec3()
            } else {
                Vec3::ZERO
            };
            out.normal.push(n.as_vec3());
            out.dir_kappa_max.push(dir);
            out.strength.push(if strength.is_finite() {
                strength as f32
            } else {
                0.0
            });
            out.anisotropy_weight.push(weight[i] as f32);
            out.planar_patch.push(patch_of[i]);
        }
        out
    }

    /// The field of a render mesh: welds it, cuts the welded mesh along its
    /// creases ([`StrokeFieldOptions::crease_angle_deg`], [`Topology::split_creases`]),
    /// computes curvature on the cut mesh (so no curvature ball reaches across a crease)
    /// and fits the field there ([`StrokeField::compute`]). With the cut and the planar
    /// rule off ([`StrokeFieldOptions::curvature_only`]) it is exactly the field of
    /// [`CurvatureField::for_mesh`]'s topology.
    pub fn for_mesh(
        mesh: &Mesh,
        curvature_options: &CurvatureOptions,
        options: &StrokeFieldOptions,
    ) -> MeshStrokeField {
        let welded = weld(mesh);
        let topo = Topology::new(&welded);
        let size = topo
            .face_areas
            .iter()
            .map(|&a| f64::from(a))
            .filter(|a| a.is_finite())
            .sum::<f64>()
            .sqrt();
        let split = topo.split_creases_longer_than(
            options.crease_angle_deg,
            options.min_crease_length.max(0.0) * size as f32,
        );
        let curvature = CurvatureField::compute(&split.topology, curvature_options);
        let field = Self::compute(&split.topology, &curvature, options);
        // Each render vertex reads the copy of its first face corner (an unused one,
        // the first copy of its welded vertex).
        let mut first_copy = vec![NONE; topo.vertex_count()];
        for (i, &v) in split.original.iter().enumerate().rev() {
            if let Some(slot) = first_copy.get_mut(v as usize) {
                *slot = i as u32;
            }
        }
        let mut render_to_field: Vec<u32> = welded
            .render_to_welded
            .iter()
            .map(|&w| first_copy.get(w as usize).copied().unwrap_or(NONE))
            .collect();
        let mut seen = vec![false; render_to_field.len()];
        for (f, t) in mesh.triangles().enumerate() {
            for (k, &v) in t.iter().enumerate() {
                let v = v as usize;
                if v < seen.len() && !seen[v] {
                    seen[v] = true;
                    if let Some(&c) = split.topology.triangles.get(f).map(|t| &t[k]) {
                        render_to_field[v] = c;
                    }
                }
            }
        }
        MeshStrokeField {
            welded,
            topology: topo,
            split,
            curvature,
            field,
            render_to_field,
        }
    }

    /// The direction of minimum curvature of the smooth field: `normal × dir_kappa_max`
    /// (zero where the field is undefined).
    pub fn dir_kappa_min(&self) -> Vec<Vec3> {
        self.normal
            .iter()
            .zip(&self.dir_kappa_max)
            .map(|(n, d)| n.cross(*d))
            .collect()
    }
}

/// Angle in degrees (0..=90) between the lines along `a` and `b` after projecting both
/// onto the plane normal to `n`; `None` when either projection vanishes.
pub fn line_angle_deg(a: Vec3, b: Vec3, n: Vec3) -> Option<f64> {
    let n = n.as_dvec3().normalize_or_zero();
    let pa = a.as_dvec3() - n * n.dot(a.as_dvec3());
    let pb = b.as_dvec3() - n * n.dot(b.as_dvec3());
    let (pa, pb) = (pa.try_normalize()?, pb.try_normalize()?);
    Some(pa.dot(pb).abs().min(1.0).acos().to_degrees())
}

/// How smooth a line field is across the edges of `topo`, and how well it follows the
/// principal directions: the measures of `cargo xtask bench hatching-directions`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineFieldStats {
    /// Share (0–1) of the measured edges across which the line turns by more than the
    /// threshold (line angle mod 180°, both ends projected onto the plane normal to the
    /// mean of the two vertex normals).
    pub jump_edge_share: f64,
    /// Edges measured (both ends with a defined direction and finite geometry).
    pub edges_measured: usize,
    /// Mean angle (degrees) between the field and the direction of maximum curvature at
    /// the valid vertices whose `|κ_max − κ_min|` is at or above the median (the most
    /// anisotropic half).
    pub aniso_dev_deg: f64,
    /// Vertices in that half with a defined direction.
    pub aniso_vertices: usize,
}

impl LineFieldStats {
    /// Measures per-vertex `directions` (one per vertex of `topo`, any sign, zero =
    /// undefined) with edge threshold `threshold_deg`, against `curvature`'s principal
    /// directions and normals.
    pub fn measure(
        topo: &Topology,
        curvature: &CurvatureField,
        directions: &[Vec3],
        threshold_deg: f64,
    ) -> Self {
        let normal = |i: usize| unit_normal(curvature, topo, i).as_vec3();
        let (mut jumps, mut measured) = (0usize, 0usize);
        for &[i, j] in &topo.edges {
            let (i, j) = (i as usize, j as usize);
            let (Some(&a), Some(&b)) = (directions.get(i), directions.get(j)) else {
                continue;
            };
            let n = normal(i) + normal(j);
            if let Some(angle) = line_angle_deg(a, b, n) {
                measured += 1;
                if angle > threshold_deg {
                    jumps += 1;
                }
            }
        }
        let aniso: Vec<(usize, f32)> = (0..topo.vertex_count().min(curvature.len()))
            .filter(|&i| curvature.valid[i])
            .map(|i| (i, (curvature.kappa_max[i] - curvature.kappa_min[i]).abs()))
            .filter(|(_, a)| a.is_finite())
            .collect();
        let med = median(aniso.iter().map(|x| x.1).collect());
        let (mut dev, mut count) = (0.0, 0usize);
        for &(i, a) in &aniso {
            if a < med {
                continue;
            }
            let Some(&d) = directions.get(i) else {
                continue;
            };
            if let Some(angle) = line_angle_deg(d, curvature.dir_kappa_max[i], normal(i)) {
                dev += angle;
                count += 1;
            }
        }
        Self {
            jump_edge_share: if measured > 0 {
                jumps as f64 / measured as f64
            } else {
                0.0
            },
            edges_measured: measured,
            aniso_dev_deg: if count > 0 { dev / count as f64 } else { 0.0 },
            aniso_vertices: count,
        }
    }
}

/// Hard-edge measures on the directions a renderer receives (one per render vertex of
/// a [`Mesh`], any sign, zero = undefined): `cargo xtask bench hatching-directions`'s
/// `jump30_smooth_edge_share` and `planar_spread_deg`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderFieldStats {
    /// Share (0–1) of the measured edges whose dihedral angle `|β|` is below the crease
    /// angle across which the stroke line turns by more than the threshold. An edge is
    /// compared within each of its faces, between that face's two corners (the render
    /// vertices it draws with), both projected onto the plane normal to the sum of their
    /// render normals; it counts once if any face sees the turn. On a mesh whose render
    /// vertices are shared this is [`LineFieldStats::jump_edge_share`] restricted to
    /// non-crease edges.
    pub jump_smooth_edge_share: f64,
    /// Edges measured for [`RenderFieldStats::jump_smooth_edge_share`].
    pub smooth_edges_measured: usize,
    /// Over the planar patches (faces within 1° of one plane, connected, [`planar_patches`],
    /// each covering at least 1 % of the area): the area-weighted median of each patch's
    /// circular standard deviation of the stroke direction as a line (angles doubled,
    /// `√(−2 ln R) / 2`, corners weighted by a third of their face's area), in degrees;
    /// `None` when the mesh has no such patch.
    pub planar_spread_deg: Option<f64>,
    /// Planar patches measured.
    pub planar_patches: usize,
}

/// Per planar patch of `topo` (the welded topology of `mesh`; faces within 1° of one
/// plane, connected, [`planar_patches`]) covering at least `min_area_share` of the area:
/// the circular standard deviation of the stroke line `directions` (per render vertex)
/// over the patch's face corners, in degrees (angles doubled, `√(−2 ln R) / 2`, corners
/// weighted by a third of their face's area), and the patch's area.
pub fn planar_spreads_deg(
    mesh: &Mesh,
    topo: &Topology,
    directions: &[Vec3],
    min_area_share: f64,
) -> Vec<(f64, f64)> {
    let patches = planar_patches(topo, 1.0);
    let total: f64 = patches.area.iter().sum();
    let mut sums = vec![(C64::new(0.0, 0.0), 0.0f64); patches.normal.len()];
    for (f, &p) in patches.face_patch.iter().enumerate() {
        if p == NONE || !(patches.area[p as usize] >= min_area_share * total) {
            continue;
        }
        let (e1, e2) = basis(patches.normal[p as usize].as_dvec3());
        let w = f64::from(topo.face_areas[f]) / 3.0;
        for k in 0..3 {
            let Some(&r) = mesh.indices.get(3 * f + k) else {
                continue;
            };
            let Some(d) = directions.get(r as usize).map(|d| d.as_dvec3()) else {
                continue;
            };
            let (x, y) = (d.dot(e1), d.dot(e2));
            if x * x + y * y > 1e-12 {
                let slot = &mut sums[p as usize];
                slot.0 += C64::from_polar(w, 2.0 * y.atan2(x));
                slot.1 += w;
            }
        }
    }
    sums.iter()
        .zip(&patches.area)
        .filter(|((_, w), _)| *w > 0.0)
        .map(|((z, w), &a)| {
            let r = (z.norm() / w).clamp(1e-300, 1.0);
            (
                ((-2.0 * r.ln()).max(0.0) + 0.0).sqrt().to_degrees() / 2.0,
                a,
            )
        })
        .collect()
}

impl RenderFieldStats {
    /// Measures `directions` (per render vertex of `mesh`) on `topo`, the topology of
    /// `mesh` welded (same faces in the same order), with edge threshold `threshold_deg`
    /// and crease angle `crease_angle_deg`.
    pub fn measure(
        mesh: &Mesh,
        topo: &Topology,
        directions: &[Vec3],
        threshold_deg: f64,
        crease_angle_deg: f32,
    ) -> Self {
        let corner = |f: usize, v: u32| -> Option<(Vec3, Vec3)> {
            let k = topo.triangles.get(f)?.iter().position(|&x| x == v)?;
            let r = *mesh.indices.get(3 * f + k)? as usize;
            Some((
                *directions.get(r)?,
                mesh.normals.get(r).copied().unwrap_or(Vec3::ZERO),
            ))
        };
        let limit = crease_angle_deg.to_radians();
        let (mut jumps, mut measured) = (0usize, 0usize);
        for (e, &[i, j]) in topo.edges.iter().enumerate() {
            if !(topo.dihedral[e].abs() < limit) {
                continue;
            }
            let mut angle: Option<f64> = None;
            for &f in topo.edge_faces(e) {
                let (Some((a, na)), Some((b, nb))) = (corner(f as usize, i), corner(f as usize, j))
                else {
                    continue;
                };
                if let Some(x) = line_angle_deg(a, b, na + nb) {
                    angle = Some(angle.map_or(x, |y| y.max(x)));
                }
            }
            if let Some(x) = angle {
                measured += 1;
                if x > threshold_deg {
                    jumps += 1;
                }
            }
        }

        let mut spreads = planar_spreads_deg(mesh, topo, directions, 0.01);
        spreads.sort_by(|a, b| a.0.total_cmp(&b.0));
        let weight: f64 = spreads.iter().map(|s| s.1).sum();
        let mut acc = 0.0;
        let planar_spread_deg = spreads
            .iter()
            .find(|s| {
                acc += s.1;
                acc >= 0.5 * weight
            })
            .map(|s| s.0);
        Self {
            jump_smooth_edge_share: if measured > 0 {
                jumps as f64 / measured as f64
            } else {
                0.0
            },
            smooth_edges_measured: measured,
            planar_spread_deg,
            planar_patches: spreads.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CurvatureOptions, generate, weld};

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let empty = Topology::from_parts(Vec::new(), Vec::new());
        let f = CurvatureField::compute(&empty, &CurvatureOptions::default());
        let s = StrokeField::compute(&empty, &f, &StrokeFieldOptions::default());
        assert!(s.dir_kappa_max.is_empty());

        // A repeated-vertex face, a zero-area face, an out-of-range index, a NaN vertex,
        // an isolated vertex.
        let positions = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::splat(f32::NAN),
            Vec3::new(5.0, 5.0, 5.0),
        ];
        let tris = vec![[0, 1, 2], [0, 0, 1], [0, 1, 3], [1, 2, 4], [0, 1, 99]];
        let topo = Topology::from_parts(positions, tris);
        let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
        let s = StrokeField::compute(&topo, &f, &StrokeFieldOptions::default());
        assert_eq!(s.dir_kappa_max.len(), 6);
        assert!(s.dir_kappa_max.iter().all(|d| d.is_finite()));
        assert_eq!(s.dir_kappa_max[5], Vec3::ZERO);
    }

    #[test]
    fn umbilic_sphere_has_a_weak_field() {
        let mesh = generate::icosphere(3, 1.0);
        let topo = Topology::new(&weld(&mesh));
        let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
        let s = StrokeField::compute(&topo, &f, &StrokeFieldOptions::default());
        assert!(
            s.strength.iter().all(|&x| x < 0.1),
            "{:?}",
            s.strength.iter().copied().fold(0.0, f32::max)
        );
    }
}
