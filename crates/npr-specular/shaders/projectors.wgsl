// The frame's highlights built on the GPU (beyond Lee & Choi: §3.2–§3.4 frame after
// frame), so that the highlight pass draws projectors nobody read back: this frame's
// centres (`cs_centres`, `cs_peaks`), their matching with the last frame's highlights
// (`cs_track`) and their regions (`cs_grow`, `cs_join`, `cs_fit`) made into highlights
// as `HighlightSet::update` makes them (`footprints`: fades, suppression, the change
// limit, the pieces of bent regions; `make`: the projector of Eq. (7)–(9) with the
// composed §3.4 controls; `receiver_rule`: the falloff; `share_regions`), written as the
// highlight pass's records, and kept as the next frame's table. Each function names its
// Rust twin in the crate (`set/mod.rs`, `set/receivers.rs`, `projector.rs`).

// The frame's settings: the global controls, the set's settings and the per-highlight
// controls the user set (`HighlightSet::controls_mut`), sorted by id.
struct ProjectParams {
    // Global translate (xy), rotation, σ.
    controls_a: vec4<f32>,
    // Global scale (xy), shininess, texture layer.
    controls_b: vec4<f32>,
    // Global tint (rgb), up (0: κmin, 1: κmax).
    controls_c: vec4<f32>,
    // Eq. (8)'s cap radius (world), the least region area (world), the change limit,
    // the fade step.
    sizes: vec4<f32>,
    // `receiver_min_cos`, `receiver_cone_margin_rad`, the set's face turn, the inverse
    // of the transform's mean scale.
    receiver: vec4<f32>,
    // Sizing (0 paper, 1 region), boundary (0 smooth, 1 per face, 2 unrestricted),
    // per-highlight controls, the layers that are normal maps (bits).
    modes: vec4<u32>,
    // `match_radius`, the mean edge (object), the mean scale, the last texture layer.
    tracking: vec4<f32>,
}

// One highlight's own controls (`HighlightControls`): id, which options it sets (bits:
// 1 σ, 2 layer, 4 shininess, 8 up), its layer and up; translate, rotation, σ; scale,
// shininess; tint.
struct ControlsRecord {
    id_flags: vec4<u32>,
    moves: vec4<f32>,
    scale: vec4<f32>,
    tint: vec4<f32>,
}

struct ProjectData {
    params: ProjectParams,
    controls: array<ControlsRecord>,
}

// `ProjectorGpu` of `pass.rs`: what `specular_highlight.wgsl` reads.
struct ProjectorRecord {
    tex_from_world: mat4x4<f32>,
    axis_u: vec4<f32>,
    axis_v: vec4<f32>,
    normal: vec4<f32>,
    tint: vec4<f32>,
    params: vec4<f32>,
    neighbours: vec4<u32>,
}

@group(0) @binding(0) var<storage, read> frame_data: RegionFrameData;
@group(0) @binding(1) var<storage, read> fits: array<RegionFit>;
@group(0) @binding(2) var<storage, read> centres: array<CentreRecord>;
@group(0) @binding(3) var<storage, read> previous: TrackData;
// `cs_track`'s dispatch, status and matching (`MATCH_AT` of `tracking.wgsl`).
@group(0) @binding(4) var<storage, read> matched: array<u32>;
@group(0) @binding(5) var<storage, read> settings: ProjectData;
@group(0) @binding(6) var<storage, read_write> next: TrackData;
// The highlight pass's records, then the §4.2 walk's frame (`receiver_frame.wgsl`; the
// CPU writes its values but the count, this pass the queries): one buffer, each part
// bound at its own offset by the pass that reads it.
struct ProjectOutput {
    records: array<ProjectorRecord, MAX_DRAWN>,
    receiver_params: ReceiverParams,
    queries: array<Query>,
}
@group(0) @binding(7) var<storage, read_write> out: ProjectOutput;

