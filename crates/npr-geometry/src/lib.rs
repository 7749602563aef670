#![doc = include_str!("../README.md")]
//!
//! CPU mesh, topology, curvature tensor and the N = H solve.
//!
//! Implements §2.2 (curvature tensor, Eq. (1)) and §3.1 (maximum specular intensity
//! point, Eq. (3)–(6)) of: Hwan-Jik Lee (이환직) and Jung-Ju Choi (최정주), "Stylized
//! Specular Reflections Using Projective Textures based on Principal Curvature Analysis"
//! (주곡률 해석 기반의 투영 텍스처를 이용한 스타일 반사 효과), Journal of the Korea Computer
//! Graphics Society. The curvature tensor itself is from P. Alliez, D. Cohen-Steiner,
//! O. Devillers, B. Lévy and M. Desbrun, "Anisotropic polygonal remeshing", ACM Trans.
//! Graph. 22(3), 485–493, 2003 (the paper's reference \[10\]).
//!
//! Pipeline: [`io::load`] (OBJ, glTF/GLB, PLY) → [`Mesh`] (render vertices) → [`weld()`] → [`Topology`] →
//! [`CurvatureField`] (once per mesh) → per frame [`HighlightSearch::find`].
//! No GPU code lives here.
//!
//! ```
//! use glam::{Mat4, Vec3};
//! use npr_geometry::{
//!     CurvatureField, CurvatureOptions, HighlightSearch, LightEye, Topology, generate, weld,
//! };
//!
//! let (major_segments, minor_segments) = generate::torus_segments_for(2.0, 0.7, 10_000);
//! let mesh = generate::torus(2.0, 0.7, major_segments, minor_segments);
//! let topo = Topology::new(&weld(&mesh));
//! let field = CurvatureField::compute(&topo, &CurvatureOptions::default());
//! // Outer equator: k_max ≈ 1/r along the meridian, k_min ≈ 1/(R + r) along the parallel.
//! let v = (0..topo.vertex_count()).max_by(|&a, &b| topo.positions[a].x.total_cmp(&topo.positions[b].x)).unwrap();
//! assert!((field.kappa_max[v] - 1.0 / 0.7).abs() < 0.01);
//! assert!((field.kappa_min[v] - 1.0 / 2.7).abs() < 0.01);
//!
//! let search = HighlightSearch::new(&topo, &field);
//! let light_eye = LightEye::Directions { to_light: Vec3::Y, to_eye: Vec3::Z };
//! let centres = search.find(light_eye, Mat4::IDENTITY);
//! assert!(!centres.is_empty());
//! ```
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]
// `!(x > 0.0)` is used on purpose throughout: it is also true for NaN, which is how
// non-finite input is turned into "invalid" instead of leaking.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(any(test, feature = "test-support"))]
pub mod analytic;
pub mod animation;
pub mod curvature;
pub mod error;
pub mod generate;
pub mod highlight;
pub mod io;
pub mod locality;
pub mod mesh;
pub mod rng;
pub mod stats;
pub mod stroke_field;
pub mod topology;
pub mod weld;

pub use curvature::{
    CurvatureField, CurvatureMethod, CurvatureOptions, CurvatureRadius, FieldDifference,
};
pub use error::GeometryError;
pub use highlight::{
    CoherenceStats, FaceSolution, HighlightCentre, HighlightSearch, LightEye, NormalInterpolation,
    NormalSource, SearchCoherence, SolveFrame, SolveHalfVector, SolveVertex, try_solve_barycentric,
    try_solve_barycentric_eq6, welded_mesh_normals,
};
/// The OBJ entry points at their former path (they live in [`io::obj`]).
pub use io::obj;
pub use io::obj::{ObjMesh, load_obj, load_obj_with_vertex_map};
pub use mesh::Mesh;
pub use stroke_field::{
    FLAT_REGION_DEG, FLAT_REGION_MIN_SHARE, LineFieldStats, MeshStrokeField, PlanarPatches,
    RenderFieldStats, StrokeField, StrokeFieldOptions, line_angle_deg, planar_direction,
    planar_patches, planar_regions, planar_spreads_deg,
};
pub use topology::{CreaseSplit, EdgeKind, Topology};
pub use weld::{Welded, weld};
