//! The per-frame search for centres: the per-frame setup, the per-vertex and per-face
//! rejection tests, the solves, the merging of duplicates, and each centre's principal
//! axes and curvatures in world space.

use glam::{Mat3, Mat4, Vec3};
use rayon::prelude::*;

use super::coherence::Budget;
use super::solve::{solve_curvature, solve_normalised};
use super::{
    ANGLE_MARGIN, HighlightCentre, HighlightSearch, LightEye, NormalInterpolation, NormalSource,
};
impl HighlightSearch {
    /// The point at barycentric (`alpha`, `beta`) of `face` under `world_from_object`,
    /// with its principal axes: how a highlight that is no longer found (fading out) is re-placed
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
    /// Then Eq. (6) and its normalised refinement ([`crate::highlight::try_solve_barycentric`]).
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
    pub(super) fn setup(&self, light_eye: LightEye, world_from_object: Mat4) -> Option<FrameSetup> {
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

    /// The slack the per-vertex tests add for the ε-acceptance, rounding and (for the
    /// curvature-blended field) its departure from the vertex normals' cone.
    pub(super) fn margin(&self, frame: &FrameSetup, v: usize) -> f32 {
        ANGLE_MARGIN
            + if frame.curved {
                self.curvature_margin.get(v).copied().unwrap_or(0.0)
            } else {
                0.0
            }
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
    pub(super) fn test_vertices(
        &self,
        frame: &FrameSetup,
        vertices: &[u32],
        scratch: &mut VertexScratch,
    ) {
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
    pub(super) fn search_vertices(
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

    pub(super) fn merge(
        &self,
        found: &mut Vec<(HighlightCentre, f32)>,
        c: HighlightCentre,
        inner: f32,
    ) {
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
        let axes = self.field.interpolate(t, alpha, beta);
        let w = [1.0 - alpha - beta, alpha, beta];
        let solved = (0..3)
            .map(|k| w[k] * self.normals[t[k] as usize])
            .sum::<Vec3>()
            .try_normalize();
        // The normal of the field the solve used (the field's interpolated normal equals
        // it for `NormalSource::Field`).
        let n_obj = match self.normal_source {
            NormalSource::Mesh => solved.or_else(|| axes.map(|f| f.normal)),
            NormalSource::Field => axes.map(|f| f.normal).or(solved),
        }?;
        let lin = Mat3::from_mat4(world_from_object);
        let n_w = (normal_world_from_object * n_obj).try_normalize()?;
        let (dmax, kmax, kmin) = match axes {
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
pub(super) const SIMILARITY_COND: f32 = 1.0 + 1e-4;

/// The per-frame values of one search.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameSetup {
    pub(super) world_from_object: Mat4,
    pub(super) lin: Mat3,
    pub(super) normal_world_from_object: Mat3,
    pub(super) sigma_max: f32,
    pub(super) cond: f32,
    pub(super) similarity: bool,
    pub(super) curved: bool,
    pub(super) kind: FrameKind,
}

#[derive(Clone, Copy, Debug)]
pub(super) enum FrameKind {
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
    pub(super) fn clusters_apply(&self) -> bool {
        self.similarity || matches!(self.kind, FrameKind::Direction(_))
    }
}

/// Per-vertex buffers of one search, reused across frames by [`SearchCoherence`]:
/// `H` in object space and whether the vertex passes (false outside a search).
#[derive(Clone, Debug, Default)]
pub(super) struct VertexScratch {
    pub(super) h: Vec<Vec3>,
    pub(super) pass: Vec<bool>,
}

impl VertexScratch {
    pub(super) fn prepare(&mut self, nv: usize) {
        if self.pass.len() != nv {
            self.h = vec![Vec3::ZERO; nv];
            self.pass = vec![false; nv];
        }
    }
}

/// How far the direction from a point to a target at distance `d` can turn when the
/// point moves by up to `r`: `asin(x) ≤ x(1 + x²)` for `x = r/(d − r) ≤ 1/2`, else π/2.
pub(super) fn turn_bound(r: f32, d: f32) -> f32 {
    if d > 3.0 * r {
        let x = r / (d - r);
        x * (1.0 + x * x)
    } else {
        std::f32::consts::FRAC_PI_2
    }
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
