//! `cargo xtask bench animation [--mesh PATH]... [--json PATH]`: what a moving model costs
//! per frame on the path `npr render --animation ... --frames` takes (the CPU reference:
//! every frame posed on the CPU and every per-mesh step recomputed on the posed surface).
//!
//! Per model, the mean over [`FRAMES`] frames of its first clip: `pose_ms` (sampling the
//! clip and skinning, `Rig::sample` + `Rig::pose_mesh`), `curvature_ms`
//! (`CurvatureField::for_mesh` of the pose), `directions_ms` (the hatching's default stroke
//! field of the pose, curvature included) and, per effect, the frame as the app draws it
//! (`animated_ms`: the posed model set (`Renderer::set_pose`) and rendered; `rigid_ms`: the
//! same model rendered
//! without changing; both wait for the GPU) and their ratio. `setup_us` is the highlight
//! setup the specular frame reports (mean, µs) and `cpu_ms_median` its median (ms): the
//! CPU time of the highlight work from the frame's start to its submit, matching
//! included. The highlights are measured on both backends, told apart by `setup`
//! (`[specular] backend`): `"cpu"`, and `"gpu"`, the whole frame's highlights on the GPU,
//! nothing read back (`cpu_ms_median` is then what recording them takes).
//! Default models: the Fox and the procedural rigs
//! (`npr_geometry::generate::bent_tube`, `stretched_sphere`, `twisted_bar`) and, as a
//! scale row reported only, the bunny on `generate::swaying`'s two-joint rig; `--mesh`
//! adds rigged glTF files. CPU times are wall time on this machine's cores.
//! `carried_ms` is the rest pose's stroke field carried through the skinning
//! (`Animated::carried_directions`), and `carried_dev_deg` the median angle between it
//! and the field computed on each pose; the hatching's frame is measured both ways. The
//! warp's frame is a warped frame between two references (recorded once): animated, the
//! proxy is posed with the model and re-binned before it is drawn.
//!
//! The posing table sets one pose into the uploaded mesh both ways, the clip sampled
//! beforehand: `cpu_pose_ms` poses on the CPU (`Rig::pose_mesh`) and uploads the vertices
//! (`GpuMesh::write_vertices`); `gpu_pose_ms` records `npr_gpu::PosingPass` (morphs,
//! skinning and, for a file without normals, the posed normals) into the vertex buffer.
//! Both wait for the GPU; `gpu_vs_cpu` is their ratio in the same run. The
//! `_curvature` columns add the pose's curvature tensor (the corrected form):
//! `CurvatureField::for_mesh` on the CPU pose, `npr_gpu::CurvaturePass` recorded after the
//! posing in the same submission.

use super::table::{Cell, Table, emit};
use npr_app::animation::{Animated, Playback};
use npr_app::engine::Renderer;
use npr_app::model::Model;
use npr_app::preset::{BackendPreset, Effect, PoseGeometry, Preset};
use npr_app::view::View;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Frames measured per model (a warm-up frame first).
const FRAMES: usize = 30;
/// The view size.
const SIZE: (u32, u32) = (640, 480);
/// The effects measured, with the hatching's two ways of following the pose and the
/// highlights' three places for their setup (the `setup` key: `"cpu"`, `"gpu"`,
/// `"gpu-frame"`).
const EFFECTS: [(Effect, PoseGeometry, BackendPreset); 6] = [
    (Effect::Phong, PoseGeometry::Recompute, BackendPreset::Cpu),
    (
        Effect::Specular,
        PoseGeometry::Recompute,
        BackendPreset::Cpu,
    ),
    (
        Effect::Specular,
        PoseGeometry::Recompute,
        BackendPreset::Gpu,
    ),
    (
        Effect::HatchingPen,
        PoseGeometry::Recompute,
        BackendPreset::Cpu,
    ),
    (
        Effect::HatchingPen,
        PoseGeometry::Carried,
        BackendPreset::Cpu,
    ),
    (Effect::Warp, PoseGeometry::Recompute, BackendPreset::Cpu),
];

