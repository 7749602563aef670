// Post-rendering 3D warping with projective textures: the warp pass of `npr-warp`.
//
// Huiwon Park (박희원) and Insung Ihm (임인성), "Post-Rendering 3D Warping using Projective
// Texture" (투영 텍스처를 이용한 렌더링 후 3차원 와핑), Journal of KIISE (정보과학회논문지),
// 2002. The simplified proxy mesh is drawn at the current pose t2 with both reference
// images (t1, t3) projected onto it (§3.3.1), each from its own reference camera
// (`tex_from_object = bias/scale * clip_from_world_ref * world_from_object_ref`, §2.2), and
// the two are blended per normal bin (§3.3.3). The reference depth test is ours: the
// paper's §3.4 leaves surfaces hidden by other polygons in the reference as open.
//
// Composed after npr-gpu's `fullscreen.wgsl` only (it does not use common.wgsl). Mirrored on the CPU by `npr_warp::pass` (uniform
// layout `WarpObjectUniforms`) and `npr_warp::bins` (the per-bin weights).

struct WarpObject {
    // Object -> clip of the current (warped) camera and pose.
    clip_from_object: mat4x4<f32>,
    // Object -> reference texture space (u w, v w, z, w) for reference 0 and 1.
    tex_from_object0: mat4x4<f32>,
    tex_from_object1: mat4x4<f32>,
    // x, y = near, far of reference 0; z, w = near, far of reference 1.
    ref_near_far: vec4<f32>,
    // x = depth tolerance (world units), y = reference width, z = height, w = surface slack
    // (the proxy's error plus inflation, world units).
    params: vec4<f32>,
    // xyz = reference 0's / 1's eye in object space, w = the angle one reference texel
    // subtends (2 tan(fov_y / 2) / height), so w * pixel_angle is a texel's size there.
    eye0_object: vec4<f32>,
    eye1_object: vec4<f32>,
    // Linear colour of the fill-floor shader (`fs_fill`) and of wireframes.
    fill_color: vec4<f32>,
};

@group(0) @binding(0) var ref0_color: texture_2d<f32>;
@group(0) @binding(1) var ref0_depth: texture_depth_2d;
@group(0) @binding(2) var ref1_color: texture_2d<f32>;
@group(0) @binding(3) var ref1_depth: texture_depth_2d;
@group(0) @binding(4) var color_sampler: sampler;
@group(1) @binding(0) var<uniform> object: WarpObject;
// Per normal bin (the draw's instance index): x = opacity of reference 0, y = of reference 1
// (§3.3.3 ramps, written each frame by `npr_warp::bins::BinPlan`).
@group(1) @binding(1) var<storage, read> bin_weights: array<vec4<f32>>;

struct WarpOut {
    @builtin(position) clip: vec4<f32>,
    // Homogeneous reference texture coordinates, interpolated perspective-correctly and
    // divided per fragment (projective texturing, §2.2).
    @location(0) tex0: vec4<f32>,
    @location(1) tex1: vec4<f32>,
    @location(2) @interpolate(flat) weight0: f32,
    // How far (along the reference ray, either way) the reference's stored surface may lie
    // from the proxy point and still be the point's surface, per reference: the proxy's
    // slack plus a texel's depth extent, both growing as the surface is seen at a grazing
    // angle.
    @location(3) tolerance: vec2<f32>,
};

// §3.3.1: the proxy at its current pose, with each reference camera's texture matrix
// applied to the same surface point as it stood when that reference was rendered: for a
// rigid proxy the current vertex (`position0 == position1 == position`), for a deforming
// one (ours) the vertex of the proxy's snapshot at reference i's pose, so a reference's
// texels stay on the surface point they show while the body moves. `instance_index` is
// the normal bin (§3.3.2).
@vertex
fn vs_warp(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(3) position0: vec3<f32>,
    @location(4) normal0: vec3<f32>,
    @location(5) position1: vec3<f32>,
    @location(6) normal1: vec3<f32>,
    @builtin(instance_index) bin: u32,
) -> WarpOut {
    let p = vec4<f32>(position, 1.0);
    var out: WarpOut;
    out.clip = object.clip_from_object * p;
    out.tex0 = object.tex_from_object0 * vec4<f32>(position0, 1.0);
    out.tex1 = object.tex_from_object1 * vec4<f32>(position1, 1.0);
    out.weight0 = bin_weights[bin].x;
    let cos0 = dot(normal0, normalize(object.eye0_object.xyz - position0));
    let cos1 = dot(normal1, normalize(object.eye1_object.xyz - position1));
    let slack = object.params.w;
    let texel = vec2<f32>(out.tex0.w * object.eye0_object.w, out.tex1.w * object.eye1_object.w);
    let grazing = max(vec2<f32>(cos0, cos1), vec2<f32>(0.05));
    out.tolerance = object.params.x + (slack + 1.5 * texel) / grazing;
    return out;
}

