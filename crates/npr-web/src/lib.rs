//! `npr-web`: the `npr view` viewer in the browser, on WebGPU.
//!
//! Nothing here re-implements a pass or the viewer: the page drives `npr-app`'s
//! `engine::Renderer` (the same frame as `npr render` and `npr view`), its
//! `viewer::state::ViewerState` (camera, picking and highlight edits from the same `Input`
//! events as the window) and its presets (TOML in and out). (Plain names, not links: on
//! native targets this crate has no dependencies to link to.) The frame is rendered into the engine's offscreen target and
//! copied onto the canvas, whose texture is `rgba8unorm` (the same bytes as the sRGB target).
//!
//! The page (`web/index.html`) and the build (`cargo xtask web`) are outside this crate's
//! code, and so are the browser check's comparisons of the compute passes with the CPU
//! (`check/`, a crate that only `cargo xtask web --check` builds). On native targets the
//! crate is empty.

#[cfg(target_arch = "wasm32")]
mod app;

#[cfg(target_arch = "wasm32")]
pub use app::Viewer;
