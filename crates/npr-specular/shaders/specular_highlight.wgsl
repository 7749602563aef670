// Stylized specular highlights by projective textures: the highlight pass.
// Hwan-Jik Lee and Jung-Ju Choi, "Stylized Specular Reflections Using Projective Textures
// based on Principal Curvature Analysis", Journal of the Korea Computer Graphics Society.
//
// One draw for all highlights (§5: a separate pass over any base shading): the vertex
// stream is a list of (render vertex, projector) pairs, three per receiver triangle
// (§4.2), pulled from storage buffers. Eq. (9) `q = M p`, `uv = ((q.x+1)/2, (1-q.y)/2)`
// is computed in the vertex shader (M = the projector's tex_from_world, which already
// holds the bias and scale). Prepended with common.wgsl.

struct Projector {
    // Eq. (9): world -> texture (u, v, depth, 1) for this orthographic projector.
    tex_from_world: mat4x4<f32>,
    // xyz = world texture-u axis (e_max after rotation), w = the facing falloff's cosine
    // where alpha reaches 0.
    axis_u: vec4<f32>,
    // xyz = world texture-up axis (e_min after rotation), w = the falloff's cosine where
    // alpha is whole.
    axis_v: vec4<f32>,
    // xyz = surface normal N at the centre, w unused.
    normal: vec4<f32>,
    // rgb = linear tint, a = opacity (fades).
    tint: vec4<f32>,
    // x = texture layer, y = 1 for a normal-map layer, z = Blinn exponent, w unused.
    params: vec4<f32>,
    // Highlights sharing this one's region (indices into `projectors`), 0xffffffff for
    // none: a pixel inside several of their ellipses goes to the one it is deepest in.
    neighbours: vec4<u32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
// Interleaved render vertices of the mesh (npr_gpu::Vertex: 3 position, 3 normal, 2 uv).
@group(2) @binding(0) var<storage, read> vertices: array<f32>;
// (render vertex index, projector index) per emitted vertex.
@group(2) @binding(1) var<storage, read> draw_list: array<vec2<u32>>;
@group(2) @binding(2) var<storage, read> projectors: array<Projector>;
// Per render vertex: the surface normal at the highlight set's abstraction scale (w = 1),
// or zero where the set has none (the mesh's own normal is taken).
@group(2) @binding(3) var<storage, read> surface_normals: array<vec4<f32>>;
@group(3) @binding(0) var highlight_textures: texture_2d_array<f32>;
@group(3) @binding(1) var highlight_sampler: sampler;

// The projector's per-fragment data travels as flat varyings, read once per vertex from
// storage; fragments read storage only for the neighbours a region is shared with.
struct VertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) tex: vec3<f32>,
    @location(1) world: vec3<f32>,
    @location(2) @interpolate(flat) tint: vec4<f32>,
    @location(3) @interpolate(flat) params: vec4<f32>,
    @location(4) @interpolate(flat) axis_u: vec3<f32>,
    @location(5) @interpolate(flat) axis_v: vec3<f32>,
    @location(6) @interpolate(flat) normal: vec3<f32>,
    // The surface normal, interpolated (world space), for the facing falloff.
    @location(7) surface_normal: vec3<f32>,
    // (cos where alpha is 0, cos where alpha is whole).
    @location(8) @interpolate(flat) falloff: vec2<f32>,
    @location(9) @interpolate(flat) neighbours: vec4<u32>,
    @location(10) @interpolate(flat) own: u32,
};

// Where a world point lies in projector `j`'s footprint ellipse: 0 at its centre, 1 on its
// rim; above 1 outside it, its depth range or the surface facing it.
fn ellipse_radius(j: u32, world: vec3<f32>, normal: vec3<f32>) -> f32 {
    let p = projectors[j];
    let q = p.tex_from_world * vec4<f32>(world, 1.0);
    let t = q.xyz / q.w;
    let inside = t.z >= 0.0 && t.z <= 1.0 && dot(normal, p.normal.xyz) > p.axis_u.w;
    return select(2.0, length(t.xy * 2.0 - vec2<f32>(1.0)), inside);
}

