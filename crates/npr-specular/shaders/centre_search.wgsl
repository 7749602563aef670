// The `N = H` search of Lee & Choi §3.1 on the GPU: one invocation per face solves
// Eq. (6) for the point where the interpolated normal (Eq. (4)) and half vector (Eq. (5))
// are parallel (Eq. (3)), refines it by Gauss–Newton on the normalised fields, and
// appends each accepted point to a compact list (an atomic counter: integer atomics only,
// as WebGPU has). The CPU reference is `npr_geometry::HighlightSearch::find`; each
// function below names its Rust twin in `npr_geometry::highlight` (`solve.rs`,
// `search.rs`). The CPU solves in `f64`; WGSL has no `f64`, so the tolerances that test
// for exact zeros in the CPU's form are set here to what `f32` resolves.
//
// A face whose cone of vertex normals cannot hold its half vectors is skipped before the
// solve (`in_cone`, the CPU's per-face rejection, conservative: it never drops a centre),
// and a whole cluster of faces whose cone cannot (`cluster_may_hold`): `cs_clusters`
// lists the others, and `cs_search` is dispatched indirectly over that list only.
// `cs_merge` then merges duplicates of one centre from neighbouring faces as the CPU
// does (`HighlightSearch::centres_from_solutions`): the list in the CPU's visiting order,
// then one pass over it, keeping the deeper of two solutions within the merge distance;
// and `cs_centres` computes each kept centre (`HighlightSearch::centre_at`): its point,
// normals, principal direction and curvatures, from the field it interpolates.

// One welded vertex (`npr_geometry::highlight::SolveVertex`): position, the normal the
// search solves on, and the columns of its shape operator S (object space).
struct SolveVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
    shape_x: vec4<f32>,
    shape_y: vec4<f32>,
    shape_z: vec4<f32>,
}

struct SearchParams {
    // The object's map to world space (kind 2: for the world-space half vector; every
    // kind: `cs_centres`).
    world_from_object: mat4x4<f32>,
    // kind 2: the transpose of its linear part (upper 3×3), taking H to object space.
    object_from_world_normal: mat4x4<f32>,
    // `cs_centres`: the inverse transpose of that linear part, taking normals to world
    // space.
    normal_world_from_object: mat4x4<f32>,
    // kind 1: object space; kind 2: world space.
    light: vec4<f32>,
    eye: vec4<f32>,
    // kind 0: the one half vector, object space.
    half_vector: vec4<f32>,
    // 0: constant H; 1: point light and eye in object space; 2: in world space.
    kind: u32,
    // 1: the curvature-blended normal field (`NormalInterpolation::Curvature`); 0: Eq. (4).
    curved: u32,
    face_count: u32,
    // Entries of `solutions`; faces past it are counted but not written.
    capacity: u32,
    // `ANGLE_MARGIN` of the CPU's rejection tests (radians).
    angle_margin: f32,
    // The device's `max_compute_workgroups_per_dimension`: the listed clusters' indirect
    // dispatch is folded into rows of this many workgroups.
    max_groups: u32,
    // `HighlightSearch::merge_distance` (object space).
    merge_distance: f32,
    // `cs_centres`: 1 / the transform's mean scale `|det|^(1/3)` (1 for a zero scale).
    inv_scale: f32,
    // `cs_centres`: 1 when the centre's normal is the field's (`NormalSource::Field`),
    // 0 for the mesh's interpolated normals first.
    field_normals: u32,
    // `cs_centres`: 1 when the normal transform is finite (else no centre, as the CPU).
    transform_ok: u32,
    // Peaks: σ of the bright regions (≤ 0: none looked for); 1 when the transform is a
    // similarity (`N·H` tested in object space, with the light and eye there).
    peak_sigma: f32,
    peak_similar: u32,
    // Peaks: the light and eye in world space and in object space (w = 1: positions,
    // w = 0: directions towards them).
    peak_light: vec4<f32>,
    peak_eye: vec4<f32>,
    peak_object_light: vec4<f32>,
    peak_object_eye: vec4<f32>,
}

struct Counter {
    found: atomic<u32>,
    // The centres `cs_merge` kept, or `NO_MERGE` when it could not merge the list.
    merged: u32,
    // The peaks `cs_peaks` appended after them, or `NO_MERGE` when it found none to give
    // (no merged list, too many, or a list of bright vertices that overflowed).
    peaks: u32,
}

// The indirect dispatch of `cs_search`, written by `cs_clusters`: one workgroup per
// listed cluster, folded into rows of `frame.params.max_groups` (x = at most that, y = rows,
// z = 1); `count` = the clusters listed.
struct Dispatch {
    x: atomic<u32>,
    y: atomic<u32>,
    z: u32,
    count: atomic<u32>,
}

