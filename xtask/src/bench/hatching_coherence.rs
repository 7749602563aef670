//! `cargo xtask bench hatching-coherence [--mesh PATH]... [--json PATH]`: does the hatching
//! move with the surface? The paper's image-space strokes stay on the screen
//! while the surface slides beneath them (the "shower-door" effect its §5 names as a
//! limit); `npr_hatching::StrokeSpace::Surface` anchors them on the surface.
//!
//! Setup: 640×480, the object turning 1° per frame about the vertical axis while the
//! camera dollies in by 2× (distance halved) over 25 frames; pen TAM, default parameters.
//! Modes: `screen` (the paper), `surface` (coherent, the default), and
//! `surface-no-refresh` (surface anchors whose reference view is never re-taken: a
//! surface-anchored texture without any scale correction, the foil for
//! `density_change`).
//!
//! Per 32×32 tile lying wholly on the object, between consecutive frames:
//! - the pattern's displacement, by phase correlation of the two hatched frames
//!   (`npr_hatching::coherence::phase_correlation`, tiles with ink only);
//! - the surface's, the tile's mean screen-space motion, from the G-buffer of a rig whose
//!   anchors are re-taken every frame (so one anchor holds each pixel's surface point's
//!   position in the previous frame: reprojected positions).
//!
//! Columns: `sliding` = median |d_pattern − d_surface| / median |d_surface| (the paper's
//! method: about 1; 0 = strokes glued to the surface). `density_change` = |ρ_last / ρ_first
//! − 1| of the screen-space stroke density ρ (mean absolute ink change per pixel step,
//! `coherence::stroke_density`) over the object with its tone set constant (0.55), first
//! frame against last (the 2× dolly); `coverage_change` the same for the mean ink
//! coverage (which a magnified texture keeps, hence ρ as the density measure).
//! `flicker` = mean over tiles and frame pairs of the smaller of the mean absolute ink
//! change with the previous frame held still and with it warped by the surface motion
//! (bilinear): the change neither the screen nor the surface motion explains.
//! `flicker_vs_bunny` = flicker over the bunny's surface-mode flicker in the same run (the
//! bunny is always measured: with `--mesh` it is added first). `ink_coverage` = the mean
//! ink (0–1) over the object's pixels, all frames; `ink_vs_screen` that over the screen
//! mode's on the same mesh (a lower flicker bought by thinner ink does not count).
//! `flicker_vs_bunny_same_tone` compares at equal tone: each tile's flicker against the
//! bunny's surface-mode mean over its tiles of the same tone (tenths of the tone range),
//! since a tile's flicker grows with its ink (a dark tile holds more strokes to change).
//! A second table gives each mesh's surface-mode flicker per tone bin and the share of its
//! tiles at mid tones (0.2–0.6, where flicker peaks on every mesh).
//! Targets: sliding ≤ 0.25, density_change ≤ 0.25, flicker ≤ 1.5 × the paper mode's;
//! on the hard-edged parts (`npr_geometry::generate::cad_parts`, the wing nut, the
//! hammer and the flange of `fixtures/meshes`) the surface mode's `flicker_vs_bunny` ≤ 1 with
//! `ink_vs_screen` within 0.9–1.1.

use super::table::{Cell, Table, emit};
use glam::{Mat4, Vec3};
use npr_geometry::Mesh;
use npr_geometry::stats::median;
use npr_gpu::figures::framing_camera;
use npr_gpu::{Camera, GpuContext, GpuMesh};
use npr_hatching::coherence::{
    Rig, ink_image, phase_correlation, rig, sample_bilinear, stroke_density,
};
use npr_hatching::figures::{directions, knot};
use npr_hatching::{
    GBuffer, HatchInputs, ShadowLight, StrokeSpace, TamParams, TonalArtMap, hatch_image_gpu,
};
use std::path::{Path, PathBuf};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
/// Frames of the sequence (24 consecutive pairs).
pub const FRAMES: usize = 25;
const TILE: usize = 32;
/// The constant tone of the density measurement.
const DENSITY_TONE: f32 = 0.55;

