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
//! Targets: sliding ≤ 0.25, density_change ≤ 0.25, flicker ≤ 1.5 × the paper mode's
//! (on the CAD parts too, `npr_geometry::generate::cad_parts`).

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

/// Per-pixel motion of frame `t` (rendered by the every-frame rig): each surface pixel's
/// position in the previous frame, and the surface mask.
fn previous_positions(
    ctx: &GpuContext,
    gbuffer: &GBuffer,
    frame_index: u64,
) -> anyhow::Result<(Vec<[f32; 2]>, Vec<bool>)> {
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
    Ok((prev, mask))
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
    let mut masks = Vec::with_capacity(FRAMES);
    for t in 0..FRAMES {
        render(ctx, &mut motion, (mesh, &gpu_mesh), sequence, t)?;
        let (p, m) = previous_positions(ctx, &motion.frame.gbuffer, t as u64)?;
        prev_pos.push(p);
        masks.push(m);
    }
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let mut out = Vec::new();
    for (mode, space, period) in MODES {
        let mut r = rig(ctx, tam, (space, period), (&gpu_mesh, &directions), size)?;
        let mut inks = Vec::with_capacity(FRAMES);
        let (mut first, mut last) = ((0.0, 0.0), (0.0, 0.0));
        for t in 0..FRAMES {
            inks.push(ink_image(&render(
                ctx,
                &mut r,
                (mesh, &gpu_mesh),
                sequence,
                t,
            )?));
            if t == 0 {
                first = density_at_constant_tone(ctx, &r, tam)?;
            }
            if t == FRAMES - 1 {
                last = density_at_constant_tone(ctx, &r, tam)?;
            }
        }
        let (mut errors, mut surface, mut flicker) = (Vec::new(), Vec::new(), Vec::new());
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
            tiles: errors.len(),
        });
    }
    Ok(out)
}

fn default_meshes() -> anyhow::Result<Vec<(String, Mesh)>> {
    let mut out = vec![("knot".to_string(), knot())];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        out.push((
            name.trim_end_matches(".obj").to_string(),
            npr_geometry::load_obj(crate::fixture_mesh(name))?,
        ));
    }
    // a hard-edged CAD part (flat faces, cylinders, fillets, creases).
    out.push(("cad-parts".to_string(), npr_geometry::generate::cad_parts()));
    Ok(out)
}

/// `path`'s model at rest and, with `clip`, [`FRAMES`] frames of that clip at 30 fps,
/// each with its stroke directions computed on the pose.
fn load_case(path: &Path, clip: Option<&str>) -> anyhow::Result<(String, Mesh, Option<Poses>)> {
    let model = npr_app::model::Model::load(path)?;
    let name = path.display().to_string();
    let Some(clip) = clip else {
        return Ok((name, npr_geometry::io::load(path)?.mesh, None));
    };
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

/// Runs the benchmark on `meshes` (OBJ paths), or the knot, Spot, the bunny and the CAD
/// parts. With `animation`, each mesh that has the clip also plays it (camera still,
/// [`FRAMES`] frames at 30 fps), beside its rigid turn: `flicker_vs_rigid` is the clip's
/// flicker over the turn's, same mode, same run (targets: sliding ≤ 0.25 in surface
/// mode, flicker ≤ 1.5× the rigid turn's).
pub fn run(meshes: &[PathBuf], json: Option<&Path>, animation: Option<&str>) -> anyhow::Result<()> {
    let cases: Vec<(String, Mesh, Option<Poses>)> = if meshes.is_empty() {
        default_meshes()?
            .into_iter()
            .map(|(n, m)| (n, m, None))
            .collect()
    } else {
        meshes
            .iter()
            .map(|p| load_case(p, animation))
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
            "flicker_vs_rigid",
            "tiles",
        ],
    );
    let bar = super::progress(cases.len() as u64, "hatching-coherence");
    for (name, mesh, poses) in &cases {
        let rigid = measure(&ctx, &tam, mesh, Motion::Turntable)?;
        let mut runs = vec![("turntable".to_string(), rigid)];
        if let Some((clip, frames)) = poses {
            runs.push((
                format!("clip {clip}"),
                measure(&ctx, &tam, mesh, Motion::Clip(frames))?,
            ));
        }
        let rigid_flicker = |mode: &str| {
            runs[0]
                .1
                .iter()
                .find(|r| r.mode == mode)
                .map_or(f64::NAN, |r| r.flicker)
        };
        for (motion, rows) in &runs {
            let screen_flicker = rows
                .iter()
                .find(|r| r.mode == "screen")
                .map_or(f64::NAN, |r| r.flicker);
            for r in rows {
                table.push(vec![
                    Cell::from(name.as_str()),
                    Cell::from(motion.as_str()),
                    Cell::from(r.mode),
                    Cell::Num(r.sliding, 3),
                    Cell::Num(r.density_change, 3),
                    Cell::Num(r.coverage_change, 3),
                    Cell::Num(r.flicker, 4),
                    Cell::Num(r.flicker / screen_flicker, 2),
                    Cell::Num(r.flicker / rigid_flicker(r.mode), 2),
                    Cell::from(r.tiles),
                ]);
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    emit(&[table], json)
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
