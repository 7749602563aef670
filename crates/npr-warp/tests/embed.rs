//! The README's embedding example (`examples/embed.rs`, included here as a module): its
//! warped frame is close to the full render at the same pose (the ground truth the warp
//! approximates; the same bound as `warper_draws_into_a_bgra_target_like_into_rgba`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod embed;

use npr_gpu::{GpuMesh, TargetFormats};
use npr_warp::FullRenderer;

#[test]
fn embed_example_is_close_to_the_full_render() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("embed_example_is_close_to_the_full_render")
    else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let warped = embed::render(d, q).unwrap();
    // The full render of frame 4 in the same formats.
    let mesh = GpuMesh::upload(d, &embed::knot()).unwrap();
    let pose = embed::pose(4.0);
    let (light, material) = embed::look();
    let mut full = FullRenderer::new(d, q, TargetFormats::new(embed::COLOR, embed::DEPTH));
    let input = npr_warp::FullInput {
        frame: npr_gpu::FrameId(0),
        camera: &pose.camera,
        world_from_objects: &[pose.world_from_object],
        light: &light,
        material: &material,
    };
    full.prepare(q, &mesh, &input).unwrap();
    let target = npr_gpu::OffscreenTarget::new(d, embed::SIZE, embed::SIZE).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    full.record(
        &mut encoder,
        &target.color_view,
        &target.depth_view,
        [0.0; 4],
    )
    .unwrap();
    q.submit(Some(encoder.finish()));
    let reference = npr_gpu::readback_rgba(d, q, &target.color).unwrap();
    let quality = npr_warp::metrics::compare(&reference, &warped);
    eprintln!("embed warp vs full render: {quality:?}");
    assert!(quality.pixels > 5000, "{quality:?}");
    assert!(quality.psnr_db > 20.0, "{quality:?}");
}
