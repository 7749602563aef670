//! The GPU search's clusters: the faces in the Morton (Z-order) order of their centroids,
//! cut into runs of one workgroup, each with a normal cone and a bounding sphere, so that
//! `cs_clusters` (`cluster_may_hold` in `shaders/centre_search.wgsl`) leaves out of
//! `cs_search` every run whose faces cannot hold `N = H`, as the CPU search skips whole
//! vertex clusters
//! (`HighlightSearch::find`, its step 0). Built on the CPU once per mesh (the order) and
//! once per pose (the cones and spheres).

use glam::Vec3;
use npr_geometry::{HighlightSearch, SolveVertex};

/// Faces a cluster holds: `WORKGROUP` of `centre_search.wgsl`, so that one workgroup
/// solves one cluster.
pub(crate) const CLUSTER_FACES: usize = 64;

/// Added to every cluster's cone (radians) on top of the solve's own tolerances: the
/// cone must never drop a face the per-face test and the solve would accept.
pub(crate) const SAFETY: f32 = 0.02;

/// `ClusterRecord` of `centre_search.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ClusterRecord {
    /// Unit axis of the faces' vertex normals; `w` = the largest angle from it to one of
    /// them, plus the search's fixed margin and [`SAFETY`] (≥ π: no cone, never skipped).
    pub(crate) axis: [f32; 4],
    /// Centre and radius of a sphere holding every point of the cluster's faces.
    pub(crate) sphere: [f32; 4],
    /// `x` = the angle of the largest per-face slack of the curvature-blended field
    /// ([`HighlightSearch::face_margins`], a sine; π where it bounds nothing); `yzw`
    /// unused.
    pub(crate) margin: [f32; 4],
}

/// The order in which the GPU search visits the faces: by the cube face their mean
/// vertex normal points through (its largest axis and sign), then by the Morton code of
/// their centroids (10 bits an axis over the mesh's bounding box), ties by index. The
/// normal comes first so that a cluster does not take both sides of a thin part (a
/// spatial cell across a torus's tube holds its top and its bottom).
pub(crate) fn face_order(vertices: &[SolveVertex], triangles: &[[u32; 3]]) -> Vec<u32> {
    let get = |v: u32, normal: bool| {
        vertices.get(v as usize).map_or(Vec3::ZERO, |s| {
            let q = if normal { s.normal } else { s.position };
            Vec3::new(q[0], q[1], q[2])
        })
    };
    let at = |v: u32| get(v, false);
    let side = |t: &[u32; 3]| {
        let n = get(t[0], true) + get(t[1], true) + get(t[2], true);
        let a = n.abs();
        let axis: usize = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        2 * axis as u32 + u32::from(n[axis] < 0.0)
    };
    let sides: Vec<u32> = triangles.iter().map(side).collect();
    let centroids: Vec<Vec3> = triangles
        .iter()
        .map(|t| (at(t[0]) + at(t[1]) + at(t[2])) / 3.0)
        .collect();
    let codes = npr_geometry::locality::morton_codes(&centroids);
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    order.sort_by_key(|&f| (sides[f as usize], codes[f as usize], f));
    order
}

/// The cones and spheres of the clusters of `order` (runs of [`CLUSTER_FACES`]) for the
/// search's current pose.
/// `margins`: the search's per-face slack ([`HighlightSearch::face_margins`]).
pub(crate) fn cluster_records(
    triangles: &[[u32; 3]],
    margins: &[f32],
    vertices: &[SolveVertex],
    order: &[u32],
) -> Vec<ClusterRecord> {
    let three = |v: [f32; 4]| Vec3::new(v[0], v[1], v[2]);
    order
        .chunks(CLUSTER_FACES)
        .map(|faces| {
            let corners = || {
                faces
                    .iter()
                    .filter_map(|&f| triangles.get(f as usize))
                    .flat_map(|t| t.iter().filter_map(|&v| vertices.get(v as usize)))
            };
            let normal_sum: Vec3 = corners().map(|v| three(v.normal)).sum();
            let axis = normal_sum.normalize_or_zero();
            let spread = corners()
                .map(|v| axis.dot(three(v.normal)).clamp(-1.0, 1.0).acos())
                .fold(0.0f32, f32::max);
            let (lo, hi) = corners().map(|v| three(v.position)).fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            );
            let centre = (lo + hi) * 0.5;
            let radius = corners()
                .map(|v| three(v.position).distance(centre))
                .fold(0.0f32, f32::max);
            // The per-face slack is a sine (the per-face test compares it with the sine of
            // H's distance to an edge's plane): as an angle, asin of it; 1 or more bounds
            // nothing, and the cluster is always solved then.
            let slack = faces
                .iter()
                .filter_map(|&f| margins.get(f as usize))
                .fold(0.0f32, |m, x| m.max(*x));
            let margin = if (0.0..1.0).contains(&slack) {
                slack.asin()
            } else {
                std::f32::consts::PI
            };
            let limit = spread + HighlightSearch::angle_margin() + SAFETY;
            // A cap wider than a hemisphere is not convex: the arc between two of its
            // normals (a face's interpolated normals) can leave it. Such a cluster is
            // always solved.
            let usable = axis != Vec3::ZERO
                && spread < std::f32::consts::FRAC_PI_2
                && limit.is_finite()
                && radius.is_finite();
            let limit = if usable { limit } else { std::f32::consts::PI };
            ClusterRecord {
                axis: [axis.x, axis.y, axis.z, limit],
                sphere: [centre.x, centre.y, centre.z, radius],
                margin: [margin, 0.0, 0.0, 0.0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_order_is_a_permutation_and_keeps_clusters_compact() {
        let mesh = npr_geometry::generate::torus(1.0, 0.35, 96, 48);
        let (_, topo, field) = npr_geometry::CurvatureField::for_mesh(
            &mesh,
            &npr_geometry::CurvatureOptions::default(),
        );
        let search = HighlightSearch::new(&topo, &field);
        let vertices = search.solve_vertices();
        let order = face_order(&vertices, search.triangles());
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(
            sorted,
            (0..search.triangles().len() as u32).collect::<Vec<_>>()
        );
        // A torus cut into 64-face runs by side and Morton order: the median run's
        // normals span well under a hemisphere and its sphere is a small part of the
        // torus (outer radius 1.35); without the sides, a third of the runs spanned more
        // than 69° (the top and the bottom of the tube in one spatial cell).
        let margins = search.face_margins();
        let records = cluster_records(search.triangles(), &margins, &vertices, &order);
        assert_eq!(records.len(), order.len().div_ceil(CLUSTER_FACES));
        let median = |mut v: Vec<f32>| {
            v.sort_by(f32::total_cmp);
            v[v.len() / 2]
        };
        let cone = median(records.iter().map(|r| r.axis[3]).collect());
        let radius = median(records.iter().map(|r| r.sphere[3]).collect());
        assert!(
            cone < 0.9 && radius < 0.5,
            "median cone {cone}, radius {radius}"
        );
    }
}
