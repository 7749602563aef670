//! Per-vertex stroke directions from principal curvature (Kim & Lee: "a principal
//! curvature direction projected to the screen"), computed by `npr-geometry` and carried
//! per render vertex into the G-buffer pass ([`crate::ScenePasses::create_object`]).
//!
//! Two sources ([`DirectionSource`]): the default, a globally smooth line field fitted to
//! the principal directions (Knöppel et al. 2013, [`npr_geometry::stroke_field`]), which
//! follows curvature where it is clearly directional and stays smooth elsewhere; and the
//! raw principal directions of the curvature field, vertex by vertex (the paper's rule).
//!
//! Hard-edged models: by default the smooth field is cut along creases (edges
//! bending by more than 50°, the outline's crease angle, so strokes turn where a crease
//! line is drawn; in lines at least a fifth of the mesh size long, so a scan's noise is
//! not cut), and each flat patch gets one straight direction: the curvature field
//! carried in where a curved surface joins it smoothly (a fillet), otherwise the planar
//! rule `up × n` (`x × n` within 30° of facing up). Cylinders and cones keep the
//! curvature direction (around them). [`StrokeFieldOptions::curvature_only`] is the
//! field without these rules.

use glam::Vec3;
use npr_geometry::stroke_field::NONE;
use npr_geometry::{CurvatureField, CurvatureOptions, Mesh, StrokeField, StrokeFieldOptions};

/// Where the per-vertex stroke directions come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DirectionSource {
    /// The smooth line field of [`npr_geometry::StrokeField`] (the default): on the
    /// Stanford bunny it turns by more than 30° across 1.7 % of the edges, against 9.8 %
    /// for [`DirectionSource::Principal`]. By default it is cut at creases and straight
    /// on flat patches (see the module docs);
    /// `Smooth(StrokeFieldOptions::curvature_only())` is the field without those rules.
    Smooth(StrokeFieldOptions),
    /// The principal directions of the curvature field, vertex by vertex
    /// ([`principal_directions`]): the paper's rule (Kim & Lee).
    Principal,
}

impl Default for DirectionSource {
    fn default() -> Self {
        Self::Smooth(StrokeFieldOptions::default())
    }
}

impl DirectionSource {
    /// Short name for tables and file names: `smooth` or `raw`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Smooth(_) => "smooth",
            Self::Principal => "raw",
        }
    }
}

/// Below this [`StrokeField::strength`] a vertex of the smooth field takes the fallback
/// direction: the field is (nearly) zero only on components without any anisotropic
/// vertex (a sphere), where it carries no direction.
pub const SMOOTH_FALLBACK_STRENGTH: f32 = 0.01;

/// The axis after `axis` for the fallback and the planar rule: +x, or +z when `axis` is
/// within about 25° of ±x.
pub fn second_axis(axis: Vec3) -> Vec3 {
    if axis.normalize_or_zero().dot(Vec3::X).abs() > 0.9 {
        Vec3::Z
    } else {
        Vec3::X
    }
}

/// `d` projected onto the tangent plane of `n` and normalised, or `fallback_axis × n`
/// when that vanishes, or `second_axis(fallback_axis) × n` where `n` is parallel to the
/// axis (a flat cap facing up gets a direction, not θ = 0).
fn tangent_or_fallback(d: Option<Vec3>, n: Vec3, fallback_axis: Vec3) -> Vec3 {
    d.map(|d| (d - n * n.dot(d)).normalize_or_zero())
        .filter(|d| *d != Vec3::ZERO)
        .unwrap_or_else(|| {
            let a = fallback_axis.normalize_or_zero().cross(n);
            if a.length() > 1e-3 {
                a.normalize_or_zero()
            } else {
                second_axis(fallback_axis).cross(n).normalize_or_zero()
            }
        })
}

/// One unit stroke direction per render vertex of `mesh` (object space) from `source`,
/// along the chosen principal direction.
///
/// The smooth source runs [`StrokeField::for_mesh`] with the source's options, except
/// that the planar rule's axes become `fallback_axis` and [`second_axis`] of it, so one
/// up axis drives both rules. A render vertex reads the field on the side of the crease
/// of its first face.
///
/// Where the source defines no direction (umbilic or flat regions for
/// [`DirectionSource::Principal`], see [`principal_directions`]; components where the
/// smooth field is weaker than [`SMOOTH_FALLBACK_STRENGTH`]) the direction falls back to
/// `fallback_axis × n`, as [`principal_directions`] does.
pub fn stroke_directions(
    mesh: &Mesh,
    source: &DirectionSource,
    which: StrokeDirection,
    options: &CurvatureOptions,
    fallback_axis: Vec3,
) -> Vec<Vec3> {
    let field_options = match source {
        DirectionSource::Principal => {
            return principal_directions(mesh, which, options, fallback_axis);
        }
        DirectionSource::Smooth(o) => StrokeFieldOptions {
            planar_axis: fallback_axis,
            planar_second_axis: second_axis(fallback_axis),
            ..*o
        },
    };
    let smooth = StrokeField::for_mesh(mesh, options, &field_options);
    let field = &smooth.field;
    let along = match which {
        StrokeDirection::KappaMax => field.dir_kappa_max.clone(),
        StrokeDirection::KappaMin => field.dir_kappa_min(),
    };
    (0..mesh.positions.len())
        .map(|v| {
            let n = mesh.normals.get(v).copied().unwrap_or(Vec3::Y);
            let d = smooth
                .render_to_field
                .get(v)
                .copied()
                .filter(|&w| w != NONE)
                .map(|w| w as usize)
                .filter(|&w| {
                    field
                        .strength
                        .get(w)
                        .is_some_and(|&s| s >= SMOOTH_FALLBACK_STRENGTH)
                })
                .and_then(|w| along.get(w).copied());
            tangent_or_fallback(d, n, fallback_axis)
        })
        .collect()
}