// A run of `WORKGROUP` faces in Morton order (`ClusterRecord` in `search_clusters.rs`):
// the cone of its vertex normals (axis; w = the largest angle to one of them plus the
// fixed margin and a safety, ≥ π without a cone), the sphere holding its faces, and the
// largest curvature slack of its faces (x).
struct ClusterRecord {
    axis: vec4<f32>,
    sphere: vec4<f32>,
    margin: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> vertices: array<SolveVertex>;
// Per face: its three welded vertices, and the bits of its cone test's slack for the
// curvature-blended field (`HighlightSearch::face_margins`).
@group(0) @binding(1) var<storage, read> triangles: array<vec4<u32>>;
// The frame's counts and values in one storage buffer (not a uniform one: lavapipe
// inlines a uniform buffer's values into the shader and compiles it again whenever they
// change, which a moving object's transform does every frame: 230 ms a frame).
struct SearchFrame {
    counter: Counter,
    params: SearchParams,
}

@group(0) @binding(2) var<storage, read_write> frame: SearchFrame;
// Four parts of `frame.params.capacity` entries, then `MAX_MERGED`:
// - per accepted face: (face, α and β as bits, its slot in `order`), from `cs_search`;
// - `cs_merge`'s scratch: each entry's visiting rank (x);
// - the accepted faces in visiting order;
// - the merged list, as (face, α, β, slot), in the CPU's order.
@group(0) @binding(3) var<storage, read_write> solutions: array<vec4<u32>>;
// The face each invocation solves (`triangles` is stored in this order), slot -> (face,
// its place in the CPU's merge order: `HighlightSearch::visit_ranks`).
@group(0) @binding(5) var<storage, read> order: array<vec2<u32>>;
// One per run of `WORKGROUP` faces.
@group(0) @binding(6) var<storage, read> clusters: array<ClusterRecord>;
// The clusters `cs_clusters` kept, each as its index + 1, in no particular order; 0 past
// them (cleared every frame).
@group(0) @binding(7) var<storage, read_write> listed: array<u32>;
// `cs_clusters` only (a buffer the indirect dispatch reads may not be bound writable to it).
@group(1) @binding(0) var<storage, read_write> dispatch: Dispatch;

const WORKGROUP: u32 = 64u;
// Centres `cs_merge` keeps at most (`MAX_MERGED` of `search_pass.rs`), and its
// workgroup's size.
const MAX_MERGED: u32 = 256u;
const MERGE_WORKGROUP: u32 = 256u;
// `Counter::merged` when the list was not merged (it overflowed, or more than
// `MAX_MERGED` centres).
const NO_MERGE: u32 = 0xffffffffu;
// `BARYCENTRIC_EPSILON` and `RESIDUAL_TOLERANCE` of `solve.rs`.
const BARYCENTRIC_EPSILON: f32 = 1e-3;
const RESIDUAL_TOLERANCE: f32 = 1e-3;
// The rank test of `eq6` relative to the columns' size: 1e-12 in `f64`, here above
// `f32`'s rounding of `g11 g22 − g12²` (a few 1e-7), so a rank-deficient system (a
// face across which N − H changes along one direction only) is refused as on the CPU.
const RANK_TOLERANCE: f32 = 1e-5;
// Gauss–Newton's stopping steps (`gauss_newton`: 1e-12, 1e-14, 1e-13 in `f64`).
const RESIDUAL_FLOOR: f32 = 1e-7;
const JACOBIAN_TOLERANCE: f32 = 1e-7;
const STEP_FLOOR: f32 = 1e-7;

// `finite` and `try_normalize` are in npr-gpu's `numeric.wgsl`, composed before this file.

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if l > 0.0 && finite(l) {
        return v / l;
    }
    return vec3<f32>(0.0);
}

fn shape_of(v: SolveVertex) -> mat3x3<f32> {
    return mat3x3<f32>(v.shape_x.xyz, v.shape_y.xyz, v.shape_z.xyz);
}

// `test_vertices` (`search.rs`): the unit half vector at object point `p`, in object
// space; w = 0 where it is undefined.
fn half_vector_at(p: vec3<f32>) -> vec4<f32> {
    if frame.params.kind == 0u {
        return vec4<f32>(frame.params.half_vector.xyz, 1.0);
    }
    var q = p;
    if frame.params.kind == 2u {
        q = (frame.params.world_from_object * vec4<f32>(p, 1.0)).xyz;
    }
    let l = frame.params.light.xyz - q;
    let e = frame.params.eye.xyz - q;
    let s = l / length(l) + e / length(e);
    let sl = length(s);
    if !(sl > 1e-6) || !finite(sl) {
        return vec4<f32>(0.0);
    }
    var h = s / sl;
    if frame.params.kind == 2u {
        let m = frame.params.object_from_world_normal;
        h = normalize_or_zero(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz) * h);
        if all(h == vec3<f32>(0.0)) {
            return vec4<f32>(0.0);
        }
    }
    return vec4<f32>(h, 1.0);
}

// One face's data, positions relative to its vertex 0.
struct Face {
    n0: vec3<f32>,
    n1: vec3<f32>,
    n2: vec3<f32>,
    h0: vec3<f32>,
    h1: vec3<f32>,
    h2: vec3<f32>,
    dp1: vec3<f32>,
    dp2: vec3<f32>,
    s0: mat3x3<f32>,
    s1: mat3x3<f32>,
    s2: mat3x3<f32>,
}

// The normal field at (α, β) and its derivatives: `solve_normalised`'s linear field of
// Eq. (4), or `solve_curvature`'s blend of each vertex's first-order model
// `N_i + S_i (p − p_i)`.
struct Field {
    n: vec3<f32>,
    d1: vec3<f32>,
    d2: vec3<f32>,
}

fn field_at(f: Face, a: f32, b: f32) -> Field {
    let dn1 = f.n1 - f.n0;
    let dn2 = f.n2 - f.n0;
    if frame.params.curved == 0u {
        return Field(f.n0 + a * dn1 + b * dn2, dn1, dn2);
    }
    let w0 = 1.0 - a - b;
    let x = a * f.dp1 + b * f.dp2;
    let m0 = f.n0 + f.s0 * x;
    let m1 = f.n1 + f.s1 * (x - f.dp1);
    let m2 = f.n2 + f.s2 * (x - f.dp2);
    let blended = f.s0 * w0 + f.s1 * a + f.s2 * b;
    return Field(w0 * m0 + a * m1 + b * m2, m1 - m0 + blended * f.dp1, m2 - m0 + blended * f.dp2);
}

