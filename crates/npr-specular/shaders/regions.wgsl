// The regions `N·H ≥ σ` a highlight stylizes (beyond Lee & Choi: §3.3 sizes the projector
// from κ at the centre, Eq. (8)), grown over the mesh from each centre's face and fitted
// with the ellipse of the same area moments, on the GPU. The CPU reference is
// `crate::region::RegionGrower::grow_all` face by face; each function below names its
// Rust twin in `crate::region` (`measure.rs`, `classify.rs`, `fit.rs`, `grow.rs`).
//
// The CPU grows every seed at once in one breadth-first queue, so a face goes to the seed
// that reaches it in fewest steps, the lower seed on a tie (the queue holds each level in
// seed order), and a face one seed reached is closed to the others whether that seed
// took it or not. Here each seed is first walked by a workgroup of its own, level by
// level (`cs_grow`), and marks every face it takes with `(steps, seed)`; where two walks
// reach one face both are marked met (`claim`). Walks that met no other are the CPU's
// (a walk among others reaches only faces it reaches alone, so no one else's walk came
// near theirs). The seeds that met are then walked again together by one workgroup
// (`cs_join`), level by level, each face going to the least `(steps, seed)` that reached
// it, as the CPU's queue gives it. `cs_fit` then sums, per
// seed, the moments of the faces it won (each workgroup reduces its own: WebGPU has no
// float atomics), fits the ellipse and the scale of it that fits the region best (radial
// bins in fixed point, integer atomics). Nothing mesh-sized is read back: one `RegionFit`
// per seed.

// One welded vertex: object-space position and the unit normal the regions use.
struct RegionVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
}

// One face: vertices (w: 1 when degenerate) and its object-space face normal.
struct RegionFace {
    tri: vec4<u32>,
    normal: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> frame_data: RegionFrameData;
@group(0) @binding(2) var<storage, read> vertices: array<RegionVertex>;
@group(0) @binding(3) var<storage, read> faces: array<RegionFace>;
// Face adjacency: `face_count + 1` offsets, then the neighbour list.
@group(0) @binding(4) var<storage, read> adjacency: array<u32>;
@group(0) @binding(5) var<storage, read_write> visited: array<atomic<u32>>;
// Per face the complement of the least `(steps << SEED_BITS) | seed` that took it (0:
// none).
@group(0) @binding(6) var<storage, read_write> owner: array<atomic<u32>>;
// Per seed `capacity` entries: (face, steps) of each face it took.
@group(0) @binding(7) var<storage, read_write> work: array<vec2<u32>>;
@group(0) @binding(8) var<storage, read_write> fits: array<RegionFit>;

const WORKGROUP: u32 = 256u;
const SEED_BITS: u32 = 12u;
// `classify::SUB`, `EXACT_H_TURN`, `LINEAR_TOLERANCE`.
const SUB: u32 = 4u;
const EXACT_H_TURN: f32 = 0.05;
const LINEAR_TOLERANCE: f32 = 0.05;
const INFINITE: f32 = 3.0e38;

var<workgroup> wg_tail: atomic<u32>;
var<workgroup> wg_overflow: atomic<u32>;
var<workgroup> wg_level_end: u32;
// `cs_fit`'s reduction: area, first (2), second (3), faces, the positive areas; the cone
// apart (a minimum); the seed's fit once written; the overlap scale's radial bins.
var<workgroup> wg_sum: array<array<f32, 8>, 256>;
var<workgroup> wg_cone: array<f32, 256>;
var<workgroup> wg_fitted: RegionFit;
// The overlap scale's radial bins (the first 128), or the cut's bins along the axis.
var<workgroup> wg_bins: array<atomic<u32>, 1024>;
// The won faces' range along the cut's axis (ordered bits: least, greatest).
var<workgroup> wg_range: array<atomic<u32>, 2>;
// Per cut: the bin along the axis the piece before it ends in, the area of the bins
// before that one, and the running area at which the piece closes; then the won faces
// of those bins (`CUT_LIST` at most, kept in `wg_bins`, four words each), which are
// ordered one by one as `split_bent` orders them.
var<workgroup> wg_cuts: array<u32, 6>;
var<workgroup> wg_cut_before: array<f32, 6>;
var<workgroup> wg_cut_target: array<f32, 6>;
var<workgroup> wg_list_len: atomic<u32>;

// `finite` and `atan2_reduced` are in npr-gpu's `numeric.wgsl`, composed before this file.

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if l > 0.0 && finite(1.0 / l) {
        return v / l;
    }
    return vec3<f32>(0.0);
}

// `LightEye::half_vector`.
fn half_vector(p: vec3<f32>) -> vec3<f32> {
    if frame_data.params.light.w == 0.0 {
        return normalize_or_zero(normalize_or_zero(frame_data.params.light.xyz) + normalize_or_zero(frame_data.params.eye.xyz));
    }
    return normalize_or_zero(normalize_or_zero(frame_data.params.light.xyz - p) + normalize_or_zero(frame_data.params.eye.xyz - p));
}

// A vertex's values this frame (`measure::VertexCache`).
struct Values {
    world: vec3<f32>,
    normal: vec3<f32>,
    h: vec3<f32>,
    // Distances to the light and the eye and |L̂ + V̂| (zero for directions).
    dist: vec3<f32>,
    nh: f32,
}

// `RegionGrower::compute_vertex`.
fn vertex_values(v: u32) -> Values {
    var out: Values;
    let r = vertices[v];
    let p = (frame_data.params.world_from_object * vec4<f32>(r.position.xyz, 1.0)).xyz;
    out.world = p;
    out.normal = normalize_or_zero((frame_data.params.normal_from_object * vec4<f32>(r.normal.xyz, 0.0)).xyz);
    out.dist = vec3<f32>(0.0);
    if frame_data.params.light.w != 0.0 {
        let l = frame_data.params.light.xyz - p;
        let e = frame_data.params.eye.xyz - p;
        let dl = length(l);
        let de = length(e);
        let s = l / dl + e / de;
        let ds = length(s);
        if dl > 0.0 && de > 0.0 && ds > 0.0 && finite(ds) {
            out.h = s / ds;
        } else {
            out.h = half_vector(p);
        }
        out.dist = vec3<f32>(dl, de, ds);
    } else {
        out.h = half_vector(p);
    }
    let nh = dot(out.normal, out.h);
    out.nh = select(-1.0, nh, finite(nh));
    return out;
}

