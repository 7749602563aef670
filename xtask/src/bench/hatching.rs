//! `cargo xtask bench hatching`: the image-space hatching paper's three workloads (§4:
//! single objects at 640×480, a ~35,000-triangle scene at 640×480, a ~1,100,000-triangle
//! scene at 1280×480). For each: the median time of the whole hatching frame (variance
//! shadow map + G-buffer + hatching pass) against a Phong frame with the same shadow map,
//! same scene, same adapter, same run, frames alternating, the GPU waited for after each;
//! and the CPU reference's throughput on that scene's G-buffer (`cpu_mpix_per_s`; paper
//! pixels cost one comparison) and on an image of the same size inked everywhere
//! (`cpu_mpix_per_s_all_inked`, the worst case; median and best of 15), with the machine's
//! load average beside them, since other processes take cores from rayon.
//! Targets: ratio ≤ 1.5, CPU ≥ 20 megapixels per second on 2 cores.
//!
//! Both frames share the 1024² variance shadow map and its two blur passes, which
//! dominate on a software adapter. So each pass is also timed alone: the VSM (the shadow
//! pass and its blur), the G-buffer pass, the hatching pass and the Phong pass, each
//! recorded in its own command buffer, submitted and waited for (wall time; no timestamp
//! queries, which the shared device does not request). `ratio_without_vsm` is
//! (G-buffer + hatching pass) divided by the Phong pass.

use super::table::{Cell, Table, emit};
use glam::{Mat4, Vec3};
use npr_geometry::stats::median;
use npr_geometry::{Mesh, generate};
use npr_gpu::{Camera, GpuContext, GpuMesh, ObjectUniforms, OffscreenTarget};
use npr_hatching::figures::directions;
use npr_hatching::{
    CpuHatcher, HatchFrame, HatchFrameSettings, HatchObject, HatchParams, HatchPrepared, HatchView,
    SceneSettings, ShadowLight, StrokeSpace, TamParams, TonalArtMap,
};
use std::path::Path;
use std::time::{Duration, Instant};

/// One benchmark scene: objects with transforms and stroke directions, camera, light.
struct Workload {
    name: &'static str,
    objects: Vec<(Mesh, Mat4, Vec<Vec3>)>,
    size: (u32, u32),
    eye: Vec3,
    light: ShadowLight,
    paper_fps: f64,
    frames: usize,
}

fn object(mesh: Mesh, m: Mat4) -> (Mesh, Mat4, Vec<Vec3>) {
    let d = directions(&mesh);
    (mesh, m, d)
}

fn workloads() -> Vec<Workload> {
    let light = |radius: f32| ShadowLight::Directional {
        towards_light: Vec3::new(-1.2, 2.0, 0.9),
        center: Vec3::ZERO,
        radius,
    };
    let t = |x: f32, y: f32, z: f32| Mat4::from_translation(Vec3::new(x, y, z));
    let knot = |segments, tube_segments| {
        generate::torus_knot(&generate::TorusKnot::trefoil(0.15, segments, tube_segments))
    };
    vec![
        Workload {
            name: "single object (torus)",
            objects: vec![object(generate::torus(1.0, 0.4, 96, 48), Mat4::IDENTITY)],
            size: (640, 480),
            eye: Vec3::new(1.2, 2.0, 3.2),
            light: light(1.5),
            paper_fps: 51.0,
            frames: 21,
        },
        Workload {
            name: "scene (6 objects on a plane)",
            objects: vec![
                object(generate::plane(9.0, 7.0, 8, 8), Mat4::IDENTITY),
                object(generate::icosphere(4, 0.8), t(-2.2, 0.8, 0.6)),
                object(generate::torus(0.9, 0.35, 96, 48), t(0.2, 0.35, 1.4)),
                object(
                    generate::cylinder(0.5, 1.8, 64, 16, true),
                    t(2.3, 0.9, -0.4),
                ),
                object(
                    knot(280, 24),
                    t(0.0, 1.3, -1.3) * Mat4::from_scale(Vec3::splat(0.8)),
                ),
                object(generate::ellipsoid(0.9, 0.5, 0.6, 16), t(-1.4, 0.5, -1.8)),
            ],
            size: (640, 480),
            eye: Vec3::new(1.5, 4.2, 7.0),
            light: light(5.5),
            paper_fps: 45.0,
            frames: 21,
        },
        Workload {
            name: "benchmark_knot",
            objects: vec![object(generate::benchmark_knot(), Mat4::IDENTITY)],
            size: (1280, 480),
            eye: Vec3::new(0.0, 1.2, 3.4),
            light: light(1.7),
            paper_fps: 21.0,
            frames: 9,
        },
    ]
}

