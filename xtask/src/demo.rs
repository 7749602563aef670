//! `cargo xtask demo`: runs every crate's figure examples (`examples/fig*.rs` and the
//! like, each writing its images into the directory it is given) into `target/demo/`,
//! checks that they wrote exactly the gallery's files, and writes the gallery
//! ([`crate::gallery`], `target/demo/index.html`).

use crate::project_root;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where demo images go.
pub fn demo_dir() -> PathBuf {
    project_root().join("target/demo")
}

/// The figure examples, by crate, in the gallery's order: npr-gpu's base shadings, the
/// specular paper's figures, the hatching paper's and ours, the warping paper's.
const FIGURES: [(&str, &[&str]); 4] = [
    ("npr-gpu", &["base_shading"]),
    (
        "npr-specular",
        &["fig2", "fig4", "fig5", "fig6", "fig7", "fig8", "sizing"],
    ),
    (
        "npr-hatching",
        &[
            "tam",
            "fig1",
            "fig2",
            "fig3",
            "fig4",
            "directions",
            "coherence",
            "flow",
        ],
    ),
    ("npr-warp", &["fig8_10", "sequence", "occlusion"]),
];

/// Runs every figure example, checks that they wrote exactly the gallery's files, and
/// writes the gallery page (`target/demo/index.html`).
pub fn run() -> anyhow::Result<()> {
    let dir = demo_dir();
    std::fs::create_dir_all(&dir)?;
    let bar = crate::bench::progress(FIGURES.len() as u64, "demo");
    let mut written = Vec::new();
    for (krate, examples) in FIGURES {
        written.extend(run_examples(krate, examples, &dir, &bar)?);
        bar.inc(1);
    }
    bar.set_message("the pen plotter's SVGs");
    written.extend(plotter_figures(&dir)?);
    bar.set_message("animated models");
    written.extend(animated_figures(&dir)?);
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

/// The plotter section: for each of [`crate::gallery::PLOTTER_SUBJECTS`], the SVG that
/// `npr render --effect hatching-pen --svg` writes (A4, 0.3 mm pen, from the 640×480
/// view), its rasterisation by resvg at one dot per view pixel (cropped to the view), the
/// raster hatching of the same view, and the two side by side.
fn plotter_figures(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    use crate::bench::plotter::{SIZE, pen_preset, rasterise, trace};
    let ctx = npr_gpu::GpuContext::new()?;
    let mut written = Vec::new();
    for name in crate::gallery::PLOTTER_SUBJECTS {
        let model = npr_app::model::Model::load(
            &project_root().join(format!("fixtures/meshes/{name}.obj")),
        )?;
        let t = trace(&ctx, model, pen_preset())?;
        let (scale, origin) = t.page.fit(SIZE);
        let pixmap = rasterise(&t.svg, &t.page, 1.0 / scale)?;
        let (x0, y0) = (
            (origin[0] / scale).round() as u32,
            (origin[1] / scale).round() as u32,
        );
        let svg_png = image::RgbaImage::from_fn(SIZE.0, SIZE.1, |x, y| {
            let p = pixmap.pixel(x + x0, y + y0);
            let v = p.map_or(255, |p| p.red());
            image::Rgba([v, v, v, 255])
        });
        let svg_path = dir.join(format!("plotter-{name}.svg"));
        std::fs::write(&svg_path, &t.svg)?;
        written.push(svg_path);
        let files = [
            (format!("plotter-{name}-svg.png"), svg_png.clone()),
            (format!("plotter-{name}-raster.png"), t.raster.clone()),
            (
                format!("plotter-{name}.png"),
                npr_gpu::figures::row(&[svg_png, t.raster]),
            ),
        ];
        for (file, img) in files {
            let path = dir.join(file);
            img.save(&path)?;
            written.push(path);
        }
    }
    Ok(written)
}

/// The animated section: the Fox's Walk clip in each of
/// [`crate::gallery::ANIMATED_EFFECTS`], 24 frames at 30 fps with the camera still, as
/// `npr render --animation Walk --frames 24 --gif` writes it, and four of its frames side by
/// side.
fn animated_figures(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    use npr_app::animation::{Animated, ClipChoice, Playback, resolve_clip};
    let ctx = npr_gpu::GpuContext::new()?;
    let fox = npr_app::model::Model::load(&project_root().join("fixtures/meshes/Fox.glb"))?;
    let clip = resolve_clip(&fox, &ClipChoice::Name("Walk".into()))?;
    let animated = Animated::new(fox, clip, Playback::default())?;
    let mut written = Vec::new();
    for effect in crate::gallery::ANIMATED_EFFECTS {
        let mut preset = npr_app::preset::Preset {
            effect: npr_app::preset::Effect::from_name(effect)
                .ok_or_else(|| anyhow::anyhow!("no effect {effect}"))?,
            ..npr_app::preset::Preset::default()
        };
        preset.output.width = 400;
        preset.output.height = 300;
        let mut frames = Vec::new();
        npr_app::render::render_clip_frames(
            &ctx,
            &animated,
            &preset,
            (24, false),
            &mut |_, img, _| {
                frames.push(img);
                Ok(())
            },
        )?;
        let gif = dir.join(format!("animated-fox-{effect}.gif"));
        npr_app::output::save_gif(&gif, &frames, 33)?;
        written.push(gif);
        let strip: Vec<image::RgbaImage> = frames.iter().step_by(6).cloned().collect();
        let png = dir.join(format!("animated-fox-{effect}-strip.png"));
        npr_gpu::figures::row(&strip).save(&png)?;
        written.push(png);
    }
    Ok(written)
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
