//! `cargo xtask demo`: renders the demo images into `target/demo/` and prints where.
//! Base shadings of the procedural fixtures and the real meshes in `fixtures/meshes/`;
//! each technique adds its figures here, and [`crate::gallery`] lists and captions them
//! all in `target/demo/index.html`.

use crate::{fixture_mesh, project_root};
use anyhow::Context;
use glam::Vec3;
use npr_geometry::{Mesh, generate};
use npr_gpu::snapshot::{BaseScene, render_base};
use npr_gpu::{GpuContext, GpuMesh, Light, ObjectUniforms, ShadingModel};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where demo images go.
pub fn demo_dir() -> PathBuf {
    project_root().join("target/demo")
}

/// The procedural demo meshes, plus the real meshes from `fixtures/meshes/`.
pub fn demo_meshes() -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut meshes = vec![
        ("sphere".to_string(), generate::icosphere(4, 1.0)),
        ("torus".to_string(), generate::torus(1.0, 0.4, 96, 48)),
        (
            "ellipsoid".to_string(),
            generate::ellipsoid(1.2, 0.8, 0.6, 24),
        ),
        (
            "cylinder".to_string(),
            generate::cylinder(0.6, 1.6, 64, 16, true),
        ),
        ("knot".to_string(), generate::paper_knot()),
    ];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        let mesh = npr_geometry::load_obj(fixture_mesh(name))
            .with_context(|| format!("loading fixtures/meshes/{name}"))?;
        meshes.push((name.trim_end_matches(".obj").to_string(), mesh));
    }
    Ok(meshes)
}

use npr_gpu::figures::{framing_camera, paste};

/// Writes `image` to `path` and records the path in `written`.
pub fn save(
    image: &image::RgbaImage,
    path: &Path,
    written: &mut Vec<PathBuf>,
) -> anyhow::Result<()> {
    image
        .save(path)
        .with_context(|| format!("writing {}", path.display()))?;
    written.push(path.to_path_buf());
    Ok(())
}

/// A demo: writes its figures into the directory and returns their paths, naming its
/// long parts on the progress bar (and adding steps to it with `inc_length`).
type Demo = fn(&GpuContext, &Path, &indicatif::ProgressBar) -> anyhow::Result<Vec<PathBuf>>;

