// A pose's tables on the GPU: what `HighlightSet::repose` builds on the CPU for a new
// pose of the same mesh (the search's solve vertices, per-face slack, cluster cones and
// spheres and field; the regions' vertices and faces; the receivers' positions and
// faces; the highlight draw's normals), made from the posed vertex buffer and
// `CurvaturePass`'s field (`npr_gpu::CurvaturePass`, per welded vertex) without reading
// anything back. Each entry point names its Rust twin.
//
//   cs_weld            per welded vertex: its position, the mesh's normal (the mean of its
//                      render vertices' normals), and the value the abstraction diffuses
//                      (normal and shape operator `S`);
//   cs_diffuse         per welded vertex, one step of the diffusion (run as many times as
//                      the abstraction asks, ping-pong);
//   cs_finish          per welded vertex: the field re-analysed at the abstraction's
//                      scale, the solve vertex, the region vertex;
//   cs_faces           per face: its normal, the curvature-blended field's slack of the
//                      search's cone test, the regions' and receivers' face records;
//   cs_clusters        one workgroup per run of faces in the search's order: the faces in
//                      that order with their slack, and the run's cone and sphere;
//   cs_render_normals  per render vertex: the normal the highlight draw shades with.

// Fixed per object: welded vertices, faces, render vertices, whether the abstraction
// diffuses (1) or not (0), whether the mesh has its own normals (1) or not (0), runs of
// faces (clusters), the search's fixed angle margin (bits) and the clusters' safety
// (bits).
@group(0) @binding(5) var<storage, read> params: array<u32, 8>;

// cs_weld
@group(0) @binding(0) var<storage, read> mesh_vertices: array<f32>;
@group(0) @binding(1) var<storage, read> field: array<vec4<f32>>;
// `welded + 1` offsets, then the render vertices of each welded vertex (ascending).
@group(0) @binding(2) var<storage, read> weld: array<u32>;
// Per welded vertex three records: (normal, valid ? 1 : 0), (S00, S01, S02, S11),
// (S12, S22, 0, 0).
@group(0) @binding(3) var<storage, read_write> values: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> positions: array<vec4<f32>>;

// cs_diffuse
@group(0) @binding(6) var<storage, read> d_from: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> d_to: array<vec4<f32>>;
// `welded + 1` offsets, then each welded vertex's neighbours along the mesh's edges.
@group(0) @binding(8) var<storage, read> neighbours: array<u32>;

// cs_finish
@group(0) @binding(9) var<storage, read> f_values: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read> f_positions: array<vec4<f32>>;
// `SolveVertex` of `centre_search.wgsl`: five records a vertex.
@group(0) @binding(11) var<storage, read_write> solve: array<vec4<f32>>;
// `FieldVertex` of `centre_search.wgsl`: three records a vertex (the field's layout).
@group(0) @binding(12) var<storage, read_write> field_out: array<vec4<f32>>;
// `RegionVertex` of `regions.wgsl`: (position, 1), (normal, 0).
@group(0) @binding(13) var<storage, read_write> region_vertices: array<vec4<f32>>;

// cs_faces
// Per face two records: (welded corners, 1 where two corners are one vertex) and
// (render corners, 0).
@group(0) @binding(14) var<storage, read> triangles: array<vec4<u32>>;
@group(0) @binding(15) var<storage, read> s_vertices: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> margins: array<f32>;
// `RegionFace` of `regions.wgsl`: (corners, degenerate), (normal, 0).
@group(0) @binding(17) var<storage, read_write> region_faces: array<vec4<u32>>;
// The receivers' `Face` (`receivers.wgsl`): (corners, degenerate), (render corners,
// slack's sine bits), (normal, slack's cosine).
@group(0) @binding(18) var<storage, read_write> receiver_faces: array<vec4<u32>>;

// cs_clusters
@group(0) @binding(19) var<storage, read> order: array<u32>;
@group(0) @binding(20) var<storage, read> c_margins: array<f32>;
// The search's triangles in its order, the slack's bits in `w`.
@group(0) @binding(21) var<storage, read_write> ordered: array<vec4<u32>>;
// `ClusterRecord` of `centre_search.wgsl`: (axis, limit), (centre, radius), (margin, 0…).
@group(0) @binding(22) var<storage, read_write> clusters: array<vec4<f32>>;

// cs_render_normals
@group(0) @binding(23) var<storage, read> render_to_welded: array<u32>;
@group(0) @binding(24) var<storage, read_write> render_normals: array<vec4<f32>>;

