//! `cargo xtask test`: rustfmt check, clippy with warnings denied, the API docs with
//! rustdoc warnings denied (broken intra-doc links included), every workspace test with
//! `NPR_REQUIRE_GPU=1` (a GPU test without an adapter fails, even when the caller's
//! environment has `NPR_SKIP_GPU=1`; see `npr_gpu::testing`), then every library crate's
//! `embed` example, each writing its PNG to `target/embed/`; then the browser build in
//! headless Chromium (`cargo xtask web --check`, installing Chromium as root when missing).

use crate::cargo::cargo;
use crate::{gpu_setup, project_root};
use anyhow::bail;
use std::time::Instant;

/// The crates whose `examples/embed.rs` (the README's embedding example) the check runs.
pub const EMBED_CRATES: [&str; 3] = ["npr-specular", "npr-hatching", "npr-warp"];

/// Runs the whole check.
pub fn run() -> anyhow::Result<()> {
    let started = Instant::now();
    cargo(&["fmt", "--all", "--", "--check"], &[])?;
    // The browser front end is its own workspace (see crates/npr-web/Cargo.toml).
    cargo(
        &[
            "fmt",
            "--all",
            "--manifest-path",
            "crates/npr-web/Cargo.toml",
            "--",
            "--check",
        ],
        &[],
    )?;
    cargo(
        &[
            "clippy",
            "--workspace",
            "--all-targets",
            "--release",
            "--",
            "-D",
            "warnings",
        ],
        &[],
    )?;
    cargo(
        &["doc", "--no-deps", "--workspace", "--release"],
        &[("RUSTDOCFLAGS", "-D warnings")],
    )?;
    let adapter = gpu_setup::ensure_adapter()?;
    println!("xtask: GPU adapter: {adapter}");
    gpu_setup::ensure_xvfb()?;
    cargo(
        &["test", "--workspace", "--release", "--no-fail-fast"],
        &[(npr_gpu::testing::REQUIRE_GPU_ENV, "1")],
    )?;
    let out_dir = project_root().join("target/embed");
    std::fs::create_dir_all(&out_dir)?;
    for krate in EMBED_CRATES {
        let png = out_dir.join(format!("{krate}.png"));
        let png = png.to_string_lossy();
        cargo(
            &[
                "run",
                "--release",
                "-p",
                krate,
                "--example",
                "embed",
                "--",
                &png,
            ],
            &[(npr_gpu::testing::REQUIRE_GPU_ENV, "1")],
        )?;
        if !std::path::Path::new(png.as_ref()).is_file() {
            bail!("the {krate} embed example did not write {png}");
        }
    }
    // The browser: the page built for wasm32 and run in headless Chromium against the
    // native render (`cargo xtask web --check`).
    gpu_setup::ensure_chromium()?;
    let web_started = Instant::now();
    crate::web::run(false, true, 0)?;
    println!(
        "xtask: the browser build and test took {:.1} s",
        web_started.elapsed().as_secs_f64()
    );
    println!(
        "xtask: all checks passed in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
