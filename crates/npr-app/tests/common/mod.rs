//! What the app's test binaries share: the workspace root, a fresh output folder per
//! test, the `npr` binary, and the frames of a GIF it wrote.
// Each test binary uses its own share of these.
#![allow(dead_code, clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An empty folder for test `name` of this process.
pub fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("npr-app-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the `npr` binary with `args`, waiting for its output.
pub fn npr(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_npr"))
        .args(args)
        .output()
        .unwrap()
}

/// The frames of the GIF at `path`.
pub fn gif_frames(path: &Path) -> Vec<image::Frame> {
    use image::AnimationDecoder as _;
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(path).unwrap(),
    ))
    .unwrap();
    decoder.into_frames().collect_frames().unwrap()
}
