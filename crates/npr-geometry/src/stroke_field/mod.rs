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

use glam::{DVec3, Vec3};

use crate::{CreaseSplit, CurvatureField, CurvatureOptions, Mesh, Topology, Welded, weld};

mod planar;
mod solve;
mod stats;
#[cfg(test)]
mod tests;

pub use planar::{PlanarPatches, planar_direction, planar_patches, planar_regions};
pub use stats::{
    FLAT_REGION_DEG, FLAT_REGION_MIN_SHARE, LineFieldStats, RenderFieldStats, line_angle_deg,
    planar_spreads_deg,
};
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
    /// its figures), and a CAD part's creases join into lines around whole faces. A
    /// shorter line is cut too when it closes into one loop of 8 edges or more (the rim
    /// of a small hole or boss). 0 cuts every crease edge.
    pub min_crease_length: f32,
    /// Planar patches: faces connected across non-crease edges whose normals stay
    /// within a tolerance of their region's mean normal form a region; the tolerance is
    /// three times the mesh's normal noise, at least this many degrees (at most 8°). A
    /// region flat against the mesh's scale (see
    /// [`StrokeFieldOptions::planar_max_curvature`]) gets one constant direction; a second
    /// pass at 4° or more over the other faces adds the faces bounded by their edges
    /// (gently curved faces of a remeshed part). Default 1°; 0 turns the planar rule off.
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

impl StrokeField {
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
        let size = topo.area_scale();
        let split = topo.split_creases_longer_than(
            options.crease_angle_deg,
            options.min_crease_length.max(0.0) * size,
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

/// A line direction as a complex number (`z = e^{2iθ}`, module doc).
type C64 = nalgebra::Complex<f64>;

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

/// The unit normal of vertex `i`: the curvature field's, else the mesh's, else `+Z`.
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
