//! npr-warp inside your own wgpu renderer: your device and queue, your command encoder,
//! your colour and depth formats. The README's example; run it with
//! `cargo run --release -p npr-warp --example embed -- out.png`.
//!
//! A torus knot turns one degree per frame in front of a fixed camera. Frames 0 and 10
//! are full renders (references, §3.3); frame 4 is the simplified proxy (2 % of the
//! triangles, §3.2) with both references projected onto it (§3.3.1). What a reference
//! shows is your base pass (`PhongBase` here). `tests/embed.rs` renders through the same
//! code and compares frame 4 with the full render at that pose.

use glam::{Mat4, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::{Camera, FrameId, GpuMesh, Light, ObjectUniforms, TargetFormats};
use npr_warp::{Departures, ObjectView, PhongBase, Proxy, WarpError, Warper};

/// The renderer's colour format in this example.
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The renderer's depth format in this example.
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Width and height of the example's frames.
pub const SIZE: u32 = 256;

/// The example's model: a (2, 3) torus knot of about 30k triangles.
pub fn knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot::trefoil(0.22, 480, 32))
}

/// World units per object unit: the knot is scaled to fit the view.
pub const SCALE: f32 = 0.6;

/// The pose of frame `t`: the knot turned `t` degrees about y, seen from a fixed camera.
pub fn pose(t: f32) -> ObjectView {
    ObjectView {
        camera: Camera::look_at(Vec3::new(0.0, 1.2, 3.6), Vec3::ZERO, 1.0),
        world_from_object: Mat4::from_rotation_y(t.to_radians())
            * Mat4::from_scale(Vec3::splat(SCALE)),
    }
}

/// The light and material of the example's base pass.
pub fn look() -> (Light, ObjectUniforms) {
    let light = Light::directional(Vec3::new(1.0, 1.5, 2.0));
    (light, ObjectUniforms::default_material(Mat4::IDENTITY))
}

/// Records references at frames 0 and 10 and the warp of frame 4 into your `encoder`,
/// drawing the warp into your `color` and `depth` views.
///
/// # Errors
/// A proxy, format or GPU error.
pub fn record_frames(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: &mut wgpu::CommandEncoder,
    (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
    mesh: &Mesh,
    gpu_mesh: &GpuMesh,
) -> Result<(), WarpError> {
    // Once: the proxy (§3.2), the warper in your formats, your base pass.
    let proxy = Proxy::simplify(mesh, 0.02)?;
    let formats = TargetFormats::new(COLOR, DEPTH);
    let size = (SIZE, SIZE);
    let mut warper = Warper::new(
        device,
        queue,
        &proxy,
        Departures::OURS,
        SCALE,
        size,
        (formats, formats),
    )?;
    let (light, material) = look();
    let mut base = PhongBase::new(gpu_mesh, light, material, formats);
    // Your submission: references and warps recorded before one submit share its id.
    let frame = FrameId::default();
    // Every k-th frame: a full render of the model becomes the newest reference.
    for t in [0.0, 10.0] {
        warper.record_reference(device, queue, encoder, &mut base, frame, &pose(t))?;
    }
    // The frames between: the proxy, warped from the two newest references.
    let now = pose(4.0);
    let s = warper.position(&now);
    warper.record_warp(queue, encoder, (color, depth), frame, &now, s)?;
    Ok(())
}

/// Renders frame 4 through [`record_frames`] into new targets and reads it back.
///
/// # Errors
/// A GPU or proxy error.
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
) -> Result<image::RgbaImage, Box<dyn std::error::Error>> {
    let mesh = knot();
    let gpu_mesh = GpuMesh::upload(device, &mesh)?;
    let target = |format| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("my renderer target"),
            size: wgpu::Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let (color, depth) = (target(COLOR), target(DEPTH));
    let views = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    record_frames(
        device,
        queue,
        &mut encoder,
        (&views.0, &views.1),
        &mesh,
        &gpu_mesh,
    )?;
    queue.submit(Some(encoder.finish()));
    Ok(npr_gpu::readback_rgba(device, queue, &color)?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embed-warp.png".into());
    // Your renderer's device and queue; here a headless one.
    let ctx = npr_gpu::GpuContext::new()?;
    render(&ctx.device, &ctx.queue)?.save(&out)?;
    println!("wrote {out}");
    Ok(())
}
