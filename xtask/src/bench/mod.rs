//! Benchmarks: `cargo xtask bench NAME [--mesh PATH]... [--json PATH]`.

pub mod animation;
pub mod curvature;
pub mod curvature_gpu;
pub mod hatching;
pub mod hatching_coherence;
pub mod hatching_directions;
pub mod plotter;
pub mod specular;
pub mod specular_fidelity;
pub mod table;
pub mod vpype;
pub mod warp;
pub mod warp_clip;
pub mod warp_tables;

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
    "animation",
    "curvature",
    "specular",
    "specular-fidelity",
    "hatching",
    "hatching-directions",
    "hatching-coherence",
    "warp",
    "plotter",
];

/// The benchmarks that take `--mesh`.
const TAKE_MESHES: &[&str] = &[
    "animation",
    "hatching-directions",
    "hatching-coherence",
    "specular",
    "specular-fidelity",
    "plotter",
    "warp",
];

/// The benchmarks that take `--animation CLIP` (played on their `--mesh` models).
const TAKE_ANIMATION: &[&str] = &["specular-fidelity", "hatching-coherence", "warp"];

/// Runs benchmark `name` (on `meshes`, added to or instead of its defaults, where it
/// takes them).
pub fn run(
    name: &str,
    meshes: &[PathBuf],
    json: Option<&Path>,
    animation: Option<&str>,
) -> anyhow::Result<()> {
    if !meshes.is_empty() && !TAKE_MESHES.contains(&name) {
        anyhow::bail!(
            "benchmark `{name}` has fixed meshes; --mesh applies to: {}",
            TAKE_MESHES.join(", ")
        );
    }
    if animation.is_some() && !TAKE_ANIMATION.contains(&name) {
        anyhow::bail!(
            "benchmark `{name}` plays no clip; --animation applies to: {}",
            TAKE_ANIMATION.join(", ")
        );
    }
    if animation.is_some() && meshes.is_empty() && name != "warp" {
        anyhow::bail!("--animation plays a clip of a --mesh: name a rigged glTF with --mesh");
    }
    match name {
        "animation" => animation::run(meshes, json),
        "hatching-directions" => hatching_directions::run(meshes, json),
        "hatching-coherence" => hatching_coherence::run(meshes, json, animation),
        "curvature" => curvature::run(json),
        "specular" => specular::run(meshes, json),
        "specular-fidelity" => specular_fidelity::run(json, meshes, animation),
        "hatching" => hatching::run(json),
        "warp" => warp::run(json, meshes, animation),
        "plotter" => plotter::run(meshes, json),
        _ => anyhow::bail!("unknown benchmark `{name}`; known: {}", NAMES.join(", ")),
    }
}