fn default_models() -> anyhow::Result<Vec<Model>> {
    let rigged = |name: &str, r: npr_geometry::generate::Rigged| {
        let mut m = Model::from_mesh(name, r.mesh);
        m.rig = Some(r.rig);
        m
    };
    Ok(vec![
        Model::load(&crate::fixture_mesh("Fox.glb"))?,
        rigged(
            "bent tube (procedural)",
            npr_geometry::generate::bent_tube(0.3, 2.0, std::f32::consts::FRAC_PI_2, 32, 48),
        ),
        rigged(
            "stretched sphere (procedural)",
            npr_geometry::generate::stretched_sphere(1.5, 0.7, 1.0, 16),
        ),
        rigged(
            "twisted bar (procedural)",
            npr_geometry::generate::twisted_bar(0.4, 3.0, 40),
        ),
        // The scale row, reported only: a 35k-vertex scan on a two-joint sway.
        rigged(
            "bunny (sway rig, scale)",
            npr_geometry::generate::swaying(
                Model::load(&crate::fixture_mesh("stanford-bunny.obj"))?.mesh,
            ),
        ),
    ])
}

/// Runs the bench on the default models and `meshes`.
pub fn run(meshes: &[PathBuf], json: Option<&Path>) -> anyhow::Result<()> {
    let mut models = default_models()?;
    for p in meshes {
        let m = Model::load(p)?;
        anyhow::ensure!(
            m.rig.as_ref().is_some_and(|r| !r.clips().is_empty()),
            "{}: no clip to play (bench animation needs a rigged or morphing glTF)",
            p.display()
        );
        models.push(m);
    }
    let ctx = npr_gpu::GpuContext::new()?;
    let mut cpu = Table::new(
        "animation: CPU work per frame on the posed surface (means over 30 frames)",
        &[
            "model",
            "vertices",
            "pose_ms",
            "curvature_ms",
            "directions_ms",
            "carried_ms",
            "carried_dev_deg",
        ],
    );
    let mut gpu = Table::new(
        &format!(
            "animation: each effect's animated frame against its rigid frame, 640×480 (adapter {})",
            ctx.adapter.get_info().name
        ),
        &[
            "model",
            "effect",
            "rigid_ms",
            "animated_ms",
            "animated_vs_rigid",
            "setup",
            "setup_us",
            "cpu_ms_median",
        ],
    );
    let mut posing = Table::new(
        &format!(
            "animation: one pose set into the uploaded mesh, CPU reference vs GPU compute (adapter {})",
            ctx.adapter.get_info().name
        ),
        &[
            "model",
            "vertices",
            "cpu_pose_ms",
            "gpu_pose_ms",
            "gpu_vs_cpu",
            "cpu_pose_curvature_ms",
            "gpu_pose_curvature_ms",
            "gpu_vs_cpu_with_curvature",
        ],
    );
    let bar = super::progress(models.len() as u64, "animation");
    for model in models {
        let name = model.name.clone();
        let rig = model.rig.clone();
        let animated = Animated::new(model, Some(0), Playback::default())?;
        cpu.push(cpu_row(&name, &animated));
        if let Some(rig) = &rig {
            posing.push(posing_row(&ctx, &name, rig, &animated)?);
        }
        for (effect, geometry, search) in EFFECTS {
            gpu.push(gpu_row(&ctx, &name, &animated, (effect, geometry, search))?);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    emit(&[cpu, posing, gpu], json)
}

/// Mean milliseconds of `f` over the frames.
fn mean_ms(mut f: impl FnMut(usize)) -> f64 {
    f(0);
    let started = Instant::now();
    for i in 1..=FRAMES {
        f(i);
    }
    started.elapsed().as_secs_f64() * 1e3 / FRAMES as f64
}

fn cpu_row(name: &str, animated: &Animated) -> Vec<Cell> {
    let vertices = animated.posed_mesh(0).positions.len();
    let pose_ms = mean_ms(|i| {
        std::hint::black_box(animated.posed_mesh(i));
    });
    let poses: Vec<npr_geometry::Mesh> = (0..=FRAMES).map(|i| animated.posed_mesh(i)).collect();
    let opts = npr_geometry::CurvatureOptions::default();
    let curvature_ms = mean_ms(|i| {
        std::hint::black_box(npr_geometry::CurvatureField::for_mesh(&poses[i], &opts));
    });
    let source = npr_hatching::DirectionSource::default();
    let directions_ms = mean_ms(|i| {
        std::hint::black_box(npr_hatching::figures::directions_from(&poses[i], &source));
    });
    let which = npr_app::preset::DirectionPreset::default();
    let rest = animated.rest_directions(which);
    let posed: Vec<Model> = (0..=FRAMES).map(|i| animated.frame(i)).collect();
    let carried_ms = mean_ms(|i| {
        std::hint::black_box(animated.carried_directions(&rest, animated.time_of(i), &posed[i]));
    });
    // The carried field against the one computed on each pose: the median angle between
    // the two lines (in the model's vertex order, with the model's normals).
    let mut dev = Vec::new();
    for i in (0..=FRAMES).step_by(5) {
        let model = &posed[i];
        let exact = npr_hatching::figures::directions_from(&model.mesh, &source);
        let carried = animated.carried_directions(&rest, animated.time_of(i), model);
        for ((a, b), n) in exact.iter().zip(&carried).zip(&model.mesh.normals) {
            if let Some(d) = npr_geometry::line_angle_deg(*a, *b, *n) {
                dev.push(d);
            }
        }
    }
    dev.sort_by(f64::total_cmp);
    let median = dev.get(dev.len() / 2).copied().unwrap_or(f64::NAN);
    vec![
        name.into(),
        vertices.into(),
        Cell::Num(pose_ms, 2),
        Cell::Num(curvature_ms, 2),
        Cell::Num(directions_ms, 2),
        Cell::Num(carried_ms, 2),
        Cell::Num(median, 1),
    ]
}

fn gpu_row(
    ctx: &npr_gpu::GpuContext,
    name: &str,
    animated: &Animated,
    (effect, geometry, search): (Effect, PoseGeometry, BackendPreset),
) -> anyhow::Result<Vec<Cell>> {
    let mut preset = Preset {
        effect,
        ..Preset::default()
    };
    preset.specular.backend = search;
    preset.animation.geometry = geometry;
    let which = preset.hatching.direction;
    let rest = (geometry == PoseGeometry::Carried).then(|| animated.rest_directions(which));
    preset.output.width = SIZE.0;
    preset.output.height = SIZE.1;
    let framing = animated.framing();
    let view = View::new(&preset, &framing, SIZE, 0.0);
    let frames: Vec<Model> = (0..=FRAMES).map(|i| animated.frame(i)).collect();
    let mut renderer = Renderer::new(ctx, frames[0].clone(), SIZE)?;
    let wait = || {
        let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
    };
    // The warp's frame is a warped one, between two references recorded here (at the
    // first pose; the animated frames pose the proxy with the model before warping).
    if effect == Effect::Warp {
        renderer.warp_reference(&ctx.device, &ctx.queue, &preset, &view)?;
        renderer.warp_reference(&ctx.device, &ctx.queue, &preset, &view)?;
    }
    let draw = |renderer: &mut Renderer| {
        if effect == Effect::Warp {
            renderer.warp_frame(&ctx.device, &ctx.queue, &preset, &view, Some(0.5))
        } else {
            renderer.render(&ctx.device, &ctx.queue, &preset, &view)
        }
    };
    let mut result = Ok(());
    let mut setup = Vec::new();
    let rigid_ms = mean_ms(|_| {
        if let Err(e) = draw(&mut renderer) {
            result = Err(e);
        }
        wait();
    });
    let animated_ms = mean_ms(|i| {
        let model = frames[i].clone();
        let posed = match &rest {
            Some(r) => {
                let dirs = animated.carried_directions(r, animated.time_of(i), &model);
                renderer.set_pose_with_directions(&ctx.queue, model, (which, dirs))
            }
            None => renderer.set_pose(&ctx.queue, model),
        };
        let step = posed.and_then(|()| draw(&mut renderer));
        match step {
            Ok(s) => setup.push(s.setup_us),
            Err(e) => result = Err(e),
        }
        wait();
    });
    result?;
    let label = match geometry {
        PoseGeometry::Carried if effect.is_hatching() => format!("{} (carried)", effect.name()),
        _ => effect.name().to_string(),
    };
    Ok(vec![
        name.into(),
        label.into(),
        Cell::Num(rigid_ms, 2),
        Cell::Num(animated_ms, 2),
        Cell::Num(animated_ms / rigid_ms.max(1e-9), 2),
        if effect == Effect::Specular {
            match search {
                BackendPreset::Gpu => "gpu".into(),
                _ => "cpu".into(),
            }
        } else {
            Cell::Empty
        },
        if effect == Effect::Specular {
            Cell::Num(setup.iter().sum::<f64>() / setup.len().max(1) as f64, 0)
        } else {
            Cell::Empty
        },
        if effect == Effect::Specular {
            Cell::Num(npr_geometry::stats::median(setup) / 1e3, 3)
        } else {
            Cell::Empty
        },
    ])
}

fn posing_row(
    ctx: &npr_gpu::GpuContext,
    name: &str,
    rig: &npr_geometry::animation::Rig,
    animated: &Animated,
) -> anyhow::Result<Vec<Cell>> {
    let (d, q) = (&ctx.device, &ctx.queue);
    let clip = &rig.clips()[0];
    let poses: Vec<_> = (0..=FRAMES)
        .map(|i| rig.sample(clip, animated.time_of(i)))
        .collect();
    let bind = rig.pose_mesh(&rig.bind_pose());
    let mesh = npr_gpu::GpuMesh::upload(d, &bind)?;
    let wait = || {
        let _ = d.poll(wgpu::PollType::wait_indefinitely());
    };
    let mut result: anyhow::Result<()> = Ok(());
    let cpu_ms = mean_ms(|i| {
        if let Err(e) = mesh.write_vertices(q, &rig.pose_mesh(&poses[i])) {
            result = Err(e.into());
        }
        q.submit([]);
        wait();
    });
    let pass = npr_gpu::PosingPass::new(d);
    let mut object = pass.create_object(d, &mesh, rig, None)?;
    let mut frame = npr_gpu::FrameId::default();
    let gpu_ms = mean_ms(|i| {
        frame = frame.next();
        let input = npr_gpu::PoseInput {
            frame,
            pose: &poses[i],
        };
        let mut encoder = d.create_command_encoder(&Default::default());
        let step = pass
            .prepare(q, &mut object, &input)
            .and_then(|p| pass.record(&mut encoder, &object, &p));
        if let Err(e) = step {
            result = Err(e.into());
        }
        q.submit([encoder.finish()]);
        wait();
    });
    // The pose and its curvature tensor (the corrected form, default radius) both ways:
    // CurvatureField::for_mesh on the CPU pose, CurvaturePass on the GPU pose in the same
    // submission as the posing.
    let opts = npr_geometry::CurvatureOptions::default();
    let cpu_curvature_ms = mean_ms(|i| {
        let posed = rig.pose_mesh(&poses[i]);
        std::hint::black_box(npr_geometry::CurvatureField::for_mesh(&posed, &opts));
    });
    let curvature = npr_gpu::CurvaturePass::new(d);
    let mut field =
        curvature.create_object(d, &mesh, &bind, npr_geometry::CurvatureRadius::default())?;
    let gpu_curvature_ms = mean_ms(|i| {
        frame = frame.next();
        let input = npr_gpu::PoseInput {
            frame,
            pose: &poses[i],
        };
        let mut encoder = d.create_command_encoder(&Default::default());
        let step = pass
            .prepare(q, &mut object, &input)
            .and_then(|p| pass.record(&mut encoder, &object, &p))
            .and_then(|()| {
                let c = curvature.prepare(q, &mut field, &npr_gpu::CurvatureInput { frame })?;
                curvature.record(&mut encoder, &field, &c)
            });
        if let Err(e) = step {
            result = Err(e.into());
        }
        q.submit([encoder.finish()]);
        wait();
    });
    result?;
    Ok(vec![
        name.into(),
        bind.positions.len().into(),
        Cell::Num(cpu_ms, 3),
        Cell::Num(gpu_ms, 3),
        Cell::Num(gpu_ms / cpu_ms.max(1e-9), 2),
        Cell::Num(cpu_curvature_ms, 3),
        Cell::Num(gpu_curvature_ms, 3),
        Cell::Num(gpu_curvature_ms / cpu_curvature_ms.max(1e-9), 2),
    ])
}