// Area moments of a planar region (`fit::Moments`): area, first (x, y), second (xx, xy,
// yy).
struct Moments {
    area: f32,
    first: vec2<f32>,
    second: vec3<f32>,
}

// `Moments::add_triangle` (functions return the sum: naga's SPIR-V writer fails on a
// pointer to a struct's member passed to a function).
fn add_triangle(m_in: Moments, a: vec2<f32>, b: vec2<f32>, c: vec2<f32>) -> Moments {
    var m = m_in;
    let ab = b - a;
    let ac = c - a;
    let area = 0.5 * (ab.x * ac.y - ab.y * ac.x);
    let s = a + b + c;
    m.area += area;
    m.first += area * s / 3.0;
    let k = area / 12.0;
    m.second += k * vec3<f32>(
        a.x * a.x + b.x * b.x + c.x * c.x + s.x * s.x,
        a.x * a.y + b.x * b.y + c.x * c.y + s.x * s.y,
        a.y * a.y + b.y * b.y + c.y * c.y + s.y * s.y,
    );
    return m;
}

// `Moments::add_clipped`: the part of the triangle (plane point xy, value z) where the
// linear interpolant of the values is ≥ 0.
fn add_clipped(m_in: Moments, t0: vec3<f32>, t1: vec3<f32>, t2: vec3<f32>) -> Moments {
    var m = m_in;
    var tri = array<vec3<f32>, 3>(t0, t1, t2);
    var poly: array<vec2<f32>, 4>;
    var len = 0u;
    for (var k = 0u; k < 3u; k++) {
        let p = tri[k];
        let q = tri[(k + 1u) % 3u];
        if p.z >= 0.0 {
            poly[len] = p.xy;
            len += 1u;
        }
        if (p.z >= 0.0) != (q.z >= 0.0) && len < 4u {
            let t = p.z / (p.z - q.z);
            poly[len] = p.xy + (q.xy - p.xy) * t;
            len += 1u;
        }
    }
    for (var k = 1u; k + 1u < len; k++) {
        m = add_triangle(m, poly[0], poly[k], poly[k + 1u]);
    }
    return m;
}

// Index of sub-grid point (i, j) (`classify::grid_index`).
fn grid_index(steps: u32, i: u32, j: u32) -> u32 {
    return i * (2u * steps + 3u - i) / 2u + j;
}

// One face measured against a seed's region (`RegionGrower::measure`).
struct Measured {
    taken: bool,
    m: Moments,
    cone: f32,
}

// `classify::classify`: 0 outside, 1 inside, 2 linear, else the sub-grid's steps + 8
// (with `delta` in `*delta`).
fn classify(vs: array<Values, 3>, reach: f32, sigma: f32, delta_out: ptr<function, f32>) -> u32 {
    let lo = min(min(vs[0].nh, vs[1].nh), vs[2].nh);
    let hi = max(max(vs[0].nh, vs[1].nh), vs[2].nh);
    var delta = 0.0;
    if frame_data.params.light.w != 0.0 {
        let r = reach;
        let d0 = min(min(vs[0].dist.x, vs[1].dist.x), vs[2].dist.x);
        let d1 = min(min(vs[0].dist.y, vs[1].dist.y), vs[2].dist.y);
        let s = min(min(vs[0].dist.z, vs[1].dist.z), vs[2].dist.z);
        let ds = select(2.0, r / (d0 - r), d0 > 2.0 * r) + select(2.0, r / (d1 - r), d1 > 2.0 * r);
        delta = select(2.0, ds / (s - ds), s - ds > 1e-3);
    }
    *delta_out = delta;
    let finest = 8u + SUB;
    if !finite(delta) || !finite(lo) || !finite(hi) {
        *delta_out = INFINITE;
        return finest;
    }
    if sigma >= 0.0 && lo - delta >= sigma {
        return 1u;
    }
    let c = min(min(dot(vs[0].normal, vs[1].normal), dot(vs[1].normal, vs[2].normal)), dot(vs[2].normal, vs[0].normal));
    if !(c > 0.0) {
        return finest;
    }
    let eps = 1.0 / sqrt((1.0 + 2.0 * c) / 3.0) - 1.0
        + delta * (sqrt(max(2.0 * (1.0 - c), 0.0)) + 2.0 * delta);
    if hi + eps < sigma {
        return 0u;
    }
    if eps <= LINEAR_TOLERANCE * (hi - lo) {
        return 2u;
    }
    let need = sqrt(eps / max(LINEAR_TOLERANCE * (hi - lo), 1.17549435e-38));
    if need <= 2.0 {
        return 8u + 2u;
    }
    if need <= 3.0 {
        return 8u + 3u;
    }
    return finest;
}

// `b`ᵀ m `b` of a symmetric 3×3 given by rows.
fn quad(m: mat3x3<f32>, b: vec3<f32>) -> f32 {
    return dot(b, m * b);
}

