//! Building a [`HighlightSearch`] once per mesh: the normals it solves on, the
//! per-vertex bounds of its rejection tests, the shape operators of the
//! curvature-blended field and the vertex clusters.

use glam::{Mat3, Vec3};

use super::clusters::build_clusters;
use super::{HighlightSearch, NormalInterpolation, NormalSource};
use crate::{CurvatureField, Mesh, Topology, Welded};
/// The render mesh's normals per welded vertex: the normalised sum over the render
/// vertices that weld into it. `None` when the mesh has no usable normals (count differs
/// from the positions', or the weld map does not fit the mesh); a welded vertex whose
/// normals sum to zero or are not finite gets `Vec3::ZERO` (callers fall back there).
pub fn welded_mesh_normals(mesh: &Mesh, welded: &Welded) -> Option<Vec<Vec3>> {
    let n = mesh.positions.len();
    if n == 0 || mesh.normals.len() != n || welded.render_to_welded.len() != n {
        return None;
    }
    let mut sum = vec![Vec3::ZERO; welded.positions.len()];
    for (&w, &normal) in welded.render_to_welded.iter().zip(&mesh.normals) {
        if let Some(s) = sum.get_mut(w as usize) {
            *s += normal;
        }
    }
    let out: Vec<Vec3> = sum
        .into_iter()
        .map(|s| s.try_normalize().unwrap_or(Vec3::ZERO))
        .collect();
    out.iter().any(|v| *v != Vec3::ZERO).then_some(out)
}

impl HighlightSearch {
    /// Prepares the search on the curvature field's normals ([`NormalSource::Field`]).
    /// For a render mesh prefer [`HighlightSearch::for_mesh`], which solves on the normals
    /// the mesh is shaded with.
    pub fn new(topo: &Topology, field: &CurvatureField) -> Self {
        Self::with_normals(topo, field, None)
    }

    /// Prepares the search for a render mesh and its weld (`topo` built from `welded`):
    /// on the mesh's own normals ([`NormalSource::Mesh`], see [`welded_mesh_normals`])
    /// when it has them, else on the field's. Principal directions and curvatures still
    /// come from `field`, projected onto the tangent plane of the normal used.
    pub fn for_mesh(mesh: &Mesh, welded: &Welded, topo: &Topology, field: &CurvatureField) -> Self {
        let normals = welded_mesh_normals(mesh, welded).filter(|n| n.len() == topo.vertex_count());
        Self::with_normals(topo, field, normals.as_deref())
    }

    /// `normals`: one per welded vertex (zero entries fall back to the field's), or
    /// `None` for the field's.
    fn with_normals(topo: &Topology, field: &CurvatureField, given: Option<&[Vec3]>) -> Self {
        let nv = topo.vertex_count();
        let normal_source = if given.is_some() {
            NormalSource::Mesh
        } else {
            NormalSource::Field
        };
        let normals: Vec<Vec3> = (0..nv)
            .map(|v| {
                given
                    .and_then(|n| n.get(v).copied())
                    .filter(|n| *n != Vec3::ZERO && n.is_finite())
                    .or_else(|| field.normal.get(v).copied())
                    .unwrap_or(topo.vertex_normals[v])
            })
            .collect();
        let (vf_offsets, vf) = vertex_face_lists(topo);
        let (cos_spread, reach) = spread_and_reach(topo, &normals);
        let shape = shape_operators(field, nv);
        let (curvature_margin, face_curvature_margin) = curvature_margins(topo, &normals, &shape);
        let (clusters, cluster_vertices) = build_clusters(
            &topo.positions,
            &normals,
            &cos_spread,
            &reach,
            &curvature_margin,
        );
        static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        Self {
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            clusters,
            cluster_vertices,
            positions: topo.positions.clone(),
            triangles: topo.triangles.clone(),
            normals,
            field: field.clone(),
            vf_offsets,
            vf,
            cos_spread,
            reach,
            merge_distance: 1e-2 * topo.mean_edge_length,
            shape,
            curvature_margin,
            face_curvature_margin,
            interpolation: NormalInterpolation::default(),
            normal_source,
        }
    }
}

/// Vertex → faces as one offsets array and one flat list (the faces of `v` are
/// `vf[vf_offsets[v]..vf_offsets[v + 1]]`).
fn vertex_face_lists(topo: &Topology) -> (Vec<u32>, Vec<u32>) {
    let nv = topo.vertex_count();
    let mut vf_offsets = Vec::with_capacity(nv + 1);
    let mut vf = Vec::new();
    vf_offsets.push(0);
    for v in 0..nv {
        vf.extend_from_slice(topo.vertex_faces(v));
        vf_offsets.push(vf.len() as u32);
    }
    (vf_offsets, vf)
}

