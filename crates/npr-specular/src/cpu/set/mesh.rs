//! What the set measures of its mesh: the check that it is usable, its bounding radius,
//! its corners' normals and their typical turn across a face, and a transform's scale.

use crate::SpecularError;
use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureField, Topology};

/// The median over faces of the largest angle between two of a face's corner normals
/// (`corners[3f + i]`), radians; faces with a missing or non-unit normal are skipped, 0
/// when none is left.
pub(super) fn face_turn(corners: &[Vec3]) -> f32 {
    let unit = |n: &Vec3| n.is_finite() && (n.length_squared() - 1.0).abs() < 1e-2;
    let mut turns: Vec<f32> = corners
        .chunks_exact(3)
        .filter(|c| c.iter().all(unit))
        .map(|c| {
            let cos = c[0].dot(c[1]).min(c[1].dot(c[2])).min(c[2].dot(c[0]));
            cos.clamp(-1.0, 1.0).acos()
        })
        .collect();
    if turns.is_empty() {
        return 0.0;
    }
    let mid = turns.len() / 2;
    *turns.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// Per face corner (`3f + i`), the vertex normal of that corner.
pub(super) fn corner_normals(topology: &Topology, normals: &[Vec3]) -> Vec<Vec3> {
    topology
        .triangles
        .iter()
        .flat_map(|t| t.map(|v| normals.get(v as usize).copied().unwrap_or(Vec3::ZERO)))
        .collect()
}

/// The set needs a usable face and one curvature entry per vertex.
pub(super) fn check(topology: &Topology, field: &CurvatureField) -> Result<(), SpecularError> {
    if topology.face_count() == 0 || (0..topology.face_count()).all(|f| topology.is_degenerate(f)) {
        return Err(SpecularError::EmptyMesh);
    }
    if field.len() != topology.vertex_count() {
        return Err(SpecularError::Mismatch(format!(
            "{} curvature entries for {} vertices",
            field.len(),
            topology.vertex_count()
        )));
    }
    Ok(())
}

/// The mean scale `|det|^(1/3)` of a transform's linear part (1 when singular).
pub(crate) fn mean_scale(m: Mat4) -> f32 {
    let d = glam::Mat3::from_mat4(m).determinant().abs().cbrt();
    if d.is_finite() && d > 0.0 { d } else { 1.0 }
}

/// Radius of the bounding sphere about the box centre.
pub(super) fn bounding_radius(topology: &Topology) -> f32 {
    let (lo, hi) = topology.positions.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x > hi.x {
        0.0
    } else {
        (hi - lo).length() * 0.5
    }
}
