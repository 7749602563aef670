//! glTF 2.0 (`.gltf` JSON with external or data-URI buffers, `.glb`): every triangle
//! primitive of the default scene (or the first scene), node transforms applied, merged
//! into one mesh.
//!
//! The `gltf` crate provides the validated document; the GLB container, the buffers and
//! the accessors are read here with checked byte ranges, so a truncated or inconsistent
//! file is a [`LoadError`] naming the byte, buffer or accessor, never a panic.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use super::{LoadError, LoadNote, Raw};

/// Extensions that do not change geometry: required or not, the mesh reads the same.
fn geometry_neutral(ext: &str) -> bool {
    ext.starts_with("KHR_materials_")
        || ext.starts_with("KHR_texture_")
        || ext.starts_with("EXT_texture_")
        || ext == "KHR_lights_punctual"
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn parse(&self, at: impl Into<String>, reason: impl Into<String>) -> LoadError {
        LoadError::Parse {
            file: self.file.to_string(),
            at: at.into(),
            reason: reason.into(),
        }
    }
    fn truncated(&self, at: impl Into<String>, reason: impl Into<String>) -> LoadError {
        LoadError::Truncated {
            file: self.file.to_string(),
            at: at.into(),
            reason: reason.into(),
        }
    }
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    let s = b.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

/// Splits a GLB into its JSON chunk and optional BIN chunk, checking every length.
fn split_glb<'b>(bytes: &'b [u8], c: &Ctx<'_>) -> Result<(&'b [u8], Option<&'b [u8]>), LoadError> {
    if bytes.len() < 12 {
        return Err(c.truncated(
            format!("byte {}", bytes.len()),
            "the GLB header needs 12 bytes",
        ));
    }
    let version = u32_at(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(c.parse(
            "byte 4",
            format!("GLB version {version}, only 2 is supported"),
        ));
    }
    let length = u32_at(bytes, 8).unwrap_or(0) as usize;
    if length > bytes.len() {
        return Err(c.truncated(
            format!("byte {}", bytes.len()),
            format!("the GLB header says the file has {length} bytes"),
        ));
    }
    let bytes = &bytes[..length];
    let chunk = |at: usize| -> Result<Option<(u32, &'b [u8])>, LoadError> {
        if at >= bytes.len() {
            return Ok(None);
        }
        let (Some(len), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            return Err(c.truncated(
                format!("byte {}", bytes.len()),
                "a GLB chunk header needs 8 bytes",
            ));
        };
        let start = at + 8;
        let end = start + len as usize;
        if end > bytes.len() {
            return Err(c.truncated(
                format!("byte {}", bytes.len()),
                format!("the GLB chunk at byte {at} says it has {len} bytes"),
            ));
        }
        Ok(Some((kind, &bytes[start..end])))
    };
    let json = match chunk(12)? {
        Some((CHUNK_JSON, json)) => json,
        Some((kind, _)) => {
            return Err(c.parse(
                "byte 16",
                format!("first GLB chunk has type {kind:#010x}, not JSON"),
            ));
        }
        None => return Err(c.truncated("byte 12", "the GLB has no JSON chunk")),
    };
    let next = (20 + json.len()).next_multiple_of(4);
    let bin = match chunk(next)? {
        Some((CHUNK_BIN, bin)) => Some(bin),
        _ => None,
    };
    Ok((json, bin))
}

