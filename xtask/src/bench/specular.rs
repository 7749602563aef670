//! `cargo xtask bench specular`: the specular paper's Table 1 on our meshes — highlight
//! count, CPU setup per frame (N = H search + matching + projectors + BFS visibility),
//! GPU frame time with and without the highlight pass on the adapter in use, and two
//! ratios against the base frame: `highlight_cost_ratio_gpu` (the GPU frame with the
//! highlight pass alone) and `highlight_cost_ratio_frame` (that GPU frame plus the CPU
//! setup it waits on: the whole frame). Frames rotate the object 3° each; GPU times
//! include submit and wait. The setup is also timed on one core (`setup_us_median_1core`,
//! the updates run in a one-thread rayon pool), the measure. Meshes are reordered
//! for locality as `npr` loads them (`npr_geometry::locality`); the same one-core setup
//! on the file's own triangle order is `setup_us_median_1core_file_order`, from the same
//! run. Default meshes plus the 1.1M-triangle knot and any `--mesh PATH` (OBJ, PLY,
//! glTF).
//!
//! Each mesh has two rows from the same run, told apart by `setup`, one per highlight
//! backend (`npr_specular::Backend`), each frame's highlights set up by
//! `npr_specular::HighlightSetup` as an embedder sets them up: `"cpu"` (the set's update
//! before the frame's commands) and `"gpu"` (the whole frame as compute passes, search,
//! regions, projectors and §4.2 receivers recorded into the frame's own submission,
//! nothing read back on its path). `cpu_ms_median` is the setup's CPU time in the frame
//! (`SetupStats::cpu_us`: the CPU backend's update, matching included; the GPU backend's
//! recording); the GPU frame with highlights is the whole frame less that for the CPU
//! backend, the whole frame for the GPU backend. The `gpu` row's search, region and
//! visibility cells are empty (none of it runs on the CPU), and its receiver count is read
//! back after the timed frame. `highlights_min`/`max` count the highlights the CPU knows
//! after each frame (a split one once; the GPU backend's read back). The one-core columns
//! are the CPU backend's. A mesh whose GPU tables exceed the device's storage bindings
//! loses its `gpu` row, with a line saying why (the setup ran the CPU for it).
//!
//! A second table, from the same run, times the regions `N·H ≥ σ` of each frame's centres
//! grown on the CPU and as a compute pass (`npr_specular::gpu::RegionPass`): see `regions.rs`.

mod regions;

use super::table::{Cell, Table, emit};
use glam::{Mat4, Vec3};
use npr_geometry::stats::median;
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::{Camera, GpuContext, GpuMesh, Light, ObjectUniforms, ShadingModel};
use npr_specular::snapshot::{HighlightScene, Renderer};
use npr_specular::{Backend, BackendSetting, HighlightSet, HighlightSetup, SpecularSettings};
use std::path::{Path, PathBuf};
use std::time::Instant;

const FRAMES: usize = 60;
const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;

