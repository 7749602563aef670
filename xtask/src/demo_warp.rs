//! `cargo xtask demo` figures of the warping paper (Park & Ihm, "Post-Rendering 3D Warping
//! using Projective Texture", KIISE 2002):
//! - `warp-ratios-*.png`: full render, then proxy wireframe and warped frame for three proxy
//!   ratios (the paper's Fig. 8–10: the bunny, and the 870k and 1.1M knots standing in for
//!   Dragon and Buddha);
//! - `warp-sequence-*.png` / `warp-sequence-psnr-*.png`: frames of a [`WarpSequence`] with a
//!   reference every 10 frames and the per-frame PSNR against the full render, plotted;
//! - `warp-occlusion-knot.png`: the paper's path ([`Departures::PAPER`]) and ours, with
//!   their differences from the full render (the §3.4 problem and its fix): top row a
//!   self-occluding knot, bottom row a synthetic occluder in reference 0 (first tile);
//!   `warp-occlusion-knot-paper.png` / `-ours.png` hold the top row's two warps alone.

use crate::demo::save;
use crate::warp_rig::{CLEAR, Rig, Variant, WarpModel, light, path_for};
use glam::{Mat4, Vec3};
use npr_geometry::generate;
use npr_gpu::readback_rgba;
use npr_gpu::{GpuContext, GpuMesh, ObjectUniforms, TargetFormats};
use npr_warp::metrics::difference_image;
use npr_warp::{
    Departures, PhongBase, Proxy, ReferenceFrame, ScenePose, WarpMode, WarpSchedule, WarpSequence,
    compare,
};
use std::path::{Path, PathBuf};

const TILE: u32 = 320;

/// Composites an image with transparent background over white.
fn on_white(img: &image::RgbaImage) -> image::RgbaImage {
    image::RgbaImage::from_fn(img.width(), img.height(), |x, y| {
        let p = img.get_pixel(x, y);
        let a = u32::from(p[3]);
        let c = |i: usize| ((u32::from(p[i]) * a + 255 * (255 - a)) / 255) as u8;
        image::Rgba([c(0), c(1), c(2), 255])
    })
}

impl Rig<'_> {
    /// The paper's warp and ours of the same frame.
    fn paper_and_ours(
        &self,
        refs: [&ReferenceFrame; 2],
        [paper, ours]: [&Variant; 2],
        scene: &ScenePose,
        s: f32,
    ) -> anyhow::Result<(image::RgbaImage, image::RgbaImage)> {
        Ok((
            self.warp(refs, paper, scene, s, paper.mode, false)?,
            self.warp(refs, ours, scene, s, ours.mode, false)?,
        ))
    }

    /// The warp (or, with `wire`, the proxy filled light grey with its edges over it).
    fn warp(
        &self,
        refs: [&ReferenceFrame; 2],
        variant: &Variant,
        scene: &ScenePose,
        s: f32,
        mode: WarpMode,
        wire: bool,
    ) -> anyhow::Result<image::RgbaImage> {
        let (d, q) = (&self.ctx.device, &self.ctx.queue);
        let pair = self.pass.bind_pair(d, refs);
        let object = &variant.object;
        let mut settings = variant.settings;
        if wire {
            settings.fill_color = [0.8, 0.8, 0.8, 1.0];
        }
        let plan = self
            .pass
            .prepare(q, object, &pair, &scene.object(0), s, &settings);
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut rpass = self.target.begin_clear_pass(&mut enc, CLEAR);
            self.pass.draw(&mut rpass, &pair, object, &plan, mode);
        }
        q.submit(Some(enc.finish()));
        if wire {
            settings.fill_color = [0.05, 0.1, 0.3, 1.0];
            self.pass
                .prepare(q, object, &pair, &scene.object(0), s, &settings);
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut rpass = self.target.begin_load_pass(&mut enc);
                self.pass.draw_wireframe(&mut rpass, &pair, object);
            }
            q.submit(Some(enc.finish()));
        }
        Ok(readback_rgba(d, q, &self.target.color)?)
    }
}

