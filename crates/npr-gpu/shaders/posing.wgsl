// Posing on the GPU: morph targets, then linear blend skinning, written into the mesh's
// own vertex buffer, which every pass then draws (glTF 2.0, §3.7.2.2 Morph Targets and
// §3.7.3 Skins). The CPU reference is `npr_geometry::animation::Rig::pose_mesh`; each
// function below names its Rust twin.
//
// One invocation per vertex of the rig (the file's render vertices); `info[2v + 1].z`
// says where the vertex sits in the uploaded mesh.

// Per rig vertex v, two records:
//   info[2v]     = (first influence, influence count, first morph delta, morph count)
//   info[2v + 1] = (first morph weight, weld representative, output vertex, 0)
@group(0) @binding(0) var<storage, read> base: array<vec4<f32>>;       // 2v: position, 2v+1: normal
@group(0) @binding(1) var<storage, read> info: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read> influences: array<vec2<u32>>; // (palette matrix, weight bits)
@group(0) @binding(3) var<storage, read> morphs: array<vec4<f32>>;     // 2k: position delta, 2k+1: normal delta
@group(0) @binding(4) var<storage, read> palette: array<mat4x4<f32>>;  // joints of every skin, then node globals
@group(0) @binding(5) var<storage, read> weights: array<f32>;          // morph weights of every instance
@group(0) @binding(6) var<storage, read_write> vertices: array<f32>;   // the mesh: 8 floats per vertex

// The normal pass (its own bindings): per rig vertex, the faces around its welded vertex.
@group(0) @binding(8) var<storage, read> n_info: array<vec4<u32>>;
@group(0) @binding(9) var<storage, read> n_offsets: array<u32>;        // per rig vertex, into n_faces
@group(0) @binding(10) var<storage, read> n_faces: array<vec4<u32>>;   // a face's output vertices
@group(0) @binding(11) var<storage, read_write> n_vertices: array<f32>;

const WORKGROUP: u32 = 64u;

fn invocation(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

// `Σ wᵢ Mᵢ` over a vertex's influences. Rust twin: `npr_geometry::animation::skin::blend`.
fn blend(first: u32, count: u32) -> mat4x4<f32> {
    var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    for (var k = 0u; k < count; k++) {
        let inf = influences[first + k];
        m += palette[inf.x] * bitcast<f32>(inf.y);
    }
    return m;
}

// The inverse-transpose of `m`'s linear part as the cofactor matrix times the sign of the
// determinant; `(0, 0, 1)` where the result vanishes. Rust twin:
// `npr_geometry::animation::skin::transform_normal`.
fn transform_normal(m: mat4x4<f32>, n: vec3<f32>) -> vec3<f32> {
    let x = m[0].xyz;
    let y = m[1].xyz;
    let z = m[2].xyz;
    let cof = mat3x3<f32>(cross(y, z), cross(z, x), cross(x, y));
    var r = cof * n;
    if dot(x, cross(y, z)) < 0.0 {
        r = -r;
    }
    let l = dot(r, r);
    if !(l > 0.0) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    return r * inverseSqrt(l);
}

// Vertex `v` morphed and skinned: (position, normal). Rust twin: the body of
// `npr_geometry::animation::Rig::pose_mesh` (`morph`, then `vertex_transforms`).
fn posed(v: u32) -> array<vec3<f32>, 2> {
    let a = info[2u * v];
    let b = info[2u * v + 1u];
    var p = base[2u * v].xyz;
    var n = base[2u * v + 1u].xyz;
    for (var k = 0u; k < a.w; k++) {
        let w = weights[b.x + k];
        p += w * morphs[2u * (a.z + k)].xyz;
        n += w * morphs[2u * (a.z + k) + 1u].xyz;
    }
    let m = blend(a.x, a.y);
    return array<vec3<f32>, 2>((m * vec4<f32>(p, 1.0)).xyz, transform_normal(m, n));
}

@compute @workgroup_size(64)
fn cs_pose(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = invocation(gid, groups);
    if v >= arrayLength(&info) / 2u {
        return;
    }
    let b = info[2u * v + 1u];
    let own = posed(v);
    var p = own[0];
    if b.y != v {
        // A seam duplicate takes its representative's position, as the CPU pose does.
        p = posed(b.y)[0];
    }
    let o = 8u * b.z;
    vertices[o] = p.x;
    vertices[o + 1u] = p.y;
    vertices[o + 2u] = p.z;
    vertices[o + 3u] = own[1].x;
    vertices[o + 4u] = own[1].y;
    vertices[o + 5u] = own[1].z;
}

fn position_of(o: u32) -> vec3<f32> {
    return vec3<f32>(n_vertices[8u * o], n_vertices[8u * o + 1u], n_vertices[8u * o + 2u]);
}

// Area-weighted normals of the posed triangles, gathered per welded vertex (no atomics:
// WebGPU has no float atomics). Rust twin: `npr_geometry::Mesh::recompute_normals`.
@compute @workgroup_size(64)
fn cs_normals(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = invocation(gid, groups);
    if v >= arrayLength(&n_info) / 2u {
        return;
    }
    let b = n_info[2u * v + 1u];
    let r = b.y;
    var acc = vec3<f32>(0.0);
    for (var k = n_offsets[r]; k < n_offsets[r + 1u]; k++) {
        let f = n_faces[k];
        let p0 = position_of(f.x);
        acc += cross(position_of(f.y) - p0, position_of(f.z) - p0);
    }
    var n = vec3<f32>(0.0, 0.0, 1.0);
    let l = dot(acc, acc);
    if l > 0.0 {
        n = acc * inverseSqrt(l);
    }
    let o = 8u * b.z;
    n_vertices[o + 3u] = n.x;
    n_vertices[o + 4u] = n.y;
    n_vertices[o + 5u] = n.z;
}
