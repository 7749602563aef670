// The image-space hatching pass of Yongjin Kim and Seungyong Lee, "Real-time Image-space
// Hatching" (실시간 영상 공간 해칭), Journal of the Korea Computer Graphics Society, 2008:
// Eq. (1) (§3.1), Eq. (2)-(3) (§3.2) and §3.3, in one fragment shader over a full-screen
// triangle. Each pixel reads only its own tone and direction from the G-buffer.
// CPU twin: `npr_hatching::CpuHatcher` (crates/npr-hatching/src/cpu.rs); the two
// read the same uniform block (`HatchUniforms`) and must stay in step.

struct Hatch {
    // Per bin k: (cos, sin) of theta_k = k*dtheta and of the offset partition's
    // theta_k = (k + 1/2)*dtheta, each divided by the stroke scale (pixels per texel).
    bins: array<vec4<f32>, 24>,
    // rgb = ink (linear), a = 1 / dtheta.
    ink: vec4<f32>,
    // rgb = paper (linear), a = max coverage of the tonal art map.
    paper: vec4<f32>,
    // x = (tones - 1) / max coverage.
    tone: vec4<f32>,
    // x = bins, y = mode (0 cut-and-paste, 1 blended, 2 offset partition; the shader
    // branches on its copy, the pipeline constant MODE),
    // z = map size - 1 (texel mask), w = tones.
    config: vec4<u32>,
    // x = stroke space: 0 screen (the paper: Eq. (1) rotates the pixel position), 1 surface
    // (Eq. (1) rotates the pixel's surface anchors, cross-faded; see `fs_hatch`); yzw unused.
    space: vec4<u32>,
    // Short strokes where the direction field turns (off when w = 0): x = how many times
    // shorter the short strokes are, y = turn rate (rad/pixel) below which strokes are
    // long, z = 1 / (turn rate of all-short strokes - y), w = 1 when on.
    length: vec4<f32>,
};

@group(0) @binding(0) var<uniform> hatch: Hatch;
// Pipeline constants mirroring `hatch.space.x` and `hatch.length.w > 0`, so that each
// pipeline variant compiles only the lookups it uses (a software rasterizer may run both
// sides of a uniform branch). `HatchPass` builds the four variants and picks one.
override SURFACE: bool = false;
override SHORT_STROKES: bool = false;
// Which surface anchors the variant reads: 2 = both, cross-faded by the
// G-buffer's weight; 0 or 1 = that anchor alone, for a frame whose weight is 0 or 1 on
// every pixel (`ScenePasses::anchor_weight`), with the same result as 2 there.
override ANCHORS: u32 = 2u;
// The blend mode, mirroring `hatch.config.y` (0 cut-and-paste, 1 blended, 2 offset
// partition): lavapipe runs every mode's lookups behind a branch on the uniform, so each
// mode is its own pipeline variant.
override MODE: u32 = 2u;
// The tonal art map as tone pairs (`TonalArtMap::upload_tone_pairs`): layer s holds slice
// s in r and slice s + 1 in g (Rg8Unorm), light to dark; fetched nearest, one fetch per
// rotated position for both slices the tone blends.
@group(0) @binding(1) var tam: texture_2d_array<f32>;
// The G-buffer: r = tone (1 = paper), g = theta in [0, pi), b = weight of anchor 1,
// a = 1 + the direction field's turn rate in rad/pixel on surfaces, 0 elsewhere.
@group(0) @binding(2) var gbuffer: texture_2d<f32>;
// The surface anchors: xy = anchor 0, zw = anchor 1 (pixels at two reference views).
@group(0) @binding(3) var anchors: texture_2d<f32>;
// Bilinear with wrap-around (`HatchPass`'s `tam_sampler`). The surface variants read the
// map through it: their lookup positions, anchored on the surface, move by fractions of a
// texel from frame to frame, and a nearest read would snap stroke edges from texel to
// texel (shimmer). The paper's screen space reads texels nearest, as Eq. (1) indexes them.
@group(0) @binding(4) var tam_sampler: sampler;

