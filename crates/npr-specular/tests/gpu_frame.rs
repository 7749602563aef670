//! A frame's highlights made wholly on the GPU ([`FrameOnGpu`]: search, regions seeded
//! on the GPU's own table of the last frame, projectors built by `ProjectorPass`,
//! receivers walked from them, drawn where they lie; nothing read back) against the
//! CPU's update drawn by the highlight pass on the same frames: the images within the
//! FLIP bound the GPU setup is held to (mean 0.05 over the object's pixels), frame after
//! frame of a turning light (fades, matching), on procedural surfaces and the scanned
//! and CAD fixtures. The frames read back one frame late are the CPU's highlights.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::CurvatureOptions;
use npr_gpu::{GpuMesh, ObjectUniforms};
use npr_specular::snapshot::{HighlightScene, Renderer, light_eye_along};
use npr_specular::{HighlightSet, gpu::FrameOnGpu, gpu::GpuFrameStatus};

mod common;
use common::{bounding_radius, meshes};

/// The mean FLIP a frame made on the GPU may be from the CPU's.
const MAX_FLIP: f64 = 0.05;

#[test]
fn frames_made_wholly_on_the_gpu_are_the_cpu_frames_within_flip() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "frames_made_wholly_on_the_gpu_are_the_cpu_frames_within_flip",
    ) else {
        return;
    };
    let (w, h) = (256, 192);
    let renderer = Renderer::new(&ctx.device, &ctx.queue, w, h).unwrap();
    let (mut worst, mut frames, mut read) = (0f64, 0, 0);
    for (name, mut mesh) in meshes() {
        let centre =
            mesh.positions.iter().fold(Vec3::ZERO, |a, p| a + *p) / mesh.positions.len() as f32;
        for p in &mut mesh.positions {
            *p -= centre;
        }
        let radius = bounding_radius(&mesh);
        let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
        let mut cpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let gpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let mut on_gpu = FrameOnGpu::new(&ctx.device, &gpu_set, &mesh.indices).unwrap();
        let mut gpu_res = renderer.resources(&ctx.device, &gpu_mesh);
        for step in 0..4 {
            let a = 0.15 * step as f32;
            let dir = Vec3::new(0.3 + a, 0.5, 1.0 - 0.5 * a);
            let (light_eye, camera, light) =
                light_eye_along(dir, 3.0 * radius, w as f32 / h as f32);
            cpu_set.update(light_eye, Mat4::IDENTITY);
            // A grey Phong base under the highlights, the background transparent, so that
            // FLIP is taken over the object's pixels.
            let scene = |set| HighlightScene {
                object: ObjectUniforms::new(Mat4::IDENTITY, Vec3::splat(0.4), 0.0, Vec3::ZERO, 1.0),
                clear: [0.0; 4],
                ..HighlightScene::on_black(&gpu_mesh, &mesh.indices, set, camera, light)
            };
            let cpu = renderer
                .render(&ctx.device, &ctx.queue, &scene(&cpu_set))
                .unwrap();
            renderer
                .submit_frame_on_gpu(
                    &ctx.device,
                    &ctx.queue,
                    &scene(&gpu_set),
                    &mut gpu_res,
                    (&mut on_gpu, light_eye),
                )
                .unwrap();
            on_gpu.read_after_submit(&ctx.device, &ctx.queue);
            let gpu =
                npr_gpu::readback_rgba(&ctx.device, &ctx.queue, &renderer.target().color).unwrap();
            assert!(
                gpu_set.highlights().is_empty(),
                "{name}: the CPU updated the set"
            );
            let flip = npr_gpu::testing::flip_mean(&cpu, &gpu).expect("object pixels");
            let mut bare = scene(&cpu_set);
            bare.highlights = false;
            let bare = renderer.render(&ctx.device, &ctx.queue, &bare).unwrap();
            let without = npr_gpu::testing::flip_mean(&cpu, &bare).expect("object pixels");
            assert!(
                flip <= MAX_FLIP && without > 4.0 * flip.max(1e-4),
                "{name} frame {step}: the GPU's frame is FLIP {flip:.4} from the CPU's (bound \
                 {MAX_FLIP}), the frame without highlights {without:.4}; {}",
                npr_gpu::testing::image_failure("gpu-frame", &cpu, &gpu)
            );
            worst = worst.max(flip);
            frames += 1;
            // The receivers the GPU walked from its own projectors are the CPU's (the walks
            // agree on 99.5 % of faces, `gpu_receivers.rs`).
            let walked = *on_gpu.walked().expect("a walk");
            let counts = on_gpu
                .receivers()
                .map_counts(&ctx.device, &ctx.queue, &walked)
                .unwrap()
                .wait(&ctx.device)
                .unwrap();
            let gpu_faces: u32 = counts.counts.iter().map(|c| c.received).sum();
            let cpu_faces = cpu_set.stats().receiver_faces as u32;
            assert!(
                gpu_faces.abs_diff(cpu_faces) as f64 <= 0.005 * f64::from(cpu_faces) + 2.0,
                "{name} frame {step}: {gpu_faces} receivers walked on the GPU, {cpu_faces} on \
                 the CPU"
            );
            // The readback (here after the device went idle) is this frame's highlights.
            let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
            if let Some(latest) = on_gpu.latest() {
                assert_eq!(latest.status, GpuFrameStatus::Built, "{name} frame {step}");
                let ids: Vec<u64> = latest.highlights.iter().map(|h| h.id).collect();
                let want: Vec<u64> = cpu_set
                    .highlights()
                    .iter()
                    .filter(|h| h.piece == 0)
                    .map(|h| h.id)
                    .collect();
                assert_eq!(ids, want, "{name} frame {step}: ids read back");
                read += 1;
            }
        }
    }
    eprintln!("{frames} frames made on the GPU, worst FLIP {worst:.4}, {read} read back");
    assert_eq!(frames, 4 * meshes().len());
    assert!(read >= frames / 2, "only {read} frames read back");
}

