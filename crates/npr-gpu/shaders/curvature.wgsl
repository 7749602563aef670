// The per-vertex curvature tensor of Lee & Choi §2.2, Eq. (1), in the corrected form
// (`npr_geometry::CurvatureMethod::Corrected`), its principal curvatures and directions,
// measured on the GPU from the mesh's own vertex buffer (so a mesh posed by `cs_pose` is
// measured without a copy), after Griffin, Wang, Berrios and Olano 2012 (per-vertex
// tensors gathered on the GPU). The CPU reference is `npr_geometry::CurvatureField::compute`;
// each function below names its Rust twin.
//
// Two passes, both gathers (WebGPU has no float atomics):
//   cs_faces     one invocation per face: its centroid, area, unit normal and the share
//                of its edges' tensors `T_f = Σ_e share_f(e) β(e) |e| ē ēᵀ`;
//   cs_vertices  one invocation per welded vertex: the mesh normal from its own faces,
//                `T = Σ w_f T_f / Σ w_f A_f` over the faces of its ball, and the
//                eigen-analysis in the tangent plane.
// Vertex indices are render vertices (the welded vertex's representative), 8 floats each.

// cs_faces
@group(0) @binding(0) var<storage, read> vertices: array<f32>;
// Per face two records: (corner 0, 1, 2, 0) and, per corner k, the third vertex of the
// face across edge k → k+1 (`NONE` where that edge has no dihedral angle: a boundary,
// non-manifold or inconsistently oriented edge).
@group(0) @binding(1) var<storage, read> faces: array<vec4<u32>>;
// Per face four records: (centroid, area), (Txx, Txy, Txz, Tyy), (Tyz, Tzz, 0, 0),
// (unit normal, 0).
@group(0) @binding(2) var<storage, read_write> records: array<vec4<f32>>;

// cs_vertices (its own bindings)
@group(0) @binding(8) var<storage, read> v_vertices: array<f32>;
// Per welded vertex: (first own face, first ball face, end of ball faces, render vertex)
// into `v_lists`; its own faces run from the first own face to the first ball face.
@group(0) @binding(9) var<storage, read> v_ranges: array<vec4<u32>>;
@group(0) @binding(10) var<storage, read> v_records: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read> v_lists: array<u32>;
// Per welded vertex three records: (normal, kappa_max), (dir_kappa_max, kappa_min),
// (dir_kappa_min, valid ? 1 : 0).
@group(0) @binding(12) var<storage, read_write> v_out: array<vec4<f32>>;

struct CurvatureParams {
    // Ball radius r (world units).
    radius: f32,
    // Welded vertices of this dispatch of `cs_vertices` (one chunk of the mesh's), or of
    // the whole mesh for `cs_faces`.
    vertex_count: u32,
    face_count: u32,
    // The chunk's first welded vertex: `v_ranges` and `v_lists` hold the chunk's own
    // vertices, so one chunk's lists fit a storage binding (a 1.1M-face mesh's do not).
    first_vertex: u32,
}
@group(0) @binding(13) var<uniform> params: CurvatureParams;

const WORKGROUP: u32 = 64u;
const NONE: u32 = 0xffffffffu;