// `measure::sample_sub_grid`.
fn sample_sub_grid(vs: array<Values, 3>, qs: array<vec2<f32>, 3>, s: Seed, steps: u32, delta: f32) -> Measured {
    var out: Measured;
    let axis = s.n.xyz;
    let sigma = s.origin.w;
    let exact_h = delta > EXACT_H_TURN;
    let n0 = vs[0].normal;
    let n1 = vs[1].normal;
    let n2 = vs[2].normal;
    // Columns of the matrices whose rows are Nᵢ·Hⱼ and Nᵢ·Nⱼ (symmetric for the second).
    let nh = transpose(mat3x3<f32>(
        vec3<f32>(dot(n0, vs[0].h), dot(n0, vs[1].h), dot(n0, vs[2].h)),
        vec3<f32>(dot(n1, vs[0].h), dot(n1, vs[1].h), dot(n1, vs[2].h)),
        vec3<f32>(dot(n2, vs[0].h), dot(n2, vs[1].h), dot(n2, vs[2].h)),
    ));
    let nn = mat3x3<f32>(
        vec3<f32>(dot(n0, n0), dot(n0, n1), dot(n2, n0)),
        vec3<f32>(dot(n0, n1), dot(n1, n1), dot(n1, n2)),
        vec3<f32>(dot(n2, n0), dot(n1, n2), dot(n2, n2)),
    );
    let na = vec3<f32>(dot(n0, axis), dot(n1, axis), dot(n2, axis));
    var grid: array<vec3<f32>, 15>;
    var hit = false;
    var cone = 1.0;
    let inv = 1.0 / f32(steps);
    for (var i = 0u; i <= steps; i++) {
        for (var j = 0u; j + i <= steps; j++) {
            let b1 = f32(i) * inv;
            let b2 = f32(j) * inv;
            let b = vec3<f32>(1.0 - b1 - b2, b1, b2);
            let len2 = quad(nn, b);
            let inv_len = select(0.0, 1.0 / sqrt(len2), len2 > 0.0);
            var d = 0.0;
            if exact_h {
                let p = vs[0].world * b.x + vs[1].world * b.y + vs[2].world * b.z;
                let u = n0 * b.x + n1 * b.y + n2 * b.z;
                d = dot(u, half_vector(p)) * inv_len - sigma;
            } else {
                d = quad(nh, b) * inv_len - sigma;
            }
            d = select(-1.0, d, finite(d));
            if d >= 0.0 {
                hit = true;
                cone = min(cone, dot(b, na) * inv_len);
            }
            grid[grid_index(steps, i, j)] = vec3<f32>(qs[0] * b.x + qs[1] * b.y + qs[2] * b.z, d);
        }
    }
    if !hit {
        return out;
    }
    // `classify::for_sub_triangles`.
    for (var i = 0u; i < steps; i++) {
        for (var j = 0u; j + i < steps; j++) {
            let a = grid_index(steps, i, j);
            let b = grid_index(steps, i + 1u, j);
            let c = grid_index(steps, i, j + 1u);
            out.m = add_clipped(out.m, grid[a], grid[b], grid[c]);
            if i + j + 1u < steps {
                out.m = add_clipped(out.m, grid[b], grid[grid_index(steps, i + 1u, j + 1u)], grid[c]);
            }
        }
    }
    out.taken = true;
    out.cone = cone;
    return out;
}

// `RegionGrower::measure`: face `fi` against seed `s`'s region.
fn measure(fi: u32, s: Seed) -> Measured {
    var out: Measured;
    let face = faces[fi];
    let axis = s.n.xyz;
    if face.tri.w != 0u || dot((frame_data.params.normal_from_object * vec4<f32>(face.normal.xyz, 0.0)).xyz, axis) <= 0.0 {
        return out;
    }
    let vs = array<Values, 3>(vertex_values(face.tri.x), vertex_values(face.tri.y), vertex_values(face.tri.z));
    let sigma = s.origin.w;
    let q0 = vs[0].world - s.origin.xyz;
    let q1 = vs[1].world - s.origin.xyz;
    let q2 = vs[2].world - s.origin.xyz;
    let qs = array<vec2<f32>, 3>(
        vec2<f32>(dot(q0, s.e_u.xyz), dot(q0, s.e_v.xyz)),
        vec2<f32>(dot(q1, s.e_u.xyz), dot(q1, s.e_v.xyz)),
        vec2<f32>(dot(q2, s.e_u.xyz), dot(q2, s.e_v.xyz)),
    );
    let e0 = vs[0].world - vs[1].world;
    let e1 = vs[1].world - vs[2].world;
    let e2 = vs[2].world - vs[0].world;
    let reach = sqrt(max(max(dot(e0, e0), dot(e1, e1)), dot(e2, e2)));
    var delta = 0.0;
    let kind = classify(vs, reach, sigma, &delta);
    let vertex_cone = min(min(dot(vs[0].normal, axis), dot(vs[1].normal, axis)), dot(vs[2].normal, axis));
    if kind == 0u {
        return out;
    }
    if kind == 1u {
        out.m = add_triangle(out.m, qs[0], qs[1], qs[2]);
        out.taken = true;
        out.cone = vertex_cone;
        return out;
    }
    if kind == 2u {
        let t0 = vec3<f32>(qs[0], vs[0].nh - sigma);
        let t1 = vec3<f32>(qs[1], vs[1].nh - sigma);
        let t2 = vec3<f32>(qs[2], vs[2].nh - sigma);
        if t0.z < 0.0 && t1.z < 0.0 && t2.z < 0.0 {
            return out;
        }
        out.m = add_clipped(out.m, t0, t1, t2);
        out.taken = true;
        out.cone = vertex_cone;
        return out;
    }
    return sample_sub_grid(vs, qs, s, kind - 8u, delta);
}

// `visited` holds per face a word the walks that reach it meet in (`cs_grow`: the
// greatest seed + 1 that reached it; `cs_join`: the least (steps, seed) that reached it,
// complemented), then one bit per seed that reached it and one per seed that took it;
// after the faces, a head of four words (whether any walk met another) and per seed four
// (whether its walk met another's; `cs_join`'s queue tail).
fn face_words() -> u32 {
    return 2u * frame_data.params.words + 1u;
}

fn join_head() -> u32 {
    return frame_data.params.face_count * face_words();
}

fn seed_state(k: u32) -> u32 {
    return join_head() + 4u + 4u * k;
}

// Seed `k`'s walk reached a face another walk reached.
fn mark_met(k: u32) {
    atomicStore(&visited[seed_state(k)], 1u);
    atomicStore(&visited[join_head() + 1u], 1u);
}

