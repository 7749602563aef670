//! `npr-web`: the `npr view` viewer in the browser, on WebGPU.
//!
//! Nothing here re-implements a pass or the viewer: the page drives `npr-app`'s
//! [`Renderer`](npr_app::engine::Renderer) (the same frame as `npr render` and `npr view`),
//! its [`ViewerState`](npr_app::viewer::state::ViewerState) (camera, picking and highlight
//! edits from the same [`Input`](npr_app::viewer::state::Input) events as the window) and its
//! presets (TOML in and out). The frame is rendered into the engine's offscreen target and
//! copied onto the canvas, whose texture is `rgba8unorm` (the same bytes as the sRGB target).
//!
//! The page (`web/index.html`) and the build (`cargo xtask web`) are outside this crate's
//! code. On native targets the crate is empty.

#[cfg(target_arch = "wasm32")]
mod app;

#[cfg(target_arch = "wasm32")]
pub use app::Viewer;
