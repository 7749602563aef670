//! The scene the GPU tests of npr-warp share: a (2, 3) torus knot, its material and light.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::{Light, ObjectUniforms};

/// Image size of the tests, pixels.
pub const SIZE: u32 = 256;
/// Clear colour (transparent black).
pub const CLEAR: [f64; 4] = [0.0; 4];

/// The test knot (about 30k triangles).
pub fn knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot::trefoil(0.22, 480, 32))
}

/// Its material.
pub fn material() -> ObjectUniforms {
    ObjectUniforms::new(
        Mat4::IDENTITY,
        Vec3::new(0.75, 0.55, 0.35),
        0.4,
        Vec3::ONE,
        30.0,
    )
}

/// The light.
pub fn light() -> Light {
    Light::directional(Vec3::new(1.0, 1.5, 2.0))
}