// Claims face `f` for seed `k`'s walk: true when it had not reached it. Where another
// walk reached it too, both are marked met: the CPU's single queue would have shared
// the face out between them (a face one seed reached, taken or not, is closed to the
// others), which walks of their own do not; `cs_join` walks those seeds again together.
fn claim(f: u32, k: u32) -> bool {
    let bit = 1u << (k % 32u);
    let old = atomicOr(&visited[f * face_words() + 1u + k / 32u], bit);
    if (old & bit) != 0u {
        return false;
    }
    // One word per face: of two walks reaching it, the later sees the earlier.
    let other = atomicMax(&visited[f * face_words()], k + 1u);
    if other != 0u {
        mark_met(other - 1u);
        mark_met(k);
    }
    return true;
}

// Face `f` taken by seed `k` in `steps` steps: queued, and marked for the least mark.
fn take(f: u32, k: u32, steps: u32, base: u32) {
    // Taken, for `cs_join` (a walk among others takes what it takes alone).
    atomicOr(&visited[f * face_words() + 1u + frame_data.params.words + k / 32u], 1u << (k % 32u));
    let slot = atomicAdd(&wg_tail, 1u);
    if slot < frame_data.params.capacity {
        work[base + slot] = vec2<u32>(f, steps);
        atomicMax(&owner[f], ~((steps << SEED_BITS) | k));
    } else {
        atomicStore(&wg_overflow, 1u);
    }
}

// `RegionGrower::grow_pass`, one seed: breadth first from its face, one level per round,
// through the faces its region takes.
@compute @workgroup_size(256)
fn cs_grow(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let k = group.x;
    let s = frame_data.seeds[k];
    let base = k * frame_data.params.capacity;
    if lane == 0u {
        atomicStore(&wg_tail, 0u);
        atomicStore(&wg_overflow, 0u);
        let start = s.start.x;
        // (No call on the right of `&&`: naga's SPIR-V writer fails on one.)
        if start < frame_data.params.face_count && s.n.w != 0.0 && s.start.y == 0u {
            if claim(start, k) {
                let m = measure(start, s);
                if m.taken {
                    take(start, k, 0u, base);
                }
            }
        }
    }
    var begin = 0u;
    loop {
        // The level's entries were written to `work` (storage) by other lanes: a
        // workgroup barrier alone orders workgroup memory only.
        storageBarrier();
        workgroupBarrier();
        if lane == 0u {
            wg_level_end = min(atomicLoad(&wg_tail), frame_data.params.capacity);
        }
        let end = workgroupUniformLoad(&wg_level_end);
        if end <= begin {
            break;
        }
        for (var i = begin + lane; i < end; i += WORKGROUP) {
            let entry = work[base + i];
            let first = adjacency[entry.x];
            let last = adjacency[entry.x + 1u];
            for (var j = first; j < last; j++) {
                let g = adjacency[frame_data.params.face_count + 1u + j];
                if !claim(g, k) {
                    continue;
                }
                let m = measure(g, s);
                if m.taken {
                    take(g, k, entry.y + 1u, base);
                }
            }
        }
        begin = end;
    }
    workgroupBarrier();
    if lane == 0u {
        fits[k].flags = vec4<u32>(0u, 0u, min(atomicLoad(&wg_tail), frame_data.params.capacity), atomicLoad(&wg_overflow));
    }
}

// `cs_join`'s key of a face reached in `steps` steps by seed `k`: complemented, so that
// an atomic maximum keeps the least (steps, seed) — the CPU's queue's order — and every
// key is above the `k + 1` that `cs_grow` left (steps < 2²⁰ - 2).
fn join_key(steps: u32, k: u32) -> u32 {
    return ~((steps << SEED_BITS) | k);
}

// Face `f` taken by seed `k` in `steps` steps in `cs_join`: queued at its tail and marked
// as its own.
fn join_take(f: u32, k: u32, steps: u32) {
    let slot = atomicAdd(&visited[seed_state(k) + 1u], 1u);
    if slot < frame_data.params.capacity {
        work[k * frame_data.params.capacity + slot] = vec2<u32>(f, steps);
        atomicStore(&owner[f], ~((steps << SEED_BITS) | k));
    }
}

// Most seeds `cs_join` walks together; more met seeds are marked overflowed (the CPU
// grows that frame).
const MAX_JOIN: u32 = 256u;

var<workgroup> wg_join: u32;
var<workgroup> wg_met: atomic<u32>;
// Per met seed: the seed, its level's range in its queue, and the ranges' running sum.
var<workgroup> wg_seed: array<u32, MAX_JOIN>;
var<workgroup> wg_begin: array<u32, MAX_JOIN>;
var<workgroup> wg_end: array<u32, MAX_JOIN>;
var<workgroup> wg_prefix: array<u32, 257>;

// Which met seed's range holds entry `e` of the level (`wg_prefix[i] ≤ e`).
fn join_slot(e: u32, met: u32) -> u32 {
    var lo = 0u;
    var hi = met - 1u;
    while lo < hi {
        let mid = (lo + hi + 1u) / 2u;
        if wg_prefix[mid] <= e {
            lo = mid;
        } else {
            hi = mid - 1u;
        }
    }
    return lo;
}

// One half of a level of `cs_join`: the faces the met seeds took in the last level visit
// their neighbours, spread over the lanes as one list, which either bid (`take` false:
// the least key stays) or, where the bid that stayed is this seed's at this level, are
// taken by it if its walk alone took them (once: the first visit closes the face).
fn join_level(met: u32, total: u32, lane: u32, steps: u32, take: bool) {
    let nf = frame_data.params.face_count;
    let words = frame_data.params.words;
    for (var e = lane; e < total; e += WORKGROUP) {
        let i = join_slot(e, met);
        let k = wg_seed[i];
        let at = wg_begin[i] + e - wg_prefix[i];
        let face = work[k * frame_data.params.capacity + at].x;
        let key = join_key(steps, k);
        for (var j = adjacency[face]; j < adjacency[face + 1u]; j++) {
            let g = adjacency[nf + 1u + j];
            let word = g * face_words();
            if !take {
                atomicMax(&visited[word], key);
                continue;
            }
            if atomicLoad(&visited[word]) != key {
                continue;
            }
            // Close the face (0xffffffff is above every later key); a weak exchange may
            // fail spuriously, so try again while the key is still there.
            loop {
                let r = atomicCompareExchangeWeak(&visited[word], key, 0xffffffffu);
                if r.exchanged {
                    let bits = atomicLoad(&visited[word + 1u + words + k / 32u]);
                    if (bits & (1u << (k % 32u))) != 0u {
                        join_take(g, k, steps);
                    }
                    break;
                }
                if r.old_value != key {
                    break;
                }
            }
        }
    }
}

