// Inputs of the image-space hatching pass (§2 of Kim & Lee, "Real-time Image-space
// Hatching", 2008): per-pixel tone from Phong shading with variance shadow maps
// (W. Donnelly, A. Lauritzen, "Variance Shadow Maps", I3D 2006, pp. 161-165; the paper's
// reference [4]) and a per-pixel stroke direction theta in [0, pi), a per-vertex surface
// direction projected to the screen. Also the Phong + VSM colour pass that the benchmark
// compares against. Prepended with `common.wgsl`. Rust side: `npr_hatching::ScenePasses`.

struct Scene {
    // World -> light clip space (orthographic for a directional light, perspective for a
    // spot light; depth 0..1).
    light_clip_from_world: mat4x4<f32>,
    // xyz = spot light position, w = 1 / range (spot) or 0 (directional).
    light_pos: vec4<f32>,
    // xyz = spot axis (unit, from the light), w = cos of the outer cone half-angle.
    spot: vec4<f32>,
    // x = minimum variance, y = light-bleeding reduction, z = shadow map size in texels,
    // w = 1 with shadows, 0 without.
    vsm: vec4<f32>,
    // xy = viewport size in pixels, z = cos of the inner cone half-angle, w unused.
    viewport: vec4<f32>,
};

// Surface anchoring (coherent hatching, beyond the paper's §5 shower-door limit): two
// reference views per object, re-taken in turn; a surface point's anchor is where it was
// on the screen at that reference view, at the pose the mesh had then (a snapshot of its
// vertices, `@location(4)` and `(5)` of `vs_scene`). Written by `ScenePasses::record_gbuffer` (buffer
// copies of the frame's and the object's matrices at the reference frame).
struct Anchor {
    clip_from_world: array<mat4x4<f32>, 2>,
    world_from_object: array<mat4x4<f32>, 2>,
};

// x = weight of anchor 1 (anchor 0 gets 1 - x), the cross-fade between the two reference
// views; yzw unused.
struct Coherence {
    weights: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> scene: Scene;
@group(0) @binding(2) var<uniform> coherence: Coherence;
@group(1) @binding(0) var<uniform> object: Object;
@group(1) @binding(1) var<uniform> anchor: Anchor;
// Moments (E[d], E[d^2]) of light depth, Rg32Float, filtered by hand.
@group(2) @binding(0) var shadow_moments: texture_2d<f32>;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

// Light depth of a world point, linear in distance: the orthographic clip depth for a
// directional light, distance / range for a spot light.
// `spot` is `scene.light_pos.w` as the fragment stage receives it (see `SceneOut::light`).
fn light_depth(p_world: vec3<f32>, spot: f32) -> f32 {
    if spot > 0.0 {
        return distance(p_world, scene.light_pos.xyz) * scene.light_pos.w;
    }
    let c = scene.light_clip_from_world * vec4<f32>(p_world, 1.0);
    return c.z / c.w;
}

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    // scene.light_pos.w, passed on (see `SceneOut::light`).
    @location(1) @interpolate(flat) spot: f32,
};

@vertex
fn vs_shadow(v: VertexIn) -> ShadowOut {
    var out: ShadowOut;
    let world = object.world_from_object * vec4<f32>(v.position, 1.0);
    out.world = world.xyz;
    out.clip = scene.light_clip_from_world * world;
    out.spot = scene.light_pos.w;
    return out;
}

// The two moments of Donnelly & Lauritzen 2006 (§3), with the depth-derivative term of
// their §4 added to the second moment to reduce self-shadowing on slopes.
@fragment
fn fs_shadow(in: ShadowOut) -> @location(0) vec4<f32> {
    let d = light_depth(in.world, in.spot);
    let dx = dpdx(d);
    let dy = dpdy(d);
    return vec4<f32>(d, d * d + 0.25 * (dx * dx + dy * dy), 0.0, 0.0);
}

fn load_moments(p: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(shadow_moments));
    return textureLoad(shadow_moments, clamp(p, vec2<i32>(0), size - 1), 0).rg;
}