// Texel holding `uv` in a reference of the given size, clamped to the image.
fn texel_of(uv: vec2<f32>) -> vec2<i32> {
    let size = object.params.yz;
    let t = vec2<i32>(floor(uv * size));
    return clamp(t, vec2<i32>(0), vec2<i32>(size) - vec2<i32>(1));
}

fn in_frame(uv: vec2<f32>) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
}

// What reference i says about a proxy point (the reference depth test, ours: the paper's
// §3.4 leaves surfaces hidden by other polygons open). As with a shadow map, the point's
// distance from the reference camera (`t.w`, the clip w of a perspective camera) is
// compared with the distance of the surface the reference stored at its texel:
// - `see`: the stored surface is within `tolerance` of the point along the reference ray
//   (nearer by more: the point is hidden there; farther by more: it floats in empty
//   space); `tolerance` covers the proxy's error and inflation and a texel's depth extent,
//   seen at the proxy's angle;
// - `empty`: the texel shows background (cleared depth 1) or the stored surface is more
//   than `tolerance` behind the point: no surface lies near the point, which is off the
//   object (the proxy bulges past the true surface);
// - `gap`: how far the stored surface is in front of the point (hidden by that much).
// Mirrors `npr_warp::pass::reference_sees` and `reference_empty`.
struct Look {
    see: bool,
    empty: bool,
    gap: f32,
    // The bilinear colour sample, premultiplied by coverage (see `unpremultiply`).
    color: vec4<f32>,
};

// `coverage` is the bilinear alpha of the reference at the point: below 1/2 the point lies
// outside the object's silhouette in that reference, located to a fraction of a texel
// (the nearest texel's depth alone would snap the silhouette to the reference's grid).
// `min_alpha` is the coverage below which the point counts as off the object: 1/2 for
// aliased references; near 0 with MSAA, where the fragment's sample mask
// (`coverage_mask`) places the silhouette per sample instead. CPU twins:
// `npr_warp::pass::reference_sees` and `reference_empty`.
fn look(t: vec4<f32>, uv: vec2<f32>, stored_depth: f32, near: f32, far: f32, tolerance: f32, color: vec4<f32>, min_alpha: f32) -> Look {
    var out: Look;
    out.see = false;
    out.empty = false;
    out.gap = 3.4e38;
    out.color = color;
    if !in_frame(uv) {
        return out;
    }
    if stored_depth >= 1.0 || color.a < min_alpha {
        out.empty = true;
        return out;
    }
    // WebGPU (0..1) perspective depth back to view distance.
    let seen = near * far / (far - stored_depth * (far - near));
    out.gap = t.w - seen;
    out.see = abs(out.gap) <= tolerance;
    out.empty = -out.gap > tolerance;
    return out;
}

fn look0(in: WarpOut, uv0: vec2<f32>, min_alpha: f32) -> Look {
    let d0 = textureLoad(ref0_depth, texel_of(uv0), 0);
    let c0 = textureSampleLevel(ref0_color, color_sampler, uv0, 0.0);
    return look(in.tex0, uv0, d0, object.ref_near_far.x, object.ref_near_far.y, in.tolerance.x, c0, min_alpha);
}

fn look1(in: WarpOut, uv1: vec2<f32>, min_alpha: f32) -> Look {
    let d1 = textureLoad(ref1_depth, texel_of(uv1), 0);
    let c1 = textureSampleLevel(ref1_color, color_sampler, uv1, 0.0);
    return look(in.tex1, uv1, d1, object.ref_near_far.z, object.ref_near_far.w, in.tolerance.y, c1, min_alpha);
}

// A bilinear reference lookup. References are cleared to transparent black, so a filtered
// sample is premultiplied by coverage: dividing by alpha averages only the object's texels
// and keeps the background out of silhouette pixels.
fn unpremultiply(c: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(c.rgb / max(c.a, 1e-4), 1.0);
}