/// One mode's measurements.
struct Measured {
    mode: &'static str,
    sliding: f64,
    density_change: f64,
    coverage_change: f64,
    flicker: f64,
    /// Mean ink coverage (0–1) over the object's pixels, all frames.
    ink: f64,
    /// Per tile and frame pair: the tile's mean tone and its flicker.
    tile_flicker: Vec<(f64, f64)>,
    tiles: usize,
}

/// The modes measured: name, stroke space, anchor period.
const MODES: [(&str, StrokeSpace, u32); 3] = [
    (
        "screen",
        StrokeSpace::Screen,
        npr_hatching::DEFAULT_ANCHOR_PERIOD,
    ),
    (
        "surface",
        StrokeSpace::Surface,
        npr_hatching::DEFAULT_ANCHOR_PERIOD,
    ),
    ("surface-no-refresh", StrokeSpace::Surface, u32::MAX),
];

/// The sequence's camera and object transform at frame `t` (of `FRAMES`): turning 1° per
/// frame, the camera moving from twice the framing distance to the framing distance.
pub fn pose(mesh: &Mesh, t: usize) -> (Camera, Mat4) {
    let (camera, world_from_object) = framing_camera(mesh, WIDTH as f32 / HEIGHT as f32);
    let s = 2.0f32.powf(1.0 - t as f32 / (FRAMES - 1) as f32);
    let camera = Camera::look_at(camera.eye * s, Vec3::ZERO, WIDTH as f32 / HEIGHT as f32);
    let turn = Mat4::from_rotation_y((t as f32).to_radians());
    (camera, turn * world_from_object)
}

/// The sequence's light (fixed in the world).
pub fn light() -> ShadowLight {
    ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 1.6, 1.2),
        center: Vec3::ZERO,
        radius: 1.05,
    }
}

/// What moves in a sequence: the object turning under a dollying camera (rigid), or a
/// clip's poses with camera and object still.
#[derive(Clone, Copy)]
enum Motion<'a> {
    /// [`pose`]: 1° per frame and the 2× dolly.
    Turntable,
    /// Frame `t` is `poses[t]` (posed mesh, its stroke directions), written into the
    /// uploaded mesh before it is drawn.
    Clip(&'a [(Mesh, Vec<Vec3>)]),
}

/// Renders frame `t` of the sequence with `rig`: the hatched image.
fn render(
    ctx: &GpuContext,
    rig: &mut Rig,
    (cpu_mesh, gpu_mesh): (&Mesh, &GpuMesh),
    motion: Motion<'_>,
    t: usize,
) -> anyhow::Result<image::RgbaImage> {
    let (camera, world_from_object) = match motion {
        Motion::Turntable => pose(cpu_mesh, t),
        Motion::Clip(poses) => {
            let (posed, directions) = &poses[t.min(poses.len() - 1)];
            gpu_mesh.write_vertices(&ctx.queue, posed)?;
            rig.frame
                .write_directions(&ctx.queue, &rig.object, directions)?;
            framing_camera(cpu_mesh, WIDTH as f32 / HEIGHT as f32)
        }
    };
    Ok(rig.render(ctx, &camera, &light(), world_from_object)?)
}

/// Per pixel of a frame: the previous position, whether it is on the surface, the tone.
type FrameMotion = (Vec<[f32; 2]>, Vec<bool>, Vec<f32>);