// Bilinear filtering of the moments (Rg32Float is not filterable everywhere).
fn sample_moments(uv: vec2<f32>) -> vec2<f32> {
    let t = uv * scene.vsm.z - 0.5;
    let i = vec2<i32>(floor(t));
    let f = t - floor(t);
    let a = mix(load_moments(i), load_moments(i + vec2<i32>(1, 0)), f.x);
    let b = mix(load_moments(i + vec2<i32>(0, 1)), load_moments(i + vec2<i32>(1, 1)), f.x);
    return mix(a, b, f.y);
}

// Fraction of light reaching p: Chebyshev's upper bound p_max = s^2 / (s^2 + (d - mu)^2)
// (Donnelly & Lauritzen 2006, Eq. (5)), with a minimum variance and the light-bleeding
// reduction that maps [amount, 1] to [0, 1].
fn shadow_visibility(p_world: vec3<f32>, light: vec2<f32>) -> f32 {
    if light.x == 0.0 {
        return 1.0;
    }
    let lc = scene.light_clip_from_world * vec4<f32>(p_world, 1.0);
    if lc.w <= 0.0 {
        return 1.0;
    }
    let ndc = lc.xyz / lc.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) {
        return 1.0;
    }
    let m = sample_moments(uv);
    let d = light_depth(p_world, light.y);
    if d <= m.x {
        return 1.0;
    }
    let variance = max(m.y - m.x * m.x, scene.vsm.x);
    let dd = d - m.x;
    let p_max = variance / (variance + dd * dd);
    return clamp((p_max - scene.vsm.y) / (1.0 - scene.vsm.y), 0.0, 1.0);
}

struct SceneOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The screen stroke direction as a line field: (cos 2theta, sin 2theta) scaled by
    // nothing, so that d and -d agree and interpolation does not cancel opposite signs.
    @location(2) line: vec2<f32>,
    // The point in the clip space of the two reference views (anchors, see `Anchor`).
    @location(3) ref0: vec4<f32>,
    @location(4) ref1: vec4<f32>,
    // (scene.vsm.w, scene.light_pos.w): shadows on, spot light. The fragment stage
    // branches on these copies, not on the uniforms: Mesa's lavapipe (22.3) recompiles a
    // fragment shader whose branches on uniform values guard enough work ("uniform
    // inlining") at every draw and never frees the variants, about 0.7 MB per pass.
    @location(5) @interpolate(flat) light: vec2<f32>,
};

// Projects the per-vertex surface direction to the screen (§2: "a principal curvature
// direction projected to the screen"): the clip-space images of p and p + eps*dir, in
// pixels, y up. Returns (cos 2theta, sin 2theta), or 0 where the direction is degenerate.
fn screen_line(world: vec3<f32>, clip: vec4<f32>, dir_object: vec3<f32>) -> vec2<f32> {
    let dir_world = (object.world_from_object * vec4<f32>(dir_object, 0.0)).xyz;
    let len = length(dir_world);
    if !(len > 1e-20) || clip.w <= 0.0 {
        return vec2<f32>(0.0);
    }
    let eps = 1e-3 * clip.w;
    let c1 = frame.clip_from_world * vec4<f32>(world + dir_world * (eps / len), 1.0);
    if c1.w <= 0.0 {
        return vec2<f32>(0.0);
    }
    let s = (c1.xy / c1.w - clip.xy / clip.w) * scene.viewport.xy;
    let l2 = dot(s, s);
    if !(l2 > 0.0) {
        return vec2<f32>(0.0);
    }
    return vec2<f32>(s.x * s.x - s.y * s.y, 2.0 * s.x * s.y) / l2;
}

