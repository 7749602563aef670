//! The specular paper's Fig. 2: a directional texture (the streak, long along u) beside
//! its projection with up = e_min (the paper's choice, Eq. (7)) and up = e_max. One row
//! per subject, `specular-fig2-SUBJECT.png`.
//!
//! `cargo run --release -p npr-specular --example fig2 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{ALL_SUBJECTS, Error, TILE, phong};
use glam::Vec2;
use npr_gpu::figures::{out_dir, row, save};
use npr_specular::{HighlightShape, ProjectorControls, UpAxis};

/// A highlight texture as a tile: the texture (straight alpha) over mid grey.
fn texture_tile(shape: HighlightShape) -> image::RgbaImage {
    let tex = npr_specular::textures::generate(shape, TILE);
    let mut out = image::RgbaImage::from_pixel(TILE, TILE, image::Rgba([96, 96, 96, 255]));
    image::imageops::overlay(&mut out, &tex, 0, 0);
    out
}

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    let streak = ProjectorControls {
        texture_layer: HighlightShape::Streak.layer(),
        scale: Vec2::splat(1.3),
        ..Default::default()
    };
    for mut s in common::subjects(&ctx, &ALL_SUBJECTS)? {
        let mut tiles = vec![texture_tile(HighlightShape::Streak)];
        for up in [UpAxis::KappaMin, UpAxis::KappaMax] {
            tiles.push(phong(
                &ctx,
                &renderer,
                &mut s,
                ProjectorControls { up, ..streak },
            )?);
        }
        save(
            &row(&tiles),
            &dir.join(format!("specular-fig2-{}.png", s.name)),
        )?;
    }
    Ok(())
}
