//! Benchmarks: `cargo xtask bench NAME [--json PATH]`.

pub mod curvature;
pub mod table;
pub mod warp;

use std::path::Path;

/// The benchmarks by name.
pub const NAMES: &[&str] = &["curvature", "warp"];

/// Runs benchmark `name`.
pub fn run(name: &str, json: Option<&Path>) -> anyhow::Result<()> {
    match name {
        "curvature" => curvature::run(json),
        "warp" => warp::run(json),
        _ => anyhow::bail!("unknown benchmark `{name}`; known: {}", NAMES.join(", ")),
    }
}
