//! `cargo xtask test`: rustfmt check, clippy with warnings denied, then every workspace
//! test with `NPR_REQUIRE_GPU=1`: a GPU test without an adapter fails, even when the
//! caller's environment has `NPR_SKIP_GPU=1` (see `npr_gpu::testing`).

use crate::{gpu_setup, project_root};
use anyhow::bail;
use std::process::Command;
use std::time::Instant;

fn cargo(args: &[&str], extra_env: &[(&str, &str)]) -> anyhow::Result<()> {
    let started = Instant::now();
    println!("xtask: cargo {}", args.join(" "));
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.args(args).current_dir(project_root());
    for (k, v) in extra_env {
        cmd.env(k, v);
    }
    let status = cmd.status()?;
    println!(
        "xtask: cargo {} finished in {:.1} s",
        args.first().copied().unwrap_or(""),
        started.elapsed().as_secs_f64()
    );
    if !status.success() {
        bail!("cargo {} failed ({status})", args.join(" "));
    }
    Ok(())
}

/// Runs the whole check.
pub fn run() -> anyhow::Result<()> {
    let started = Instant::now();
    cargo(&["fmt", "--all", "--", "--check"], &[])?;
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
    let adapter = gpu_setup::ensure_adapter()?;
    println!("xtask: GPU adapter: {adapter}");
    gpu_setup::ensure_xvfb()?;
    cargo(
        &["test", "--workspace", "--release", "--no-fail-fast"],
        &[(npr_gpu::testing::REQUIRE_GPU_ENV, "1")],
    )?;
    println!(
        "xtask: all checks passed in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