/// Writes the warping figures into `dir`.
pub fn run(
    ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    progress.set_message("warp: loading and building the models");
    let models = crate::warp_rig::warp_models()?;
    // Fig. 8-10: the bunny, then the knots standing in for Dragon and Buddha.
    progress.inc_length(models.len() as u64);
    for model in &models {
        progress.set_message(format!("warp: Fig. 8-10, {}", model.name));
        ratios_figure(ctx, model, dir, &mut written)?;
        progress.inc(1);
    }
    progress.set_message("warp: sequence and occlusion");
    let Some(bunny) = models.first() else {
        anyhow::bail!("no warping model");
    };
    let (name, mesh, ratios) = (bunny.slug, &bunny.mesh, bunny.ratios);
    let mut rig = Rig::new(ctx, mesh, TILE)?;
    let (path, world_per_object) = path_for(mesh, vec![Vec3::ZERO], 3.3, true);
    let k = 10;

    // A sequence: references every 10 frames (spread over the frames between), 41 frames.
    let proxy = Proxy::simplify(mesh, ratios[1])?;
    let ours = Departures::OURS;
    let mut seq = WarpSequence::new(
        &ctx.device,
        WarpSchedule::new(k, true)?,
        ours.settings(&proxy, world_per_object),
        TILE,
        TILE,
        TargetFormats::default(),
    )?;
    let objects =
        [seq.pass()
            .create_object(&ctx.device, &proxy, 16, ours.inflation(&proxy), false)?];
    let scene = |f: u32| path.pose(f as f32);
    let frames = 41u32;
    let mut psnr = Vec::new();
    let mut strip = image::RgbaImage::from_pixel(TILE / 2 * 6, TILE / 2, image::Rgba([255; 4]));
    for f in 0..frames {
        rig.sequence_frame(&mut seq, &objects, &scene, f)?;
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
    save(
        &strip,
        &dir.join(format!("warp-sequence-{name}.png")),
        &mut written,
    )?;
    save(
        &plot(&psnr, k),
        &dir.join(format!("warp-sequence-psnr-{name}.png")),
        &mut written,
    )?;
    println!(
        "demo warp: sequence PSNR per frame (k = {k}): {}",
        psnr.iter()
            .map(|p| format!("{p:.1}"))
            .collect::<Vec<_>>()
            .join(" ")
    );

    // §3.4: surfaces hidden by other polygons in a reference. A self-occluding knot turning
    // 20 degrees between references, seen halfway.
    let knot = generate::torus_knot(&generate::TorusKnot {
        p: 2,
        q: 3,
        major_radius: 1.0,
        minor_radius: 0.4,
        tube_radius: 0.2,
        segments: 600,
        tube_segments: 48,
    });
    let mut rig = Rig::new(ctx, &knot, TILE)?;
    let (path, world_per_object) = path_for(&knot, vec![Vec3::ZERO], 3.3, false);
    let (r0, r1) = (
        rig.reference(&path.pose(0.0))?,
        rig.reference(&path.pose(20.0))?,
    );
    let mid = path.pose(10.0);
    let full = rig.full(&mid)?;
    let proxy = Proxy::simplify(&knot, 0.05)?;
    let paper_path = rig.variant(&proxy, Departures::PAPER, world_per_object, 16, false)?;
    let ours_path = rig.variant(&proxy, Departures::OURS, world_per_object, 16, false)?;
    let variants = [&paper_path, &ours_path];
    let (paper, ours) = rig.paper_and_ours([&r0, &r1], variants, &mid, 0.5)?;
    let (qp, qo) = (compare(&full, &paper), compare(&full, &ours));
    println!(
        "demo warp: occlusion, knot 20 degrees between references: paper's path PSNR {:.2} dB, ours {:.2} dB",
        qp.psnr_db, qo.psnr_db
    );
    let mut sheet = image::RgbaImage::from_pixel(TILE * 5, TILE * 2, image::Rgba([255; 4]));
    for (i, img) in [
        on_white(&full),
        on_white(&paper),
        on_white(&ours),
        difference_image(&full, &paper, 4.0),
        difference_image(&full, &ours, 4.0),
    ]
    .iter()
    .enumerate()
    {
        image::imageops::replace(&mut sheet, img, i64::from(TILE) * i as i64, 0);
    }
    // Second row: a red square hides part of the knot in reference 0 only (a synthetic
    // occluder that is not part of the warped object). The paper's pass projects it onto
    // the knot; the depth test falls back to reference 1 there.
    let square = GpuMesh::upload(&ctx.device, &generate::plane(0.5, 0.5, 1, 1))?;
    let eye = r0.pose.camera.eye;
    let world_from_square = Mat4::from_translation(eye * 0.4)
        * Mat4::from_quat(glam::Quat::from_rotation_arc(Vec3::Y, eye.normalize()));
    let red = ObjectUniforms::new(
        world_from_square,
        Vec3::new(1.0, 0.0, 0.0),
        0.0,
        Vec3::ZERO,
        1.0,
    );
    let mut occluder = PhongBase::new(&square, light(), red, TargetFormats::default());
    let over = npr_warp::Pose {
        camera: r0.pose.camera,
        world_from_object: world_from_square,
    };
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    r0.record_over(&ctx.device, &ctx.queue, &mut enc, &mut occluder, &over, 0)?;
    ctx.queue.submit(Some(enc.finish()));
    let occluded = readback_rgba(&ctx.device, &ctx.queue, &r0.color)?;
    let at = path.pose(6.0);
    let full6 = rig.full(&at)?;
    let (paper6, ours6) = rig.paper_and_ours([&r0, &r1], variants, &at, 0.3)?;
    let (qp6, qo6) = (compare(&full6, &paper6), compare(&full6, &ours6));
    println!(
        "demo warp: synthetic occluder in reference 0: paper's path PSNR {:.2} dB, ours {:.2} dB",
        qp6.psnr_db, qo6.psnr_db
    );
    for (i, img) in [
        on_white(&occluded),
        on_white(&paper6),
        on_white(&ours6),
        difference_image(&full6, &paper6, 4.0),
        difference_image(&full6, &ours6, 4.0),
    ]
    .iter()
    .enumerate()
    {
        image::imageops::replace(&mut sheet, img, i64::from(TILE) * i as i64, i64::from(TILE));
    }
    save(&sheet, &dir.join("warp-occlusion-knot.png"), &mut written)?;
    // The same pair alone, for the gallery's before/after (paper's path, ours).
    for (img, label) in [(&paper, "paper"), (&ours, "ours")] {
        save(
            &on_white(img),
            &dir.join(format!("warp-occlusion-knot-{label}.png")),
            &mut written,
        )?;
    }
    Ok(written)
}

/// The warping paper's Fig. 8-10 for one model: the full render, then the proxy (light
/// grey with its edges) and the warped frame (ours, halfway between references 10 frames
/// apart) for each of its three proxy ratios; `warp-ratios-{slug}.png`.
fn ratios_figure(
    ctx: &GpuContext,
    model: &WarpModel,
    dir: &Path,
    written: &mut Vec<PathBuf>,
) -> anyhow::Result<()> {
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
        let ours = rig.variant(&proxy, Departures::OURS, world_per_object, 16, true)?;
        let wire = rig.warp([&r0, &r1], &ours, &mid, 0.5, WarpMode::Fill, true)?;
        let warped = rig.warp([&r0, &r1], &ours, &mid, 0.5, ours.mode, false)?;
        let q = compare(&full_mid, &warped);
        println!(
            "demo warp: {name} {:.2} % ({} triangles, error {:.4} of the extent): PSNR {:.2} dB, SSIM {:.4} halfway between references 10 frames apart",
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
    save(
        &sheet,
        &dir.join(format!("warp-ratios-{}.png", model.slug)),
        written,
    )
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