// `eq6`: least-squares (α, β) of Eq. (6) by pseudo-inverse; z = 0 for a rank-deficient
// system.
fn eq6(f: Face) -> vec3<f32> {
    let c1 = (f.n1 - f.n0) - (f.h1 - f.h0);
    let c2 = (f.n2 - f.n0) - (f.h2 - f.h0);
    let rhs = f.h0 - f.n0;
    let g11 = dot(c1, c1);
    let g12 = dot(c1, c2);
    let g22 = dot(c2, c2);
    let det = g11 * g22 - g12 * g12;
    if !(det > RANK_TOLERANCE * g11 * g22) || !(g11 * g22 > 1e-30) {
        return vec3<f32>(0.0);
    }
    let r1 = dot(c1, rhs);
    let r2 = dot(c2, rhs);
    let a = (g22 * r1 - g12 * r2) / det;
    let b = (g11 * r2 - g12 * r1) / det;
    if !finite(a) || !finite(b) {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(a, b, 1.0);
}

// `inside`: the ε test of §3.1.
fn inside(a: f32, b: f32) -> bool {
    let e = BARYCENTRIC_EPSILON;
    return a >= -e && b >= -e && a + b <= 1.0 + e && a <= 1.0 + e && b <= 1.0 + e;
}

// d(v/|v|) = (I − v̂v̂ᵀ) dv / |v|
fn unit_derivative(u: vec3<f32>, d: vec3<f32>, l: f32) -> vec3<f32> {
    return (d - u * dot(u, d)) / l;
}

// `gauss_newton`: from the Eq. (6) start, Gauss–Newton on N̂(α,β) − Ĥ(α,β) = 0; z = 1
// where the residual ends below `RESIDUAL_TOLERANCE` inside the face.
fn solve(f: Face) -> vec3<f32> {
    let start = eq6(f);
    var a = start.x;
    var b = start.y;
    if start.z == 0.0 || a < -0.5 || b < -0.5 || a + b > 1.5 {
        return vec3<f32>(0.0);
    }
    let dh1 = f.h1 - f.h0;
    let dh2 = f.h2 - f.h0;
    var res = 3.0e38;
    let iterations = select(6u, 10u, frame.params.curved == 1u);
    for (var i = 0u; i < iterations; i++) {
        let nf = field_at(f, a, b);
        let hv = f.h0 + a * dh1 + b * dh2;
        let ln = length(nf.n);
        let lh = length(hv);
        if !(ln > 1e-12 && lh > 1e-12) {
            return vec3<f32>(0.0);
        }
        let nn = nf.n / ln;
        let hn = hv / lh;
        let r = nn - hn;
        res = length(r);
        if res < RESIDUAL_FLOOR {
            break;
        }
        let j1 = unit_derivative(nn, nf.d1, ln) - unit_derivative(hn, dh1, lh);
        let j2 = unit_derivative(nn, nf.d2, ln) - unit_derivative(hn, dh2, lh);
        let g11 = dot(j1, j1);
        let g12 = dot(j1, j2);
        let g22 = dot(j2, j2);
        let det = g11 * g22 - g12 * g12;
        if !(det > JACOBIAN_TOLERANCE * g11 * g22) {
            break;
        }
        let r1 = dot(j1, r);
        let r2 = dot(j2, r);
        let da = -(g22 * r1 - g12 * r2) / det;
        let db = -(g11 * r2 - g12 * r1) / det;
        a += da;
        b += db;
        if !finite(a) || !finite(b) || abs(a) > 4.0 || abs(b) > 4.0 {
            return vec3<f32>(0.0);
        }
        if abs(da) + abs(db) < STEP_FLOOR {
            let nv = field_at(f, a, b).n;
            let hw = f.h0 + a * dh1 + b * dh2;
            res = length(normalize_or_zero(nv) - normalize_or_zero(hw));
            break;
        }
    }
    if res < RESIDUAL_TOLERANCE && inside(a, b) {
        return vec3<f32>(a, b, 1.0);
    }
    return vec3<f32>(0.0);
}

// `in_cone` (`search.rs`): whether the interpolated half vector can lie in the cone
// spanned by the vertex normals, with the slack of the largest chord from the averaged
// half vector to the vertices' and `margin`; a flat cone passes.
fn in_cone(f: Face, margin: f32) -> bool {
    let hb = normalize_or_zero(f.h0 + f.h1 + f.h2);
    if all(hb == vec3<f32>(0.0)) {
        return true;
    }
    let det = dot(cross(f.n0, f.n1), f.n2);
    if abs(det) < 1e-6 {
        return true;
    }
    let min_dot = min(1.0, min(dot(f.h0, hb), min(dot(f.h1, hb), dot(f.h2, hb))));
    let slack = sqrt(max(2.0 * (1.0 - min_dot), 0.0)) + margin;
    let s = sign(det);
    var n = array<vec3<f32>, 3>(f.n0, f.n1, f.n2);
    for (var k = 0u; k < 3u; k++) {
        let c = cross(n[k], n[(k + 1u) % 3u]);
        if s * dot(c, hb) < -length(c) * slack {
            return false;
        }
    }
    return true;
}

// Whether a cluster's faces can hold a point where N = H (conservative): H, over every
// point of the cluster, within its normal cone widened by the faces' slack. The CPU
// search's cluster rejection (`HighlightSearch::find`, step 0), which applies to
// directions (kind 0) and to positions in object space (kind 1, similarity maps); kind 2
// solves every cluster. For positions, H is taken at the sphere's centre: over the sphere
// (radius r) the unit directions to light and eye turn by at most 2r/d each, so their sum
// s moves by at most that and H by asin(|Δs| / |s|).
fn cluster_may_hold(c: ClusterRecord) -> bool {
    var limit = c.axis.w;
    if frame.params.curved == 1u {
        limit += c.margin.x;
    }
    if frame.params.kind == 2u || !(limit < 3.0) {
        return true;
    }
    var h = frame.params.half_vector.xyz;
    if frame.params.kind == 1u {
        let r = c.sphere.w;
        let l = frame.params.light.xyz - c.sphere.xyz;
        let e = frame.params.eye.xyz - c.sphere.xyz;
        let dl = length(l);
        let de = length(e);
        if !(dl > 2.0 * r) || !(de > 2.0 * r) {
            return true;
        }
        let s = l / dl + e / de;
        let sl = length(s);
        let ds = 2.0 * r / dl + 2.0 * r / de;
        if !(ds < 0.9 * sl) {
            return true;
        }
        h = s / sl;
        limit += asin(ds / sl);
        if !(limit < 3.0) {
            return true;
        }
    }
    return dot(h, c.axis.xyz) >= cos(limit);
}

// The clusters whose faces can hold N = H, one invocation per cluster: appended to
// `listed`, their count the workgroups of `cs_search`'s indirect dispatch.
@compute @workgroup_size(64)
fn cs_clusters(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let c = gid.x + gid.y * groups.x * WORKGROUP;
    if c == 0u {
        dispatch.z = 1u;
    }
    if c >= arrayLength(&clusters) || c * WORKGROUP >= frame.params.face_count {
        return;
    }
    if !cluster_may_hold(clusters[c]) {
        return;
    }
    let k = atomicAdd(&dispatch.count, 1u);
    listed[k] = c + 1u;
    let row = max(frame.params.max_groups, 1u);
    atomicMax(&dispatch.x, min(k + 1u, row));
    atomicMax(&dispatch.y, k / row + 1u);
}

// `search_vertices` with its per-face rejection (`HighlightSearch::find_exhaustive`), one
// face per invocation, one workgroup per cluster `cs_clusters` listed.
@compute @workgroup_size(64)
fn cs_search(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let k = wid.x + wid.y * max(frame.params.max_groups, 1u);
    // The last row's workgroups past the count find 0: no cluster.
    if k >= arrayLength(&listed) || listed[k] == 0u {
        return;
    }
    let at = (listed[k] - 1u) * WORKGROUP + lid;
    if at >= frame.params.face_count {
        return;
    }
    let face = order[at].x;
    let t = triangles[at];
    let nv = arrayLength(&vertices);
    if t.x >= nv || t.y >= nv || t.z >= nv {
        return;
    }
    let v0 = vertices[t.x];
    let v1 = vertices[t.y];
    let v2 = vertices[t.z];
    let h0 = half_vector_at(v0.position.xyz);
    let h1 = half_vector_at(v1.position.xyz);
    let h2 = half_vector_at(v2.position.xyz);
    if h0.w == 0.0 || h1.w == 0.0 || h2.w == 0.0 {
        return;
    }
    let f = Face(
        v0.normal.xyz, v1.normal.xyz, v2.normal.xyz,
        h0.xyz, h1.xyz, h2.xyz,
        v1.position.xyz - v0.position.xyz, v2.position.xyz - v0.position.xyz,
        shape_of(v0), shape_of(v1), shape_of(v2),
    );
    var margin = frame.params.angle_margin;
    if frame.params.curved == 1u {
        margin += bitcast<f32>(t.w);
    }
    if !in_cone(f, margin) {
        return;
    }
    let s = solve(f);
    if s.z == 0.0 {
        return;
    }
    let slot = atomicAdd(&frame.counter.found, 1u);
    if slot < frame.params.capacity {
        solutions[slot] = vec4<u32>(face, bitcast<u32>(s.x), bitcast<u32>(s.y), at);
    }
}

// `cs_merge`'s kept centres (lane 0 only): object-space point and depth inside its face
// (w), and the entry.
var<workgroup> kept_point: array<vec4<f32>, MAX_MERGED>;
var<workgroup> kept_entry: array<vec4<u32>, MAX_MERGED>;
var<workgroup> merge_count: u32;

// The object-space point of a solution entry and how deep inside its face it lies
// (`HighlightSearch::centre_at`'s position; `centres_from_solutions`'s `inner`).
fn solution_point(e: vec4<u32>) -> vec4<f32> {
    let t = triangles[e.w];
    let p0 = vertices[t.x].position.xyz;
    let p1 = vertices[t.y].position.xyz;
    let p2 = vertices[t.z].position.xyz;
    let a = bitcast<f32>(e.y);
    let b = bitcast<f32>(e.z);
    let p = p0 + a * (p1 - p0) + b * (p2 - p0);
    return vec4<f32>(p, min(min(a, b), 1.0 - a - b));
}

// `HighlightSearch::centres_from_solutions` on the list `cs_search` appended, one
// workgroup: the entries ordered by their face's visiting rank (each counts the ranks
// below its own, the ranks being a permutation), then lane 0 walks them in that order,
// each replacing the first kept centre within `merge_distance` when deeper inside its
// face, else dropped, or kept when none is that close (`HighlightSearch::merge`). The
// CPU leaves out, before merging, a face whose centre has no normal; here every accepted
// face takes part (a face the solve accepts has one).
@compute @workgroup_size(256)
fn cs_merge(@builtin(local_invocation_index) lid: u32) {
    // `frame` is read-write storage, so its values are not uniform: the count (or
    // `NO_MERGE` for an overflowed list) goes through workgroup memory, which makes it
    // uniform for the barriers below.
    let cap = frame.params.capacity;
    if lid == 0u {
        let found = atomicLoad(&frame.counter.found);
        merge_count = select(found, NO_MERGE, found > cap);
    }
    let n = workgroupUniformLoad(&merge_count);
    if n == NO_MERGE {
        if lid == 0u {
            frame.counter.merged = NO_MERGE;
        }
        return;
    }
    for (var i = lid; i < n; i += MERGE_WORKGROUP) {
        solutions[cap + i] = vec4<u32>(order[solutions[i].w].y, 0u, 0u, 0u);
    }
    storageBarrier();
    workgroupBarrier();
    for (var i = lid; i < n; i += MERGE_WORKGROUP) {
        let key = solutions[cap + i].x;
        var below = 0u;
        for (var j = 0u; j < n; j += 1u) {
            below += select(0u, 1u, solutions[cap + j].x < key);
        }
        solutions[2u * cap + below] = solutions[i];
    }
    storageBarrier();
    workgroupBarrier();
    if lid != 0u {
        return;
    }
    var kept = 0u;
    var overflow = false;
    for (var k = 0u; k < n; k += 1u) {
        let e = solutions[2u * cap + k];
        let c = solution_point(e);
        var matched = false;
        for (var m = 0u; m < kept; m += 1u) {
            if distance(kept_point[m].xyz, c.xyz) <= frame.params.merge_distance {
                if c.w > kept_point[m].w {
                    kept_point[m] = c;
                    kept_entry[m] = e;
                }
                matched = true;
                break;
            }
        }
        if !matched {
            if kept == MAX_MERGED {
                overflow = true;
                break;
            }
            kept_point[kept] = c;
            kept_entry[kept] = e;
            kept += 1u;
        }
    }
    for (var m = 0u; m < kept; m += 1u) {
        solutions[3u * cap + m] = kept_entry[m];
    }
    frame.counter.merged = select(kept, NO_MERGE, overflow);
}

// One welded vertex of the curvature field the centres interpolate, in `CurvaturePass`'s
// output layout: (normal, κmax), (dir κmax, κmin), (dir κmin, valid ? 1 : 0).
struct FieldVertex {
    normal_kmax: vec4<f32>,
    dir_kmin: vec4<f32>,
    dir_min_valid: vec4<f32>,
}

// `cs_centres` only, beside group 0's tables.
@group(1) @binding(1) var<storage, read> centre_field: array<FieldVertex>;
@group(1) @binding(2) var<storage, read_write> centres: array<CentreRecord>;

// `CurvatureField::interpolate`: the principal frame at (α, β) of triangle `t`, invalid
// vertices left out, directions flipped to agree with the first valid one. `ok` is 0
// where it has none.
struct Axes {
    normal: vec3<f32>,
    dir_kappa_max: vec3<f32>,
    kappa_max: f32,
    kappa_min: f32,
    ok: bool,
}

fn interpolate_axes(t: vec3<u32>, a: f32, b: f32) -> Axes {
    let w = vec3<f32>(1.0 - a - b, a, b);
    var n = vec3<f32>(0.0);
    var d = vec3<f32>(0.0);
    var kmax = 0.0;
    var kmin = 0.0;
    var wsum = 0.0;
    var d0 = vec3<f32>(0.0);
    var first = true;
    let nf = arrayLength(&centre_field);
    for (var k = 0u; k < 3u; k += 1u) {
        let i = t[k];
        if i >= nf || centre_field[i].dir_min_valid.w != 1.0 {
            continue;
        }
        let f = centre_field[i];
        var di = f.dir_kmin.xyz;
        if first {
            d0 = di;
            first = false;
        } else if dot(d0, di) < 0.0 {
            di = -di;
        }
        n += w[k] * f.normal_kmax.xyz;
        d += w[k] * di;
        kmax += w[k] * f.normal_kmax.w;
        kmin += w[k] * f.dir_kmin.w;
        wsum += w[k];
    }
    var out = Axes(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, false);
    let nn = try_normalize(n);
    if abs(wsum) < 1e-12 || nn.w == 0.0 {
        return out;
    }
    let dm = try_normalize(d - nn.xyz * dot(nn.xyz, d));
    out.normal = nn.xyz;
    out.dir_kappa_max = select(any_orthonormal(nn.xyz), dm.xyz, dm.w == 1.0);
    out.kappa_max = kmax / wsum;
    out.kappa_min = kmin / wsum;
    out.ok = true;
    return out;
}

// `HighlightSearch::centre_at` at (α, β) of `face` (its triangle at visiting `slot`):
// the point, its normals (the mesh's interpolated normal or the field's, as the search's
// `NormalSource` says), the principal direction in world space and the curvatures at the
// transform's scale; w of `position_object` 0 where the CPU has none. `solution` holds
// (face, α, β, slot).
fn centre_record(face: u32, slot: u32, a: f32, b: f32) -> CentreRecord {
    var r: CentreRecord;
    r.solution = vec4<u32>(face, bitcast<u32>(a), bitcast<u32>(b), slot);
    let t = triangles[slot].xyz;
    let nv = arrayLength(&vertices);
    if frame.params.transform_ok == 0u || t.x >= nv || t.y >= nv || t.z >= nv {
        return r;
    }
    let p0 = vertices[t.x].position.xyz;
    let p = p0 + a * (vertices[t.y].position.xyz - p0) + b * (vertices[t.z].position.xyz - p0);
    let axes = interpolate_axes(t, a, b);
    let w = vec3<f32>(1.0 - a - b, a, b);
    let solved = try_normalize(
        w.x * vertices[t.x].normal.xyz + w.y * vertices[t.y].normal.xyz + w.z * vertices[t.z].normal.xyz,
    );
    var n_obj = vec4<f32>(0.0);
    if frame.params.field_normals == 1u {
        n_obj = select(solved, vec4<f32>(axes.normal, 1.0), axes.ok);
    } else {
        n_obj = select(vec4<f32>(axes.normal, select(0.0, 1.0, axes.ok)), solved, solved.w == 1.0);
    }
    if n_obj.w == 0.0 {
        return r;
    }
    let nw = try_normalize((frame.params.normal_world_from_object * vec4<f32>(n_obj.xyz, 0.0)).xyz);
    if nw.w == 0.0 {
        return r;
    }
    let m = frame.params.world_from_object;
    let lin = mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz);
    var dmax = any_orthonormal(nw.xyz);
    var curv = vec2<f32>(0.0);
    if axes.ok {
        let d = lin * axes.dir_kappa_max;
        let dt = try_normalize(d - nw.xyz * dot(nw.xyz, d));
        dmax = select(dmax, dt.xyz, dt.w == 1.0);
        curv = vec2<f32>(axes.kappa_max, axes.kappa_min);
    }
    r.position_object = vec4<f32>(p, 1.0);
    r.position_world = vec4<f32>((m * vec4<f32>(p, 1.0)).xyz, 1.0);
    r.normal_object = vec4<f32>(n_obj.xyz, 0.0);
    r.normal_world = vec4<f32>(nw.xyz, 0.0);
    r.dir_kappa_max = vec4<f32>(dmax, 0.0);
    r.curvature = vec4<f32>(curv * frame.params.inv_scale, 0.0, 0.0);
    return r;
}