@vertex
fn vs_highlight(@builtin(vertex_index) index: u32) -> VertexOut {
    let entry = draw_list[index];
    let base = entry.x * 8u;
    let position = vec3<f32>(vertices[base], vertices[base + 1u], vertices[base + 2u]);
    // Same expression as base_shading.wgsl so depth matches bit for bit (LessEqual test).
    let world = object.world_from_object * vec4<f32>(position, 1.0);
    var out: VertexOut;
    out.clip = frame.clip_from_world * world;
    // Eq. (9): q = M p; orthographic, so w = 1.
    let p = projectors[entry.y];
    let q = p.tex_from_world * world;
    out.tex = q.xyz / q.w;
    out.world = world.xyz;
    out.tint = p.tint;
    out.params = p.params;
    out.axis_u = p.axis_u.xyz;
    out.axis_v = p.axis_v.xyz;
    out.normal = p.normal.xyz;
    let own = vec3<f32>(vertices[base + 3u], vertices[base + 4u], vertices[base + 5u]);
    let scaled = surface_normals[entry.x];
    let n = select(own, scaled.xyz, scaled.w > 0.5);
    out.surface_normal = object.normal_from_object * n;
    out.falloff = vec2<f32>(p.axis_u.w, p.axis_v.w);
    out.neighbours = p.neighbours;
    out.own = entry.y;
    return out;
}

@fragment
fn fs_highlight(in: VertexOut) -> @location(0) vec4<f32> {
    // Outside the projector's frustum nothing is projected.
    if any(in.tex.xy < vec2<f32>(0.0)) || any(in.tex.xy > vec2<f32>(1.0)) || in.tex.z < 0.0 || in.tex.z > 1.0 {
        discard;
    }
    let texel = textureSampleLevel(highlight_textures, highlight_sampler, in.tex.xy, i32(in.params.x), 0.0);
    var rgb = in.tint.rgb * texel.rgb;
    var alpha = texel.a * in.tint.a;
    if in.params.y > 0.5 {
        // Normal-map layer (Fig. 6c): the texel is a normal in the projector frame;
        // shade it with Blinn's (N.H)^n, Eq. (2)-(3).
        let t = texel.rgb * 2.0 - vec3<f32>(1.0);
        let n = normalize(t.x * in.axis_u + t.y * in.axis_v + t.z * in.normal);
        let l = light_dir_world(frame, in.world);
        let v = normalize(frame.eye_world.xyz - in.world);
        let h = normalize(l + v);
        let intensity = pow(max(dot(n, h), 0.0), in.params.z);
        rgb = in.tint.rgb * frame.light_color.rgb;
        alpha = alpha * intensity;
    }
    // The normal limit as a falloff smooth per pixel (beyond the paper): the edge is where
    // the surface turns away from the projector, not a triangle edge.
    let surface_normal = normalize(in.surface_normal);
    // A region shared by several highlights is split between them (no pile-ups): the
    // pixel goes to the ellipse it lies deepest in (ties to the lower index).
    let mine = length(in.tex.xy * 2.0 - vec2<f32>(1.0));
    for (var k = 0u; k < 4u; k = k + 1u) {
        let j = in.neighbours[k];
        if j != 0xffffffffu && j < arrayLength(&projectors) {
            let theirs = ellipse_radius(j, in.world, surface_normal);
            if theirs < 1.0 && (theirs < mine || (theirs == mine && j < in.own)) {
                discard;
            }
        }
    }
    let facing = dot(surface_normal, in.normal);
    alpha = alpha * smoothstep(in.falloff.x, in.falloff.y, facing);
    if alpha <= 0.0 {
        discard;
    }
    return vec4<f32>(rgb, alpha);
}
