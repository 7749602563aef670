//! Running cargo from xtask: one timed call in the workspace root, shared by the test and
//! the web commands.

use crate::project_root;
use anyhow::bail;
use std::process::Command;
use std::time::Instant;

/// Cargo's target directory: `CARGO_TARGET_DIR` or the workspace's `target/`.
pub fn target_dir() -> std::path::PathBuf {
    let root = project_root();
    std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .map(|d| if d.is_absolute() { d } else { root.join(d) })
        .unwrap_or_else(|| root.join("target"))
}

/// Runs `cargo ARGS` in the workspace root with `extra_env`, timed; fails on failure.
pub fn cargo(args: &[&str], extra_env: &[(&str, &str)]) -> anyhow::Result<()> {
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
