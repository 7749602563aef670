// One highlight centre as the GPU search computes it (`cs_centres` of
// `centre_search.wgsl`), composed before the shaders that read or write it (the search,
// the tracking of `tracking.wgsl`).

// One merged centre (`npr_geometry::HighlightCentre`): w of `position_object` is 1 where
// the CPU would have one (`HighlightSearch::centre_at`), 0 where not.
struct CentreRecord {
    position_object: vec4<f32>,
    position_world: vec4<f32>,
    normal_object: vec4<f32>,
    normal_world: vec4<f32>,
    dir_kappa_max: vec4<f32>,
    // (κmax, κmin) in 1/world unit; z: 1 for a peak (`cs_peaks`), 0 for a merged centre.
    curvature: vec4<f32>,
    // (face, α and β as bits, the face's visiting slot).
    solution: vec4<u32>,
}

// glam's `Vec3::any_orthonormal_vector` (Duff et al.'s branchless basis): sign of z as
// Rust's `signum`, which is −1 for −0.
fn any_orthonormal(n: vec3<f32>) -> vec3<f32> {
    let s = select(1.0, -1.0, (bitcast<u32>(n.z) & 0x80000000u) != 0u);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, s + n.y * n.y * a, -n.y);
}