// The last frame's highlights (a table, `highlight_table.wgsl`) placed again on this
// frame's pose and transform at their faces and barycentrics (`HighlightSearch::centre_at`,
// as `match_centres` places a highlight it lost), after the search's centres:
// `centres[MAX_MERGED + i]`. A record the CPU placed already (slot `NONE`), or one with no
// frame here (the CPU keeps the old centre then), stays as the table holds it.
@group(1) @binding(5) var<storage, read> replace_table: TrackData;

@compute @workgroup_size(64)
fn cs_replace(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= min(replace_table.params.count, MAX_MERGED) {
        return;
    }
    let old = replace_table.previous[i].centre;
    var r = old;
    if old.solution.w != 0xffffffffu {
        let placed = centre_record(old.solution.x, old.solution.w, bitcast<f32>(old.solution.y), bitcast<f32>(old.solution.z));
        if placed.position_object.w == 1.0 {
            r = placed;
            r.curvature.z = old.curvature.z;
        }
    }
    centres[MAX_MERGED + i] = r;
}

// `HighlightSearch::centre_at` for each centre `cs_merge` kept, one invocation each.
@compute @workgroup_size(64)
fn cs_centres(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    let kept = frame.counter.merged;
    if kept == NO_MERGE || k >= kept || k >= MAX_MERGED {
        return;
    }
    let e = solutions[3u * frame.params.capacity + k];
    centres[k] = centre_record(e.x, e.w, bitcast<f32>(e.y), bitcast<f32>(e.z));
}

