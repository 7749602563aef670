//! Making sure a GPU adapter exists: Mesa's software Vulkan driver (lavapipe) is installed
//! on Debian/Ubuntu when running as root and no adapter is found.

use anyhow::{Context, bail};
use std::process::Command;

/// The exact command that installs the software Vulkan driver.
pub const INSTALL_HINT: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

/// The exact command that installs the virtual X server the windowed `npr view` test uses.
pub const XVFB_HINT: &str = "apt-get install -y xvfb xauth";

/// See [`npr_app::ensure_runtime_dir`] (shared with the `npr` binary).
pub fn ensure_runtime_dir() -> anyhow::Result<()> {
    Ok(npr_app::ensure_runtime_dir()?)
}

fn probe() -> Result<String, String> {
    npr_gpu::GpuContext::new()
        .map(|c| c.adapter_summary())
        .map_err(|e| e.to_string())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

fn is_debian_like() -> bool {
    std::path::Path::new("/etc/debian_version").exists()
}

fn apt(args: &[&str]) -> anyhow::Result<()> {
    let status = Command::new("apt-get")
        .args(args)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .context("running apt-get")?;
    if !status.success() {
        bail!("apt-get {} failed ({status})", args.join(" "));
    }
    Ok(())
}

/// Returns the adapter summary, installing lavapipe first if needed and possible.
///
/// # Errors
/// When no adapter exists and the driver cannot be installed here; the message gives the
/// exact command to run.
pub fn ensure_adapter() -> anyhow::Result<String> {
    match probe() {
        Ok(summary) => return Ok(summary),
        Err(e) => eprintln!("xtask: no GPU adapter found: {e}"),
    }
    if !(is_debian_like() && is_root()) {
        bail!(
            "no GPU adapter found. Install a Vulkan driver; on Debian/Ubuntu run as root:\n    \
             {INSTALL_HINT}\nthen run `cargo xtask test` again."
        );
    }
    eprintln!(
        "xtask: installing Mesa's software Vulkan driver (lavapipe) so the GPU tests can run: \
         {INSTALL_HINT}"
    );
    if apt(&["install", "-y", "-qq", "mesa-vulkan-drivers", "libvulkan1"]).is_err() {
        apt(&["update", "-qq"])?;
        apt(&["install", "-y", "-qq", "mesa-vulkan-drivers", "libvulkan1"])?;
    }
    probe().map_err(|e| {
        anyhow::anyhow!(
            "still no GPU adapter after installing the driver: {e}\nTry: {INSTALL_HINT}"
        )
    })
}

fn has_xvfb() -> bool {
    Command::new("xvfb-run").arg("--help").output().is_ok()
}

/// Makes sure `xvfb-run` exists for the windowed `npr view` test, installing Xvfb on
/// Debian/Ubuntu as root (and saying so).
///
/// # Errors
/// When it is missing and cannot be installed here; the message gives the command.
pub fn ensure_xvfb() -> anyhow::Result<()> {
    if has_xvfb() {
        return Ok(());
    }
    if !(is_debian_like() && is_root()) {
        bail!(
            "xvfb-run not found: the windowed `npr view` test needs a virtual X server. On \
             Debian/Ubuntu run as root:\n    {XVFB_HINT}\nthen run `cargo xtask test` again."
        );
    }
    eprintln!("xtask: installing Xvfb so the windowed `npr view` test can run: {XVFB_HINT}");
    if apt(&["install", "-y", "-qq", "xvfb", "xauth"]).is_err() {
        apt(&["update", "-qq"])?;
        apt(&["install", "-y", "-qq", "xvfb", "xauth"])?;
    }
    if !has_xvfb() {
        bail!("still no xvfb-run after installing it; try: {XVFB_HINT}");
    }
    Ok(())
}
