//! Highlight projectors, Eq. (7)–(8), §3.2–§3.4 of the specular paper.
//!
//! An orthographic projector sits on the normal line through the highlight centre and
//! looks down `−N`. Its view basis is the principal frame: Eq. (7) `V_p = [e_max e_min −N]ᵀ`
//! (the paper's left-handed DirectX form). We use the right-handed equivalent rows
//! `[e_max, e_min, N]` (`e_max × e_min = N`), looking down −z, which maps the same points
//! to the same texture coordinates.
//!
//! Eq. (8): the frustum size along a principal direction with curvature κ is
//! `s = min(2r, 2/|κ| · sqrt(1 − σ²))`, where the highlight region is `N·H > σ` and `r` is
//! the curvature ball radius. On a surface of curvature κ the normal turns by `arccos σ`
//! after an arc of about `sqrt(1 − σ²)/|κ|`, so `s` is the region's full width: the
//! frustum spans `[−s/2, s/2]` along each axis (half-extent `s/2`).

use crate::cpu::region::Footprint;
use glam::{Mat4, Vec2, Vec3};
use npr_geometry::HighlightCentre;

/// Which principal direction is the projector's up (texture −v) axis (§3.2: `e_min`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UpAxis {
    /// Up = `e_min`, u along `e_max` (the paper's choice).
    #[default]
    KappaMin,
    /// Up = `e_max`, u along `−e_min`.
    KappaMax,
}

/// The §3.4 controls of one projector. They change the projector only, never the mesh.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectorControls {
    /// Translation of the projector along (`e_max`, `e_min`), in world units.
    pub translate: Vec2,
    /// Rotation about the normal, radians, counter-clockwise seen from outside.
    pub rotate_rad: f32,
    /// Scale of the frustum along (`e_max`, `e_min`). It multiplies the Eq. (8) size,
    /// equivalent to dividing κ where the `2r` clamp is inactive; applied after the clamp
    /// so that it always acts.
    pub scale: Vec2,
    /// Highlight threshold σ of Eq. (8) (region `N·H > σ`), in (−1, 1).
    pub sigma: f32,
    /// Texture layer (see [`crate::HighlightShape::layer`]).
    pub texture_layer: u32,
    /// Linear RGB tint of the highlight.
    pub tint: Vec3,
    /// Blinn exponent used when the layer is a normal map.
    pub shininess: f32,
    /// Which principal direction is up.
    pub up: UpAxis,
}

impl Default for ProjectorControls {
    fn default() -> Self {
        Self {
            translate: Vec2::ZERO,
            rotate_rad: 0.0,
            scale: Vec2::ONE,
            sigma: 0.9,
            texture_layer: 0,
            tint: Vec3::ONE,
            shininess: 24.0,
            up: UpAxis::KappaMin,
        }
    }
}

impl ProjectorControls {
    /// Combines these global controls with a highlight's own: translations and rotations
    /// add, scales and tints multiply; σ, texture, shininess and up are the highlight's
    /// where it sets them, else the global ones.
    pub fn compose(&self, local: &HighlightControls) -> ProjectorControls {
        ProjectorControls {
            translate: self.translate + local.translate,
            rotate_rad: self.rotate_rad + local.rotate_rad,
            scale: self.scale * local.scale,
            sigma: local.sigma.unwrap_or(self.sigma),
            texture_layer: local.texture_layer.unwrap_or(self.texture_layer),
            tint: self.tint * local.tint,
            shininess: local.shininess.unwrap_or(self.shininess),
            up: local.up.unwrap_or(self.up),
        }
    }
}

/// One highlight's own §3.4 controls, composed with the global [`ProjectorControls`] by
/// [`ProjectorControls::compose`]: offsets add to the global ones, factors multiply, and
/// the `Option` fields override the global value when set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HighlightControls {
    /// Added translation along (`e_max`, `e_min`), world units.
    pub translate: Vec2,
    /// Added rotation about the normal, radians.
    pub rotate_rad: f32,
    /// Scale factor per axis, multiplied with the global scale.
    pub scale: Vec2,
    /// Tint factor, multiplied with the global tint.
    pub tint: Vec3,
    /// This highlight's σ, if it differs from the global one.
    pub sigma: Option<f32>,
    /// This highlight's texture layer, if it differs.
    pub texture_layer: Option<u32>,
    /// This highlight's Blinn exponent for normal-map layers, if it differs.
    pub shininess: Option<f32>,
    /// This highlight's up axis, if it differs.
    pub up: Option<UpAxis>,
}

