//! Stanford PLY (ASCII, binary little and big endian) through `ply-rs-bw`, read straight
//! into typed vertex and face records.
//!
//! Vertex: `x y z` of any scalar type; optional `nx ny nz`; texture coordinates as
//! `u v`, `s t`, `texture_u texture_v` or `texture_s texture_t`. Face: a `vertex_indices`
//! or `vertex_index` list of any integer types; polygons are fan-triangulated. Other
//! elements (edges, materials, ...) are read and ignored.

use std::io::{BufReader, ErrorKind};

use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::{LoadError, LoadNote, Raw, fan};

/// One `vertex` element: every field optional, filled by name.
#[derive(Default)]
struct PlyVertex {
    p: [f64; 3],
    n: [f64; 3],
    uv: [f64; 2],
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v.into(),
        Property::UChar(v) => v.into(),
        Property::Short(v) => v.into(),
        Property::UShort(v) => v.into(),
        Property::Int(v) => v.into(),
        Property::UInt(v) => v.into(),
        Property::Float(v) => v.into(),
        Property::Double(v) => v,
        _ => return None,
    })
}

fn int_list(p: Property) -> Option<Vec<i64>> {
    fn conv<T: Into<i64>>(v: Vec<T>) -> Vec<i64> {
        v.into_iter().map(Into::into).collect()
    }
    Some(match p {
        Property::ListChar(v) => conv(v),
        Property::ListUChar(v) => conv(v),
        Property::ListShort(v) => conv(v),
        Property::ListUShort(v) => conv(v),
        Property::ListInt(v) => conv(v),
        Property::ListUInt(v) => conv(v),
        _ => return None,
    })
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.p[0],
            "y" => &mut self.p[1],
            "z" => &mut self.p[2],
            "nx" => &mut self.n[0],
            "ny" => &mut self.n[1],
            "nz" => &mut self.n[2],
            "u" | "s" | "texture_u" | "texture_s" => &mut self.uv[0],
            "v" | "t" | "texture_v" | "texture_t" => &mut self.uv[1],
            _ => return PropertyAccessResult::Ignored,
        };
        match scalar(&property) {
            Some(v) => {
                *slot = v;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::UnsupportedType,
        }
    }
}

/// One `face` element.
#[derive(Default)]
struct PlyFace(Vec<i64>);

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if name != "vertex_indices" && name != "vertex_index" {
            return PropertyAccessResult::Ignored;
        }
        match int_list(property) {
            Some(v) => {
                self.0 = v;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::UnsupportedType,
        }
    }
}

/// Any other element: read and dropped.
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// ply-rs's message in a person's words: `Line 2: Couldn't parse line.; String: 'c'; Error:
/// ParseError { .. }` becomes `couldn't parse line: 'c'` (the line is already in `at`, and
/// the grammar's internals say nothing to the user).
fn parser_message(e: &ply_rs_bw::parser::ParseError) -> String {
    let text = super::error::one_line(&e.to_string());
    let text = text.split("; Error:").next().unwrap_or("");
    let text = match text.split_once(": ") {
        Some((line, rest)) if line.starts_with("Line ") => rest,
        _ => text,
    };
    let text = text.replace(".; String:", ":");
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => "unreadable".into(),
    }
}

fn has(e: &ElementDef, names: &[&str]) -> bool {
    names.iter().any(|n| e.properties.contains_key(*n))
}