// ---- Peaks: bright regions without an `N = H` point (`set::peaks` of the crate) ----
//
// `cs_bright` marks the vertices with `N·H ≥ σ` (`bright_vertices`); `cs_join_bright`
// joins the bright vertices that share a face into parts (a union-find over the
// vertices, each part's root its lowest vertex, joined by compare-and-swap, so any
// number of workgroups may join at once); `cs_part_best` and `cs_part_brightest` find
// each part's brightest vertex (the lowest index on ties) and list the roots; `cs_peaks`
// (one invocation) leaves out the parts that hold an `N = H` centre, and each other
// part's brightest vertex is a peak, the parts in order of their lowest vertex, its
// centre at the maximum of `N̂·Ĥ` over the faces around it (`centre_at_vertex`, by
// `ascend`), appended to `centres` after the merged ones (`curvature.z` = 1) and
// counted in `Counter::peaks`.

// The vertices' neighbours and faces: `nv + 1` offsets into this array, the neighbours,
// then `nv + 1` offsets (the first at `peak_adjacency[nv]`) and, per face around a
// vertex in the order of `Topology::vertex_faces`, (face, slot | corner << 29).
@group(1) @binding(3) var<storage, read> peak_adjacency: array<u32>;

// The peaks' scratch (cleared every frame but `list_room`): the parts' roots listed,
// whether the list overflowed, the list's room; per vertex its `N·H` bits where bright
// (0 where not), its parent in the union-find (the parent + 1; 0: a root), its part's
// greatest `N·H` bits (at the root) and its part's brightest vertex (complemented, at the
// root); then the roots' list.
struct PeakScratch {
    listed: atomic<u32>,
    overflowed: atomic<u32>,
    list_room: u32,
    pad: u32,
    data: array<atomic<u32>>,
}
@group(1) @binding(4) var<storage, read_write> peak_scratch: PeakScratch;