/// Runs the benchmark.
pub fn run(extra: &[PathBuf], json: Option<&Path>) -> anyhow::Result<()> {
    let ctx = GpuContext::new()?;
    let adapter = ctx.adapter_summary();
    let meshes = bench_meshes(extra)?;
    let one_core = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let renderer = Renderer::new(&ctx.device, &ctx.queue, WIDTH, HEIGHT)?;
    let mut table = new_table(&adapter);
    let mut region_table = regions::new_table(&adapter);
    for (name, file_mesh) in &meshes {
        let reordered = npr_geometry::locality::reorder_for_locality(file_mesh).mesh;
        let mesh = &reordered;
        let (camera, world_from_normalized) =
            npr_gpu::figures::framing_camera(mesh, WIDTH as f32 / HEIGHT as f32);
        let view = View {
            camera,
            world_from_normalized,
            to_light: Vec3::new(0.4, 0.7, 1.0).normalize(),
        };
        region_table.push(regions::row(&ctx, mesh, &view, name, &adapter)?);
        let (setup_1core, setup_1core_file_order) =
            measure_one_core(&one_core, mesh, file_mesh, &view)?;
        for setup in Backend::ALL {
            let gpu = match measure_gpu(&ctx, &renderer, mesh, &view, name, setup) {
                Err(e) if e.is::<NotRun>() => {
                    println!("{name}: no {setup} row: the setup runs {e}");
                    continue;
                }
                made => made?,
            };
            let (b, w, f) = (median(gpu.base), median(gpu.with), median(gpu.whole));
            let one_core = |samples: &[f64]| match setup {
                Backend::Cpu => Cell::Num(median(samples.to_vec()), 1),
                Backend::Gpu => Cell::Empty,
            };
            // The frame made wholly on the GPU has no CPU search, regions or walk.
            let cpu_part = |samples: Vec<f64>| match setup {
                Backend::Gpu => Cell::Empty,
                Backend::Cpu => Cell::Num(median(samples), 1),
            };
            table.push(vec![
                name.as_str().into(),
                setup.name().into(),
                (mesh.indices.len() / 3).into(),
                gpu.hmin.into(),
                gpu.hmax.into(),
                Cell::Num(median(gpu.receivers), 0),
                Cell::Num(median(gpu.setup.clone()) / 1e3, 3),
                Cell::Num(median(gpu.setup), 1),
                one_core(&setup_1core),
                one_core(&setup_1core_file_order),
                cpu_part(gpu.search),
                cpu_part(gpu.region),
                cpu_part(gpu.visibility),
                Cell::Num(b, 3),
                Cell::Num(w, 3),
                Cell::Num(f, 3),
                Cell::Num(w / b, 3),
                Cell::Num(f / b, 3),
                adapter.as_str().into(),
            ]);
        }
    }
    emit(&[table, region_table], json)
}

/// The meshes measured, in table order: the defaults, the 1.1M-face knot, then `extra`.
fn bench_meshes(extra: &[PathBuf]) -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut meshes: Vec<(String, Mesh)> = vec![
        ("sphere".into(), generate::icosphere(3, 1.0)),
        ("knot (paper, 2,880 faces)".into(), generate::paper_knot()),
        (
            "torus (2,200 faces)".into(),
            generate::torus(1.0, 0.45, 55, 20),
        ),
    ];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        meshes.push((
            name.trim_end_matches(".obj").into(),
            npr_geometry::load_obj(crate::fixture_mesh(name))?,
        ));
    }
    meshes.push(("knot (1.1M faces)".into(), generate::benchmark_knot()));
    for path in extra {
        let mesh = npr_geometry::io::load(path)?.mesh;
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        meshes.push((name, mesh));
    }
    Ok(meshes)
}

/// The empty table, titled with the frame size, frame count and adapter.
fn new_table(adapter: &str) -> Table {
    Table::new(
        &format!(
            "specular: Table 1 on our meshes, {WIDTH}x{HEIGHT}, {FRAMES} frames, adapter {adapter}"
        ),
        &[
            "mesh",
            "setup",
            "faces",
            "highlights_min",
            "highlights_max",
            "receiver_faces_median",
            "cpu_ms_median",
            "setup_us_median",
            "setup_us_median_1core",
            "setup_us_median_1core_file_order",
            "search_us_median",
            "region_us_median",
            "visibility_us_median",
            "base_ms_median",
            "with_highlights_ms_median",
            "frame_with_setup_ms_median",
            "highlight_cost_ratio_gpu",
            "highlight_cost_ratio_frame",
            "adapter",
        ],
    )
}

/// The camera, framing and light shared by a mesh's frames.
struct View {
    /// The camera framing the mesh.
    camera: Camera,
    /// Places the mesh, normalised, in the world before the frame's turn.
    world_from_normalized: Mat4,
    /// Unit direction towards the light.
    to_light: Vec3,
}