/// Per vertex: the cos of the largest angle between two vertex normals of any face
/// around it, and its longest incident edge.
fn spread_and_reach(topo: &Topology, normals: &[Vec3]) -> (Vec<f32>, Vec<f32>) {
    let nv = topo.vertex_count();
    let mut cos_spread = vec![1f32; nv];
    let mut reach = vec![0f32; nv];
    for t in &topo.triangles {
        if t.iter().any(|&i| i as usize >= nv) {
            continue;
        }
        let mut c = 1f32;
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            c = c.min(normals[a].dot(normals[b]).clamp(-1.0, 1.0));
            let l = topo.positions[a].distance(topo.positions[b]);
            reach[a] = reach[a].max(l);
            reach[b] = reach[b].max(l);
        }
        for &i in t {
            cos_spread[i as usize] = cos_spread[i as usize].min(c);
        }
    }
    (cos_spread, reach)
}

/// Per vertex, the shape operator `S = κ_max e_max e_maxᵀ + κ_min e_min e_minᵀ` (zero
/// where the field is invalid).
fn shape_operators(field: &CurvatureField, nv: usize) -> Vec<Mat3> {
    (0..nv)
        .map(|v| {
            if !field.valid.get(v).copied().unwrap_or(false) {
                return Mat3::ZERO;
            }
            let outer = |d: Vec3, k: f32| Mat3::from_cols(d * d.x, d * d.y, d * d.z) * k;
            outer(field.dir_kappa_max[v], field.kappa_max[v])
                + outer(field.dir_kappa_min[v], field.kappa_min[v])
        })
        .collect()
}

/// The curvature-blended field's extra slack of the rejection tests: per vertex (the
/// largest over its faces) and per face.
fn curvature_margins(topo: &Topology, normals: &[Vec3], shape: &[Mat3]) -> (Vec<f32>, Vec<f32>) {
    let nv = topo.vertex_count();
    // How far the blended normal can leave the cone of the vertex normals in a face:
    // N(w) − Σ wᵢNᵢ = Σᵢ wᵢSᵢ(x − pᵢ) = Σ_{i<j} wᵢwⱼ(Sᵢ − Sⱼ)(pⱼ − pᵢ), at most
    // (1/3)·max‖Sᵢ − Sⱼ‖·e_max since Σ_{i<j} wᵢwⱼ ≤ 1/3; against |Σ wᵢNᵢ| ≥
    // sqrt((1 + 2c)/3) (c the smallest Nᵢ·Nⱼ) that turns the unit normal by at most
    // the ratio, which bounds the change of any cosine. Small where the curvature is
    // consistent (Sᵢ ≈ Sⱼ), large on a noisy scan's bumps. Kept per face for the face
    // test and per vertex (largest over its faces) for the vertex and cluster tests,
    // so that rough regions do not weaken the rejection elsewhere.
    let mut curvature_margin = vec![0f32; nv];
    let mut face_curvature_margin = vec![2f32; topo.triangles.len()];
    for (f, t) in topo
        .triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| t.iter().all(|&i| (i as usize) < nv))
    {
        let [a, b, c] = t.map(|i| i as usize);
        let frob = |m: Mat3| {
            (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared())
                .sqrt()
        };
        let ds = frob(shape[a] - shape[b])
            .max(frob(shape[b] - shape[c]))
            .max(frob(shape[c] - shape[a]));
        let p = &topo.positions;
        let e = p[a]
            .distance(p[b])
            .max(p[b].distance(p[c]))
            .max(p[c].distance(p[a]));
        let cmin = normals[a]
            .dot(normals[b])
            .min(normals[b].dot(normals[c]))
            .min(normals[c].dot(normals[a]));
        let u_min = ((1.0 + 2.0 * cmin) / 3.0).max(0.0).sqrt();
        let bound = ds * e / 3.0;
        // A slack of 2 in a cosine passes everything.
        let m = if u_min > 0.25 && bound.is_finite() {
            (bound / u_min).min(2.0)
        } else {
            2.0
        };
        face_curvature_margin[f] = m;
        for &i in t {
            curvature_margin[i as usize] = curvature_margin[i as usize].max(m);
        }
    }
    (curvature_margin, face_curvature_margin)
}
