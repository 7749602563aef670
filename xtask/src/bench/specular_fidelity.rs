//! `cargo xtask bench specular-fidelity [--mesh PATH]... [--json PATH]`: do the highlights
//! cover the light they stylize? (Lee & Choi Eq. (8) sizes each projector so that
//! its footprint is the region `N·H ≥ σ`). For each mesh, over 12 views × 2 lights at
//! 640×480, the GPU renders the `N·H ≥ σ` mask and the projected-highlight mask
//! (`npr_specular::fidelity`), for the paper's sizing and ours
//! (`HighlightSizing::{Paper, Region}`). Then the 360° turn of the bunny and of each
//! `--mesh` in 1° steps: highlights that pop in or out without their fade, and the
//! largest change of a footprint's area between consecutive frames. With
//! `--animation CLIP`, each `--mesh` that has the clip also plays it (361 frames at
//! 30 fps, camera still, the highlight set reposed every frame), beside its own turn.
//!
//! Every score row and every turn is measured on both highlight backends, told apart by
//! `setup`: `"cpu"` (`HighlightSet::update`) and `"gpu"` (`GpuSetup::whole_frame`: the
//! whole frame made on the GPU, projectors included, and drawn from the projectors the
//! GPU built, as npr's GPU backend draws it; the overlap is not measured there: the
//! GPU's frames carry their own fades). A clip runs on both: `"cpu"` (each pose reposed
//! on the CPU) and `"gpu"` (each pose's curvature and tables made on the GPU,
//! `GpuSetup::pose_on_gpu`). A mesh whose GPU tables the device cannot bind loses its
//! `gpu` rows, with a line saying why.

use super::table::{Cell, Table, emit};
use glam::Vec3;
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::{GpuContext, GpuMesh};
use npr_specular::fidelity::{
    FidelityRig, FidelityScore, GpuSetup, pose_coherence, pose_coherence_with, standard_views,
    surface_at_scale, turntable_coherence, turntable_coherence_with, unit_sphere_transform,
};
use npr_specular::{HighlightBoundary, HighlightSet, HighlightSizing};
use std::path::{Path, PathBuf};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
const VIEWS: usize = 12;

/// Loads a mesh given by path (OBJ for now; `npr_geometry::io::load` adds PLY and glTF).
fn load(path: &Path) -> anyhow::Result<Mesh> {
    Ok(npr_geometry::io::load(path)?.mesh)
}

/// The default meshes: the analytic shapes and the shipped scans.
fn default_meshes() -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut meshes: Vec<(String, Mesh)> = vec![
        ("sphere".into(), generate::icosphere(4, 1.0)),
        ("ellipsoid".into(), ellipsoid(generate::icosphere(4, 1.0))),
        ("torus".into(), generate::torus(1.0, 0.45, 96, 48)),
        ("knot (paper)".into(), generate::paper_knot()),
    ];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        meshes.push((
            name.trim_end_matches(".obj").into(),
            load(&crate::fixture_mesh(name))?,
        ));
    }
    Ok(meshes)
}

/// A sphere stretched to semi-axes 1.4 × 1 × 0.7, normals transformed with it.
fn ellipsoid(mut mesh: Mesh) -> Mesh {
    let s = Vec3::new(1.4, 1.0, 0.7);
    for p in &mut mesh.positions {
        *p *= s;
    }
    for n in &mut mesh.normals {
        *n = (*n / s).normalize_or_zero();
    }
    mesh
}

