//! The typed errors of `npr-warp`.

/// Everything that can go wrong in `npr-warp`.
#[derive(Debug, thiserror::Error)]
pub enum WarpError {
    /// The mesh has no triangles (or no vertices). Cause: an empty or fully degenerate
    /// input. Fix: pass a mesh with at least one non-degenerate triangle.
    #[error("the mesh is empty: {0}")]
    EmptyMesh(String),
    /// The mesh breaks the `npr_geometry::Mesh` invariants (array lengths, index range,
    /// finite positions). Fix: run `Mesh::validate` and repair the input.
    #[error("invalid mesh: {0}")]
    InvalidMesh(#[from] npr_geometry::GeometryError),
    /// The proxy ratio is not in `(0, 1]` (or not finite). Cause: a percentage passed as
    /// a number like `5.0` instead of `0.05`, or zero. Fix: pass the kept fraction of
    /// triangles, e.g. `0.02` for the paper's 2 %.
    #[error("proxy ratio {0} is outside (0, 1]")]
    RatioOutOfRange(f32),
    /// The simplifier kept no triangle. Cause: a ratio so small that fewer than one
    /// triangle is targeted on a tiny mesh. Fix: raise the ratio.
    #[error("simplifying {triangles} triangles to ratio {ratio} left nothing")]
    SimplifiedAway {
        /// Triangles of the input.
        triangles: usize,
        /// Requested ratio.
        ratio: f32,
    },
    /// The normal-bin grid has zero bins per axis (§3.3.2 needs N ≥ 1). Fix: pass N ≥ 1
    /// (the paper's trade-off: a larger N culls closer to the silhouette, costs more draws).
    #[error("bins per axis must be at least 1 (got {0})")]
    ZeroBins(u32),
    /// Too many bins: `N × N` draw ranges above [`crate::bins::MAX_BINS_PER_AXIS`]². Fix:
    /// use a smaller N; beyond ~64 the bins hold a handful of faces each and only add draws.
    #[error("bins per axis {0} exceeds the maximum {max}", max = crate::bins::MAX_BINS_PER_AXIS)]
    TooManyBins(u32),
    /// The warp period k is zero (a reference every k frames needs k ≥ 1). Fix: pass k ≥ 1.
    #[error("the reference period k must be at least 1")]
    ZeroPeriod,
    /// A setting is outside its documented range (named in the message). Fix: use a value
    /// in the documented range.
    #[error("invalid setting: {0}")]
    InvalidSetting(String),
    /// A base pass, renderer or caller's target has another sample count than the pass it
    /// is recorded into (e.g. a [`crate::PhongBase`] built for one-sample targets recorded
    /// into a multisampled reference, or a multisampled [`crate::FullRenderer`] recorded
    /// into a one-sample target); wgpu would reject the draw. Fix: build both for the same
    /// [`npr_gpu::TargetFormats`] (e.g. [`crate::Antialiasing::references`]).
    #[error("{what} has {got} sample(s) per pixel, the pass it is recorded into {expected}")]
    SampleCountMismatch {
        /// What mismatches (the base pass, the renderer, the target).
        what: &'static str,
        /// Its samples per pixel.
        got: u32,
        /// The pass's samples per pixel.
        expected: u32,
    },
    /// A pose that is not a pose of the proxy's mesh or object (another vertex count, a
    /// non-finite position). Fix: pose the mesh the proxy was simplified from, keeping its
    /// vertices and triangles.
    #[error("not a pose of this proxy: {0}")]
    PoseMismatch(String),
    /// The GPU layer failed (target size, mesh upload, readback). Fix: see the wrapped
    /// [`npr_gpu::GpuError`].
    #[error(transparent)]
    Gpu(#[from] npr_gpu::GpuError),
    /// A pass refused an object or its prepared state (see [`npr_gpu::PassError`]).
    #[error(transparent)]
    Pass(#[from] npr_gpu::PassError),
}

impl WarpError {
    /// `Ok` when `got == expected`, else [`WarpError::SampleCountMismatch`].
    pub(crate) fn check_samples(what: &'static str, got: u32, expected: u32) -> Result<(), Self> {
        if got == expected {
            Ok(())
        } else {
            Err(Self::SampleCountMismatch {
                what,
                got,
                expected,
            })
        }
    }
}
