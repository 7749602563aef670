//! The WGSL of this crate, embedded at compile time from its own `shaders/` directory and
//! composed with the shared snippets of [`npr_gpu::shaders`]. The passes compile
//! [`ShaderFile::full_source`]; the naga validation and uniform-layout tests read the same
//! text.

use npr_gpu::shaders::{FULLSCREEN, ShaderFile};

/// The warp pass (§3.3) and the MSAA depth resolve, after `fullscreen.wgsl`.
pub const WARP: ShaderFile = ShaderFile {
    name: "warp.wgsl",
    source: include_str!("../shaders/warp.wgsl"),
    prelude: &[FULLSCREEN],
};

/// Every shader file of this crate.
pub const ALL: &[ShaderFile] = &[WARP];
