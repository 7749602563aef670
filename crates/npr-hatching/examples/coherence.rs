//! Beyond the hatching paper's §5 (ours): the paper's screen-space strokes against
//! surface-anchored ones on a turning object. `hatching-coherence-NAME.gif`: the object
//! turning 2° per frame while the camera dollies in by 2× and back, hatched in screen space
//! (left, the paper: the strokes stay on the screen, the surface slides beneath) and
//! surface space (right, the default: the strokes move with the surface at constant
//! density); and `hatching-coherence-NAME-strip.png`, every 12th frame. For the bunny and
//! the knot.
//!
//! `cargo run --release -p npr-hatching --example coherence -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, fixture, single_light};
use glam::{Mat4, Vec3};
use npr_gpu::figures::{framing_camera, out_dir, save, save_gif, sheet};
use npr_gpu::{Camera, GpuContext, GpuMesh};
use npr_hatching::coherence::rig;
use npr_hatching::{StrokeSpace, TamParams, TonalArtMap};
use std::path::Path;

/// The subjects, in the gallery's order.
const SUBJECTS: [&str; 2] = ["stanford-bunny", "knot"];
/// Frames of a GIF, and the turn per frame.
const FRAMES: usize = 48;
const STEP_DEG: f32 = 2.0;

fn gif(ctx: &GpuContext, dir: &Path, name: &str, tam: &TonalArtMap) -> Result<(), Error> {
    let mesh = if name == "knot" {
        npr_hatching::figures::knot()
    } else {
        fixture(name)?
    };
    let (w, h) = (320u32, 240u32);
    let (camera0, world_from_object) = framing_camera(&mesh, w as f32 / h as f32);
    let light = single_light();
    let directions = npr_hatching::figures::directions(&mesh);
    let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh)?;
    let period = npr_hatching::DEFAULT_ANCHOR_PERIOD;
    let mut rigs = StrokeSpace::ALL
        .into_iter()
        .map(|space| rig(ctx, tam, (space, period), (&gpu_mesh, &directions), (w, h)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut frames = Vec::with_capacity(FRAMES);
    for t in 0..FRAMES {
        // Distance: twice the framing distance → the framing distance → back (a 2× dolly).
        let phase = (t as f32 / FRAMES as f32 * std::f32::consts::TAU).cos();
        let camera = Camera::look_at(
            camera0.eye * 2f32.powf(0.5 + 0.5 * phase),
            Vec3::ZERO,
            w as f32 / h as f32,
        );
        let turn = Mat4::from_rotation_y((t as f32 * STEP_DEG).to_radians());
        let mut tiles = Vec::new();
        for r in &mut rigs {
            tiles.push(r.render(ctx, &camera, &light, turn * world_from_object)?);
        }
        frames.push(sheet(&tiles, 2));
    }
    let strip: Vec<_> = frames.iter().step_by(12).cloned().collect();
    let strip_path = dir.join(format!("hatching-coherence-{name}-strip.png"));
    save(&sheet(&strip, 1), &strip_path)?;
    let gif_path = dir.join(format!("hatching-coherence-{name}.gif"));
    save_gif(&gif_path, frames, 80)?;
    Ok(())
}

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    for name in SUBJECTS {
        gif(&ctx, &dir, name, &pen)?;
    }
    Ok(())
}
