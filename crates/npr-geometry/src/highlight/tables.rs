//! The search's per-mesh data as flat tables, and its per-frame values, for a solve that
//! runs elsewhere (the `N = H` compute pass of `npr-specular`); and the centres of the
//! faces such a solve accepted, merged in the order the CPU search visits them, so both
//! paths give the same set.

use glam::{Mat3, Mat4, Vec3};

use super::search::FrameKind;
use super::{HighlightCentre, HighlightSearch, LightEye, NormalInterpolation};

/// One welded vertex as a solve reads it: position, the normal the search solves on and
/// the shape operator of the curvature-blended field (columns), object space; the fourth
/// component of each is padding.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveVertex {
    /// Position, `w` = 0.
    pub position: [f32; 4],
    /// Unit normal, `w` = 0.
    pub normal: [f32; 4],
    /// Columns of the shape operator `S = κ_max e_max e_maxᵀ + κ_min e_min e_minᵀ`.
    pub shape: [[f32; 4]; 3],
}

/// Where the half vector of a frame comes from, as a solve computes it per vertex
/// (the CPU search's own rules; see [`HighlightSearch::find`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolveHalfVector {
    /// One half vector for the whole mesh, object space (directional light and eye).
    Constant(Vec3),
    /// Point light and eye in object space, under a similarity transform (angles kept).
    ObjectPositions {
        /// Light, object space.
        light: Vec3,
        /// Eye, object space.
        eye: Vec3,
    },
    /// Point light and eye in world space, under a general affine map: `H` is built in
    /// world space at `world_from_object · p` and taken to object space by the
    /// transpose of the map's linear part.
    WorldPositions {
        /// Light, world space.
        light: Vec3,
        /// Eye, world space.
        eye: Vec3,
        /// `world_from_object`.
        world_from_object: Mat4,
        /// The transpose of its linear part.
        object_from_world_normal: Mat3,
    },
}

/// The per-frame values of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveFrame {
    /// How `H` is found per vertex.
    pub half_vector: SolveHalfVector,
    /// Whether the solve uses the curvature-blended normal field
    /// ([`NormalInterpolation::Curvature`]) or the linear one of Eq. (4).
    pub curved: bool,
}

/// One face whose `N = H` point a solve accepted: the face and its barycentric `(α, β)`
/// of Eq. (4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceSolution {
    /// Triangle index.
    pub face: u32,
    /// Barycentric α (weight of vertex 1).
    pub alpha: f32,
    /// Barycentric β (weight of vertex 2).
    pub beta: f32,
}

impl SolveVertex {
    /// The record as 20 `f32`: position, normal, then the shape operator's columns.
    pub fn to_floats(&self) -> [f32; 20] {
        let mut out = [0.0; 20];
        out[..4].copy_from_slice(&self.position);
        out[4..8].copy_from_slice(&self.normal);
        for (k, c) in self.shape.iter().enumerate() {
            out[8 + 4 * k..12 + 4 * k].copy_from_slice(c);
        }
        out
    }
}

impl HighlightSearch {
    /// This search's identity: unique per built search, shared by its clones (the same
    /// data), so a GPU copy of its tables knows when to be uploaded again.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Every welded vertex as a solve reads it ([`SolveVertex`]).
    pub fn solve_vertices(&self) -> Vec<SolveVertex> {
        let four = |v: Vec3| [v.x, v.y, v.z, 0.0];
        (0..self.positions.len())
            .map(|v| {
                let s = self.shape.get(v).copied().unwrap_or(Mat3::ZERO);
                SolveVertex {
                    position: four(self.positions[v]),
                    normal: four(self.normals[v]),
                    shape: [four(s.x_axis), four(s.y_axis), four(s.z_axis)],
                }
            })
            .collect()
    }

    /// The curvature field the search interpolates at a centre
    /// ([`HighlightSearch::centre_at`]), per welded vertex as twelve floats: `(normal,
    /// kappa_max)`, `(dir_kappa_max, kappa_min)`, `(dir_kappa_min, valid ? 1 : 0)` (the
    /// layout of `npr-gpu`'s curvature pass output), for a centre computed elsewhere.
    pub fn field_floats(&self) -> Vec<[f32; 12]> {
        let f = &self.field;
        (0..f.len())
            .map(|v| {
                let (n, d, e) = (f.normal[v], f.dir_kappa_max[v], f.dir_kappa_min[v]);
                [
                    n.x,
                    n.y,
                    n.z,
                    f.kappa_max[v],
                    d.x,
                    d.y,
                    d.z,
                    f.kappa_min[v],
                    e.x,
                    e.y,
                    e.z,
                    if f.valid[v] { 1.0 } else { 0.0 },
                ]
            })
            .collect()
    }

