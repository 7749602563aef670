//! The receivers of §4.2 walked on the GPU ([`ReceiverPass`], `receivers.wgsl`) against
//! the CPU walk (the reference, what [`HighlightSet::update`] fills) on the same frame:
//! the same faces for every highlight on at least 99.5 % of the faces either received,
//! over directional and point lights, rigid, non-uniformly scaled and sheared transforms,
//! procedural surfaces and the scanned and CAD fixtures, under each boundary rule; and a
//! frame drawn from the GPU's stream (indirectly, nothing read back) is the frame drawn
//! from the CPU's list.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, Mesh, generate};
use npr_gpu::{FrameId, GpuContext, GpuMesh};
use npr_specular::snapshot::{HighlightScene, Renderer, light_eye_along};
use npr_specular::{
    HighlightBoundary, HighlightPass, HighlightSet, ReceiverInput, ReceiverPass, ReceiverReadback,
};
use std::collections::HashSet;

mod common;
use common::{bounding_radius, fixture, frames, meshes};

/// The GPU walk of `set`'s current highlights.
fn gpu_walk(
    ctx: &GpuContext,
    pass: &ReceiverPass,
    set: &HighlightSet,
    indices: &[u32],
    world_from_object: Mat4,
    frame: FrameId,
) -> ReceiverReadback {
    let mut object = pass.create_object(&ctx.device, set, indices).unwrap();
    let input = ReceiverInput {
        frame,
        set,
        world_from_object,
    };
    let prepared = pass.prepare(&ctx.queue, &mut object, &input).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &object, &prepared).unwrap();
    ctx.queue.submit([encoder.finish()]);
    object.read(&ctx.device, &ctx.queue, &prepared).unwrap()
}

/// (highlight, render triangle) of each received face in a stream.
fn triangles(stream: &[[u32; 2]]) -> HashSet<(u32, [u32; 3])> {
    stream
        .chunks_exact(3)
        .map(|t| (t[0][1], [t[0][0], t[1][0], t[2][0]]))
        .collect()
}

#[test]
fn the_gpu_walk_receives_the_cpu_faces() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("the_gpu_walk_receives_the_cpu_faces") else {
        return;
    };
    let pass = ReceiverPass::new(&ctx.device);
    let mut meshes = meshes();
    meshes.push(("flange", fixture("flange.obj")));
    let boundaries = [
        HighlightBoundary::Smooth,
        HighlightBoundary::PerFace,
        HighlightBoundary::Unrestricted,
    ];
    let mut frame = FrameId(1);
    let (mut both_all, mut either_all) = (0usize, 0usize);
    for (name, mesh) in &meshes {
        let radius = bounding_radius(mesh);
        let mut set = HighlightSet::new(mesh, &CurvatureOptions::default()).unwrap();
        let (mut both, mut either) = (0usize, 0usize);
        for (k, (light_eye, world)) in frames(radius).into_iter().enumerate() {
            set.boundary = boundaries[k % boundaries.len()];
            set.reset();
            set.update(light_eye, world);
            let cpu = triangles(&HighlightPass::draw_list(&set, &mesh.indices));
            let walked = gpu_walk(ctx, &pass, &set, &mesh.indices, world, frame);
            frame = frame.next();
            assert_eq!(walked.counts.len(), set.highlights().len());
            assert!(
                walked.counts.iter().all(|c| !c.overflowed),
                "{name} frame {k}: a walk overflowed"
            );
            // The stream lies highlight by highlight, in the set's order.
            let order: Vec<u32> = walked.stream.iter().map(|e| e[1]).collect();
            assert!(
                order.windows(2).all(|w| w[0] <= w[1]),
                "{name} frame {k}: out of order"
            );
            let gpu = triangles(&walked.stream);
            assert_eq!(
                gpu.len() * 3,
                walked.stream.len(),
                "{name} frame {k}: a face twice"
            );
            both += cpu.intersection(&gpu).count();
            either += cpu.union(&gpu).count();
        }
        let agree = both as f64 / either.max(1) as f64;
        eprintln!(
            "{name}: {both} of {either} received faces agree ({:.3} %)",
            100.0 * agree
        );
        assert!(either > 0, "{name}: no face received in any frame");
        assert!(
            agree >= 0.995,
            "{name}: the walks agree on {:.3} %",
            100.0 * agree
        );
        (both_all, either_all) = (both_all + both, either_all + either);
    }
    assert!(
        either_all >= 5_000,
        "only {either_all} received faces over every mesh"
    );
}

