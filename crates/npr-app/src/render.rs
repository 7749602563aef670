//! `npr render MODEL`: one image, a turntable of frames, or a GIF of any effect on a
//! user's model, with per-frame statistics as JSON. Outputs are written all-or-nothing:
//! a failure at frame 57 of 60 leaves no frame files and no GIF behind.

use crate::engine::{FrameStats, Renderer};
use crate::model::Model;
use crate::preset::{Effect, Preset};
use crate::view::View;
use crate::{AppError, output, progress};
use std::path::{Path, PathBuf};

/// Arguments of `npr render`.
#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// The model: OBJ, PLY (ASCII or binary) or glTF (.gltf/.glb).
    pub model: PathBuf,
    /// The effect (overrides the preset's).
    #[arg(long, value_enum)]
    pub effect: Option<Effect>,
    /// A preset TOML with every parameter (see fixtures/presets/example.toml).
    #[arg(long)]
    pub preset: Option<PathBuf>,
    /// Image size WxH (overrides the preset's).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Output image (PNG), or GIF with --gif. Turntable frames without --gif are written
    /// beside it as STEM_0000.png, STEM_0001.png, ...
    #[arg(long, default_value = "out.png")]
    pub out: PathBuf,
    /// Render N frames of the model turning 360° about the vertical axis.
    #[arg(long, value_name = "N")]
    pub turntable: Option<u32>,
    /// Write the turntable as one looping GIF at --out.
    #[arg(long)]
    pub gif: bool,
    /// Write per-frame statistics (setup time, highlight and receiver counts, warp PSNR)
    /// as a JSON array.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Draw the hatching as vector strokes for a pen plotter into this SVG instead of a
    /// PNG (with --turntable: STEM_0000.svg, ...). Needs a hatching effect.
    #[arg(long, value_name = "OUT.svg")]
    pub svg: Option<PathBuf>,
    /// The SVG's page: a4, a3, letter or WxHmm (e.g. 200x150mm); 10 mm margins.
    #[arg(long, default_value = "a4")]
    pub page: String,
    /// The pen's width in mm (the SVG's stroke-width).
    #[arg(long, default_value_t = 0.3)]
    pub pen_mm: f32,
    /// The glTF clip to play: its name, its index, or `none` for the bind pose. Default:
    /// the model's first clip.
    #[arg(long, value_name = "NAME|INDEX|none")]
    pub animation: Option<String>,
    /// The moment shown (the first frame's), seconds into the clip (overrides the
    /// preset's `[animation] time`, default 0).
    #[arg(long)]
    pub time: Option<f32>,
    /// Render N frames of the clip with the camera still (numbered PNGs, or a GIF with
    /// --gif).
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,
    /// Frames per second of the clip, for --frames and --turntable.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f32,
    /// Hold the clip's last pose past its end instead of looping.
    #[arg(long)]
    pub no_loop: bool,
}