/// Decodes standard base64 (padding optional, whitespace not allowed).
fn base64(s: &str) -> Option<Vec<u8>> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let s = s.trim_end_matches('=').as_bytes();
    if s.len() % 4 == 1 {
        return None;
    }
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    for chunk in s.chunks(4) {
        let mut acc = 0u32;
        for (k, &ch) in chunk.iter().enumerate() {
            acc |= val(ch)? << (18 - 6 * k);
        }
        let bytes = acc.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

/// Decodes `%XX` escapes of a relative URI.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |k: usize| b.get(k).and_then(|&c| (c as char).to_digit(16));
        match (b[i], hex(i + 1), hex(i + 2)) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (c, _, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn load_buffers(
    doc: &gltf::Document,
    bin: Option<&[u8]>,
    dir: Option<&Path>,
    c: &Ctx<'_>,
) -> Result<Vec<Vec<u8>>, LoadError> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let i = b.index();
        let data = match b.source() {
            gltf::buffer::Source::Bin => bin
                .ok_or_else(|| {
                    c.parse(
                        format!("buffer {i}"),
                        "refers to the GLB BIN chunk, which is absent",
                    )
                })?
                .to_vec(),
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let payload = uri
                    .split_once(";base64,")
                    .map(|(_, p)| p)
                    .ok_or_else(|| c.parse(format!("buffer {i}"), "data URI is not base64"))?;
                base64(payload)
                    .ok_or_else(|| c.parse(format!("buffer {i}"), "invalid base64 in data URI"))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let Some(dir) = dir else {
                    return Err(LoadError::UnsupportedFeature {
                        file: c.file.to_string(),
                        at: format!("buffer {i}"),
                        feature: format!(
                            "the external buffer `{uri}` (load from a path instead of bytes)"
                        ),
                    });
                };
                let path = dir.join(percent_decode(uri));
                let label = format!("{} (buffer {i}: {})", c.file, path.display());
                std::fs::read(&path).map_err(|source| {
                    if source.kind() == std::io::ErrorKind::NotFound {
                        LoadError::Missing { file: label }
                    } else {
                        LoadError::Io {
                            file: label,
                            source,
                        }
                    }
                })?
            }
        };
        if data.len() < b.length() {
            return Err(c.truncated(
                format!("buffer {i}"),
                format!(
                    "byteLength is {} but only {} bytes are there",
                    b.length(),
                    data.len()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Reads an accessor as `f64` components (`dims` per element), normalised integers
/// mapped per the glTF spec, every byte range checked.
fn read_accessor(
    acc: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<(Vec<f64>, usize), LoadError> {
    let at = || format!("accessor {}", acc.index());
    if acc.sparse().is_some() {
        return Err(LoadError::UnsupportedFeature {
            file: c.file.to_string(),
            at: at(),
            feature: "a sparse accessor".into(),
        });
    }
    let Some(view) = acc.view() else {
        return Err(LoadError::UnsupportedFeature {
            file: c.file.to_string(),
            at: at(),
            feature: "an accessor without bufferView".into(),
        });
    };
    let dims = match acc.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        d => return Err(c.parse(at(), format!("unexpected accessor type {d:?}"))),
    };
    let ty = acc.data_type();
    let comp = ty.size();
    let elem = comp * dims;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(c.parse(
            at(),
            format!("byteStride {stride} is smaller than an element ({elem} bytes)"),
        ));
    }
    let count = acc.count();
    let data = buffers
        .get(view.buffer().index())
        .map(Vec::as_slice)
        .unwrap_or(&[]);
    let view_end = view.offset().checked_add(view.length());
    let view_bytes = view_end
        .and_then(|e| data.get(view.offset()..e))
        .ok_or_else(|| {
            c.truncated(
                format!("bufferView {}", view.index()),
                format!(
                    "bytes {}..+{} are past the end of buffer {} ({} bytes)",
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    data.len()
                ),
            )
        })?;
    let need = if count == 0 {
        Some(0)
    } else {
        (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(elem))
            .and_then(|x| x.checked_add(acc.offset()))
    };
    if need.is_none_or(|n| n > view_bytes.len()) {
        return Err(c.parse(
            at(),
            format!(
                "{count} elements of {elem} bytes (stride {stride}, offset {}) do not fit in bufferView {} ({} bytes)",
                acc.offset(),
                view.index(),
                view_bytes.len()
            ),
        ));
    }
    let norm = acc.normalized();
    let mut out = Vec::with_capacity(count * dims);
    for k in 0..count {
        let base = acc.offset() + k * stride;
        for d in 0..dims {
            let o = base + d * comp;
            let b = &view_bytes[o..o + comp];
            let v = match ty {
                DataType::I8 => {
                    let x = f64::from(b[0] as i8);
                    if norm { (x / 127.0).max(-1.0) } else { x }
                }
                DataType::U8 => {
                    let x = f64::from(b[0]);
                    if norm { x / 255.0 } else { x }
                }
                DataType::I16 => {
                    let x = f64::from(i16::from_le_bytes([b[0], b[1]]));
                    if norm { (x / 32767.0).max(-1.0) } else { x }
                }
                DataType::U16 => {
                    let x = f64::from(u16::from_le_bytes([b[0], b[1]]));
                    if norm { x / 65535.0 } else { x }
                }
                DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            };
            out.push(v);
        }
    }
    Ok((out, dims))
}

fn vec3s(
    acc: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Vec<Vec3>, LoadError> {
    let (v, dims) = read_accessor(acc, buffers, c)?;
    if dims != 3 {
        return Err(c.parse(
            format!("accessor {}", acc.index()),
            format!("expected VEC3, found {dims} components"),
        ));
    }
    Ok(v.chunks_exact(3)
        .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
        .collect())
}

pub(crate) fn parse(bytes: &[u8], file: &str, dir: Option<&Path>) -> Result<Raw, LoadError> {
    let c = Ctx { file };
    let (json, bin) = if bytes.starts_with(GLB_MAGIC) {
        split_glb(bytes, &c)?
    } else {
        (bytes, None)
    };
    let doc = read_document(json, &c)?;
    let buffers = load_buffers(&doc, bin, dir, &c)?;
    let instances = mesh_instances(&doc, &c)?;
    let mut merged = Merged::default();
    for (mesh, world) in &instances {
        merged.instance(mesh, *world, &buffers, &c)?;
    }
    Ok(merged.into_raw(instances.len()))
}

/// Parses and validates the JSON document, refusing extensions that change geometry.
fn read_document(json: &[u8], c: &Ctx<'_>) -> Result<gltf::Document, LoadError> {
    let root = gltf::json::Root::from_slice(json).map_err(|e| {
        c.parse(
            format!("JSON line {} column {}", e.line(), e.column()),
            super::error::one_line(&e.to_string()),
        )
    })?;
    if let Some(ext) = root
        .extensions_required
        .iter()
        .find(|e| !geometry_neutral(e))
    {
        return Err(LoadError::UnsupportedExtension {
            file: c.file.to_string(),
            extension: ext.clone(),
        });
    }
    // `gltf-json`'s validation indexes the POSITION accessor unchecked: check primitive
    // accessor indices first.
    check_primitive_accessors(&root, c)?;
    validate(root, c)
}

/// Checks that every accessor a primitive refers to exists.
fn check_primitive_accessors(root: &gltf::json::Root, c: &Ctx<'_>) -> Result<(), LoadError> {
    let n_acc = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let bad = prim
                .attributes
                .values()
                .chain(prim.indices.iter())
                .map(|i| i.value())
                .find(|&i| i >= n_acc);
            if let Some(i) = bad {
                return Err(c.parse(
                    format!("meshes[{m}].primitives[{p}]"),
                    format!("accessor {i} does not exist ({n_acc} accessors)"),
                ));
            }
        }
    }
    Ok(())
}

/// Validates the document, tolerating only missing POSITION `min`/`max`.
fn validate(root: gltf::json::Root, c: &Ctx<'_>) -> Result<gltf::Document, LoadError> {
    // `min`/`max`: required by the spec, left out by some exporters, never read here.
    match gltf::Document::from_json(root.clone()) {
        Ok(doc) => Ok(doc),
        Err(gltf::Error::Validation(errs)) => {
            let serious: Vec<_> = errs
                .iter()
                .filter(|(p, _)| {
                    let p = p.to_string();
                    !(p.ends_with(".min") || p.ends_with(".max"))
                })
                .collect();
            match serious.first() {
                None => Ok(gltf::Document::from_json_without_validation(root)),
                Some((path, err)) => Err(c.parse(
                    path.to_string(),
                    format!("invalid glTF: {err} ({} problem(s) in all)", serious.len()),
                )),
            }
        }
        Err(e) => Err(c.parse("document", super::error::one_line(&e.to_string()))),
    }
}

/// Mesh instances: (mesh, world matrix) from the default (or first) scene's graph.
fn mesh_instances<'d>(
    doc: &'d gltf::Document,
    c: &Ctx<'_>,
) -> Result<Vec<(gltf::Mesh<'d>, Mat4)>, LoadError> {
    // Iteratively, with a step bound so a cyclic graph cannot loop; without a scene,
    // every mesh untransformed.
    let mut instances: Vec<(gltf::Mesh<'_>, Mat4)> = Vec::new();
    match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            let mut stack: Vec<(gltf::Node<'_>, Mat4)> =
                scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
            stack.reverse();
            let mut steps = 0usize;
            let limit = doc.nodes().len().max(1) * 64;
            while let Some((node, parent)) = stack.pop() {
                steps += 1;
                if steps > limit {
                    return Err(c.parse("nodes", "the node hierarchy has a cycle"));
                }
                let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
                if let Some(mesh) = node.mesh() {
                    instances.push((mesh, world));
                }
                // Reversed: nodes pop in document order, depth first.
                let at = stack.len();
                stack.extend(node.children().map(|n| (n, world)));
                stack[at..].reverse();
            }
        }
        None => instances.extend(doc.meshes().map(|m| (m, Mat4::IDENTITY))),
    }
    Ok(instances)
}

/// A mesh instance's world transform, for points, normals and winding.
struct Placement {
    /// Positions: the node's world matrix.
    world: Mat4,
    /// Normals: the inverse-transpose of the world matrix's linear part.
    normal: Mat3,
    /// Whether the transform mirrors, so triangles must be rewound.
    flip: bool,
}

impl Placement {
    /// The placement for a node's world matrix.
    fn new(world: Mat4) -> Self {
        Self {
            world,
            normal: Mat3::from_mat4(world).inverse().transpose(),
            flip: Mat3::from_mat4(world).determinant() < 0.0,
        }
    }
}

/// The triangle primitives of every instance merged so far, and what the report says.
#[derive(Default)]
struct Merged {
    raw: Raw,
    /// Whether some primitive has NORMAL.
    any_normals: bool,
    /// Whether some primitive lacks NORMAL.
    some_without_normals: bool,
    /// Whether some primitive has TEXCOORD_0.
    any_uvs: bool,
    /// Point and line primitives skipped, by mode.
    skipped: BTreeMap<String, usize>,
    /// Strip and fan primitives converted.
    strips: usize,
    /// Instances with a transform other than the identity.
    placed: usize,
}

impl Merged {
    /// Adds every triangle primitive of `mesh`, placed by `world`.
    fn instance(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        world: Mat4,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        if world != Mat4::IDENTITY {
            self.placed += 1;
        }
        let place = Placement::new(world);
        for prim in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let mode = prim.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                *self.skipped.entry(format!("{mode:?}")).or_insert(0usize) += 1;
                continue;
            }
            self.primitive(&prim, &at, &place, buffers, c)?;
        }
        Ok(())
    }

    /// Adds one triangle primitive: positions, triangles, normals and uvs.
    fn primitive(
        &mut self,
        prim: &gltf::Primitive<'_>,
        at: &str,
        place: &Placement,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        let positions = primitive_positions(prim, at, buffers, c)?;
        let n = positions.len();
        let ids = primitive_indices(prim, n, at, buffers, c)?;
        let mode = prim.mode();
        if matches!(mode, Mode::TriangleStrip | Mode::TriangleFan) {
            self.strips += 1;
        }
        let mut tris = triangle_list(mode, &ids);
        if place.flip {
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        let raw = &mut self.raw;
        let base = raw.positions.len() as u32;
        raw.triangles
            .extend(tris.iter().map(|t| t.map(|i| i + base)));
        raw.positions
            .extend(positions.iter().map(|&p| place.world.transform_point3(p)));
        self.normals(prim, n, place, buffers, c)?;
        self.uvs(prim, n, buffers, c)
    }

    /// Appends the primitive's NORMALs (transformed), or zeros when it has none.
    fn normals(
        &mut self,
        prim: &gltf::Primitive<'_>,
        n: usize,
        place: &Placement,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        match prim.get(&Semantic::Normals) {
            Some(acc) => {
                self.any_normals = true;
                let normals = vec3s(&acc, buffers, c)?;
                if normals.len() != n {
                    return Err(c.parse(
                        format!("accessor {}", acc.index()),
                        format!("{} normals for {n} positions", normals.len()),
                    ));
                }
                self.raw.normals.extend(
                    normals
                        .iter()
                        .map(|&v| (place.normal * v).normalize_or_zero()),
                );
            }
            None => {
                self.some_without_normals = true;
                self.raw.normals.extend(std::iter::repeat_n(Vec3::ZERO, n));
            }
        }
        Ok(())
    }

    /// Appends the primitive's TEXCOORD_0, or zeros when it has none.
    fn uvs(
        &mut self,
        prim: &gltf::Primitive<'_>,
        n: usize,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        match prim.get(&Semantic::TexCoords(0)) {
            Some(acc) => {
                self.any_uvs = true;
                let (v, dims) = read_accessor(&acc, buffers, c)?;
                if dims != 2 || v.len() != 2 * n {
                    return Err(c.parse(
                        format!("accessor {}", acc.index()),
                        format!("TEXCOORD_0 must be {n} VEC2"),
                    ));
                }
                self.raw.uvs.extend(
                    v.chunks_exact(2)
                        .map(|p| Vec2::new(p[0] as f32, p[1] as f32)),
                );
            }
            None => self.raw.uvs.extend(std::iter::repeat_n(Vec2::ZERO, n)),
        }
        Ok(())
    }

    /// The merged mesh with its notes; `instances` is how many the scene placed.
    fn into_raw(self, instances: usize) -> Raw {
        let mut raw = self.raw;
        if self.some_without_normals {
            if self.any_normals {
                raw.normals_incomplete = Some("some glTF primitives have no NORMAL");
            }
            raw.normals.clear();
        }
        if !self.any_uvs {
            raw.uvs.clear();
        }
        let skipped_total: usize = self.skipped.values().sum();
        for (mode, count) in &self.skipped {
            raw.notes.push(LoadNote::Skipped {
                what: format!("glTF primitives of mode {mode}"),
                count: *count,
            });
        }
        if self.strips > 0 {
            raw.notes.push(LoadNote::StripsConverted {
                primitives: self.strips,
            });
        }
        if self.placed > 0 {
            raw.notes.push(LoadNote::TransformsApplied {
                instances: self.placed,
            });
        }
        raw.found = format!(
            "{instances} mesh instance(s) in the scene, {skipped_total} point/line primitive(s)"
        );
        raw
    }
}

/// The primitive's POSITIONs (untransformed), every one finite.
fn primitive_positions(
    prim: &gltf::Primitive<'_>,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Vec<Vec3>, LoadError> {
    let pos = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| c.parse(at, "no POSITION attribute"))?;
    let positions = vec3s(&pos, buffers, c)?;
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(LoadError::NonFinite {
            file: c.file.to_string(),
            at: format!("{at}, POSITION element {k}"),
            what: format!("position {:?}", positions[k].to_array()),
        });
    }
    Ok(positions)
}

