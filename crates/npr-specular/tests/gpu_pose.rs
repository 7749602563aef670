//! Frames of a moving mesh made wholly on the GPU, the pose included: each pose written
//! into the vertex buffer, its curvature measured there (`CurvaturePass` at
//! `POSE_REACH`), its tables made there (`FrameOnGpu::record_pose`) and the frame's
//! highlights made from them, nothing read back between frames; against the CPU's repose
//! and update of the same poses, the projectors' records included. Procedural rigs whose poses stretch, bend and sway.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, LightEye};
use npr_gpu::{FrameId, GpuMesh};
use npr_specular::{HighlightSet, gpu::FrameOnGpu, gpu::projector_gpu};

mod common;
use common::{bounding_radius, record_gap};

#[test]
fn frames_of_a_moving_mesh_posed_on_the_gpu_are_the_cpu_frames() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "frames_of_a_moving_mesh_posed_on_the_gpu_are_the_cpu_frames",
    ) else {
        return;
    };
    let (device, queue) = (&ctx.device, &ctx.queue);
    let models = [
        (
            "stretched sphere",
            npr_geometry::generate::stretched_sphere(1.0, 0.7, 0.5, 12),
        ),
        (
            "swaying knot",
            npr_geometry::generate::swaying(npr_geometry::generate::paper_knot()),
        ),
        (
            "bent tube",
            npr_geometry::generate::bent_tube(0.3, 1.0, 1.5, 24, 48),
        ),
    ];
    let options = CurvatureOptions::default();
    let curvature_pass = npr_gpu::CurvaturePass::new(device);
    let (mut frames, mut highlights, mut worst, mut records) = (0, 0, 0.0f32, 0.0f32);
    for (name, rigged) in models {
        let (rest, rig) = (&rigged.mesh, &rigged.rig);
        let clip = &rig.clips()[0];
        let radius = bounding_radius(rest);
        let abstraction = npr_specular::DEFAULT_ABSTRACTION;
        let mut cpu = HighlightSet::with_abstraction(rest, &options, abstraction).unwrap();
        let gpu = HighlightSet::with_abstraction(rest, &options, abstraction).unwrap();
        let gpu_mesh = GpuMesh::upload(device, rest).unwrap();
        let mut curvature = curvature_pass
            .create_object_with_reach(device, &gpu_mesh, rest, options.radius, npr_gpu::POSE_REACH)
            .unwrap();
        let mut on_gpu = FrameOnGpu::new(device, &gpu, &rest.indices).unwrap();
        on_gpu
            .pose_on_gpu(device, &gpu, (rest, &gpu_mesh), &curvature)
            .unwrap();
        for k in 0..6 {
            let posed = rig.pose_mesh(&rig.sample(clip, clip.duration() * k as f32 / 6.0));
            let a = 0.2 * k as f32;
            let light_eye = LightEye::Positions {
                light: radius * Vec3::new(2.0 * a.cos(), 2.5, 2.0 * a.sin() + 1.0),
                eye: radius * Vec3::new(0.3, 0.4, 3.5),
            };
            let world = Mat4::from_rotation_y(0.1 * k as f32);
            gpu_mesh.write_vertices(queue, &posed).unwrap();
            let frame = FrameId(k as u64 + 1);
            let mut encoder = device.create_command_encoder(&Default::default());
            let measured = curvature_pass
                .prepare(queue, &mut curvature, &npr_gpu::CurvatureInput { frame })
                .unwrap();
            curvature_pass
                .record(&mut encoder, &curvature, &measured)
                .unwrap();
            on_gpu.record_pose(queue, &mut encoder, frame).unwrap();
            on_gpu
                .record(queue, &mut encoder, &gpu, (light_eye, world), frame)
                .unwrap();
            queue.submit([encoder.finish()]);
            on_gpu.read_after_submit(device, queue);
            let _ = device.poll(wgpu::PollType::wait_indefinitely());
            let got = on_gpu.latest().expect("the frame read back").clone();
            cpu.repose(&posed, &options).unwrap();
            cpu.update(light_eye, world);
            let want: Vec<_> = cpu.highlights().iter().filter(|h| h.piece == 0).collect();
            let at = format!("{name}, pose {k}");
            let tell = |v: Vec<(u64, bool, bool, u8)>| format!("{v:?}");
            assert_eq!(
                tell(
                    got.highlights
                        .iter()
                        .map(|g| (g.id, g.found, g.peak, g.pieces))
                        .collect()
                ),
                tell(
                    want.iter()
                        .map(|w| (w.id, w.found, w.peak, w.pieces))
                        .collect()
                ),
                "{at}: (id, found, peak, pieces)"
            );
            for (g, w) in got.highlights.iter().zip(&want) {
                assert!((g.opacity - w.opacity).abs() <= 1e-5, "{at}: fades");
                let d = g.centre.position_world.distance(w.centre.position_world) / radius;
                worst = worst.max(d);
                assert!(
                    d <= 1e-4,
                    "{at}: highlight {} is {d:.2e} of the radius from the CPU's",
                    g.id
                );
            }
            // The wholes' records for the highlight pass (pieces are cut a patch at a time
            // by the set's grower, `tests/gpu_projectors.rs`): the projector's frame, its
            // principal direction's sign included.
            for (g, h) in got.projectors.iter().zip(cpu.highlights()) {
                if h.piece != 0 {
                    continue;
                }
                let w = projector_gpu(h, h.controls.texture_layer.min(7), false);
                let gap = record_gap(g, &w);
                records = records.max(gap);
                assert!(
                    gap <= 2e-3,
                    "{at}: highlight {}'s record {gap:.2e} apart",
                    h.id
                );
            }
            frames += 1;
            highlights += want.len();
        }
    }
    eprintln!(
        "{frames} posed frames made on the GPU: {highlights} highlights, the CPU's; centres within {worst:.2e} of the radius, records within {records:.2e}"
    );
    assert!(highlights >= frames, "too few highlights to compare");
}
