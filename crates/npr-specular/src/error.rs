//! The typed errors of `npr-specular`.

/// Everything that can go wrong when building highlights.
#[derive(Debug, thiserror::Error)]
pub enum SpecularError {
    /// The mesh has no usable triangles. Cause: an empty mesh or one whose every face is
    /// degenerate. Fix: pass a mesh with at least one non-degenerate triangle.
    #[error("the mesh has no usable triangles")]
    EmptyMesh,
    /// The mesh, topology and curvature field disagree in size. Cause: they were built
    /// from different meshes. Fix: build all three from the same mesh
    /// (`CurvatureField::for_mesh`).
    #[error("mesh and curvature data disagree: {0}")]
    Mismatch(String),
    /// A highlight texture could not be read. Cause: missing or non-PNG file. Fix: pass a
    /// readable PNG.
    #[error("cannot read highlight texture {path}: {reason}")]
    Texture {
        /// The file.
        path: String,
        /// What failed.
        reason: String,
    },
    /// More highlight textures than the layer limit, or textures of different sizes.
    /// Fix: resize to one square size and pass at most the device's array-layer limit.
    #[error("invalid highlight texture set: {0}")]
    TextureSet(String),
    /// A pass refused an object or its prepared state (see [`npr_gpu::PassError`]).
    #[error(transparent)]
    Pass(#[from] npr_gpu::PassError),
    /// A frame made wholly on the GPU, which a measure waited for, was not made
    /// ([`crate::gpu::GpuFrameStatus::Held`]: its regions found no room however often it was
    /// made again). Fix: measure the frame with the CPU's update.
    #[error("the GPU did not make the frame ({0:?})")]
    GpuFrame(crate::gpu::GpuFrameStatus),
    /// A GPU-layer error.
    #[error(transparent)]
    Gpu(#[from] npr_gpu::GpuError),
}
