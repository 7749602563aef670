//! Benchmarks: `cargo xtask bench NAME [--json PATH]`.

pub mod curvature;
pub mod hatching;
pub mod specular;
pub mod table;
pub mod warp;

use std::path::Path;

/// The benchmarks by name.
pub const NAMES: &[&str] = &["curvature", "specular", "hatching", "warp"];

/// Runs benchmark `name`.
pub fn run(name: &str, json: Option<&Path>) -> anyhow::Result<()> {
    match name {
        "curvature" => curvature::run(json),
        "specular" => specular::run(json),
        "hatching" => hatching::run(json),
        "warp" => warp::run(json),
        _ => anyhow::bail!("unknown benchmark `{name}`; known: {}", NAMES.join(", ")),
    }
}
