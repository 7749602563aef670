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
    ElementDef, Encoding, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType,
    ScalarType,
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
    let r = PlyReader { bytes, file };
    if !bytes.starts_with(b"ply") {
        return Err(r.parse_err(
            "byte 0".into(),
            "missing the `ply` magic line (is this really a PLY file?)".into(),
        ));
    }
    let mut reader = Reader::new(BufReader::new(bytes));
    let header = r.read_header(&mut reader)?;
    let vdef = r.vertex_def(&header)?;
    r.check_binary_sizes(&header)?;
    let (vertices, faces) = r.read_elements(&mut reader, &header)?;
    let mut raw = vertex_attributes(&vertices, vdef);
    r.triangulate_faces(&faces, vertices.len(), &mut raw)?;
    raw.found = format!("{} vertices and {} faces", vertices.len(), faces.len());
    Ok(raw)
}

/// The file being read, for the errors that name it and the checks on its raw bytes.
struct PlyReader<'a> {
    bytes: &'a [u8],
    file: &'a str,
}

impl PlyReader<'_> {
    /// A `parse` error at `at`.
    fn parse_err(&self, at: String, reason: String) -> LoadError {
        LoadError::Parse {
            file: self.file.to_string(),
            at,
            reason,
        }
    }

    /// A parser error as `truncated` (with what was expected) or `parse` (its message).
    fn classify(
        &self,
        e: &ply_rs_bw::parser::ParseError,
        truncated: bool,
        at: String,
        expected: &str,
    ) -> LoadError {
        if truncated {
            LoadError::Truncated {
                file: self.file.to_string(),
                at,
                reason: expected.to_string(),
            }
        } else {
            self.parse_err(at, parser_message(e))
        }
    }

    /// Reads the header, naming its line on error.
    fn read_header(&self, reader: &mut Reader<BufReader<&[u8]>>) -> Result<Header, LoadError> {
        Parser::<PlyVertex>::new().read_header(reader).map_err(|e| {
            let at = e
                .line()
                .map_or("header".into(), |l| format!("header line {l}"));
            let truncated = e.kind() == ErrorKind::UnexpectedEof;
            self.classify(&e, truncated, at, "the header has no `end_header` line")
        })
    }

    /// The `vertex` element's definition, which must have `x`, `y` and `z`.
    fn vertex_def<'h>(&self, header: &'h Header) -> Result<&'h ElementDef, LoadError> {
        let vdef = header
            .elements
            .get("vertex")
            .ok_or_else(|| self.parse_err("header".into(), "no `vertex` element".into()))?;
        if !(has(vdef, &["x"]) && has(vdef, &["y"]) && has(vdef, &["z"])) {
            return Err(self.parse_err(
                "header".into(),
                "the `vertex` element lacks an `x`, `y` or `z` property".into(),
            ));
        }
        Ok(vdef)
    }

    /// Binary: checks the fixed-size element blocks fit, to name where the data runs out.
    fn check_binary_sizes(&self, header: &Header) -> Result<(), LoadError> {
        // Checked before reading, up to the first element with a list property.
        if header.encoding == Encoding::Ascii {
            return Ok(());
        }
        let bytes = self.bytes;
        let body = bytes
            .windows(10)
            .position(|w| w == b"end_header")
            .and_then(|p| {
                bytes[p..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .map(|q| p + q + 1)
            });
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
                    file: self.file.to_string(),
                    at: format!("byte {}", bytes.len()),
                    reason: format!(
                        "{} `{name}` elements of {size} bytes need the file to reach byte {end}",
                        e.count
                    ),
                });
            }
            offset = end;
        }
        Ok(())
    }

    /// An error reading the payload of element `name`, as `truncated` or `parse`.
    fn element_err(&self, name: &str, e: ply_rs_bw::parser::ParseError) -> LoadError {
        let bytes = self.bytes;
        let last_line = bytes.iter().filter(|&&b| b == b'\n').count() + 1;
        let at = match e.line() {
            Some(l) => format!("line {l} (element `{name}`)"),
            None => format!("element `{name}`"),
        };
        // ASCII cut mid-line: the parser sees a short last line, not the end of the file.
        let cut_last_line = !bytes.ends_with(b"\n") && e.line() == Some(last_line);
        let truncated = e.kind() == ErrorKind::UnexpectedEof || cut_last_line;
        self.classify(
            &e,
            truncated,
            at,
            "the file ends before the elements its header announces",
        )
    }

    /// Reads every element in header order: the vertices and faces, the others dropped.
    fn read_elements(
        &self,
        reader: &mut Reader<BufReader<&[u8]>>,
        header: &Header,
    ) -> Result<(Vec<PlyVertex>, Vec<PlyFace>), LoadError> {
        let vparser = Parser::<PlyVertex>::new();
        let fparser = Parser::<PlyFace>::new();
        let sparser = Parser::<Skip>::new();
        let mut vertices = Vec::new();
        let mut faces = Vec::new();
        for (name, def) in &header.elements {
            match name.as_str() {
                "vertex" => {
                    vertices = vparser
                        .read_payload_for_element(reader, def, header)
                        .map_err(|e| self.element_err(name, e))?;
                }
                "face" => {
                    faces = fparser
                        .read_payload_for_element(reader, def, header)
                        .map_err(|e| self.element_err(name, e))?;
                }
                _ => {
                    sparser
                        .read_payload_for_element(reader, def, header)
                        .map_err(|e| self.element_err(name, e))?;
                }
            }
        }
        Ok((vertices, faces))
    }

    /// Checks the face indices and fan-triangulates the faces into `raw`, with the notes.
    fn triangulate_faces(
        &self,
        faces: &[PlyFace],
        nv: usize,
        raw: &mut Raw,
    ) -> Result<(), LoadError> {
        let (mut polygons, mut small) = (0, 0);
        let mut poly = Vec::new();
        for (k, f) in faces.iter().enumerate() {
            poly.clear();
            for &i in &f.0 {
                if !(0..nv as i64).contains(&i) {
                    return Err(LoadError::IndexOutOfRange {
                        file: self.file.to_string(),
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
        Ok(())
    }
}

/// Positions, and normals and uvs where the `vertex` element has all their properties.
fn vertex_attributes(vertices: &[PlyVertex], vdef: &ElementDef) -> Raw {
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
    raw
}
