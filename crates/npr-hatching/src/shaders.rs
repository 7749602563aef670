//! The WGSL of this crate, embedded at compile time from its own `shaders/` directory and
//! composed with the shared snippets of [`npr_gpu::shaders`]. The passes compile
//! [`ShaderFile::full_source`]; the naga validation and uniform-layout tests read the same
//! text.

use npr_gpu::shaders::{COMMON, FULLSCREEN, ShaderFile};

/// The hatching pass: Eq. (1)–(3), §3.1–§3.3, after `fullscreen.wgsl`.
pub const HATCHING: ShaderFile = ShaderFile {
    name: "hatching.wgsl",
    source: include_str!("../shaders/hatching.wgsl"),
    prelude: &[FULLSCREEN],
};
/// Hatching inputs: VSM shadow pass, tone + direction G-buffer, Phong + VSM; after
/// `common.wgsl`.
pub const HATCHING_SCENE: ShaderFile = ShaderFile {
    name: "hatching_scene.wgsl",
    source: include_str!("../shaders/hatching_scene.wgsl"),
    prelude: &[COMMON],
};
/// Separable blur of variance-shadow-map moments, after `fullscreen.wgsl`.
pub const VSM_BLUR: ShaderFile = ShaderFile {
    name: "vsm_blur.wgsl",
    source: include_str!("../shaders/vsm_blur.wgsl"),
    prelude: &[FULLSCREEN],
};

/// Every shader file of this crate.
pub const ALL: &[ShaderFile] = &[HATCHING, HATCHING_SCENE, VSM_BLUR];