/// Runs every demo, checks that it wrote exactly the gallery's files, and writes the
/// gallery page (`target/demo/index.html`).
pub fn run() -> anyhow::Result<()> {
    let dir = demo_dir();
    std::fs::create_dir_all(&dir)?;
    let ctx = GpuContext::new()?;
    println!("demo: adapter {}", ctx.adapter_summary());
    let demos: [(&str, Demo); 4] = [
        ("base shading", base_shading),
        ("specular", specular),
        ("hatching", hatching),
        ("warp", warp),
    ];
    let bar = crate::bench::progress(demos.len() as u64, "demo");
    let mut written = Vec::new();
    for (name, demo) in demos {
        bar.set_message(name);
        written.extend(demo(&ctx, &dir, &bar)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    for p in &written {
        println!("demo: wrote {}", p.display());
    }
    crate::gallery::check_written(&dir, &written)?;
    let index = crate::gallery::write(&dir)?;
    println!(
        "demo: {} images in {}; the gallery: {}",
        written.len(),
        dir.display(),
        index.display()
    );
    Ok(())
}

/// The specular paper's figures: `npr-specular`'s figure examples.
const SPECULAR_FIGURES: [&str; 7] = ["fig2", "fig4", "fig5", "fig6", "fig7", "fig8", "sizing"];

fn specular(
    _ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    run_examples("npr-specular", &SPECULAR_FIGURES, dir, progress)
}

/// The hatching paper's figures and ours: `npr-hatching`'s figure examples.
const HATCHING_FIGURES: [&str; 8] = [
    "tam",
    "fig1",
    "fig2",
    "fig3",
    "fig4",
    "directions",
    "coherence",
    "flow",
];

fn hatching(
    _ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    run_examples("npr-hatching", &HATCHING_FIGURES, dir, progress)
}

/// The warping paper's figures and ours: `npr-warp`'s figure examples.
const WARP_FIGURES: [&str; 3] = ["fig8_10", "sequence", "occlusion"];

fn warp(
    _ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    run_examples("npr-warp", &WARP_FIGURES, dir, progress)
}

/// Builds `examples` of `krate`, runs each with `dir` as its output directory, and returns
/// the files they report (`wrote PATH` lines, `npr_gpu::figures::save`).
pub fn run_examples(
    krate: &str,
    examples: &[&str],
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut build = Command::new(&cargo);
    build.args(["build", "--release", "--quiet", "-p", krate]);
    for e in examples {
        build.args(["--example", e]);
    }
    progress.set_message(format!("{krate}: building the figure examples"));
    let status = build.current_dir(project_root()).status()?;
    anyhow::ensure!(
        status.success(),
        "building {krate}'s examples failed ({status})"
    );
    progress.inc_length(examples.len() as u64);
    let mut written = Vec::new();
    for e in examples {
        progress.set_message(format!("{krate}: example {e}"));
        let out = Command::new(&cargo)
            .args([
                "run",
                "--release",
                "--quiet",
                "-p",
                krate,
                "--example",
                e,
                "--",
            ])
            .arg(dir)
            .current_dir(project_root())
            .stderr(std::process::Stdio::inherit())
            .output()?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        for line in stdout.lines() {
            match line.strip_prefix("wrote ") {
                Some(path) => written.push(PathBuf::from(path)),
                None => println!("{line}"),
            }
        }
        anyhow::ensure!(
            out.status.success(),
            "cargo run -p {krate} --example {e} failed ({})",
            out.status
        );
        progress.inc(1);
    }
    Ok(written)
}

/// Base shadings (Phong, Gouraud, cel with outlines) of every demo mesh, one PNG each
/// and a sheet.
fn base_shading(
    ctx: &GpuContext,
    dir: &Path,
    _progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    const TILE: u32 = 320;
    let meshes = demo_meshes()?;
    let models = ShadingModel::ALL;
    let mut sheet = image::RgbaImage::new(TILE * models.len() as u32, TILE * meshes.len() as u32);
    let mut written = Vec::new();
    let light = Light::directional(Vec3::new(1.0, 1.5, 2.0));
    for (row, (name, mesh)) in meshes.iter().enumerate() {
        let gpu = GpuMesh::upload(&ctx.device, mesh)?;
        let (camera, world_from_object) = framing_camera(mesh, 1.0);
        let object = ObjectUniforms::new(
            world_from_object,
            Vec3::new(0.75, 0.45, 0.3),
            0.5,
            Vec3::ONE,
            40.0,
        );
        let scene = BaseScene {
            objects: &[(&gpu, object)],
            camera,
            light,
            clear: [1.0, 1.0, 1.0, 1.0],
        };
        for (col, model) in models.iter().enumerate() {
            let mut image = render_base(&ctx.device, &ctx.queue, &scene, *model, TILE, TILE)?;
            if *model == ShadingModel::Cel {
                // Cel shading with ink outlines (npr_gpu::outline), as cartoons are drawn.
                let objects = [(&gpu, world_from_object)];
                let settings = npr_gpu::outline::OutlineSettings::default();
                image = npr_gpu::outline::outline_image(
                    &ctx.device,
                    &ctx.queue,
                    &image,
                    &camera,
                    &objects,
                    &settings,
                )?;
            }
            let path = dir.join(format!("base-{name}-{}.png", model.name()));
            save(&image, &path, &mut written)?;
            paste(&mut sheet, &image, col as u32 * TILE, row as u32 * TILE);
        }
    }
    save(&sheet, &dir.join("base-shading-sheet.png"), &mut written)?;
    Ok(written)
}