// The seeds whose walks met (`claim`) walked again together, as the CPU's single queue
// walks them (`RegionGrower::grow_pass`): level by level, every face going to the least
// (steps, seed) that reached it, taken or not. One workgroup; nothing to do where no walk
// met another. A seed's walk among others reaches only faces its walk alone reached, and
// takes those its walk alone took (marked in `visited`: nothing is measured again), so
// the seeds that met no one keep their walks: no face of theirs is anyone else's. The
// met seeds' queues and marks are written anew; `cs_fit` reads them as `cs_grow`'s.
@compute @workgroup_size(256)
fn cs_join(@builtin(local_invocation_index) lane: u32) {
    let head = join_head();
    if lane == 0u {
        wg_join = atomicLoad(&visited[head + 1u]);
        atomicStore(&wg_met, 0u);
    }
    if workgroupUniformLoad(&wg_join) == 0u {
        return;
    }
    let n = frame_data.params.seed_count;
    let capacity = frame_data.params.capacity;
    // The met seeds listed, their queues emptied, their start faces bid for.
    for (var k = lane; k < n; k += WORKGROUP) {
        let at = seed_state(k);
        if atomicLoad(&visited[at]) == 0u {
            continue;
        }
        let i = atomicAdd(&wg_met, 1u);
        if i < MAX_JOIN {
            wg_seed[i] = k;
        }
        atomicStore(&visited[at + 1u], 0u);
        let s = frame_data.seeds[k];
        if s.start.x < frame_data.params.face_count && s.n.w != 0.0 && s.start.y == 0u {
            atomicMax(&visited[s.start.x * face_words()], join_key(0u, k));
        }
    }
    storageBarrier();
    workgroupBarrier();
    if lane == 0u {
        wg_join = atomicLoad(&wg_met);
    }
    let listed = workgroupUniformLoad(&wg_join);
    if listed > MAX_JOIN {
        for (var k = lane; k < n; k += WORKGROUP) {
            if atomicLoad(&visited[seed_state(k)]) != 0u {
                fits[k].flags.w = 1u;
            }
        }
        return;
    }
    let met = listed;
    if lane < met {
        let k = wg_seed[lane];
        let s = frame_data.seeds[k];
        wg_end[lane] = 0u;
        if s.start.x < frame_data.params.face_count && s.n.w != 0.0 && s.start.y == 0u {
            let word = s.start.x * face_words();
            if atomicLoad(&visited[word]) == join_key(0u, k) {
                atomicStore(&visited[word], 0xffffffffu);
                let bits = atomicLoad(&visited[word + 1u + frame_data.params.words + k / 32u]);
                if (bits & (1u << (k % 32u))) != 0u {
                    join_take(s.start.x, k, 0u);
                }
            }
        }
    }
    for (var steps = 1u; steps < (1u << (32u - SEED_BITS)) - 2u; steps++) {
        storageBarrier();
        workgroupBarrier();
        // Each met seed's level: its queue from the last level's end to its tail.
        if lane < met {
            let begin = wg_end[lane];
            wg_begin[lane] = begin;
            wg_end[lane] = min(atomicLoad(&visited[seed_state(wg_seed[lane]) + 1u]), capacity);
        }
        workgroupBarrier();
        if lane == 0u {
            var sum = 0u;
            for (var i = 0u; i < met; i++) {
                wg_prefix[i] = sum;
                sum += wg_end[i] - wg_begin[i];
            }
            wg_prefix[met] = sum;
            wg_join = sum;
        }
        let total = workgroupUniformLoad(&wg_join);
        if total == 0u {
            break;
        }
        join_level(met, total, lane, steps, false);
        storageBarrier();
        workgroupBarrier();
        join_level(met, total, lane, steps, true);
    }
    storageBarrier();
    workgroupBarrier();
    if lane < met {
        let k = wg_seed[lane];
        let tail = atomicLoad(&visited[seed_state(k) + 1u]);
        // A walk cut short alone stays cut short: its marks are incomplete.
        let cut = fits[k].flags.w;
        fits[k].flags = vec4<u32>(0u, 0u, min(tail, capacity), select(cut, 1u, tail > capacity));
    }
}

// The ellipse with the same moments (`Moments::footprint`): half extents and centre in
// `ellipse`, rotation in `theta`; `ok` when it is not degenerate.
struct Ellipse {
    ellipse: vec4<f32>,
    theta: f32,
    ok: bool,
}

