//! The specular paper's Fig. 7: stylized highlights over other base shadings, Gouraud with
//! the star and cel with the disc. One row per subject, `specular-fig7-SUBJECT.png`.
//!
//! `cargo run --release -p npr-specular --example fig7 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{ALL_SUBJECTS, Draw, Error, disc, spin, star, tile};
use npr_gpu::ShadingModel;
use npr_gpu::figures::{out_dir, row, save};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    let draw = Draw::Restricted(&renderer);
    for mut s in common::subjects(&ctx, &ALL_SUBJECTS)? {
        let tiles = vec![
            tile(
                &ctx,
                draw,
                &mut s,
                (spin(), ShadingModel::Gouraud),
                Some(star()),
                false,
            )?,
            tile(
                &ctx,
                draw,
                &mut s,
                (spin(), ShadingModel::Cel),
                Some(disc()),
                false,
            )?,
        ];
        save(
            &row(&tiles),
            &dir.join(format!("specular-fig7-{}.png", s.name)),
        )?;
    }
    Ok(())
}
