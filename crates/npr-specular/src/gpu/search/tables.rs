//! The search's tables and parameters as `centre_search.wgsl` reads them.

use glam::Mat4;
use npr_geometry::{HighlightSearch, SolveFrame, SolveHalfVector};

/// `SearchParams` of `centre_search.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Params {
    world_from_object: [[f32; 4]; 4],
    object_from_world_normal: [[f32; 4]; 4],
    normal_world_from_object: [[f32; 4]; 4],
    light: [f32; 4],
    eye: [f32; 4],
    half_vector: [f32; 4],
    kind: u32,
    curved: u32,
    face_count: u32,
    capacity: u32,
    angle_margin: f32,
    max_groups: u32,
    merge_distance: f32,
    inv_scale: f32,
    field_normals: u32,
    transform_ok: u32,
    peak_sigma: f32,
    peak_similar: u32,
    peak_light: [f32; 4],
    peak_eye: [f32; 4],
    peak_object_light: [f32; 4],
    peak_object_eye: [f32; 4],
}

/// `FieldVertex` of `centre_search.wgsl`: one welded vertex of the field `cs_centres`
/// interpolates, in `npr_gpu::CurvaturePass`'s output layout.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FieldVertex {
    normal_kmax: [f32; 4],
    dir_kmin: [f32; 4],
    dir_min_valid: [f32; 4],
}

/// The search's field ([`HighlightSearch::field_floats`]) as `cs_centres` reads it.
pub(super) fn field_records(search: &HighlightSearch) -> Vec<FieldVertex> {
    search
        .field_floats()
        .iter()
        .map(|f| FieldVertex {
            normal_kmax: [f[0], f[1], f[2], f[3]],
            dir_kmin: [f[4], f[5], f[6], f[7]],
            dir_min_valid: [f[8], f[9], f[10], f[11]],
        })
        .collect()
}

/// `SolveVertex` of `centre_search.wgsl`: 20 floats.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct VertexRecord {
    position: [f32; 4],
    normal: [f32; 4],
    shape_x: [f32; 4],
    shape_y: [f32; 4],
    shape_z: [f32; 4],
}

pub(super) fn vertex_records(solve_vertices: &[npr_geometry::SolveVertex]) -> Vec<VertexRecord> {
    solve_vertices
        .iter()
        .map(|v| VertexRecord {
            position: v.position,
            normal: v.normal,
            shape_x: v.shape[0],
            shape_y: v.shape[1],
            shape_z: v.shape[2],
        })
        .collect()
}

/// The search's triangles in `order`, each with its cone test's slack (`margins`, per
/// face; in `w` as bits).
pub(crate) fn ordered_triangles(
    search: &HighlightSearch,
    margins: &[f32],
    order: &[u32],
) -> Vec<[u32; 4]> {
    order
        .iter()
        .map(|&f| {
            let t = search.triangles()[f as usize];
            let m = margins.get(f as usize).copied().unwrap_or(2.0);
            [t[0], t[1], t[2], m.to_bits()]
        })
        .collect()
}

/// The frame's parameters: the solve's (`frame`, none without a half vector), the list's
/// sizes, and what `cs_merge` and `cs_centres` need from `search` and the transform (the
/// values `HighlightSearch::centre_at` takes).
pub(super) fn params_of(
    frame: Option<SolveFrame>,
    (faces, capacity): (usize, usize),
    max_groups: u32,
    (search, world_from_object): (&HighlightSearch, Mat4),
    peaks: Option<super::peaks::PeakParams>,
) -> Params {
    let four = |v: glam::Vec3| [v.x, v.y, v.z, 0.0];
    let lin = glam::Mat3::from_mat4(world_from_object);
    let normal = lin.inverse().transpose();
    let scale = lin.determinant().abs().cbrt();
    let mut p = Params {
        world_from_object: world_from_object.to_cols_array_2d(),
        normal_world_from_object: Mat4::from_mat3(normal).to_cols_array_2d(),
        face_count: faces as u32,
        capacity: capacity as u32,
        angle_margin: HighlightSearch::angle_margin(),
        max_groups,
        merge_distance: search.merge_distance(),
        inv_scale: if scale > 0.0 { 1.0 / scale } else { 1.0 },
        field_normals: u32::from(search.normal_source() == npr_geometry::NormalSource::Field),
        transform_ok: u32::from(normal.is_finite()),
        ..Params::default()
    };
    if let Some(q) = peaks {
        p.peak_sigma = q.sigma;
        p.peak_similar = q.similar;
        p.peak_light = q.light;
        p.peak_eye = q.eye;
        p.peak_object_light = q.object_light;
        p.peak_object_eye = q.object_eye;
    }
    let Some(frame) = frame else {
        return p;
    };
    p.curved = u32::from(frame.curved);
    match frame.half_vector {
        SolveHalfVector::Constant(h) => {
            p.kind = 0;
            p.half_vector = four(h);
        }
        SolveHalfVector::ObjectPositions { light, eye } => {
            p.kind = 1;
            (p.light, p.eye) = (four(light), four(eye));
        }
        SolveHalfVector::WorldPositions {
            light,
            eye,
            world_from_object,
            object_from_world_normal,
        } => {
            p.kind = 2;
            (p.light, p.eye) = (four(light), four(eye));
            p.world_from_object = world_from_object.to_cols_array_2d();
            p.object_from_world_normal =
                Mat4::from_mat3(object_from_world_normal).to_cols_array_2d();
        }
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `SearchFrame` of `centre_search.wgsl`: the counter, then the params.
    #[repr(C)]
    #[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
    struct FrameLayout {
        counter: [u32; 4],
        params: Params,
    }
    use crate::cpu::clusters::ClusterRecord;

    #[test]
    fn params_layout_matches_wgsl() {
        // `SearchParams` is bound inside `SearchFrame` (checked below, with its size):
        // its fields' offsets by WGSL's rules (vec4 and mat4 on 16 bytes).
        let offsets = [
            std::mem::offset_of!(Params, object_from_world_normal),
            std::mem::offset_of!(Params, normal_world_from_object),
            std::mem::offset_of!(Params, light),
            std::mem::offset_of!(Params, half_vector),
            std::mem::offset_of!(Params, kind),
            std::mem::offset_of!(Params, angle_margin),
            std::mem::offset_of!(Params, merge_distance),
            std::mem::offset_of!(Params, inv_scale),
            std::mem::offset_of!(Params, field_normals),
            std::mem::offset_of!(Params, transform_ok),
            std::mem::offset_of!(Params, peak_sigma),
            std::mem::offset_of!(Params, peak_similar),
            std::mem::offset_of!(Params, peak_light),
            std::mem::offset_of!(Params, peak_object_eye),
            std::mem::size_of::<Params>(),
        ];
        assert_eq!(
            offsets,
            [
                64, 128, 192, 224, 240, 256, 264, 268, 272, 276, 280, 284, 288, 336, 352
            ]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            ClusterRecord,
            "ClusterRecord",
            [axis, sphere, margin]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            VertexRecord,
            "SolveVertex",
            [position, normal, shape_x, shape_y, shape_z]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FrameLayout,
            "SearchFrame",
            [counter, params]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            super::super::peaks::ScratchLayout,
            "PeakScratch",
            [listed, overflowed, list_room, pad, data]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            FieldVertex,
            "FieldVertex",
            [normal_kmax, dir_kmin, dir_min_valid]
        );
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            super::super::readback::CentreRecord,
            "CentreRecord",
            [
                position_object,
                position_world,
                normal_object,
                normal_world,
                dir_kappa_max,
                curvature,
                solution
            ]
        );
    }
}
