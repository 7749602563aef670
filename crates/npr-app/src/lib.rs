//! The `npr` application: the three techniques of the workspace applied to a user's own
//! model, through the technique crates' public API only (as any outside user would).
//!
//! - `npr render MODEL --effect E`: batch images, turntables and GIFs ([`render`]).
//! - `npr view [MODEL]`: the live window ([`viewer`]).
//! - `npr curvature IN OUT.csv`: per-vertex principal curvatures ([`curvature`]).
//!
//! The pieces are a library so that tests (and the viewer) drive the same code paths:
//! [`preset::Preset`] (every parameter, TOML), [`model::Model`] (loading and framing),
//! [`view`] (camera and light), [`engine::Renderer`] (the GPU frame).
//!
//! On wasm32 (the browser, through `npr-web`) the library keeps what a page shares with the
//! desktop viewer (presets, models, views, the engine, [`viewer::state`] and
//! [`viewer::script`]); the command line, the batch renderer and the winit + egui window
//! are native only.
#![cfg_attr(test, allow(clippy::unwrap_used, clippy::expect_used))]

pub mod animation;
#[cfg(not(target_arch = "wasm32"))]
pub mod curvature;
pub mod engine;
mod error;
#[cfg(not(target_arch = "wasm32"))]
pub mod memory;
pub mod model;
pub mod output;
pub mod preset;
#[cfg(not(target_arch = "wasm32"))]
pub mod progress;
#[cfg(not(target_arch = "wasm32"))]
pub mod render;
pub mod view;
pub mod viewer;

pub use error::AppError;

/// Gives Mesa's Vulkan drivers a private `XDG_RUNTIME_DIR` when the environment has none
/// (a bare CI shell or container): without it they print an error on every start.
///
/// Call it at the start of `main`, before any thread exists.
///
/// # Errors
/// [`AppError::Io`] when the directory cannot be created.
#[cfg(not(target_arch = "wasm32"))]
pub fn ensure_runtime_dir() -> Result<(), AppError> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return Ok(());
    }
    let dir = std::env::temp_dir().join(format!("npr-xdg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| AppError::io(&dir, e))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
            .map_err(|e| AppError::io(&dir, e))?;
    }
    // SAFETY: documented precondition: called at the start of `main`, before the program
    // starts any thread, so nothing reads the environment concurrently. Children inherit it.
    #[allow(unsafe_code)]
    unsafe {
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
    Ok(())
}
