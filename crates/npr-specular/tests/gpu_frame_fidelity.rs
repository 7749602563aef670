//! The fidelity figures of frames made wholly on the GPU (`fidelity::GpuSetup::
//! whole_frame`: search, regions, projectors and receivers on the GPU, the highlights
//! drawn from the projectors the GPU built) against the CPU's update of the same views
//! and turns: precision, recall, the highlights seen, edit completeness, pops and the
//! largest footprint change. A procedural torus and hammer CAD scan (neither used to
//! tune the GPU frame) and Spot; and clips of procedural rigs, each pose made on the GPU.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::Vec3;
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::GpuMesh;
use npr_specular::fidelity::{
    Coherence, FidelityRig, FidelityScore, GpuSetup, pose_coherence, pose_coherence_with,
    standard_views, surface_at_scale, turntable_coherence, turntable_coherence_with,
    unit_sphere_transform,
};
use npr_specular::{HighlightSet, HighlightSizing};

mod common;
use common::fixture;

/// How far a pooled share (precision, recall, edit completeness) of the GPU frames may
/// be from the CPU's: a few edge pixels of f32 against f64 solves.
const SHARE_GAP: f64 = 0.01;

/// Scores `views` with `set` on the CPU, or with frames made wholly on the GPU.
fn score(
    ctx: &npr_gpu::GpuContext,
    (mesh, set): (&Mesh, &mut HighlightSet),
    rig: &FidelityRig,
    whole_frame: bool,
) -> FidelityScore {
    let gpu = GpuMesh::upload(&ctx.device, &surface_at_scale(mesh, set)).unwrap();
    let mut setup =
        whole_frame.then(|| GpuSetup::whole_frame(&ctx.device, set, &mesh.indices).unwrap());
    let views = standard_views(unit_sphere_transform(mesh), 3, 4.0 / 3.0);
    let scores: Vec<_> = views
        .iter()
        .map(|v| {
            rig.score_with(
                &ctx.device,
                &ctx.queue,
                (&gpu, &mesh.indices),
                set,
                v,
                setup.as_mut(),
            )
            .unwrap()
        })
        .collect();
    FidelityScore::pool(&scores)
}

