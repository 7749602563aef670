#![doc = include_str!("../README.md")]
//!
//! Stylized specular highlights by curvature-driven texture projectors.
//!
//! Implements Hwan-Jik Lee and Jung-Ju Choi, "Stylized Specular Reflections Using
//! Projective Textures based on Principal Curvature Analysis", Journal of the Korea
//! Computer Graphics Society (Lee & Choi): highlight centres where `N = H` (§3.1, in
//! `npr-geometry`), orthographic projectors from the principal frame (Eq. (7)) sized to
//! the region `N·H ≥ σ` measured on the mesh (default, [`region`]) or by the principal
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

mod error;
#[cfg(any(test, feature = "test-support"))]
pub mod fidelity;
pub mod frame_gpu;
pub mod pass;
pub mod projector;
pub mod projector_pass;
pub mod receiver_pass;
pub mod region;
pub mod region_pass;
pub mod repose_pass;
mod search_clusters;
pub mod search_pass;
pub mod set;
pub mod setup;
pub mod shaders;
#[cfg(any(test, feature = "test-support"))]
pub mod snapshot;
pub mod textures;
pub mod visibility;

pub use error::SpecularError;
pub use frame_gpu::FrameOnGpu;
pub use pass::{
    HighlightInput, HighlightObject, HighlightPass, HighlightSettings, ProjectorGpu, projector_gpu,
};
pub use projector::{
    HighlightControls, Projector, ProjectorControls, UpAxis, eq8_footprint, frustum_size,
};
pub use projector_pass::{
    GpuFrame, GpuFrameStatus, GpuHighlight, MAX_DRAWN, PendingFrame, ProjectorInput,
    ProjectorObject, ProjectorPass,
};
pub use receiver_pass::{
    DEFAULT_WALK_CAPACITY, PendingReceivers, ReceiverCounts, ReceiverInput, ReceiverObject,
    ReceiverPass, ReceiverReadback,
};
pub use region::Footprint;
pub use region_pass::{
    DEFAULT_REGION_CAPACITY, GpuRegion, MAX_REGION_SEEDS, MAX_TRACKED, PendingRegions,
    PendingTracked, RegionInput, RegionObject, RegionPass, TRACKED_SEEDS, TrackStatus,
    TrackedInput, TrackedRegions, TrackedSeed,
};
pub use repose_pass::{ReposeInput, ReposeObject, ReposePass, ReposeTargets};
pub use search_pass::{
    CentreSearchPass, MAX_MERGED, PendingSolutions, SearchInput, SearchObject, SearchSolutions,
};
pub use set::{
    DEFAULT_ABSTRACTION, Highlight, HighlightBoundary, HighlightSet, HighlightSizing, NO_FALLOFF,
    UpdateStats,
};
pub use setup::{
    Backend, BackendChoice, BackendSetting, ChoiceReason, HighlightFrame, HighlightSetup,
    SetupInput, SetupObject, SetupPrepared, SetupSettings, SetupStats,
};
pub use textures::HighlightShape;