    /// The triangles the search solves (welded vertex indices).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Per face, the slack (radians) its cone test (the cheap per-face rejection of
    /// [`HighlightSearch::find`]) adds for the curvature-blended field, whose normals can
    /// leave the cone of the three vertex normals; the test's fixed margin comes on top.
    pub fn face_margins(&self) -> Vec<f32> {
        (0..self.triangles.len())
            .map(|f| self.face_curvature_margin.get(f).copied().unwrap_or(2.0))
            .collect()
    }

    /// The fixed margin (radians) of the rejection tests, for the ε-acceptance and
    /// rounding.
    pub const fn angle_margin() -> f32 {
        super::ANGLE_MARGIN
    }

    /// This frame's values for a solve; `None` where the CPU search finds nothing either
    /// (a singular transform, an empty mesh, a light and eye without a half vector).
    pub fn solve_frame(&self, light_eye: LightEye, world_from_object: Mat4) -> Option<SolveFrame> {
        let frame = self.setup(light_eye, world_from_object)?;
        let half_vector = match frame.kind {
            FrameKind::Direction(h) => SolveHalfVector::Constant(h),
            FrameKind::Positions { light_o, eye_o, .. } if frame.similarity => {
                SolveHalfVector::ObjectPositions {
                    light: light_o,
                    eye: eye_o,
                }
            }
            FrameKind::Positions { light, eye, .. } => SolveHalfVector::WorldPositions {
                light,
                eye,
                world_from_object,
                object_from_world_normal: frame.lin.transpose(),
            },
        };
        Some(SolveFrame {
            half_vector,
            curved: self.interpolation == NormalInterpolation::Curvature,
        })
    }

    /// The centres of the faces a solve accepted for this transform, duplicates from
    /// neighbouring faces merged as [`HighlightSearch::find`] merges them (faces visited
    /// at their smallest vertex index, in the order of that vertex's face list; of two
    /// centres within the merge distance the one deeper inside its face is kept).
    /// Solutions of unknown faces are ignored.
    pub fn centres_from_solutions(
        &self,
        solutions: &[FaceSolution],
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        let mut ordered: Vec<((u32, usize), FaceSolution)> = solutions
            .iter()
            .filter_map(|s| Some((self.visit_order(s.face)?, *s)))
            .collect();
        ordered.sort_by_key(|(key, _)| *key);
        let mut found = Vec::new();
        for (_, s) in ordered {
            if let Some(c) = self.centre_at(s.face, s.alpha, s.beta, world_from_object) {
                let inner = s.alpha.min(s.beta).min(1.0 - s.alpha - s.beta);
                self.merge(&mut found, c, inner);
            }
        }
        found.into_iter().map(|(c, _)| c).collect()
    }

    /// The centres of `solutions` as given, one per entry, none merged (entries whose
    /// face is unknown or has no normal there are left out): for a list already merged
    /// elsewhere, such as the GPU's (`cs_merge` of the search pass), whose entries are
    /// in [`HighlightSearch::centres_from_solutions`]'s order and pairs it merged gone.
    pub fn centres_at_solutions(
        &self,
        solutions: &[FaceSolution],
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        solutions
            .iter()
            .filter_map(|s| self.centre_at(s.face, s.alpha, s.beta, world_from_object))
            .collect()
    }

    /// Per face, its place in the order [`HighlightSearch::centres_from_solutions`]
    /// merges solutions in (faces by their smallest vertex, then by their place in that
    /// vertex's face list): a permutation of `0..face_count`, for a merge elsewhere that
    /// must visit the faces as the CPU does. A face whose smallest vertex is out of range
    /// ranks after every valid one.
    pub fn visit_ranks(&self) -> Vec<u32> {
        let n = self.triangles.len();
        let mut keyed: Vec<((u32, usize), u32)> = (0..n as u32)
            .map(|f| (self.visit_order(f).unwrap_or((u32::MAX, f as usize)), f))
            .collect();
        keyed.sort_unstable();
        let mut ranks = vec![0u32; n];
        for (rank, (_, f)) in keyed.into_iter().enumerate() {
            ranks[f as usize] = rank as u32;
        }
        ranks
    }

    /// The distance (object space) within which two centres are one: of two solutions
    /// that close, [`HighlightSearch::centres_from_solutions`] keeps the one deeper
    /// inside its face.
    pub fn merge_distance(&self) -> f32 {
        self.merge_distance
    }

    /// Where the CPU search solves `face`: its smallest vertex, and its place in that
    /// vertex's face list.
    fn visit_order(&self, face: u32) -> Option<(u32, usize)> {
        let t = self.triangles.get(face as usize)?;
        let v = *t.iter().min()?;
        let s = *self.vf_offsets.get(v as usize)? as usize;
        let e = *self.vf_offsets.get(v as usize + 1)? as usize;
        let at = self.vf.get(s..e)?.iter().position(|&f| f == face)?;
        Some((v, at))
    }
}
