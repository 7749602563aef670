//! The energy of the module doc assembled over the unknowns (one per free vertex, one
//! per flat patch) and minimised by Jacobi-preconditioned conjugate gradients.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::planar::{flat_patches, planar_direction, vertex_patches};
use super::{C64, NONE, StrokeField, StrokeFieldOptions, angle_in, basis, median, unit_normal};
use crate::{CurvatureField, Topology};
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
    /// docs for the energy. Never panics: vertices without valid principal directions get
    /// no fit term, isolated vertices and components without any anisotropic vertex end
    /// with a zero direction, non-finite geometry contributes nothing.
    pub fn compute(
        topo: &Topology,
        curvature: &CurvatureField,
        options: &StrokeFieldOptions,
    ) -> Self {
        let nv = topo.vertex_count();
        let normals: Vec<DVec3> = (0..nv).map(|i| unit_normal(curvature, topo, i)).collect();
        let (area, total) = vertex_areas(topo);

        // Planar patches: the vertices of a flat patch share one unknown.
        let flat = flat_patches(topo, curvature, options, total);
        let unknowns = Unknowns {
            nv,
            patch_of: vertex_patches(topo, &flat),
            patch_normal: flat.normal.iter().map(|n| n.as_dvec3()).collect(),
            normals,
        };
        let (weight, target) = unknowns.fit_terms(curvature, options);
        let ell = (f64::from(options.smoothing.max(0.0)) * total.sqrt()).max(f64::from(
            options.min_smoothing_edges.max(0.0) * topo.mean_edge_length,
        ));
        let lambda = if ell > 0.0 && ell.is_finite() {
            1.0 / (ell * ell)
        } else {
            1.0
        };
        let mut system = unknowns.assemble(topo, &area, &flat.area, &weight, &target, lambda);
        let fixed = unknowns.fixed_patches(&mut system.component, &weight, options);
        let (a, b) = system.eliminate(&fixed);
        // Warm start from the weighted target (and the fixed patches).
        let mut z: Vec<C64> = (0..unknowns.count())
            .map(|u| match fixed[u] {
                Some(z) => z,
                None if u < nv => target[u] * weight[u],
                None => C64::new(0.0, 0.0),
            })
            .collect();
        let (iterations, relative_residual) =
            solve_cg(&a, &b, &mut z, options.max_iterations, options.tolerance);
        let mut out = unknowns.read_out(&z, &weight);
        out.iterations = iterations;
        out.relative_residual = relative_residual;
        out
    }
}

/// Barycentric vertex areas (a third of each valid face's area) and their total.
fn vertex_areas(topo: &Topology) -> (Vec<f64>, f64) {
    let nv = topo.vertex_count();
    let mut area = vec![0.0f64; nv];
    for (f, t) in topo.triangles.iter().enumerate() {
        let a = f64::from(topo.face_areas.get(f).copied().unwrap_or(0.0));
        if a > 0.0 && a.is_finite() && t.iter().all(|&i| (i as usize) < nv) {
            t.iter().for_each(|&i| area[i as usize] += a / 3.0);
        }
    }
    let total: f64 = area.iter().sum();
    (area, total)
}

/// The unknowns of the solve: one per free vertex (`0..nv`; a planar vertex's own is a
/// dummy) and one per flat patch (`nv..`), each in its own tangent basis.
struct Unknowns {
    nv: usize,
    /// Unit normal per vertex.
    normals: Vec<DVec3>,
    /// Per vertex, the flat patch whose unknown it takes ([`NONE`]: its own).
    patch_of: Vec<u32>,
    /// Per flat patch, its unit normal.
    patch_normal: Vec<DVec3>,
}

/// The system `(L + λ A S + ε A) z = λ A S u` over the unknowns, as assembled: real
/// diagonal, off-diagonal rows, right side, and the unknowns' connected components.
struct System {
    diag: Vec<f64>,
    rows: Vec<Vec<(u32, C64)>>,
    b: Vec<C64>,
    component: Vec<u32>,
}

impl Unknowns {
    /// Number of unknowns.
    fn count(&self) -> usize {
        self.nv + self.patch_normal.len()
    }

    /// The unknown of vertex `i`.
    fn of(&self, i: usize) -> usize {
        match self.patch_of[i] {
            NONE => i,
            p => self.nv + p as usize,
        }
    }

    /// The normal of the tangent basis unknown `u` (of vertex `v`) is expressed in.
    fn basis_normal(&self, u: usize, v: usize) -> DVec3 {
        if u >= self.nv {
            self.patch_normal[u - self.nv]
        } else {
            self.normals[v]
        }
    }

