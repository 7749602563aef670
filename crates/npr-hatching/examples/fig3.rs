//! The hatching paper's Fig. 3: a multi-object scene on a ground plane with cast shadows,
//! pen and pencil, beside its Phong + VSM baseline (`hatching-fig3-scene-STYLE.png`,
//! `hatching-fig3-scene-phong-vsm.png`); and ours, the same scene under a spot light (cone
//! and shadows from the VSM) with ink outlines, `hatching-fig3-scene-spot-pen.png`.
//!
//! `cargo run --release -p npr-hatching --example fig3 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, Outlines, render, scene_fig3};
use glam::Vec3;
use npr_gpu::GpuContext;
use npr_gpu::figures::{out_dir, save};
use npr_hatching::{HatchParams, ShadowLight, TamParams, TamStyle, TonalArtMap};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let pencil = TonalArtMap::generate(&TamParams::pencil())?;
    let mut scene = scene_fig3();
    let params = [HatchParams::default()];
    let size = (960, 600);
    for (tam, style) in [(&pen, TamStyle::Pen), (&pencil, TamStyle::Pencil)] {
        let phong = style == TamStyle::Pen;
        let imgs = render(&ctx, &scene, tam, &params, phong, Outlines::Paper, size)?;
        let name = format!("hatching-fig3-scene-{}.png", style.name());
        save(&imgs[0], &dir.join(name))?;
        if let Some(phong) = imgs.get(1) {
            save(phong, &dir.join("hatching-fig3-scene-phong-vsm.png"))?;
        }
    }
    scene.light = ShadowLight::Spot {
        position: Vec3::new(-2.5, 5.0, 2.5),
        target: Vec3::new(0.0, 0.5, 0.0),
        outer_angle_rad: 38f32.to_radians(),
        inner_angle_rad: 26f32.to_radians(),
        range: 14.0,
    };
    let imgs = render(&ctx, &scene, &pen, &params, false, Outlines::On, size)?;
    save(&imgs[0], &dir.join("hatching-fig3-scene-spot-pen.png"))?;
    Ok(())
}