fn scalar_size(t: &ScalarType) -> usize {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

pub(crate) fn parse(bytes: &[u8], file: &str) -> Result<Raw, LoadError> {
    let parse_err = |at: String, reason: String| LoadError::Parse {
        file: file.to_string(),
        at,
        reason,
    };
    if !bytes.starts_with(b"ply") {
        return Err(parse_err(
            "byte 0".into(),
            "missing the `ply` magic line (is this really a PLY file?)".into(),
        ));
    }
    // A parser error as `truncated` (with what was expected) or `parse` (its message).
    let classify =
        |e: &ply_rs_bw::parser::ParseError, truncated: bool, at: String, expected: &str| {
            if truncated {
                LoadError::Truncated {
                    file: file.to_string(),
                    at,
                    reason: expected.to_string(),
                }
            } else {
                parse_err(at, parser_message(e))
            }
        };
    let mut reader = Reader::new(BufReader::new(bytes));
    let vparser = Parser::<PlyVertex>::new();
    let header = vparser.read_header(&mut reader).map_err(|e| {
        let at = e
            .line()
            .map_or("header".into(), |l| format!("header line {l}"));
        let truncated = e.kind() == ErrorKind::UnexpectedEof;
        classify(&e, truncated, at, "the header has no `end_header` line")
    })?;
    let vdef = header
        .elements
        .get("vertex")
        .ok_or_else(|| parse_err("header".into(), "no `vertex` element".into()))?;
    if !(has(vdef, &["x"]) && has(vdef, &["y"]) && has(vdef, &["z"])) {
        return Err(parse_err(
            "header".into(),
            "the `vertex` element lacks an `x`, `y` or `z` property".into(),
        ));
    }
    // Binary with fixed-size vertices: check the vertex block fits before reading it, to
    // name the byte where the data runs out.
    let body = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .and_then(|p| {
            bytes[p..]
                .iter()
                .position(|&b| b == b'\n')
                .map(|q| p + q + 1)
        });
    if header.encoding != Encoding::Ascii {
        let mut offset = body.unwrap_or(bytes.len()) as u128;
        for (name, e) in &header.elements {
            let size: Option<usize> = e
                .properties
                .values()
                .map(|p| match &p.data_type {
                    PropertyType::Scalar(t) => Some(scalar_size(t)),
                    PropertyType::List(..) => None,
                })
                .sum();
            let Some(size) = size else { break };
            let end = offset + size as u128 * e.count as u128;
            if end > bytes.len() as u128 {
                return Err(LoadError::Truncated {
                    file: file.to_string(),
                    at: format!("byte {}", bytes.len()),
                    reason: format!(
                        "{} `{name}` elements of {size} bytes need the file to reach byte {end}",
                        e.count
                    ),
                });
            }
            offset = end;
        }
    }

    let last_line = bytes.iter().filter(|&&b| b == b'\n').count() + 1;
    let element_err = |name: &str, e: ply_rs_bw::parser::ParseError| {
        let at = match e.line() {
            Some(l) => format!("line {l} (element `{name}`)"),
            None => format!("element `{name}`"),
        };
        // ASCII cut mid-line: the parser sees a short last line, not the end of the file.
        let cut_last_line = !bytes.ends_with(b"\n") && e.line() == Some(last_line);
        let truncated = e.kind() == ErrorKind::UnexpectedEof || cut_last_line;
        classify(
            &e,
            truncated,
            at,
            "the file ends before the elements its header announces",
        )
    };
    let fparser = Parser::<PlyFace>::new();
    let sparser = Parser::<Skip>::new();
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (name, def) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = vparser
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| element_err(name, e))?;
            }
            "face" => {
                faces = fparser
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| element_err(name, e))?;
            }
            _ => {
                sparser
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| element_err(name, e))?;
            }
        }
    }

    let mut raw = Raw::default();
    let nv = vertices.len();
    raw.positions = vertices
        .iter()
        .map(|v| Vec3::from(v.p.map(|c| c as f32)))
        .collect();
    raw.vertex_at = Some((0..nv).map(|i| format!("vertex element {i}")).collect());
    if has(vdef, &["nx"]) && has(vdef, &["ny"]) && has(vdef, &["nz"]) {
        raw.normals = vertices
            .iter()
            .map(|v| Vec3::from(v.n.map(|c| c as f32)))
            .collect();
    }
    let u = has(vdef, &["u", "s", "texture_u", "texture_s"]);
    let v = has(vdef, &["v", "t", "texture_v", "texture_t"]);
    if u && v {
        raw.uvs = vertices
            .iter()
            .map(|v| Vec2::new(v.uv[0] as f32, v.uv[1] as f32))
            .collect();
    }
    let (mut polygons, mut small) = (0, 0);
    let mut poly = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        poly.clear();
        for &i in &f.0 {
            if !(0..nv as i64).contains(&i) {
                return Err(LoadError::IndexOutOfRange {
                    file: file.to_string(),
                    at: format!("face element {k}"),
                    index: i,
                    count: nv,
                });
            }
            poly.push(i as u32);
        }
        match poly.len() {
            0..=2 => small += 1,
            3 => {}
            _ => polygons += 1,
        }
        fan(&poly, &mut raw.triangles);
    }
    if polygons > 0 {
        raw.notes.push(LoadNote::Triangulated { polygons });
    }
    if small > 0 {
        raw.notes.push(LoadNote::Skipped {
            what: "PLY faces with fewer than 3 vertices".into(),
            count: small,
        });
    }
    raw.found = format!("{nv} vertices and {} faces", faces.len());
    Ok(raw)
}