// Not a peak: `curvature.z` of a merged centre; a peak's is 1.
const PEAK: f32 = 1.0;

// glam's `LightEye::half_vector` at `p` for light and eye `l`, `e` (w = 1: positions,
// w = 0: directions towards them).
fn half_at(p: vec3<f32>, l: vec4<f32>, e: vec4<f32>) -> vec3<f32> {
    var a = l.xyz;
    var b = e.xyz;
    if l.w == 1.0 {
        a = l.xyz - p;
        b = e.xyz - p;
    }
    return try_normalize(try_normalize(a).xyz + try_normalize(b).xyz).xyz;
}

// The vertex's `N·H` and the unit normal and half vector that give it: in object space
// under a similarity (angles kept), else in world space (`bright_vertices`).
fn vertex_nh(v: u32) -> f32 {
    let q = vertices[v];
    var n = vec3<f32>(0.0);
    var h = vec3<f32>(0.0);
    if frame.params.peak_similar == 1u {
        n = try_normalize(q.normal.xyz).xyz;
        h = half_at(q.position.xyz, frame.params.peak_object_light, frame.params.peak_object_eye);
    } else {
        n = try_normalize((frame.params.normal_world_from_object * vec4<f32>(q.normal.xyz, 0.0)).xyz).xyz;
        let p = (frame.params.world_from_object * vec4<f32>(q.position.xyz, 1.0)).xyz;
        h = half_at(p, frame.params.peak_light, frame.params.peak_eye);
    }
    let zero = vec3<f32>(0.0);
    if all(n == zero) || all(h == zero) {
        return -2.0;
    }
    return dot(n, h);
}

