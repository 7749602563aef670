//! Loading users' models: Wavefront OBJ, glTF 2.0 (`.gltf` with external or data-URI
//! buffers, `.glb`) and PLY (ASCII, binary little and big endian) into one [`Mesh`].
//!
//! [`load`] picks the format from the extension (case-insensitive), [`load_bytes`] takes
//! the format explicitly (fuzzing, in-memory assets). Every path ends in the same
//! validation: non-finite coordinates and out-of-range indices are typed
//! [`LoadError`]s, never panics; what was changed on the way (triangulated polygons,
//! skipped points and lines, removed unreferenced vertices, recomputed normals, kept
//! degenerate faces) is listed in [`Loaded::report`].
//!
//! ```
//! let dir = std::env::temp_dir().join(format!("npr-io-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! let path = dir.join("quad.OBJ");
//! std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
//! let loaded = npr_geometry::io::load(&path).unwrap();
//! assert_eq!(loaded.mesh.triangle_count(), 2);
//! for note in &loaded.report {
//!     println!("{note}"); // "1 polygon with more than 3 vertices fan-triangulated", ...
//! }
//! let err = npr_geometry::io::load(dir.join("missing.ply")).unwrap_err();
//! assert_eq!(err.kind(), "missing");
//! ```

mod error;
pub mod fixtures;
mod gltf;
pub mod obj;
mod ply;
pub mod write;

use std::fmt;
use std::path::Path;

use glam::{Vec2, Vec3};

pub use error::LoadError;

use crate::Mesh;
use crate::animation::Rig;

/// A model file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ text.
    Obj,
    /// glTF 2.0 JSON (`.gltf`); buffers external (next to the file) or data URIs.
    Gltf,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// Stanford PLY, ASCII or binary.
    Ply,
}

impl Format {
    /// The format for a file extension (without the dot, any case), if supported.
    pub fn from_extension(ext: &str) -> Option<Self> {
        match ext.to_ascii_lowercase().as_str() {
            "obj" => Some(Self::Obj),
            "gltf" => Some(Self::Gltf),
            "glb" => Some(Self::Glb),
            "ply" => Some(Self::Ply),
            _ => None,
        }
    }

    /// The lower-case extension of the format.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Obj => "obj",
            Self::Gltf => "gltf",
            Self::Glb => "glb",
            Self::Ply => "ply",
        }
    }
}

/// A loaded model: the merged render mesh and what the loader changed on the way.
#[derive(Clone, Debug, Default)]
pub struct Loaded {
    /// Every triangle of the file in one mesh, validated ([`Mesh::validate`] holds).
    pub mesh: Mesh,
    /// What was dropped, converted or recomputed, for the caller to print.
    pub report: Vec<LoadNote>,
    /// The skins, morph targets and clips of a glTF file that has any, tied to `mesh`'s
    /// render vertices ([`Rig::pose_mesh`] gives `mesh` again in [`Rig::bind_pose`]);
    /// `None` for other files.
    pub rig: Option<Rig>,
}

/// One thing the loader dropped, converted or recomputed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LoadNote {
    /// Faces with more than 3 vertices were fan-triangulated.
    Triangulated {
        /// How many such polygons.
        polygons: usize,
    },
    /// Elements that are not triangles were skipped (OBJ `p`/`l` lines, glTF point and
    /// line primitives, PLY faces with fewer than 3 vertices).
    Skipped {
        /// What (e.g. "glTF primitives of mode Lines").
        what: String,
        /// How many.
        count: usize,
    },
    /// glTF triangle strips or fans were converted to triangle lists.
    StripsConverted {
        /// How many primitives.
        primitives: usize,
    },
    /// Vertices used by no triangle were removed.
    UnreferencedVerticesRemoved {
        /// How many.
        count: usize,
    },
    /// Smooth area-weighted normals were computed ([`Mesh::recompute_normals`]).
    NormalsRecomputed {
        /// Why (absent, partly absent, zero or non-finite).
        reason: &'static str,
    },
    /// The file has no normals and sharp edges: vertices on its crease lines were
    /// split, one copy per side, each side with its own smooth normal
    /// ([`Mesh::split_at_creases`]).
    CreasesSplit {
        /// How many vertices were added.
        vertices: usize,
    },
    /// Degenerate triangles (a repeated vertex, or zero area) were kept as they are:
    /// topology and curvature ignore them, rendering draws nothing for them.
    DegenerateKept {
        /// How many.
        count: usize,
    },
    /// glTF node transforms were applied to the vertices (normals by the
    /// inverse-transpose).
    TransformsApplied {
        /// How many mesh instances were placed.
        instances: usize,
    },
    /// glTF skin weights that did not sum to 1 were normalised.
    WeightsNormalised {
        /// How many vertices.
        vertices: usize,
    },
    /// The transform of a node with a skinned mesh was ignored, as glTF 2.0 requires
    /// (§3.7.3: the joints alone place skinned vertices).
    SkinnedTransformIgnored {
        /// How many instances.
        instances: usize,
    },
}

