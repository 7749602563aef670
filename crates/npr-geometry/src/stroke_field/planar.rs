//! Planar patches (flat parts of a CAD-like mesh) and the planar rule that gives a flat
//! patch its one straight direction.

use glam::{DVec3, Vec3};

use super::{NONE, StrokeFieldOptions};
use crate::{CurvatureField, Topology};
/// The planar rule (see [`StrokeFieldOptions::planar_axis`]): the unit
/// direction `axis × n`, or `second_axis × n` when `n` is within 30° of `±axis`
/// (`|axis × n| < ½`); the zero vector only if that vanishes too.
pub fn planar_direction(n: Vec3, axis: Vec3, second_axis: Vec3) -> Vec3 {
    let n = n.normalize_or_zero();
    let primary = axis.normalize_or_zero().cross(n);
    if primary.length() >= 0.5 {
        return primary.normalize_or_zero();
    }
    let second = second_axis.normalize_or_zero().cross(n).normalize_or_zero();
    if second != Vec3::ZERO {
        second
    } else {
        primary.normalize_or_zero()
    }
}

/// Faces of a mesh grouped into planar patches ([`planar_patches`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanarPatches {
    /// Patch of each face ([`NONE`] for degenerate faces).
    pub face_patch: Vec<u32>,
    /// Area-weighted unit normal of each patch.
    pub normal: Vec<Vec3>,
    /// Area of each patch.
    pub area: Vec<f64>,
}

/// Grows planar patches: from each face not yet in a patch (in face order),
/// adds the faces reached across edges with exactly two faces whose normals are within
/// `tolerance_deg` of the seed face's normal. Every non-degenerate face ends in one patch
/// (most patches of a curved mesh are single faces). On a [`Topology::split_creases`]
/// result no patch crosses a crease.
pub fn planar_patches(topo: &Topology, tolerance_deg: f32) -> PlanarPatches {
    let nf = topo.face_count();
    let cos_tol = tolerance_deg.max(0.0).to_radians().cos();
    let mut out = PlanarPatches {
        face_patch: vec![NONE; nf],
        ..PlanarPatches::default()
    };
    let mut stack = Vec::new();
    for seed in 0..nf {
        if out.face_patch[seed] != NONE || topo.is_degenerate(seed) {
            continue;
        }
        let id = out.normal.len() as u32;
        let n0 = topo.face_normals[seed];
        let (mut sum, mut area) = (DVec3::ZERO, 0.0f64);
        out.face_patch[seed] = id;
        stack.push(seed);
        while let Some(f) = stack.pop() {
            let a = f64::from(topo.face_areas[f]);
            sum += topo.face_normals[f].as_dvec3() * a;
            area += a;
            for &e in &topo.face_edges[f] {
                if e == crate::topology::NO_EDGE {
                    continue;
                }
                let faces = topo.edge_faces(e as usize);
                if faces.len() != 2 {
                    continue;
                }
                for &g in faces {
                    let g = g as usize;
                    if out.face_patch[g] == NONE
                        && !topo.is_degenerate(g)
                        && topo.face_normals[g].dot(n0) >= cos_tol
                    {
                        out.face_patch[g] = id;
                        stack.push(g);
                    }
                }
            }
        }
        out.normal
            .push(sum.try_normalize().unwrap_or(n0.as_dvec3()).as_vec3());
        out.area.push(area);
    }
    out
}

/// The planar patches of `topo` that are flat against the mesh's scale: the
/// median `(|κ_max| + |κ_min|) · √total_area` over a patch's face corners is at most
/// [`StrokeFieldOptions::planar_max_curvature`]. Renumbered: only those patches remain,
/// `face_patch` is [`NONE`] elsewhere.
pub(super) fn flat_patches(
    topo: &Topology,
    curvature: &CurvatureField,
    options: &StrokeFieldOptions,
    total_area: f64,
) -> PlanarPatches {
    if !(options.planar_tolerance_deg > 0.0) || !(total_area > 0.0) || !total_area.is_finite() {
        return PlanarPatches {
            face_patch: vec![NONE; topo.face_count()],
            ..PlanarPatches::default()
        };
    }
    let all = planar_patches(topo, options.planar_tolerance_deg);
    let scale = total_area.sqrt();
    // (patch, κ · scale) per valid face corner, grouped by patch.
    let mut corners: Vec<(u32, f32)> = Vec::new();
    for (f, t) in topo.triangles.iter().enumerate() {
        let p = all.face_patch[f];
        if p == NONE {
            continue;
        }
        for &v in t {
            let v = v as usize;
            if curvature.valid.get(v).copied().unwrap_or(false) {
                let k = f64::from(curvature.kappa_max[v].abs() + curvature.kappa_min[v].abs());
                if k.is_finite() {
                    corners.push((p, (k * scale) as f32));
                }
            }
        }
    }
    corners.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut keep = vec![NONE; all.normal.len()];
    let mut out = PlanarPatches {
        face_patch: vec![NONE; topo.face_count()],
        ..PlanarPatches::default()
    };
    let mut k = 0;
    while k < corners.len() {
        let p = corners[k].0;
        let mut e = k;
        while e < corners.len() && corners[e].0 == p {
            e += 1;
        }
        if corners[k + (e - k) / 2].1 <= options.planar_max_curvature {
            keep[p as usize] = out.normal.len() as u32;
            out.normal.push(all.normal[p as usize]);
            out.area.push(all.area[p as usize]);
        }
        k = e;
    }
    for (f, &p) in all.face_patch.iter().enumerate() {
        if p != NONE {
            out.face_patch[f] = keep[p as usize];
        }
    }
    out
}

/// The flat patch each vertex takes its direction from: that of its largest face in a
/// flat patch ([`NONE`] if none of its faces is in one).
pub(super) fn vertex_patches(topo: &Topology, flat: &PlanarPatches) -> Vec<u32> {
    let nv = topo.vertex_count();
    let mut best = vec![(NONE, 0.0f32); nv];
    for (f, t) in topo.triangles.iter().enumerate() {
        let p = flat.face_patch.get(f).copied().unwrap_or(NONE);
        if p == NONE {
            continue;
        }
        let a = topo.face_areas[f];
        for &v in t {
            if let Some(slot) = best.get_mut(v as usize) {
                if slot.0 == NONE || a > slot.1 {
                    *slot = (p, a);
                }
            }
        }
    }
    best.into_iter().map(|(p, _)| p).collect()
}
