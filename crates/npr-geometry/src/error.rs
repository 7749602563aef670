//! The crate's error type: every fallible entry point (model loading, mesh validation)
//! returns a [`GeometryError`] whose variant says what went wrong and how to fix it.

/// Everything that can go wrong when reading or validating a mesh.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    /// A model file could not be loaded: see [`crate::io::LoadError`] and its
    /// [`kind`](crate::io::LoadError::kind).
    #[error(transparent)]
    Load(#[from] crate::io::LoadError),
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