impl Default for HighlightControls {
    fn default() -> Self {
        Self {
            translate: Vec2::ZERO,
            rotate_rad: 0.0,
            scale: Vec2::ONE,
            tint: Vec3::ONE,
            sigma: None,
            texture_layer: None,
            shininess: None,
            up: None,
        }
    }
}

/// Eq. (8): `s = min(2r, 2/|κ| · sqrt(1 − σ²))`, the full frustum width along a principal
/// direction with curvature `kappa`; `2r` when κ = 0. σ is clamped to [−1, 1].
pub fn frustum_size(kappa: f32, sigma: f32, radius: f32) -> f32 {
    let s = sigma.clamp(-1.0, 1.0);
    let cap = 2.0 * radius.abs();
    let k = kappa.abs();
    if k <= f32::MIN_POSITIVE || !k.is_finite() {
        return cap;
    }
    (2.0 / k * (1.0 - s * s).max(0.0).sqrt()).min(cap)
}

/// Eq. (8)'s footprint of `centre` at threshold `sigma` with the cap radius `radius_world`:
/// full widths [`frustum_size`] along `e_max`, `e_min`, centred on the centre.
pub fn eq8_footprint(centre: &HighlightCentre, sigma: f32, radius_world: f32) -> Footprint {
    Footprint {
        half_extent: Vec2::new(
            frustum_size(centre.kappa_max, sigma, radius_world),
            frustum_size(centre.kappa_min, sigma, radius_world),
        ) * 0.5,
        ..Footprint::default()
    }
}

/// One orthographic highlight projector in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projector {
    /// The (translated) centre on the surface the projector looks at.
    pub centre_world: Vec3,
    /// The untranslated `N = H` centre; the visibility search starts from its face and
    /// walks to the translated frustum (§3.4 translation, §4.2).
    pub anchor_world: Vec3,
    /// World direction of texture u (after rotation; `e_max` for the default up).
    pub axis_u: Vec3,
    /// World direction of texture −v, the projector's up.
    pub axis_v: Vec3,
    /// Unit surface normal at the centre; the projector looks along `−normal`.
    pub normal: Vec3,
    /// Frustum half-extents along `axis_u`, `axis_v` (half of Eq. (8)'s `s`, times scale).
    pub half_extent: Vec2,
    /// Half the depth range; the frustum spans `±half_depth` about the tangent plane.
    pub half_depth: f32,
    /// World → projector clip space (orthographic, WebGPU depth 0..1).
    pub clip_from_world: Mat4,
    /// Eq. (9) `tex_from_world = bias_scale · clip_from_world`.
    pub tex_from_world: Mat4,
}

impl Projector {
    /// Builds the projector of `centre` (world-space frame, as `HighlightSearch::find`
    /// returns it) with `controls`, `radius_world` being the curvature radius `r` of
    /// Eq. (8) in world units. `None` when the frame is degenerate (zero or non-finite
    /// vectors) or the size would be zero.
    pub fn new(
        centre: &HighlightCentre,
        controls: &ProjectorControls,
        radius_world: f32,
    ) -> Option<Self> {
        Self::with_footprint(
            centre,
            controls,
            &eq8_footprint(centre, controls.sigma, radius_world),
        )
    }

