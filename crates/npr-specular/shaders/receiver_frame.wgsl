// The §4.2 walk's frame: its values and one query per highlight, composed before the
// shaders that read or write it (`receivers.wgsl` walks from it; `projectors.wgsl`
// writes the queries of a frame whose projectors the GPU built).

// Frame-wide values.
struct ReceiverParams {
    // M⁻ᵀ, the object's normal map (upper 3×3 in the columns' xyz).
    normal_from_object: mat4x4<f32>,
    highlight_count: u32,
    face_count: u32,
    // Visited words per face: one bit per highlight.
    words: u32,
    // Queue (and received) entries per highlight; faces past it are dropped and the
    // highlight is marked as overflowed.
    capacity: u32,
    // 1: M is a similarity, so |M⁻ᵀ n| = `k` for every unit n.
    similar: u32,
    k: f32,
    // Faces the vertex stream holds (three entries each).
    list_faces: u32,
    _pad: u32,
}

// One highlight's walk (`receiver_pass::Query`).
struct Query {
    // The projector's map from object space (`clip_from_world · world_from_object`).
    ndc_from_object: mat4x4<f32>,
    // xyz: M⁻¹ N_max (the facing test in object space); w: 1 when the map is affine.
    n_max: vec4<f32>,
    // The box the walk crosses (frustum and untranslated centre); w: sin and cos of the
    // interpolated test's limit angle.
    walk_lo: vec4<f32>,
    walk_hi: vec4<f32>,
    // x: start face (≥ face count: no walk); y: 0 a fixed cosine, 1 interpolated; z: the
    // fixed cosine's bits.
    rule: vec4<u32>,
}

// The frame's values, then one query per highlight, in one storage buffer (not a
// uniform one: lavapipe inlines a uniform buffer's values into the shader and compiles it
// again whenever they change, which a moving object's transform does every frame).
struct ReceiverFrame {
    params: ReceiverParams,
    queries: array<Query>,
}
