// Base shading passes shared by every technique: per-pixel Phong (Blinn-Phong, Lee & Choi
// Eq. (2)-(3)), per-vertex Gouraud, and cel/toon shading with a 1-D ramp texture
// (Lake, Marshall, Harris, Blackstein, "Stylized Rendering Techniques for Scalable
// Real-Time 3D Animation", NPAR 2000). Prepended with `common.wgsl`.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
@group(2) @binding(0) var ramp_texture: texture_2d<f32>;
@group(2) @binding(1) var ramp_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct VertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
};

fn transform(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let world = object.world_from_object * vec4<f32>(v.position, 1.0);
    out.world = world.xyz;
    out.clip = frame.clip_from_world * world;
    out.normal = normalize(object.normal_from_object * v.normal);
    out.color = vec3<f32>(0.0);
    return out;
}

@vertex
fn vs_pixel(v: VertexIn) -> VertexOut {
    return transform(v);
}

// Gouraud: the lighting model evaluated per vertex and interpolated.
@vertex
fn vs_gouraud(v: VertexIn) -> VertexOut {
    var out = transform(v);
    let l = light_dir_world(frame, out.world);
    let view = normalize(frame.eye_world.xyz - out.world);
    out.color = blinn_phong(frame, object, out.normal, l, view);
    return out;
}

@fragment
fn fs_phong(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = light_dir_world(frame, in.world);
    let v = normalize(frame.eye_world.xyz - in.world);
    return vec4<f32>(blinn_phong(frame, object, n, l, v), 1.0);
}

@fragment
fn fs_gouraud(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color, 1.0);
}

// Cel shading (Lake et al. 2000): the ramp is indexed by max(N.L, 0) with nearest
// filtering, so only the ramp's shades appear, modulated by the diffuse albedo.
@fragment
fn fs_cel(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let l = light_dir_world(frame, in.world);
    let s = clamp(dot(n, l), 0.0, 1.0);
    let shade = textureSampleLevel(ramp_texture, ramp_sampler, vec2<f32>(s, 0.5), 0.0).rgb;
    return vec4<f32>(object.diffuse.rgb * shade, 1.0);
}
