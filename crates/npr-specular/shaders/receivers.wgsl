// The receivers of Lee & Choi §4.2 on the GPU: a triangle receives a highlight only if it
// is reachable by breadth-first search from the triangle holding the centre, lies at
// least partly inside the projector's frustum, and faces it. One workgroup walks one
// highlight level by level (the frontier shared through storage, the queue's tail an
// integer atomic in workgroup memory: WebGPU has no float atomics, and nothing here
// needs them). A face is claimed by an atomic OR of its highlight's bit, so each is
// tested once. Then the received faces of every highlight are laid out, highlight by
// highlight, as the highlight pass's vertex stream, and the indirect draw's count is
// written: nothing is read back.
//
// The CPU reference is `crate::visibility::receivers_within` (`walk_faces` and its
// `visit`); `face_state` below is its `visit`, `cs_walk` its `walk_faces`.

// One face: topology vertices (w: 1 when degenerate), render vertices (w: bits of the
// sine of its slack angle), face normal (w: cosine of its slack angle).
struct Face {
    tri: vec4<u32>,
    render: vec4<u32>,
    normal: vec4<f32>,
}

// The indirect draw's arguments, then per highlight (faces crossed, received, overflow
// flag, first face in the stream).
struct Meta {
    args: vec4<u32>,
    counts: array<vec4<u32>>,
}

@group(0) @binding(1) var<storage, read> receiver_frame: ReceiverFrame;
@group(0) @binding(2) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> faces: array<Face>;
// Face adjacency: `face_count + 1` offsets, then the neighbour list.
@group(0) @binding(4) var<storage, read> adjacency: array<u32>;
@group(0) @binding(5) var<storage, read_write> visited: array<atomic<u32>>;
// Per highlight `2 · capacity` entries: its queue, then its received faces.
@group(0) @binding(6) var<storage, read_write> work: array<u32>;
@group(0) @binding(7) var<storage, read_write> meta_data: Meta;
// The highlight pass's vertex stream: (render vertex, highlight) per triangle corner.
@group(0) @binding(8) var<storage, read_write> list: array<vec2<u32>>;

const WORKGROUP: u32 = 256u;

var<workgroup> wg_tail: atomic<u32>;
var<workgroup> wg_received: atomic<u32>;
var<workgroup> wg_overflow: atomic<u32>;
var<workgroup> wg_level_end: u32;

// Whether the triangle with projector coordinates q0..q2 can overlap the box lo..hi
// (`overlaps_box`: its bounding box meets the box on every axis).
fn overlaps(q0: vec3<f32>, q1: vec3<f32>, q2: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let q_lo = min(min(q0, q1), q2);
    let q_hi = max(max(q0, q1), q2);
    return all(q_hi >= lo) && all(q_lo <= hi);
}