/// Parses `WxH`.
///
/// # Errors
/// A sentence saying what is wrong.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH (e.g. 800x600), got '{s}'"))?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| (1..=16384).contains(&n))
            .ok_or_else(|| format!("each side must be an integer in 1..=16384, got '{s}'"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// What `npr render` did.
#[derive(Debug)]
pub struct RenderSummary {
    /// Files written.
    pub written: Vec<PathBuf>,
    /// Per-frame statistics.
    pub stats: Vec<FrameStats>,
    /// The loader's notes on the model.
    pub notes: Vec<String>,
}

/// The preset a render uses: the file's (or the default), with the command line's
/// overrides.
///
/// # Errors
/// As [`Preset::load`], or [`AppError::Usage`] for inconsistent flags.
pub fn resolve_preset(args: &RenderArgs) -> Result<Preset, AppError> {
    let mut preset = match &args.preset {
        Some(p) => Preset::load(p)?,
        None => Preset::default(),
    };
    if let Some(e) = args.effect {
        preset.effect = e;
    }
    if let Some((w, h)) = args.size {
        preset.output.width = w;
        preset.output.height = h;
    }
    if args.turntable == Some(0) {
        return Err(AppError::Usage("--turntable needs at least 1 frame".into()));
    }
    if args.frames.is_some() && args.turntable.is_some() {
        return Err(AppError::Usage(
            "--frames and --turntable do not go together (with a clip, --turntable plays it \
             during the turn)"
                .into(),
        ));
    }
    if args.frames == Some(0) {
        return Err(AppError::Usage("--frames needs at least 1 frame".into()));
    }
    if args.gif && args.turntable.is_none() && args.frames.is_none() {
        return Err(AppError::Usage(
            "--gif needs --turntable N or --frames N".into(),
        ));
    }
    if args.svg.is_some() {
        if !preset.effect.is_hatching() {
            return Err(AppError::Usage(format!(
                "--svg draws the hatching: use --effect hatching-pen or hatching-pencil (the \
                 effect is {})",
                preset.effect.name()
            )));
        }
        if args.gif {
            return Err(AppError::Usage("--svg and --gif do not go together".into()));
        }
    }
    Ok(preset)
}

/// The page and pen of `--svg`, checked.
///
/// # Errors
/// [`AppError::Hatching`] for an unknown page, a page smaller than its margins or a pen
/// width that is not above 0.
pub fn resolve_page(args: &RenderArgs) -> Result<npr_hatching::pen::Page, AppError> {
    let page = npr_hatching::pen::Page {
        pen_mm: args.pen_mm,
        ..npr_hatching::pen::Page::named(&args.page)?
    };
    page.validate()?;
    Ok(page)
}

/// Renders `frames` turntable frames of a hatching preset and hands each frame's SVG for
/// a pen plotter to `sink` (frame index, SVG text, stats).
///
/// # Errors
/// GPU or technique errors, or what `sink` returns.
pub fn render_svgs(
    ctx: &npr_gpu::GpuContext,
    model: Model,
    preset: &Preset,
    (frames, page): (u32, &npr_hatching::pen::Page),
    mut sink: impl FnMut(usize, String, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let framing = model.framing;
    let mut renderer = Renderer::new(ctx, model, size)?;
    let bar = progress::bar(u64::from(frames), "pen strokes");
    let mm_per_px = page.fit(size).0;
    let mut stats = Vec::new();
    for i in 0..frames {
        let turn = 360.0 * i as f32 / frames as f32;
        let view = View::new(preset, &framing, size, turn);
        let s = renderer.render(&ctx.device, &ctx.queue, preset, &view)?;
        let drawing = renderer
            .pen_drawing(
                &ctx.device,
                &ctx.queue,
                preset,
                &view,
                (page.pen_px(size), mm_per_px),
            )?
            .unwrap_or_default();
        let svg = npr_hatching::pen::to_svg(&drawing, page)?;
        sink(i as usize, svg, &s)?;
        stats.push(s);
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// Renders `frames` frames of `animated`'s clip with `preset`, the camera still (or turning
/// once over the frames with `turntable`), and hands each image to `sink`. Each frame's
/// model is the posed mesh ([`Renderer::set_pose`]), so curvature, highlights, stroke
/// directions and outlines are computed on the posed surface, and the highlights keep
/// their ids from frame to frame. The warp effect warps the frames between references
/// posed at their own moments ([`crate::engine::render_clip_warp_frames`]).
///
/// # Errors
/// GPU or technique errors, or what `sink` returns.
pub fn render_clip_frames(
    ctx: &npr_gpu::GpuContext,
    animated: &crate::animation::Animated,
    preset: &Preset,
    (frames, turntable): (u32, bool),
    sink: &mut dyn FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    if preset.effect == Effect::Warp {
        return crate::engine::render_clip_warp_frames(
            ctx,
            animated,
            preset,
            (frames, turntable),
            sink,
        );
    }
    let size = (preset.output.width, preset.output.height);
    let framing = animated.framing();
    let mut renderer = Renderer::new(ctx, animated.frame(0), size)?;
    let bar = progress::bar(u64::from(frames), preset.effect.name());
    let mut stats = Vec::new();
    let which = preset.hatching.direction;
    let carried = (preset.effect.is_hatching()
        && preset.animation.geometry == crate::preset::PoseGeometry::Carried)
        .then(|| animated.rest_directions(which));
    for i in 0..frames as usize {
        if i > 0 || carried.is_some() || preset.animation.posing == crate::preset::Posing::Gpu {
            crate::animation::set_pose_at(
                &mut renderer,
                (&ctx.device, &ctx.queue),
                animated,
                animated.time_of(i),
                preset,
                carried.as_deref(),
            )?;
        }
        let turn = if turntable {
            360.0 * i as f32 / frames as f32
        } else {
            0.0
        };
        let view = View::new(preset, &framing, size, turn);
        let s = renderer.render(&ctx.device, &ctx.queue, preset, &view)?;
        let image = renderer.read(&ctx.device, &ctx.queue)?;
        sink(i, image, &s)?;
        stats.push(s);
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// Renders `frames` turntable frames of `model` with `preset` and hands each image to
/// `sink` (frame index, image, stats).
///
/// # Errors
/// GPU or technique errors, or what `sink` returns.
pub fn render_frames(
    ctx: &npr_gpu::GpuContext,
    model: Model,
    preset: &Preset,
    frames: u32,
    mut sink: impl FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>,
) -> Result<Vec<FrameStats>, AppError> {
    let size = (preset.output.width, preset.output.height);
    let framing = model.framing;
    if preset.effect == Effect::Warp {
        return crate::engine::render_warp_frames(ctx, model, preset, frames, sink);
    }
    let mut renderer = Renderer::new(ctx, model, size)?;
    let bar = progress::bar(u64::from(frames), preset.effect.name());
    let mut stats = Vec::new();
    for i in 0..frames {
        let turn = 360.0 * i as f32 / frames as f32;
        let view = View::new(preset, &framing, size, turn);
        let s = renderer.render(&ctx.device, &ctx.queue, preset, &view)?;
        let image = renderer.read(&ctx.device, &ctx.queue)?;
        sink(i as usize, image, &s)?;
        stats.push(s);
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// Runs `npr render`.
///
/// # Errors
/// Any [`AppError`]; nothing is written then.
pub fn run(args: &RenderArgs) -> Result<RenderSummary, AppError> {
    let preset = resolve_preset(args)?;
    let spin = progress::spinner(&format!("loading {}", args.model.display()));
    let model = Model::load(&args.model)?;
    spin.finish_and_clear();
    let notes = model.notes.clone();
    let a = &preset.animation;
    let clip = crate::animation::resolve_clip(
        &model,
        &crate::animation::ClipChoice::parse(Some(args.animation.as_deref().unwrap_or(&a.clip))),
    )?;
    let playback = crate::animation::Playback {
        time: args.time.unwrap_or(a.time),
        fps: args.fps,
        speed: a.speed,
        looped: a.looped && !args.no_loop,
    };
    let animated = crate::animation::Animated::new(model, clip, playback)?;
    let frames = args.turntable.or(args.frames).unwrap_or(1);
    let moving = animated.plays() && frames > 1;
    if moving && args.svg.is_some() {
        return Err(AppError::Usage(
            "a playing clip is not drawn as SVG frames yet: pick one moment (--time) or the \
             bind pose (--animation none)"
                .to_string(),
        ));
    }
    let ctx = npr_gpu::GpuContext::new()?;
    let turntable = args.turntable.is_some();
    let draw =
        |sink: &mut dyn FnMut(usize, image::RgbaImage, &FrameStats) -> Result<(), AppError>| {
            if moving {
                render_clip_frames(&ctx, &animated, &preset, (frames, turntable), sink)
            } else {
                render_frames(&ctx, animated.frame(0), &preset, frames, sink)
            }
        };
    let gif_delay_ms = if args.frames.is_some() {
        (1000.0 / args.fps).round().clamp(10.0, 10_000.0) as u32
    } else {
        40
    };
    let mut written = Vec::new();
    let stats = if let Some(svg) = &args.svg {
        let page = resolve_page(args)?;
        // Every SVG goes to a temporary name and is renamed only once all exist.
        let mut temps: Vec<(PathBuf, PathBuf)> = Vec::new();
        let result = render_svgs(
            &ctx,
            animated.frame(0),
            &preset,
            (frames, &page),
            |i, text, _| {
                let path = if frames > 1 {
                    output::frame_path(svg, i).with_extension("svg")
                } else {
                    svg.clone()
                };
                let tmp = output::temp_path(&path);
                std::fs::write(&tmp, text.as_bytes()).map_err(|e| AppError::io(&tmp, e))?;
                temps.push((tmp, path));
                Ok(())
            },
        );
        let stats = commit_temps(result, &temps)?;
        written.extend(temps.into_iter().map(|(_, p)| p));
        stats
    } else if args.gif {
        let mut images = Vec::new();
        let stats = draw(&mut |_, img, _| {
            images.push(img);
            Ok(())
        })?;
        output::save_gif(&args.out, &images, gif_delay_ms)?;
        written.push(args.out.clone());
        stats
    } else if frames > 1 {
        // Frames go to temporary names and are renamed only once all exist.
        let mut temps: Vec<(PathBuf, PathBuf)> = Vec::new();
        let result = draw(&mut |i, img, _| {
            let path = output::frame_path(&args.out, i);
            let tmp = output::temp_path(&path);
            output::save_png(&tmp, &img)?;
            temps.push((tmp, path));
            Ok(())
        });
        let stats = commit_temps(result, &temps)?;
        written.extend(temps.into_iter().map(|(_, p)| p));
        stats
    } else {
        let mut image = None;
        let stats = draw(&mut |_, img, _| {
            image = Some(img);
            Ok(())
        })?;
        if let Some(img) = image {
            output::save_png(&args.out, &img)?;
            written.push(args.out.clone());
        }
        stats
    };
    if let Some(json) = &args.json {
        write_stats(json, &stats)?;
        written.push(json.clone());
    }
    Ok(RenderSummary {
        written,
        stats,
        notes,
    })
}

/// Renames every temporary file to its final name when `result` is a success; removes
/// them all otherwise (or when a rename fails), so that nothing is left half written.
///
/// # Errors
/// `result`'s error, or [`AppError::Io`] for a failed rename.
fn commit_temps<T>(
    result: Result<T, AppError>,
    temps: &[(PathBuf, PathBuf)],
) -> Result<T, AppError> {
    let finish = result.and_then(|stats| {
        for (tmp, path) in temps {
            std::fs::rename(tmp, path).map_err(|e| AppError::io(path, e))?;
        }
        Ok(stats)
    });
    if finish.is_err() {
        for (tmp, _) in temps {
            let _ = std::fs::remove_file(tmp);
        }
    }
    finish
}

/// Writes per-frame statistics as a JSON array, atomically.
///
/// # Errors
/// [`AppError::Io`] or [`AppError::Encode`].
pub fn write_stats(path: &Path, stats: &[FrameStats]) -> Result<(), AppError> {
    let text = serde_json::to_string_pretty(stats).map_err(|e| AppError::Encode {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    output::write_atomic(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_say_why() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        for bad in ["800", "0x600", "axb", "800x99999", "-1x5"] {
            let e = parse_size(bad).unwrap_err();
            assert!(e.contains(bad), "{e}");
        }
    }
}