#[test]
fn whole_frames_on_the_gpu_score_as_the_cpus_update() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("whole_frames_on_the_gpu_score_as_the_cpus_update")
    else {
        return;
    };
    let rig = FidelityRig::new(&ctx.device, &ctx.queue, 200, 150).unwrap();
    let meshes = [
        ("torus", generate::torus(1.0, 0.45, 64, 32)),
        ("spot", fixture("spot.obj")),
        ("hammer", fixture("hammer.obj")),
    ];
    let mut failures = Vec::new();
    let mut rows = Vec::new();
    for (name, mesh) in &meshes {
        for sizing in [HighlightSizing::Region, HighlightSizing::Paper] {
            let mut set = HighlightSet::new(mesh, &CurvatureOptions::default()).unwrap();
            set.tuning.sizing = sizing;
            let cpu = score(ctx, (mesh, &mut set), &rig, false);
            let gpu = score(ctx, (mesh, &mut set), &rig, true);
            assert!(
                cpu.highlights_median > 0.0,
                "{name}: no highlight to compare"
            );
            let shares = [
                ("precision", cpu.precision, gpu.precision),
                ("recall", cpu.recall, gpu.recall),
                ("edits", cpu.edit_completeness, gpu.edit_completeness),
            ];
            for (what, c, g) in shares {
                if (c - g).abs() > SHARE_GAP {
                    failures.push(format!("{name} {sizing:?} {what}: GPU {g:.4}, CPU {c:.4}"));
                }
            }
            // Every highlight is seen with its own code: a frame drawn without the
            // user's per-highlight tints would count one.
            if (cpu.highlights_median - gpu.highlights_median).abs() > 0.5
                || (cpu.drawn_median - gpu.drawn_median).abs() > 0.5
            {
                failures.push(format!(
                    "{name} {sizing:?}: {} highlights seen of {} on the GPU, {} of {} on the CPU",
                    gpu.highlights_median,
                    gpu.drawn_median,
                    cpu.highlights_median,
                    cpu.drawn_median
                ));
            }
            rows.push((*name, sizing, cpu, gpu));
        }
    }
    for (name, sizing, cpu, gpu) in &rows {
        eprintln!(
            "{name} {sizing:?}: precision {:.4}/{:.4} recall {:.4}/{:.4} edits {:.4}/{:.4} \
             seen {}/{} (CPU/GPU)",
            cpu.precision,
            gpu.precision,
            cpu.recall,
            gpu.recall,
            cpu.edit_completeness,
            gpu.edit_completeness,
            cpu.highlights_median,
            gpu.highlights_median
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A sequence made on the GPU pops and changes its footprints as the CPU's.
fn assert_same_coherence(name: &str, (cpu, on_gpu): (&Coherence, &Coherence), frames: usize) {
    eprintln!("{name}: CPU {cpu:?}\n GPU {on_gpu:?}");
    assert_eq!(on_gpu.frames, frames);
    assert_eq!(
        (on_gpu.pops_in, on_gpu.pops_out),
        (cpu.pops_in, cpu.pops_out),
        "{name}"
    );
    assert!(
        (on_gpu.area_change_max - cpu.area_change_max).abs() <= 1e-3,
        "{name}: largest area change {} on the GPU, {} on the CPU",
        on_gpu.area_change_max,
        cpu.area_change_max
    );
}

#[test]
fn a_turn_made_on_the_gpu_fades_as_the_cpus() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_turn_made_on_the_gpu_fades_as_the_cpus")
    else {
        return;
    };
    for (name, mesh) in [
        ("spot", fixture("spot.obj")),
        ("hammer", fixture("hammer.obj")),
    ] {
        let (camera, world) = npr_gpu::figures::framing_camera(&mesh, 4.0 / 3.0);
        let le = LightEye::Positions {
            light: Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
            eye: camera.eye,
        };
        let mut set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        // 5° steps: highlights come and go, and the change limit acts.
        let (frames, step) = (48, 5.0);
        let cpu = turntable_coherence(&mut set, le, world, frames, step);
        let mut gpu = GpuSetup::whole_frame(&ctx.device, &set, &mesh.indices).unwrap();
        let on_gpu = turntable_coherence_with(&mut set, (le, world), (frames, step), |s, f| {
            gpu.update(&ctx.device, &ctx.queue, s, f)
        })
        .unwrap();
        assert_same_coherence(name, (&cpu, &on_gpu), frames);
    }
}

#[test]
fn a_clip_made_on_the_gpu_fades_as_the_cpus() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_clip_made_on_the_gpu_fades_as_the_cpus")
    else {
        return;
    };
    let options = CurvatureOptions::default();
    let rigs = [
        ("bent tube", generate::bent_tube(0.3, 1.0, 1.5, 24, 48)),
        (
            "stretched sphere",
            generate::stretched_sphere(1.0, 0.7, 0.5, 12),
        ),
        ("swaying knot", generate::swaying(generate::paper_knot())),
    ];
    for (name, rigged) in rigs {
        let (rest, rig) = (&rigged.mesh, &rigged.rig);
        let clip = &rig.clips()[0];
        let frames = 36;
        let poses: Vec<Mesh> = (0..frames)
            .map(|k| rig.pose_mesh(&rig.sample(clip, clip.duration() * k as f32 / frames as f32)))
            .collect();
        let (camera, world) = npr_gpu::figures::framing_camera(rest, 4.0 / 3.0);
        let le = LightEye::Positions {
            light: Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
            eye: camera.eye,
        };
        let mut set = HighlightSet::new(rest, &options).unwrap();
        let mut gpu = GpuSetup::whole_frame(&ctx.device, &set, &rest.indices).unwrap();
        gpu.pose_on_gpu(&ctx.device, &set, (rest, &options))
            .unwrap();
        let on_gpu = pose_coherence_with(&mut set, (le, world), poses.clone(), |s, pose, f| {
            gpu.update_pose(&ctx.device, &ctx.queue, s, pose, f)
        })
        .unwrap();
        let cpu = pose_coherence(&mut set, le, world, poses, &options).unwrap();
        assert_same_coherence(name, (&cpu, &on_gpu), frames);
    }
}
