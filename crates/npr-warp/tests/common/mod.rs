//! The scene the GPU tests of npr-warp share: a (2, 3) torus knot, its material and light,
//! the full render warped frames are compared with, and a warp drawn and read back.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::{Camera, GpuContext, GpuMesh, Light, ObjectUniforms, OffscreenTarget, TargetFormats};

/// Image size of the tests, pixels.
pub const SIZE: u32 = 256;
/// Clear colour (transparent black).
pub const CLEAR: [f64; 4] = [0.0; 4];

/// The test knot (about 30k triangles).
pub fn knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot::trefoil(0.22, 480, 32))
}

/// Its material.
pub fn material() -> ObjectUniforms {
    ObjectUniforms::new(
        Mat4::IDENTITY,
        Vec3::new(0.75, 0.55, 0.35),
        0.4,
        Vec3::ONE,
        30.0,
    )
}

/// The light.
pub fn light() -> Light {
    Light::directional(Vec3::new(1.0, 1.5, 2.0))
}

/// The full render of `mesh` at `camera`, one object per transform, in the tests' light
/// and material, read back.
pub fn full_render(
    ctx: &GpuContext,
    mesh: &GpuMesh,
    camera: &Camera,
    world_from_objects: &[Mat4],
) -> image::RgbaImage {
    let (d, q) = (&ctx.device, &ctx.queue);
    let mut renderer = npr_warp::FullRenderer::new(d, q, TargetFormats::default());
    let input = npr_warp::FullInput {
        frame: npr_gpu::FrameId(0),
        camera,
        world_from_objects,
        light: &light(),
        material: &material(),
    };
    renderer.prepare(q, mesh, &input).unwrap();
    let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    let (c, z) = (&target.color_view, &target.depth_view);
    renderer.record(&mut encoder, c, z, CLEAR).unwrap();
    q.submit(Some(encoder.finish()));
    npr_gpu::readback_rgba(d, q, &target.color).unwrap()
}

/// `object` warped by `pass` as `input` says, into a cleared target, read back.
pub fn warp_render(
    ctx: &GpuContext,
    pass: &npr_warp::WarpPass,
    object: &mut npr_warp::WarpObject,
    input: &npr_warp::WarpInput<'_>,
) -> image::RgbaImage {
    let (d, q) = (&ctx.device, &ctx.queue);
    let prepared = pass.prepare(q, object, input).unwrap();
    let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    {
        let mut rpass = target.begin_clear_pass(&mut encoder, CLEAR);
        pass.draw(&mut rpass, object, &prepared).unwrap();
    }
    q.submit(Some(encoder.finish()));
    npr_gpu::readback_rgba(d, q, &target.color).unwrap()
}
