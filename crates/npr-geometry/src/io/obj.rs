//! Wavefront OBJ. The parser behind [`crate::io::load`]: `tobj` (triangulated,
//! single-indexed render vertices), after a line scan that locates what `tobj` reports
//! without a place: unparsable or non-finite `v` lines and face indices out of range, by
//! line number. And the OBJ entry points, kept for the callers that want an OBJ's
//! `v`-line numbering: [`load_obj`] and [`load_obj_with_vertex_map`] go through
//! [`crate::io`] (same parsing, same validation, same typed errors) and differ only in
//! what they return.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::{Format, LoadError, LoadNote, Raw, load_path_as};
use crate::weld::position_key;
use crate::{GeometryError, Mesh, Welded, weld};

/// file (in file order) the welded vertex at that position.
#[derive(Clone, Debug)]
pub struct ObjMesh {
    /// Render vertices and triangles (every object and group of the file, concatenated).
    pub mesh: Mesh,
    /// The welded mesh built from `mesh`.
    pub welded: Welded,
    /// One entry per `v` line, in file order: the welded vertex with exactly that
    /// position, or `None` when no face uses a vertex at that position.
    pub obj_to_welded: Vec<Option<u32>>,
}

/// Loads an OBJ file (whatever its extension) as a render [`Mesh`]: all objects and
/// groups concatenated, polygons fan-triangulated, points and lines ignored, materials
/// ignored. [`crate::io::load`] does the same and also returns the report of what changed.
///
/// Normals come from the file when every face corner has one; otherwise smooth
/// area-weighted normals are computed over the welded mesh (see
/// [`Mesh::recompute_normals`]). Missing texture coordinates are zero.
///
/// # Errors
/// [`GeometryError::Load`] with the [`crate::io::LoadError`] (missing file, parse error
/// with its line, index out of range, non-finite coordinate, no faces).
pub fn load_obj(path: impl AsRef<Path>) -> Result<Mesh, GeometryError> {
    Ok(load_path_as(path.as_ref(), Format::Obj)?.0.mesh)
}

/// Like [`load_obj`], and also maps every `v` line of the file to its welded vertex, for
/// per-input-vertex output (the `cargo xtask curvature` CSV).
///
/// `tobj`'s single-index mode renumbers vertices in order of first use and duplicates
/// them per (v, vt, vn) triple, so the `v` lines are read a second time here, in file
/// order, with the same float parsing (`str::parse::<f32>`, divided by an optional `w`)
/// and matched to the welded vertex with the bit-identical position.
///
/// # Errors
/// As [`load_obj`]; a non-finite `v` line is reported even if no face uses it.
pub fn load_obj_with_vertex_map(path: impl AsRef<Path>) -> Result<ObjMesh, GeometryError> {
    let (loaded, bytes) = load_path_as(path.as_ref(), Format::Obj)?;
    let mesh = loaded.mesh;
    let welded = weld(&mesh);
    let lookup: HashMap<[u32; 3], u32> = welded
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (position_key(p), i as u32))
        .collect();
    // The loader has checked every `v` line (parsable, finite) and that the bytes are UTF-8.
    let text = String::from_utf8_lossy(&bytes);
    let obj_to_welded = text
        .lines()
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            (words.next() == Some("v")).then(|| {
                let vals: Vec<&str> = words.collect();
                parse_v(&vals).and_then(|p| lookup.get(&position_key(p)).copied())
            })
        })
        .collect();
    Ok(ObjMesh {
        mesh,
        welded,
        obj_to_welded,
    })
}

/// Parses `x y z [w]` (or `x y z r g b`) the way `tobj` does.
fn parse_v(vals: &[&str]) -> Option<Vec3> {
    let f = |s: &str| s.parse::<f32>().ok();
    let mut p = [f(vals.first()?)?, f(vals.get(1)?)?, f(vals.get(2)?)?];
    if vals.len() == 4 {
        let w = f(vals[3])?;
        for c in p.iter_mut() {
            *c /= w;
        }
    }
    Some(Vec3::from(p))
}

