//! Projective texture mapping, shared by the specular and warping crates.
//!
//! - Specular: Eq. (9), §3.3 of "Stylized specular highlights using projective textures
//!   based on principal curvature analysis" (`q = M p`, `uv = ((q.x+1)/2, (1-q.y)/2)`).
//! - Warping: §3.2 of "Post-rendering 3D warping using projective textures" (texture
//!   matrix = reference camera view-projection, then scale 0.5 and bias 0.5).
//!
//! Both are `tex_from_world = bias_scale * clip_from_world_of_projector` with texture v
//! pointing down (WebGPU texture space), depth kept as WebGPU clip depth (0..1).

use glam::{Mat4, Vec2, Vec3, Vec4};

/// Clip → texture: `u = (x + 1)/2`, `v = (1 − y)/2`, z and w unchanged. Eq. (9).
pub const TEX_FROM_CLIP: Mat4 = Mat4::from_cols(
    Vec4::new(0.5, 0.0, 0.0, 0.0),
    Vec4::new(0.0, -0.5, 0.0, 0.0),
    Vec4::new(0.0, 0.0, 1.0, 0.0),
    Vec4::new(0.5, 0.5, 0.0, 1.0),
);

/// `tex_from_world = TEX_FROM_CLIP * clip_from_world_of_projector` (Lee & Choi Eq. (9), §4).
/// Applied to a homogeneous world point it gives `(u·w, v·w, z, w)`; divide by `w` for a
/// perspective projector (w = 1 for an orthographic one).
pub fn tex_from_world(clip_from_world_of_projector: Mat4) -> Mat4 {
    TEX_FROM_CLIP * clip_from_world_of_projector
}

/// Texture coordinates and depth of `p_world` under `tex_from_world`, after the
/// perspective divide. `None` when the point is behind a perspective projector (w ≤ 0).
pub fn project(tex_from_world: Mat4, p_world: Vec3) -> Option<(Vec2, f32)> {
    let q = tex_from_world * p_world.extend(1.0);
    (q.w > 0.0).then(|| (Vec2::new(q.x / q.w, q.y / q.w), q.z / q.w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq9_maps_clip_corners_to_texture_corners() {
        let m = tex_from_world(Mat4::IDENTITY);
        let uv = |x: f32, y: f32| project(m, Vec3::new(x, y, 0.5)).map(|(uv, _)| uv);
        assert_eq!(uv(-1.0, 1.0), Some(Vec2::new(0.0, 0.0)));
        assert_eq!(uv(1.0, -1.0), Some(Vec2::new(1.0, 1.0)));
        assert_eq!(uv(0.0, 0.0), Some(Vec2::new(0.5, 0.5)));
        assert_eq!(project(m, Vec3::splat(0.5)).map(|(_, z)| z), Some(0.5));
    }

    #[test]
    fn perspective_projector_matches_screen_mapping() {
        let cam = crate::Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.5);
        let m = tex_from_world(cam.clip_from_world());
        let p = Vec3::new(0.3, -0.2, 0.4);
        let clip = cam.clip_from_world() * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let (uv, _) = project(m, p).unwrap_or_default();
        assert!((uv.x - (ndc.x + 1.0) * 0.5).abs() < 1e-6);
        assert!((uv.y - (1.0 - ndc.y) * 0.5).abs() < 1e-6);
        let behind = Vec3::new(0.0, 0.0, 6.0);
        assert!(project(m, behind).is_none());
    }
}