    /// Builds the projector of `centre` over a given footprint (Eq. (8)'s from
    /// [`eq8_footprint`], or a measured region's from [`crate::cpu::region`]), with the §3.4
    /// `controls` on top: the footprint's offset and rotation add to the controls'
    /// translation and rotation, its half extents are scaled by `controls.scale`. `None`
    /// as for [`Projector::new`].
    pub fn with_footprint(
        centre: &HighlightCentre,
        controls: &ProjectorControls,
        footprint: &Footprint,
    ) -> Option<Self> {
        let n = centre.normal_world.try_normalize()?;
        // Re-orthonormalise the principal frame against the normal.
        let e_max = (centre.dir_kappa_max - n * n.dot(centre.dir_kappa_max)).try_normalize()?;
        let e_min = n.cross(e_max);
        let fh = footprint.half_extent;
        let (mut u, mut v, mut half) = match controls.up {
            UpAxis::KappaMin => (e_max, e_min, fh),
            UpAxis::KappaMax => (-e_min, e_max, Vec2::new(fh.y, fh.x)),
        };
        half *= controls.scale.abs();
        let (s, c) = (controls.rotate_rad + footprint.rotate_rad).sin_cos();
        (u, v) = (u * c + v * s, v * c - u * s);
        let translate = controls.translate + footprint.offset;
        let centre_world = centre.position_world + e_max * translate.x + e_min * translate.y;
        let half_depth = 2.0 * half.max_element();
        let positive = half.min_element() > 0.0; // false for NaN too
        if !positive || !centre_world.is_finite() || !half_depth.is_finite() {
            return None;
        }
        let origin = centre_world + n * half_depth;
        // Rows [u, v, n]: right-handed view basis looking down −n.
        let view_from_world =
            Mat4::from_cols(u.extend(0.0), v.extend(0.0), n.extend(0.0), glam::Vec4::W).transpose()
                * Mat4::from_translation(-origin);
        let clip_from_view = glam::camera::rh::proj::directx::orthographic(
            -half.x,
            half.x,
            -half.y,
            half.y,
            0.0,
            2.0 * half_depth,
        );
        let clip_from_world = clip_from_view * view_from_world;
        Some(Self {
            centre_world,
            anchor_world: centre.position_world,
            axis_u: u,
            axis_v: v,
            normal: n,
            half_extent: half,
            half_depth,
            clip_from_world,
            tex_from_world: npr_gpu::projective::tex_from_world(clip_from_world),
        })
    }

    /// Projector coordinates of a world point: (x, y) in [−1, 1]² inside the frustum
    /// (x along `axis_u`, y along `axis_v`), z in [0, 1] inside its depth range.
    pub fn ndc(&self, p_world: Vec3) -> Vec3 {
        self.clip_from_world.project_point3(p_world)
    }

    /// Eq. (9) texture coordinates of a world point.
    pub fn uv(&self, p_world: Vec3) -> Vec2 {
        let q = self.ndc(p_world);
        Vec2::new((q.x + 1.0) * 0.5, (1.0 - q.y) * 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn centre() -> HighlightCentre {
        HighlightCentre {
            face: 0,
            alpha: 0.0,
            beta: 0.0,
            position_object: Vec3::new(0.0, 0.0, 2.0),
            position_world: Vec3::new(0.0, 0.0, 2.0),
            normal_object: Vec3::Z,
            normal_world: Vec3::Z,
            dir_kappa_max: Vec3::X,
            dir_kappa_min: Vec3::Y,
            kappa_max: 0.5,
            kappa_min: 0.5,
        }
    }

    #[test]
    fn eq8_sizes_and_clamp() {
        let s = frustum_size(0.5, 0.8, 10.0);
        assert!((s - 2.0 / 0.5 * 0.6).abs() < 1e-6);
        assert_eq!(frustum_size(0.0, 0.8, 0.3), 0.6);
        assert_eq!(frustum_size(1e-6, 0.8, 0.3), 0.6);
    }

    #[test]
    fn projector_maps_centre_to_texture_middle_and_axes_to_edges() {
        let c = centre();
        let p = Projector::new(&c, &ProjectorControls::default(), 10.0).unwrap();
        let uv = p.uv(c.position_world);
        assert!((uv - Vec2::splat(0.5)).length() < 1e-5, "{uv}");
        let edge = p.uv(c.position_world + Vec3::X * p.half_extent.x);
        assert!((edge - Vec2::new(1.0, 0.5)).length() < 1e-5, "{edge}");
        let top = p.uv(c.position_world + Vec3::Y * p.half_extent.y);
        assert!((top - Vec2::new(0.5, 0.0)).length() < 1e-5, "{top}");
        let z = p.ndc(c.position_world).z;
        assert!((z - 0.5).abs() < 1e-5, "{z}");
        assert!((p.axis_u.cross(p.axis_v) - p.normal).length() < 1e-6);
    }

    #[test]
    fn degenerate_frames_give_none() {
        let mut c = centre();
        c.dir_kappa_max = Vec3::Z; // parallel to the normal
        assert!(Projector::new(&c, &ProjectorControls::default(), 1.0).is_none());
        let mut c = centre();
        c.normal_world = Vec3::NAN;
        assert!(Projector::new(&c, &ProjectorControls::default(), 1.0).is_none());
        let c = centre();
        let zero = ProjectorControls {
            scale: Vec2::ZERO,
            ..Default::default()
        };
        assert!(Projector::new(&c, &zero, 1.0).is_none());
    }
}