/// Per-pixel motion of frame `t` (rendered by the every-frame rig): each surface pixel's
/// position in the previous frame, the surface mask and the tone.
fn previous_positions(
    ctx: &GpuContext,
    gbuffer: &GBuffer,
    frame_index: u64,
) -> anyhow::Result<FrameMotion> {
    let inputs = gbuffer.read(&ctx.device, &ctx.queue)?;
    let mask = gbuffer.read_surface_mask(&ctx.device, &ctx.queue)?;
    // Period 1: the slot re-taken this frame is `frame_index % 2`; the other one holds the
    // previous frame's view.
    let newest_is_b = frame_index % 2 == 1;
    let prev = inputs
        .anchors()
        .unwrap_or_default()
        .iter()
        .map(|a| if newest_is_b { a.a } else { a.b })
        .collect();
    Ok((prev, mask, inputs.tone().to_vec()))
}

/// Stroke density and mean ink of the frame's G-buffer hatched at a constant tone.
fn density_at_constant_tone(
    ctx: &GpuContext,
    rig: &Rig,
    tam: &TonalArtMap,
) -> anyhow::Result<(f64, f64)> {
    let mut inputs: HatchInputs = rig.frame.gbuffer.read(&ctx.device, &ctx.queue)?;
    let mask = rig
        .frame
        .gbuffer
        .read_surface_mask(&ctx.device, &ctx.queue)?;
    inputs.set_tone_where(DENSITY_TONE, |i| mask.get(i).copied().unwrap_or(false));
    let image = hatch_image_gpu(&ctx.device, &ctx.queue, &inputs, tam, &rig.params)?;
    let ink = ink_image(&image);
    let rho = stroke_density(&ink, &mask, WIDTH as usize).unwrap_or(0.0);
    let (sum, n) = ink
        .iter()
        .zip(&mask)
        .filter(|(_, m)| **m)
        .fold((0.0f64, 0usize), |(s, n), (i, _)| {
            (s + f64::from(*i), n + 1)
        });
    Ok((f64::from(rho), sum / n.max(1) as f64))
}

/// The 32×32 tiles (top-left corners) lying wholly on the surface in both masks.
fn tiles(mask_a: &[bool], mask_b: &[bool]) -> Vec<(usize, usize)> {
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut out = Vec::new();
    for ty in (0..h - TILE + 1).step_by(TILE) {
        for tx in (0..w - TILE + 1).step_by(TILE) {
            let inside = (0..TILE).all(|y| {
                (0..TILE).all(|x| {
                    let i = (ty + y) * w + tx + x;
                    mask_a[i] && mask_b[i]
                })
            });
            if inside {
                out.push((tx, ty));
            }
        }
    }
    out
}

fn tile_of(img: &[f32], (tx, ty): (usize, usize)) -> Vec<f32> {
    let w = WIDTH as usize;
    (0..TILE * TILE)
        .map(|i| img[(ty + i / TILE) * w + tx + i % TILE])
        .collect()
}

