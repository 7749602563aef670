//! Wavefront OBJ through `tobj` (triangulated, single-indexed render vertices), after a
//! line scan that locates what `tobj` reports without a place: unparsable or non-finite
//! `v` lines and face indices out of range, by line number.

use std::io::BufReader;

use glam::{Vec2, Vec3};

use super::{LoadError, LoadNote, Raw};

/// Parses `x y z [w]` (or `x y z r g b`) the way `tobj` does.
pub(crate) fn parse_v(vals: &[&str]) -> Option<Vec3> {
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
    let err = |at: String, reason: String| LoadError::Parse {
        file: file.to_string(),
        at,
        reason,
    };
    let text = std::str::from_utf8(bytes).map_err(|e| {
        err(
            format!("byte {}", e.valid_up_to()),
            "not UTF-8 text (is this really an OBJ file?)".into(),
        )
    })?;

    // The scan: counts for the report, places for the errors.
    let (mut nv, mut polygons, mut small, mut points, mut lines) = (0i64, 0, 0, 0, 0);
    // `vt` and `vn` lines so far: face corners `v/vt/vn` are checked against all three,
    // positive indices against the file's totals (a face may precede its vertices),
    // negative ones against the lines so far.
    let (mut nvt, mut nvn) = (0i64, 0i64);
    let mut total = [0i64; 3];
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => total[0] += 1,
            Some("vt") => total[1] += 1,
            Some("vn") => total[2] += 1,
            _ => {}
        }
    }
    for (k, line) in text.lines().enumerate() {
        let at = || format!("line {}", k + 1);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let vals: Vec<&str> = words.collect();
                let p = parse_v(&vals)
                    .ok_or_else(|| err(at(), format!("bad vertex line `{}`", line.trim())))?;
                if !p.is_finite() {
                    return Err(LoadError::NonFinite {
                        file: file.to_string(),
                        at: at(),
                        what: format!("position {:?}", p.to_array()),
                    });
                }
                nv += 1;
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                match corners.len() {
                    0..=2 => small += 1,
                    3 => {}
                    _ => polygons += 1,
                }
                for c in corners {
                    let so_far = [nv, nvt, nvn];
                    for (slot, part) in c.split('/').take(3).enumerate() {
                        if part.is_empty() && slot > 0 {
                            continue;
                        }
                        let i: i64 = part
                            .parse()
                            .map_err(|_| err(at(), format!("bad face corner `{c}`")))?;
                        // 1-based, or negative = relative to the last line so far.
                        let (resolved, count) = if i < 0 {
                            (so_far[slot].checked_add(i), so_far[slot])
                        } else {
                            (i.checked_sub(1), total[slot])
                        };
                        if !resolved.is_some_and(|r| (0..count).contains(&r)) {
                            return Err(LoadError::IndexOutOfRange {
                                file: file.to_string(),
                                at: format!(
                                    "{} (`{}` of a face corner)",
                                    at(),
                                    ["v", "vt", "vn"][slot]
                                ),
                                index: i,
                                count: count as usize,
                            });
                        }
                    }
                }
            }
            Some("vt") => nvt += 1,
            Some("vn") => nvn += 1,
            Some("p") => points += 1,
            Some("l") => lines += 1,
            _ => {}
        }
    }

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
        .map_err(|e| err("file".into(), e.to_string()))?;

    let mut raw = Raw::default();
    let mut all_normals = true;
    for m in &models {
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
    Ok(raw)
}