@vertex
fn vs_scene(
    v: VertexIn,
    @location(3) dir: vec3<f32>,
    // The vertex where it was when each anchor was taken (the same as `v.position` on a
    // rigid mesh; a deforming mesh's earlier pose).
    @location(4) anchor_position0: vec3<f32>,
    @location(5) anchor_position1: vec3<f32>,
) -> SceneOut {
    var out: SceneOut;
    let world = object.world_from_object * vec4<f32>(v.position, 1.0);
    out.world = world.xyz;
    out.clip = frame.clip_from_world * world;
    out.normal = normalize(object.normal_from_object * v.normal);
    out.line = screen_line(world.xyz, out.clip, dir);
    let p0 = vec4<f32>(anchor_position0, 1.0);
    let p1 = vec4<f32>(anchor_position1, 1.0);
    out.ref0 = anchor.clip_from_world[0] * (anchor.world_from_object[0] * p0);
    out.ref1 = anchor.clip_from_world[1] * (anchor.world_from_object[1] * p1);
    out.light = vec2<f32>(scene.vsm.w, scene.light_pos.w);
    return out;
}

// Pixel position (y down, the convention of @builtin(position)) of a reference clip-space
// point; the current pixel where the point was behind the reference camera.
fn anchor_pixel(r: vec4<f32>, here: vec2<f32>) -> vec2<f32> {
    if !(r.w > 1e-8) {
        return here;
    }
    let ndc = r.xy / r.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * scene.viewport.xy;
}

// Blinn-Phong (common.wgsl) with the direct light attenuated by the VSM visibility and,
// for a spot light, by its cone; the ambient term is unshadowed.
fn shade(in: SceneOut) -> vec3<f32> {
    let n = normalize(in.normal);
    let l = light_dir_world(frame, in.world);
    let v = normalize(frame.eye_world.xyz - in.world);
    let ambient = object.diffuse.rgb * frame.ambient.rgb;
    let lit = blinn_phong(frame, object, n, l, v);
    var vis = shadow_visibility(in.world, in.light);
    if in.light.y > 0.0 {
        vis = vis * smoothstep(scene.spot.w, scene.viewport.z, dot(-l, scene.spot.xyz));
    }
    return ambient + (lit - ambient) * vis;
}

struct GBufferOut {
    // r = tone, g = theta, b = weight of anchor 1, a = 1 + turn rate (rad/pixel).
    @location(0) main: vec4<f32>,
    // xy = anchor 0, zw = anchor 1, in pixels.
    @location(1) anchors: vec4<f32>,
};

// G-buffer: r = tone (linear luminance of the shaded colour, 1 = paper), g = theta in
// [0, pi) counter-clockwise from +x on screen, b = anchor 1's weight, a = 1 + the turn rate; and the two
// anchors (the pixel's surface point at the two reference views, in pixels).
@fragment
fn fs_gbuffer(in: SceneOut) -> GBufferOut {
    let c = shade(in);
    let tone = clamp(dot(c, vec3<f32>(0.2126, 0.7152, 0.0722)), 0.0, 1.0);
    // How fast the stroke direction turns on the screen: for the unit line vector
    // (cos 2theta, sin 2theta), |d theta| = |d line| / 2 (derivatives in uniform control
    // flow, before any branch).
    let ln = in.line * inverseSqrt(max(dot(in.line, in.line), 1e-20));
    let turn = 0.5 * max(length(dpdx(ln)), length(dpdy(ln)));
    var theta = 0.0;
    if dot(in.line, in.line) > 1e-12 {
        theta = 0.5 * atan2(in.line.y, in.line.x);
        if theta < 0.0 {
            theta = theta + 3.14159265;
        }
        theta = clamp(theta, 0.0, 3.1415925);
    }
    var out: GBufferOut;
    out.main = vec4<f32>(tone, theta, coherence.weights.x, 1.0 + min(turn, 1e3));
    out.anchors = vec4<f32>(anchor_pixel(in.ref0, in.clip.xy), anchor_pixel(in.ref1, in.clip.xy));
    return out;
}

// The comparison frame: the same Phong shading with the same VSM, as colour.
@fragment
fn fs_phong_vsm(in: SceneOut) -> @location(0) vec4<f32> {
    return vec4<f32>(shade(in), 1.0);
}