impl fmt::Display for LoadNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Triangulated { polygons } => write!(
                f,
                "{polygons} polygon(s) with more than 3 vertices fan-triangulated"
            ),
            Self::Skipped { what, count } => write!(f, "{count} {what} skipped"),
            Self::StripsConverted { primitives } => write!(
                f,
                "{primitives} triangle strip/fan primitive(s) converted to triangle lists"
            ),
            Self::UnreferencedVerticesRemoved { count } => {
                write!(f, "{count} vertices used by no triangle removed")
            }
            Self::NormalsRecomputed { reason } => {
                write!(f, "normals recomputed (area-weighted): {reason}")
            }
            Self::CreasesSplit { vertices } => write!(
                f,
                "{vertices} vertices added along crease lines (edges bending over {}°): each side keeps its own normal",
                crate::StrokeFieldOptions::default().crease_angle_deg
            ),
            Self::DegenerateKept { count } => write!(
                f,
                "{count} degenerate triangle(s) (repeated vertex or zero area) kept"
            ),
            Self::TransformsApplied { instances } => {
                write!(f, "node transforms applied to {instances} mesh instance(s)")
            }
            Self::WeightsNormalised { vertices } => write!(
                f,
                "skin weights of {vertices} vertices did not sum to 1 and were normalised"
            ),
            Self::SkinnedTransformIgnored { instances } => write!(
                f,
                "the node transform of {instances} skinned mesh instance(s) ignored (glTF: joints place skinned vertices)"
            ),
        }
    }
}

/// Loads a model file; the format comes from the extension (case-insensitive).
///
/// # Errors
/// A [`LoadError`] naming the file: `missing`, `io`, `empty`, `unsupported-format`, and
/// the format's parse and validation errors (see [`LoadError::kind`]).
pub fn load(path: impl AsRef<Path>) -> Result<Loaded, LoadError> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    let format = Format::from_extension(&ext).ok_or_else(|| LoadError::UnsupportedFormat {
        file: path.display().to_string(),
        extension: ext,
    })?;
    Ok(load_path_as(path, format)?.0)
}

/// Reads `path` as `format` whatever its extension; also returns the file's bytes.
pub(crate) fn load_path_as(path: &Path, format: Format) -> Result<(Loaded, Vec<u8>), LoadError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            LoadError::Missing { file: file.clone() }
        } else {
            LoadError::Io {
                file: file.clone(),
                source,
            }
        }
    })?;
    let loaded = load_source(&bytes, format, &file, path.parent())?;
    Ok((loaded, bytes))
}

/// Loads a model from memory. `format` says how to read it (a `.gltf` whose bytes are
/// binary glTF is read as GLB). External glTF buffers cannot be resolved here and are an
/// `unsupported-feature` error; data URIs work. Errors name the file `<bytes>.EXT`.
///
/// # Errors
/// As [`load`], without `missing` and `io`.
pub fn load_bytes(bytes: &[u8], format: Format) -> Result<Loaded, LoadError> {
    load_source(
        bytes,
        format,
        &format!("<bytes>.{}", format.extension()),
        None,
    )
}

/// As [`load_bytes`], with errors naming the file `name` (a dropped or uploaded file's
/// name, as its user knows it).
///
/// # Errors
/// As [`load_bytes`].
pub fn load_bytes_named(bytes: &[u8], format: Format, name: &str) -> Result<Loaded, LoadError> {
    load_source(bytes, format, name, None)
}

