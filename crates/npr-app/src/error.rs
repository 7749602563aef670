//! The application's typed errors: one line each, naming what is wrong and where.

use std::path::{Path, PathBuf};

/// Everything `npr` can fail with. Each message is one line that names the file or the
/// setting at fault; nothing here panics and no command leaves a partial output file.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The model could not be loaded (the loader's message names the file and the place).
    #[error("{source}")]
    Load {
        /// The model file.
        path: PathBuf,
        /// The loader's typed error (`kind()` is a stable name).
        #[source]
        source: npr_geometry::io::LoadError,
    },
    /// The model loaded but is unusable (a geometry-layer error).
    #[error("{0}")]
    Geometry(#[from] npr_geometry::GeometryError),
    /// A preset file is malformed or holds an invalid value.
    #[error("preset {path}: {reason}")]
    Preset {
        /// The preset file.
        path: PathBuf,
        /// What is wrong (with the TOML line and column where known).
        reason: String,
    },
    /// `npr view` found no display to open a window on.
    #[error("npr view: {0}")]
    NoDisplay(String),
    /// A command-line value is invalid.
    #[error("{0}")]
    Usage(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// Encoding an image failed.
    #[error("{path}: cannot encode image: {reason}")]
    Encode {
        /// The output file.
        path: PathBuf,
        /// The encoder's message.
        reason: String,
    },
    /// The GPU layer failed (no adapter, a size past the device's limits, readback).
    #[error(transparent)]
    Gpu(#[from] npr_gpu::GpuError),
    /// The specular technique failed.
    #[error("specular: {0}")]
    Specular(#[from] npr_specular::SpecularError),
    /// The hatching technique failed.
    #[error("hatching: {0}")]
    Hatching(#[from] npr_hatching::HatchError),
    /// The warping technique failed.
    #[error("warp: {0}")]
    Warp(#[from] npr_warp::WarpError),
}

impl AppError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// A short stable name of the error's kind (for tests and scripts).
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Load { .. } => "load",
            Self::Geometry(_) => "geometry",
            Self::Preset { .. } => "preset",
            Self::Usage(_) => "usage",
            Self::NoDisplay(_) => "no-display",
            Self::Io { .. } => "io",
            Self::Encode { .. } => "encode",
            Self::Gpu(_) => "gpu",
            Self::Specular(_) => "specular",
            Self::Hatching(_) => "hatching",
            Self::Warp(_) => "warp",
        }
    }
}

impl From<npr_gpu::PassError> for AppError {
    fn from(e: npr_gpu::PassError) -> Self {
        Self::from(npr_gpu::GpuError::from(e))
    }
}