/// The 1-minute load average (Linux), to read the CPU numbers of a shared machine by.
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// Median of durations, in milliseconds.
fn median_ms(v: &[Duration]) -> f64 {
    median(v.iter().map(|d| d.as_secs_f64() * 1e3))
}

/// Runs the benchmark and prints (and optionally writes) its table.
pub fn run(json: Option<&Path>) -> anyhow::Result<()> {
    let ctx = GpuContext::new()?;
    let adapter = ctx.adapter.get_info().name;
    println!("bench hatching: adapter {}", ctx.adapter_summary());
    let tam = TonalArtMap::generate(&TamParams::pen())?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut table = new_table();
    let workloads = workloads();
    for (w, space) in workloads
        .iter()
        .flat_map(|w| [StrokeSpace::Surface, StrokeSpace::Screen].map(move |s| (w, s)))
    {
        let params = HatchParams {
            space,
            ..HatchParams::default()
        };
        let cpu = CpuHatcher::new(&tam, &params)?;
        let mut scene = GpuScene::new(&ctx, &tam, w)?;
        let (gpu_t, last) = time_frames(&ctx, &mut scene, w, space, &params)?;
        let cpu_t = time_cpu(&ctx, &scene, w.size, &cpu, last.as_ref())?;
        let (width, height) = w.size;
        let g = &gpu_t;
        table.push(vec![
            w.name.into(),
            space.name().into(),
            scene.triangles.into(),
            width.into(),
            height.into(),
            adapter.clone().into(),
            w.frames.into(),
            Cell::Num(g.hatch_ms, 2),
            Cell::Num(g.phong_ms, 2),
            Cell::Num(g.hatch_ms / g.phong_ms, 3),
            Cell::Num(g.vsm_ms, 2),
            Cell::Num(g.gbuffer_ms, 2),
            Cell::Num(g.hatching_ms, 2),
            Cell::Num(g.phong_pass_ms, 2),
            Cell::Num((g.gbuffer_ms + g.hatching_ms) / g.phong_pass_ms, 3),
            Cell::Num(1e3 / g.hatch_ms, 1),
            Cell::Num(w.paper_fps, 0),
            Cell::Num(cpu_t.mpix, 1),
            Cell::Num(cpu_t.mpix_inked, 1),
            Cell::Num(cpu_t.mpix_inked_best, 1),
            threads.into(),
            load_average().map_or(Cell::Empty, |l| Cell::Num(l, 2)),
        ]);
    }
    emit(&[table], json)
}

/// The empty table, with its title and columns.
fn new_table() -> Table {
    Table::new(
        "image-space hatching: whole frame vs Phong + VSM frame (median, GPU waited each frame); \
         passes alone: one submit each, waited (wall time, no timestamp queries)",
        &[
            "scene",
            "mode",
            "triangles",
            "width_px",
            "height_px",
            "adapter",
            "frames",
            "hatch_ms_median",
            "phong_vsm_ms_median",
            "ratio",
            "vsm_ms_median",
            "gbuffer_ms_median",
            "hatching_pass_ms_median",
            "phong_pass_ms_median",
            "ratio_without_vsm",
            "hatch_fps",
            "paper_fps",
            "cpu_mpix_per_s",
            "cpu_mpix_per_s_all_inked",
            "cpu_mpix_per_s_all_inked_best",
            "cpu_threads",
            "load_avg_1m",
        ],
    )
}

