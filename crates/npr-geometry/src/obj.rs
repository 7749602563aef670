//! Wavefront OBJ loading, kept for the callers that want an OBJ's `v`-line numbering:
//! both entry points go through [`crate::io`] (same parsing, same validation, same
//! typed errors) and differ only in what they return.

use std::collections::HashMap;
use std::path::Path;

use crate::io::{Format, load_path_as, parse_v};
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
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
