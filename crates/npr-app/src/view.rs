//! Framing and the orbit camera: any model, whatever its units and scale, is centred on
//! its bounding sphere and scaled to unit radius in world space, so presets, cameras and
//! lights work the same on a 1e-3 m scan and a 1e4 mm CAD part.

use crate::preset::{CameraPreset, LightPreset, Preset};
use glam::{Mat4, Vec2, Vec3};
use npr_geometry::Mesh;
use npr_gpu::{Camera, Light};

/// The bounding sphere used to frame a model (centre of the bounding box, radius to the
/// farthest vertex).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framing {
    /// Object-space centre.
    pub centre: Vec3,
    /// Object-space radius (> 0).
    pub radius: f32,
}

impl Framing {
    /// The framing of an axis-aligned box `lo..hi` (its centre; the radius to its
    /// corners), as for a mesh that moves within it.
    pub fn of_bounds(lo: Vec3, hi: Vec3) -> Self {
        if !lo.is_finite() || !hi.is_finite() {
            return Self {
                centre: Vec3::ZERO,
                radius: 1.0,
            };
        }
        let centre = ((lo.as_dvec3() + hi.as_dvec3()) * 0.5).as_vec3();
        let radius = ((hi.as_dvec3() - lo.as_dvec3()).length() * 0.5) as f32;
        let radius = if radius.is_normal() { radius } else { 1.0 };
        Self { centre, radius }
    }

    /// Frames `mesh`'s finite positions (a mesh with none gets the unit sphere).
    pub fn of(mesh: &Mesh) -> Self {
        let finite = || mesh.positions.iter().filter(|p| p.is_finite());
        let (lo, hi) = finite().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        if !lo.is_finite() || !hi.is_finite() {
            return Self {
                centre: Vec3::ZERO,
                radius: 1.0,
            };
        }
        // The midpoint in f64: (lo + hi) / 2 in f32 overflows for coordinates near f32::MAX.
        let centre = ((lo.as_dvec3() + hi.as_dvec3()) * 0.5).as_vec3();
        let radius = finite()
            .map(|p| (p.as_dvec3() - centre.as_dvec3()).length())
            .fold(0.0f64, f64::max) as f32;
        let radius = if radius.is_normal() { radius } else { 1.0 };
        Self { centre, radius }
    }

    /// Object → world: centre at the origin, unit bounding radius, then turned by
    /// `turn_rad` about +y. The scale is applied in two steps so that it stays finite for
    /// radii near the f32 limits.
    pub fn world_from_object(&self, turn_rad: f32) -> Mat4 {
        let s = 1.0 / self.radius;
        let scale = if s.is_finite() && s > 0.0 {
            Mat4::from_scale(Vec3::splat(s))
        } else {
            Mat4::IDENTITY
        };
        Mat4::from_rotation_y(turn_rad) * scale * Mat4::from_translation(-self.centre)
    }
}

/// The world-space camera of a preset (the model is framed to unit radius at the origin).
pub fn camera(c: &CameraPreset, aspect: f32) -> Camera {
    let (yaw, pitch) = (
        c.yaw_deg.to_radians(),
        c.pitch_deg.to_radians().clamp(-1.55, 1.55),
    );
    let dir = Vec3::new(
        yaw.sin() * pitch.cos(),
        pitch.sin(),
        yaw.cos() * pitch.cos(),
    );
    let forward = -dir;
    let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
    let up = right.cross(forward);
    let target = right * c.pan[0] + up * c.pan[1];
    let eye = target + dir * c.distance;
    let mut cam = Camera::look_at(eye, target, aspect);
    cam.fov_y_rad = c.fov_deg.to_radians();
    // The model spans the unit sphere: keep it whole between the planes.
    cam.near = (c.distance - 1.5).max(c.distance * 0.01).max(1e-3);
    cam.far = c.distance + 1.5;
    cam
}

/// The world-space light of a preset.
pub fn light(l: &LightPreset) -> Light {
    let mut light = Light::directional(Vec3::from(l.direction).normalize_or(Vec3::Y));
    light.color = Vec3::from(l.color);
    light.ambient = Vec3::from(l.ambient);
    light
}

/// Per-frame view state: the preset's camera and light with the model turned by
/// `turn_deg` (the preset's own plus a turntable's progress).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Camera.
    pub camera: Camera,
    /// Light.
    pub light: Light,
    /// Object → world.
    pub world_from_object: Mat4,
}

impl View {
    /// The view of `preset` for a `width × height` image, the model turned by an extra
    /// `extra_turn_deg`.
    pub fn new(preset: &Preset, framing: &Framing, size: (u32, u32), extra_turn_deg: f32) -> Self {
        let aspect = size.0.max(1) as f32 / size.1.max(1) as f32;
        Self {
            camera: camera(&preset.camera, aspect),
            light: light(&preset.light),
            world_from_object: framing
                .world_from_object((preset.turn_deg + extra_turn_deg).to_radians()),
        }
    }

    /// The N = H search's light and eye (world space). A directional light is placed far
    /// along its direction: the search then sees the same H as the Blinn-Phong shader,
    /// which uses the true eye position.
    pub fn light_eye(&self) -> npr_geometry::LightEye {
        npr_geometry::LightEye::Positions {
            light: self.light.position_or_direction.normalize_or(Vec3::Y) * 1.0e4,
            eye: self.camera.eye,
        }
    }

    /// Projects a world point to pixel coordinates (origin top-left) of a
    /// `width × height` image; `None` behind the eye.
    pub fn to_pixel(&self, p_world: Vec3, size: (u32, u32)) -> Option<Vec2> {
        let clip = self.camera.clip_from_world() * p_world.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            (ndc.x * 0.5 + 0.5) * size.0 as f32,
            (0.5 - ndc.y * 0.5) * size.1 as f32,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use npr_geometry::generate;

    #[test]
    fn framing_maps_any_scale_to_the_unit_sphere() {
        for scale in [1e-30f32, 1e-3, 1.0, 1e4, 1e30] {
            let mut m = generate::icosphere(2, 1.0);
            for p in &mut m.positions {
                *p = *p * scale + Vec3::new(3.0, -2.0, 5.0) * scale;
            }
            let f = Framing::of(&m);
            let w = f.world_from_object(0.0);
            let r = m
                .positions
                .iter()
                .map(|p| w.transform_point3(*p).length())
                .fold(0.0f32, f32::max);
            assert!((r - 1.0).abs() < 1e-3, "scale {scale}: radius {r}");
        }
    }

    #[test]
    fn the_framed_model_projects_inside_the_image() {
        let preset = Preset::default();
        let m = generate::icosphere(2, 1.0);
        let f = Framing::of(&m);
        let view = View::new(&preset, &f, (640, 480), 0.0);
        for p in &m.positions {
            let px = view
                .to_pixel(view.world_from_object.transform_point3(*p), (640, 480))
                .unwrap();
            assert!((0.0..640.0).contains(&px.x) && (0.0..480.0).contains(&px.y));
        }
    }
}