/// A workload on the GPU: its hatching frame, uploaded objects, camera and target.
struct GpuScene {
    /// The hatching frame (VSM, G-buffer, hatching pass, Phong pass).
    frame: HatchFrame,
    /// The uploaded meshes, kept alive for the objects that draw them.
    _meshes: Vec<GpuMesh>,
    /// Each object's hatching state and uniforms.
    objects: Vec<(HatchObject, ObjectUniforms)>,
    /// Triangles in all objects.
    triangles: usize,
    /// The workload's camera, looking at (0, 0.3, 0).
    camera: Camera,
    /// The colour target the frames draw into.
    target: OffscreenTarget,
}

impl GpuScene {
    /// Creates the frame at the workload's size and uploads its objects.
    fn new(ctx: &GpuContext, tam: &TonalArtMap, w: &Workload) -> anyhow::Result<Self> {
        let (width, height) = w.size;
        let settings = HatchFrameSettings {
            tam: tam.clone(),
            scene: SceneSettings::default(),
        };
        let formats = npr_gpu::TargetFormats::default();
        let frame = HatchFrame::new(&ctx.device, &ctx.queue, formats, &settings, w.size)?;
        let (mut meshes, mut objects) = (Vec::new(), Vec::new());
        let mut triangles = 0usize;
        for (mesh, m, dirs) in &w.objects {
            triangles += mesh.triangle_count();
            let g = GpuMesh::upload(&ctx.device, mesh)?;
            let u = ObjectUniforms::new(*m, Vec3::splat(0.9), 0.35, Vec3::ONE, 24.0);
            let o = frame.create_object(&ctx.device, &g, dirs)?;
            meshes.push(g);
            objects.push((o, u));
        }
        let camera = Camera::look_at(
            w.eye,
            Vec3::new(0.0, 0.3, 0.0),
            width as f32 / height as f32,
        );
        let target = OffscreenTarget::new(&ctx.device, width, height)?;
        Ok(Self {
            frame,
            _meshes: meshes,
            objects,
            triangles,
            camera,
            target,
        })
    }
}

/// Median GPU times of a workload, in milliseconds.
struct GpuTimes {
    /// The whole hatching frame.
    hatch_ms: f64,
    /// The Phong frame with the same shadow map.
    phong_ms: f64,
    /// The VSM alone (shadow pass and blur).
    vsm_ms: f64,
    /// The G-buffer pass alone.
    gbuffer_ms: f64,
    /// The hatching pass alone.
    hatching_ms: f64,
    /// The Phong pass alone.
    phong_pass_ms: f64,
}

