//! The hatching paper's §5: 2-D flow visualisation, a uniform stream past two
//! counter-rotating vortices, tone from speed, hatched on the GPU with the pen
//! (`hatching-flow-gpu.png`) and on the CPU with the pencil
//! (`hatching-flow-cpu-pencil.png`).
//!
//! `cargo run --release -p npr-hatching --example flow -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

use glam::Vec2;
use npr_gpu::GpuContext;
use npr_gpu::figures::{out_dir, save};
use npr_hatching::{
    HatchError, HatchInputs, HatchParams, TamParams, TonalArtMap, hatch_cpu, hatch_image_gpu,
};

/// A 2-D flow: a uniform stream past two counter-rotating vortices; tone from speed.
fn flow_inputs(w: u32, h: u32) -> Result<HatchInputs, HatchError> {
    let mut dir = Vec::with_capacity((w * h) as usize);
    let mut mag = Vec::with_capacity((w * h) as usize);
    let vortices = [
        (Vec2::new(0.32, 0.45), 1.0f32),
        (Vec2::new(0.68, 0.58), -1.0),
    ];
    for y in 0..h {
        for x in 0..w {
            // Screen axes, y up, in units of the height.
            let p = Vec2::new(x as f32 + 0.5, h as f32 - y as f32 - 0.5) / h as f32;
            let mut v = Vec2::new(0.25, 0.0);
            for (c, s) in vortices {
                let d = p - c;
                let r2 = d.length_squared() + 0.004;
                v += s * 0.08 * Vec2::new(-d.y, d.x) / r2;
            }
            dir.push([v.x, v.y]);
            mag.push(v.length());
        }
    }
    HatchInputs::from_flow(w, h, &dir, &mag, 3.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let pencil = TonalArtMap::generate(&TamParams::pencil())?;
    let flow = flow_inputs(640, 480)?;
    let params = HatchParams::default();
    let gpu = hatch_image_gpu(&ctx.device, &ctx.queue, &flow, &pen, &params)?;
    save(&gpu, &dir.join("hatching-flow-gpu.png"))?;
    let cpu = hatch_cpu(&flow, &pencil, &params)?;
    save(&cpu, &dir.join("hatching-flow-cpu-pencil.png"))?;
    Ok(())
}