const WORKGROUP: u32 = 64u;
const PI: f32 = 3.141592653589793;

fn invocation(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

fn welded_count() -> u32 {
    return params[0];
}

fn face_count() -> u32 {
    return params[1];
}

fn diffuses() -> bool {
    return params[3] != 0u;
}

fn has_mesh_normals() -> bool {
    return params[4] != 0u;
}

fn mesh_position(r: u32) -> vec3<f32> {
    return vec3<f32>(mesh_vertices[8u * r], mesh_vertices[8u * r + 1u], mesh_vertices[8u * r + 2u]);
}

fn mesh_normal(r: u32) -> vec3<f32> {
    return vec3<f32>(mesh_vertices[8u * r + 3u], mesh_vertices[8u * r + 4u], mesh_vertices[8u * r + 5u]);
}

// `S = κ_max e_max e_maxᵀ + κ_min e_min e_minᵀ` of a field entry, upper triangle.
// Rust twin: `shape_operators` of `npr_geometry::HighlightSearch`.
fn shape_of(a: vec4<f32>, b: vec4<f32>) -> array<vec4<f32>, 2> {
    let d = a.xyz;
    let e = b.xyz;
    let ka = a.w;
    let kb = b.w;
    return array<vec4<f32>, 2>(
        vec4<f32>(
            ka * d.x * d.x + kb * e.x * e.x,
            ka * d.x * d.y + kb * e.x * e.y,
            ka * d.x * d.z + kb * e.x * e.z,
            ka * d.y * d.y + kb * e.y * e.y,
        ),
        vec4<f32>(ka * d.y * d.z + kb * e.y * e.z, ka * d.z * d.z + kb * e.z * e.z, 0.0, 0.0),
    );
}

// One welded vertex: its position (its first render vertex's), the mean of its render
// vertices' normals where the mesh has them (Rust twin: `npr_geometry::welded_mesh_normals`),
// and the value the abstraction diffuses: the normal the search solves on where there is
// no diffusion (the mesh's where usable, else the field's: `HighlightSearch::for_mesh`),
// else the shaded normal (the mesh's, for valid vertices) and `S`, zero where the field
// is invalid (`CurvatureField::at_scale`'s value).
@compute @workgroup_size(64)
fn cs_weld(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = invocation(gid, groups);
    if v >= welded_count() {
        return;
    }
    let first = weld[v];
    let end = weld[v + 1u];
    let base = welded_count() + 1u;
    positions[v] = vec4<f32>(mesh_position(weld[base + first]), 1.0);
    var sum = vec3<f32>(0.0);
    for (var k = first; k < end; k++) {
        sum += mesh_normal(weld[base + k]);
    }
    var own = vec4<f32>(0.0);
    if has_mesh_normals() {
        own = try_normalize(sum);
    }
    let f0 = field[3u * v];
    let f1 = field[3u * v + 1u];
    let f2 = field[3u * v + 2u];
    let valid = f2.w > 0.5;
    var n = f0.xyz;
    if own.w > 0.0 && (valid || !diffuses()) {
        n = own.xyz;
    }
    var s = array<vec4<f32>, 2>(vec4<f32>(0.0), vec4<f32>(0.0));
    if valid {
        s = shape_of(vec4<f32>(f1.xyz, f0.w), vec4<f32>(f2.xyz, f1.w));
    }
    if diffuses() && !valid {
        n = vec3<f32>(0.0);
    }
    values[3u * v] = vec4<f32>(n, select(0.0, 1.0, valid));
    values[3u * v + 1u] = s[0];
    values[3u * v + 2u] = s[1];
}

// One step of the abstraction's diffusion, `x ← (x + mean of valid neighbours) / 2` for
// valid vertices. Rust twin: `npr_geometry::CurvatureField::at_scale`.
@compute @workgroup_size(64)
fn cs_diffuse(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = invocation(gid, groups);
    if v >= welded_count() {
        return;
    }
    let own0 = d_from[3u * v];
    let own1 = d_from[3u * v + 1u];
    let own2 = d_from[3u * v + 2u];
    var out0 = own0;
    var out1 = own1;
    var out2 = own2;
    if own0.w > 0.5 {
        let base = welded_count() + 1u;
        var s0 = vec3<f32>(0.0);
        var s1 = vec4<f32>(0.0);
        var s2 = vec4<f32>(0.0);
        var count = 0u;
        for (var k = neighbours[v]; k < neighbours[v + 1u]; k++) {
            let w = neighbours[base + k];
            let x0 = d_from[3u * w];
            if x0.w > 0.5 {
                s0 += x0.xyz;
                s1 += d_from[3u * w + 1u];
                s2 += d_from[3u * w + 2u];
                count += 1u;
            }
        }
        if count > 0u {
            let inv = 1.0 / f32(count);
            out0 = vec4<f32>(0.5 * own0.xyz + 0.5 * s0 * inv, own0.w);
            out1 = 0.5 * own1 + 0.5 * s1 * inv;
            out2 = 0.5 * own2 + 0.5 * s2 * inv;
        }
    }
    d_to[3u * v] = out0;
    d_to[3u * v + 1u] = out1;
    d_to[3u * v + 2u] = out2;
}

fn write_vertex(v: u32, n: vec3<f32>, s: array<vec4<f32>, 2>, f0: vec4<f32>, f1: vec4<f32>, f2: vec4<f32>) {
    let p = f_positions[v];
    solve[5u * v] = vec4<f32>(p.xyz, 0.0);
    solve[5u * v + 1u] = vec4<f32>(n, 0.0);
    solve[5u * v + 2u] = vec4<f32>(s[0].x, s[0].y, s[0].z, 0.0);
    solve[5u * v + 3u] = vec4<f32>(s[0].y, s[0].w, s[1].x, 0.0);
    solve[5u * v + 4u] = vec4<f32>(s[0].z, s[1].x, s[1].y, 0.0);
    field_out[3u * v] = f0;
    field_out[3u * v + 1u] = f1;
    field_out[3u * v + 2u] = f2;
    region_vertices[2u * v] = vec4<f32>(p.xyz, 1.0);
    region_vertices[2u * v + 1u] = vec4<f32>(n, 0.0);
}

// One welded vertex's tables. Without diffusion: the search's normal and the field as
// measured (`HighlightSearch::for_mesh`, `HighlightSearch::solve_vertices`,
// `field_floats`). With it: the diffused normal, and the diffused `S` projected onto its
// tangent plane and analysed there (the principal pair: `CurvatureField::at_scale`, whose
// eigenvectors least along the normal are the tangent plane's); a vertex without a field
// keeps the measured one.
@compute @workgroup_size(64)
fn cs_finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = invocation(gid, groups);
    if v >= welded_count() {
        return;
    }
    let x0 = f_values[3u * v];
    let f0 = field[3u * v];
    let f1 = field[3u * v + 1u];
    let f2 = field[3u * v + 2u];
    let valid = f2.w > 0.5;
    var s = array<vec4<f32>, 2>(f_values[3u * v + 1u], f_values[3u * v + 2u]);
    if !diffuses() {
        write_vertex(v, x0.xyz, s, f0, f1, f2);
        return;
    }
    let unit = try_normalize(x0.xyz);
    if !valid || unit.w == 0.0 {
        // Invalid, or a normal that did not survive the averaging (the CPU keeps the
        // shaded normal there, here the measured one: a valid vertex whose neighbours'
        // normals cancel out is the only place they differ).
        if valid {
            s = shape_of(vec4<f32>(f1.xyz, f0.w), vec4<f32>(f2.xyz, f1.w));
        }
        write_vertex(v, f0.xyz, s, f0, f1, f2);
        return;
    }
    let n = unit.xyz;
    let m = mat3x3<f32>(
        vec3<f32>(s[0].x, s[0].y, s[0].z),
        vec3<f32>(s[0].y, s[0].w, s[1].x),
        vec3<f32>(s[0].z, s[1].x, s[1].y),
    );
    let tp = orthonormal_pair(n);
    let m1 = m * tp[0];
    let m2 = m * tp[1];
    let e = sym2_eigen(dot(tp[0], m1), 0.5 * (dot(tp[0], m2) + dot(tp[1], m1)), dot(tp[1], m2));
    let e_max = try_normalize(e.z * tp[0] + e.w * tp[1]);
    if e_max.w == 0.0 || !(finite(e.x) && finite(e.y)) {
        let keep = shape_of(vec4<f32>(f1.xyz, f0.w), vec4<f32>(f2.xyz, f1.w));
        write_vertex(v, f0.xyz, keep, f0, f1, f2);
        return;
    }
    // The measured direction's sign (a pose's `at_steps` keeps it too).
    let d = select(e_max.xyz, -e_max.xyz, dot(e_max.xyz, f1.xyz) < 0.0);
    let e_min = cross(n, d);
    let shape = shape_of(vec4<f32>(d, e.x), vec4<f32>(e_min, e.y));
    write_vertex(v, n, shape, vec4<f32>(n, e.x), vec4<f32>(d, e.y), vec4<f32>(e_min, 1.0));
}

