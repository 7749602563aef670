//! Small writers for the formats [`super::load`] reads: test meshes, fixtures, and
//! exporting a processed mesh. Positions, normals, uvs and triangles are written as they
//! are (`f32`, `u32` indices).

use crate::Mesh;

/// Wavefront OBJ text: `v`, `vn`, `vt` lines and `f v/vt/vn` faces.
pub fn obj(mesh: &Mesh) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in &mesh.normals {
        let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
    }
    for t in &mesh.uvs {
        let _ = writeln!(s, "vt {} {}", t.x, t.y);
    }
    let (hn, ht) = (!mesh.normals.is_empty(), !mesh.uvs.is_empty());
    for t in mesh.triangles() {
        s.push('f');
        for i in t.map(|i| i + 1) {
            match (ht, hn) {
                (true, true) => {
                    let _ = write!(s, " {i}/{i}/{i}");
                }
                (false, true) => {
                    let _ = write!(s, " {i}//{i}");
                }
                (true, false) => {
                    let _ = write!(s, " {i}/{i}");
                }
                (false, false) => {
                    let _ = write!(s, " {i}");
                }
            }
        }
        s.push('\n');
    }
    s
}

/// The encoding of a PLY file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    /// `format ascii 1.0`.
    Ascii,
    /// `format binary_little_endian 1.0`.
    BinaryLittleEndian,
    /// `format binary_big_endian 1.0`.
    BinaryBigEndian,
}

/// A PLY file: `vertex` with `x y z nx ny nz u v` floats (normals and uvs only when the
/// mesh has them for every vertex), `face` with a `uchar uint vertex_indices` list.
pub fn ply(mesh: &Mesh, encoding: PlyEncoding) -> Vec<u8> {
    let n = mesh.positions.len();
    let has_n = mesh.normals.len() == n;
    let has_t = mesh.uvs.len() == n;
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    let mut h = format!("ply\nformat {format} 1.0\nelement vertex {n}\n");
    h += "property float x\nproperty float y\nproperty float z\n";
    if has_n {
        h += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if has_t {
        h += "property float u\nproperty float v\n";
    }
    h += &format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.triangle_count()
    );
    let mut out = h.into_bytes();
    let mut floats = Vec::new();
    let vertex = |i: usize, f: &mut Vec<f32>| {
        f.clear();
        f.extend(mesh.positions[i].to_array());
        if has_n {
            f.extend(mesh.normals[i].to_array());
        }
        if has_t {
            f.extend(mesh.uvs[i].to_array());
        }
    };
    for i in 0..n {
        vertex(i, &mut floats);
        match encoding {
            PlyEncoding::Ascii => {
                let line: Vec<String> = floats.iter().map(f32::to_string).collect();
                out.extend(line.join(" ").bytes());
                out.push(b'\n');
            }
            PlyEncoding::BinaryLittleEndian => {
                floats.iter().for_each(|f| out.extend(f.to_le_bytes()));
            }
            PlyEncoding::BinaryBigEndian => {
                floats.iter().for_each(|f| out.extend(f.to_be_bytes()));
            }
        }
    }
    for t in mesh.triangles() {
        match encoding {
            PlyEncoding::Ascii => out.extend(format!("3 {} {} {}\n", t[0], t[1], t[2]).bytes()),
            PlyEncoding::BinaryLittleEndian => {
                out.push(3);
                t.iter().for_each(|i| out.extend(i.to_le_bytes()));
            }
            PlyEncoding::BinaryBigEndian => {
                out.push(3);
                t.iter().for_each(|i| out.extend(i.to_be_bytes()));
            }
        }
    }
    out
}

/// A GLB container around a JSON document and an optional BIN chunk (both padded to 4
/// bytes, JSON with spaces, BIN with zeros).
pub fn glb_container(json: &str, bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |len: usize| len.next_multiple_of(4) - len;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.map_or(0, |b| b.len() + pad(b.len()));
    let total = 12 + 8 + json_len + if bin.is_some() { 8 + bin_len } else { 0 };
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json_len as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json.bytes());
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    if let Some(b) = bin {
        out.extend((bin_len as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(b);
        out.extend(std::iter::repeat_n(0u8, pad(b.len())));
    }
    out
}

/// Appends one primitive's data (positions, then normals and uvs when the mesh has one
/// per vertex, then `u32` indices) to `bin`, one bufferView and one accessor per array.
/// Returns the JSON of those `bufferViews` and `accessors` (to splice into a document's
/// arrays) and the primitive object (`attributes`, `indices`, mode 4). Views and
/// accessors are numbered alike, from `first`: pass the number of accessors written so
/// far, and keep the two arrays in step.
pub fn glb_primitive(
    mesh: &Mesh,
    bin: &mut Vec<u8>,
    first: usize,
) -> (Vec<String>, Vec<String>, String) {
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut add = |bytes: &[u8], count: usize, ty: &str, comp: u32, target: u32, minmax: &str| {
        let offset = bin.len();
        bin.extend(bytes);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let view = first + views.len();
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{},"target":{target}}}"#,
            bytes.len()
        ));
        accessors.push(format!(
            r#"{{"bufferView":{view},"componentType":{comp},"count":{count},"type":"{ty}"{minmax}}}"#
        ));
    };
    let f32s = |v: &mut dyn Iterator<Item = f32>| v.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
    let n = mesh.positions.len();
    let (lo, hi) = mesh.positions.iter().fold(
        (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let minmax = format!(
        r#","min":[{},{},{}],"max":[{},{},{}]"#,
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
    );
    let mut attrs = vec![format!(r#""POSITION":{first}"#)];
    add(
        &f32s(&mut mesh.positions.iter().flat_map(|p| p.to_array())),
        n,
        "VEC3",
        5126,
        34962,
        &minmax,
    );
    if mesh.normals.len() == n {
        attrs.push(format!(r#""NORMAL":{}"#, first + 1));
        add(
            &f32s(&mut mesh.normals.iter().flat_map(|p| p.to_array())),
            n,
            "VEC3",
            5126,
            34962,
            "",
        );
    }
    if mesh.uvs.len() == n {
        attrs.push(format!(r#""TEXCOORD_0":{}"#, first + attrs.len()));
        add(
            &f32s(&mut mesh.uvs.iter().flat_map(|p| p.to_array())),
            n,
            "VEC2",
            5126,
            34962,
            "",
        );
    }
    let ind = first + attrs.len();
    let idx: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    add(&idx, mesh.indices.len(), "SCALAR", 5125, 34963, "");
    let prim = format!(
        r#"{{"attributes":{{{}}},"indices":{ind},"mode":4}}"#,
        attrs.join(",")
    );
    (views, accessors, prim)
}

/// A GLB holding `mesh` as one primitive of one mesh on one node, without transform.
pub fn glb(mesh: &Mesh) -> Vec<u8> {
    let mut bin = Vec::new();
    let (views, accessors, prim) = glb_primitive(mesh, &mut bin, 0);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{prim}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    glb_container(&json, Some(&bin))
}
