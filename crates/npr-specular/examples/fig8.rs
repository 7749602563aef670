//! The specular paper's Fig. 8: the rotating knot, cel shaded with star highlights, as a
//! frame strip (`specular-fig8-knot-strip.png`) and an animated GIF
//! (`specular-fig8-knot.gif`, 72 frames).
//!
//! `cargo run --release -p npr-specular --example fig8 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Draw, Error, star, tile};
use glam::Mat4;
use npr_gpu::ShadingModel;
use npr_gpu::figures::{out_dir, row, save, save_gif};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    let mut knot = common::subjects(&ctx, &["knot"])?.remove(0);
    let mut frames = Vec::new();
    for step in 0..72 {
        let spin =
            Mat4::from_rotation_y((step as f32 * 5.0).to_radians()) * Mat4::from_rotation_x(0.5);
        let how = (spin, ShadingModel::Cel);
        frames.push(tile(
            &ctx,
            Draw::Restricted(&renderer),
            &mut knot,
            how,
            Some(star()),
            false,
        )?);
    }
    let strip: Vec<_> = frames.iter().step_by(9).cloned().collect();
    save(&row(&strip), &dir.join("specular-fig8-knot-strip.png"))?;
    save_gif(&dir.join("specular-fig8-knot.gif"), frames, 60)?;
    Ok(())
}
