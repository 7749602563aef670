// The region growth's frame: its values and seeds, and the fits it gives, composed before
// the shaders that read or write them (`regions.wgsl` grows from it; `tracking.wgsl`
// writes the seeds of a frame seeded on the GPU; `projectors.wgsl` reads the fits).

// Frame-wide values.
struct RegionParams {
    world_from_object: mat4x4<f32>,
    // M⁻ᵀ, the object's normal map (upper 3×3 in the columns' xyz).
    normal_from_object: mat4x4<f32>,
    // xyz: the light's position (w = 1) or the direction towards it (w = 0).
    light: vec4<f32>,
    // xyz: the eye's position or the direction towards it.
    eye: vec4<f32>,
    seed_count: u32,
    face_count: u32,
    // Visited words per face: one bit per seed.
    words: u32,
    // Queue entries per seed; faces past it are dropped and the seed marked overflowed.
    capacity: u32,
    // A frame seeded on the GPU (`tracking.wgsl`): the seeds it has room for (more, and
    // none is seeded), and a new highlight's σ (the global controls').
    track_room: u32,
    track_sigma: f32,
    pad: vec2<u32>,
}

// One seed (`grow::Part`): its centre (world; w: σ), its projector frame (the axis n,
// w: 1 when the centre has a frame; e_u = e_max, e_v = e_min), its start face (x; y: 1
// when an earlier seed starts on the same face, so it is covered; for a frame seeded on
// the GPU, `tracking.wgsl`, z: the centre's place in the search's list, w: its face,
// even where it has no frame to grow).
struct Seed {
    origin: vec4<f32>,
    n: vec4<f32>,
    e_u: vec4<f32>,
    e_v: vec4<f32>,
    start: vec4<u32>,
}

// The frame's values and seeds. A storage buffer, not a uniform one: lavapipe inlines
// a uniform buffer's values into the shader and compiles it again whenever they change,
// which the object's transform does every frame of a moving model (0.4–0.65 s a frame).
struct RegionFrameData {
    params: RegionParams,
    seeds: array<Seed>,
}

// One seed's result: the moments of the faces it won on its projector's plane (area, the
// first moments, the second (uu, uv, vv) about the centre), the smallest cos of their
// normals with the axis, the ellipse (half extents, offset, rotation), and flags (status:
// 0 fitted, 1 covered, 2 empty; faces won; faces walked; overflowed); `fit` holds the
// rotation, the region's area, the cone and the ellipse's overlap scale. A long bent
// region is also cut into `piece_count.x` pieces along its length (`split.rs`).
struct RegionFit {
    moments: vec4<f32>,
    second: vec4<f32>,
    ellipse: vec4<f32>,
    fit: vec4<f32>,
    flags: vec4<u32>,
    piece_count: vec4<u32>,
    pieces: array<RegionPiece, 6>,
}

// One piece of a bent region: its ellipse (half extents, offset) and its rotation, area
// and overlap scale (w unused).
struct RegionPiece {
    ellipse: vec4<f32>,
    fit: vec4<f32>,
}