/// Which principal direction the strokes follow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StrokeDirection {
    /// Along the direction of maximum curvature (around a tube or a cylinder).
    #[default]
    KappaMax,
    /// Along the direction of minimum curvature (along a tube).
    KappaMin,
}

/// One unit stroke direction per render vertex of `mesh` (object space), from its
/// curvature field.
///
/// Where the principal directions are undefined or unstable — umbilic points (a sphere,
/// `|κ_max − κ_min|` below 5 % of `|κ_max| + |κ_min|`), flat regions, vertices the field
/// could not define — the direction falls back to `fallback_axis × n`, the parallels of a
/// surface of revolution about that axis (use `Vec3::Y` for y-up scenes); where the
/// normal is parallel to the axis (a flat cap), `second_axis(fallback_axis) × n`.
pub fn principal_directions(
    mesh: &Mesh,
    which: StrokeDirection,
    options: &CurvatureOptions,
    fallback_axis: Vec3,
) -> Vec<Vec3> {
    let (welded, _, field) = CurvatureField::for_mesh(mesh, options);
    let field = field.to_render(&welded.render_to_welded);
    (0..mesh.positions.len())
        .map(|v| {
            let n = mesh.normals.get(v).copied().unwrap_or(Vec3::Y);
            let (Some(&valid), Some(&kmax), Some(&kmin)) = (
                field.valid.get(v),
                field.kappa_max.get(v),
                field.kappa_min.get(v),
            ) else {
                return tangent_or_fallback(None, n, fallback_axis);
            };
            let anisotropic = (kmax - kmin).abs() > 0.05 * (kmax.abs() + kmin.abs());
            let d = (valid && anisotropic).then(|| match which {
                StrokeDirection::KappaMax => field.dir_kappa_max[v],
                StrokeDirection::KappaMin => field.dir_kappa_min[v],
            });
            tangent_or_fallback(d, n, fallback_axis)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use npr_geometry::generate;

    #[test]
    fn torus_directions_follow_the_chosen_principal_direction() {
        let (big, small) = (1.0, 0.35);
        let mesh = generate::torus(big, small, 64, 32);
        let opts = CurvatureOptions::default();
        let around = principal_directions(&mesh, StrokeDirection::KappaMax, &opts, Vec3::Y);
        let along = principal_directions(&mesh, StrokeDirection::KappaMin, &opts, Vec3::Y);
        for (v, p) in mesh.positions.iter().enumerate() {
            // The parallel (around the main axis) is the k_min direction on a torus.
            let parallel = Vec3::Y.cross(*p).normalize();
            assert!(along[v].dot(parallel).abs() > 0.99, "vertex {v}");
            assert!(around[v].dot(parallel).abs() < 0.1, "vertex {v}");
            assert!((around[v].length() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn smooth_torus_directions_follow_the_chosen_principal_direction() {
        let mesh = generate::torus(1.0, 0.35, 64, 32);
        let opts = CurvatureOptions::default();
        let source = DirectionSource::default();
        let around = stroke_directions(&mesh, &source, StrokeDirection::KappaMax, &opts, Vec3::Y);
        let along = stroke_directions(&mesh, &source, StrokeDirection::KappaMin, &opts, Vec3::Y);
        for (v, p) in mesh.positions.iter().enumerate() {
            let parallel = Vec3::Y.cross(*p).normalize();
            assert!(along[v].dot(parallel).abs() > 0.999, "vertex {v}");
            assert!(around[v].dot(parallel).abs() < 0.05, "vertex {v}");
            assert!((around[v].length() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn the_field_cuts_creases_where_outlines_draw_them() {
        // Strokes turn exactly where a crease line is drawn.
        assert_eq!(
            StrokeFieldOptions::default().crease_angle_deg,
            npr_gpu::outline::OutlineSettings::default().crease_angle_deg
        );
    }

    #[test]
    fn umbilic_sphere_falls_back_to_parallels() {
        let mesh = generate::icosphere(3, 1.0);
        for source in [DirectionSource::Principal, DirectionSource::default()] {
            let d = stroke_directions(
                &mesh,
                &source,
                StrokeDirection::KappaMax,
                &CurvatureOptions::default(),
                Vec3::Y,
            );
            for (v, n) in mesh.normals.iter().enumerate() {
                // At the poles (normal along the axis) the second axis takes over.
                let want = if Vec3::Y.cross(*n).length() > 1e-3 {
                    Vec3::Y.cross(*n).normalize()
                } else {
                    Vec3::X.cross(*n).normalize()
                };
                assert!((d[v] - want).length() < 1e-5, "{source:?} vertex {v}");
                assert!((d[v].length() - 1.0).abs() < 1e-5, "{source:?} vertex {v}");
            }
        }
    }
}
