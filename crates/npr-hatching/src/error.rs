//! The typed errors of `npr-hatching`.

/// Everything that can go wrong in `npr-hatching`. No function of the crate panics on bad
/// input; it returns one of these.
#[derive(Debug, thiserror::Error)]
pub enum HatchError {
    /// An image or target of zero (or too large) size. Cause: a width or height of 0, or a
    /// pixel count that overflows. Fix: pass a size of at least 1×1.
    #[error("invalid size {width}x{height}: {reason}")]
    InvalidSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// Two inputs that must have the same length do not. Cause: e.g. a tone image of
    /// `width × height` values with a direction image of another size, or one stroke
    /// direction per *welded* vertex where one per render vertex is needed. Fix: pass one
    /// value per pixel (images) or per render vertex (directions).
    #[error("length mismatch for {what}: expected {expected}, got {actual}")]
    LengthMismatch {
        /// Which input.
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        actual: usize,
    },
    /// A tonal-art-map parameter is out of its range. Cause: a texture size that is not a
    /// power of two in 16..=2048, fewer than 6 or more than 32 tones, a maximum coverage
    /// outside (0, 1]. Fix: use [`crate::TamParams::pen`] / [`crate::TamParams::pencil`] and
    /// change one field at a time within the ranges documented there.
    #[error("invalid tonal art map parameter {what}: {reason}")]
    InvalidTam {
        /// Which parameter.
        what: &'static str,
        /// The accepted range.
        reason: String,
    },
    /// A hatching parameter is out of its range. Cause: a bin count outside 12..=24
    /// (Eq. (1), §3.1 of the paper) or a stroke scale that is not a finite positive number.
    /// Fix: see [`crate::HatchParams`] for the ranges.
    #[error("invalid hatching parameter {what}: {reason}")]
    InvalidParams {
        /// Which parameter.
        what: &'static str,
        /// The accepted range.
        reason: String,
    },
    /// A GPU resource could not be created or read back. Cause: the device was lost, a
    /// texture exceeds the device limits, or readback failed. Fix: check the wrapped
    /// message; use a smaller target or a more capable adapter.
    #[error(transparent)]
    Gpu(#[from] npr_gpu::GpuError),
    /// A pass refused an object or its prepared state (see [`npr_gpu::PassError`]).
    #[error(transparent)]
    Pass(#[from] npr_gpu::PassError),
}
