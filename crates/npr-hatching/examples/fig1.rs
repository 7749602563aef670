//! The hatching paper's Fig. 1: the three ways to combine the TAM's direction bins on one
//! object (cut-and-paste, blended, offset partition), a close-up of the knot with strokes
//! 1.5 px per texel so that the partitions show: `hatching-fig1-MODE.png` and the row
//! `hatching-fig1.png`.
//!
//! `cargo run --release -p npr-hatching --example fig1 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, Outlines, render, single};
use glam::Vec3;
use npr_gpu::GpuContext;
use npr_gpu::figures::{out_dir, save, sheet};
use npr_hatching::{BlendMode, HatchParams, TamParams, TonalArtMap};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let mut scene = single(npr_hatching::figures::knot());
    scene.camera.eye = Vec3::new(0.5, 0.9, 2.4).normalize() * 1.45;
    scene.camera.target = Vec3::new(0.15, 0.0, 0.2);
    let params: Vec<HatchParams> = BlendMode::ALL
        .iter()
        .map(|&mode| HatchParams {
            mode,
            stroke_scale: 1.5,
            ..Default::default()
        })
        .collect();
    let images = render(
        &ctx,
        &scene,
        &pen,
        &params,
        false,
        Outlines::Paper,
        (480, 360),
    )?;
    for (img, mode) in images.iter().zip(BlendMode::ALL) {
        save(img, &dir.join(format!("hatching-fig1-{}.png", mode.name())))?;
    }
    save(&sheet(&images, 3), &dir.join("hatching-fig1.png"))?;
    Ok(())
}
