//! The crate's error type: every fallible entry point (OBJ loading, mesh validation)
//! returns a [`GeometryError`] whose variant says what went wrong and how to fix it.

use std::path::PathBuf;

/// Everything that can go wrong when reading or validating a mesh.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    /// The file could not be read (missing, no permission, not UTF-8 text).
    /// Fix: check the path and that the file is a plain-text Wavefront OBJ.
    #[error("cannot read {path}: {source}")]
    Unreadable {
        /// The path given to the loader.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The OBJ text could not be parsed (bad number, bad face line, face index out of
    /// range of the `v`/`vt`/`vn` lines, ...). Fix: repair or re-export the file; the
    /// reason names the parser's complaint.
    #[error("malformed OBJ {path}: {reason}")]
    Malformed {
        /// The path given to the loader.
        path: PathBuf,
        /// What the OBJ parser reported.
        reason: String,
    },
    /// The file parsed but holds no triangles (only points, lines or nothing).
    /// Fix: export the model with its faces.
    #[error("{path} has no faces")]
    NoFaces {
        /// The path given to the loader.
        path: PathBuf,
    },
    /// An OBJ face refers to a `v` line that does not exist (index past the end, or 0).
    /// Fix: the file was truncated or hand-edited; re-export it.
    #[error("{path}: a face uses a vertex index past the last `v` line")]
    ObjIndexOutOfRange {
        /// The path given to the loader.
        path: PathBuf,
    },
    /// A vertex position (or normal) is NaN or infinite. Fix: clean the model in a
    /// modeller; such coordinates have no geometric meaning.
    #[error("vertex {vertex} has a non-finite {what}")]
    NonFinite {
        /// Index of the offending vertex (render vertex, or `v` line for OBJ input).
        vertex: usize,
        /// `"position"` or `"normal"`.
        what: &'static str,
    },
    /// A triangle refers to a vertex that does not exist. Fix: the index buffer and the
    /// vertex arrays come from different meshes; rebuild one from the other.
    #[error("triangle {triangle} uses vertex {index}, but there are {vertex_count} vertices")]
    IndexOutOfRange {
        /// Triangle number (index / 3).
        triangle: usize,
        /// The out-of-range index.
        index: u32,
        /// Number of vertices available.
        vertex_count: usize,
    },
    /// The index buffer's length is not a multiple of 3, or the per-vertex arrays differ
    /// in length. Fix: build all attribute arrays for the same vertex set, triangles only.
    #[error("inconsistent mesh arrays: {0}")]
    Inconsistent(String),
}
