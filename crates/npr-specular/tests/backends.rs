//! The two highlight backends through one harness: every case plays the same frames on
//! [`Backend::Cpu`] and [`Backend::Gpu`] through [`HighlightSetup`] (as an embedder does)
//! and holds the highlights the CPU sees after each frame (the GPU backend's read back
//! and adopted) to each other: ids, found, peaks, pieces and fades equal, centres within
//! 1e-4 of the bounding radius, the footprints of unsplit highlights within 3e-3 of it
//! (`same_view`). The cases are the setup's features: a turning light and object on
//! scanned and procedural meshes (matching, fades, peaks), bright parts of over 8,192
//! vertices (peaks joined over all vertices), highlights the user sized apart (their own
//! σ), and the paper's sizing (Eq. (8)). Then the backend rule's last step on a device
//! whose storage bindings a generated mesh exceeds.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::{FrameId, GpuContext, GpuMesh};
use npr_specular::{
    Backend, BackendSetting, ChoiceReason, Highlight, HighlightSet, HighlightSetup, SetupInput,
    SpecularSettings,
};

mod common;
use common::{bounding_radius, fixture};

/// A change to a set before a frame: its settings, or the user's edits of the highlights
/// it knows (`step`: the frame's index).
type Edit<'a> = &'a dyn Fn(&mut HighlightSet, usize);

/// The highlights the CPU knows after each of `frames` of `mesh` on `backend`, `edit`
/// applied before each (the GPU backend's frame waited for and adopted before the next).
fn play(
    ctx: &GpuContext,
    mesh: &Mesh,
    backend: Backend,
    edit: Edit<'_>,
    frames: &[(LightEye, Mat4)],
) -> Vec<Vec<Highlight>> {
    let (device, queue) = (&ctx.device, &ctx.queue);
    let gpu_mesh = GpuMesh::upload(device, mesh).unwrap();
    let settings = SpecularSettings {
        backend: match backend {
            Backend::Cpu => BackendSetting::Cpu,
            Backend::Gpu => BackendSetting::Gpu,
        },
        ..SpecularSettings::default()
    };
    let setup = HighlightSetup::new(device, queue, &Default::default());
    let mut object = setup
        .create_object(device, queue, mesh, &settings, &ctx.adapter.get_info())
        .unwrap();
    assert_eq!(object.backend(), backend, "{}", object.choice());
    let mut seen = Vec::new();
    for (step, &(light_eye, world_from_object)) in frames.iter().enumerate() {
        edit(object.set_mut(), step);
        let input = SetupInput {
            frame: FrameId(step as u64 + 1),
            light_eye,
            world_from_object,
            mesh,
            gpu: &gpu_mesh,
        };
        let mut encoder = device.create_command_encoder(&Default::default());
        let prepared = setup.prepare(device, queue, &mut object, &input).unwrap();
        setup.record(&mut encoder, &mut object, &prepared).unwrap();
        queue.submit([encoder.finish()]);
        setup.after_submit(device, queue, &mut object);
        // Other tests poll the same device: its read may arrive after this poll returns.
        let mut adopted = false;
        for _ in 0..10_000 {
            device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
            adopted = object.adopt_read_back();
            if adopted || backend == Backend::Cpu {
                break;
            }
            std::thread::yield_now();
        }
        assert_eq!(
            adopted,
            backend == Backend::Gpu,
            "frame {step}: the GPU frame was read back"
        );
        seen.push(object.set().highlights().to_vec());
    }
    seen
}

/// Holds the GPU backend's view of a frame to the CPU backend's (see the module docs);
/// returns the largest footprint difference, of `radius`.
fn same_view(gpu: &[Highlight], cpu: &[Highlight], radius: f32, at: &str) -> f32 {
    // The GPU backend lists a split highlight once, its whole standing for its pieces.
    let cpu: Vec<&Highlight> = cpu.iter().filter(|h| h.piece == 0).collect();
    assert_eq!(gpu.len(), cpu.len(), "{at}: highlight counts");
    let mut worst = 0f32;
    for (g, c) in gpu.iter().zip(cpu) {
        assert_eq!(
            (g.id, g.found, g.peak, g.pieces),
            (c.id, c.found, c.peak, c.pieces),
            "{at}"
        );
        assert!((g.opacity - c.opacity).abs() <= 1e-5, "{at}: fades");
        let d = g.centre.position_world.distance(c.centre.position_world) / radius;
        assert!(
            d <= 1e-4,
            "{at}: highlight {} moved {d:.2e} of the radius",
            g.id
        );
        if c.pieces <= 1 {
            let e = (g.projector.half_extent - c.projector.half_extent).abs();
            worst = worst.max(e.max_element() / radius);
        }
    }
    assert!(
        worst <= 3e-3,
        "{at}: footprints {worst:.2e} of the radius apart"
    );
    worst
}