impl View {
    /// The object's placement and the light and eye positions of frame `frame` (3° a frame).
    fn frame(&self, frame: usize) -> (Mat4, LightEye) {
        let world_from_object =
            Mat4::from_rotation_y((frame as f32 * 3.0).to_radians()) * self.world_from_normalized;
        let le = LightEye::Positions {
            light: self.to_light * 50.0,
            eye: self.camera.eye,
        };
        (world_from_object, le)
    }
}

/// Per-frame samples of the multi-threaded run, warm-up frames left out.
struct GpuSamples {
    /// CPU setup per frame, µs.
    setup: Vec<f64>,
    /// GPU frame without the highlight pass, ms.
    base: Vec<f64>,
    /// GPU frame with the highlight pass, ms.
    with: Vec<f64>,
    /// GPU frame with the highlight pass plus the setup, ms.
    whole: Vec<f64>,
    /// Receiver faces per frame.
    receivers: Vec<f64>,
    /// N = H search per frame, µs.
    search: Vec<f64>,
    /// Highlight region per frame, µs.
    region: Vec<f64>,
    /// BFS visibility per frame, µs.
    visibility: Vec<f64>,
    /// Fewest highlights in a frame.
    hmin: usize,
    /// Most highlights in a frame.
    hmax: usize,
}

/// Why a backend's row of a mesh is left out: the setup chose another backend for it (a
/// mesh whose GPU tables the device cannot bind runs the CPU), with its line.
#[derive(Debug)]
struct NotRun(String);

impl std::fmt::Display for NotRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotRun {}

