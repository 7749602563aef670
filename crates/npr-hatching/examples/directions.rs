//! Stroke directions before and after (ours, beyond the paper): the raw principal field
//! (the paper's rule) against the smooth line field, pen with ink outlines, on the bunny
//! (`hatching-directions-bunny*.png`) and the procedural CAD parts
//! (`hatching-directions-cad*.png`).
//!
//! `cargo run --release -p npr-hatching --example directions -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, cad_directions, directions_sheet, fixture};
use glam::Mat4;
use npr_gpu::GpuContext;
use npr_gpu::figures::out_dir;
use npr_hatching::{TamParams, TonalArtMap};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let bunny = fixture("stanford-bunny")?;
    let stem = "hatching-directions-bunny";
    directions_sheet(&ctx, &dir, &pen, (&bunny, Mat4::IDENTITY), stem)?;
    cad_directions(&ctx, &dir, &pen)
}