/// Times the frames and each pass alone; returns the medians and the last preparation.
fn time_frames(
    ctx: &GpuContext,
    scene: &mut GpuScene,
    w: &Workload,
    space: StrokeSpace,
    params: &HatchParams,
) -> anyhow::Result<(GpuTimes, Option<HatchPrepared>)> {
    let wait = || {
        ctx.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| anyhow::anyhow!("poll: {e}"))
    };
    let (mut hatch_t, mut phong_t) = (Vec::new(), Vec::new());
    let mut passes_t: [Vec<Duration>; 4] = Default::default();
    // Records with `record`, submits, waits: the wall time of that work alone.
    let timed = |record: &dyn Fn(
        &mut wgpu::CommandEncoder,
    ) -> Result<(), npr_hatching::HatchError>|
     -> anyhow::Result<Duration> {
        let t = Instant::now();
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        record(&mut enc)?;
        ctx.queue.submit(Some(enc.finish()));
        wait()?;
        Ok(t.elapsed())
    };
    let bar = super::progress(
        w.frames as u64 + 2,
        &format!("{} ({})", w.name, space.name()),
    );
    let target = &scene.target;
    // Two warm-up frames of each, then alternate.
    let mut last = None;
    for i in 0..w.frames + 2 {
        // One displayed frame each: advances the surface anchors' schedule (and so
        // their cross-fade) as an application does. The prepare (uniform writes) is
        // outside the timed work, as the CPU side of a frame.
        let view = HatchView {
            frame: npr_gpu::FrameId(i as u64),
            clock: i as u64,
            camera: &scene.camera,
            light: &w.light,
            params,
        };
        let mut pairs: Vec<_> = scene.objects.iter_mut().map(|(o, u)| (o, &*u)).collect();
        let prepared = scene.frame.prepare(&ctx.queue, &view, &mut pairs)?;
        let objects: Vec<_> = scene.objects.iter().map(|(o, _)| o).collect();
        let (frame, p) = (&scene.frame, &prepared);
        let hatch = timed(&|enc| frame.record(enc, &target.color_view, &objects, p))?;
        let phong = timed(&|enc| frame.record_phong(enc, target, &objects, p))?;
        let passes = [
            timed(&|enc| frame.record_shadow(enc, &objects, p))?,
            timed(&|enc| frame.record_gbuffer(enc, &objects, p))?,
            timed(&|enc| frame.record_hatching(enc, &target.color_view, p))?,
            timed(&|enc| {
                let mut pass = target.begin_clear_pass(enc, [1.0; 4]);
                for (o, q) in objects.iter().zip(p.objects()) {
                    frame.scene.draw(&mut pass, o, q)?;
                }
                Ok(())
            })?,
        ];
        last = Some(prepared);
        if i >= 2 {
            hatch_t.push(hatch);
            phong_t.push(phong);
            for (all, t) in passes_t.iter_mut().zip(passes) {
                all.push(t);
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let [vsm_ms, gbuffer_ms, hatching_ms, phong_pass_ms] = passes_t.map(|t| median_ms(&t));
    let times = GpuTimes {
        hatch_ms: median_ms(&hatch_t),
        phong_ms: median_ms(&phong_t),
        vsm_ms,
        gbuffer_ms,
        hatching_ms,
        phong_pass_ms,
    };
    Ok((times, last))
}

/// The CPU reference's throughput, in megapixels per second.
struct CpuTimes {
    /// On the scene's G-buffer, median of 7.
    mpix: f64,
    /// On an image inked everywhere, median of 15.
    mpix_inked: f64,
    /// On an image inked everywhere, best of 15.
    mpix_inked_best: f64,
}

/// Times the CPU reference on the scene's G-buffer and on an image inked everywhere.
fn time_cpu(
    ctx: &GpuContext,
    scene: &GpuScene,
    (width, height): (u32, u32),
    cpu: &CpuHatcher,
    last: Option<&HatchPrepared>,
) -> anyhow::Result<CpuTimes> {
    let frame = &scene.frame;
    // CPU reference on this scene's G-buffer (left by the last hatching frame).
    let objects: Vec<_> = scene.objects.iter().map(|(o, _)| o).collect();
    if let Some(p) = last {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        frame.record(&mut enc, &scene.target.color_view, &objects, p)?;
        ctx.queue.submit(Some(enc.finish()));
    }
    let inputs = frame.gbuffer.read(&ctx.device, &ctx.queue)?;
    let mut cpu_t = Vec::new();
    for _ in 0..7 {
        let t = Instant::now();
        let img = cpu.hatch_rgba8(&inputs)?;
        cpu_t.push(t.elapsed());
        std::hint::black_box(img);
    }
    let mpix = f64::from(width * height) / 1e6 / (median_ms(&cpu_t) / 1e3);
    // Worst case: every pixel inked (no paper background), θ varying.
    let inked = npr_hatching::HatchInputs::from_fn(width, height, |x, y| {
        (0.5 + 0.4 * (0.01 * x).sin(), 0.003 * x + 0.002 * y)
    })?;
    let mut cpu_t = Vec::new();
    for _ in 0..15 {
        let t = Instant::now();
        let img = cpu.hatch_rgba8(&inked)?;
        cpu_t.push(t.elapsed());
        std::hint::black_box(img);
    }
    let best = cpu_t.iter().min().map_or(f64::NAN, |d| d.as_secs_f64());
    Ok(CpuTimes {
        mpix,
        mpix_inked: f64::from(width * height) / 1e6 / (median_ms(&cpu_t) / 1e3),
        mpix_inked_best: f64::from(width * height) / 1e6 / best,
    })
}
