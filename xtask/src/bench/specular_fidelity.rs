//! `cargo xtask bench specular-fidelity [--mesh PATH]... [--json PATH]`: do the highlights
//! cover the light they stylize? (Lee & Choi Eq. (8) sizes each projector so that
//! its footprint is the region `N·H ≥ σ`). For each mesh, over 12 views × 2 lights at
//! 640×480, the GPU renders the `N·H ≥ σ` mask and the projected-highlight mask
//! (`npr_specular::fidelity`), for the paper's sizing and ours
//! (`HighlightSizing::{Paper, Region}`). Then the 360° turn of the bunny in 1° steps:
//! highlights that pop in or out without their fade, and the largest change of a
//! footprint's area between consecutive frames.

use super::table::{Cell, Table, emit};
use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::{GpuContext, GpuMesh};
use npr_specular::fidelity::{
    Coherence, FidelityRig, FidelityScore, standard_views, surface_at_scale, unit_sphere_transform,
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
pub fn run(json: Option<&Path>, extra: &[PathBuf]) -> anyhow::Result<()> {
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
            set.sizing = sizing;
            set.boundary = boundary;
            let abstraction = set.abstraction();
            let bar = super::progress(views.len() as u64, &format!("{name} {label}"));
            let mut scores = Vec::with_capacity(views.len());
            for view in &views {
                scores.push(rig.score(&ctx.device, &ctx.queue, (gpu, &mesh.indices), set, view)?);
                bar.inc(1);
            }
            bar.finish_and_clear();
            let s = FidelityScore::pool(&scores);
            table.push(vec![
                name.as_str().into(),
                label.into(),
                Cell::Num(f64::from(abstraction), 3),
                Cell::Num(s.precision, 3),
                Cell::Num(s.recall, 3),
                Cell::Num(s.highlights_median, 1),
                Cell::Num(s.drawn_median, 1),
                Cell::Num(s.blobs_median, 1),
                format!("{}/{}", s.count_within, s.views).into(),
                Cell::Num(f64::from(s.stretch_max), 2),
                Cell::Num(s.overlap_share, 3),
                Cell::Num(s.cut_boundary_share, 3),
                Cell::Num(s.edit_completeness, 3),
                adapter.as_str().into(),
            ]);
        }
    }
    emit(&[table, turning()?], json)
}

/// The bunny turning 360° in 1° steps under a fixed light and eye, for both sizings.
fn turning() -> anyhow::Result<Table> {
    let mesh = load(&crate::fixture_mesh("stanford-bunny.obj"))?;
    let (camera, world_from_normalized) = npr_gpu::figures::framing_camera(&mesh, 4.0 / 3.0);
    let mut table = Table::new(
        "specular-fidelity: the bunny turning 360° in 1° steps (fade rule, footprint area)",
        &[
            "mesh",
            "sizing",
            "max_area_change",
            "frames",
            "pops_in",
            "pops_out",
            "area_change_max",
        ],
    );
    let le = LightEye::Positions {
        light: Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
        eye: camera.eye,
    };
    let mut set = HighlightSet::new(&mesh, &CurvatureOptions::default())?;
    for (sizing, limit) in [
        (HighlightSizing::Paper, 0.25),
        (HighlightSizing::Region, 0.25),
        (HighlightSizing::Region, 0.0),
    ] {
        set.sizing = sizing;
        set.max_area_change = limit;
        set.reset();
        let mut c = Coherence::new(set.fade_frames);
        for deg in 0..=360 {
            let m = Mat4::from_rotation_y((deg as f32).to_radians()) * world_from_normalized;
            set.update(le, m);
            c.step(&set);
        }
        table.push(vec![
            "stanford-bunny".into(),
            format!("{sizing:?}").to_lowercase().into(),
            Cell::Num(f64::from(limit), 2),
            c.frames.into(),
            c.pops_in.into(),
            c.pops_out.into(),
            Cell::Num(f64::from(c.area_change_max), 3),
        ]);
    }
    Ok(table)
}
