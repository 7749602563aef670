//! npr-hatching inside your own wgpu renderer: your device and queue, your command
//! encoder, your colour format. The README's example; run it with
//! `cargo run --release -p npr-hatching --example embed -- out.png`.
//!
//! Your renderer writes tone and stroke direction θ per pixel into a [`GBuffer`] (its
//! `view` is a render attachment in [`npr_hatching::GBUFFER_FORMAT`]: tone in r, θ in g);
//! here they are uploaded from a function instead. `HatchPass` then hatches that G-buffer
//! into your target, recorded into your encoder. `tests/embed.rs` renders through the same
//! code and compares the image with the CPU reference, `CpuHatcher`.

use npr_gpu::{FrameId, TargetFormats, render};
use npr_hatching::{
    GBuffer, HatchInput, HatchInputs, HatchParams, HatchPass, HatchSettings, TamParams, TonalArtMap,
};

/// The renderer's colour format in this example (any renderable format works).
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The tone and θ this example hatches: a tone ramp from black (left) to white, strokes
/// turning down the image.
///
/// # Errors
/// A zero size.
pub fn inputs(width: u32, height: u32) -> Result<HatchInputs, npr_hatching::HatchError> {
    HatchInputs::from_fn(width, height, |x, y| (x / width as f32, 0.01 * y + 0.3))
}

/// Hatches [`inputs`] with the pen style into your `target` (of [`COLOR`], the inputs'
/// size), recording into your `encoder`. In a renderer, create the pass and the G-buffer
/// once and re-record every frame.
///
/// # Errors
/// Bad parameters or size.
pub fn record_hatching(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: &mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    inputs: &HatchInputs,
) -> Result<(), npr_hatching::HatchError> {
    // Once: the tonal art map, the pass in your colour format, the G-buffer it reads.
    let tam = TonalArtMap::generate(&TamParams::pen())?;
    let formats = TargetFormats::new(COLOR, wgpu::TextureFormat::Depth32Float);
    let pass = HatchPass::new(device, queue, formats, &HatchSettings { tam })?;
    let gbuffer = GBuffer::new(device, inputs.width(), inputs.height())?;
    let mut source = pass.create_object(device, &gbuffer);
    // Per frame: your G-buffer pass writes tone and θ (here: an upload), `prepare` writes
    // the parameters, then the hatching pass draws one full-screen triangle into your
    // target.
    gbuffer.write(queue, inputs);
    let input = HatchInput {
        frame: FrameId::default(),
        params: &HatchParams::default(),
        anchor_weight: None,
    };
    let prepared = pass.prepare(queue, &mut source, &input)?;
    let white = wgpu::LoadOp::Clear(wgpu::Color::WHITE);
    let mut rpass = render::begin_color_pass(encoder, "my hatching pass", target, white);
    pass.draw(&mut rpass, &source, &prepared)?;
    Ok(())
}

/// Renders [`inputs`] at `width × height` through [`record_hatching`] and reads it back.
///
/// # Errors
/// A GPU or parameter error.
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage, Box<dyn std::error::Error>> {
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let target = npr_gpu::texture_2d(device, "my renderer target", width, height, COLOR, usage);
    let view = target.create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    record_hatching(device, queue, &mut encoder, &view, &inputs(width, height)?)?;
    queue.submit(Some(encoder.finish()));
    Ok(npr_gpu::readback_rgba(device, queue, &target)?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed-hatching.png".into());
    // Your renderer's device and queue; here a headless one.
    let ctx = npr_gpu::GpuContext::new()?;
    render(&ctx.device, &ctx.queue, 320, 240)?.save(&out)?;
    println!("wrote {out}");
    Ok(())
}
