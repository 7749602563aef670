#![doc = include_str!("../README.md")]
//!
//! Stylized specular highlights by curvature-driven texture projectors.
//!
//! Implements Hwan-Jik Lee and Jung-Ju Choi, "Stylized Specular Reflections Using
//! Projective Textures based on Principal Curvature Analysis", Journal of the Korea
//! Computer Graphics Society (Lee & Choi): highlight centres where `N = H` (§3.1, in
//! `npr-geometry`), orthographic projectors from the principal frame (Eq. (7)) sized to
//! the region `N·H ≥ σ` measured on the mesh (default, [`cpu::region`]) or by the principal
//! curvatures (Eq. (8), [`HighlightSizing::Paper`]), user controls (§3.4), visibility by
//! breadth-first search (§4.2), a highlight pass over any base shading (§5, Eq. (9)), and
//! the measurement of how well the highlights cover that region (`fidelity`, behind the
//! `test-support` feature).
//!
//! Per frame: [`HighlightSetup::prepare`] and [`HighlightSetup::record`] (on the
//! [`Backend`] chosen once per mesh: the CPU's [`HighlightSet::update`], or the whole
//! frame as compute passes) give a [`HighlightFrame`] → [`HighlightPass::prepare`] →
//! [`HighlightPass::draw`] (one draw call, recorded into the caller's render pass after
//! the base shading).

pub mod cpu;
mod error;
#[cfg(any(test, feature = "test-support"))]
pub mod fidelity;
pub mod gpu;
pub mod pass;
pub mod projector;
pub mod settings;
pub mod setup;
pub mod shaders;
#[cfg(any(test, feature = "test-support"))]
pub mod snapshot;
pub mod textures;

// The names an embedder needs; the stages and their records stay in `cpu` and `gpu`.
pub use cpu::region::Footprint;
pub use cpu::set::{
    DEFAULT_ABSTRACTION, Highlight, HighlightBoundary, HighlightSet, HighlightSizing,
};
pub use error::SpecularError;
pub use pass::{HighlightInput, HighlightObject, HighlightPass, HighlightSettings};
pub use projector::{HighlightControls, Projector, ProjectorControls, UpAxis};
pub use settings::{HighlightTuning, SpecularSettings};
pub use setup::{
    Backend, BackendChoice, BackendSetting, ChoiceReason, HighlightFrame, HighlightSetup,
    SetupInput, SetupObject, SetupPrepared, SetupSettings, SetupStats,
};
pub use textures::HighlightShape;