    /// Anisotropy weight `s_i` and the target `u_i = e^{2iθ_i}` per vertex (free
    /// vertices only; zero elsewhere).
    fn fit_terms(
        &self,
        curvature: &CurvatureField,
        options: &StrokeFieldOptions,
    ) -> (Vec<f64>, Vec<C64>) {
        let (nv, patch_of, normals) = (self.nv, &self.patch_of, &self.normals);
        let valid = |i: usize| {
            curvature.valid.get(i).copied().unwrap_or(false)
                && curvature.kappa_max[i].is_finite()
                && curvature.kappa_min[i].is_finite()
        };
        let kappa_scale = median(
            (0..nv)
                .filter(|&i| valid(i) && patch_of[i] == NONE)
                .map(|i| curvature.kappa_max[i].abs() + curvature.kappa_min[i].abs())
                .collect(),
        );
        let full = f64::from(options.anisotropy_scale.max(0.0) * kappa_scale);
        (0..nv)
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
            .unzip()
    }

    /// Assembles the system (rows `0..nv` per vertex, a planar vertex's a dummy; rows
    /// `nv..` per patch) with the smoothness weight `lambda`.
    fn assemble(
        &self,
        topo: &Topology,
        area: &[f64],
        patch_area: &[f64],
        weight: &[f64],
        target: &[C64],
        lambda: f64,
    ) -> System {
        let (nv, np, patch_of) = (self.nv, self.patch_normal.len(), &self.patch_of);
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
            .chain((0..np).map(|p| lambda * patch_area[p] * 1e-6))
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
            let (ui, uj) = (self.of(iu), self.of(ju));
            if ui == uj {
                continue;
            }
            let rho =
                angle_in(d, self.basis_normal(ui, iu)) - angle_in(d, self.basis_normal(uj, ju));
            let r = C64::from_polar(1.0, 2.0 * rho);
            diag[ui] += wij;
            diag[uj] += wij;
            rows[ui].push((uj as u32, -r * wij));
            rows[uj].push((ui as u32, -r.conj() * wij));
            crate::topology::union_sets(&mut component, ui as u32, uj as u32);
        }
        let b: Vec<C64> = (0..nu)
            .map(|i| {
                if i < nv {
                    target[i] * (lambda * area[i] * weight[i])
                } else {
                    C64::new(0.0, 0.0)
                }
            })
            .collect();
        System {
            diag,
            rows,
            b,
            component,
        }
    }

    /// The patches whose connected part of the mesh holds no curvature to follow, each
    /// with its fixed value by the planar rule (`None` for every other unknown).
    fn fixed_patches(
        &self,
        component: &mut [u32],
        weight: &[f64],
        options: &StrokeFieldOptions,
    ) -> Vec<Option<C64>> {
        let (nv, np, nu) = (self.nv, self.patch_normal.len(), self.count());
        // A patch whose connected part of the mesh holds no curvature to follow (no free
        // vertex with a fit weight: a face bounded by creases) takes the planar rule.
        let mut anchored = vec![false; nu];
        for (i, &s) in weight.iter().enumerate() {
            if s > 0.0 {
                let root = crate::topology::find_set(component, i as u32) as usize;
                anchored[root] = true;
            }
        }
        let mut fixed: Vec<Option<C64>> = vec![None; nu];
        for p in 0..np {
            let root = crate::topology::find_set(component, (nv + p) as u32) as usize;
            if !anchored[root] {
                let n = self.patch_normal[p];
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
        fixed
    }

    /// The field from the solution `z`: per vertex its unknown's direction in the plane
    /// of its own normal, the strength `|z|` and the fit weight.
    fn read_out(&self, z: &[C64], weight: &[f64]) -> StrokeField {
        let nv = self.nv;
        let mut out = StrokeField::default();
        for i in 0..nv {
            let n = self.normals[i];
            let zi = z[self.of(i)];
            let strength = zi.norm();
            let dir = if strength > 1e-9 && strength.is_finite() {
                let (e1, e2) = basis(self.basis_normal(self.of(i), i));
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
            out.planar_patch.push(self.patch_of[i]);
        }
        out
    }
}

impl System {
    /// The system with the fixed unknowns moved to the right side (and invalid rows made
    /// trivial), as a sparse Hermitian matrix and its right side.
    fn eliminate(self, fixed: &[Option<C64>]) -> (Hermitian, Vec<C64>) {
        let System {
            mut diag,
            mut rows,
            mut b,
            ..
        } = self;
        let nu = diag.len();
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
        (a, b)
    }
}