/// A set updated on the CPU goes on on the GPU from where it was
/// (`FrameOnGpu::start_from`: its highlights keep their ids and fades), and a frame read
/// back becomes the set's highlights (`HighlightSet::adopt_gpu_frame`: the panel's and
/// picking's view), from which the CPU's update goes on in turn.
#[test]
fn a_sequence_moves_between_the_cpu_and_the_gpu_keeping_its_highlights() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "a_sequence_moves_between_the_cpu_and_the_gpu_keeping_its_highlights",
    ) else {
        return;
    };
    let mesh = common::fixture("spot.obj");
    let radius = bounding_radius(&mesh);
    let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let (w, h) = (160, 120);
    let renderer = Renderer::new(&ctx.device, &ctx.queue, w, h).unwrap();
    let mut reference = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let mut moving = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let mut on_gpu = FrameOnGpu::new(&ctx.device, &moving, &mesh.indices).unwrap();
    let mut res = renderer.resources(&ctx.device, &gpu_mesh);
    let ids = |set: &HighlightSet| -> Vec<(u64, u32)> {
        set.highlights()
            .iter()
            .filter(|h| h.piece == 0)
            .map(|h| (h.id, (h.opacity * 1e4).round() as u32))
            .collect()
    };
    let centres = |set: &HighlightSet| -> Vec<Vec3> {
        set.highlights()
            .iter()
            .filter(|h| h.piece == 0)
            .map(|h| h.centre.position_world)
            .collect()
    };
    let mut on_gpu_frames = 0;
    // The light sweeps and the object turns: highlights are lost and fade out where the
    // object carries them, on the GPU as on the CPU (placed again each frame).
    let mut faded = 0;
    for step in 0..9 {
        let dir = Vec3::new(0.2 + 0.2 * step as f32, 0.5, 1.0);
        let (light_eye, camera, light) = light_eye_along(dir, 3.0 * radius, w as f32 / h as f32);
        let world = Mat4::from_rotation_y(0.08 * step as f32);
        reference.update(light_eye, world);
        if (3..6).contains(&step) {
            // On the GPU from the set's last update.
            if step == 3 {
                on_gpu.start_from(&ctx.queue, &moving, world);
            }
            let scene = HighlightScene {
                object: ObjectUniforms::new(world, Vec3::splat(0.4), 0.0, Vec3::ZERO, 1.0),
                ..HighlightScene::on_black(&gpu_mesh, &mesh.indices, &moving, camera, light)
            };
            renderer
                .submit_frame_on_gpu(
                    &ctx.device,
                    &ctx.queue,
                    &scene,
                    &mut res,
                    (&mut on_gpu, light_eye),
                )
                .unwrap();
            on_gpu.read_after_submit(&ctx.device, &ctx.queue);
            let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
            let latest = on_gpu.latest().expect("the frame read back").clone();
            moving.adopt_gpu_frame(&latest);
            on_gpu_frames += 1;
        } else {
            moving.update(light_eye, world);
        }
        assert_eq!(
            ids(&moving),
            ids(&reference),
            "frame {step}: ids and opacities"
        );
        for (a, b) in centres(&moving).iter().zip(centres(&reference)) {
            assert!(
                a.distance(b) <= 1e-4 * radius,
                "frame {step}: {a} against {b}"
            );
        }
        faded += reference.highlights().iter().filter(|h| !h.found).count();
    }
    assert_eq!(on_gpu_frames, 3);
    assert!(!ids(&reference).is_empty());
    assert!(faded >= 1, "no highlight faded out");
}

