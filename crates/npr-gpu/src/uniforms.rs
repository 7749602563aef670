//! Uniform blocks, `#[repr(C)]` Pod with explicit padding, mirrored byte for byte by the
//! `Frame` and `Object` structs of `shaders/common.wgsl`.

use crate::camera::{Camera, Light};
use glam::{Mat3, Mat4, Vec3, Vec4};

/// Per-frame uniforms (`Frame` in WGSL, 128 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    /// World → clip (WebGPU clip space, depth 0..1).
    pub clip_from_world: [[f32; 4]; 4],
    /// Eye position in world space, w = 1.
    pub eye_world: [f32; 4],
    /// w = 0: unit direction towards a directional light; w = 1: point light position.
    pub light_world: [f32; 4],
    /// Linear light colour, a unused.
    pub light_color: [f32; 4],
    /// Linear ambient colour, a unused.
    pub ambient: [f32; 4],
}

impl FrameUniforms {
    /// Uniforms for a camera and a light.
    pub fn new(camera: &Camera, light: &Light) -> Self {
        Self {
            clip_from_world: camera.clip_from_world().to_cols_array_2d(),
            eye_world: camera.eye.extend(1.0).to_array(),
            light_world: light.as_vec4().to_array(),
            light_color: light.color.extend(0.0).to_array(),
            ambient: light.ambient.extend(0.0).to_array(),
        }
    }
}

/// Per-object uniforms (`Object` in WGSL, 144 bytes): transform and Blinn-Phong material.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObjectUniforms {
    /// Object → world.
    pub world_from_object: [[f32; 4]; 4],
    /// Inverse transpose of the upper 3×3 of `world_from_object`, columns padded to 16 bytes
    /// (WGSL `mat3x3<f32>` layout).
    pub normal_from_object: [[f32; 4]; 3],
    /// rgb = linear diffuse albedo, a = k_s.
    pub diffuse: [f32; 4],
    /// rgb = linear specular colour, a = Blinn exponent n.
    pub specular: [f32; 4],
}

impl ObjectUniforms {
    /// Uniforms for an object transform and a material.
    ///
    /// A singular transform gives a zero normal matrix rather than NaN.
    pub fn new(world_from_object: Mat4, diffuse: Vec3, k_s: f32, specular: Vec3, n: f32) -> Self {
        let m3 = Mat3::from_mat4(world_from_object);
        let nm = if m3.determinant().abs() > f32::MIN_POSITIVE {
            m3.inverse().transpose()
        } else {
            Mat3::ZERO
        };
        let col = |c: Vec3| Vec4::from((c, 0.0)).to_array();
        Self {
            world_from_object: world_from_object.to_cols_array_2d(),
            normal_from_object: [col(nm.x_axis), col(nm.y_axis), col(nm.z_axis)],
            diffuse: diffuse.extend(k_s).to_array(),
            specular: specular.extend(n).to_array(),
        }
    }

    /// A white plastic-like default material (diffuse 0.8, k_s 0.5, n 32).
    pub fn default_material(world_from_object: Mat4) -> Self {
        Self::new(world_from_object, Vec3::splat(0.8), 0.5, Vec3::ONE, 32.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_wgsl() {
        // Sizes and member offsets read from every shader that binds the structs.
        let (frames, objects) = crate::testing::wgsl_layout::shared_blocks(crate::shaders::ALL);
        assert!(frames >= 1 && objects >= 2, "{frames} / {objects} blocks");
    }

    #[test]
    fn singular_transform_gives_finite_normal_matrix() {
        let u = ObjectUniforms::default_material(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)));
        assert!(u.normal_from_object.iter().flatten().all(|v| v.is_finite()));
    }
}