pub(crate) fn parse(bytes: &[u8], file: &str) -> Result<Raw, LoadError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        parse_err(
            file,
            format!("byte {}", e.valid_up_to()),
            "not UTF-8 text (is this really an OBJ file?)".into(),
        )
    })?;
    let scan = Scan::run(text, file)?;
    let models = read_models(text, file)?;
    let mut raw = merge_models(&models);
    scan.add_notes(&mut raw);
    Ok(raw)
}

/// A `parse` error at `at`.
fn parse_err(file: &str, at: String, reason: String) -> LoadError {
    LoadError::Parse {
        file: file.to_string(),
        at,
        reason,
    }
}

/// The line scan: counts for the report, places for the errors.
#[derive(Default)]
struct Scan {
    /// `v` lines so far.
    nv: i64,
    /// `vt` and `vn` lines so far: face corners `v/vt/vn` are checked against all three,
    /// positive indices against the file's totals (a face may precede its vertices),
    /// negative ones against the lines so far.
    nvt: i64,
    nvn: i64,
    /// The file's `v`, `vt` and `vn` line totals.
    total: [i64; 3],
    /// Faces with more than 3 corners.
    polygons: usize,
    /// Faces with fewer than 3 corners.
    small: usize,
    /// `p` lines.
    points: usize,
    /// `l` lines.
    lines: usize,
}

impl Scan {
    /// Scans every line: `v` lines parsed and finite, face corners in range.
    fn run(text: &str, file: &str) -> Result<Self, LoadError> {
        let mut scan = Self::default();
        for line in text.lines() {
            match line.split_whitespace().next() {
                Some("v") => scan.total[0] += 1,
                Some("vt") => scan.total[1] += 1,
                Some("vn") => scan.total[2] += 1,
                _ => {}
            }
        }
        for (k, line) in text.lines().enumerate() {
            let at = || format!("line {}", k + 1);
            let mut words = line.split_whitespace();
            match words.next() {
                Some("v") => {
                    let vals: Vec<&str> = words.collect();
                    let p = parse_v(&vals).ok_or_else(|| {
                        parse_err(file, at(), format!("bad vertex line `{}`", line.trim()))
                    })?;
                    if !p.is_finite() {
                        return Err(LoadError::NonFinite {
                            file: file.to_string(),
                            at: at(),
                            what: format!("position {:?}", p.to_array()),
                        });
                    }
                    scan.nv += 1;
                }
                Some("f") => scan.face(words.collect(), &at, file)?,
                Some("vt") => scan.nvt += 1,
                Some("vn") => scan.nvn += 1,
                Some("p") => scan.points += 1,
                Some("l") => scan.lines += 1,
                _ => {}
            }
        }
        Ok(scan)
    }

    /// Counts an `f` line's corners and checks each corner's `v/vt/vn` indices.
    fn face(
        &mut self,
        corners: Vec<&str>,
        at: &dyn Fn() -> String,
        file: &str,
    ) -> Result<(), LoadError> {
        match corners.len() {
            0..=2 => self.small += 1,
            3 => {}
            _ => self.polygons += 1,
        }
        for c in corners {
            let so_far = [self.nv, self.nvt, self.nvn];
            for (slot, part) in c.split('/').take(3).enumerate() {
                if part.is_empty() && slot > 0 {
                    continue;
                }
                let i: i64 = part
                    .parse()
                    .map_err(|_| parse_err(file, at(), format!("bad face corner `{c}`")))?;
                // 1-based, or negative = relative to the last line so far.
                let (resolved, count) = if i < 0 {
                    (so_far[slot].checked_add(i), so_far[slot])
                } else {
                    (i.checked_sub(1), self.total[slot])
                };
                if !resolved.is_some_and(|r| (0..count).contains(&r)) {
                    return Err(LoadError::IndexOutOfRange {
                        file: file.to_string(),
                        at: format!("{} (`{}` of a face corner)", at(), ["v", "vt", "vn"][slot]),
                        index: i,
                        count: count as usize,
                    });
                }
            }
        }
        Ok(())
    }