fn solve_normal(v: u32) -> vec3<f32> {
    return s_vertices[5u * v + 1u].xyz;
}

fn solve_position(v: u32) -> vec3<f32> {
    return s_vertices[5u * v].xyz;
}

// The Frobenius norm of the difference of two vertices' shape operators.
fn shape_gap(a: u32, b: u32) -> f32 {
    let x = s_vertices[5u * a + 2u].xyz - s_vertices[5u * b + 2u].xyz;
    let y = s_vertices[5u * a + 3u].xyz - s_vertices[5u * b + 3u].xyz;
    let z = s_vertices[5u * a + 4u].xyz - s_vertices[5u * b + 4u].xyz;
    return sqrt(dot(x, x) + dot(y, y) + dot(z, z));
}

// The normal a face corner is shaded with: the mesh's own where the draw keeps it,
// else the search's.
fn corner_normal(welded: u32, render: u32) -> vec3<f32> {
    if has_mesh_normals() && !diffuses() {
        return mesh_normal(render);
    }
    return solve_normal(welded);
}

// One face: its unit normal and whether it is degenerate (Rust twin:
// `npr_geometry::topology::build::face_normal_area`), the curvature-blended field's
// slack of the search's cone test (`curvature_margins` of `HighlightSearch`), and the
// largest angle between its normal and a corner's shading normal
// (`npr_specular::visibility::face_slack`).
@compute @workgroup_size(64)
fn cs_faces(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let f = invocation(gid, groups);
    if f >= face_count() {
        return;
    }
    let t = triangles[2u * f];
    let r = triangles[2u * f + 1u];
    let pa = solve_position(t.x);
    let pb = solve_position(t.y);
    let pc = solve_position(t.z);
    var na = vec4<f32>(0.0);
    if t.w == 0u {
        na = normal_area(pa, pb, pc);
    }
    let degenerate = select(0u, 1u, na.w == 0.0);
    let normal = na.xyz;
    // The slack of the curvature-blended field.
    let ds = max(max(shape_gap(t.x, t.y), shape_gap(t.y, t.z)), shape_gap(t.z, t.x));
    let e = max(max(distance(pa, pb), distance(pb, pc)), distance(pc, pa));
    let a = solve_normal(t.x);
    let b = solve_normal(t.y);
    let c = solve_normal(t.z);
    let cmin = min(min(dot(a, b), dot(b, c)), dot(c, a));
    let u_min = sqrt(max((1.0 + 2.0 * cmin) / 3.0, 0.0));
    let bound = ds * e / 3.0;
    var m = 2.0;
    if u_min > 0.25 && finite(bound) {
        m = min(bound / u_min, 2.0);
    }
    margins[f] = m;
    // The receivers' slack: the corners' shading normals against the face's.
    let corners = array<vec3<f32>, 3>(corner_normal(t.x, r.x), corner_normal(t.y, r.y), corner_normal(t.z, r.z));
    var angle = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let q = corners[k];
        let l2 = dot(q, q);
        if finite(q.x) && finite(q.y) && finite(q.z) && abs(l2 - 1.0) < 1e-2 {
            angle = max(angle, acos(clamp(dot(q, normal), 0.0, 1.0)));
        }
    }
    region_faces[2u * f] = vec4<u32>(t.xyz, degenerate);
    region_faces[2u * f + 1u] = bitcast<vec4<u32>>(vec4<f32>(normal, 0.0));
    receiver_faces[3u * f] = vec4<u32>(t.xyz, degenerate);
    receiver_faces[3u * f + 1u] = vec4<u32>(r.xyz, bitcast<u32>(sin(angle)));
    receiver_faces[3u * f + 2u] = bitcast<vec4<u32>>(vec4<f32>(normal, cos(angle)));
}

