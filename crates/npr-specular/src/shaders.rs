//! The WGSL of this crate, embedded at compile time from its own `shaders/` directory and
//! composed with the shared snippets of [`npr_gpu::shaders`]. The passes compile
//! [`ShaderFile::full_source`]; the naga validation and uniform-layout tests read the same
//! text.

use npr_gpu::shaders::{COMMON, NUMERIC, ShaderFile};

/// The highlight pass (Eq. (9), §5), after `common.wgsl`.
pub const SPECULAR_HIGHLIGHT: ShaderFile = ShaderFile {
    name: "specular_highlight.wgsl",
    source: include_str!("../shaders/specular_highlight.wgsl"),
    prelude: &[COMMON],
};

/// The `N = H` search (§3.1, Eq. (3)–(6)) as a compute pass, one face per invocation,
/// after `numeric.wgsl`.
pub const CENTRE_SEARCH: ShaderFile = ShaderFile {
    name: "centre_search.wgsl",
    source: include_str!("../shaders/centre_search.wgsl"),
    prelude: &[NUMERIC],
};

/// The §4.2 receivers as a compute pass, one workgroup per highlight's walk (no shared
/// snippet).
pub const RECEIVERS: ShaderFile = ShaderFile {
    name: "receivers.wgsl",
    source: include_str!("../shaders/receivers.wgsl"),
    prelude: &[],
};

/// The regions `N·H ≥ σ` grown and fitted with their moment ellipses as a compute pass,
/// one workgroup per seed, after `numeric.wgsl`.
pub const REGIONS: ShaderFile = ShaderFile {
    name: "regions.wgsl",
    source: include_str!("../shaders/regions.wgsl"),
    prelude: &[NUMERIC],
};

/// Every shader file of this crate.
pub const ALL: &[ShaderFile] = &[SPECULAR_HIGHLIGHT, CENTRE_SEARCH, RECEIVERS, REGIONS];
