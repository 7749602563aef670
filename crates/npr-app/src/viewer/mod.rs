//! `npr view [MODEL]`: the live window (winit + egui). The 3-D view is the same
//! [`Renderer`](crate::engine::Renderer) as `npr render`, drawn into its offscreen target and shown as an egui image,
//! so a screenshot of the view equals `npr render` of the saved preset.
//!
//! Mouse: left-drag orbits (or moves the picked highlight along e_max/e_min), Shift-drag
//! turns the picked highlight about N, the wheel zooms (or scales the picked highlight),
//! right-drag pans, Ctrl-drag moves the light. Keys: 1–7 effects, T turntable, R reset
//! view, Escape deselects, space plays or pauses a glTF model's clip ([`timeline`]).
//! Models can be dropped on the window.

//!
//! The window's state and input ([`state`]), the script format ([`script`]) and live
//! warping ([`live`]) need no window, and are shared with the web front end (`npr-web`);
//! the winit + egui shell around them is native only.

pub mod live;
pub mod script;
pub mod state;
pub mod timeline;

#[cfg(not(target_arch = "wasm32"))]
mod desktop;
#[cfg(not(target_arch = "wasm32"))]
mod ui;

#[cfg(not(target_arch = "wasm32"))]
pub use desktop::*;