fn color0(uv: vec2<f32>) -> vec4<f32> {
    return unpremultiply(textureSampleLevel(ref0_color, color_sampler, uv, 0.0));
}

fn color1(uv: vec2<f32>) -> vec4<f32> {
    return unpremultiply(textureSampleLevel(ref1_color, color_sampler, uv, 0.0));
}

// Which reference colours a fragment, from what the primary reference p (the one the bin's
// ramp favours) and the other one q say about the proxy point (ours, beyond §3.4):
// 0 = p's colour, 1 = q's colour, -1 = discard. A reference that sees the point gives its
// colour, p first. A primary that finds the point in empty space drops the fragment (the
// proxy bulges past the true surface there); one that has it hidden (the open problem of
// §3.4) defers to q. Hidden in both, the reference whose stored surface is nearer the
// point is the better guess. (Trusting either reference's "seen" before the primary's
// "empty" measured 38.4 against 33.0 dB with the exact mesh as proxy but 26.5 against
// 28.1 dB with the bunny's 2 % proxy: the rim spills; the benchmark's proxies decide.)
fn choose(p: Look, q: Look) -> i32 {
    if p.see {
        return 0;
    }
    if p.empty {
        return -1;
    }
    if q.see {
        return 1;
    }
    if q.empty {
        return -1;
    }
    return select(1, 0, p.gap <= q.gap);
}

// A depth-tested fragment's colour and how much of it comes from reference 0 (1: reference
// 0 alone, 0: reference 1 alone), for the MSAA sample mask.
struct Shade {
    color: vec4<f32>,
    w0: f32,
};

// §3.3.3, bins seen by reference 0 only (or whose ramp gives reference 0 full opacity):
// one depth load and one colour lookup where reference 0 sees the point; otherwise
// `choose` decides with reference 1.
fn single0(in: WarpOut, min_alpha: f32) -> Shade {
    let uv0 = in.tex0.xy / in.tex0.w;
    let l0 = look0(in, uv0, min_alpha);
    if l0.see {
        return Shade(unpremultiply(l0.color), 1.0);
    }
    let uv1 = in.tex1.xy / in.tex1.w;
    let l1 = look1(in, uv1, min_alpha);
    let pick = choose(l0, l1);
    if pick < 0 {
        discard;
    }
    if pick == 1 {
        return Shade(unpremultiply(l1.color), 0.0);
    }
    return Shade(unpremultiply(l0.color), 1.0);
}

// As `single0` with the references' roles swapped.
fn single1(in: WarpOut, min_alpha: f32) -> Shade {
    let uv1 = in.tex1.xy / in.tex1.w;
    let l1 = look1(in, uv1, min_alpha);
    if l1.see {
        return Shade(unpremultiply(l1.color), 0.0);
    }
    let uv0 = in.tex0.xy / in.tex0.w;
    let l0 = look0(in, uv0, min_alpha);
    let pick = choose(l1, l0);
    if pick < 0 {
        discard;
    }
    if pick == 1 {
        return Shade(unpremultiply(l0.color), 1.0);
    }
    return Shade(unpremultiply(l1.color), 0.0);
}

// §3.3.3, bins seen by both references: both drawn and blended with the bin's opacity
// ramp `weight0` (reference 1 gets 1 - weight0). With the depth test a reference that does
// not see the point never enters the blend; the primary is the one with weight >= 1/2.
fn blend(in: WarpOut, min_alpha: f32) -> Shade {
    let uv0 = in.tex0.xy / in.tex0.w;
    let uv1 = in.tex1.xy / in.tex1.w;
    let l0 = look0(in, uv0, min_alpha);
    let l1 = look1(in, uv1, min_alpha);
    let c0 = unpremultiply(l0.color);
    let c1 = unpremultiply(l1.color);
    if l0.see && l1.see {
        return Shade(mix(c1, c0, in.weight0), in.weight0);
    }
    if in.weight0 >= 0.5 {
        let pick = choose(l0, l1);
        if pick < 0 {
            discard;
        }
        return Shade(select(c0, c1, pick == 1), select(1.0, 0.0, pick == 1));
    }
    let pick = choose(l1, l0);
    if pick < 0 {
        discard;
    }
    return Shade(select(c1, c0, pick == 1), select(0.0, 1.0, pick == 1));
}