const NONE: u32 = 0xffffffffu;
const MATCH_AT: u32 = 8u;
// Where the search's `cs_replace` put the last frame's highlights (after its
// `MAX_MERGED` centres).
const REPLACED_AT: u32 = 256u;
// Projectors a frame draws at most (pieces included): the workgroup's table of them
// (40 bytes each, within WebGPU's 16 KiB of workgroup memory).
const MAX_DRAWN: u32 = 384u;
const MAX_TRACKED: u32 = 256u;
const PI_2: f32 = 1.5707963267948966;
const TAU: f32 = 6.283185307179586;

// `ProjectorControls` composed with a highlight's own (`ProjectorControls::compose`);
// `edited`: its own move, turn or scale (`share_regions`' test).
struct Controls {
    translate: vec2<f32>,
    rotate: f32,
    scale: vec2<f32>,
    sigma: f32,
    layer: u32,
    tint: vec3<f32>,
    shininess: f32,
    up: u32,
    edited: bool,
}

// `Footprint`: half extents, offset, rotation, region area, normal cone, fit scale.
struct Footprint {
    half: vec2<f32>,
    offset: vec2<f32>,
    rotate: f32,
    area: f32,
    cone: f32,
    fit_scale: f32,
}

// `Projector`.
struct Projector {
    ok: bool,
    centre_world: vec3<f32>,
    anchor_world: vec3<f32>,
    u: vec3<f32>,
    v: vec3<f32>,
    n: vec3<f32>,
    half: vec2<f32>,
    clip_from_world: mat4x4<f32>,
}

// The workgroup's record of each projector drawn: its projector's centre and larger
// half extent, its anchor (the N = H centre) and smaller half extent; id and flags
// (1 found, 2 drawn itself, 4 edited).
var<workgroup> wg_centre: array<vec4<f32>, MAX_DRAWN>;
var<workgroup> wg_anchor: array<vec4<f32>, MAX_DRAWN>;
var<workgroup> wg_key: array<vec2<u32>, MAX_DRAWN>;
var<workgroup> wg_drawn: u32;