/// The primitive's vertex indices, each below `n`; `0..n` when it has no indices.
fn primitive_indices(
    prim: &gltf::Primitive<'_>,
    n: usize,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Vec<u32>, LoadError> {
    let Some(acc) = prim.indices() else {
        return Ok((0..n as u32).collect());
    };
    let (v, _) = read_accessor(&acc, buffers, c)?;
    let mut ids = Vec::with_capacity(v.len());
    for x in v {
        if !(x >= 0.0 && (x as usize) < n) {
            return Err(LoadError::IndexOutOfRange {
                file: c.file.to_string(),
                at: format!("{at} (indices accessor {})", acc.index()),
                index: x as i64,
                count: n,
            });
        }
        ids.push(x as u32);
    }
    Ok(ids)
}

/// The triangles of a triangle list, strip or fan, all wound like the first one.
fn triangle_list(mode: Mode, ids: &[u32]) -> Vec<[u32; 3]> {
    // Strips: every other triangle has its first two vertices swapped.
    match mode {
        Mode::TriangleStrip => ids
            .windows(3)
            .enumerate()
            .map(|(k, w)| {
                if k % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                }
            })
            .collect(),
        Mode::TriangleFan => {
            let mut t = Vec::new();
            super::fan(ids, &mut t);
            t
        }
        _ => ids.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}