/// Runs the benchmark on the default meshes and `extra` ones.
pub fn run(json: Option<&Path>, extra: &[PathBuf], animation: Option<&str>) -> anyhow::Result<()> {
    let ctx = GpuContext::new()?;
    let adapter = ctx.adapter_summary();
    let mut meshes = default_meshes()?;

    for path in extra {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        meshes.push((name, load(path)?));
    }
    let rig = FidelityRig::new(&ctx.device, &ctx.queue, WIDTH, HEIGHT)?;
    let mut table = Table::new(
        &format!(
            "specular-fidelity: highlights vs N·H ≥ σ (σ = 0.9, footprint ellipse), {VIEWS} views × 2 lights, {WIDTH}x{HEIGHT}, adapter {adapter}"
        ),
        &[
            "mesh",
            "sizing",
            "setup",
            "abstraction",
            "precision",
            "recall",
            "highlights_median",
            "drawn_median",
            "blobs_median",
            "count_within_50pct_views",
            "stretch_max",
            "overlap_share",
            "cut_boundary_share",
            "edit_completeness",
            "default",
            "adapter",
        ],
    );
    let aspect = WIDTH as f32 / HEIGHT as f32;
    for (name, mesh) in &meshes {
        let world_from_object = unit_sphere_transform(mesh);
        let views = standard_views(world_from_object, VIEWS, aspect);
        // The surface at scale 0 (the raw mesh) and at the default abstraction; each scale
        // is measured against its own N·H ≥ σ.
        let raw = HighlightSet::with_abstraction(mesh, &CurvatureOptions::default(), 0.0)?;
        let raw_gpu = GpuMesh::upload(&ctx.device, &surface_at_scale(mesh, &raw))?;
        let scaled = HighlightSet::new(mesh, &CurvatureOptions::default())?;
        let scaled_gpu = GpuMesh::upload(&ctx.device, &surface_at_scale(mesh, &scaled))?;
        let mut sets = [(raw, raw_gpu), (scaled, scaled_gpu)];
        for (sizing, boundary, scale, label) in [
            (
                HighlightSizing::Paper,
                HighlightBoundary::Unrestricted,
                0,
                "paper",
            ),
            (
                HighlightSizing::Region,
                HighlightBoundary::PerFace,
                0,
                "region, per-face",
            ),
            (
                HighlightSizing::Region,
                HighlightBoundary::Smooth,
                0,
                "region",
            ),
            (
                HighlightSizing::Region,
                HighlightBoundary::Smooth,
                1,
                "region",
            ),
        ] {
            let (set, gpu) = &mut sets[scale];
            set.tuning.sizing = sizing;
            set.tuning.boundary = boundary;
            let abstraction = set.abstraction();
            for key in SETUPS {
                let mut setup = match gpu_setup(&ctx.device, set, &mesh.indices, key) {
                    None => None,
                    Some(Ok(setup)) => Some(setup),
                    Some(Err(e)) => {
                        left_out(name, key, &e);
                        continue;
                    }
                };
                let bar = super::progress(views.len() as u64, &format!("{name} {label} {key}"));
                let mut scores = Vec::with_capacity(views.len());
                for view in &views {
                    scores.push(rig.score_with(
                        &ctx.device,
                        &ctx.queue,
                        (gpu, &mesh.indices),
                        set,
                        view,
                        setup.as_mut(),
                    )?);
                    bar.inc(1);
                }
                bar.finish_and_clear();
                let s = FidelityScore::pool(&scores);
                table.push(vec![
                    name.as_str().into(),
                    label.into(),
                    key.into(),
                    Cell::Num(f64::from(abstraction), 3),
                    Cell::Num(s.precision, 3),
                    Cell::Num(s.recall, 3),
                    Cell::Num(s.highlights_median, 1),
                    Cell::Num(s.drawn_median, 1),
                    Cell::Num(s.blobs_median, 1),
                    format!("{}/{}", s.count_within, s.views).into(),
                    Cell::Num(f64::from(s.stretch_max), 2),
                    s.overlap_share.map_or(Cell::Empty, |o| Cell::Num(o, 3)),
                    Cell::Num(s.cut_boundary_share, 3),
                    Cell::Num(s.edit_completeness, 3),
                    // The settings `npr` and `HighlightSet::new` use.
                    Cell::Bool(scale == 1 && sizing == HighlightSizing::default()),
                    adapter.as_str().into(),
                ]);
            }
        }
    }
    emit(&[table, turning(&ctx, extra, animation)?], json)
}

/// The setups each row is measured with (`setup`).
const SETUPS: [&str; 2] = ["cpu", "gpu"];

/// The GPU setup of `key` (none for `"cpu"`); an error for a mesh whose tables this
/// device cannot bind, whose rows are then left out with a line saying so.
fn gpu_setup(
    device: &wgpu::Device,
    set: &HighlightSet,
    indices: &[u32],
    key: &str,
) -> Option<Result<GpuSetup, npr_specular::SpecularError>> {
    match key {
        "gpu" => Some(GpuSetup::whole_frame(device, set, indices)),
        _ => None,
    }
}

/// Says why `key`'s rows of `name` are left out.
fn left_out(name: &str, key: &str, error: &npr_specular::SpecularError) {
    eprintln!("specular-fidelity: {name}: no `{key}` rows: {error}");
}

/// A mesh for the turning table: its name, the mesh at rest and, with `--animation`,
/// its clip's frames.
struct Turning {
    name: String,
    mesh: Mesh,
    clip: Option<(String, Vec<Mesh>)>,
}

/// Frames of each sequence of the turning table: the turn's 361 one-degree steps, and as
/// many frames of a clip at 30 fps.
const TURN_FRAMES: usize = 361;