/// Plays `frames` of `mesh` on both backends and compares every frame; the CPU's
/// highlights per frame.
fn both(
    ctx: &GpuContext,
    (name, mesh): (&str, &Mesh),
    edit: Edit<'_>,
    frames: &[(LightEye, Mat4)],
) -> Vec<Vec<Highlight>> {
    let cpu = play(ctx, mesh, Backend::Cpu, edit, frames);
    let gpu = play(ctx, mesh, Backend::Gpu, edit, frames);
    let radius = bounding_radius(mesh);
    let worst = cpu
        .iter()
        .zip(&gpu)
        .enumerate()
        .map(|(i, (c, g))| same_view(g, c, radius, &format!("{name} frame {i}")))
        .fold(0f32, f32::max);
    eprintln!(
        "{name}: {} frames alike, footprints within {worst:.2e}",
        cpu.len()
    );
    cpu
}

/// The first `steps` frames of the twin tests' turn ([`common::turn`]).
fn turn(radius: f32, steps: usize) -> Vec<(LightEye, Mat4)> {
    (0..steps).map(|step| common::turn(radius, step)).collect()
}

fn no_edit(_: &mut HighlightSet, _: usize) {}

#[test]
fn both_backends_see_the_same_highlights_through_a_turn() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("both_backends_see_the_same_highlights_through_a_turn")
    else {
        return;
    };
    let (mut shown, mut peaks) = (0, 0);
    for (name, mesh) in [
        ("spot", fixture("spot.obj")),
        ("bunny", fixture("stanford-bunny.obj")),
        ("torus", generate::torus(1.0, 0.35, 64, 32)),
    ] {
        let frames = turn(bounding_radius(&mesh), 14);
        let cpu = both(ctx, (name, &mesh), &no_edit, &frames);
        shown += cpu.iter().map(Vec::len).sum::<usize>();
        peaks += cpu.iter().flatten().filter(|h| h.peak).count();
    }
    assert!(shown >= 30, "only {shown} highlights");
    assert!(peaks >= 10, "only {peaks} peaks");
}

/// Bright parts of over 8,192 vertices (the most a single invocation once held): a dense
/// knot under the bench's light, wide highlights.
#[test]
fn both_backends_find_the_peaks_of_large_bright_parts() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("both_backends_find_the_peaks_of_large_bright_parts")
    else {
        return;
    };
    let knot = generate::TorusKnot::trefoil(0.15, 1800, 130);
    let mesh = generate::torus_knot(&knot);
    let radius = bounding_radius(&mesh);
    let light_eye = LightEye::Positions {
        light: Vec3::new(0.4, 0.7, 1.0).normalize() * 50.0 * radius,
        eye: Vec3::new(0.0, 0.0, 3.0 * radius),
    };
    let frames: Vec<_> = (0..4)
        .map(|step| {
            let world = Mat4::from_rotation_y((step as f32 * 3.0).to_radians());
            (light_eye, world)
        })
        .collect();
    let wide = |set: &mut HighlightSet, _: usize| set.tuning.controls.sigma = 0.8;
    // The bright vertices at σ = 0.8 in the first frame, as the peaks count them.
    let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let LightEye::Positions { light, eye } = light_eye else {
        unreachable!()
    };
    let bright = set
        .topology()
        .positions
        .iter()
        .zip(set.search().normals())
        .filter(|(p, n)| {
            n.dot(((light - **p).normalize() + (eye - **p).normalize()).normalize()) >= 0.8
        })
        .count();
    assert!(bright > 8192, "only {bright} bright vertices");
    let cpu = both(ctx, ("knot", &mesh), &wide, &frames);
    assert!(cpu.iter().flatten().any(|h| h.peak), "no peak in any frame");
}

