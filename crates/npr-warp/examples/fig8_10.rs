//! The warping paper's Fig. 8–10 (Park & Ihm, "Post-Rendering 3D Warping using
//! Projective Texture", KIISE 2002): for each model, the full render, then the proxy
//! (light grey with its edges) and the warped frame (ours, halfway between references 10
//! frames apart) for each of its three proxy ratios: `warp-ratios-SLUG.png` for the bunny
//! (Fig. 8) and the 870k and 1.1M knots standing in for Dragon and Buddha (Fig. 9, 10).
//!
//! `cargo run --release -p npr-warp --example fig8_10 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, TILE, on_white};
use glam::Vec3;
use npr_gpu::GpuContext;
use npr_gpu::figures::{out_dir, save};
use npr_warp::rig::{Rig, WarpModel, path_for, warp_models};
use npr_warp::{Departures, Proxy, WarpMode, compare};
use std::path::Path;

fn ratios_figure(ctx: &GpuContext, model: &WarpModel, dir: &Path) -> Result<(), Error> {
    let (name, mesh) = (&model.name, &model.mesh);
    let mut rig = Rig::new(ctx, mesh, TILE)?;
    let (path, world_per_object) = path_for(mesh, vec![Vec3::ZERO], 3.3, true);
    let k = 10;
    let (r0, r1) = (
        rig.reference(&path.pose(0.0))?,
        rig.reference(&path.pose(k as f32))?,
    );
    let mid = path.pose(5.0);
    let full_mid = rig.full(&mid)?;
    let mut sheet = image::RgbaImage::from_pixel(TILE * 7, TILE, image::Rgba([255; 4]));
    image::imageops::replace(&mut sheet, &on_white(&full_mid), 0, 0);
    for (i, &ratio) in model.ratios.iter().enumerate() {
        let proxy = Proxy::simplify(mesh, ratio)?;
        let mut ours = rig.variant(&proxy, Departures::OURS, world_per_object, 16, true)?;
        let at = (&mid, 0.5);
        let wire = rig.warp_image([&r0, &r1], &mut ours, at, WarpMode::Fill, true)?;
        let mode = ours.mode;
        let warped = rig.warp_image([&r0, &r1], &mut ours, at, mode, false)?;
        let q = compare(&full_mid, &warped);
        println!(
            "warp: {name} {:.2} % ({} triangles, error {:.4} of the extent): PSNR {:.2} dB, \
             SSIM {:.4} halfway between references 10 frames apart",
            ratio * 100.0,
            proxy.triangles(),
            proxy.error_relative,
            q.psnr_db,
            q.ssim
        );
        let x = i64::from(TILE) * (1 + 2 * i as i64);
        image::imageops::replace(&mut sheet, &on_white(&wire), x, 0);
        image::imageops::replace(&mut sheet, &on_white(&warped), x + i64::from(TILE), 0);
    }
    save(&sheet, &dir.join(format!("warp-ratios-{}.png", model.slug)))?;
    Ok(())
}

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    for model in &warp_models()? {
        ratios_figure(&ctx, model, &dir)?;
    }
    Ok(())
}
