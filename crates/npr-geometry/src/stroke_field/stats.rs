//! Measures of a line field: smoothness across edges, agreement with the principal
//! directions, and the spread of directions over planar patches.

use glam::Vec3;

use super::planar::planar_regions;
use super::{C64, NONE, basis, median, unit_normal};
use crate::{CurvatureField, Mesh, Topology};
/// Angle in degrees (0..=90) between the lines along `a` and `b` after projecting both
/// onto the plane normal to `n`; `None` when either projection vanishes.
pub fn line_angle_deg(a: Vec3, b: Vec3, n: Vec3) -> Option<f64> {
    let n = n.as_dvec3().normalize_or_zero();
    let pa = a.as_dvec3() - n * n.dot(a.as_dvec3());
    let pb = b.as_dvec3() - n * n.dot(b.as_dvec3());
    let (pa, pb) = (pa.try_normalize()?, pb.try_normalize()?);
    Some(pa.dot(pb).abs().min(1.0).acos().to_degrees())
}

/// How smooth a line field is across the edges of `topo`, and how well it follows the
/// principal directions: the measures of `cargo xtask bench hatching-directions`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineFieldStats {
    /// Share (0–1) of the measured edges across which the line turns by more than the
    /// threshold (line angle mod 180°, both ends projected onto the plane normal to the
    /// mean of the two vertex normals).
    pub jump_edge_share: f64,
    /// Edges measured (both ends with a defined direction and finite geometry).
    pub edges_measured: usize,
    /// Mean angle (degrees) between the field and the direction of maximum curvature at
    /// the valid vertices whose `|κ_max − κ_min|` is at or above the median (the most
    /// anisotropic half).
    pub aniso_dev_deg: f64,
    /// Vertices in that half with a defined direction.
    pub aniso_vertices: usize,
}

impl LineFieldStats {
    /// Measures per-vertex `directions` (one per vertex of `topo`, any sign, zero =
    /// undefined) with edge threshold `threshold_deg`, against `curvature`'s principal
    /// directions and normals.
    pub fn measure(
        topo: &Topology,
        curvature: &CurvatureField,
        directions: &[Vec3],
        threshold_deg: f64,
    ) -> Self {
        let normal = |i: usize| unit_normal(curvature, topo, i).as_vec3();
        let (mut jumps, mut measured) = (0usize, 0usize);
        for &[i, j] in &topo.edges {
            let (i, j) = (i as usize, j as usize);
            let (Some(&a), Some(&b)) = (directions.get(i), directions.get(j)) else {
                continue;
            };
            let n = normal(i) + normal(j);
            if let Some(angle) = line_angle_deg(a, b, n) {
                measured += 1;
                if angle > threshold_deg {
                    jumps += 1;
                }
            }
        }
        let aniso: Vec<(usize, f32)> = (0..topo.vertex_count().min(curvature.len()))
            .filter(|&i| curvature.valid[i])
            .map(|i| (i, (curvature.kappa_max[i] - curvature.kappa_min[i]).abs()))
            .filter(|(_, a)| a.is_finite())
            .collect();
        let med = median(aniso.iter().map(|x| x.1).collect());
        let (mut dev, mut count) = (0.0, 0usize);
        for &(i, a) in &aniso {
            if a < med {
                continue;
            }
            let Some(&d) = directions.get(i) else {
                continue;
            };
            if let Some(angle) = line_angle_deg(d, curvature.dir_kappa_max[i], normal(i)) {
                dev += angle;
                count += 1;
            }
        }
        Self {
            jump_edge_share: if measured > 0 {
                jumps as f64 / measured as f64
            } else {
                0.0
            },
            edges_measured: measured,
            aniso_dev_deg: if count > 0 { dev / count as f64 } else { 0.0 },
            aniso_vertices: count,
        }
    }
}

/// Hard-edge measures on the directions a renderer receives (one per render vertex of
/// a [`Mesh`], any sign, zero = undefined): `cargo xtask bench hatching-directions`'s
/// `jump30_smooth_edge_share` and `planar_spread_deg`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderFieldStats {
    /// Share (0–1) of the measured edges whose dihedral angle `|β|` is below the crease
    /// angle across which the stroke line turns by more than the threshold. An edge is
    /// compared within each of its faces, between that face's two corners (the render
    /// vertices it draws with), both projected onto the plane normal to the sum of their
    /// render normals; it counts once if any face sees the turn. On a mesh whose render
    /// vertices are shared this is [`LineFieldStats::jump_edge_share`] restricted to
    /// non-crease edges.
    pub jump_smooth_edge_share: f64,
    /// Edges measured for [`RenderFieldStats::jump_smooth_edge_share`].
    pub smooth_edges_measured: usize,
    /// Over the flat regions ([`FLAT_REGION_DEG`], [`planar_regions`], each covering at
    /// least [`FLAT_REGION_MIN_SHARE`] of the area): the area-weighted median of each
    /// region's circular standard deviation of the stroke direction as a line (angles
    /// doubled, `√(−2 ln R) / 2`, corners weighted by a third of their face's area), in
    /// degrees; `None` when the mesh has no such region.
    pub planar_spread_deg: Option<f64>,
    /// Flat regions measured.
    pub planar_patches: usize,
    /// The share (0–1) of the mesh's area those regions cover.
    pub planar_area_share: f64,
}