/// Times the setup and the GPU frame without and with the highlight pass, frame by frame,
/// the highlights set up by `npr_specular::HighlightSetup` on `backend` (as an embedder
/// sets them up: the CPU backend's update inside the frame, the GPU backend's stages
/// recorded into it). [`NotRun`] where the setup runs another backend for this mesh.
fn measure_gpu(
    ctx: &GpuContext,
    renderer: &Renderer,
    mesh: &Mesh,
    view: &View,
    name: &str,
    backend: Backend,
) -> anyhow::Result<GpuSamples> {
    let settings = SpecularSettings {
        backend: match backend {
            Backend::Cpu => BackendSetting::Cpu,
            Backend::Gpu => BackendSetting::Gpu,
        },
        ..SpecularSettings::default()
    };
    let setup = HighlightSetup::new(&ctx.device, &ctx.queue, &Default::default());
    let adapter = ctx.adapter.get_info();
    let mut object = setup.create_object(&ctx.device, &ctx.queue, mesh, &settings, &adapter)?;
    if object.backend() != backend {
        return Err(NotRun(object.choice().to_string()).into());
    }
    // The scene's set is not read by a setup's frames (the object holds its own); the
    // base frames draw no highlights.
    let unread = HighlightSet::new(&generate::icosphere(0, 1.0), &CurvatureOptions::default())?;
    let gpu = GpuMesh::upload(&ctx.device, mesh)?;
    let mut res = renderer.resources(&ctx.device, &gpu);
    let light = Light::directional(view.to_light);
    let mut out = GpuSamples {
        setup: Vec::new(),
        base: Vec::new(),
        with: Vec::new(),
        whole: Vec::new(),
        receivers: Vec::new(),
        search: Vec::new(),
        region: Vec::new(),
        visibility: Vec::new(),
        hmin: usize::MAX,
        hmax: 0,
    };
    let bar = super::progress(FRAMES as u64 + 3, name);
    for frame in 0..FRAMES + 3 {
        let (world_from_object, le) = view.frame(frame);
        let scene = |highlights| HighlightScene {
            mesh: &gpu,
            indices: &mesh.indices,
            set: &unread,
            object: ObjectUniforms::new(
                world_from_object,
                Vec3::new(0.8, 0.35, 0.25),
                0.0,
                Vec3::ONE,
                60.0,
            ),
            camera: view.camera,
            light,
            base: ShadingModel::Phong,
            highlights,
            clear: [1.0; 4],
        };
        let t = Instant::now();
        renderer.submit(&ctx.device, &ctx.queue, &scene(false), &mut res)?;
        ctx.device.poll(wgpu::PollType::wait_indefinitely())?;
        let b = t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        let frame_setup = (&setup, &mut object, mesh, le);
        renderer.submit_setup(&ctx.device, &ctx.queue, &scene(true), &mut res, frame_setup)?;
        ctx.device.poll(wgpu::PollType::wait_indefinitely())?;
        let whole = t.elapsed().as_secs_f64() * 1e3;
        let st = object.stats();
        // The CPU backend's update runs before the frame's commands, the GPU backend's
        // recording with them: the GPU frame is the whole less the CPU's update.
        let with = match backend {
            Backend::Cpu => whole - st.cpu_us / 1e3,
            Backend::Gpu => whole,
        };
        // What the CPU knows after the frame: the GPU backend's read back (waited for).
        object.adopt_read_back();
        let shown = object
            .set()
            .highlights()
            .iter()
            .filter(|h| h.piece == 0)
            .count();
        let receivers = match object.gpu_frame() {
            Some(f) => walked_faces(ctx, f, name)?,
            None => st.receiver_faces,
        };
        if frame >= 3 {
            let set = object.set().stats();
            out.setup.push(st.cpu_us);
            out.search.push(set.search_us);
            out.region.push(set.region_us);
            out.visibility.push(set.visibility_us);
            out.base.push(b);
            out.with.push(with);
            out.whole.push(whole);
            out.receivers.push(receivers as f64);
            out.hmin = out.hmin.min(shown);
            out.hmax = out.hmax.max(shown);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(out)
}

/// The faces the GPU frame's last walk received (read after the timed frame, the panel's
/// way); an error where a walk overflowed.
fn walked_faces(
    ctx: &GpuContext,
    frame: &npr_specular::gpu::FrameOnGpu,
    name: &str,
) -> anyhow::Result<usize> {
    let Some(walked) = frame.walked() else {
        return Ok(0);
    };
    let walk = frame.receivers();
    let read = walk
        .map_counts(&ctx.device, &ctx.queue, walked)?
        .wait(&ctx.device)?;
    anyhow::ensure!(
        read.counts.iter().all(|c| !c.overflowed),
        "{name}: a GPU receiver walk overflowed its {} faces",
        walk.capacity()
    );
    Ok(read.counts.iter().map(|c| c.received as usize).sum())
}

/// Times the setup alone on one core, as loaded and in the file's order; µs each.
fn measure_one_core(
    one_core: &rayon::ThreadPool,
    mesh: &Mesh,
    file_mesh: &Mesh,
    view: &View,
) -> anyhow::Result<(Vec<f64>, Vec<f64>)> {
    // The same turning sequence, setup only, on one core: as loaded, and in the file's own
    // triangle order, frame by frame in turn so both see the same machine load.
    let mut loaded = HighlightSet::new(mesh, &CurvatureOptions::default())?;
    let mut file_order = HighlightSet::new(file_mesh, &CurvatureOptions::default())?;
    let (mut setup_1core, mut setup_1core_file_order) = (Vec::new(), Vec::new());
    one_core.install(|| {
        for frame in 0..FRAMES + 3 {
            let (world_from_object, le) = view.frame(frame);
            for (set, times) in [
                (&mut loaded, &mut setup_1core),
                (&mut file_order, &mut setup_1core_file_order),
            ] {
                let t = Instant::now();
                set.update(le, world_from_object);
                if frame >= 3 {
                    times.push(t.elapsed().as_secs_f64() * 1e6);
                }
            }
        }
    });
    Ok((setup_1core, setup_1core_file_order))
}
