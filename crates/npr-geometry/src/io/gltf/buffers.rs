//! The GLB container, the buffers and the accessors, every byte range checked.

use std::path::Path;

use glam::Vec3;
use gltf::accessor::{DataType, Dimensions};

use super::Ctx;
use crate::io::LoadError;

pub(super) const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    let s = b.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

/// Splits a GLB into its JSON chunk and optional BIN chunk, checking every length.
pub(super) fn split_glb<'b>(
    bytes: &'b [u8],
    c: &Ctx<'_>,
) -> Result<(&'b [u8], Option<&'b [u8]>), LoadError> {
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

pub(super) fn load_buffers(
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
pub(super) fn read_accessor(
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
        // Columns of 4 components need no padding for any component type.
        Dimensions::Mat4 => 16,
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

pub(super) fn vec3s(
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
