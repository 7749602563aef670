//! The GPU backend: each stage of a frame's highlight setup as a compute pass on the pass
//! contract (`new`, `create_object`, `prepare`, `record`), the whole frame they make
//! together ([`FrameOnGpu`], which [`crate::HighlightSetup`] drives on
//! [`crate::Backend::Gpu`]), and the tables they read of a set (`tables`, crate-private). Each stage
//! has a CPU reference in [`crate::cpu`] that its tests compare it with.
//!
//! In the order a frame records them: [`ReposePass`] (a new pose's tables),
//! [`CentreSearchPass`] (`N = H` and the peaks), [`RegionPass`] (the regions `N·H ≥ σ`,
//! seeded from the centres matched with the last frame's highlights), [`ProjectorPass`]
//! (projectors, fades, edits) and [`ReceiverPass`] (§4.2, and the draw's arguments).

pub mod frame;
pub mod projectors;
pub mod receivers;
pub mod regions;
pub mod repose;
pub mod search;
pub(crate) mod tables;

pub use crate::pass::{ProjectorGpu, projector_gpu};
pub use frame::FrameOnGpu;
pub use projectors::{
    GpuFrame, GpuFrameStatus, GpuHighlight, MAX_DRAWN, PendingFrame, ProjectorInput,
    ProjectorObject, ProjectorPass,
};
pub use receivers::{
    DEFAULT_WALK_CAPACITY, PendingReceivers, ReceiverCounts, ReceiverInput, ReceiverObject,
    ReceiverPass, ReceiverReadback,
};
pub use regions::{
    DEFAULT_REGION_CAPACITY, GpuRegion, MAX_REGION_SEEDS, MAX_TRACKED, PendingRegions,
    PendingTracked, RegionInput, RegionObject, RegionPass, TRACKED_SEEDS, TrackStatus,
    TrackedInput, TrackedRegions, TrackedSeed,
};
pub use repose::{ReposeInput, ReposeObject, ReposePass, ReposeTargets};
pub use search::{
    CentreSearchPass, MAX_MERGED, PendingSolutions, SearchInput, SearchObject, SearchSolutions,
};
