// Shared declarations: the frame and object uniforms of npr-gpu (`uniforms.rs` mirrors
// these layouts byte for byte) and the Blinn-Phong model (Lee & Choi Eq. (2)-(3)) whose CPU
// twin is `npr_gpu::cpu_twin::blinn_phong`.
//
// This file is prepended to every shader that uses it (see `npr_gpu::shaders::compose`).

struct Frame {
    clip_from_world: mat4x4<f32>,
    // xyz = eye position in world space, w = 1.
    eye_world: vec4<f32>,
    // w = 0: xyz is the direction towards a directional light; w = 1: a point light position.
    light_world: vec4<f32>,
    // rgb = light colour (linear), a = unused.
    light_color: vec4<f32>,
    // rgb = ambient colour (linear), a = unused.
    ambient: vec4<f32>,
};

struct Object {
    world_from_object: mat4x4<f32>,
    // Inverse transpose of the upper 3x3 of world_from_object, stored as 3 padded columns.
    normal_from_object: mat3x3<f32>,
    // rgb = diffuse albedo (linear), a = k_s (specular weight).
    diffuse: vec4<f32>,
    // rgb = specular colour (linear), a = Blinn exponent n.
    specular: vec4<f32>,
};

// Unit vector from a world point towards the light.
fn light_dir_world(frame: Frame, p_world: vec3<f32>) -> vec3<f32> {
    if frame.light_world.w == 0.0 {
        return normalize(frame.light_world.xyz);
    }
    return normalize(frame.light_world.xyz - p_world);
}

// Blinn-Phong, Eq. (2)-(3) of the specular paper: I = k_a + k_d (N.L) + k_s (N.H)^n,
// H = (L + V) / |L + V|. All vectors unit length, world space. Mirrors
// `npr_gpu::cpu_twin::blinn_phong`.
fn blinn_phong(frame: Frame, object: Object, n: vec3<f32>, l: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let n_dot_l = max(dot(n, l), 0.0);
    var spec = 0.0;
    if n_dot_l > 0.0 {
        let h = normalize(l + v);
        spec = object.diffuse.a * pow(max(dot(n, h), 0.0), object.specular.a);
    }
    let diffuse = object.diffuse.rgb * frame.ambient.rgb
        + object.diffuse.rgb * frame.light_color.rgb * n_dot_l;
    return diffuse + object.specular.rgb * frame.light_color.rgb * spec;
}