fn load_source(
    bytes: &[u8],
    format: Format,
    file: &str,
    dir: Option<&Path>,
) -> Result<Loaded, LoadError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(LoadError::Empty {
            file: file.to_string(),
        });
    }
    let (raw, rig) = match format {
        Format::Obj => (obj::parse(bytes, file)?, None),
        Format::Ply => (ply::parse(bytes, file)?, None),
        Format::Gltf | Format::Glb => gltf::parse(bytes, file, dir)?,
    };
    let (mut loaded, kept) = finish_mapped(raw, file)?;
    if let Some(parts) = rig {
        loaded.rig = Some(parts.into_rig(&kept, &loaded));
    } else {
        split_creases_without_normals(&mut loaded);
    }
    Ok(loaded)
}

/// A file without usable normals: its render vertices split along the crease lines
/// ([`Mesh::split_at_creases`] at the stroke field's crease angle and line length), so
/// the sides of a hard edge get their own normals and stroke directions, as a modeller's
/// "auto smooth" shows them. A file's own normals are kept as they are. Rigged models
/// are left whole: [`crate::animation::Rig::pose_mesh`] recomputes smooth normals per
/// pose over the welded mesh, so split normals would hold in the bind pose only.
fn split_creases_without_normals(loaded: &mut Loaded) {
    let recomputed = loaded
        .report
        .iter()
        .any(|n| matches!(n, LoadNote::NormalsRecomputed { .. }));
    if !recomputed {
        return;
    }
    let options = crate::StrokeFieldOptions::default();
    if let Some((mesh, _)) = loaded
        .mesh
        .split_at_creases(options.crease_angle_deg, options.min_crease_length)
    {
        let added = mesh.vertex_count() - loaded.mesh.vertex_count();
        loaded.mesh = mesh;
        loaded
            .report
            .push(LoadNote::CreasesSplit { vertices: added });
    }
}

/// What a format parser produces; [`finish`] validates and cleans it.
#[derive(Debug, Default)]
pub(crate) struct Raw {
    pub positions: Vec<Vec3>,
    /// Empty, or one per position.
    pub normals: Vec<Vec3>,
    /// Empty, or one per position.
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
    /// Why normals are incomplete, when `normals` is empty although the file has some.
    pub normals_incomplete: Option<&'static str>,
    /// How to name vertex `i` in an error (`"line 12"`, `"vertex 3"`).
    pub vertex_at: Option<Vec<String>>,
    pub notes: Vec<LoadNote>,
    /// What the file held when it has no triangle.
    pub found: String,
}

impl Raw {
    fn vertex_label(&self, i: usize) -> String {
        self.vertex_at
            .as_ref()
            .and_then(|v| v.get(i).cloned())
            .unwrap_or_else(|| format!("vertex {i}"))
    }
}

/// The common end of every loader: non-finite and range checks, unreferenced vertices
/// removed, normals kept or recomputed, the report completed.
/// Also returns, for each vertex of the mesh, its index in `raw`.
pub(crate) fn finish_mapped(mut raw: Raw, file: &str) -> Result<(Loaded, Vec<u32>), LoadError> {
    check(&raw, file)?;
    let mut notes = std::mem::take(&mut raw.notes);
    let (unused, kept) = remove_unreferenced(&mut raw);
    if unused > 0 {
        notes.push(LoadNote::UnreferencedVerticesRemoved { count: unused });
    }
    let degenerate = count_degenerate(&raw);
    if degenerate > 0 {
        notes.push(LoadNote::DegenerateKept { count: degenerate });
    }
    let (mesh, recomputed) = into_mesh(raw);
    if let Some(reason) = recomputed {
        notes.push(LoadNote::NormalsRecomputed { reason });
    }
    // Cannot fail after the checks above; kept as the single source of the invariants.
    mesh.validate().map_err(|e| LoadError::Parse {
        file: file.to_string(),
        at: "mesh".into(),
        reason: e.to_string(),
    })?;
    Ok((
        Loaded {
            mesh,
            report: notes,
            rig: None,
        },
        kept,
    ))
}

