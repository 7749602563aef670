//! The specular paper's Fig. 6: Phong's own highlight beside stylized ones, a disc texture
//! and a normal-map texture. One row per subject, `specular-fig6-SUBJECT.png`.
//!
//! `cargo run --release -p npr-specular --example fig6 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{ALL_SUBJECTS, Draw, Error, disc, normal_map, phong, spin, tile};
use npr_gpu::ShadingModel;
use npr_gpu::figures::{out_dir, row, save};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    for mut s in common::subjects(&ctx, &ALL_SUBJECTS)? {
        let how = (spin(), ShadingModel::Phong);
        let tiles = vec![
            tile(&ctx, Draw::Restricted(&renderer), &mut s, how, None, true)?,
            phong(&ctx, &renderer, &mut s, disc())?,
            phong(&ctx, &renderer, &mut s, normal_map())?,
        ];
        save(
            &row(&tiles),
            &dir.join(format!("specular-fig6-{}.png", s.name)),
        )?;
    }
    Ok(())
}