/// A field of `n × n` small flat tiles, each tilted a little from +z, apart: seen and lit
/// from above each is a bright part with no `N = H` point, so each gets a peak.
fn tiles(n: usize) -> npr_geometry::Mesh {
    let mut m = npr_geometry::Mesh::default();
    for i in 0..n {
        for j in 0..n {
            let c = Vec3::new(i as f32 * 0.1, j as f32 * 0.1, 0.0);
            let a = (i * 7 + j * 13) as f32 * 0.37;
            let tilt = Vec3::new(0.08 * a.cos(), 0.08 * a.sin(), 1.0).normalize();
            let u = tilt.any_orthonormal_vector();
            let v = tilt.cross(u);
            let base = m.positions.len() as u32;
            for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(c + 0.03 * (du * u + dv * v));
                m.normals.push(tilt);
                m.uvs.push(glam::Vec2::ZERO);
            }
            m.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    m
}

/// Peaks on the GPU's frame: 100 tiles' peaks are the CPU's; 324 are more than the
/// search keeps (`MAX_MERGED` centres in all), and the frame says it was drawn without
/// them rather than pass for the CPU's.
#[test]
fn a_frame_whose_peaks_the_gpu_cannot_find_says_so() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("a_frame_whose_peaks_the_gpu_cannot_find_says_so")
    else {
        return;
    };
    let overhead = npr_geometry::LightEye::Directions {
        to_light: Vec3::Z,
        to_eye: Vec3::Z,
    };
    for (n, found) in [(10, true), (18, false)] {
        let mesh = tiles(n);
        let mut cpu = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let gpu = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        cpu.update(overhead, Mat4::IDENTITY);
        assert_eq!(cpu.stats().peaks, n * n, "{n}: the CPU's peaks");
        let mut on_gpu = FrameOnGpu::new(&ctx.device, &gpu, &mesh.indices).unwrap();
        // The first frame has room for 64 seeds: 100 tiles are held (none drawn), and the
        // next frames have room for more. A held frame is no update: the first frame
        // built still starts the sequence, its highlights at the CPU's first opacities.
        let mut statuses = Vec::new();
        let mut opacities = Vec::new();
        for k in 0..3 {
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            on_gpu
                .record(
                    &ctx.queue,
                    &mut encoder,
                    &gpu,
                    (overhead, Mat4::IDENTITY),
                    npr_gpu::FrameId(k + 1),
                )
                .unwrap();
            ctx.queue.submit([encoder.finish()]);
            on_gpu.read_after_submit(&ctx.device, &ctx.queue);
            let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
            let latest = on_gpu.latest().expect("read back");
            statuses.push(latest.status);
            opacities.push(
                latest
                    .highlights
                    .iter()
                    .map(|h| h.opacity)
                    .collect::<Vec<_>>(),
            );
        }
        let frame = on_gpu.latest().expect("read back");
        eprintln!("{n} x {n} tiles: {statuses:?}");
        if found {
            assert_eq!(
                statuses[0],
                GpuFrameStatus::Held,
                "{n}: 100 seeds in a room of 64"
            );
            assert_eq!(statuses[1], GpuFrameStatus::Built, "{n}");
            let first: Vec<f32> = cpu.highlights().iter().map(|h| h.opacity).collect();
            assert_eq!(
                opacities[1], first,
                "{n}: the first frame built after a held one"
            );
            assert_eq!(frame.status, GpuFrameStatus::Built, "{n}");
            assert_eq!(frame.highlights.len(), cpu.highlights().len(), "{n}");
            assert!(frame.highlights.iter().all(|h| h.peak), "{n}");
        } else {
            assert_eq!(frame.status, GpuFrameStatus::NoPeaks, "{n}");
        }
    }
}
