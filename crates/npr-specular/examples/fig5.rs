//! The specular paper's Fig. 5: a projector enlarged (2.5×; 1.5× on the scans, whose many
//! highlights would cover them) so its frustum reaches other parts of the surface: (a)
//! every face receives, (b) the §4.2 receivers only. One pair per subject,
//! `specular-fig5-SUBJECT.png`.
//!
//! `cargo run --release -p npr-specular --example fig5 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{ALL_SUBJECTS, Draw, Error, Unrestricted, phong, spin, star, tile};
use glam::Vec2;
use npr_gpu::ShadingModel;
use npr_gpu::figures::{out_dir, row, save};
use npr_specular::ProjectorControls;

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let (ctx, renderer) = common::setup()?;
    let unrestricted = Unrestricted::new(&ctx)?;
    for mut s in common::subjects(&ctx, &ALL_SUBJECTS)? {
        let enlarge = if matches!(s.name.as_str(), "knot" | "ellipsoid") {
            2.5
        } else {
            1.5
        };
        let big = ProjectorControls {
            scale: Vec2::splat(enlarge),
            ..star()
        };
        let how = (spin(), ShadingModel::Phong);
        let draw = Draw::Unrestricted(&unrestricted);
        let unrestricted_tile = tile(&ctx, draw, &mut s, how, Some(big), false)?;
        let restricted_tile = phong(&ctx, &renderer, &mut s, big)?;
        let pair = row(&[unrestricted_tile, restricted_tile]);
        save(&pair, &dir.join(format!("specular-fig5-{}.png", s.name)))?;
    }
    Ok(())
}
