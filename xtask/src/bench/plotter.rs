//! `cargo xtask bench plotter [--mesh PATH]...`: the pen plotter's SVG against the tone it
//! should draw. Each model is hatched at 640 × 480 (pen style, default preset), traced
//! into an A4 SVG, and the SVG rasterised at 300 dpi by resvg (an independent renderer).
//! Tone error: the ink of the SVG, averaged over each view pixel and blurred over 16 view
//! pixels (about the widest pen spacing), against `1 − tone` of the G-buffer, on the
//! object's pixels; the raster hatching's own ink, blurred alike, is the row to beat, and
//! `ink_vs_raster` is the mean absolute difference of the two blurred inks. Pen-up travel
//! is between strokes of a layer; the plot time is at 25 mm/s drawing, 80 mm/s travel.
//! `trace_ms` is the G-buffer readback and the trace, one core. vpype (see
//! [`super::vpype`]) reads each SVG, must see its three layers, and sorts it with its own
//! `linesort --two-opt`: `travel_vs_vpype` is our pen-up travel over what that reaches, both
//! measured by vpype's `stat`.

use super::table::{Cell, Table, emit};
use npr_app::engine::Renderer;
use npr_app::model::Model;
use npr_app::preset::{Effect, Preset};
use npr_app::view::View;
use npr_hatching::pen::{Page, page_layers, plot_stats, to_svg};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The view size traced.
pub const SIZE: (u32, u32) = (640, 480);
/// Rasterisation resolution of the SVG, dots per mm (300 dpi).
const DOTS_PER_MM: f32 = 300.0 / 25.4;
/// Blur width in view pixels.
const BLUR: usize = 16;

