//! The specular paper's Fig. 4: one highlight texture (the star) under the projector's
//! controls: original, scaled, rotated, translated. One row per subject,
//! `specular-fig4-SUBJECT.png`.
//!
//! `cargo run --release -p npr-specular --example fig4 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{ALL_SUBJECTS, Error, phong, star};
use glam::Vec2;
use npr_gpu::figures::{out_dir, row, save};
use npr_specular::ProjectorControls;

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    for mut s in common::subjects(&ctx, &ALL_SUBJECTS)? {
        let star = star();
        let controls = [
            star,
            ProjectorControls {
                scale: Vec2::new(1.6, 0.8),
                ..star
            },
            ProjectorControls {
                rotate_rad: 0.6,
                ..star
            },
            ProjectorControls {
                translate: Vec2::new(0.02, 0.1),
                ..star
            },
        ];
        let tiles = controls
            .iter()
            .map(|c| phong(&ctx, &renderer, &mut s, *c))
            .collect::<Result<Vec<_>, _>>()?;
        save(
            &row(&tiles),
            &dir.join(format!("specular-fig4-{}.png", s.name)),
        )?;
    }
    Ok(())
}
