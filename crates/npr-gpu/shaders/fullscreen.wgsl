// The full-screen vertex stage shared by every post-process pass (outlines, hatching, the
// VSM blur, the warp's depth resolve): one triangle covering the screen, drawn with
// `draw(0..3, 0..1)` and no vertex buffer. Vertices 0, 1, 2 go to clip (-1, -1), (3, -1),
// (-1, 3). Exported as `npr_gpu::shaders::FULLSCREEN` and composed before the shader that
// uses it (`npr_gpu::shaders::compose`).

struct FullscreenOut {
    @builtin(position) clip: vec4<f32>,
};

// Vertex `i` of the triangle at depth `z`.
fn fullscreen_vertex(i: u32, z: f32) -> FullscreenOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var out: FullscreenOut;
    out.clip = vec4<f32>(uv * 2.0 - 1.0, z, 1.0);
    return out;
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> FullscreenOut {
    return fullscreen_vertex(i, 0.0);
}

// The same triangle at the far plane (depth 1), for a pass that tests against a depth
// buffer: where depth was cleared to 1 (the background) a `Greater` test fails and the pass
// shades nothing.
@vertex
fn vs_fullscreen_far(@builtin(vertex_index) i: u32) -> FullscreenOut {
    return fullscreen_vertex(i, 1.0);
}
