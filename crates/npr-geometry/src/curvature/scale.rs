//! The curvature field seen at a scale (beyond the paper): normals and shape operators
//! diffused over the mesh's edge graph, then analysed again.

use glam::Vec3;
use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use super::CurvatureField;
use crate::topology::Topology;
impl CurvatureField {
    /// The diffusion steps [`CurvatureField::at_scale`] takes on `topology` for `sigma`:
    /// `⌈4σ²/h²⌉` (h the mean edge length), at most [`MAX_SCALE_STEPS`]; 0 where there
    /// is nothing to diffuse (`sigma ≤ 0` or not finite, no edges).
    pub fn scale_steps(topology: &Topology, sigma: f32) -> usize {
        let h = topology.mean_edge_length;
        if !(sigma > 0.0 && sigma.is_finite() && h > 0.0) {
            return 0;
        }
        ((4.0 * sigma * sigma / (h * h)).ceil() as usize).min(MAX_SCALE_STEPS)
    }

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
        self.smoothed(topology, Self::scale_steps(topology, sigma), false)
    }

    /// [`CurvatureField::at_scale`] with its number of diffusion steps given (a pose of a
    /// moving mesh keeps the steps of the pose it was built on, so its smoothing follows
    /// the surface as it stretches), and each principal direction signed as the measured
    /// one (the eigen solver's sign is its own: a pose measured elsewhere, on the GPU,
    /// agrees with this one only so); 0 returns the field as it is.
    pub fn at_steps(&self, topology: &Topology, steps: usize) -> CurvatureField {
        self.smoothed(topology, steps, true)
    }

    /// The diffusion and re-analysis of [`CurvatureField::at_scale`]; `measured_signs`
    /// signs each principal direction as the measured one, else as the solver gives it.
    fn smoothed(&self, topology: &Topology, steps: usize, measured_signs: bool) -> CurvatureField {
        let n = self.len();
        if steps == 0 || topology.vertex_count() != n {
            return self.clone();
        }
        let (degree, neighbours) = topology.vertex_neighbours();
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
            // An eigenvector's sign is the solver's choice; the measured direction's is
            // one any solver (the GPU's `repose.wgsl` too) can give.
            let e_max = if measured_signs && e_max.dot(self.dir_kappa_max[v]) < 0.0 {
                -e_max
            } else {
                e_max
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
