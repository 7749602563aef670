// Separable blur of a variance shadow map's moments (Donnelly & Lauritzen, "Variance
// Shadow Maps", I3D 2006, §3.3: the moments may be filtered like colour). A 5-tap binomial
// kernel (1 4 6 4 1)/16, horizontal then vertical, over full-screen triangles. Rust side:
// `npr_hatching::ScenePasses`.

@group(0) @binding(0) var blur_source: texture_2d<f32>;

// `vs_fullscreen` and `FullscreenOut`: npr-gpu's `fullscreen.wgsl`, composed before this file.

fn blur(p: vec2<i32>, step: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(blur_source));
    let w = array<f32, 5>(0.0625, 0.25, 0.375, 0.25, 0.0625);
    var acc = vec4<f32>(0.0);
    for (var k = -2; k <= 2; k++) {
        let q = clamp(p + step * k, vec2<i32>(0), size - 1);
        acc += w[k + 2] * textureLoad(blur_source, q, 0);
    }
    return acc;
}

@fragment
fn fs_blur_h(in: FullscreenOut) -> @location(0) vec4<f32> {
    return blur(vec2<i32>(floor(in.clip.xy)), vec2<i32>(1, 0));
}

@fragment
fn fs_blur_v(in: FullscreenOut) -> @location(0) vec4<f32> {
    return blur(vec2<i32>(floor(in.clip.xy)), vec2<i32>(0, 1));
}