fn peak_vertex(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * 64u;
}

// Vertex `v`'s `N·H` bits (0: not bright).
fn bright_bits(v: u32) -> u32 {
    return atomicLoad(&peak_scratch.data[v]);
}

// The root of `v`'s part, halving the path on the way (a vertex that has a parent is
// never joined again, so any ancestor may stand for its parent).
fn part_root(v0: u32) -> u32 {
    let nv = arrayLength(&vertices);
    var v = v0;
    loop {
        let p = atomicLoad(&peak_scratch.data[nv + v]);
        if p == 0u {
            return v;
        }
        let gp = atomicLoad(&peak_scratch.data[nv + p - 1u]);
        if gp != 0u {
            atomicStore(&peak_scratch.data[nv + v], gp);
        }
        v = p - 1u;
    }
    return v;
}

@compute @workgroup_size(64)
fn cs_bright(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = peak_vertex(gid, groups);
    if v >= arrayLength(&vertices) {
        return;
    }
    let d = vertex_nh(v);
    if d >= frame.params.peak_sigma {
        atomicStore(&peak_scratch.data[v], bitcast<u32>(d));
    }
}

// Joins each bright vertex with its bright neighbours above it: the greater root hung
// under the lesser, by compare-and-swap (tried again where another join moved it).
@compute @workgroup_size(64)
fn cs_join_bright(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = peak_vertex(gid, groups);
    let nv = arrayLength(&vertices);
    if v >= nv || bright_bits(v) == 0u {
        return;
    }
    for (var k = peak_adjacency[v]; k < peak_adjacency[v + 1u]; k += 1u) {
        let u = peak_adjacency[k];
        if u <= v || bright_bits(u) == 0u {
            continue;
        }
        loop {
            let a = part_root(v);
            let b = part_root(u);
            if a == b {
                break;
            }
            let hi = max(a, b);
            let lo = min(a, b);
            let r = atomicCompareExchangeWeak(&peak_scratch.data[nv + hi], 0u, lo + 1u);
            if r.exchanged {
                break;
            }
        }
    }
}

// This invocation's vertex, its `N·H` bits (0: none or not bright) and its part's root.
fn bright_part(gid: vec3<u32>, groups: vec3<u32>) -> vec3<u32> {
    let v = peak_vertex(gid, groups);
    if v >= arrayLength(&vertices) {
        return vec3<u32>(v, 0u, 0u);
    }
    let d = bright_bits(v);
    if d == 0u {
        return vec3<u32>(v, 0u, 0u);
    }
    return vec3<u32>(v, d, part_root(v));
}

// Each part's greatest `N·H` at its root, and the roots listed.
@compute @workgroup_size(64)
fn cs_part_best(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let b = bright_part(gid, groups);
    let v = b.x;
    let d = b.y;
    let r = b.z;
    let nv = arrayLength(&vertices);
    if d == 0u {
        return;
    }
    atomicMax(&peak_scratch.data[2u * nv + r], d);
    if r == v {
        let k = atomicAdd(&peak_scratch.listed, 1u);
        if k < peak_scratch.list_room {
            atomicStore(&peak_scratch.data[4u * nv + k], v);
        } else {
            atomicStore(&peak_scratch.overflowed, 1u);
        }
    }
}

// Each part's brightest vertex, the lowest on ties (its complement's maximum).
@compute @workgroup_size(64)
fn cs_part_brightest(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let b = bright_part(gid, groups);
    let v = b.x;
    let d = b.y;
    let r = b.z;
    let nv = arrayLength(&vertices);
    if d == 0u {
        return;
    }
    if atomicLoad(&peak_scratch.data[2u * nv + r]) == d {
        atomicMax(&peak_scratch.data[3u * nv + r], ~v);
    }
}

// `centre_at_vertex`'s `value`: `N̂·Ĥ` at (α, β) of a face, both interpolated linearly
// from its corners' world normals and half vectors.
fn peak_value(n: array<vec3<f32>, 3>, h: array<vec3<f32>, 3>, a: f32, b: f32) -> f32 {
    let nn = n[0] + a * (n[1] - n[0]) + b * (n[2] - n[0]);
    let hh = h[0] + a * (h[1] - h[0]) + b * (h[2] - h[0]);
    return dot(try_normalize(nn).xyz, try_normalize(hh).xyz);
}

// `ascend`'s projection onto the triangle (α, β ≥ 0, α + β ≤ 1).
fn onto_triangle(a0: f32, b0: f32) -> vec2<f32> {
    let a = max(a0, 0.0);
    let b = max(b0, 0.0);
    let over = a + b - 1.0;
    if over > 0.0 {
        return vec2<f32>(clamp(a - 0.5 * over, 0.0, 1.0), clamp(b - 0.5 * over, 0.0, 1.0));
    }
    return vec2<f32>(a, b);
}

