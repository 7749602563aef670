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

use glam::Vec3;

use crate::topology::Topology;
use crate::{Mesh, weld};

mod ball;
mod compute;
mod difference;
mod eigen;
mod scale;
mod tensor;
#[cfg(test)]
mod tests;

pub use ball::BallFaces;
pub use difference::FieldDifference;
pub use scale::MAX_SCALE_STEPS;
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
/// the axes' handedness is fixed). Where `valid[v]` is false (isolated vertex,
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

/// One vertex's result: its principal axes (`n`, `dmax`, `dmin`) and curvatures.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PrincipalAxes {
    pub(super) n: Vec3,
    pub(super) dmax: Vec3,
    pub(super) dmin: Vec3,
    pub(super) kmax: f32,
    pub(super) kmin: f32,
    pub(super) valid: bool,
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

    /// Principal axes and curvatures at barycentric point `(alpha, beta)` of triangle
    /// `[i0, i1, i2]` (`p = (1-α-β) p0 + α p1 + β p2`, Eq. (4)), interpolated "the same
    /// way" as the paper's §3.1: curvatures linearly, the normal linearly then
    /// normalised, `dir_kappa_max` linearly after flipping the vertex directions to agree
    /// with vertex 0's, then projected onto the tangent plane; `dir_kappa_min` completes
    /// the right-handed axes. Invalid vertices are left out (`None` if all are).
    pub fn interpolate(&self, tri: [u32; 3], alpha: f32, beta: f32) -> Option<InterpolatedAxes> {
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
        Some(InterpolatedAxes {
            normal: n,
            dir_kappa_max: dmax,
            dir_kappa_min: n.cross(dmax),
            kappa_max: kmax / wsum,
            kappa_min: kmin / wsum,
        })
    }
}

/// Principal axes and curvatures at a point inside a triangle ([`CurvatureField::interpolate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolatedAxes {
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

pub(super) fn invalid(n: Vec3) -> PrincipalAxes {
    PrincipalAxes {
        n: if n.is_finite() { n } else { Vec3::Z },
        ..PrincipalAxes::default()
    }
}
