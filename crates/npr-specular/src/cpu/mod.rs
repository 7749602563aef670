//! The CPU backend: the per-mesh highlight set and its per-frame update (§3: the `N = H`
//! search, matching, regions `N·H ≥ σ`, projectors), the regions themselves, the §4.2
//! receivers by breadth-first search, and the face clusters both searches skip by.
//! Nothing here imports a GPU pass: [`crate::gpu`] reads the set's tables.

pub(crate) mod clusters;
pub mod region;
pub mod set;
pub mod visibility;

pub use set::{NO_FALLOFF, UpdateStats};