/// Highlights the user sized apart (their own σ, as the panel edits them) grow their
/// regions among the others' at their own σ on both backends.
#[test]
fn both_backends_grow_highlights_of_their_own_sigma_alike() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("both_backends_grow_highlights_of_their_own_sigma_alike")
    else {
        return;
    };
    // From the second frame on, every other highlight it knows tighter or wider.
    let sized = |set: &mut HighlightSet, step: usize| {
        if step == 0 {
            return;
        }
        let ids: Vec<u64> = set.highlights().iter().map(|h| h.id).collect();
        for (i, id) in ids.into_iter().enumerate() {
            set.controls_mut(id).sigma = Some(if i % 2 == 0 { 0.97 } else { 0.8 });
        }
    };
    let mut edited = 0;
    for (name, mesh) in [
        ("spot", fixture("spot.obj")),
        ("bunny", fixture("stanford-bunny.obj")),
    ] {
        let frames = turn(bounding_radius(&mesh), 8);
        let cpu = both(ctx, (name, &mesh), &sized, &frames);
        edited += cpu[..cpu.len() - 1].iter().map(Vec::len).sum::<usize>();
    }
    assert!(edited >= 20, "only {edited} highlights edited");
}

/// The paper's sizing (Eq. (8): no regions, no peaks) on both backends.
#[test]
fn both_backends_size_by_the_papers_eq8_alike() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("both_backends_size_by_the_papers_eq8_alike")
    else {
        return;
    };
    let mesh = fixture("spot.obj");
    let paper = |set: &mut HighlightSet, _: usize| {
        set.tuning.sizing = npr_specular::HighlightSizing::Paper;
    };
    let frames = turn(bounding_radius(&mesh), 6);
    let cpu = both(ctx, ("spot", &mesh), &paper, &frames);
    let shown: usize = cpu.iter().map(Vec::len).sum();
    assert!(shown >= 6, "only {shown} highlights");
}

/// The binding limit of the lowered device, bytes.
const LIMIT: u64 = 1 << 19;

/// The backend rule's last step: a mesh whose GPU frame tables exceed the device's
/// storage bindings runs the CPU backend, says why in one line, and still draws its
/// highlights; a mesh whose tables fit runs the GPU backend it asked for. The device is
/// this machine's adapter with its storage binding limit lowered, so the generated mesh
/// is past it without being large.
#[test]
fn a_mesh_past_the_binding_limit_runs_the_cpu_backend_and_says_why() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "a_mesh_past_the_binding_limit_runs_the_cpu_backend_and_says_why",
    ) else {
        return;
    };
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: LIMIT,
        ..wgpu::Limits::default().using_resolution(ctx.adapter.limits())
    };
    let (device, queue) = pollster::block_on(ctx.adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("a device with small storage bindings"),
        required_limits: limits,
        ..Default::default()
    }))
    .unwrap();
    let setup = HighlightSetup::new(&device, &queue, &Default::default());
    let settings = SpecularSettings {
        backend: BackendSetting::Gpu,
        ..SpecularSettings::default()
    };
    let info = ctx.adapter.get_info();
    // 80 faces fit; 20,480 faces (a level-5 sphere) do not, though its vertex buffer does.
    for (level, fits) in [(1, true), (5, false)] {
        let mesh = generate::icosphere(level, 1.0);
        let gpu_mesh = GpuMesh::upload(&device, &mesh).unwrap();
        let mut object = setup
            .create_object(&device, &queue, &mesh, &settings, &info)
            .unwrap();
        let said = object.choice().to_string();
        eprintln!("level {level}: {said}");
        assert!(!said.contains('\n'), "one line: {said}");
        if fits {
            assert_eq!(object.backend(), Backend::Gpu, "{said}");
            assert_eq!(object.choice().reason, ChoiceReason::Setting);
        } else {
            assert_eq!(object.backend(), Backend::Cpu, "{said}");
            assert!(
                matches!(object.choice().reason, ChoiceReason::MeshTooLarge(_)),
                "{said}"
            );
            assert!(
                said.contains("max_storage_buffer_binding_size")
                    && said.contains(&LIMIT.to_string()),
                "the line names the limit: {said}"
            );
        }
        // A frame either way, with its highlight.
        let d = Vec3::new(0.3, 0.4, 1.0).normalize();
        let input = SetupInput {
            frame: FrameId(1),
            light_eye: LightEye::Directions {
                to_light: d,
                to_eye: d,
            },
            world_from_object: Mat4::IDENTITY,
            mesh: &mesh,
            gpu: &gpu_mesh,
        };
        let mut encoder = device.create_command_encoder(&Default::default());
        let prepared = setup.prepare(&device, &queue, &mut object, &input).unwrap();
        let frame = setup.record(&mut encoder, &mut object, &prepared).unwrap();
        assert_eq!(frame.on_the_gpu(), fits);
        queue.submit([encoder.finish()]);
        setup.after_submit(&device, &queue, &mut object);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        object.adopt_read_back();
        assert_eq!(
            object.set().highlights().len(),
            1,
            "level {level}: the highlight"
        );
    }
}
