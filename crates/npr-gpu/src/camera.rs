//! A perspective camera and a light, in the workspace conventions: world space
//! right-handed, y up; WebGPU clip space (depth 0..1).

use glam::{Mat4, Vec3, Vec4};

/// A perspective camera looking from `eye` at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in world space.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y_rad: f32,
    /// Width / height of the target.
    pub aspect: f32,
    /// Near plane distance (> 0).
    pub near: f32,
    /// Far plane distance (> near).
    pub far: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`, y up, 40° vertical field of view, near/far
    /// chosen from the distance to the target.
    pub fn look_at(eye: Vec3, target: Vec3, aspect: f32) -> Self {
        let d = eye.distance(target).max(1e-3);
        Self {
            eye,
            target,
            up: Vec3::Y,
            fov_y_rad: 40f32.to_radians(),
            aspect,
            near: d * 0.05,
            far: d * 10.0,
        }
    }

    /// World → view (right-handed, looking down −z).
    pub fn view_from_world(&self) -> Mat4 {
        let dir = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        // Fall back to another up vector when looking along `up`.
        let up = if dir.cross(self.up).length_squared() < 1e-8 {
            Vec3::Z
        } else {
            self.up
        };
        glam::camera::rh::view::look_to_mat4(self.eye, dir, up)
    }

    /// View → clip (WebGPU: depth 0..1, y up).
    pub fn clip_from_view(&self) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(
            self.fov_y_rad,
            self.aspect.max(1e-6),
            self.near,
            self.far,
        )
    }

    /// World → clip.
    pub fn clip_from_world(&self) -> Mat4 {
        self.clip_from_view() * self.view_from_world()
    }
}

/// A light: directional (at infinity) or point, with colour and ambient term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// For a directional light, the direction towards the light; for a point light, its
    /// world position.
    pub position_or_direction: Vec3,
    /// `true` for a directional light.
    pub directional: bool,
    /// Linear light colour.
    pub color: Vec3,
    /// Linear ambient colour.
    pub ambient: Vec3,
}

impl Light {
    /// A white directional light shining from `towards_light` (normalized; a zero vector
    /// becomes +z), with a small ambient term.
    pub fn directional(towards_light: Vec3) -> Self {
        Self {
            position_or_direction: towards_light.normalize_or(Vec3::Z),
            directional: true,
            color: Vec3::ONE,
            ambient: Vec3::splat(0.1),
        }
    }

    /// A white point light at `position`, with a small ambient term.
    pub fn point(position: Vec3) -> Self {
        Self {
            position_or_direction: position,
            directional: false,
            color: Vec3::ONE,
            ambient: Vec3::splat(0.1),
        }
    }

    /// The WGSL encoding: w = 0 direction, w = 1 position.
    pub fn as_vec4(&self) -> Vec4 {
        self.position_or_direction
            .extend(if self.directional { 0.0 } else { 1.0 })
    }

    /// Unit vector from `p_world` towards the light.
    pub fn dir_from(&self, p_world: Vec3) -> Vec3 {
        if self.directional {
            self.position_or_direction.normalize_or(Vec3::Z)
        } else {
            (self.position_or_direction - p_world).normalize_or(Vec3::Z)
        }
    }
}
