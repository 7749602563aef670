//! The bad-input corpus `fixtures/bad/`: tiny files, each broken in one way, with the
//! [`super::LoadError::kind`] that loading it must give. `cargo xtask fixtures` writes
//! them and `expected.txt`; a test checks the committed files against this code and
//! loads each one.

use glam::{Vec2, Vec3};

use super::write::{self, PlyEncoding};
use crate::Mesh;

/// A unit tetrahedron with normals and uvs: the valid base the broken files start from.
pub fn tetrahedron() -> Mesh {
    let positions = vec![
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(1.0, -1.0, -1.0),
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(-1.0, -1.0, 1.0),
    ];
    let normals = positions.iter().map(|p| p.normalize()).collect();
    let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE];
    Mesh {
        positions,
        normals,
        uvs,
        indices: vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2],
    }
}

fn gltf_requiring(ext: &str) -> Vec<u8> {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["{ext}"],"extensionsRequired":["{ext}"],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],"accessors":[{{"componentType":5126,"count":3,"type":"VEC3"}}]}}"#
    )
    .into_bytes()
}

/// Every bad file: `(name, bytes, expected kind)`.
pub fn bad() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let tet = tetrahedron();
    let ply_le = write::ply(&tet, PlyEncoding::BinaryLittleEndian);
    let ply_header = ply_le
        .windows(11)
        .position(|w| w == b"end_header\n")
        .map_or(0, |p| p + 11);
    let ascii = write::ply(&tet, PlyEncoding::Ascii);
    let ascii_header = ascii
        .windows(11)
        .position(|w| w == b"end_header\n")
        .map_or(0, |p| p + 11);
    let glb = write::glb(&tet);
    let mut nan = tet.clone();
    nan.positions[2].y = f32::NAN;
    let mut inf = tet.clone();
    inf.positions[1].x = f32::INFINITY;
    let mut out_of_range = tet.clone();
    out_of_range.indices[4] = 7;
    let points = r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":0}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3"}],"bufferViews":[{"buffer":0,"byteLength":12}],"buffers":[{"byteLength":12,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}]}"#;
    vec![
        ("empty.obj", Vec::new(), "empty"),
        ("blank.ply", b"\n  \n".to_vec(), "empty"),
        ("not-utf8.obj", vec![b'v', b' ', 0xff, 0xfe, b'\n'], "parse"),
        ("bad-number.obj", b"v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n".to_vec(), "parse"),
        ("garbage.ply", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR".to_vec(), "parse"),
        ("garbage.gltf", b"{\"asset\": [1, 2,".to_vec(), "parse"),
        ("garbage.glb", b"glTF\x07\0\0\0\x14\0\0\0\0\0\0\0".to_vec(), "parse"),
        ("no-end-header.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n".to_vec(), "truncated"),
        ("truncated-vertices.ply", ply_le[..ply_header + 30].to_vec(), "truncated"),
        ("truncated-faces.ply", ply_le[..ply_le.len() - 5].to_vec(), "truncated"),
        ("truncated.ply", ascii[..ascii_header + 40].to_vec(), "truncated"),
        ("truncated.glb", glb[..glb.len() - 40].to_vec(), "truncated"),
        ("truncated-header.glb", glb[..9].to_vec(), "truncated"),
        ("index-out-of-range.obj", write::obj(&out_of_range).into_bytes(), "index-out-of-range"),
        ("index-out-of-range.ply", write::ply(&out_of_range, PlyEncoding::BinaryBigEndian), "index-out-of-range"),
        ("index-out-of-range.glb", write::glb(&out_of_range), "index-out-of-range"),
        ("nan.obj", write::obj(&nan).into_bytes(), "non-finite"),
        ("inf.ply", write::ply(&inf, PlyEncoding::BinaryLittleEndian), "non-finite"),
        ("nan.glb", write::glb(&nan), "non-finite"),
        ("draco.gltf", gltf_requiring("KHR_draco_mesh_compression"), "unsupported-extension"),
        ("meshopt.gltf", gltf_requiring("EXT_meshopt_compression"), "unsupported-extension"),
        ("quantized.gltf", gltf_requiring("KHR_mesh_quantization"), "unsupported-extension"),
        ("points.gltf", points.as_bytes().to_vec(), "no-triangles"),
        ("lines-only.obj", b"v 0 0 0\nv 1 0 0\nl 1 2\n".to_vec(), "no-triangles"),
        (
            "missing-buffer.gltf",
            br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":12,"uri":"missing-buffer.bin"}]}"#.to_vec(),
            "missing",
        ),
        ("model.stl", b"solid x\nendsolid x\n".to_vec(), "unsupported-format"),
    ]
}

/// `expected.txt`: one `FILE KIND` line per bad file.
pub fn expected_txt() -> String {
    bad()
        .iter()
        .map(|(name, _, kind)| format!("{name} {kind}\n"))
        .collect()
}
