//! The region `N·H ≥ σ` a highlight stylizes, measured on the mesh (beyond the paper).
//!
//! Eq. (8) sizes a projector from the principal curvatures at the centre: exact on a
//! sphere, but on a real mesh κ is noisy and the region is not an ellipse, so the paper's
//! footprint misses most of it (recall 0.37–0.80 measured by `cargo xtask bench
//! specular-fidelity`). Here the region itself is grown over the mesh from the centre's
//! face, on the normals the `N = H` search uses (the shaded ones), with `H` per vertex
//! from the light and eye: each face is clipped to the linear interpolant of
//! `N·H − σ ≥ 0`, projected onto the projector's plane (e_max, e_min) and its area
//! moments summed. The footprint is the ellipse with the same moments: centred at the
//! region's centroid, half extent `2·sqrt(variance)` along each axis (a uniform ellipse of
//! half axis `a` has variance `a²/4`), turned towards the moments' own axes when the
//! region is clearly anisotropic. The highlight set then draws it scaled by
//! [`RegionGrower::overlap_scale`]: to the region's own area, since any region that is not
//! an ellipse has a moment ellipse larger than itself.

mod classify;
mod fit;
mod grow;
mod measure;
mod patches;
mod split;
#[cfg(test)]
mod tests;

pub use grow::RegionGrower;
pub use patches::{REGION_PATCH_FACES, RegionPatches};

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{LightEye, Topology};

/// A projector's footprint before the §3.4 controls: the ellipse inscribed in its square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Half extents along the (rotated) `e_max` and `e_min` axes, world units.
    pub half_extent: Vec2,
    /// Offset of the footprint's centre from the `N = H` point along (`e_max`, `e_min`),
    /// world units (zero for Eq. (8)).
    pub offset: Vec2,
    /// Rotation of the footprint's axes about the normal from (`e_max`, `e_min`), radians
    /// (zero for Eq. (8)).
    pub rotate_rad: f32,
    /// Area of the region measured (projected onto the projector plane), world units²;
    /// zero for Eq. (8).
    pub region_area: f32,
    /// Smallest `cos` between the region's normals and the projector's axis (the
    /// region's normal cone; receivers beyond it cannot be in the region); −1 when not
    /// measured (Eq. (8)).
    pub normal_cone_cos: f32,
    /// The scale (≤ 1) the region's moment ellipse was fitted with
    /// ([`RegionGrower::overlap_scale`]); 1 for Eq. (8). `half_extent / fit_scale` is
    /// the moment ellipse's own, what matching from frame to frame reaches over.
    pub fit_scale: f32,
}

impl Default for Footprint {
    fn default() -> Self {
        Self {
            half_extent: Vec2::ZERO,
            offset: Vec2::ZERO,
            rotate_rad: 0.0,
            region_area: 0.0,
            normal_cone_cos: -1.0,
            fit_scale: 1.0,
        }
    }
}

/// What growing a centre's region found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// The centre's face is an earlier centre's: the highlight would stylize a region
    /// another one covers.
    Covered,
    /// The linear interpolant of `N·H − σ` is negative at every vertex of the centre's
    /// face: the region is smaller than a triangle (or absent).
    Empty,
    /// The fitted footprint and the number of faces the region touches.
    Fit(Footprint, usize),
}

/// How [`RegionGrower::grow_all`] classified the faces it looked at in its last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionCounts {
    /// Faces proved inside the region from their vertices alone (added whole).
    pub inside: usize,
    /// Faces proved outside from their vertices alone (skipped).
    pub outside: usize,
    /// Faces the boundary crosses, clipped once by their vertex values.
    pub linear: usize,
    /// Faces the boundary may cross where the field is curved, clipped on the sub-grid.
    pub grid: usize,
    /// Patches taken whole ([`RegionPatches`]) and the faces in them.
    pub patches: usize,
    /// Faces in the patches taken whole.
    pub patch_faces: usize,
    /// Seeds grown again face by face because their regions met another's (so shared out
    /// as without patches).
    pub regrown: usize,
}

/// Everything of the current frame the growth needs.
#[derive(Clone, Copy, Debug)]
pub struct RegionFrame<'a> {
    /// The mesh (object space).
    pub topology: &'a Topology,
    /// Unit vertex normals the search uses, object space.
    pub normals: &'a [Vec3],
    /// Object → world.
    pub world_from_object: Mat4,
    /// Light and eye, world space.
    pub light_eye: LightEye,
}

/// A region is split into pieces along its length ([`RegionGrower::pieces`]) when its
/// moment ellipse is this much larger than the region (an ellipse region reads 1, a
/// rectangle 1.05; a band that bends reads more: the ellipse covers the inside of the
/// bend) ...
pub const SPLIT_AREA_RATIO: f32 = 1.3;
/// ... and the ellipse is at least this elongated.
pub const SPLIT_ELONGATION: f32 = 2.5;
/// Most pieces a region is split into.
pub const MAX_PIECES: usize = 6;

/// Largest number of faces one region may visit (a flat mesh facing the light would
/// otherwise be walked whole every frame; the fit of a truncated region is still its best).
const MAX_REGION_FACES: usize = 200_000;