/// Measures one mesh in every mode.
fn measure(
    ctx: &GpuContext,
    tam: &TonalArtMap,
    mesh: &Mesh,
    motion: Motion<'_>,
) -> anyhow::Result<Vec<Measured>> {
    let sequence = motion;
    let gpu_mesh = GpuMesh::upload(&ctx.device, mesh)?;
    let directions = directions(mesh);
    // Reprojection rig: anchors re-taken every frame.
    let size = (WIDTH, HEIGHT);
    let mut motion = rig(
        ctx,
        tam,
        (StrokeSpace::Surface, 1),
        (&gpu_mesh, &directions),
        size,
    )?;
    let mut prev_pos = Vec::with_capacity(FRAMES);
    let mut tones = Vec::with_capacity(FRAMES);
    let mut masks = Vec::with_capacity(FRAMES);
    for t in 0..FRAMES {
        render(ctx, &mut motion, (mesh, &gpu_mesh), sequence, t)?;
        let (p, m, tone) = previous_positions(ctx, &motion.frame.gbuffer, t as u64)?;
        prev_pos.push(p);
        masks.push(m);
        tones.push(tone);
    }
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut out = Vec::new();
    for (mode, space, period) in MODES {
        let mut r = rig(ctx, tam, (space, period), (&gpu_mesh, &directions), size)?;
        let mut inks = Vec::with_capacity(FRAMES);
        let (mut first, mut last) = ((0.0, 0.0), (0.0, 0.0));
        let mut ink = Vec::with_capacity(FRAMES);
        for t in 0..FRAMES {
            inks.push(ink_image(&render(
                ctx,
                &mut r,
                (mesh, &gpu_mesh),
                sequence,
                t,
            )?));
            ink.push(mean_on(&inks[t], &masks[t]));
            if t == 0 {
                first = density_at_constant_tone(ctx, &r, tam)?;
            }
            if t == FRAMES - 1 {
                last = density_at_constant_tone(ctx, &r, tam)?;
            }
        }
        let (mut errors, mut surface, mut flicker) = (Vec::new(), Vec::new(), Vec::new());
        let mut tile_flicker = Vec::new();
        for t in 1..FRAMES {
            let (a, b) = (&inks[t - 1], &inks[t]);
            for tile in tiles(&masks[t - 1], &masks[t]) {
                // Surface motion: mean of p − previous position over the tile.
                let (mut sx, mut sy) = (0.0f64, 0.0f64);
                let (mut still, mut warped) = (0.0f64, 0.0f64);
                for i in 0..TILE * TILE {
                    let (x, y) = (tile.0 + i % TILE, tile.1 + i / TILE);
                    let p = y * w + x;
                    let q = prev_pos[t][p];
                    sx += f64::from(x as f32 + 0.5 - q[0]);
                    sy += f64::from(y as f32 + 0.5 - q[1]);
                    still += f64::from((b[p] - a[p]).abs());
                    warped += f64::from((b[p] - sample_bilinear(a, w, h, q[0], q[1])).abs());
                }
                let n = (TILE * TILE) as f64;
                let d_surface = [sx / n, sy / n];
                flicker.push(still.min(warped) / n);
                let tone = mean_on(&tile_of(&tones[t], tile), &[true; TILE * TILE]);
                tile_flicker.push((tone, still.min(warped) / n));
                let Some(d) = phase_correlation(&tile_of(a, tile), &tile_of(b, tile), TILE) else {
                    continue;
                };
                let e = (f64::from(d[0]) - d_surface[0]).hypot(f64::from(d[1]) - d_surface[1]);
                errors.push(e);
                surface.push(d_surface[0].hypot(d_surface[1]));
            }
        }
        let ratio = |l: f64, f: f64| {
            if f > 0.0 {
                (l / f - 1.0).abs()
            } else {
                f64::NAN
            }
        };
        out.push(Measured {
            mode,
            sliding: median(errors.iter().copied()) / median(surface.iter().copied()).max(1e-9),
            // A still camera over a clip has no dolly to measure.
            density_change: match sequence {
                Motion::Turntable => ratio(last.0, first.0),
                Motion::Clip(_) => f64::NAN,
            },
            coverage_change: match sequence {
                Motion::Turntable => ratio(last.1, first.1),
                Motion::Clip(_) => f64::NAN,
            },
            flicker: flicker.iter().sum::<f64>() / flicker.len().max(1) as f64,
            ink: ink.iter().sum::<f64>() / ink.len().max(1) as f64,
            tile_flicker,
            tiles: errors.len(),
        });
    }
    Ok(out)
}

/// Tone bins of `flicker_vs_bunny_same_tone` (tiles by their mean tone, 0–1).
const TONE_BINS: usize = 10;

fn tone_bin(tone: f64) -> usize {
    ((tone.clamp(0.0, 1.0) * TONE_BINS as f64) as usize).min(TONE_BINS - 1)
}

/// The mean flicker per tone bin of `tiles` (`None` for an empty bin).
fn flicker_by_tone(tiles: &[(f64, f64)]) -> Vec<Option<f64>> {
    let mut sums = [(0.0f64, 0usize); TONE_BINS];
    for &(tone, f) in tiles {
        let slot = &mut sums[tone_bin(tone)];
        slot.0 += f;
        slot.1 += 1;
    }
    sums.iter()
        .map(|&(s, n)| (n > 0).then(|| s / n as f64))
        .collect()
}