fn fit_ellipse(m: Moments) -> Ellipse {
    var out: Ellipse;
    if !(finite(m.area) && m.area > 1e-20) {
        return out;
    }
    let mean = m.first / m.area;
    let cxx = max(m.second.x / m.area - mean.x * mean.x, 0.0);
    let cxy = m.second.y / m.area - mean.x * mean.y;
    let cyy = max(m.second.z / m.area - mean.y * mean.y, 0.0);
    // `fit.rs`'s `atan2`, by `atan2_reduced` (some compilers' `atan2` is inexact).
    var theta = 0.5 * atan2_reduced(2.0 * cxy, cxx - cyy);
    let quarter = 1.5707963267948966;
    if theta > quarter / 2.0 {
        theta -= quarter;
    } else if theta < -quarter / 2.0 {
        theta += quarter;
    }
    let spread = sqrt((cxx - cyy) * (cxx - cyy) + 4.0 * cxy * cxy) / max(cxx + cyy, 1e-30);
    let t = clamp((spread - 0.05) / 0.15, 0.0, 1.0);
    theta *= t * t * (3.0 - 2.0 * t);
    let sn = sin(theta);
    let cs = cos(theta);
    let var_u = cxx * cs * cs + 2.0 * cxy * sn * cs + cyy * sn * sn;
    let var_v = cxx * sn * sn - 2.0 * cxy * sn * cs + cyy * cs * cs;
    let halves = 2.0 * sqrt(max(vec2<f32>(var_u, var_v), vec2<f32>(0.0)));
    out.ellipse = vec4<f32>(halves, mean);
    out.theta = theta;
    out.ok = min(halves.x, halves.y) > 0.0 && finite(halves.x) && finite(halves.y) && finite(mean.x) && finite(mean.y);
    return out;
}

// The seed's moments and their ellipse into `fits[k]` (status 2 when the region is empty
// or degenerate).
fn write_fit(k: u32, m: Moments, cone: f32, won: u32) {
    var fit = fits[k];
    fit.moments = vec4<f32>(m.area, m.first, cone);
    fit.second = vec4<f32>(m.second, 0.0);
    fit.flags.x = 2u;
    fit.flags.y = won;
    fit.piece_count = vec4<u32>(0u);
    let e = fit_ellipse(m);
    if won > 0u && e.ok {
        fit.ellipse = e.ellipse;
        fit.fit = vec4<f32>(e.theta, m.area, cone, 1.0);
        fit.flags.x = 0u;
    }
    fits[k] = fit;
}

// The bins of `best_overlap_scale` (`fit.rs`) over the moment ellipse's normalised radius.
const OVERLAP_BINS: u32 = 128u;
// Fixed-point units of a bin per whole region area: the bins are integer atomics.
const BIN_UNITS: f32 = 1073741824.0;

// Whether the won face at `entry` is seed `k`'s.
fn won_by(entry: vec2<u32>, k: u32) -> bool {
    return atomicLoad(&owner[entry.x]) == ~((entry.y << SEED_BITS) | k);
}

// One won face's moments `m` spread over the radial bins of the ellipse `fp` (half
// extents xy, centre zw; `turn`: sin, cos of its rotation), by its own extent along the
// radius (`best_overlap_scale`'s loop body), in units of `unit` per area.
fn bin_face(m: Moments, fp: vec4<f32>, turn: vec2<f32>, unit: f32) {
    if !(m.area > 0.0) {
        return;
    }
    let n = f32(OVERLAP_BINS);
    let h = fp.xy;
    let sn = turn.x;
    let cs = turn.y;
    let c = m.first / m.area;
    let d = c - fp.zw;
    let q = vec2<f32>(d.x * cs + d.y * sn, d.y * cs - d.x * sn) / h;
    let r = length(q);
    var g = vec2<f32>(0.0);
    if r > 0.0 && finite(1.0 / r) {
        g = q / r / h;
    }
    g = vec2<f32>(g.x * cs - g.y * sn, g.x * sn + g.y * cs);
    let cxx = m.second.x / m.area - c.x * c.x;
    let cxy = m.second.y / m.area - c.x * c.y;
    let cyy = m.second.z / m.area - c.y * c.y;
    let var_r = max(g.x * g.x * cxx + 2.0 * g.x * g.y * cxy + g.y * g.y * cyy, 0.0);
    let half = sqrt(3.0) * sqrt(var_r);
    let lo = (r - half) * n;
    let hi = (r + half) * n;
    if !(hi - lo > 1e-9) {
        if r < 1.0 {
            let b = min(u32(r * n), OVERLAP_BINS - 1u);
            atomicAdd(&wg_bins[b], u32(round(m.area * unit)));
        }
        return;
    }
    let density = m.area / (hi - lo);
    var first = 0u;
    if lo > 0.0 {
        first = u32(lo);
    }
    for (var b = first; b < OVERLAP_BINS; b++) {
        let a = f32(b);
        if a >= hi {
            break;
        }
        // What falls below radius 0 lies on the other side of the centre, at −r.
        let folded = max(min(a + 1.0, -lo) - a, 0.0);
        let part = density * (max(min(a + 1.0, hi) - max(a, lo), 0.0) + folded);
        atomicAdd(&wg_bins[b], u32(round(part * unit)));
    }
}

// `best_overlap_scale` from the filled bins (`unit` per area), the region's area `total`
// and the ellipse's half extents `h`.
fn overlap_scale(total: f32, h: vec2<f32>, unit: f32) -> f32 {
    let ellipse = 3.141592653589793 * h.x * h.y;
    if !(total > 0.0) || !finite(ellipse) {
        return 1.0;
    }
    let s_area = min(sqrt(total / ellipse), 1.0);
    let x = s_area * f32(OVERLAP_BINS);
    let full = min(u32(x), OVERLAP_BINS);
    var within = 0.0;
    for (var b = 0u; b < full; b++) {
        within += f32(atomicLoad(&wg_bins[b])) / unit;
    }
    if full < OVERLAP_BINS {
        within += f32(atomicLoad(&wg_bins[full])) / unit * (x - f32(full));
    }
    if within >= 0.25 * total {
        return s_area;
    }
    var best = -1.0;
    var best_s = 1.0;
    var inside = 0.0;
    for (var b = 0u; b < OVERLAP_BINS; b++) {
        inside += f32(atomicLoad(&wg_bins[b])) / unit;
        let s = f32(b + 1u) / f32(OVERLAP_BINS);
        let held = min(inside, total);
        let iou = held / (total + ellipse * s * s - held);
        if iou > best {
            best = iou;
            best_s = s;
        }
    }
    return best_s;
}

