//! The warping paper's §4 (ours as a figure): frames of a `WarpSequence` of the bunny with
//! a reference every 10 frames, spread over the frames between, 41 frames: a strip of
//! frames (`warp-sequence-bunny.png`) and the per-frame PSNR against the full render,
//! plotted (`warp-sequence-psnr-bunny.png`: grid every 5 dB from 15 to 50 dB, 30 dB in red,
//! reference frames marked with vertical lines).
//!
//! `cargo run --release -p npr-warp --example sequence -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, TILE, on_white};
use glam::Vec3;
use npr_gpu::figures::{out_dir, save};
use npr_gpu::{GpuContext, TargetFormats};
use npr_warp::rig::{Rig, path_for, warp_models};
use npr_warp::{Departures, Proxy, WarpSchedule, WarpSequence, compare};

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let models = warp_models()?;
    let bunny = models.first().ok_or("no warping model")?;
    let (name, mesh, ratios) = (bunny.slug, &bunny.mesh, bunny.ratios);
    let mut rig = Rig::new(&ctx, mesh, TILE)?;
    let (path, world_per_object) = path_for(mesh, vec![Vec3::ZERO], 3.3, true);
    let k = 10;
    let proxy = Proxy::simplify(mesh, ratios[1])?;
    let ours = Departures::OURS;
    let mut seq = WarpSequence::new(
        &ctx.device,
        &ctx.queue,
        WarpSchedule::new(k, true)?,
        ours.settings(&proxy, world_per_object),
        TILE,
        TILE,
        TargetFormats::default(),
    )?;
    let mut objects =
        [seq.pass()
            .create_object(&ctx.device, &proxy, 16, ours.inflation(&proxy), false)?];
    let scene = |f: u32| path.pose(f as f32);
    let frames = 41u32;
    let mut psnr = Vec::new();
    let mut strip = image::RgbaImage::from_pixel(TILE / 2 * 6, TILE / 2, image::Rgba([255; 4]));
    for f in 0..frames {
        rig.sequence_frame(&mut seq, &mut objects, &scene, f)?;
        let warped = rig.image()?;
        let full = rig.full(&scene(f))?;
        psnr.push(compare(&full, &warped).psnr_db);
        if f % 4 == 1 && f / 4 < 6 {
            let small = image::imageops::resize(
                &on_white(&warped),
                TILE / 2,
                TILE / 2,
                image::imageops::FilterType::Triangle,
            );
            image::imageops::replace(&mut strip, &small, i64::from(TILE / 2 * (f / 4)), 0);
        }
    }
    save(&strip, &dir.join(format!("warp-sequence-{name}.png")))?;
    save(
        &plot(&psnr, k),
        &dir.join(format!("warp-sequence-psnr-{name}.png")),
    )?;
    println!(
        "warp: sequence PSNR per frame (k = {k}): {}",
        psnr.iter()
            .map(|p| format!("{p:.1}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    Ok(())
}

/// PSNR per frame as a line plot (white background, grid every 5 dB from 15 to 50 dB,
/// reference frames marked with vertical lines), 640 × 240 pixels. No text: the caption
/// lives in the README and the demo's printout.
fn plot(values: &[f64], k: u32) -> image::RgbaImage {
    let (w, h) = (640u32, 240u32);
    let (lo, hi) = (15.0f64, 50.0f64);
    let mut img = image::RgbaImage::from_pixel(w, h, image::Rgba([255, 255, 255, 255]));
    let n = values.len().max(2) as f64 - 1.0;
    let x_of = |i: f64| (20.0 + i / n * f64::from(w - 40)) as i64;
    let y_of = |v: f64| {
        (f64::from(h - 20) - (v.clamp(lo, hi) - lo) / (hi - lo) * f64::from(h - 40)) as i64
    };
    let put = |img: &mut image::RgbaImage, x: i64, y: i64, c: [u8; 3]| {
        if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h {
            img.put_pixel(x as u32, y as u32, image::Rgba([c[0], c[1], c[2], 255]));
        }
    };
    let mut db = lo;
    while db <= hi + 1e-9 {
        let y = y_of(db);
        let c = if (db - 30.0).abs() < 1e-9 {
            [150, 60, 60]
        } else {
            [215, 215, 215]
        };
        for x in 20..(w as i64 - 20) {
            put(&mut img, x, y, c);
        }
        db += 5.0;
    }
    for (i, _) in values
        .iter()
        .enumerate()
        .filter(|(i, _)| (*i as u32).is_multiple_of(k.max(1)))
    {
        let x = x_of(i as f64);
        for y in 20..(h as i64 - 20) {
            put(&mut img, x, y, [120, 120, 200]);
        }
    }
    let mut last: Option<(i64, i64)> = None;
    for (i, v) in values.iter().enumerate() {
        let p = (x_of(i as f64), y_of(*v));
        if let Some(a) = last {
            let steps = (p.0 - a.0).abs().max((p.1 - a.1).abs()).max(1);
            for s in 0..=steps {
                let x = a.0 + (p.0 - a.0) * s / steps;
                let y = a.1 + (p.1 - a.1) * s / steps;
                for d in -1..=1 {
                    put(&mut img, x, y + d, [20, 20, 20]);
                }
            }
        }
        for dx in -2..=2 {
            for dy in -2..=2 {
                put(&mut img, p.0 + dx, p.1 + dy, [200, 40, 40]);
            }
        }
        last = Some(p);
    }
    img
}