/// `tiles`' flicker over what the reference gives at the same tones: the sum of the
/// tiles' flicker over the sum of the reference's mean flicker in each tile's tone bin
/// (tiles whose bin the reference lacks are left out).
fn same_tone_ratio(tiles: &[(f64, f64)], reference: &[Option<f64>]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for &(tone, f) in tiles {
        if let Some(r) = reference[tone_bin(tone)] {
            num += f;
            den += r;
        }
    }
    if den > 0.0 { num / den } else { f64::NAN }
}

/// The row of `mode` in one mesh's measurements.
fn in_mode<'a>(rows: &'a [Measured], mode: &str) -> Option<&'a Measured> {
    rows.iter().find(|r| r.mode == mode)
}

/// Mean of `values` over the pixels where `mask` is set (0 for none).
fn mean_on(values: &[f32], mask: &[bool]) -> f64 {
    let (sum, n) = values
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0f64, 0usize), |(s, n), (v, _)| {
            (s + f64::from(*v), n + 1)
        });
    sum / n.max(1) as f64
}

/// The mesh whose surface-mode flicker the others are compared with (`flicker_vs_bunny`).
const REFERENCE: &str = "stanford-bunny";

fn fixture(name: &str) -> anyhow::Result<(String, Mesh)> {
    Ok((
        name.trim_end_matches(".obj").to_string(),
        npr_geometry::load_obj(crate::fixture_mesh(name))?,
    ))
}

fn default_meshes() -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut out = vec![("knot".to_string(), knot())];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        out.push(fixture(name)?);
    }
    // Hard-edged CAD parts (flat faces, cylinders, fillets, creases): the procedural
    // ones and three real triangulations.
    out.push(("cad-parts".to_string(), npr_geometry::generate::cad_parts()));
    for name in ["wingnut.obj", "hammer.obj", "flange.obj"] {
        out.push(fixture(name)?);
    }
    Ok(out)
}

/// `path`'s model at rest and, with `clip`, [`FRAMES`] frames of that clip at 30 fps,
/// each with its stroke directions computed on the pose.
fn load_case(path: &Path, clip: Option<&str>) -> anyhow::Result<Case> {
    let name = path.display().to_string();
    let Some(clip) = clip else {
        return Ok((name, npr_geometry::io::load(path)?.mesh, None));
    };
    let model = npr_app::model::Model::load(path)?;
    let choice = npr_app::animation::ClipChoice::parse(Some(clip));
    let index = npr_app::animation::resolve_clip(&model, &choice)?;
    let rest = match &model.rig {
        Some(rig) => rig.pose_mesh(&rig.bind_pose()),
        None => model.mesh.clone(),
    };
    let poses = match index {
        Some(_) => {
            let animated = npr_app::animation::Animated::new(
                model,
                index,
                npr_app::animation::Playback::default(),
            )?;
            let frames = (0..FRAMES)
                .map(|i| {
                    let m = animated.posed_mesh(i);
                    let d = directions(&m);
                    (m, d)
                })
                .collect();
            Some((clip.to_string(), frames))
        }
        None => None,
    };
    Ok((name, rest, poses))
}

/// A clip's name and its frames (posed mesh, stroke directions).
type Poses = (String, Vec<(Mesh, Vec<Vec3>)>);
/// A mesh to measure: its name, the mesh at rest, and a clip to play.
type Case = (String, Mesh, Option<Poses>);

