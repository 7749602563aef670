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

use glam::{Mat3, Vec3};

use crate::CurvatureField;

mod build;
mod clusters;
mod coherence;
mod search;
mod solve;
mod tables;
#[cfg(test)]
mod tests;

pub use build::welded_mesh_normals;
pub use coherence::{CoherenceStats, SearchCoherence};
pub use solve::{
    BARYCENTRIC_EPSILON, NormalInterpolation, RESIDUAL_TOLERANCE, try_solve_barycentric,
    try_solve_barycentric_eq6,
};
pub use tables::{FaceSolution, SolveFrame, SolveHalfVector, SolveVertex};

use clusters::Cluster;
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

impl LightEye {
    /// The unit half vector `H` (§3.1) at world point `p`: the normalised sum of the unit
    /// directions towards the light and the eye; zero where either is undefined.
    pub fn half_vector(self, p: Vec3) -> Vec3 {
        match self {
            Self::Positions { light, eye } => {
                (light - p).normalize_or_zero() + (eye - p).normalize_or_zero()
            }
            Self::Directions { to_light, to_eye } => {
                to_light.normalize_or_zero() + to_eye.normalize_or_zero()
            }
        }
        .normalize_or_zero()
    }
}

/// One highlight centre (maximum specular intensity point, §3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightCentre {
    /// Triangle holding the point (index into [`crate::Topology::triangles`]).
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

/// Margin (rad) added to the rejection bounds for the ε-acceptance and rounding.
const ANGLE_MARGIN: f32 = 0.01;

impl HighlightSearch {
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
}
