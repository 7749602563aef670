//! Making sure a GPU adapter exists: Mesa's software Vulkan driver (lavapipe) is installed
//! on Debian/Ubuntu when running as root and no adapter is found.

use anyhow::{Context, bail};
use std::process::Command;

/// The exact command that installs the software Vulkan driver.
pub const INSTALL_HINT: &str = "apt-get install -y mesa-vulkan-drivers libvulkan1";

/// The Debian packages the windowed `npr view` test needs: the virtual X server and the X
/// client libraries winit loads at run time (it `dlopen`s them, so the build does not
/// need them and a missing one only shows when a window opens).
const XVFB_PACKAGES: [&str; 7] = [
    "xvfb",
    "xauth",
    "libxkbcommon-x11-0",
    "libx11-xcb1",
    "libxcursor1",
    "libxrandr2",
    "libxi6",
];

/// The exact command that installs them.
pub const XVFB_HINT: &str = "apt-get install -y xvfb xauth libxkbcommon-x11-0 libx11-xcb1 \
     libxcursor1 libxrandr2 libxi6";

/// The shared libraries of [`XVFB_PACKAGES`] that winit opens.
const X_CLIENT_LIBS: [&str; 6] = [
    "libX11.so.6",
    "libX11-xcb.so.1",
    "libXcursor.so.1",
    "libXrandr.so.2",
    "libXi.so.6",
    "libxkbcommon-x11.so.0",
];

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

/// Installs `packages` with apt-get, refreshing the package lists once when the first
/// try fails (a fresh image often has none).
fn apt_install(packages: &[&str]) -> anyhow::Result<()> {
    let install: Vec<&str> = ["install", "-y", "-qq"]
        .into_iter()
        .chain(packages.iter().copied())
        .collect();
    if apt(&install).is_err() {
        apt(&["update", "-qq"])?;
        apt(&install)?;
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
    apt_install(&["mesa-vulkan-drivers", "libvulkan1"])?;
    probe().map_err(|e| {
        anyhow::anyhow!(
            "still no GPU adapter after installing the driver: {e}\nTry: {INSTALL_HINT}"
        )
    })
}

/// Whether `xvfb-run` and every X client library winit opens are present.
fn has_xvfb() -> bool {
    let libs = Command::new("ldconfig")
        .arg("-p")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    Command::new("xvfb-run").arg("--help").output().is_ok()
        && X_CLIENT_LIBS.iter().all(|l| libs.contains(l))
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
            "xvfb-run or an X client library is missing: the windowed `npr view` test needs a \
             virtual X server. On Debian/Ubuntu run as root:\n    {XVFB_HINT}\nthen run \
             `cargo xtask test` again."
        );
    }
    eprintln!("xtask: installing Xvfb so the windowed `npr view` test can run: {XVFB_HINT}");
    apt_install(&XVFB_PACKAGES)?;
    if !has_xvfb() {
        bail!("still no xvfb-run or X client libraries after installing them; try: {XVFB_HINT}");
    }
    Ok(())
}

/// The exact command that installs the headless browser the page's test drives.
pub const CHROMIUM_HINT: &str = "apt-get install -y chromium chromium-driver";

/// Whether `chromium` and `chromedriver` both run.
fn has_chromium() -> bool {
    ["chromium", "chromedriver"].iter().all(|tool| {
        Command::new(tool)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// Makes sure Chromium and chromedriver exist for the browser test (`cargo xtask web
/// --check`), installing them on Debian/Ubuntu as root (and saying so; about 70 s).
///
/// # Errors
/// When they are missing and cannot be installed here; the message gives the command.
pub fn ensure_chromium() -> anyhow::Result<()> {
    if has_chromium() {
        return Ok(());
    }
    if !(is_debian_like() && is_root()) {
        bail!(
            "chromium or chromedriver is missing: the browser test runs the page in headless \
             Chromium. On Debian/Ubuntu run as root:\n    {CHROMIUM_HINT}\nthen run \
             `cargo xtask test` again."
        );
    }
    eprintln!("xtask: installing Chromium so the browser test can run: {CHROMIUM_HINT}");
    apt_install(&["chromium", "chromium-driver"])?;
    if !has_chromium() {
        bail!("still no chromium or chromedriver after installing them; try: {CHROMIUM_HINT}");
    }
    Ok(())
}