// `vs_fullscreen`, `vs_fullscreen_far` and `FullscreenOut`: npr-gpu's `fullscreen.wgsl`,
// composed before this file. The scene's pass (`HatchPass::record_scene`) draws at the far
// plane against the G-buffer depth: the background fails `Greater` and is never shaded,
// its paper colour coming from the pass's clear.

// f(u_k, v_k) of Eq. (2): the pixel (x, y) rotated by theta_k (Eq. (1), §3.1), read from
// the map nearest with wrap-around (filtered in the surface variants), blended between
// slices `slice` and `slice + 1` by `a`.
// `cs` = (cos theta_k, sin theta_k) / stroke scale. Mirrors `CpuHatcher::stroke_texel`.
// `k` shortens the strokes (which run along u) k times.
fn stroke_texel(cs: vec2<f32>, p: vec2<f32>, slice: i32, a: f32, k: f32) -> f32 {
    let u = (cs.x * p.x - cs.y * p.y) * k;
    let v = cs.y * p.x + cs.x * p.y;
    let mask = i32(hatch.config.z);
    if SURFACE {
        // Filtered through `tam_sampler` (texel centres at (i + 1/2) / size, wrapping),
        // with the fraction between centres eased to f^2 (3 - 2f): strokes slide
        // continuously and stay nearly as crisp as a nearest read (plain bilinear blurs
        // thin pen lines, and their blur grows as the anchors magnify). Mirrors
        // `CpuHatcher::filtered_texel`.
        let size = f32(hatch.config.z + 1u);
        let q = vec2<f32>(u, v) - 0.5;
        let i = floor(q);
        let f = q - i;
        let e = f * f * (3.0 - 2.0 * f);
        let filtered = textureSampleLevel(tam, tam_sampler, (i + e + 0.5) / size, slice, 0.0).rg;
        return filtered.x + (filtered.y - filtered.x) * a;
    }
    let t = vec2<i32>(i32(floor(u)) & mask, i32(floor(v)) & mask);
    let pair = textureLoad(tam, t, slice, 0).rg;
    return pair.x + (pair.y - pair.x) * a;
}

// Bin k's (cos, sin) / stroke scale, k taken modulo the bin count. The modulo is
// k - n*floor(k/n) in floats, exact for any |k| below 2^20 (k/n is then at least 1/n away
// from the next integer or exactly on it), because integer `%` has no vector instruction
// and a software rasterizer runs it lane by lane. The CPU twin indexes the
// same bin (`CpuHatcher::bin_cs`, `rem_euclid`).
fn bin_cs(k: i32, offset: bool) -> vec2<f32> {
    let n = f32(hatch.config.x);
    let b = hatch.bins[k - i32(n) * i32(floor(f32(k) / n))];
    if offset {
        return b.zw;
    }
    return b.xy;
}

// Eq. (2)-(3), §3.2: sum_k w_k f(u_k, v_k), w_k = 1 - |theta - theta_k| / dtheta, on the
// partition offset by `offset` (0 or 1/2 bin, §3.3). Only the nearest bin and its
// neighbour on theta's side have non-zero weight (1 - |d| and |d|). Mirrors
// `CpuHatcher::blended`.
fn blended(t: f32, offset: bool, p: vec2<f32>, slice: i32, a: f32, k: f32) -> f32 {
    var tt = t;
    if offset {
        tt = t - 0.5;
    }
    let q = i32(floor(tt + 0.5));
    let d = tt - f32(q);
    var k1 = q - 1;
    var w1 = -d;
    if d >= 0.0 {
        k1 = q + 1;
        w1 = d;
    }
    let f0 = stroke_texel(bin_cs(q, offset), p, slice, a, k);
    let f1 = stroke_texel(bin_cs(k1, offset), p, slice, a, k);
    return (1.0 - w1) * f0 + w1 * f1;
}

