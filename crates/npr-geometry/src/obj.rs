//! Wavefront OBJ loading through `tobj`: triangulated, single-indexed render vertices
//! (each keeps its own uv and normal), smooth normals computed when the file has none,
//! and an optional map from the file's `v` lines to welded vertices.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use crate::weld::position_key;
use crate::{GeometryError, Mesh, Welded, weld};

/// An OBJ file as loaded: the render mesh, its welding, and for every `v` line of the
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

/// Loads an OBJ file as a render [`Mesh`] (all objects and groups concatenated,
/// polygons fan-triangulated, points and lines ignored, materials ignored).
///
/// Normals come from the file when every face corner has one; otherwise smooth
/// area-weighted normals are computed over the welded mesh (see
/// [`Mesh::recompute_normals`]). Missing texture coordinates are zero.
///
/// # Errors
/// [`GeometryError::Unreadable`], [`GeometryError::Malformed`] (parse errors),
/// [`GeometryError::ObjIndexOutOfRange`], [`GeometryError::NoFaces`],
/// [`GeometryError::NonFinite`].
pub fn load_obj(path: impl AsRef<Path>) -> Result<Mesh, GeometryError> {
    let text = read(path.as_ref())?;
    parse(&text, path.as_ref())
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
    let path = path.as_ref();
    let text = read(path)?;
    let mesh = parse(&text, path)?;
    let welded = weld(&mesh);
    let lookup: HashMap<[u32; 3], u32> = welded
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (position_key(p), i as u32))
        .collect();
    let mut obj_to_welded = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        let vals: Vec<&str> = words.collect();
        let p = parse_v(&vals).ok_or_else(|| GeometryError::Malformed {
            path: path.to_path_buf(),
            reason: format!("bad vertex line `{line}`"),
        })?;
        if !p.is_finite() {
            return Err(GeometryError::NonFinite {
                vertex: obj_to_welded.len(),
                what: "position",
            });
        }
        obj_to_welded.push(lookup.get(&position_key(p)).copied());
    }
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

fn read(path: &Path) -> Result<String, GeometryError> {
    std::fs::read_to_string(path).map_err(|source| GeometryError::Unreadable {
        path: path.to_path_buf(),
        source,
    })
}

fn parse(text: &str, path: &Path) -> Result<Mesh, GeometryError> {
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let malformed = |e: tobj::LoadError| match e {
        tobj::LoadError::FaceVertexOutOfBounds => GeometryError::ObjIndexOutOfRange {
            path: PathBuf::from(path),
        },
        e => GeometryError::Malformed {
            path: PathBuf::from(path),
            reason: e.to_string(),
        },
    };
    let (models, _materials) =
        tobj::load_obj_buf(&mut BufReader::new(text.as_bytes()), &opts, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(malformed)?;

    let mut mesh = Mesh::default();
    let mut all_normals = true;
    for m in &models {
        let t = &m.mesh;
        let base = mesh.positions.len() as u32;
        let n = t.positions.len() / 3;
        mesh.positions.extend(
            t.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if t.normals.len() == 3 * n {
            mesh.normals.extend(
                t.normals
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
        } else {
            all_normals = false;
            mesh.normals.extend(std::iter::repeat_n(Vec3::ZERO, n));
        }
        if t.texcoords.len() == 2 * n {
            mesh.uvs
                .extend(t.texcoords.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])));
        } else {
            mesh.uvs.extend(std::iter::repeat_n(Vec2::ZERO, n));
        }
        mesh.indices.extend(t.indices.iter().map(|&i| i + base));
    }
    if mesh.indices.len() < 3 {
        return Err(GeometryError::NoFaces {
            path: path.to_path_buf(),
        });
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(GeometryError::NonFinite {
            vertex: i,
            what: "position",
        });
    }
    // Normals: keep the file's when complete and finite, normalised; else smooth ones.
    let usable = all_normals
        && mesh
            .normals
            .iter()
            .all(|n| n.is_finite() && n.length_squared() > 0.0);
    if usable {
        for n in &mut mesh.normals {
            *n = n.normalize();
        }
    } else {
        mesh.recompute_normals();
    }
    mesh.validate()?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert!(matches!(
            load_obj("/nonexistent/x.obj"),
            Err(GeometryError::Unreadable { .. })
        ));
        let p = write("nofaces.obj", "v 0 0 0\nv 1 0 0\n");
        assert!(matches!(load_obj(&p), Err(GeometryError::NoFaces { .. })));
        let p = write("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(matches!(load_obj(&p), Err(GeometryError::NonFinite { .. })));
        let p = write("inf.obj", "v 0 0 inf\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(matches!(load_obj(&p), Err(GeometryError::NonFinite { .. })));
        let p = write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
        assert!(matches!(
            load_obj(&p),
            Err(GeometryError::ObjIndexOutOfRange { .. })
        ));
        let p = write("bad.obj", "v 0 x 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(matches!(load_obj(&p), Err(GeometryError::Malformed { .. })));
    }
}