// `split.rs`'s `SPLIT_AREA_RATIO`, `SPLIT_ELONGATION` and `MAX_PIECES`; the bins a bent
// region's won faces are counted in along its axis to place the cuts.
const SPLIT_AREA_RATIO: f32 = 1.3;
const SPLIT_ELONGATION: f32 = 2.5;
const MAX_PIECES: u32 = 6u;
const CUT_BINS: u32 = 1024u;
const CUT_LIST: u32 = CUT_BINS / 4u;

// A float's bits, ordered as the floats are (for integer atomic minima and maxima).
fn ordered(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    if (b & 0x80000000u) != 0u {
        return ~b;
    }
    return b | 0x80000000u;
}

fn from_ordered(u: u32) -> f32 {
    if (u & 0x80000000u) != 0u {
        return bitcast<f32>(u & 0x7fffffffu);
    }
    return bitcast<f32>(~u);
}

// Sums `wg_sum` (and the least of `wg_cone`) into lane 0's; every lane calls it.
fn reduce(lane: u32) {
    for (var stride = WORKGROUP / 2u; stride > 0u; stride /= 2u) {
        workgroupBarrier();
        if lane < stride {
            for (var c = 0u; c < 8u; c++) {
                wg_sum[lane][c] += wg_sum[lane + stride][c];
            }
            wg_cone[lane] = min(wg_cone[lane], wg_cone[lane + stride]);
        }
    }
    workgroupBarrier();
}

// The overlap scale of the ellipse `fp` (half extents, centre; rotation `theta`) over the
// faces seed `k` won, for a region of area `total` (`best_overlap_scale`); every lane
// calls it and gets it.
fn overlap_over_won(k: u32, walked: u32, lane: u32, fp: vec4<f32>, theta: f32, total: f32, unit: f32) -> f32 {
    let s = frame_data.seeds[k];
    let base = k * frame_data.params.capacity;
    if lane < OVERLAP_BINS {
        atomicStore(&wg_bins[lane], 0u);
    }
    workgroupBarrier();
    let turn = vec2<f32>(sin(theta), cos(theta));
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if won_by(entry, k) {
            bin_face(measure(entry.x, s).m, fp, turn, unit);
        }
    }
    workgroupBarrier();
    let scale = overlap_scale(total, fp.xy, unit);
    workgroupBarrier();
    return scale;
}

// Where a won face's centroid lies along the axis from the ellipse's centre.
fn along(m: Moments, centre: vec2<f32>, axis: vec2<f32>) -> f32 {
    return dot(m.first / m.area - centre, axis);
}

// The bin along the axis of a position `t` on it, over `lo` and `width`.
fn cut_bin(t: f32, lo: f32, width: f32) -> u32 {
    return min(u32(max((t - lo) / width * f32(CUT_BINS), 0.0)), CUT_BINS - 1u);
}

