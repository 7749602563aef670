//! Benchmarks: `cargo xtask bench NAME [--json PATH]`.

pub mod curvature;
pub mod hatching;
pub mod specular;
pub mod specular_fidelity;
pub mod table;
pub mod warp;

use std::path::{Path, PathBuf};

/// A progress bar of `len` steps labelled `what`, on stderr; indicatif draws nothing when
/// stderr is not a terminal, so piped output and `--json` runs stay clean.
pub fn progress(len: u64, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg:>28} [{bar:32}] {pos}/{len} {elapsed}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what.to_string());
    bar
}

/// The benchmarks by name.
pub const NAMES: &[&str] = &[
    "curvature",
    "specular",
    "specular-fidelity",
    "hatching",
    "warp",
];

/// Runs benchmark `name` (`meshes`: extra meshes, for the benchmarks that take them).
pub fn run(name: &str, json: Option<&Path>, meshes: &[PathBuf]) -> anyhow::Result<()> {
    match name {
        "curvature" => curvature::run(json),
        "specular" => specular::run(json),
        "specular-fidelity" => specular_fidelity::run(json, meshes),
        "hatching" => hatching::run(json),
        "warp" => warp::run(json),
        _ => anyhow::bail!("unknown benchmark `{name}`; known: {}", NAMES.join(", ")),
    }
}
