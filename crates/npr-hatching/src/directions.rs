//! Per-vertex stroke directions from principal curvature (SPEC §3: "a principal
//! curvature direction projected to the screen"), computed by `npr-geometry`'s curvature
//! field and carried per render vertex into the G-buffer pass.

use glam::Vec3;
use npr_geometry::{CurvatureField, CurvatureOptions, Mesh};

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
/// surface of revolution about that axis (use `Vec3::Y` for y-up scenes). A zero vector
/// remains only where the normal is parallel to the axis; the G-buffer pass reads it as
/// θ = 0.
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
            let fallback = fallback_axis.cross(n).normalize_or_zero();
            let (Some(&valid), Some(&kmax), Some(&kmin)) = (
                field.valid.get(v),
                field.kappa_max.get(v),
                field.kappa_min.get(v),
            ) else {
                return fallback;
            };
            let anisotropic = (kmax - kmin).abs() > 0.05 * (kmax.abs() + kmin.abs());
            if !valid || !anisotropic {
                return fallback;
            }
            let d = match which {
                StrokeDirection::KappaMax => field.dir_kappa_max[v],
                StrokeDirection::KappaMin => field.dir_kappa_min[v],
            };
            let d = (d - n * n.dot(d)).normalize_or_zero();
            if d == Vec3::ZERO { fallback } else { d }
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
    fn umbilic_sphere_falls_back_to_parallels() {
        let mesh = generate::icosphere(3, 1.0);
        let d = principal_directions(
            &mesh,
            StrokeDirection::KappaMax,
            &CurvatureOptions::default(),
            Vec3::Y,
        );
        for (v, n) in mesh.normals.iter().enumerate() {
            let want = Vec3::Y.cross(*n).normalize_or_zero();
            assert!((d[v] - want).length() < 1e-5, "vertex {v}");
        }
    }
}