#[test]
fn a_frame_drawn_from_the_gpu_stream_is_the_cpu_lists_frame() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "a_frame_drawn_from_the_gpu_stream_is_the_cpu_lists_frame",
    ) else {
        return;
    };
    let (w, h) = (320, 240);
    let renderer = Renderer::new(&ctx.device, &ctx.queue, w, h).unwrap();
    let receivers = ReceiverPass::new(&ctx.device);
    let mut compared = 0;
    for (name, mesh) in [
        ("spot", fixture("spot.obj")),
        ("torus", generate::torus(1.0, 0.35, 64, 32)),
    ] {
        let centre =
            mesh.positions.iter().fold(Vec3::ZERO, |a, p| a + *p) / mesh.positions.len() as f32;
        let mut mesh: Mesh = mesh;
        for p in &mut mesh.positions {
            *p -= centre;
        }
        let radius = bounding_radius(&mesh);
        let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
        let mut cpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let mut gpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        gpu_set.receivers_on_gpu = true;
        let mut walk = receivers
            .create_object(&ctx.device, &gpu_set, &mesh.indices)
            .unwrap();
        for dir in [Vec3::new(0.3, 0.5, 1.0), Vec3::new(-0.6, 0.2, 0.8)] {
            let (light_eye, camera, light) =
                light_eye_along(dir, 3.0 * radius, w as f32 / h as f32);
            cpu_set.update(light_eye, Mat4::IDENTITY);
            gpu_set.update(light_eye, Mat4::IDENTITY);
            assert!(!cpu_set.highlights().is_empty(), "{name}: no highlight");
            assert!(
                gpu_set.receiver_faces().is_empty(),
                "{name}: the update walked on the CPU"
            );
            let scene =
                |set| HighlightScene::on_black(&gpu_mesh, &mesh.indices, set, camera, light);
            let read = || {
                npr_gpu::readback_rgba(&ctx.device, &ctx.queue, &renderer.target().color).unwrap()
            };
            let mut res = renderer.resources(&ctx.device, &gpu_mesh);
            renderer
                .submit(&ctx.device, &ctx.queue, &scene(&cpu_set), &mut res)
                .unwrap();
            let cpu = read();
            renderer
                .submit_gpu_receivers(
                    &ctx.device,
                    &ctx.queue,
                    &scene(&gpu_set),
                    &mut res,
                    (&receivers, &mut walk),
                )
                .unwrap();
            let gpu = read();
            let lit = cpu
                .pixels()
                .filter(|p| p.0[..3].iter().any(|&c| c > 8))
                .count();
            let differ = cpu
                .pixels()
                .zip(gpu.pixels())
                .filter(|(a, b)| a.0.iter().zip(b.0).any(|(&x, y)| x.abs_diff(y) > 2))
                .count();
            eprintln!("{name} {dir}: {lit} lit pixels, {differ} differ");
            assert!(lit >= 100, "{name} {dir}: only {lit} highlight pixels");
            assert!(
                differ as f64 <= 0.002 * lit as f64,
                "{name} {dir}: {differ} of {lit} highlight pixels differ"
            );
            compared += 1;
        }
    }
    assert_eq!(compared, 4);
}

#[test]
fn a_walk_past_its_capacity_stops_there_and_says_so() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("a_walk_past_its_capacity_stops_there_and_says_so")
    else {
        return;
    };
    let pass = ReceiverPass::new(&ctx.device);
    let mesh = fixture("stanford-bunny.obj");
    let radius = bounding_radius(&mesh);
    let mut set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let (light_eye, world) = frames(radius)[0];
    set.update(light_eye, world);
    let capacity = 8;
    let mut object = pass
        .create_object_with_capacity(&ctx.device, &set, &mesh.indices, capacity)
        .unwrap();
    let input = ReceiverInput {
        frame: FrameId(1),
        set: &set,
        world_from_object: world,
    };
    let prepared = pass.prepare(&ctx.queue, &mut object, &input).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &object, &prepared).unwrap();
    ctx.queue.submit([encoder.finish()]);
    let walked = object.read(&ctx.device, &ctx.queue, &prepared).unwrap();
    let longer = set
        .highlights()
        .iter()
        .filter(|h| h.receivers.len() > capacity)
        .count();
    assert!(longer > 0, "no CPU walk is longer than {capacity} faces");
    assert!(walked.counts.iter().filter(|c| c.overflowed).count() >= longer);
    assert!(
        walked
            .counts
            .iter()
            .all(|c| c.received as usize <= capacity)
    );
    let total: u32 = walked.counts.iter().map(|c| c.received).sum();
    assert_eq!(walked.stream.len(), 3 * total as usize);
    // The counts alone (the panel's readback) are the same counts, without the stream.
    let counts = object
        .map_counts(&ctx.device, &ctx.queue, &prepared)
        .unwrap()
        .wait(&ctx.device)
        .unwrap();
    assert_eq!(counts.counts, walked.counts);
    assert!(counts.stream.is_empty());
}