fn project(q: Query, v: u32) -> vec4<f32> {
    let c = q.ndc_from_object * vec4<f32>(positions[v].xyz, 1.0);
    if q.n_max.w != 0.0 {
        return vec4<f32>(c.xyz, 1.0);
    }
    // A vertex at the projector's plane at infinity is not received (`overlaps_box`).
    if abs(c.w) <= 0.0 {
        return vec4<f32>(0.0, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(c.xyz / c.w, 1.0);
}

// `visit` of `receivers_impl`: 0 not crossed, 1 crossed, 2 crossed and received.
fn face_state(f: u32, q: Query) -> u32 {
    let face = faces[f];
    if face.tri.w != 0u {
        return 0u;
    }
    let n = face.normal.xyz;
    // `Facing::face_cos`: cos(limit + slack), at least 0.
    var min_cos = bitcast<f32>(q.rule.z);
    if q.rule.y == 1u {
        let c = face.normal.w;
        let s = bitcast<f32>(face.render.w);
        min_cos = max(q.walk_hi.w * c - q.walk_lo.w * s, 0.0);
    }
    let d = dot(n, q.n_max.xyz);
    var facing = d > 0.0;
    if min_cos > 0.0 {
        var floor = min_cos * receiver_frame.params.k;
        if receiver_frame.params.similar == 0u {
            floor = min_cos * length((receiver_frame.params.normal_from_object * vec4<f32>(n, 0.0)).xyz);
        }
        facing = d > floor;
    }
    if !facing {
        return 0u;
    }
    let a = project(q, face.tri.x);
    let b = project(q, face.tri.y);
    let c = project(q, face.tri.z);
    if a.w == 0.0 || b.w == 0.0 || c.w == 0.0 {
        return 0u;
    }
    if !overlaps(a.xyz, b.xyz, c.xyz, q.walk_lo.xyz, q.walk_hi.xyz) {
        return 0u;
    }
    let received = overlaps(a.xyz, b.xyz, c.xyz, vec3<f32>(-1.0, -1.0, 0.0), vec3<f32>(1.0));
    return select(1u, 2u, received);
}

// Claims face `f` for highlight `h`: true when no invocation had.
fn claim(f: u32, h: u32) -> bool {
    let bit = 1u << (h % 32u);
    let old = atomicOr(&visited[f * receiver_frame.params.words + h / 32u], bit);
    return (old & bit) == 0u;
}

// Queues face `f` (crossed, `state` ≥ 1) of the walk whose entries start at `base`.
fn push(f: u32, state: u32, base: u32) {
    let slot = atomicAdd(&wg_tail, 1u);
    if slot < receiver_frame.params.capacity {
        work[base + slot] = f;
    } else {
        atomicStore(&wg_overflow, 1u);
    }
    if state == 2u {
        let r = atomicAdd(&wg_received, 1u);
        if r < receiver_frame.params.capacity {
            work[base + receiver_frame.params.capacity + r] = f;
        }
    }
}

// `walk_faces`: breadth first from the start face, one level per round.
@compute @workgroup_size(256)
fn cs_walk(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let h = group.x;
    // A frame whose projectors the GPU built is dispatched over its room.
    if h >= receiver_frame.params.highlight_count {
        return;
    }
    let q = receiver_frame.queries[h];
    let base = h * 2u * receiver_frame.params.capacity;
    if lane == 0u {
        atomicStore(&wg_tail, 0u);
        atomicStore(&wg_received, 0u);
        atomicStore(&wg_overflow, 0u);
        let start = q.rule.x;
        if start < receiver_frame.params.face_count && claim(start, h) {
            let state = face_state(start, q);
            if state != 0u {
                push(start, state, base);
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
            wg_level_end = min(atomicLoad(&wg_tail), receiver_frame.params.capacity);
        }
        let end = workgroupUniformLoad(&wg_level_end);
        if end <= begin {
            break;
        }
        for (var i = begin + lane; i < end; i += WORKGROUP) {
            let f = work[base + i];
            let first = adjacency[f];
            let last = adjacency[f + 1u];
            for (var j = first; j < last; j++) {
                let g = adjacency[receiver_frame.params.face_count + 1u + j];
                if !claim(g, h) {
                    continue;
                }
                let state = face_state(g, q);
                if state != 0u {
                    push(g, state, base);
                }
            }
        }
        begin = end;
    }
    workgroupBarrier();
    if lane == 0u {
        let crossed = min(atomicLoad(&wg_tail), receiver_frame.params.capacity);
        let received = min(atomicLoad(&wg_received), receiver_frame.params.capacity);
        meta_data.counts[h] = vec4<u32>(crossed, received, atomicLoad(&wg_overflow), 0u);
    }
}

// Each highlight's first face in the stream (in highlight order, as the CPU's
// `HighlightPass::draw_list`), and the indirect draw's vertex count.
@compute @workgroup_size(1)
fn cs_offsets() {
    var total = 0u;
    for (var h = 0u; h < receiver_frame.params.highlight_count; h++) {
        var c = meta_data.counts[h];
        let room = receiver_frame.params.list_faces - min(total, receiver_frame.params.list_faces);
        if c.y > room {
            c.y = room;
            c.z = 1u;
        }
        c.w = total;
        meta_data.counts[h] = c;
        total += c.y;
    }
    meta_data.args = vec4<u32>(3u * total, 1u, 0u, 0u);
    // Past the count (a frame dispatched over its room), no walk this frame.
    for (var h = receiver_frame.params.highlight_count; h < arrayLength(&meta_data.counts); h++) {
        meta_data.counts[h] = vec4<u32>(0u, 0u, 0u, total);
    }
}

// The received faces of highlight `group.x`, three stream entries each.
@compute @workgroup_size(256)
fn cs_scatter(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let h = group.x;
    if h >= receiver_frame.params.highlight_count {
        return;
    }
    let c = meta_data.counts[h];
    let base = h * 2u * receiver_frame.params.capacity + receiver_frame.params.capacity;
    for (var i = lane; i < c.y; i += WORKGROUP) {
        let f = work[base + i];
        let r = faces[f].render;
        let at = 3u * (c.w + i);
        list[at] = vec2<u32>(r.x, h);
        list[at + 1u] = vec2<u32>(r.y, h);
        list[at + 2u] = vec2<u32>(r.z, h);
    }
}
