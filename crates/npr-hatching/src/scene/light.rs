//! The light of a hatched scene and its variance shadow map's settings (W. Donnelly and
//! A. Lauritzen, "Variance Shadow Maps", I3D 2006; the hatching paper's reference \[4\]).

use glam::{Mat4, Vec3};
use npr_gpu::Light;

/// Format of the variance shadow map's moments.
pub const MOMENTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// The light that casts the variance shadow map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowLight {
    /// A directional light, shining from `towards_light`; the shadow map is an
    /// orthographic box around the sphere (`center`, `radius`) that holds the scene.
    Directional {
        /// Direction from the scene towards the light.
        towards_light: Vec3,
        /// Centre of the scene's bounding sphere (world).
        center: Vec3,
        /// Radius of the scene's bounding sphere (world, > 0).
        radius: f32,
    },
    /// A spot light at `position` aimed at `target`, lighting a cone of half-angle
    /// `outer_angle_rad` (full strength inside `inner_angle_rad`), reaching `range`.
    Spot {
        /// Light position (world).
        position: Vec3,
        /// Point the cone's axis passes through.
        target: Vec3,
        /// Half-angle where the light falls to zero, radians in (0, π/2).
        outer_angle_rad: f32,
        /// Half-angle of full strength, radians, ≤ `outer_angle_rad`.
        inner_angle_rad: f32,
        /// Farthest lit distance (world, > 0); also the shadow map's far plane.
        range: f32,
    },
}

impl ShadowLight {
    /// The light as the shading uniforms see it (white, ambient 0.1).
    pub fn light(&self) -> Light {
        match *self {
            Self::Directional { towards_light, .. } => Light::directional(towards_light),
            Self::Spot { position, .. } => Light::point(position),
        }
    }

    /// World → light clip space (depth 0..1).
    pub fn light_clip_from_world(&self) -> Mat4 {
        match *self {
            Self::Directional {
                towards_light,
                center,
                radius,
            } => {
                let r = radius.max(1e-4);
                let dir = towards_light.normalize_or(Vec3::Y);
                let up = if dir.cross(Vec3::Y).length_squared() < 1e-6 {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                let view =
                    glam::camera::rh::view::look_at_mat4(center + dir * (2.0 * r), center, up);
                glam::camera::rh::proj::directx::orthographic(-r, r, -r, r, 0.5 * r, 3.5 * r) * view
            }
            Self::Spot {
                position,
                target,
                outer_angle_rad,
                range,
                ..
            } => {
                let dir = (target - position).normalize_or(Vec3::NEG_Y);
                let up = if dir.cross(Vec3::Y).length_squared() < 1e-6 {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                let view = glam::camera::rh::view::look_at_mat4(position, position + dir, up);
                let fov = (2.0 * outer_angle_rad).clamp(0.01, 3.0);
                let far = range.max(1e-3);
                glam::camera::rh::proj::directx::perspective(fov, 1.0, far * 1e-3, far) * view
            }
        }
    }
}

/// Variance-shadow-map settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VsmSettings {
    /// Side of the square shadow map in texels (≥ 16).
    pub size: u32,
    /// Blur the moments (5-tap binomial, separable) before shading.
    pub blur: bool,
    /// Minimum variance (Donnelly & Lauritzen §3.1), in squared light-depth units.
    pub min_variance: f32,
    /// Light-bleeding reduction in [0, 1): visibilities below it become 0.
    pub light_bleed_reduction: f32,
    /// `false` turns shadows off (visibility 1 everywhere).
    pub enabled: bool,
}

impl Default for VsmSettings {
    /// 1024², blurred, minimum variance 1e-5, bleeding reduction 0.3.
    fn default() -> Self {
        Self {
            size: 1024,
            blur: true,
            min_variance: 1e-5,
            light_bleed_reduction: 0.3,
            enabled: true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_matrices_are_finite_for_degenerate_lights() {
        for l in [
            ShadowLight::Directional {
                towards_light: Vec3::ZERO,
                center: Vec3::ZERO,
                radius: 0.0,
            },
            ShadowLight::Directional {
                towards_light: Vec3::Y,
                center: Vec3::ONE,
                radius: 2.0,
            },
            ShadowLight::Spot {
                position: Vec3::ZERO,
                target: Vec3::ZERO,
                outer_angle_rad: 0.0,
                inner_angle_rad: 0.0,
                range: 0.0,
            },
        ] {
            assert!(l.light_clip_from_world().is_finite(), "{l:?}");
        }
    }
}