// Aliased targets: coverage 1/2 places the silhouette at a fraction of a texel.
@fragment
fn fs_single0(in: WarpOut) -> @location(0) vec4<f32> {
    return single0(in, 0.5).color;
}

@fragment
fn fs_single1(in: WarpOut) -> @location(0) vec4<f32> {
    return single1(in, 0.5).color;
}

@fragment
fn fs_blend(in: WarpOut) -> @location(0) vec4<f32> {
    return blend(in, 0.5).color;
}

// MSAA (ours): the references were rendered with 4× MSAA and resolved, so a rim texel's
// alpha is the share of it the object covers. A fragment whose reference coverage is
// above `MSAA_MIN_ALPHA` is shaded (with the coverage-normalised colour) and its sample
// mask keeps the samples at which the reference coverage, looked up at the sample's own
// point of the reference (the fragment's uv moved by the sample's offset through the uv
// derivatives), reaches 1/2; the resolve then blends the rim with what lies behind, as
// the full render's MSAA does. The proxy's own edges are multisampled by the rasteriser.
const MSAA_MIN_ALPHA: f32 = 0.02;

struct MsaaOut {
    @location(0) color: vec4<f32>,
    @builtin(sample_mask) mask: u32,
};

// Reference coverage at `uv` blended as the colour was (`w0` of reference 0).
fn coverage_at(uv0: vec2<f32>, uv1: vec2<f32>, w0: f32) -> f32 {
    var a = 0.0;
    if w0 > 0.0 {
        a += w0 * textureSampleLevel(ref0_color, color_sampler, uv0, 0.0).a;
    }
    if w0 < 1.0 {
        a += (1.0 - w0) * textureSampleLevel(ref1_color, color_sampler, uv1, 0.0).a;
    }
    return a;
}

// The standard 4× sample positions (Vulkan, D3D, Metal), as offsets from the pixel centre.
fn sample_offset(i: u32) -> vec2<f32> {
    switch i {
        case 0u: { return vec2<f32>(-0.125, -0.375); }
        case 1u: { return vec2<f32>(0.375, -0.125); }
        case 2u: { return vec2<f32>(-0.375, 0.125); }
        default: { return vec2<f32>(0.125, 0.375); }
    }
}

// Uv derivatives of both references per pixel (x then y), taken in uniform control flow.
struct UvJacobian {
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    dx0: vec2<f32>,
    dy0: vec2<f32>,
    dx1: vec2<f32>,
    dy1: vec2<f32>,
};

fn jacobian(in: WarpOut) -> UvJacobian {
    let uv0 = in.tex0.xy / in.tex0.w;
    let uv1 = in.tex1.xy / in.tex1.w;
    return UvJacobian(uv0, uv1, dpdx(uv0), dpdy(uv0), dpdx(uv1), dpdy(uv1));
}

fn coverage_mask(j: UvJacobian, w0: f32) -> u32 {
    if coverage_at(j.uv0, j.uv1, w0) >= 0.999 {
        return 0xFu;
    }
    var mask = 0u;
    for (var i = 0u; i < 4u; i++) {
        let o = sample_offset(i);
        let a = coverage_at(j.uv0 + j.dx0 * o.x + j.dy0 * o.y, j.uv1 + j.dx1 * o.x + j.dy1 * o.y, w0);
        if a >= 0.5 {
            mask |= 1u << i;
        }
    }
    return mask;
}

fn msaa_out(shade: Shade, j: UvJacobian) -> MsaaOut {
    let mask = coverage_mask(j, shade.w0);
    if mask == 0u {
        discard;
    }
    return MsaaOut(shade.color, mask);
}

// MSAA references, one-sample warp (ours): the colour premultiplied by the reference's
// coverage at the pixel centre (bilinear, as `coverage_at`) and blended over what is
// behind (premultiplied-alpha blending), so the warped rim fades into the background as
// the multisampled full render's does, for the cost of a one-sample pass. Inner
// silhouettes need nothing: there the resolved reference already holds both surfaces.
fn blend_out(shade: Shade, in: WarpOut) -> vec4<f32> {
    let a = coverage_at(in.tex0.xy / in.tex0.w, in.tex1.xy / in.tex1.w, shade.w0);
    return vec4<f32>(shade.color.rgb * a, a);
}

