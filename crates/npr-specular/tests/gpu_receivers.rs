//! The receivers of §4.2 walked on the GPU ([`ReceiverPass`], `receivers.wgsl`) against
//! the CPU walk (the reference, what [`HighlightSet::update`] fills) on the same frame:
//! the same faces for every highlight on at least 99.5 % of the faces either received,
//! over directional and point lights, rigid, non-uniformly scaled and sheared transforms,
//! procedural surfaces and the scanned and CAD fixtures, under each boundary rule. (The
//! frame drawn from the GPU's stream is the GPU backend's, compared with the CPU's frame
//! in `gpu_frame.rs`.)
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::Mat4;
use npr_geometry::CurvatureOptions;
use npr_gpu::{FrameId, GpuContext};
use npr_specular::{
    HighlightBoundary, HighlightPass, HighlightSet, gpu::ReceiverInput, gpu::ReceiverPass,
    gpu::ReceiverReadback,
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
            set.tuning.boundary = boundaries[k % boundaries.len()];
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
