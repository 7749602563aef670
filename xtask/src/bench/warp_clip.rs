//! `cargo xtask bench warp`'s table of moving models: the warp of a playing clip (the
//! proxy posed with the model, each reference projected through the proxy's pose at its
//! own moment: `npr_warp::deform`) beside the same model's rigid turntable, in one run,
//! through `npr render`'s own loop (`npr_app::engine::render_clip_warp_frames` and
//! `render_warp_frames`: a reference every k frames, each warped frame against the full
//! render of its pose and view).
//!
//! Rows per model: `clip` (camera still, the clip at 30 fps), `clip + turn` (the clip
//! playing during one camera turn) and `rigid turn` (the first frame's pose, the same
//! turn). `psnr_vs_rigid_db` is the row's mean PSNR minus the rigid turn's.

use super::table::{Cell, Table};
use npr_app::animation::{Animated, ClipChoice, Playback, resolve_clip};
use npr_app::engine::{FrameStats, render_clip_warp_frames, render_warp_frames};
use npr_app::model::Model;
use npr_app::preset::{Effect, Preset};
use std::path::{Path, PathBuf};

/// Frames of each row: one camera turn of 3° a frame; 4 s of the clip at 30 fps.
const FRAMES: u32 = 120;

/// The models of the table when `--mesh` names none.
pub fn default_models() -> Vec<PathBuf> {
    vec![crate::fixture_mesh("Fox.glb")]
}

/// The table's empty shape.
fn table() -> Table {
    Table::new(
        "Warping a moving model: the clip (proxy posed with the model) beside the rigid turntable, ours, one run",
        &[
            "mesh",
            "clip",
            "motion",
            "frames",
            "k",
            "proxy_triangles",
            "warped_frames",
            "psnr_mean_db",
            "psnr_worst_db",
            "psnr_vs_rigid_db",
            "adapter",
        ],
    )
}

/// Mean and worst PSNR of the warped frames, and how many there are.
fn psnr(stats: &[FrameStats]) -> (f64, f64, usize) {
    let p: Vec<f64> = stats.iter().filter_map(|s| s.psnr_db).collect();
    let mean = p.iter().sum::<f64>() / p.len().max(1) as f64;
    let worst = p.iter().copied().fold(f64::INFINITY, f64::min);
    (mean, worst, p.len())
}

/// The table for `models` (the Fox fixture when none), each playing `clip` (its first
/// clip when `None`).
///
/// # Errors
/// A model that does not load, a clip it lacks, GPU errors.
pub fn run(
    ctx: &npr_gpu::GpuContext,
    models: &[PathBuf],
    clip: Option<&str>,
) -> anyhow::Result<Table> {
    let adapter = ctx.adapter.get_info().name;
    let preset = Preset {
        effect: Effect::Warp,
        ..Preset::default()
    };
    let models = if models.is_empty() {
        default_models()
    } else {
        models.to_vec()
    };
    let mut out = table();
    for path in &models {
        let rows = model_rows(ctx, path, clip, &preset)?;
        let rigid_mean = rows.last().map_or(f64::NAN, |r| r.1.0);
        for (motion, (mean, worst, warped), clip_name, proxy) in &rows {
            out.push(vec![
                Cell::Text(name_of(path)),
                Cell::Text(clip_name.clone()),
                Cell::Text(motion.to_string()),
                Cell::Int(i64::from(FRAMES)),
                Cell::Int(i64::from(preset.warp.k)),
                Cell::Int(*proxy as i64),
                Cell::Int(*warped as i64),
                Cell::Num(*mean, 2),
                Cell::Num(*worst, 2),
                Cell::Num(mean - rigid_mean, 2),
                Cell::Text(adapter.clone()),
            ]);
        }
    }
    Ok(out)
}

/// One row's motion, PSNR figures, clip name and proxy size.
type Row = (&'static str, (f64, f64, usize), String, usize);

fn name_of(path: &Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// The three rows of one model: the clip, the clip during a turn, the rigid turn (last);
/// the rigid turn alone for a model without a clip.
fn model_rows(
    ctx: &npr_gpu::GpuContext,
    path: &Path,
    clip: Option<&str>,
    preset: &Preset,
) -> anyhow::Result<Vec<Row>> {
    let model = Model::load(path)?;
    let index = resolve_clip(&model, &ClipChoice::parse(clip))?;
    let clip_name = match (model.rig.as_ref(), index) {
        (Some(rig), Some(i)) => rig.clips()[i]
            .name()
            .map_or_else(|| i.to_string(), str::to_string),
        _ => "-".to_string(),
    };
    let animated = Animated::new(model, index, Playback::default())?;
    let mut proxy = 0;
    let mut run = |motion: &'static str| -> anyhow::Result<Row> {
        println!("bench warp: {} {clip_name}, {motion}", path.display());
        let none = |_: usize, _: image::RgbaImage, _: &FrameStats| Ok(());
        let stats = match motion {
            "clip" => render_clip_warp_frames(ctx, &animated, preset, (FRAMES, false), none)?,
            "clip + turn" => render_clip_warp_frames(ctx, &animated, preset, (FRAMES, true), none)?,
            _ => render_warp_frames(ctx, animated.frame(0), preset, FRAMES, none)?,
        };
        proxy = stats
            .iter()
            .find(|s| s.warped)
            .map_or(proxy, |s| s.triangles);
        Ok((motion, psnr(&stats), clip_name.clone(), proxy))
    };
    if index.is_none() {
        return Ok(vec![run("rigid turn")?]);
    }
    Ok(vec![run("clip")?, run("clip + turn")?, run("rigid turn")?])
}
