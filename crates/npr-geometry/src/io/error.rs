//! [`LoadError`]: what went wrong while loading a model file, and where.

/// Everything that can go wrong in [`crate::io::load`] / [`crate::io::load_bytes`].
///
/// Every variant names the file (`file`: the path as given, or the name passed with the
/// bytes) and, where one exists, the place in it (`at`: a line, byte offset, element,
/// accessor or primitive). [`LoadError::kind`] is a stable short name for scripts and
/// tests; `Display` is one line.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file does not exist. Fix: check the path.
    #[error("{file}: no such file")]
    Missing {
        /// The file.
        file: String,
    },
    /// The file exists but could not be read (permissions, a directory, ...).
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file.
        file: String,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The file has no content (zero bytes, or only whitespace for text formats).
    #[error("{file}: the file is empty")]
    Empty {
        /// The file.
        file: String,
    },
    /// The extension names no supported format. Fix: convert to OBJ, glTF/GLB or PLY.
    #[error("{file}: unsupported format `{extension}` (supported: .obj, .gltf, .glb, .ply)")]
    UnsupportedFormat {
        /// The file.
        file: String,
        /// The extension found (empty when there is none).
        extension: String,
    },
    /// The content does not follow the format (bad number, bad header line, bad JSON,
    /// inconsistent accessor, ...). Fix: re-export the file.
    #[error("{file}: {at}: {reason}")]
    Parse {
        /// The file.
        file: String,
        /// Where.
        at: String,
        /// What the parser found.
        reason: String,
    },
    /// The file ends before the data its header announces. Fix: the file was cut off
    /// (interrupted download or copy); fetch it again.
    #[error("{file}: truncated at {at}: {reason}")]
    Truncated {
        /// The file.
        file: String,
        /// Where the data runs out.
        at: String,
        /// What was expected there.
        reason: String,
    },
    /// A face refers to a vertex that does not exist.
    #[error("{file}: {at}: vertex index {index} is out of range ({count} vertices)")]
    IndexOutOfRange {
        /// The file.
        file: String,
        /// The face (line, element or primitive) holding the index.
        at: String,
        /// The offending index as written in the file.
        index: i64,
        /// How many vertices there are.
        count: usize,
    },
    /// A coordinate is NaN or infinite. Fix: clean the model in a modeller.
    #[error("{file}: {at}: non-finite {what}")]
    NonFinite {
        /// The file.
        file: String,
        /// The vertex (line, element index or accessor element).
        at: String,
        /// `"position"`, `"normal"`, ... and the value read.
        what: String,
    },
    /// A glTF file requires an extension this loader does not implement (mesh
    /// compression, quantised attributes, ...). Fix: re-export from the modeller without
    /// Draco/meshopt compression or quantisation (gltf-transform's `dequantize` undoes
    /// `KHR_mesh_quantization`).
    #[error("{file}: requires glTF extension `{extension}`, which is not supported")]
    UnsupportedExtension {
        /// The file.
        file: String,
        /// The extension's name, as in `extensionsRequired`.
        extension: String,
    },
    /// A valid file uses a feature this loader does not implement (sparse accessors, an
    /// external buffer when loading from bytes).
    #[error("{file}: {at}: {feature} is not supported")]
    UnsupportedFeature {
        /// The file.
        file: String,
        /// Where.
        at: String,
        /// What.
        feature: String,
    },
    /// A skin, morph target or animation cannot be used (joint index out of range, key
    /// times that do not increase, NaN keys, CUBICSPLINE outputs not three per key, a
    /// skinned primitive without `JOINTS_0`, ...). Fix: re-export the animation.
    #[error("{file}: {at}: {error}")]
    Animation {
        /// The file.
        file: String,
        /// Where (mesh and primitive, skin, or animation and channel).
        at: String,
        /// What is wrong; [`crate::animation::AnimationError::kind`] names it.
        error: Box<crate::animation::AnimationError>,
    },
    /// The file parsed but holds no triangle (only points, lines, or nothing).
    /// Fix: export the model with its faces.
    #[error("{file}: no triangles ({detail})")]
    NoTriangles {
        /// The file.
        file: String,
        /// What was found instead.
        detail: String,
    },
}

impl LoadError {
    /// A stable short name for the kind of error: `missing`, `io`, `empty`,
    /// `unsupported-format`, `parse`, `truncated`, `index-out-of-range`, `non-finite`,
    /// `unsupported-extension`, `unsupported-feature`, `no-triangles`, `animation`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Missing { .. } => "missing",
            Self::Io { .. } => "io",
            Self::Empty { .. } => "empty",
            Self::UnsupportedFormat { .. } => "unsupported-format",
            Self::Parse { .. } => "parse",
            Self::Truncated { .. } => "truncated",
            Self::IndexOutOfRange { .. } => "index-out-of-range",
            Self::NonFinite { .. } => "non-finite",
            Self::UnsupportedExtension { .. } => "unsupported-extension",
            Self::UnsupportedFeature { .. } => "unsupported-feature",
            Self::NoTriangles { .. } => "no-triangles",
            Self::Animation { .. } => "animation",
        }
    }

    /// The file the error is about.
    pub fn file(&self) -> &str {
        match self {
            Self::Missing { file }
            | Self::Io { file, .. }
            | Self::Empty { file }
            | Self::UnsupportedFormat { file, .. }
            | Self::Parse { file, .. }
            | Self::Truncated { file, .. }
            | Self::IndexOutOfRange { file, .. }
            | Self::NonFinite { file, .. }
            | Self::UnsupportedExtension { file, .. }
            | Self::UnsupportedFeature { file, .. }
            | Self::NoTriangles { file, .. }
            | Self::Animation { file, .. } => file,
        }
    }
}

/// Collapses a multi-line parser message into one line.
pub(crate) fn one_line(s: &str) -> String {
    s.split(['\n', '\r', '\t'])
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
