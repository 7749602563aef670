// Outlines from a normal + depth G-buffer (npr-gpu `outline.rs`): silhouettes and
// creases found from depth and normal discontinuities between neighbouring pixels
// (Saito & Takahashi, "Comprehensible Rendering of 3-D Shapes", SIGGRAPH 1990; Decaudin,
// "Cartoon-looking rendering of 3D scenes", INRIA RR-2919, 1996), composited over the
// caller's colour target. The CPU twin is `npr_gpu::outline::outline_mask_cpu`: change
// both together. Prepended with `common.wgsl` (for `Object`) and
// `fullscreen.wgsl` (the composite's vertex stage).

// ---- Prepass: view-space normal (rgb) and linear view depth (a; 0 = background). ----

struct OutlineCamera {
    clip_from_world: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> camera: OutlineCamera;
@group(1) @binding(0) var<uniform> object: Object;

struct PrepassIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct PrepassOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
};

@vertex
fn vs_normal_depth(v: PrepassIn) -> PrepassOut {
    var out: PrepassOut;
    let world = object.world_from_object * vec4<f32>(v.position, 1.0);
    out.clip = camera.clip_from_world * world;
    out.view_pos = (camera.view_from_world * world).xyz;
    let n_world = object.normal_from_object * v.normal;
    out.view_normal = (camera.view_from_world * vec4<f32>(n_world, 0.0)).xyz;
    return out;
}

@fragment
fn fs_normal_depth(in: PrepassOut) -> @location(0) vec4<f32> {
    let len = length(in.view_normal);
    var n = vec3<f32>(0.0, 0.0, 1.0);
    if len > 0.0 {
        n = in.view_normal / len;
    }
    return vec4<f32>(n, -in.view_pos.z);
}

// ---- Full-screen outline pass. ----

struct OutlineParams {
    // rgb = line colour (linear), a = opacity.
    color: vec4<f32>,
    // Dilation radius in pixels: (width_px - 1) / 2.
    radius_px: f32,
    // cos of the crease angle: neighbours whose normals differ by more are a crease.
    cos_crease: f32,
    // A depth step larger than depth_ratio * (nearer depth) is a silhouette.
    depth_ratio: f32,
    _pad: f32,
};

@group(0) @binding(1) var<uniform> params: OutlineParams;
@group(0) @binding(2) var gbuffer: texture_2d<f32>;

fn inside(p: vec2<i32>, size: vec2<i32>) -> bool {
    return p.x >= 0 && p.y >= 0 && p.x < size.x && p.y < size.y;
}

// Whether pixel `p` is an edge pixel: foreground, and next (4-neighbourhood) to the
// background, to a surface farther by more than the depth ratio, or, at a similar depth,
// to a normal turned by more than the crease angle while p is not the farther one.
// Neighbours outside the image are ignored (no line along the frame). CPU twin:
// `is_edge` in `npr_gpu::outline` (behind `outline_mask_cpu`).
fn is_edge(p: vec2<i32>, size: vec2<i32>) -> bool {
    if !inside(p, size) {
        return false;
    }
    let c = textureLoad(gbuffer, p, 0);
    if !(c.a > 0.0) {
        return false;
    }
    let offsets = array<vec2<i32>, 4>(vec2<i32>(1, 0), vec2<i32>(-1, 0), vec2<i32>(0, 1), vec2<i32>(0, -1));
    for (var k = 0; k < 4; k++) {
        let pq = p + offsets[k];
        if !inside(pq, size) {
            continue;
        }
        let q = textureLoad(gbuffer, pq, 0);
        if !(q.a > 0.0) {
            return true;
        }
        let step = q.a - c.a;
        let limit = params.depth_ratio * min(c.a, q.a);
        if step > limit {
            return true;
        }
        if abs(step) <= limit && step >= 0.0 && dot(c.rgb, q.rgb) < params.cos_crease {
            return true;
        }
    }
    return false;
}

// The composite: `vs_fullscreen` and `FullscreenOut` come from `fullscreen.wgsl`.

@fragment
fn fs_outline(in: FullscreenOut) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(gbuffer));
    let p = vec2<i32>(floor(in.clip.xy));
    let r = i32(floor(params.radius_px));
    let r2 = params.radius_px * params.radius_px;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            if f32(dx * dx + dy * dy) <= r2 && is_edge(p + vec2<i32>(dx, dy), size) {
                return params.color;
            }
        }
    }
    discard;
    // Unreached (the invocation was discarded), but WGSL's behaviour analysis treats
    // `discard` as falling through: Chromium's compiler (Tint) rejects a function that
    // ends in it with "missing return at end of function", where naga accepts it.
    return vec4<f32>(0.0);
}