// Seed `group.x`'s moments over the faces it won, its moment ellipse and the scale of it
// that fits the region best (`RegionGrower::fit_parts` with `best_overlap_scale`, face by
// face), and a long bent region's pieces (`split_bent`): cut at equal area along the
// ellipse's long axis, placed by the won faces' areas in `CUT_BINS` bins along it, each
// piece fitted to its own faces and scaled against all of them.
@compute @workgroup_size(256)
fn cs_fit(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let k = group.x;
    let s = frame_data.seeds[k];
    let base = k * frame_data.params.capacity;
    let walked = fits[k].flags.z;
    var m: Moments;
    var cone = 1.0;
    var won = 0.0;
    var positive = 0.0;
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if !won_by(entry, k) {
            continue;
        }
        let face = measure(entry.x, s);
        m.area += face.m.area;
        m.first += face.m.first;
        m.second += face.m.second;
        cone = min(cone, face.cone);
        won += 1.0;
        positive += max(face.m.area, 0.0);
    }
    wg_sum[lane] = array<f32, 8>(m.area, m.first.x, m.first.y, m.second.x, m.second.y, m.second.z, won, positive);
    wg_cone[lane] = cone;
    reduce(lane);
    if lane == 0u {
        let t = wg_sum[0];
        var total: Moments;
        total.area = t[0];
        total.first = vec2<f32>(t[1], t[2]);
        total.second = vec3<f32>(t[3], t[4], t[5]);
        write_fit(k, total, wg_cone[0], u32(t[6]));
        if s.start.y != 0u {
            fits[k].flags.x = 1u;
        }
        wg_fitted = fits[k];
        wg_fitted.fit.w = t[7];
    }
    let fitted = workgroupUniformLoad(&wg_fitted);
    if fitted.flags.x != 0u {
        return;
    }
    // The overlap scale of the whole; `fit.w` holds the positive areas' sum meanwhile.
    let positive_total = fitted.fit.w;
    let unit = BIN_UNITS / max(positive_total, 1e-30);
    let region_area = fitted.fit.y;
    let scale = overlap_over_won(k, walked, lane, fitted.ellipse, fitted.fit.x, min(region_area, positive_total), unit);
    if lane == 0u {
        fits[k].fit.w = scale;
    }
    // A long bent band (`needs_split`)?
    let h = fitted.ellipse.xy;
    let elongation = max(h.x, h.y) / max(min(h.x, h.y), 1.17549435e-38);
    if !(3.141592653589793 * h.x * h.y > SPLIT_AREA_RATIO * region_area && elongation >= SPLIT_ELONGATION) {
        return;
    }
    // Halves away from zero, as Rust's `round` (WGSL's rounds them to even).
    let count = clamp(u32(floor(elongation / 1.5 + 0.5)), 2u, MAX_PIECES);
    let sn = sin(fitted.fit.x);
    let cs = cos(fitted.fit.x);
    var axis = vec2<f32>(cs, sn);
    if h.x < h.y {
        axis = vec2<f32>(-sn, cs);
    }
    let centre = fitted.ellipse.zw;
    // The won faces' range along the axis, then their areas in bins along it.
    if lane < 2u {
        atomicStore(&wg_range[lane], select(0u, 0xffffffffu, lane == 0u));
    }
    for (var b = lane; b < CUT_BINS; b += WORKGROUP) {
        atomicStore(&wg_bins[b], 0u);
    }
    workgroupBarrier();
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if won_by(entry, k) {
            let face = measure(entry.x, s).m;
            if face.area > 0.0 {
                let t = along(face, centre, axis);
                atomicMin(&wg_range[0], ordered(t));
                atomicMax(&wg_range[1], ordered(t));
            }
        }
    }
    workgroupBarrier();
    let lo = from_ordered(atomicLoad(&wg_range[0]));
    let width = max(from_ordered(atomicLoad(&wg_range[1])) - lo, 1e-30);
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if won_by(entry, k) {
            let face = measure(entry.x, s).m;
            if face.area > 0.0 {
                let b = cut_bin(along(face, centre, axis), lo, width);
                atomicAdd(&wg_bins[b], u32(round(face.area * unit)));
            }
        }
    }
    workgroupBarrier();
    // The cuts: after the bin in which the running area reaches each `j / count` of the
    // whole (`split_bent` closes a piece with the face that reaches it, and a bin holds
    // about one face of a region of a few thousand).
    if lane == 0u {
        var cum = 0.0;
        var j = 1u;
        for (var b = 0u; b < CUT_BINS; b++) {
            let a = f32(atomicLoad(&wg_bins[b])) / unit;
            loop {
                if j >= count {
                    break;
                }
                let target_area = positive_total * f32(j) / f32(count);
                if cum + a < target_area - 1e-12 * positive_total {
                    break;
                }
                wg_cuts[j - 1u] = b;
                wg_cut_before[j - 1u] = cum;
                wg_cut_target[j - 1u] = target_area - 1e-12 * positive_total;
                j += 1u;
            }
            cum += a;
        }
        for (; j < count; j++) {
            wg_cuts[j - 1u] = CUT_BINS;
        }
        atomicStore(&wg_list_len, 0u);
    }
    workgroupBarrier();
    // The won faces in the cut bins, listed (the bins' counts are no longer needed).
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if won_by(entry, k) {
            let face = measure(entry.x, s).m;
            if face.area > 0.0 {
                let t = along(face, centre, axis);
                let b = cut_bin(t, lo, width);
                var at_cut = false;
                for (var j = 0u; j + 1u < count; j++) {
                    at_cut = at_cut || b == wg_cuts[j];
                }
                if at_cut {
                    let slot = atomicAdd(&wg_list_len, 1u);
                    if slot < CUT_LIST {
                        atomicStore(&wg_bins[4u * slot], bitcast<u32>(t));
                        atomicStore(&wg_bins[4u * slot + 1u], bitcast<u32>(face.area));
                        atomicStore(&wg_bins[4u * slot + 2u], i);
                        atomicStore(&wg_bins[4u * slot + 3u], b);
                    }
                }
            }
        }
    }
    workgroupBarrier();
    let listed = atomicLoad(&wg_list_len);
    // Each piece's moments, its faces being those between its cuts.
    var acc: array<Moments, 6>;
    for (var i = lane; i < walked; i += WORKGROUP) {
        let entry = work[base + i];
        if won_by(entry, k) {
            let face = measure(entry.x, s).m;
            if face.area > 0.0 {
                let t = along(face, centre, axis);
                let b = cut_bin(t, lo, width);
                var p = 0u;
                for (var j = 0u; j + 1u < count; j++) {
                    if b > wg_cuts[j] {
                        p += 1u;
                    } else if b == wg_cuts[j] && listed <= CUT_LIST {
                        // In the cut's bin: after the cut when the faces before this one
                        // (by position, then by queue order) already reach the piece's
                        // share. (Past `CUT_LIST` faces, a cut bin's faces all stay before
                        // the cut.)
                        var before = wg_cut_before[j];
                        for (var e = 0u; e < listed; e++) {
                            let t2 = bitcast<f32>(atomicLoad(&wg_bins[4u * e]));
                            let i2 = atomicLoad(&wg_bins[4u * e + 2u]);
                            let earlier = t2 < t || (t2 == t && i2 < i);
                            if atomicLoad(&wg_bins[4u * e + 3u]) == b && earlier {
                                before += bitcast<f32>(atomicLoad(&wg_bins[4u * e + 1u]));
                            }
                        }
                        if before >= wg_cut_target[j] {
                            p += 1u;
                        }
                    }
                }
                acc[p].area += face.area;
                acc[p].first += face.first;
                acc[p].second += face.second;
            }
        }
    }
    for (var p = 0u; p < count; p++) {
        let a = acc[p];
        wg_sum[lane] = array<f32, 8>(a.area, a.first.x, a.first.y, a.second.x, a.second.y, a.second.z, 0.0, 0.0);
        wg_cone[lane] = 1.0;
        reduce(lane);
        if lane == 0u {
            let t = wg_sum[0];
            var piece: Moments;
            piece.area = t[0];
            piece.first = vec2<f32>(t[1], t[2]);
            piece.second = vec3<f32>(t[3], t[4], t[5]);
            let e = fit_ellipse(piece);
            // Degenerate pieces are left out, the others keep their order.
            let n = wg_fitted.piece_count.x;
            if e.ok {
                wg_fitted.pieces[n] = RegionPiece(e.ellipse, vec4<f32>(e.theta, piece.area, 1.0, 0.0));
                wg_fitted.piece_count.x = n + 1u;
            }
        }
    }
    let split = workgroupUniformLoad(&wg_fitted);
    let pieces = split.piece_count.x;
    if pieces < 2u {
        return;
    }
    for (var p = 0u; p < pieces; p++) {
        let piece = split.pieces[p];
        let piece_scale = overlap_over_won(k, walked, lane, piece.ellipse, piece.fit.x, min(piece.fit.y, positive_total), unit);
        if lane == 0u {
            fits[k].pieces[p] = RegionPiece(piece.ellipse, vec4<f32>(piece.fit.xy, piece_scale, 0.0));
        }
    }
    if lane == 0u {
        fits[k].piece_count = vec4<u32>(pieces, 0u, 0u, 0u);
    }
}