fn turning_meshes(extra: &[PathBuf], animation: Option<&str>) -> anyhow::Result<Vec<Turning>> {
    let mut out = vec![Turning {
        name: "stanford-bunny".into(),
        mesh: load(&crate::fixture_mesh("stanford-bunny.obj"))?,
        clip: None,
    }];
    for path in extra {
        let model = npr_app::model::Model::load(path)?;
        let clip = match animation {
            Some(name) => {
                let choice = npr_app::animation::ClipChoice::parse(Some(name));
                let index = npr_app::animation::resolve_clip(&model, &choice)?;
                let animated = npr_app::animation::Animated::new(
                    model.clone(),
                    index,
                    npr_app::animation::Playback::default(),
                )?;
                index.map(|_| {
                    let frames = (0..TURN_FRAMES).map(|i| animated.posed_mesh(i)).collect();
                    (name.to_string(), frames)
                })
            }
            None => None,
        };
        let mesh = match &model.rig {
            Some(rig) => rig.pose_mesh(&rig.bind_pose()),
            None => model.mesh.clone(),
        };
        out.push(Turning {
            name: model.name.clone(),
            mesh,
            clip,
        });
    }
    Ok(out)
}

/// Each mesh turning 360° in 1° steps under a fixed light and eye, for both sizings; with
/// `--animation CLIP`, the same meshes playing the clip (361 frames at 30 fps, camera and
/// object still) beside their turn, in the same run.
fn turning(ctx: &GpuContext, extra: &[PathBuf], animation: Option<&str>) -> anyhow::Result<Table> {
    let mut table = Table::new(
        "specular-fidelity: turning 360° in 1° steps, and a clip's frames (fade rule, footprint area)",
        &[
            "mesh",
            "motion",
            "sizing",
            "setup",
            "max_area_change",
            "frames",
            "pops_in",
            "pops_out",
            "area_change_max",
        ],
    );
    let options = CurvatureOptions::default();
    for t in turning_meshes(extra, animation)? {
        let (camera, world_from_normalized) = npr_gpu::figures::framing_camera(&t.mesh, 4.0 / 3.0);
        let le = LightEye::Positions {
            light: Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
            eye: camera.eye,
        };
        let mut set = HighlightSet::new(&t.mesh, &options)?;
        for (sizing, limit) in [
            (HighlightSizing::Paper, 0.25),
            (HighlightSizing::Region, 0.25),
            (HighlightSizing::Region, 0.0),
        ] {
            set.tuning.sizing = sizing;
            set.tuning.max_area_change = limit;
            let mut runs = vec![(
                "turntable".to_string(),
                "cpu",
                turntable_coherence(&mut set, le, world_from_normalized, TURN_FRAMES, 1.0),
            )];
            // The same turn set up on the GPU (the walk is drawn, not measured here).
            for key in &SETUPS[1..] {
                let mut gpu = match gpu_setup(&ctx.device, &set, &t.mesh.indices, key) {
                    Some(Ok(gpu)) => gpu,
                    Some(Err(e)) => {
                        left_out(&t.name, key, &e);
                        continue;
                    }
                    None => continue,
                };
                let on_gpu = turntable_coherence_with(
                    &mut set,
                    (le, world_from_normalized),
                    (TURN_FRAMES, 1.0),
                    |set, frame| gpu.update(&ctx.device, &ctx.queue, set, frame),
                )?;
                runs.push(("turntable".to_string(), key, on_gpu));
            }
            if let Some((clip, frames)) = &t.clip {
                let c = pose_coherence(
                    &mut set,
                    le,
                    world_from_normalized,
                    frames.iter().cloned(),
                    &options,
                )?;
                runs.push((format!("clip {clip}"), "cpu", c));
                // Back to the rest pose for the next sizing's turn (and the GPU's clip,
                // which makes each pose's tables on the GPU and leaves the set at rest).
                set.repose(&t.mesh, &options)?;
                let made = GpuSetup::whole_frame(&ctx.device, &set, &t.mesh.indices).and_then(
                    |mut gpu| {
                        gpu.pose_on_gpu(&ctx.device, &set, (&t.mesh, &options))?;
                        Ok(gpu)
                    },
                );
                match made {
                    Ok(mut gpu) => {
                        let c = pose_coherence_with(
                            &mut set,
                            (le, world_from_normalized),
                            frames.iter().cloned(),
                            |set, pose, frame| {
                                gpu.update_pose(&ctx.device, &ctx.queue, set, pose, frame)
                            },
                        )?;
                        runs.push((format!("clip {clip}"), "gpu", c));
                    }
                    Err(e) => left_out(&t.name, "gpu", &e),
                }
            }
            for (motion, setup, c) in runs {
                table.push(vec![
                    t.name.as_str().into(),
                    motion.into(),
                    format!("{sizing:?}").to_lowercase().into(),
                    setup.into(),
                    Cell::Num(f64::from(limit), 2),
                    c.frames.into(),
                    c.pops_in.into(),
                    c.pops_out.into(),
                    Cell::Num(f64::from(c.area_change_max), 3),
                ]);
            }
        }
    }
    Ok(table)
}