/// Runs the benchmark on `meshes` (model paths, with the bunny added first as the
/// flicker reference), or the knot, Spot, the bunny, the CAD parts, the wing nut and the
/// hammer. With `animation`, each mesh that has the clip also plays it (camera still,
/// [`FRAMES`] frames at 30 fps), beside its rigid turn: `flicker_vs_rigid` is the clip's
/// flicker over the turn's, same mode, same run (targets: sliding ≤ 0.25 in surface
/// mode, flicker ≤ 1.5× the rigid turn's).
pub fn run(meshes: &[PathBuf], json: Option<&Path>, animation: Option<&str>) -> anyhow::Result<()> {
    let cases: Vec<Case> = if meshes.is_empty() {
        default_meshes()?
            .into_iter()
            .map(|(n, m)| (n, m, None))
            .collect()
    } else {
        std::iter::once(fixture("stanford-bunny.obj").map(|(n, m)| (n, m, None)))
            .chain(meshes.iter().map(|p| load_case(p, animation)))
            .collect::<anyhow::Result<_>>()?
    };
    let ctx = GpuContext::new()?;
    let tam = TonalArtMap::generate(&TamParams::pen())?;
    let mut table = Table::new(
        &format!(
            "hatching coherence: {WIDTH}×{HEIGHT}, turning 1°/frame, 2× dolly over {FRAMES} \
             frames (or a clip's frames, camera still); adapter {}",
            ctx.adapter_summary()
        ),
        &[
            "mesh",
            "motion",
            "mode",
            "sliding",
            "density_change",
            "coverage_change",
            "flicker",
            "flicker_vs_screen",
            "flicker_vs_bunny",
            "flicker_vs_bunny_same_tone",
            "flicker_vs_rigid",
            "ink_coverage",
            "ink_vs_screen",
            "tiles",
        ],
    );
    let bar = super::progress(cases.len() as u64, "hatching-coherence");
    // Per mesh, its runs: the rigid turn, then the clip if it plays one.
    let mut measured = Vec::with_capacity(cases.len());
    for (name, mesh, poses) in &cases {
        let mut runs = vec![(
            "turntable".to_string(),
            measure(&ctx, &tam, mesh, Motion::Turntable)?,
        )];
        if let Some((clip, frames)) = poses {
            runs.push((
                format!("clip {clip}"),
                measure(&ctx, &tam, mesh, Motion::Clip(frames))?,
            ));
        }
        measured.push((name, runs));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let bunny_rows = measured
        .iter()
        .find(|(name, _)| name.as_str() == REFERENCE)
        .and_then(|(_, runs)| in_mode(&runs[0].1, "surface"));
    let bunny = bunny_rows.map_or(f64::NAN, |r| r.flicker);
    let bunny_by_tone =
        bunny_rows.map_or(vec![None; TONE_BINS], |r| flicker_by_tone(&r.tile_flicker));
    for (name, runs) in &measured {
        for (motion, rows) in runs {
            let screen = in_mode(rows, "screen");
            let (screen_flicker, screen_ink) =
                screen.map_or((f64::NAN, f64::NAN), |r| (r.flicker, r.ink));
            for r in rows {
                let rigid = in_mode(&runs[0].1, r.mode).map_or(f64::NAN, |x| x.flicker);
                table.push(vec![
                    Cell::from(name.as_str()),
                    Cell::from(motion.as_str()),
                    Cell::from(r.mode),
                    Cell::Num(r.sliding, 3),
                    Cell::Num(r.density_change, 3),
                    Cell::Num(r.coverage_change, 3),
                    Cell::Num(r.flicker, 4),
                    Cell::Num(r.flicker / screen_flicker, 2),
                    Cell::Num(r.flicker / bunny, 2),
                    Cell::Num(same_tone_ratio(&r.tile_flicker, &bunny_by_tone), 2),
                    Cell::Num(r.flicker / rigid, 2),
                    Cell::Num(r.ink, 3),
                    Cell::Num(r.ink / screen_ink, 3),
                    Cell::from(r.tiles),
                ]);
            }
        }
    }
    emit(&[table, by_tone_table(&measured)], json)
}

/// The surface mode's flicker per tone bin, one row per mesh and motion: where a mesh's
/// `flicker_vs_bunny` comes from (a tile's flicker depends on its tone, so a mesh whose
/// tiles are mostly mid-tone flickers more on average at the same flicker per tone).
/// One mesh's measurements: its name and, per motion (the turntable, a clip), the rows.
type MeshRuns<'a> = (&'a String, Vec<(String, Vec<Measured>)>);