/// The benchmarks' fixed measure of flat regions, independent of the stroke field's own
/// planar rule: faces grown while their normals stay within this many degrees of the
/// region's mean normal ([`planar_regions`]).
pub const FLAT_REGION_DEG: f32 = 5.0;
/// The smallest flat region measured, as a share of the mesh's area.
pub const FLAT_REGION_MIN_SHARE: f64 = 0.01;

/// Per flat region of `topo` (the welded topology of `mesh`; [`planar_regions`] at
/// [`FLAT_REGION_DEG`]) covering at least `min_area_share` of the area: the circular
/// standard deviation of the stroke line `directions` (per render vertex) over the
/// region's face corners, in degrees (angles doubled, `√(−2 ln R) / 2`, corners weighted by
/// a third of their face's area), and the region's area.
pub fn planar_spreads_deg(
    mesh: &Mesh,
    topo: &Topology,
    directions: &[Vec3],
    min_area_share: f64,
) -> Vec<(f64, f64)> {
    let patches = planar_regions(topo, FLAT_REGION_DEG);
    let total: f64 = patches.area.iter().sum();
    let mut sums = vec![(C64::new(0.0, 0.0), 0.0f64); patches.normal.len()];
    for (f, &p) in patches.face_patch.iter().enumerate() {
        if p == NONE || !(patches.area[p as usize] >= min_area_share * total) {
            continue;
        }
        let (e1, e2) = basis(patches.normal[p as usize].as_dvec3());
        let w = f64::from(topo.face_areas[f]) / 3.0;
        for k in 0..3 {
            let Some(&r) = mesh.indices.get(3 * f + k) else {
                continue;
            };
            let Some(d) = directions.get(r as usize).map(|d| d.as_dvec3()) else {
                continue;
            };
            let (x, y) = (d.dot(e1), d.dot(e2));
            if x * x + y * y > 1e-12 {
                let slot = &mut sums[p as usize];
                slot.0 += C64::from_polar(w, 2.0 * y.atan2(x));
                slot.1 += w;
            }
        }
    }
    sums.iter()
        .zip(&patches.area)
        .filter(|((_, w), _)| *w > 0.0)
        .map(|((z, w), &a)| {
            let r = (z.norm() / w).clamp(1e-300, 1.0);
            (
                ((-2.0 * r.ln()).max(0.0) + 0.0).sqrt().to_degrees() / 2.0,
                a,
            )
        })
        .collect()
}

impl RenderFieldStats {
    /// Measures `directions` (per render vertex of `mesh`) on `topo`, the topology of
    /// `mesh` welded (same faces in the same order), with edge threshold `threshold_deg`
    /// and crease angle `crease_angle_deg`.
    pub fn measure(
        mesh: &Mesh,
        topo: &Topology,
        directions: &[Vec3],
        threshold_deg: f64,
        crease_angle_deg: f32,
    ) -> Self {
        let corner = |f: usize, v: u32| -> Option<(Vec3, Vec3)> {
            let k = topo.triangles.get(f)?.iter().position(|&x| x == v)?;
            let r = *mesh.indices.get(3 * f + k)? as usize;
            Some((
                *directions.get(r)?,
                mesh.normals.get(r).copied().unwrap_or(Vec3::ZERO),
            ))
        };
        let limit = crease_angle_deg.to_radians();
        let (mut jumps, mut measured) = (0usize, 0usize);
        for (e, &[i, j]) in topo.edges.iter().enumerate() {
            if !(topo.dihedral[e].abs() < limit) {
                continue;
            }
            let mut angle: Option<f64> = None;
            for &f in topo.edge_faces(e) {
                let (Some((a, na)), Some((b, nb))) = (corner(f as usize, i), corner(f as usize, j))
                else {
                    continue;
                };
                if let Some(x) = line_angle_deg(a, b, na + nb) {
                    angle = Some(angle.map_or(x, |y| y.max(x)));
                }
            }
            if let Some(x) = angle {
                measured += 1;
                if x > threshold_deg {
                    jumps += 1;
                }
            }
        }

        let mut spreads = planar_spreads_deg(mesh, topo, directions, FLAT_REGION_MIN_SHARE);
        let total_area: f64 = topo.face_areas.iter().map(|&a| f64::from(a)).sum();
        spreads.sort_by(|a, b| a.0.total_cmp(&b.0));
        let weight: f64 = spreads.iter().map(|s| s.1).sum();
        let mut acc = 0.0;
        let planar_spread_deg = spreads
            .iter()
            .find(|s| {
                acc += s.1;
                acc >= 0.5 * weight
            })
            .map(|s| s.0);
        Self {
            jump_smooth_edge_share: if measured > 0 {
                jumps as f64 / measured as f64
            } else {
                0.0
            },
            smooth_edges_measured: measured,
            planar_spread_deg,
            planar_patches: spreads.len(),
            planar_area_share: if total_area > 0.0 {
                weight / total_area
            } else {
                0.0
            },
        }
    }
}
