//! The warping paper's §3.4 problem, surfaces hidden by other polygons in a reference, and
//! our fix: the paper's path (`Departures::PAPER`) and ours, with their differences from
//! the full render. Top row: a self-occluding knot turning 20 degrees between references,
//! seen halfway; bottom row: a synthetic occluder in reference 0 (first tile), which the
//! paper's pass projects onto the knot and the depth test rejects.
//! `warp-occlusion-knot.png`, and the top row's two warps alone,
//! `warp-occlusion-knot-{paper,ours}.png`.
//!
//! `cargo run --release -p npr-warp --example occlusion -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, TILE, on_white};
use glam::{Mat4, Vec3};
use npr_geometry::generate;
use npr_gpu::figures::{out_dir, save};
use npr_gpu::{GpuContext, GpuMesh, ObjectUniforms, TargetFormats, readback_rgba};
use npr_warp::metrics::difference_image;
use npr_warp::rig::{Rig, Variant, light, path_for};
use npr_warp::{Departures, PhongBase, Proxy, ReferenceFrame, SceneView, compare};

/// The paper's warp and ours of the same frame.
fn paper_and_ours(
    rig: &mut Rig<'_>,
    refs: [&ReferenceFrame; 2],
    [paper, ours]: [&mut Variant; 2],
    at: (&SceneView, f32),
) -> Result<(image::RgbaImage, image::RgbaImage), Error> {
    Ok((
        {
            let mode = paper.mode;
            rig.warp_image(refs, paper, at, mode, false)?
        },
        {
            let mode = ours.mode;
            rig.warp_image(refs, ours, at, mode, false)?
        },
    ))
}

/// Pastes `tiles` in a row at height `y` of `sheet`.
fn paste_row(sheet: &mut image::RgbaImage, tiles: &[image::RgbaImage], y: i64) {
    for (i, img) in tiles.iter().enumerate() {
        image::imageops::replace(sheet, img, i64::from(TILE) * i as i64, y);
    }
}

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let knot = generate::torus_knot(&generate::TorusKnot::trefoil(0.2, 600, 48));
    let mut rig = Rig::new(&ctx, &knot, TILE)?;
    let (path, world_per_object) = path_for(&knot, vec![Vec3::ZERO], 3.3, false);
    let (r0, r1) = (
        rig.reference(&path.pose(0.0))?,
        rig.reference(&path.pose(20.0))?,
    );
    let mid = path.pose(10.0);
    let full = rig.full(&mid)?;
    let proxy = Proxy::simplify(&knot, 0.05)?;
    let mut paper_path = rig.variant(&proxy, Departures::PAPER, world_per_object, 16, false)?;
    let mut ours_path = rig.variant(&proxy, Departures::OURS, world_per_object, 16, false)?;
    let (paper, ours) = paper_and_ours(
        &mut rig,
        [&r0, &r1],
        [&mut paper_path, &mut ours_path],
        (&mid, 0.5),
    )?;
    let (qp, qo) = (compare(&full, &paper), compare(&full, &ours));
    println!(
        "warp: occlusion, knot 20 degrees between references: paper's path PSNR {:.2} dB, \
         ours {:.2} dB",
        qp.psnr_db, qo.psnr_db
    );
    let mut sheet = image::RgbaImage::from_pixel(TILE * 5, TILE * 2, image::Rgba([255; 4]));
    let top = [
        on_white(&full),
        on_white(&paper),
        on_white(&ours),
        difference_image(&full, &paper, 4.0),
        difference_image(&full, &ours, 4.0),
    ];
    paste_row(&mut sheet, &top, 0);
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
    let over = npr_warp::ObjectView {
        camera: r0.pose.camera,
        world_from_object: world_from_square,
    };
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    let over = (npr_gpu::FrameId(0), &over, 0);
    r0.record_over(&ctx.device, &ctx.queue, &mut enc, &mut occluder, over)?;
    ctx.queue.submit(Some(enc.finish()));
    let occluded = readback_rgba(&ctx.device, &ctx.queue, &r0.color)?;
    let at = path.pose(6.0);
    let full6 = rig.full(&at)?;
    let (paper6, ours6) = paper_and_ours(
        &mut rig,
        [&r0, &r1],
        [&mut paper_path, &mut ours_path],
        (&at, 0.3),
    )?;
    let (qp6, qo6) = (compare(&full6, &paper6), compare(&full6, &ours6));
    println!(
        "warp: synthetic occluder in reference 0: paper's path PSNR {:.2} dB, ours {:.2} dB",
        qp6.psnr_db, qo6.psnr_db
    );
    let bottom = [
        on_white(&occluded),
        on_white(&paper6),
        on_white(&ours6),
        difference_image(&full6, &paper6, 4.0),
        difference_image(&full6, &ours6, 4.0),
    ];
    paste_row(&mut sheet, &bottom, i64::from(TILE));
    save(&sheet, &dir.join("warp-occlusion-knot.png"))?;
    // The same pair alone, for the gallery's before/after (paper's path, ours).
    for (img, label) in [(&paper, "paper"), (&ours, "ours")] {
        let file = format!("warp-occlusion-knot-{label}.png");
        save(&on_white(img), &dir.join(file))?;
    }
    Ok(())
}