fn by_tone_table(measured: &[MeshRuns<'_>]) -> Table {
    let bins: Vec<String> = (0..TONE_BINS)
        .map(|b| format!("flicker_tone_{:.1}", b as f64 / TONE_BINS as f64))
        .collect();
    let mut columns = vec!["mesh", "motion", "mid_tone_tile_share"];
    columns.extend(bins.iter().map(String::as_str));
    let mut table = Table::new(
        "surface mode's flicker by tile tone (tone bins of 0.1 from black; - where no \
         tile has that tone); mid_tone_tile_share = tiles of tone 0.2-0.6",
        &columns,
    );
    for (name, runs) in measured {
        for (motion, rows) in runs {
            let Some(r) = in_mode(rows, "surface") else {
                continue;
            };
            let mid = r
                .tile_flicker
                .iter()
                .filter(|(t, _)| (0.2..0.6).contains(t))
                .count();
            let mut row = vec![
                Cell::from(name.as_str()),
                Cell::from(motion.as_str()),
                Cell::Num(mid as f64 / r.tile_flicker.len().max(1) as f64, 2),
            ];
            row.extend(
                flicker_by_tone(&r.tile_flicker)
                    .into_iter()
                    .map(|f| f.map_or(Cell::Empty, |f| Cell::Num(f, 4))),
            );
            table.push(row);
        }
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strokes move with a moving body: on the Fox walking and on the procedural bent tube
    /// bending ([`FRAMES`] frames at 30 fps, camera still), the surface mode's sliding is
    /// at most 0.25 and its flicker at most 1.5× that of the same mesh's rigid turn in the
    /// same run.
    #[test]
    fn strokes_follow_a_moving_body() {
        let Some(ctx) = npr_gpu::testing::context_or_skip("strokes_follow_a_moving_body") else {
            return;
        };
        let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
        let fox = load_case(&crate::fixture_mesh("Fox.glb"), Some("Walk")).unwrap();
        let tube = {
            let r = npr_geometry::generate::bent_tube(0.3, 2.0, 1.5, 24, 32);
            let clip = &r.rig.clips()[0];
            let frames = (0..FRAMES)
                .map(|i| {
                    let m = r.rig.pose_mesh(&r.rig.sample(clip, i as f32 / 30.0));
                    let d = directions(&m);
                    (m, d)
                })
                .collect();
            (
                "bent tube".to_string(),
                r.mesh,
                Some(("bend".to_string(), frames)),
            )
        };
        for (name, mesh, poses) in [fox, tube] {
            let (_, frames) = poses.expect("the clip plays");
            let surface =
                |rows: Vec<Measured>| rows.into_iter().find(|r| r.mode == "surface").unwrap();
            let rigid = surface(measure(ctx, &tam, &mesh, Motion::Turntable).unwrap());
            let clip = surface(measure(ctx, &tam, &mesh, Motion::Clip(&frames)).unwrap());
            eprintln!(
                "{name}: clip sliding {:.3} over {} tiles, flicker {:.4} against the turn's {:.4}",
                clip.sliding, clip.tiles, clip.flicker, rigid.flicker
            );
            assert!(clip.tiles >= 20, "{name}: {} tiles measured", clip.tiles);
            assert!(clip.sliding <= 0.25, "{name}: sliding {:.3}", clip.sliding);
            assert!(
                clip.flicker <= 1.5 * rigid.flicker,
                "{name}: flicker {:.4} on the clip, {:.4} on the turn",
                clip.flicker,
                rigid.flicker
            );
        }
    }
}
