//! What the paper-figure examples of the technique crates share (`examples/fig*.rs`,
//! run alone or by `cargo xtask demo`): where figures go, where the project's meshes are,
//! a framing camera, contact sheets, and a save that reports each file written.
//!
//! An example writes its PNGs into [`out_dir`] and prints `wrote PATH` for each
//! ([`save`]), which is how `cargo xtask demo` learns what it wrote.

use crate::Camera;
use glam::{Mat4, Vec3};
use npr_geometry::Mesh;
use std::path::{Path, PathBuf};

/// The environment variable naming the figures' directory when no argument does.
pub const OUT_DIR_ENV: &str = "NPR_FIGURES_DIR";

/// The repository's workspace root (two levels above this crate's manifest; where the
/// fixtures are in a checkout, not in a packaged crate).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// Where an example writes its figures: its first command-line argument, else
/// [`OUT_DIR_ENV`], else `target/figures` under the current directory (the workspace
/// root under `cargo run`); created if missing.
///
/// # Errors
/// Creating the directory failing.
pub fn out_dir() -> std::io::Result<PathBuf> {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .or_else(|| std::env::var_os(OUT_DIR_ENV).map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("target/figures"));
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

/// `fixtures/meshes/NAME`: the real meshes the project ships (not in the packaged crates).
pub fn fixture_mesh(name: &str) -> PathBuf {
    workspace_root().join("fixtures/meshes").join(name)
}

/// A camera framing `mesh` (bounding sphere) from a three-quarter view, and the transform
/// that normalizes the mesh to a unit bounding sphere at the origin.
pub fn framing_camera(mesh: &Mesh, aspect: f32) -> (Camera, Mat4) {
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo) * 0.5).length().max(1e-6);
    let world_from_object =
        Mat4::from_scale(Vec3::splat(1.0 / radius)) * Mat4::from_translation(-centre);
    let eye = Vec3::new(0.9, 0.6, 2.4).normalize() * 2.3;
    (Camera::look_at(eye, Vec3::ZERO, aspect), world_from_object)
}

/// Copies `tile` into `sheet` at (x, y).
pub fn paste(sheet: &mut image::RgbaImage, tile: &image::RgbaImage, x: u32, y: u32) {
    image::imageops::replace(sheet, tile, i64::from(x), i64::from(y));
}

/// `tiles` in a grid `columns` wide on white, each cell the size of the first tile.
pub fn sheet(tiles: &[image::RgbaImage], columns: u32) -> image::RgbaImage {
    let columns = columns.max(1);
    let (tw, th) = tiles.first().map_or((1, 1), |t| t.dimensions());
    let rows = (tiles.len() as u32).div_ceil(columns);
    let mut s = image::RgbaImage::from_pixel(tw * columns, th * rows, image::Rgba([255; 4]));
    for (i, t) in tiles.iter().enumerate() {
        let i = i as u32;
        paste(&mut s, t, (i % columns) * tw, (i / columns) * th);
    }
    s
}

/// `tiles` in one row ([`sheet`]).
pub fn row(tiles: &[image::RgbaImage]) -> image::RgbaImage {
    sheet(tiles, tiles.len() as u32)
}

/// Writes `image` to `path` and prints `wrote PATH`.
///
/// # Errors
/// The encode or write failing (the error names the path).
pub fn save(image: &image::RgbaImage, path: &Path) -> std::io::Result<()> {
    image
        .save(path)
        .map_err(|e| std::io::Error::other(format!("writing {}: {e}", path.display())))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// Writes `frames` to `path` as a looping animated GIF, `delay_ms` per frame, and prints
/// `wrote PATH`.
///
/// # Errors
/// The encode or write failing (the error names the path).
pub fn save_gif(path: &Path, frames: Vec<image::RgbaImage>, delay_ms: u32) -> std::io::Result<()> {
    let named =
        |e: image::ImageError| std::io::Error::other(format!("writing {}: {e}", path.display()));
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut enc = image::codecs::gif::GifEncoder::new_with_speed(file, 10);
    enc.set_repeat(image::codecs::gif::Repeat::Infinite)
        .map_err(named)?;
    for f in frames {
        let delay = image::Delay::from_numer_denom_ms(delay_ms, 1);
        enc.encode_frame(image::Frame::from_parts(f, 0, 0, delay))
            .map_err(named)?;
    }
    drop(enc);
    println!("wrote {}", path.display());
    Ok(())
}