fn invocation(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

// `finite` and `atan2_reduced` are in `numeric.wgsl`, composed before this file.

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

fn position_of(o: u32) -> vec3<f32> {
    return vec3<f32>(vertices[8u * o], vertices[8u * o + 1u], vertices[8u * o + 2u]);
}

fn v_position_of(o: u32) -> vec3<f32> {
    return vec3<f32>(v_vertices[8u * o], v_vertices[8u * o + 1u], v_vertices[8u * o + 2u]);
}

// The upper triangle of s d dᵀ: (xx, xy, xz, yy) and (yz, zz). Rust twin:
// `npr_geometry::curvature::tensor::sym6`.
fn sym6(d: vec3<f32>, s: f32) -> array<vec4<f32>, 2> {
    return array<vec4<f32>, 2>(
        s * vec4<f32>(d.x * d.x, d.x * d.y, d.x * d.z, d.y * d.y),
        s * vec4<f32>(d.y * d.z, d.z * d.z, 0.0, 0.0),
    );
}

// One face's record: centroid, area, normal and `T_f`, each edge's share `A_f / (A_f + A_g)`
// of `β(e) |e| ē ēᵀ` with β the signed dihedral angle (convex positive). Rust twins:
// `npr_geometry::curvature::tensor::face_record` and `Topology`'s dihedral angle
// (`topology::build::EdgeCtx::dihedral`), here from the current positions.
@compute @workgroup_size(64)
fn cs_faces(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let f = invocation(gid, groups);
    if f >= params.face_count {
        return;
    }
    let corners = faces[2u * f];
    let across = faces[2u * f + 1u];
    var p = array<vec3<f32>, 3>(position_of(corners.x), position_of(corners.y), position_of(corners.z));
    let c = (p[0] + p[1] + p[2]) / 3.0;
    let na = normal_area(p[0], p[1], p[2]);
    var t0 = vec4<f32>(0.0);
    var t1 = vec4<f32>(0.0);
    if na.w > 0.0 {
        for (var k = 0u; k < 3u; k++) {
            let o = across[k];
            if o == NONE {
                continue;
            }
            let a = p[k];
            let b = p[(k + 1u) % 3u];
            // The face across runs b → a (the edge is consistently oriented).
            let g = normal_area(b, a, position_of(o));
            if !(g.w > 0.0) {
                continue;
            }
            let d = b - a;
            let l = length(d);
            let beta = atan2_reduced(dot(cross(na.xyz, g.xyz), d / l), dot(na.xyz, g.xyz));
            if beta == 0.0 || !(l > 0.0) {
                continue;
            }
            let share = na.w / (na.w + g.w);
            let s = sym6(d, share * beta / l);
            t0 += s[0];
            t1 += s[1];
        }
    }
    records[4u * f] = vec4<f32>(c, na.w);
    records[4u * f + 1u] = t0;
    records[4u * f + 2u] = t1;
    records[4u * f + 3u] = vec4<f32>(na.xyz, 0.0);
}

fn write_invalid(v: u32, n: vec3<f32>) {
    var nn = n;
    if !finite3(n) {
        nn = vec3<f32>(0.0, 0.0, 1.0);
    }
    v_out[3u * v] = vec4<f32>(nn, 0.0);
    v_out[3u * v + 1u] = vec4<f32>(0.0);
    v_out[3u * v + 2u] = vec4<f32>(0.0);
}

// The tensor (upper triangle t0 = (xx, xy, xz, yy), t1 = (yz, zz)) projected onto the
// tangent plane of `n` and eigen-decomposed there; the larger eigenvalue's eigenvector is
// the direction of minimum curvature (§2.2: the tensor swaps them). Rust twins:
// `npr_geometry::curvature::eigen::tangent_axes` and `finish`.
fn tangent_axes(v: u32, t0: vec4<f32>, t1: vec2<f32>, n: vec3<f32>) {
    let m = mat3x3<f32>(
        vec3<f32>(t0.x, t0.y, t0.z),
        vec3<f32>(t0.y, t0.w, t1.x),
        vec3<f32>(t0.z, t1.x, t1.y),
    );
    let tp = orthonormal_pair(n);
    let m1 = m * tp[0];
    let m2 = m * tp[1];
    let e = sym2_eigen(dot(tp[0], m1), 0.5 * (dot(tp[0], m2) + dot(tp[1], m1)), dot(tp[1], m2));
    let u = e.z * tp[0] + e.w * tp[1];
    let ul = length(u);
    if !(ul > 0.0) || !finite(ul) {
        write_invalid(v, n);
        return;
    }
    let dmin0 = u / ul;
    let dmax = cross(dmin0, n);
    let dmin = cross(n, dmax);
    if !(finite3(dmax) && finite3(dmin) && finite(e.x) && finite(e.y)) {
        write_invalid(v, n);
        return;
    }
    v_out[3u * v] = vec4<f32>(n, e.x);
    v_out[3u * v + 1u] = vec4<f32>(dmax, e.y);
    v_out[3u * v + 2u] = vec4<f32>(dmin, 1.0);
}

// One welded vertex: the area-weighted mesh normal from its own faces (Rust twin: the
// vertex normals of `npr_geometry::Topology::new`), then Eq. (1) in the corrected form
// over its ball, `T = Σ w_f T_f / Σ w_f A_f`, `w_f = (1 − d²/r²)²` for the faces whose
// centroid is inside (Rust twin: `npr_geometry::curvature::tensor::corrected_axes`).
@compute @workgroup_size(64)
fn cs_vertices(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let local = invocation(gid, groups);
    if local >= params.vertex_count {
        return;
    }
    let v = params.first_vertex + local;
    let range = v_ranges[local];
    var nsum = vec3<f32>(0.0);
    for (var k = range.x; k < range.y; k++) {
        let f = v_lists[k];
        nsum += v_records[4u * f + 3u].xyz * v_records[4u * f].w;
    }
    var n = vec3<f32>(0.0, 0.0, 1.0);
    let nl = length(nsum);
    if nl > 0.0 && finite(nl) {
        n = nsum / nl;
    }
    let pv = v_position_of(range.w);
    let r2 = params.radius * params.radius;
    let inv_r2 = 1.0 / r2;
    var acc0 = vec4<f32>(0.0);
    var acc1 = vec4<f32>(0.0);
    for (var k = range.y; k < range.z; k++) {
        let f = v_lists[k];
        let head = v_records[4u * f];
        let dv = head.xyz - pv;
        let d2 = dot(dv, dv);
        if d2 < r2 {
            let q = 1.0 - d2 * inv_r2;
            let w = q * q;
            acc0 += w * v_records[4u * f + 1u];
            acc1 += w * vec4<f32>(v_records[4u * f + 2u].xy, head.w, 0.0);
        }
    }
    let area = acc1.z;
    let ok = area > 0.0 && finite(area) && finite(acc0.x) && finite(acc0.y) && finite(acc0.z)
        && finite(acc0.w) && finite(acc1.x) && finite(acc1.y) && finite3(pv);
    if !ok {
        write_invalid(v, n);
        return;
    }
    tangent_axes(v, acc0 / area, acc1.xy / area, n);
}