/// Runs the bench on the fixtures' bunny and Spot, and on `meshes`.
pub fn run(meshes: &[PathBuf], json: Option<&Path>) -> anyhow::Result<()> {
    let root = crate::project_root();
    let mut paths = vec![
        root.join("fixtures/meshes/stanford-bunny.obj"),
        root.join("fixtures/meshes/spot.obj"),
    ];
    paths.extend(meshes.iter().cloned());
    let ctx = npr_gpu::GpuContext::new()?;
    let mut table = Table::new(
        &format!(
            "plotter: pen strokes on A4 from a 640×480 view (adapter {})",
            ctx.adapter.get_info().name
        ),
        &[
            "mesh",
            "strokes",
            "length_mm",
            "travel_share",
            "short_stroke_share",
            "plot_min",
            "tone_error_svg",
            "tone_error_raster",
            "ink_vs_raster",
            "trace_ms",
            "vpype_travel_share",
            "travel_vs_vpype",
        ],
    );
    let vpype = super::vpype::find_or_install();
    let bar = super::progress(paths.len() as u64, "plotter");
    for path in &paths {
        table.push(row(&ctx, path, vpype.as_deref())?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    emit(&[table], json)
}

/// A model hatched at [`SIZE`] with the default pen preset and traced onto an A4 page.
pub struct Traced {
    /// The preset drawn.
    pub preset: Preset,
    /// The raster hatching.
    pub raster: image::RgbaImage,
    /// The page the SVG is laid out on.
    pub page: Page,
    /// The pen drawing, in view pixels.
    pub drawing: npr_hatching::pen::PenDrawing,
    /// The SVG.
    pub svg: String,
    /// The G-buffer's tone on each view pixel, and which pixels the object covers.
    pub tone: Vec<f32>,
    /// Which view pixels the object covers.
    pub mask: Vec<bool>,
    /// The readback and the trace, ms.
    pub trace_ms: f64,
}

/// The default preset in the pen style at [`SIZE`].
pub fn pen_preset() -> Preset {
    let mut preset = Preset {
        effect: Effect::HatchingPen,
        ..Preset::default()
    };
    preset.output.width = SIZE.0;
    preset.output.height = SIZE.1;
    preset
}

/// Hatches `model` with `preset` (a hatching effect) and traces it onto A4 as `npr
/// render --svg` does (see [`Traced`]).
///
/// # Errors
/// GPU or technique errors.
pub fn trace(ctx: &npr_gpu::GpuContext, model: Model, preset: Preset) -> anyhow::Result<Traced> {
    let size = (preset.output.width, preset.output.height);
    let view = View::new(&preset, &model.framing, size, 0.0);
    let mut renderer = Renderer::new(ctx, model, size)?;
    renderer.render(&ctx.device, &ctx.queue, &preset, &view)?;
    let raster = renderer.read(&ctx.device, &ctx.queue)?;
    let page = Page::default();
    let started = Instant::now();
    let drawing = renderer
        .pen_drawing(
            &ctx.device,
            &ctx.queue,
            &preset,
            &view,
            (page.pen_px(size), page.fit(size).0),
        )?
        .unwrap_or_default();
    let trace_ms = started.elapsed().as_secs_f64() * 1e3;
    let svg = to_svg(&drawing, &page)?;
    let inputs = renderer
        .hatch_inputs(&ctx.device, &ctx.queue)?
        .ok_or_else(|| anyhow::anyhow!("no hatched frame"))?;
    let mask = renderer
        .hatch_coverage(&ctx.device, &ctx.queue)?
        .unwrap_or_default();
    Ok(Traced {
        preset,
        raster,
        page,
        drawing,
        svg,
        tone: inputs.tone().to_vec(),
        mask,
        trace_ms,
    })
}

/// One model's row.
fn row(ctx: &npr_gpu::GpuContext, path: &Path, vpype: Option<&Path>) -> anyhow::Result<Vec<Cell>> {
    let model = Model::load(path)?;
    let name = model.name.clone();
    let t = trace(ctx, model, pen_preset())?;
    let vpype_cells = match vpype {
        Some(exe) => {
            let dir = crate::cargo::target_dir().join("bench-plotter");
            std::fs::create_dir_all(&dir)?;
            let file = dir.join(format!("{name}.svg"));
            std::fs::write(&file, &t.svg)?;
            let ours = super::vpype::stat(exe, &file, false)?;
            let sorted = super::vpype::stat(exe, &file, true)?;
            [
                Cell::Num(sorted.pen_up / sorted.length.max(1e-9), 3),
                Cell::Num(ours.pen_up / sorted.pen_up.max(1e-9), 3),
            ]
        }
        None => [Cell::Empty, Cell::Empty],
    };
    let (scale, origin) = t.page.fit(SIZE);
    let stats = plot_stats(&page_layers(&t.drawing, &t.page));
    let target: Vec<f32> = t.tone.iter().map(|t| 1.0 - t).collect();
    let svg_ink = svg_ink(&t.svg, &t.page, (scale, origin))?;
    let [ink, paper] = [t.preset.hatching.ink, t.preset.hatching.paper].map(luma);
    let raster_ink: Vec<f32> = t
        .raster
        .pixels()
        .map(|p| {
            let l = luma([p[0], p[1], p[2]].map(srgb_to_linear));
            ((paper - l) / (paper - ink).max(1e-3)).clamp(0.0, 1.0)
        })
        .collect();
    let (svg_b, raster_b, target_b) = (blur(&svg_ink), blur(&raster_ink), blur(&target));
    let mask = &t.mask;
    let on: Vec<usize> = (0..mask.len()).filter(|&i| mask[i]).collect();
    let mean = |f: &dyn Fn(usize) -> f32| {
        on.iter().map(|&i| f64::from(f(i))).sum::<f64>() / on.len().max(1) as f64
    };
    Ok([
        name.into(),
        stats.strokes.into(),
        Cell::Num(stats.draw_mm, 0),
        Cell::Num(stats.travel_mm / stats.draw_mm.max(1e-9), 3),
        Cell::Num(stats.short_strokes as f64 / stats.strokes.max(1) as f64, 3),
        Cell::Num(stats.seconds(25.0, 80.0) / 60.0, 1),
        Cell::Num(mean(&|i| (svg_b[i] - target_b[i]).abs()), 3),
        Cell::Num(mean(&|i| (raster_b[i] - target_b[i]).abs()), 3),
        Cell::Num(mean(&|i| (svg_b[i] - raster_b[i]).abs()), 3),
        Cell::Num(t.trace_ms, 0),
    ]
    .into_iter()
    .chain(vpype_cells)
    .collect())
}

/// The SVG rasterised by resvg on white at `dots_per_mm`.
///
/// # Errors
/// An SVG resvg cannot read, or a page too large for a pixmap.
pub fn rasterise(
    svg: &str,
    page: &Page,
    dots_per_mm: f32,
) -> anyhow::Result<resvg::tiny_skia::Pixmap> {
    use resvg::{tiny_skia, usvg};
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default())?;
    let (pw, ph) = page.oriented(SIZE);
    let (w, h) = (
        (pw * dots_per_mm).ceil() as u32,
        (ph * dots_per_mm).ceil() as u32,
    );
    let mut pixmap =
        tiny_skia::Pixmap::new(w, h).ok_or_else(|| anyhow::anyhow!("no {w}×{h} pixmap"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let fit = w as f32 / tree.size().width();
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(fit, fit),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

/// The SVG's ink (0 paper, 1 black) averaged over each view pixel, rasterised by resvg at
/// [`DOTS_PER_MM`].
fn svg_ink(svg: &str, page: &Page, (scale, origin): (f32, [f32; 2])) -> anyhow::Result<Vec<f32>> {
    let pixmap = rasterise(svg, page, DOTS_PER_MM)?;
    let (w, h) = (pixmap.width(), pixmap.height());
    let dots_per_px = scale * DOTS_PER_MM;
    let (vw, vh) = (SIZE.0 as usize, SIZE.1 as usize);
    let mut ink = vec![0.0f32; vw * vh];
    for (i, v) in ink.iter_mut().enumerate() {
        let (x, y) = ((i % vw) as f32, (i / vw) as f32);
        let x0 = ((origin[0] + scale * x) * DOTS_PER_MM) as u32;
        let y0 = ((origin[1] + scale * y) * DOTS_PER_MM) as u32;
        let n = dots_per_px.ceil().max(1.0) as u32;
        let (mut sum, mut count) = (0.0f32, 0u32);
        for yy in y0..(y0 + n).min(h) {
            for xx in x0..(x0 + n).min(w) {
                if let Some(p) = pixmap.pixel(xx, yy) {
                    sum += 1.0 - srgb_to_linear(p.red());
                    count += 1;
                }
            }
        }
        *v = sum / count.max(1) as f32;
    }
    Ok(ink)
}

/// A box blur of [`BLUR`] view pixels, rows then columns (edges clamped).
fn blur(img: &[f32]) -> Vec<f32> {
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let r = BLUR / 2;
    let pass = |src: &[f32], horizontal: bool| -> Vec<f32> {
        (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let (lo, hi, at): (usize, usize, &dyn Fn(usize) -> usize) = if horizontal {
                    (x.saturating_sub(r), (x + r).min(w - 1), &|k| y * w + k)
                } else {
                    (y.saturating_sub(r), (y + r).min(h - 1), &|k| k * w + x)
                };
                (lo..=hi).map(|k| src[at(k)]).sum::<f32>() / (hi - lo + 1) as f32
            })
            .collect()
    };
    pass(&pass(img, true), false)
}

/// Rec. 709 luma of linear RGB.
fn luma(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// An 8-bit sRGB value as linear reflectance.
fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
