//! The subjects the figure examples (`examples/fig*.rs`) and the benchmarks share: the
//! hatching knot and the default stroke directions of a mesh.

use glam::Vec3;
use npr_geometry::{Mesh, generate};

/// The hatching figures' knot: the (2, 3) knot of the specular paper, finer (480 × 40
/// segments).
pub fn knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot::trefoil(0.15, 480, 40))
}

/// Stroke directions of `mesh` from `source`: the direction of maximum principal
/// curvature ([`crate::StrokeDirection::KappaMax`], default curvature options), falling
/// back to the parallels `y × n` on umbilic and flat parts.
pub fn directions_from(mesh: &Mesh, source: &crate::DirectionSource) -> Vec<Vec3> {
    crate::stroke_directions(
        mesh,
        source,
        crate::StrokeDirection::KappaMax,
        &npr_geometry::CurvatureOptions::default(),
        Vec3::Y,
    )
}

/// [`directions_from`] the default source (the smooth line field).
pub fn directions(mesh: &Mesh) -> Vec<Vec3> {
    directions_from(mesh, &crate::DirectionSource::default())
}