// Ink coverage of the pixel centred at p for a tone in [0, 1] and theta in [0, pi):
// Eq. (1) (mode 0), Eq. (2)-(3) (mode 1), or §3.3 offset partition mixed 50/50 (mode 2),
// the tone interpolated between the two nearest slices. Mirrors `CpuHatcher::coverage`.
fn hatch_coverage(p: vec2<f32>, tone: f32, theta: f32, k: f32) -> f32 {
    let max_cov = hatch.paper.a;
    let c = clamp(1.0 - tone, 0.0, max_cov);
    // Slice 0 is blank paper: no lookups needed (they would all read 0).
    if c <= 0.0 {
        return 0.0;
    }
    let s = c * hatch.tone.x;
    let slice = min(max(i32(floor(s)), 0), i32(hatch.config.w) - 2);
    let a = s - f32(slice);
    let t = theta * hatch.ink.a;
    if MODE == 0u {
        let q = i32(floor(t + 0.5));
        return stroke_texel(bin_cs(q, false), p, slice, a, k);
    }
    if MODE == 1u {
        return blended(t, false, p, slice, a, k);
    }
    return 0.5 * blended(t, false, p, slice, a, k) + 0.5 * blended(t, true, p, slice, a, k);
}

// Two fixed stroke lengths blended by the direction field's turn rate
// (beyond the paper's §5): long strokes where the field is calm, `length.x` times shorter
// where it turns fast, blended like the direction bins (a per-pixel scale would tear the
// texture). Mirrors `CpuHatcher::length_blended`.
fn length_blended(p: vec2<f32>, tone: f32, theta: f32, turn: f32) -> f32 {
    var w = 0.0;
    if SHORT_STROKES && hatch.length.w > 0.0 {
        w = clamp((turn - hatch.length.y) * hatch.length.z, 0.0, 1.0);
    }
    var c0 = 0.0;
    var c1 = 0.0;
    if w < 1.0 {
        c0 = hatch_coverage(p, tone, theta, 1.0);
    }
    if w > 0.0 {
        c1 = hatch_coverage(p, tone, theta, hatch.length.x);
    }
    return c0 + (c1 - c0) * w;
}

// Coverage at the pixel's two surface anchors, cross-faded by w (the weight of anchor 1):
// strokes drawn where the surface point was at a reference view move with the surface,
// while θ, tone and the stroke scale stay screen-space (constant density; the reference
// views are re-taken in turn, so the scale never drifts far). Mirrors
// `CpuHatcher::anchored_coverage`.
fn anchored_coverage(an: vec4<f32>, w: f32, tone: f32, theta: f32, turn: f32) -> f32 {
    // Outside the cross-fade: one anchor's lookups, not both (lavapipe runs both sides of
    // a per-pixel branch, so the variant is chosen per frame on the CPU).
    if ANCHORS == 0u {
        return length_blended(an.xy, tone, theta, turn);
    }
    if ANCHORS == 1u {
        return length_blended(an.zw, tone, theta, turn);
    }
    var c0 = 0.0;
    var c1 = 0.0;
    if w < 1.0 {
        c0 = length_blended(an.xy, tone, theta, turn);
    }
    if w > 0.0 {
        c1 = length_blended(an.zw, tone, theta, turn);
    }
    return c0 + (c1 - c0) * w;
}

@fragment
fn fs_hatch(in: FullscreenOut) -> @location(0) vec4<f32> {
    let pix = vec2<i32>(floor(in.clip.xy));
    let g = textureLoad(gbuffer, pix, 0);
    let turn = max(g.a - 1.0, 0.0);
    var c = 0.0;
    if !SURFACE || hatch.space.x == 0u {
        c = length_blended(in.clip.xy, g.r, g.g, turn);
    } else {
        c = anchored_coverage(textureLoad(anchors, pix, 0), g.b, g.r, g.g, turn);
    }
    return vec4<f32>(hatch.paper.rgb + (hatch.ink.rgb - hatch.paper.rgb) * c, 1.0);
}