@fragment
fn fs_single0_cover(in: WarpOut) -> @location(0) vec4<f32> {
    return blend_out(single0(in, MSAA_MIN_ALPHA), in);
}

@fragment
fn fs_single1_cover(in: WarpOut) -> @location(0) vec4<f32> {
    return blend_out(single1(in, MSAA_MIN_ALPHA), in);
}

@fragment
fn fs_blend_cover(in: WarpOut) -> @location(0) vec4<f32> {
    return blend_out(blend(in, MSAA_MIN_ALPHA), in);
}

@fragment
fn fs_single0_msaa(in: WarpOut) -> MsaaOut {
    let j = jacobian(in);
    return msaa_out(single0(in, MSAA_MIN_ALPHA), j);
}

@fragment
fn fs_single1_msaa(in: WarpOut) -> MsaaOut {
    let j = jacobian(in);
    return msaa_out(single1(in, MSAA_MIN_ALPHA), j);
}

@fragment
fn fs_blend_msaa(in: WarpOut) -> MsaaOut {
    let j = jacobian(in);
    return msaa_out(blend(in, MSAA_MIN_ALPHA), j);
}

// The paper's pass as published (§3.3.1–§3.3.3): the reference image projected as it is,
// no depth test, so texels outside the object project the reference's (transparent black)
// background. Reference 0 only.
@fragment
fn fs_single0_paper(in: WarpOut) -> @location(0) vec4<f32> {
    return textureSampleLevel(ref0_color, color_sampler, in.tex0.xy / in.tex0.w, 0.0);
}

// The paper's pass as published: reference 1 only.
@fragment
fn fs_single1_paper(in: WarpOut) -> @location(0) vec4<f32> {
    return textureSampleLevel(ref1_color, color_sampler, in.tex1.xy / in.tex1.w, 0.0);
}

// The paper's pass as published: both references blended with the bin's ramp (§3.3.3).
@fragment
fn fs_blend_paper(in: WarpOut) -> @location(0) vec4<f32> {
    let c0 = textureSampleLevel(ref0_color, color_sampler, in.tex0.xy / in.tex0.w, 0.0);
    let c1 = textureSampleLevel(ref1_color, color_sampler, in.tex1.xy / in.tex1.w, 0.0);
    return mix(c1, c0, in.weight0);
}

// The paper's pass with coverage-normalised lookups (ours, no depth test): reference 0 only.
@fragment
fn fs_single0_coverage(in: WarpOut) -> @location(0) vec4<f32> {
    return color0(in.tex0.xy / in.tex0.w);
}

// The paper's pass with coverage-normalised lookups: reference 1 only.
@fragment
fn fs_single1_coverage(in: WarpOut) -> @location(0) vec4<f32> {
    return color1(in.tex1.xy / in.tex1.w);
}

// The paper's pass with coverage-normalised lookups: both blended with the bin's ramp.
@fragment
fn fs_blend_coverage(in: WarpOut) -> @location(0) vec4<f32> {
    return mix(color1(in.tex1.xy / in.tex1.w), color0(in.tex0.xy / in.tex0.w), in.weight0);
}

// The fill floor: the proxy with a constant colour, the least any warp pass can cost per
// pixel (used by the benchmark's ceiling `k FULL / (FULL + k FILL)`) and for wireframes.
@fragment
fn fs_fill(in: WarpOut) -> @location(0) vec4<f32> {
    return object.fill_color;
}

// The depth resolve of an MSAA reference (WebGPU resolves colour only): each texel keeps
// the nearest of its samples, so a rim texel, whose colour is the object's share of it
// (alpha = coverage), has the object's depth for the depth test. A full-screen triangle
// writing `frag_depth` into the single-sample reference depth (compare always).
@group(0) @binding(5) var resolve_depth_ms: texture_depth_multisampled_2d;

// The vertex stage is `vs_fullscreen` of npr-gpu's `fullscreen.wgsl`, composed before
// this file.

@fragment
fn fs_resolve_depth(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    let t = vec2<i32>(frag.xy);
    var d = 1.0;
    let n = i32(textureNumSamples(resolve_depth_ms));
    for (var i = 0; i < n; i++) {
        d = min(d, textureLoad(resolve_depth_ms, t, i));
    }
    return d;
}