// `ascend`: the point of the face where `peak_value` is largest, by projected gradient
// ascent from `start` (central differences, the step halved when it does not climb);
// (α, β, value).
fn ascend(n: array<vec3<f32>, 3>, h: array<vec3<f32>, 3>, start: vec2<f32>) -> vec3<f32> {
    var a = start.x;
    var b = start.y;
    var g = peak_value(n, h, a, b);
    var step = 0.25;
    let e = 1e-3;
    for (var i = 0; i < 40; i += 1) {
        let da = peak_value(n, h, a + e, b) - peak_value(n, h, a - e, b);
        let db = peak_value(n, h, a, b + e) - peak_value(n, h, a, b - e);
        let len = sqrt(da * da + db * db);
        if !finite(len) || len <= 1e-9 || step < 1e-4 {
            break;
        }
        let q = onto_triangle(a + step * da / len, b + step * db / len);
        let ng = peak_value(n, h, q.x, q.y);
        if ng > g {
            a = q.x;
            b = q.y;
            g = ng;
        } else {
            step *= 0.5;
        }
    }
    return vec3<f32>(a, b, g);
}

// `centre_at_vertex`: the centre at the largest `N̂·Ĥ` over the faces around `v`
// (those of zero area left out), the first face on ties.
fn peak_centre(v: u32) -> CentreRecord {
    let nv = arrayLength(&vertices);
    let faces_at = peak_adjacency[nv];
    var found = false;
    var best = vec3<f32>(0.0);
    var best_face = 0u;
    var best_slot = 0u;
    for (var k = peak_adjacency[faces_at + v]; k < peak_adjacency[faces_at + v + 1u]; k += 2u) {
        let face = peak_adjacency[k];
        let word = peak_adjacency[k + 1u];
        let slot = word & 0x1fffffffu;
        let corner = (word >> 29u) & 3u;
        let t = triangles[slot].xyz;
        // A face of zero area in this pose (`Topology::is_degenerate`) is left out.
        let p0 = vertices[t.x].position.xyz;
        if all(cross(vertices[t.y].position.xyz - p0, vertices[t.z].position.xyz - p0) == vec3<f32>(0.0)) {
            continue;
        }
        var n: array<vec3<f32>, 3>;
        var h: array<vec3<f32>, 3>;
        for (var c = 0u; c < 3u; c += 1u) {
            let q = vertices[t[c]];
            n[c] = try_normalize((frame.params.normal_world_from_object * vec4<f32>(q.normal.xyz, 0.0)).xyz).xyz;
            let p = (frame.params.world_from_object * vec4<f32>(q.position.xyz, 1.0)).xyz;
            h[c] = half_at(p, frame.params.peak_light, frame.params.peak_eye);
        }
        var start = vec2<f32>(0.0, 0.0);
        if corner == 1u {
            start = vec2<f32>(1.0, 0.0);
        } else if corner == 2u {
            start = vec2<f32>(0.0, 1.0);
        }
        let r = ascend(n, h, start);
        if !found || r.z > best.z {
            found = true;
            best = r;
            best_face = face;
            best_slot = slot;
        }
    }
    var r: CentreRecord;
    if found {
        r = centre_record(best_face, best_slot, best.x, best.y);
        r.curvature.z = PEAK;
    }
    return r;
}

// The parts found (lowest vertex, brightest vertex), at most `MAX_MERGED`.
var<private> parts: array<vec2<u32>, MAX_MERGED>;

// A part's greatest `N·H` once `cs_peaks` has found an `N = H` centre in it.
const HOLDS_CENTRE: u32 = 0xffffffffu;

@compute @workgroup_size(1)
fn cs_peaks() {
    let merged = frame.counter.merged;
    let nv = arrayLength(&vertices);
    let listed = atomicLoad(&peak_scratch.listed);
    if merged == NO_MERGE || atomicLoad(&peak_scratch.overflowed) != 0u || frame.params.peak_sigma <= 0.0 {
        frame.counter.peaks = NO_MERGE;
        return;
    }
    if frame.params.transform_ok == 0u {
        frame.counter.peaks = 0u;
        return;
    }
    // The parts an `N = H` centre lies in (through its face's bright vertices) need no
    // peak.
    for (var k = 0u; k < merged; k += 1u) {
        let c = centres[k];
        if c.position_object.w != 1.0 {
            continue;
        }
        let t = triangles[c.solution.w].xyz;
        for (var i = 0u; i < 3u; i += 1u) {
            let v = t[i];
            if v < nv && bright_bits(v) != 0u {
                atomicStore(&peak_scratch.data[2u * nv + part_root(v)], HOLDS_CENTRE);
            }
        }
    }
    var count = 0u;
    for (var i = 0u; i < min(listed, peak_scratch.list_room); i += 1u) {
        let root = atomicLoad(&peak_scratch.data[4u * nv + i]);
        if atomicLoad(&peak_scratch.data[2u * nv + root]) == HOLDS_CENTRE {
            continue;
        }
        if count + merged == MAX_MERGED {
            frame.counter.peaks = NO_MERGE;
            return;
        }
        parts[count] = vec2<u32>(root, ~atomicLoad(&peak_scratch.data[3u * nv + root]));
        count += 1u;
    }
    // In order of their lowest vertex (insertion sort: a frame has few).
    for (var i = 1u; i < count; i += 1u) {
        let p = parts[i];
        var j = i;
        while j > 0u && parts[j - 1u].x > p.x {
            parts[j] = parts[j - 1u];
            j -= 1u;
        }
        parts[j] = p;
    }
    var n = 0u;
    for (var i = 0u; i < count; i += 1u) {
        let r = peak_centre(parts[i].y);
        if r.position_object.w == 1.0 {
            centres[merged + n] = r;
            n += 1u;
        }
    }
    frame.counter.peaks = n;
}