/// Rejects non-finite positions, indices out of range and a file without triangles.
fn check(raw: &Raw, file: &str) -> Result<(), LoadError> {
    let n = raw.positions.len();
    if let Some(i) = raw.positions.iter().position(|p| !p.is_finite()) {
        return Err(LoadError::NonFinite {
            file: file.to_string(),
            at: raw.vertex_label(i),
            what: format!("position {:?}", raw.positions[i].to_array()),
        });
    }
    if let Some((t, &i)) = raw
        .triangles
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().find(|&&i| i as usize >= n).map(|i| (t, i)))
    {
        return Err(LoadError::IndexOutOfRange {
            file: file.to_string(),
            at: format!("triangle {t}"),
            index: i64::from(i),
            count: n,
        });
    }
    if raw.triangles.is_empty() {
        let found = if raw.found.is_empty() {
            format!("{n} vertices and no faces")
        } else {
            raw.found.clone()
        };
        return Err(LoadError::NoTriangles {
            file: file.to_string(),
            detail: found,
        });
    }
    Ok(())
}

/// Drops the vertices no triangle uses, renumbering the triangles; returns how many, and
/// for each vertex kept its former index.
fn remove_unreferenced(raw: &mut Raw) -> (usize, Vec<u32>) {
    let n = raw.positions.len();
    let mut used = vec![false; n];
    for t in &raw.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let unused = used.iter().filter(|&&u| !u).count();
    if unused > 0 {
        let mut remap = vec![u32::MAX; n];
        let mut next = 0u32;
        for (i, &u) in used.iter().enumerate() {
            if u {
                remap[i] = next;
                next += 1;
            }
        }
        fn keep<T>(v: &mut Vec<T>, used: &[bool]) {
            let mut k = 0;
            v.retain(|_| {
                k += 1;
                used[k - 1]
            });
        }
        keep(&mut raw.positions, &used);
        if raw.normals.len() == n {
            keep(&mut raw.normals, &used);
        }
        if raw.uvs.len() == n {
            keep(&mut raw.uvs, &used);
        }
        for t in &mut raw.triangles {
            *t = t.map(|i| remap[i as usize]);
        }
    }
    let kept = (0..n as u32).filter(|&i| used[i as usize]).collect();
    (unused, kept)
}

/// How many triangles repeat a vertex or have zero area.
fn count_degenerate(raw: &Raw) -> usize {
    raw.triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| raw.positions[i as usize].as_dvec3());
            t[0] == t[1]
                || t[1] == t[2]
                || t[0] == t[2]
                || (b - a).cross(c - a) == glam::DVec3::ZERO
        })
        .count()
}

/// The mesh of the checked `raw`, and why its normals were recomputed, if they were.
fn into_mesh(raw: Raw) -> (Mesh, Option<&'static str>) {
    // The file's normals (normalised) when every one is usable; missing uvs are zero.
    let n = raw.positions.len();
    let normals_ok = raw.normals.len() == n
        && raw
            .normals
            .iter()
            .all(|v| v.is_finite() && v.length_squared() > 0.0);
    let recompute = if normals_ok {
        None
    } else if let Some(r) = raw.normals_incomplete {
        Some(r)
    } else if raw.normals.is_empty() {
        Some("the file has none")
    } else {
        Some("some are zero or non-finite")
    };
    let mut mesh = Mesh {
        positions: raw.positions,
        normals: if normals_ok {
            raw.normals.iter().map(|v| v.normalize()).collect()
        } else {
            vec![Vec3::Z; n]
        },
        uvs: if raw.uvs.len() == n {
            raw.uvs
        } else {
            vec![Vec2::ZERO; n]
        },
        indices: raw.triangles.into_iter().flatten().collect(),
    };
    if recompute.is_some() {
        mesh.recompute_normals();
    }
    (mesh, recompute)
}

/// Fan-triangulates a polygon `[v0, v1, ..., vk]` as `(v0, vi, vi+1)`.
pub(crate) fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for w in 1..poly.len().saturating_sub(1) {
        out.push([poly[0], poly[w], poly[w + 1]]);
    }
}