var<workgroup> w_vec: array<vec3<f32>, 64>;
var<workgroup> w_max: array<vec3<f32>, 64>;
var<workgroup> w_num: array<vec2<f32>, 64>;

// Sums (`w_vec`) and maxima (`w_max`, `w_num`) over the workgroup, left in element 0.
fn reduce(i: u32, sums: bool) {
    for (var step = 32u; step > 0u; step = step / 2u) {
        if i < step {
            if sums {
                w_vec[i] += w_vec[i + step];
            } else {
                w_vec[i] = min(w_vec[i], w_vec[i + step]);
            }
            w_max[i] = max(w_max[i], w_max[i + step]);
            w_num[i] = max(w_num[i], w_num[i + step]);
        }
        workgroupBarrier();
    }
}

// One run of 64 faces in the search's order: the faces written in that order with their
// slack, and the run's cone of vertex normals and sphere of positions. Rust twin:
// `npr_specular::search_clusters::cluster_records` (and `ordered_triangles`).
@compute @workgroup_size(64)
fn cs_clusters(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) i: u32) {
    let cluster = wid.x + wid.y * groups.x;
    let at = cluster * WORKGROUP + i;
    let here = at < face_count();
    var t = vec3<u32>(0u);
    var slack = 0.0;
    if here {
        let f = order[at];
        t = triangles[2u * f].xyz;
        slack = c_margins[f];
        ordered[at] = vec4<u32>(t, bitcast<u32>(slack));
    }
    // The axis: the normalised sum of the corners' normals.
    w_vec[i] = vec3<f32>(0.0);
    if here {
        w_vec[i] = solve_normal(t.x) + solve_normal(t.y) + solve_normal(t.z);
    }
    w_max[i] = vec3<f32>(-3.4e38);
    w_num[i] = vec2<f32>(0.0);
    workgroupBarrier();
    reduce(i, true);
    let sum = w_vec[0];
    workgroupBarrier();
    let axis = try_normalize(sum).xyz;
    // The spread (largest angle from the axis), the box of the corners and the slack.
    var spread = 0.0;
    w_vec[i] = vec3<f32>(3.4e38);
    w_max[i] = vec3<f32>(-3.4e38);
    if here {
        for (var k = 0u; k < 3u; k++) {
            let v = t[k];
            spread = max(spread, acos(clamp(dot(axis, solve_normal(v)), -1.0, 1.0)));
            w_vec[i] = min(w_vec[i], solve_position(v));
            w_max[i] = max(w_max[i], solve_position(v));
        }
    }
    w_num[i] = vec2<f32>(spread, select(0.0, slack, here));
    workgroupBarrier();
    reduce(i, false);
    let lo = w_vec[0];
    let hi = w_max[0];
    let spread_all = w_num[0].x;
    let slack_all = w_num[0].y;
    workgroupBarrier();
    let centre = (lo + hi) * 0.5;
    var radius = 0.0;
    if here {
        for (var k = 0u; k < 3u; k++) {
            radius = max(radius, distance(solve_position(t[k]), centre));
        }
    }
    w_num[i] = vec2<f32>(radius, 0.0);
    workgroupBarrier();
    reduce(i, false);
    let radius_all = w_num[0].x;
    if i != 0u {
        return;
    }
    var margin = PI;
    if slack_all >= 0.0 && slack_all < 1.0 {
        margin = asin(slack_all);
    }
    var limit = spread_all + bitcast<f32>(params[6]) + bitcast<f32>(params[7]);
    let usable = dot(axis, axis) > 0.0 && spread_all < 0.5 * PI && finite(limit) && finite(radius_all);
    if !usable {
        limit = PI;
    }
    clusters[3u * cluster] = vec4<f32>(axis, limit);
    clusters[3u * cluster + 1u] = vec4<f32>(centre, radius_all);
    clusters[3u * cluster + 2u] = vec4<f32>(margin, 0.0, 0.0, 0.0);
}

// One render vertex's shading normal for the highlight draw: the search's normal of its
// welded vertex where the draw takes the set's normals (an abstraction, or a mesh
// without normals), else zero (the draw keeps the vertex buffer's own). Rust twin: the
// highlight pass's `surface_normals` over `HighlightSet::render_normals`.
@compute @workgroup_size(64)
fn cs_render_normals(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let r = invocation(gid, groups);
    if r >= params[2] {
        return;
    }
    var out = vec4<f32>(0.0);
    if diffuses() || !has_mesh_normals() {
        let n = solve_normal(render_to_welded[r]);
        if finite(n.x) && finite(n.y) && finite(n.z) {
            out = vec4<f32>(n, 1.0);
        }
    }
    render_normals[r] = out;
}