    /// The report's notes and the no-triangles detail.
    fn add_notes(&self, raw: &mut Raw) {
        let Self {
            nv,
            polygons,
            small,
            points,
            lines,
            ..
        } = *self;
        if polygons > 0 {
            raw.notes.push(LoadNote::Triangulated { polygons });
        }
        for (what, count) in [
            ("OBJ faces with fewer than 3 vertices", small),
            ("OBJ point (`p`) lines", points),
            ("OBJ line (`l`) lines", lines),
        ] {
            if count > 0 {
                raw.notes.push(LoadNote::Skipped {
                    what: what.into(),
                    count,
                });
            }
        }
        raw.found = format!("{nv} `v` lines, {points} `p` lines, {lines} `l` lines and no faces");
    }
}

/// The file through `tobj`: triangulated, single-indexed, points and lines ignored.
fn read_models(text: &str, file: &str) -> Result<Vec<tobj::Model>, LoadError> {
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) =
        tobj::load_obj_buf(&mut BufReader::new(text.as_bytes()), &opts, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| parse_err(file, "file".into(), e.to_string()))?;
    Ok(models)
}

/// Every model's vertices and triangles, concatenated (normals only if all have them).
fn merge_models(models: &[tobj::Model]) -> Raw {
    let mut raw = Raw::default();
    let mut all_normals = true;
    for m in models {
        let t = &m.mesh;
        let base = raw.positions.len() as u32;
        let n = t.positions.len() / 3;
        raw.positions.extend(
            t.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if t.normals.len() == 3 * n {
            raw.normals.extend(
                t.normals
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
        } else {
            all_normals = false;
        }
        if t.texcoords.len() == 2 * n {
            raw.uvs
                .extend(t.texcoords.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])));
        } else {
            raw.uvs.extend(std::iter::repeat_n(Vec2::ZERO, n));
        }
        // Out-of-range indices from tobj are caught by `finish`.
        raw.triangles.extend(
            t.indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]].map(|i| i.saturating_add(base))),
        );
    }
    if !all_normals {
        if !raw.normals.is_empty() {
            raw.normals_incomplete = Some("only some faces have `vn` normals");
        }
        raw.normals.clear();
    }
    raw
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn write(name: &str, text: &str) -> PathBuf {
        let p = std::env::temp_dir().join(format!("npr-geometry-{}-{name}", std::process::id()));
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn quad_with_seam_and_vertex_map() {
        let p = write(
            "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
             f 1/1 2/2 3/3 4/4\nf 4/1 3/2 1/4\n",
        );
        let o = load_obj_with_vertex_map(&p).unwrap();
        assert_eq!(o.mesh.triangle_count(), 3);
        assert_eq!(o.welded.positions.len(), 4);
        assert!(
            o.mesh
                .normals
                .iter()
                .all(|n| (n.length() - 1.0).abs() < 1e-6)
        );
        assert_eq!(o.obj_to_welded.len(), 5);
        assert_eq!(o.obj_to_welded[4], None);
        for (k, w) in o.obj_to_welded.iter().take(4).enumerate() {
            let w = w.unwrap() as usize;
            assert_eq!(
                o.welded.positions[w],
                [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y][k]
            );
        }
    }

    #[test]
    fn typed_errors() {
        let kind = |r: Result<Mesh, GeometryError>| match r {
            Err(GeometryError::Load(e)) => e.kind(),
            other => panic!("expected a load error, got {other:?}"),
        };
        assert_eq!(kind(load_obj("/nonexistent/x.obj")), "missing");
        let p = write("nofaces.obj", "v 0 0 0\nv 1 0 0\n");
        assert_eq!(kind(load_obj(&p)), "no-triangles");
        let p = write("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert_eq!(kind(load_obj(&p)), "non-finite");
        // Also when no face uses the vertex.
        let p = write("inf.obj", "v 0 0 inf\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 2 3 4\n");
        assert_eq!(
            kind(load_obj_with_vertex_map(&p).map(|o| o.mesh)),
            "non-finite"
        );
        let p = write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
        let e = load_obj(&p).unwrap_err().to_string();
        assert!(e.contains("line 4") && e.contains("range.obj"), "{e}");
        let p = write("bad.obj", "v 0 x 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert_eq!(kind(load_obj(&p)), "parse");
    }
}
