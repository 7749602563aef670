// The full-screen vertex stage shared by every post-process pass (outlines, hatching, the
// VSM blur, the warp's depth resolve): one triangle covering the screen, drawn with
// `draw(0..3, 0..1)` and no vertex buffer. Vertices 0, 1, 2 go to clip (-1, -1), (3, -1),
// (-1, 3). Exported as `npr_gpu::shaders::FULLSCREEN` and composed before the shader that
// uses it (`npr_gpu::shaders::compose`).

struct FullscreenOut {
    @builtin(position) clip: vec4<f32>,
};

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> FullscreenOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var out: FullscreenOut;
    out.clip = vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
    return out;
}