fn controls_of(id: u32) -> Controls {
    let p = settings.params;
    var c: Controls;
    c.translate = p.controls_a.xy;
    c.rotate = p.controls_a.z;
    c.sigma = p.controls_a.w;
    c.scale = p.controls_b.xy;
    c.shininess = p.controls_b.z;
    c.layer = u32(p.controls_b.w);
    c.tint = p.controls_c.xyz;
    c.up = u32(p.controls_c.w);
    c.edited = false;
    // The highlight's own, by binary search over the sorted ids.
    var lo = 0u;
    var hi = p.modes.z;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if settings.controls[mid].id_flags.x < id {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if lo < p.modes.z && settings.controls[lo].id_flags.x == id {
        let o = settings.controls[lo];
        c.translate += o.moves.xy;
        c.rotate += o.moves.z;
        c.scale *= o.scale.xy;
        c.tint *= o.tint.xyz;
        let flags = o.id_flags.y;
        if (flags & 1u) != 0u {
            c.sigma = o.moves.w;
        }
        if (flags & 2u) != 0u {
            c.layer = o.id_flags.z;
        }
        if (flags & 4u) != 0u {
            c.shininess = o.scale.z;
        }
        if (flags & 8u) != 0u {
            c.up = o.id_flags.w;
        }
        c.edited = any(o.moves.xy != vec2<f32>(0.0)) || o.moves.z != 0.0 || any(o.scale.xy != vec2<f32>(1.0));
    }
    return c;
}

// `frustum_size`, Eq. (8).
fn frustum_size(kappa: f32, sigma: f32, radius: f32) -> f32 {
    let s = clamp(sigma, -1.0, 1.0);
    let cap = 2.0 * abs(radius);
    let k = abs(kappa);
    if k <= 1.17549435e-38 || !finite(k) {
        return cap;
    }
    return min(2.0 / k * sqrt(max(1.0 - s * s, 0.0)), cap);
}

fn eq8_footprint(c: CentreRecord, sigma: f32, radius: f32) -> Footprint {
    var f: Footprint;
    f.half = vec2<f32>(frustum_size(c.curvature.x, sigma, radius), frustum_size(c.curvature.y, sigma, radius)) * 0.5;
    f.cone = -1.0;
    f.fit_scale = 1.0;
    return f;
}

// `Footprint::scaled`.
fn scaled(f_in: Footprint, s: f32) -> Footprint {
    var f = f_in;
    if s > 0.0 && s < 1.0 {
        f.half *= s;
        f.fit_scale *= s;
    }
    return f;
}

// The decoded overlap scale (`decode` of `region_pass/records.rs`).
fn fit_scale_of(s: f32) -> f32 {
    return select(1.0, s, s > 0.0 && s <= 1.0);
}

// A fitted region's footprint (`decode` of `region_pass/records.rs`): its ellipse (half
// extents, offset), (rotation, area, normal cone), scaled by its overlap scale.
fn fitted(ellipse: vec4<f32>, shape: vec3<f32>, overlap: f32) -> Footprint {
    var f: Footprint;
    f.half = ellipse.xy;
    f.offset = ellipse.zw;
    f.rotate = shape.x;
    f.area = shape.y;
    f.cone = shape.z;
    f.fit_scale = 1.0;
    return scaled(f, fit_scale_of(overlap));
}

// `limit_change`.
fn limit_change(last: Footprint, next_in: Footprint, max_area_change: f32) -> Footprint {
    var next_fp = next_in;
    if !(max_area_change > 0.0) || min(last.half.x, last.half.y) <= 0.0 {
        return next_fp;
    }
    let r = sqrt(1.0 + max_area_change);
    next_fp.half = clamp(next_fp.half, last.half / r, last.half * r);
    return next_fp;
}

// `group_edit`.
fn group_edit(whole: Footprint, piece: Footprint, c: Controls) -> Footprint {
    let d = piece.offset - whole.offset;
    let sw = sin(whole.rotate);
    let cw = cos(whole.rotate);
    let local = vec2<f32>(d.x * cw + d.y * sw, d.y * cw - d.x * sw) * abs(c.scale);
    let back = vec2<f32>(local.x * cw - local.y * sw, local.x * sw + local.y * cw);
    let sr = sin(c.rotate);
    let cr = cos(c.rotate);
    let turned = vec2<f32>(back.x * cr - back.y * sr, back.x * sr + back.y * cr);
    var out = piece;
    out.offset = whole.offset + turned;
    return out;
}

// `Projector::with_footprint`: Eq. (7)'s view from the principal frame, the frustum of
// the footprint under the controls, an orthographic projection (WebGPU depth 0..1).
fn projector_with(c: CentreRecord, k: Controls, f: Footprint) -> Projector {
    var p: Projector;
    let nn = try_normalize(c.normal_world.xyz);
    if nn.w == 0.0 {
        return p;
    }
    let n = nn.xyz;
    let em = try_normalize(c.dir_kappa_max.xyz - n * dot(n, c.dir_kappa_max.xyz));
    if em.w == 0.0 {
        return p;
    }
    let e_max = em.xyz;
    let e_min = cross(n, e_max);
    var u = e_max;
    var v = e_min;
    var half = f.half;
    if k.up == 1u {
        u = -e_min;
        v = e_max;
        half = f.half.yx;
    }
    half *= abs(k.scale);
    let s = sin(k.rotate + f.rotate);
    let co = cos(k.rotate + f.rotate);
    let u2 = u * co + v * s;
    let v2 = v * co - u * s;
    let t = k.translate + f.offset;
    let centre_world = c.position_world.xyz + e_max * t.x + e_min * t.y;
    let half_depth = 2.0 * max(half.x, half.y);
    if !(min(half.x, half.y) > 0.0) || !all(abs(centre_world) < vec3<f32>(3.0e38)) || !finite(half_depth) {
        return p;
    }
    let origin = centre_world + n * half_depth;
    // Rows [u, v, n] then the translation: view_from_world.
    let view = mat4x4<f32>(
        vec4<f32>(u2.x, v2.x, n.x, 0.0),
        vec4<f32>(u2.y, v2.y, n.y, 0.0),
        vec4<f32>(u2.z, v2.z, n.z, 0.0),
        vec4<f32>(-dot(u2, origin), -dot(v2, origin), -dot(n, origin), 1.0),
    );
    // glam's right-handed orthographic projection with depth 0..1, over ±half and
    // [0, 2·half_depth].
    let far = 2.0 * half_depth;
    let clip = mat4x4<f32>(
        vec4<f32>(2.0 / (2.0 * half.x), 0.0, 0.0, 0.0),
        vec4<f32>(0.0, 2.0 / (2.0 * half.y), 0.0, 0.0),
        vec4<f32>(0.0, 0.0, 1.0 / (0.0 - far), 0.0),
        vec4<f32>(0.0, 0.0, 0.0 / (0.0 - far), 1.0),
    );
    p.ok = true;
    p.centre_world = centre_world;
    p.anchor_world = c.position_world.xyz;
    p.u = u2;
    p.v = v2;
    p.n = n;
    p.half = half;
    p.clip_from_world = clip * view;
    return p;
}

// `edit_turn` of `set/receivers.rs`: how far the edits turn the normal under the drawn
// ellipse beyond the unedited footprint's, on the centre's local quadric.
fn turn_at(c: CentreRecord, e_max: vec3<f32>, q: vec3<f32>) -> f32 {
    let len = length(q);
    if len <= 0.0 {
        return 0.0;
    }
    let cs = dot(q, e_max) / len;
    let kappa = abs(c.curvature.x * cs * cs + c.curvature.y * (1.0 - cs * cs));
    return asin(min(len * kappa, 1.0));
}

fn rim_turn(c: CentreRecord, e_max: vec3<f32>, centre: vec3<f32>, u: vec3<f32>, v: vec3<f32>, half: vec2<f32>) -> f32 {
    var most = 0.0;
    for (var k = 0u; k < 24u; k++) {
        let a = f32(k) * TAU / 24.0;
        most = max(most, turn_at(c, e_max, centre + u * (half.x * cos(a)) + v * (half.y * sin(a))));
    }
    return most;
}

fn edit_turn(c: CentreRecord, k: Controls, p: Projector, f: Footprint) -> f32 {
    if all(k.translate == vec2<f32>(0.0)) && k.rotate == 0.0 && all(k.scale == vec2<f32>(1.0)) {
        return 0.0;
    }
    let e_max = c.dir_kappa_max.xyz;
    let e_min = cross(c.normal_world.xyz, e_max);
    let drawn = rim_turn(c, e_max, p.centre_world - c.position_world.xyz, p.u, p.v, p.half);
    let s = sin(f.rotate);
    let co = cos(f.rotate);
    let own = rim_turn(c, e_max, e_max * f.offset.x + e_min * f.offset.y, e_max * co + e_min * s, e_min * co - e_max * s, f.half);
    let turn = drawn - own;
    return select(0.0, max(turn, 0.0), finite(turn));
}

// `receiver_rule`: the §4.2 walk's facing rule (`walk` false for a highlight drawn as
// pieces; mode 0 a fixed cosine, 1 interpolated at `angle`) and the per-pixel falloff
// (`Highlight::falloff_cos`; `NO_FALLOFF` where none).
struct Rule {
    walk: bool,
    mode: u32,
    // The fixed cosine (mode 0) or the interpolated test's limit angle (mode 1).
    value: f32,
    falloff: vec2<f32>,
}

fn receiver_rule(c: CentreRecord, k: Controls, p: Projector, f: Footprint, pieces: u32) -> Rule {
    var r: Rule;
    r.falloff = vec2<f32>(-3.0, -2.0);
    if pieces > 0u {
        return r;
    }
    r.walk = true;
    let s = settings.params;
    if s.modes.x != 1u || s.modes.y == 2u {
        r.value = 0.0;
        return r;
    }
    let margin = s.receiver.y;
    let grazing = acos(clamp(s.receiver.x, -1.0, 1.0));
    let turn = edit_turn(c, k, p, f);
    let cap = select(grazing, PI_2 - 0.5 * margin, turn > 0.0);
    let limit = min(acos(clamp(f.cone, -1.0, 1.0)) + turn + margin, cap);
    if s.modes.y == 1u {
        r.value = cos(limit);
        return r;
    }
    let half_margin = 0.5 * max(margin, 1e-3);
    let outer = min(cap + half_margin, PI_2);
    let band = max(min(s.receiver.z, outer - limit), half_margin);
    let zero = min(limit + band, outer);
    r.mode = 1u;
    r.value = zero;
    r.falloff = vec2<f32>(cos(zero), cos(max(zero - 2.0 * band, 0.0)));
    return r;
}

// `queries` of `receiver_pass.rs`: the walk of projector `i` (`object_space`,
// `walk_box`), or none.
fn write_query(i: u32, c: CentreRecord, p: Projector, rule: Rule) {
    var q: Query;
    q.rule = vec4<u32>(NONE, 0u, 0u, 0u);
    let m = frame_data.params.world_from_object;
    let nm = frame_data.params.normal_from_object;
    let inv = transpose(mat3x3<f32>(nm[0].xyz, nm[1].xyz, nm[2].xyz));
    let n_max = inv * p.n;
    let ndc = p.clip_from_world * m;
    let finite_map = all(abs(ndc[0]) < vec4<f32>(3.4e38)) && all(abs(ndc[1]) < vec4<f32>(3.4e38))
        && all(abs(ndc[2]) < vec4<f32>(3.4e38)) && all(abs(ndc[3]) < vec4<f32>(3.4e38));
    if rule.walk && finite_map && all(abs(n_max) < vec3<f32>(3.4e38)) {
        let affine = ndc[0].w == 0.0 && ndc[1].w == 0.0 && ndc[2].w == 0.0 && ndc[3].w == 1.0;
        let a = p.clip_from_world * vec4<f32>(p.anchor_world, 1.0);
        let anchor = a.xyz / a.w;
        var sn = 0.0;
        var cs = 1.0;
        var fixed = rule.value;
        if rule.mode == 1u {
            let angle = clamp(rule.value, 0.0, PI_2);
            sn = sin(angle);
            cs = cos(angle);
            fixed = cs;
        }
        q.ndc_from_object = ndc;
        q.n_max = vec4<f32>(n_max, select(0.0, 1.0, affine));
        q.walk_lo = vec4<f32>(min(vec3<f32>(-1.0, -1.0, 0.0), vec3<f32>(anchor.xy, 0.0)), sn);
        q.walk_hi = vec4<f32>(max(vec3<f32>(1.0, 1.0, 1.0), vec3<f32>(anchor.xy, 1.0)), cs);
        q.rule = vec4<u32>(c.solution.x, rule.mode, bitcast<u32>(fixed), 0u);
    }
    out.queries[i] = q;
}

// `projector_gpu` of `pass.rs` (non-finite values zeroed).
fn finite4(v: vec4<f32>) -> vec4<f32> {
    return select(vec4<f32>(0.0), v, abs(v) < vec4<f32>(3.4e38));
}

fn write_projector(i: u32, p: Projector, k: Controls, opacity: f32, fall: vec2<f32>) {
    let s = settings.params;
    let layer = min(k.layer, u32(s.tracking.w));
    let normal_map = select(0.0, 1.0, layer < 32u && ((s.modes.w >> layer) & 1u) != 0u);
    // Eq. (9): the texture from clip space (`TEX_FROM_CLIP`).
    let tex_from_clip = mat4x4<f32>(
        vec4<f32>(0.5, 0.0, 0.0, 0.0),
        vec4<f32>(0.0, -0.5, 0.0, 0.0),
        vec4<f32>(0.0, 0.0, 1.0, 0.0),
        vec4<f32>(0.5, 0.5, 0.0, 1.0),
    );
    let t = tex_from_clip * p.clip_from_world;
    var r: ProjectorRecord;
    r.tex_from_world = mat4x4<f32>(finite4(t[0]), finite4(t[1]), finite4(t[2]), finite4(t[3]));
    r.axis_u = finite4(vec4<f32>(p.u, fall.x));
    r.axis_v = finite4(vec4<f32>(p.v, fall.y));
    r.normal = finite4(vec4<f32>(p.n, 0.0));
    r.tint = finite4(vec4<f32>(k.tint, clamp(opacity, 0.0, 1.0)));
    r.params = finite4(vec4<f32>(f32(layer), normal_map, k.shininess, 0.0));
    r.neighbours = vec4<u32>(NONE);
    out.records[i] = r;
}

// `HighlightSet::reach`.
fn reach_of(f: Footprint) -> f32 {
    let s = settings.params;
    let fit = select(1.0, f.fit_scale, f.fit_scale > 0.0 && f.fit_scale <= 1.0);
    let extent = min(max(f.half.x, f.half.y) / fit, s.sizes.x);
    return max(s.tracking.x * extent / max(s.tracking.z, 1e-12), 2.0 * s.tracking.y);
}

fn footprint_of(h: TrackedHighlight) -> Footprint {
    var f: Footprint;
    f.half = h.footprint.xy;
    f.offset = h.footprint.zw;
    f.rotate = h.shape.x;
    f.area = h.shape.y;
    f.cone = h.shape.z;
    f.fit_scale = h.shape.w;
    return f;
}

// The next table's entry of a highlight drawn this frame.
fn keep(slot: u32, id: u32, c: CentreRecord, k: Controls, f: Footprint, state: vec3<u32>, opacity: f32) {
    var t: TrackedHighlight;
    t.position_reach = vec4<f32>(c.position_object.xyz, reach_of(f));
    t.sigma = vec4<f32>(k.sigma, 0.0, 0.0, 0.0);
    t.centre = c;
    t.footprint = vec4<f32>(f.half, f.offset);
    t.shape = vec4<f32>(f.rotate, f.area, f.cone, f.fit_scale);
    t.state = vec4<u32>(id, state);
    t.fade = vec4<f32>(opacity, 0.0, 0.0, 0.0);
    next.previous[slot] = t;
}

// One projector drawn (`f` its footprint as the CPU keeps it, `pieces` drawn in its
// place): its record, its walk and the workgroup's note of it.
fn draw(i: u32, id: u32, c: CentreRecord, k: Controls, p: Projector, f: Footprint, opacity: f32, pieces: u32, found: bool) {
    let rule = receiver_rule(c, k, p, f, pieces);
    write_projector(i, p, k, opacity, rule.falloff);
    write_query(i, c, p, rule);
    wg_centre[i] = vec4<f32>(p.centre_world, max(p.half.x, p.half.y));
    wg_anchor[i] = vec4<f32>(c.position_world.xyz, min(p.half.x, p.half.y));
    let flags = select(0u, 1u, found) | select(2u, 0u, pieces > 0u) | select(0u, 4u, k.edited);
    wg_key[i] = vec2<u32>(id, flags);
}

// The frame's highlights (`HighlightSet::footprints`, one invocation: a frame has few),
// then who shares with whom (`share_regions`, one invocation per projector).
@compute @workgroup_size(64)
fn cs_project(@builtin(local_invocation_index) lane: u32) {
    if lane == 0u {
        wg_drawn = build();
    }
    // The records lane 0 wrote (storage) before other lanes write their neighbours.
    storageBarrier();
    let drawn = workgroupUniformLoad(&wg_drawn);
    // `share_regions`: the four nearest whose footprints can overlap (pieces of one
    // highlight always; others when neither carries the user's own edits).
    for (var i = lane; i < drawn; i += 64u) {
        if (wg_key[i].y & 2u) == 0u {
            continue;
        }
        var near = array<vec2<f32>, 4>(vec2<f32>(3.0e38, 0.0), vec2<f32>(3.0e38, 0.0), vec2<f32>(3.0e38, 0.0), vec2<f32>(3.0e38, 0.0));
        var idx = vec4<u32>(NONE);
        let ci = wg_centre[i];
        let ki = wg_key[i];
        for (var j = 0u; j < drawn; j++) {
            let kj = wg_key[j];
            let shares = ki.x == kj.x || ((ki.y & 4u) == 0u && (kj.y & 4u) == 0u);
            if j == i || (kj.y & 2u) == 0u || !shares {
                continue;
            }
            let cj = wg_centre[j];
            let d = distance(ci.xyz, cj.xyz);
            if !(d < ci.w + cj.w) {
                continue;
            }
            for (var s = 0u; s < 4u; s++) {
                if d < near[s].x {
                    for (var m = 3u; m > s; m--) {
                        near[m] = near[m - 1u];
                        idx[m] = idx[m - 1u];
                    }
                    near[s] = vec2<f32>(d, 0.0);
                    idx[s] = j;
                    break;
                }
            }
        }
        out.records[i].neighbours = idx;
    }
}

// The highlights of one frame, in id order, into `projectors` and the next table;
// returns how many projectors were drawn.
fn build() -> u32 {
    let s = settings.params;
    let p_count = min(previous.params.count, MAX_TRACKED);
    // (The room is the CPU's each frame: `prepare_tracked_on_table`.)
    next.params = previous.params;
    next.params.sigma = s.controls_a.w;
    next.params.status = 0u;
    next.params.merged = 0u;
    let status = matched[3];
    let step = s.sizes.w;
    let first_frame = previous.params.tracking == 0u;
    let region_sizing = s.modes.x == 1u;
    var drawn = 0u;
    var kept = 0u;
    var merged = 0u;
    var seed = 0u;
    var next_id = previous.params.next_id;
    // A frame whose regions were not seeded holds its highlights as they were.
    let hold = status != 0u;
    // Sized by regions, the search looked for peaks: `NONE` where it could not find them
    // (more parts without a centre than it keeps), and the frame is drawn without them.
    if !hold && region_sizing && matched[7] == NONE {
        next.params.status = 4u;
    }
    let centre_count = select(matched[5], 0u, hold);
    // Per centre whether a highlight took it.
    var taken: array<u32, 8>;
    for (var w = 0u; w < 8u; w++) {
        taken[w] = 0u;
    }
    if !hold {
        for (var i = 0u; i < p_count; i++) {
            let j = matched[MATCH_AT + i];
            if j != NONE && j < 256u {
                taken[j / 32u] |= 1u << (j % 32u);
            }
        }
    }
    let total = p_count + centre_count;
    for (var e = 0u; e < total; e++) {
        var id = 0u;
        var centre: CentreRecord;
        var found = false;
        var before = false;
        var prev: TrackedHighlight;
        if e < p_count {
            prev = previous.previous[e];
            before = true;
            id = prev.state.x;
            let j = select(matched[MATCH_AT + e], NONE, hold);
            if j != NONE {
                centre = centres[j];
                found = true;
            } else {
                // Placed again on this frame by the search's `cs_replace`.
                centre = centres[REPLACED_AT + e];
                found = hold && prev.state.y != 0u;
            }
        } else {
            let j = e - p_count;
            if (taken[j / 32u] & (1u << (j % 32u))) != 0u || centres[j].position_object.w != 1.0 {
                continue;
            }
            centre = centres[j];
            found = true;
            id = next_id;
            next_id += 1u;
        }
        let k = controls_of(id);
        var has_fp = false;
        var fp: Footprint;
        var fit_seed = NONE;
        let before_fp = footprint_of(prev);
        if hold {
            has_fp = before;
            fp = before_fp;
        } else if !found {
            has_fp = before;
            fp = before_fp;
        } else if !region_sizing {
            fp = eq8_footprint(centre, k.sigma, s.sizes.x);
            has_fp = true;
        } else {
            let r = fits[seed];
            // A walk cut short (its queue's capacity) fits part of its region: the CPU
            // would have grown it; the frame says so.
            if r.flags.w != 0u {
                next.params.status = 3u;
            }
            if r.flags.x == 0u {
                fit_seed = seed;
                fp = fitted(r.ellipse, r.fit.xyz, r.fit.w);
                has_fp = fp.area >= s.sizes.y;
            }
            seed += 1u;
        }
        // The paper's sizing: a projector whose centre lies in the central half of an
        // older found one's frustum is suppressed.
        if has_fp && found && !region_sizing && !hold {
            for (var q = 0u; q < drawn; q++) {
                let a = wg_anchor[q];
                let limit = 0.5 * min(a.w, min(fp.half.x, fp.half.y));
                if (wg_key[q].y & 1u) != 0u && distance(a.xyz, centre.position_world.xyz) < limit {
                    has_fp = false;
                }
            }
        }
        let shown = select(0.0, prev.fade.x, before);
        var opacity = 0.0;
        var is_found = found;
        if hold {
            opacity = shown;
        } else if has_fp && found {
            if before {
                fp = limit_change(before_fp, fp, s.sizes.z);
            }
            opacity = select(min(shown + step, 1.0), 1.0, first_frame);
        } else if has_fp {
            opacity = shown - step;
        } else {
            if found {
                merged += 1u;
            }
            if !before {
                continue;
            }
            fp = before_fp;
            opacity = shown - step;
            is_found = false;
        }
        if opacity <= 0.0 || min(fp.half.x, fp.half.y) <= 0.0 {
            continue;
        }
        let pr = projector_with(centre, k, fp);
        if !pr.ok {
            continue;
        }
        var peak = 0u;
        if hold {
            peak = prev.state.z;
        } else if is_found {
            peak = select(0u, 1u, centre.curvature.z == 1.0);
        } else {
            peak = prev.state.z;
        }
        // The pieces of a long bent region, each edited with the whole as one group.
        var pieces = 0u;
        let whole_at = drawn;
        if drawn >= MAX_DRAWN || kept >= MAX_TRACKED {
            next.params.status = 2u;
            break;
        }
        drawn += 1u;
        if fit_seed != NONE && is_found {
            let r = fits[fit_seed];
            for (var i = 0u; i < min(r.piece_count.x, 6u); i++) {
                let rp = r.pieces[i];
                // A piece has the whole's normal cone.
                let piece = fitted(rp.ellipse, vec3<f32>(rp.fit.xy, r.fit.z), rp.fit.z);
                let edited = group_edit(fp, piece, k);
                let pp = projector_with(centre, k, edited);
                if pp.ok && drawn >= MAX_DRAWN {
                    next.params.status = 2u;
                } else if pp.ok {
                    draw(drawn, id, centre, k, pp, piece, opacity, 0u, is_found);
                    drawn += 1u;
                    pieces += 1u;
                }
            }
        }
        draw(whole_at, id, centre, k, pr, fp, opacity, pieces, is_found);
        keep(kept, id, centre, k, fp, vec3<u32>(select(0u, 1u, is_found), peak, pieces), opacity);
        kept += 1u;
    }
    next.params.count = kept;
    next.params.next_id = next_id;
    // A held frame is no update: the sequence starts (or goes on) with the next built.
    next.params.tracking = select(1u, previous.params.tracking, hold);
    next.params.drawn = drawn;
    next.params.merged = merged;
    // The walks the receivers' room holds (the CPU wrote the room there).
    out.receiver_params.highlight_count = min(drawn, out.receiver_params.highlight_count);
    if hold {
        next.params.status = 1u;
    }
    return drawn;
}
