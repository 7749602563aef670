//! Demo figures of the image-space hatching paper (Kim & Lee 2008, `npr-hatching`):
//! Fig. 1 (cut-and-paste, blended, offset partition), Fig. 2 (pen and pencil on single
//! objects), a multi-object scene like Fig. 3 with its Phong + VSM baseline, the complex
//! scene of Fig. 4 (about 1.1M triangles at 1280×480), a 2-D flow field (§5), the tonal art
//! maps themselves, and GIFs of screen-space (the paper) against surface-anchored strokes
//! on turning objects (`hatching-coherence-*.gif`). Our own figures (the scene under a spot
//! light, raw against smooth stroke directions on the bunny) add ink outlines
//! (`npr_gpu::outline`); those that reproduce the paper's figures do not.
//!
//! Stroke directions: the smooth line field fitted to the direction of maximum principal
//! curvature (`npr_hatching::stroke_directions` with the default
//! `DirectionSource::Smooth`), falling back to the parallels `y × n` on umbilic and flat
//! objects (a sphere, the ground plane).

use crate::bench::hatching_coherence::{rig, uniforms};
use crate::demo::{demo_meshes, framing_camera, save, sheet};
use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::{Camera, GpuContext, GpuMesh, ObjectUniforms};
use npr_hatching::{
    BlendMode, HatchFrame, HatchInputs, HatchParams, ShadowLight, StrokeSpace, TamParams, TamStyle,
    TonalArtMap, VsmSettings, hatch_cpu, hatch_image_gpu,
};
use std::path::{Path, PathBuf};

/// The hatching demo knot: the (2, 3) knot of the specular paper, finer.
pub fn demo_knot() -> Mesh {
    generate::torus_knot(&generate::TorusKnot {
        p: 2,
        q: 3,
        major_radius: 1.0,
        minor_radius: 0.4,
        tube_radius: 0.15,
        segments: 480,
        tube_segments: 40,
    })
}

/// Stroke directions for a demo mesh (see the module docs).
pub fn demo_directions(name: &str, mesh: &Mesh) -> Vec<Vec3> {
    directions_from(name, mesh, &npr_hatching::DirectionSource::default())
}

/// Stroke directions for a demo mesh from a chosen source.
pub fn directions_from(
    _name: &str,
    mesh: &Mesh,
    source: &npr_hatching::DirectionSource,
) -> Vec<Vec3> {
    npr_hatching::stroke_directions(
        mesh,
        source,
        npr_hatching::StrokeDirection::KappaMax,
        &npr_geometry::CurvatureOptions::default(),
        Vec3::Y,
    )
}

/// One object of a demo scene.
struct Item {
    mesh: Mesh,
    world_from_object: Mat4,
    directions: Vec<Vec3>,
}

/// Whether a figure gets ink outlines (`npr_gpu::outline`): on for our own figures, off
/// for those that reproduce the paper's.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Outlines {
    Paper,
    On,
}

/// Renders `items` hatched with each `params` (and optionally the Phong + VSM baseline),
/// with outlines over the hatched images when asked.
#[allow(clippy::too_many_arguments)]
fn render(
    ctx: &GpuContext,
    items: &[Item],
    camera: &Camera,
    light: &ShadowLight,
    tam: &TonalArtMap,
    params: &[HatchParams],
    with_phong: bool,
    outlines: Outlines,
    (w, h): (u32, u32),
) -> anyhow::Result<Vec<image::RgbaImage>> {
    let first = params.first().copied().unwrap_or_default();
    let mut frame = HatchFrame::new(
        &ctx.device,
        &ctx.queue,
        tam,
        &first,
        VsmSettings::default(),
        npr_gpu::COLOR_FORMAT,
        w,
        h,
    )?;
    let mut gpu = Vec::new();
    for item in items {
        let mesh = GpuMesh::upload(&ctx.device, &item.mesh)?;
        let uniforms = ObjectUniforms::new(
            item.world_from_object,
            Vec3::splat(0.9),
            0.35,
            Vec3::ONE,
            24.0,
        );
        let object = frame
            .scene
            .create_object(&ctx.device, &mesh, &uniforms, &item.directions)?;
        gpu.push((mesh, object));
    }
    let objects: Vec<_> = gpu.iter().map(|(m, o)| (m, o)).collect();
    frame.set_view(&ctx.queue, camera, light);
    let mut out = Vec::new();
    let outlined: Vec<(&GpuMesh, Mat4)> = gpu
        .iter()
        .zip(items)
        .map(|((m, _), item)| (m, item.world_from_object))
        .collect();
    for p in params {
        frame.hatch.set_params(&ctx.queue, p)?;
        let mut image = frame.render_hatched(&ctx.device, &ctx.queue, &objects)?;
        if outlines == Outlines::On {
            image = npr_gpu::outline::outline_image(
                &ctx.device,
                &ctx.queue,
                &image,
                camera,
                &outlined,
                &npr_gpu::outline::OutlineSettings::default(),
            )?;
        }
        out.push(image);
    }
    if with_phong {
        out.push(frame.render_phong(&ctx.device, &ctx.queue, &objects)?);
    }
    Ok(out)
}

fn single(name: &str, mesh: Mesh) -> (Item, Camera, ShadowLight) {
    let (camera, world_from_object) = framing_camera(&mesh, 4.0 / 3.0);
    let directions = demo_directions(name, &mesh);
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 1.6, 1.2),
        center: Vec3::ZERO,
        radius: 1.05,
    };
    (
        Item {
            mesh,
            world_from_object,
            directions,
        },
        camera,
        light,
    )
}

/// Writes the hatching figures into `dir` and returns their paths; `progress` names the
/// long parts.
pub fn run(
    ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let pencil = TonalArtMap::generate(&TamParams::pencil())?;

    // The tonal art maps, light to dark.
    for tam in [&pen, &pencil] {
        let tiles: Vec<image::RgbaImage> = (0..tam.tones())
            .filter_map(|i| tam.slice_image(i))
            .map(|g| image::DynamicImage::ImageLuma8(g).to_rgba8())
            .collect();
        let path = dir.join(format!("hatching-tam-{}.png", tam.style().name()));
        save(&sheet(&tiles, tam.tones()), &path, &mut written)?;
    }

    // Fig. 1: the three stages on one object.
    // A close-up, strokes 1.5 px per texel, so that the partitions are visible.
    let (item, mut camera, light) = single("knot", demo_knot());
    camera.eye = Vec3::new(0.5, 0.9, 2.4).normalize() * 1.45;
    camera.target = Vec3::new(0.15, 0.0, 0.2);
    let params: Vec<HatchParams> = BlendMode::ALL
        .iter()
        .map(|&mode| HatchParams {
            mode,
            stroke_scale: 1.5,
            ..Default::default()
        })
        .collect();
    let images = render(
        ctx,
        &[item],
        &camera,
        &light,
        &pen,
        &params,
        false,
        Outlines::Paper,
        (480, 360),
    )?;
    for (img, mode) in images.iter().zip(BlendMode::ALL) {
        save(
            img,
            &dir.join(format!("hatching-fig1-{}.png", mode.name())),
            &mut written,
        )?;
    }
    save(
        &sheet(&images, 3),
        &dir.join("hatching-fig1.png"),
        &mut written,
    )?;

    // Fig. 2: pen and pencil on single objects, 640×480 as in the paper.
    progress.set_message("hatching: Fig. 2, single objects");
    let mut singles: Vec<(String, Mesh)> = vec![("knot".to_string(), demo_knot())];
    singles.extend(
        demo_meshes()?
            .into_iter()
            .filter(|(n, _)| matches!(n.as_str(), "torus" | "sphere" | "spot" | "stanford-bunny")),
    );
    let mut tiles = Vec::new();
    for (name, mesh) in singles {
        let (item, camera, light) = single(&name, mesh);
        let styles = [(&pen, TamStyle::Pen), (&pencil, TamStyle::Pencil)];
        for (tam, style) in styles {
            let params = [HatchParams {
                stroke_scale: if style == TamStyle::Pencil { 1.25 } else { 1.0 },
                ink: if style == TamStyle::Pencil {
                    [0.04, 0.04, 0.05]
                } else {
                    [0.0; 3]
                },
                ..Default::default()
            }];
            // Spot in pen also with outlines: off (the paper's figure) against on (ours).
            let spot_pen = name == "spot" && style == TamStyle::Pen;
            for outlines in [Outlines::Paper, Outlines::On] {
                if outlines == Outlines::On && !spot_pen {
                    continue;
                }
                let imgs = render(
                    ctx,
                    std::slice::from_ref(&item),
                    &camera,
                    &light,
                    tam,
                    &params,
                    false,
                    outlines,
                    (640, 480),
                )?;
                for img in imgs {
                    let file = match outlines {
                        Outlines::Paper => format!("hatching-fig2-{name}-{}.png", style.name()),
                        Outlines::On => "hatching-outlines-spot-pen.png".to_string(),
                    };
                    save(&img, &dir.join(file), &mut written)?;
                    if outlines == Outlines::Paper {
                        tiles.push(img);
                    }
                }
            }
        }
    }
    save(
        &sheet(&tiles, 2),
        &dir.join("hatching-fig2.png"),
        &mut written,
    )?;

    // Fig. 3: a multi-object scene on a ground plane with cast shadows.
    progress.set_message("hatching: Fig. 3 scene");
    let (items, camera, light) = scene_fig3();
    for (tam, style) in [(&pen, TamStyle::Pen), (&pencil, TamStyle::Pencil)] {
        let imgs = render(
            ctx,
            &items,
            &camera,
            &light,
            tam,
            &[HatchParams::default()],
            style == TamStyle::Pen,
            Outlines::Paper,
            (960, 600),
        )?;
        save(
            &imgs[0],
            &dir.join(format!("hatching-fig3-scene-{}.png", style.name())),
            &mut written,
        )?;
        if let Some(phong) = imgs.get(1) {
            save(
                phong,
                &dir.join("hatching-fig3-scene-phong-vsm.png"),
                &mut written,
            )?;
        }
    }

    // Fig. 4: a complex scene of several objects, about 1.1M triangles, at 1280×480.
    progress.set_message("hatching: Fig. 4 scene (stroke fields)");
    let (big, big_camera, big_light) = scene_fig4()?;
    let triangles: usize = big.iter().map(|i| i.mesh.indices.len() / 3).sum();
    progress.set_message("hatching: Fig. 4 scene (render)");
    let imgs = render(
        ctx,
        &big,
        &big_camera,
        &big_light,
        &pen,
        &[HatchParams::default()],
        false,
        Outlines::Paper,
        FIG4_SIZE,
    )?;
    println!(
        "demo hatching: Fig. 4 scene, {} objects, {triangles} triangles, {}×{}",
        big.len(),
        FIG4_SIZE.0,
        FIG4_SIZE.1
    );
    save(
        &imgs[0],
        &dir.join("hatching-fig4-scene-pen.png"),
        &mut written,
    )?;
    drop(big);

    // The same scene under a spot light (cone and shadows from the VSM).
    let spot = ShadowLight::Spot {
        position: Vec3::new(-2.5, 5.0, 2.5),
        target: Vec3::new(0.0, 0.5, 0.0),
        outer_angle_rad: 38f32.to_radians(),
        inner_angle_rad: 26f32.to_radians(),
        range: 14.0,
    };
    let imgs = render(
        ctx,
        &items,
        &camera,
        &spot,
        &pen,
        &[HatchParams::default()],
        false,
        Outlines::On,
        (960, 600),
    )?;
    save(
        &imgs[0],
        &dir.join("hatching-fig3-scene-spot-pen.png"),
        &mut written,
    )?;

    progress.set_message("hatching: stroke directions, flow");
    // Stroke directions before/after: the raw principal field against the smooth line
    // field (issue 11), on the bunny, with outlines.
    let bunny = npr_geometry::load_obj(crate::fixture_mesh("stanford-bunny.obj"))?;
    written.extend(directions_sheet(
        ctx,
        dir,
        &pen,
        "stanford-bunny",
        &bunny,
        Mat4::IDENTITY,
        "hatching-directions-bunny",
    )?);
    written.extend(cad_directions(ctx, dir, &pen)?);

    // Beyond §5: the paper's screen-space strokes against surface-anchored ones on a
    // turning object (issue 14), side by side.
    for name in crate::gallery::COHERENCE_SUBJECTS {
        written.extend(coherence_gif(ctx, dir, name, &pen)?);
    }

    // §5: 2-D flow visualisation, GPU and CPU.
    let flow = flow_inputs(640, 480)?;
    let params = HatchParams::default();
    let gpu = hatch_image_gpu(&ctx.device, &ctx.queue, &flow, &pen, &params)?;
    save(&gpu, &dir.join("hatching-flow-gpu.png"), &mut written)?;
    let cpu = hatch_cpu(&flow, &pencil, &params)?;
    save(
        &cpu,
        &dir.join("hatching-flow-cpu-pencil.png"),
        &mut written,
    )?;
    Ok(written)
}

/// `hatching-directions-cad.png` (issue 22): the procedural CAD parts
/// (`npr_geometry::generate::cad_parts`), pen with outlines, the paper's rule (raw
/// principal directions) beside the default field (cut at creases, straight on flat
/// faces), turned to show top and side faces.
pub fn cad_directions(
    ctx: &GpuContext,
    dir: &Path,
    pen: &TonalArtMap,
) -> anyhow::Result<Vec<PathBuf>> {
    directions_sheet(
        ctx,
        dir,
        pen,
        "cad-parts",
        &generate::cad_parts(),
        Mat4::from_rotation_x(0.45) * Mat4::from_rotation_y(-0.5),
        "hatching-directions-cad",
    )
}

/// `STEM.png`: `mesh` hatched with the pen and outlines, the paper's rule (raw principal
/// directions, `STEM-principal.png`) beside the default field (`STEM-smooth.png`), turned
/// by `turn` after framing; returns the three files.
fn directions_sheet(
    ctx: &GpuContext,
    dir: &Path,
    pen: &TonalArtMap,
    name: &str,
    mesh: &npr_geometry::Mesh,
    turn: Mat4,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let mut tiles = Vec::new();
    for source in [
        npr_hatching::DirectionSource::Principal,
        npr_hatching::DirectionSource::default(),
    ] {
        let (mut item, camera, light) = single(name, mesh.clone());
        item.directions = directions_from(name, &item.mesh, &source);
        item.world_from_object = turn * item.world_from_object;
        let imgs = render(
            ctx,
            &[item],
            &camera,
            &light,
            pen,
            &[HatchParams::default()],
            false,
            Outlines::On,
            (640, 480),
        )?;
        save(
            &imgs[0],
            &dir.join(format!("{stem}-{}.png", source.name())),
            &mut written,
        )?;
        tiles.extend(imgs);
    }
    save(
        &sheet(&tiles, 2),
        &dir.join(format!("{stem}.png")),
        &mut written,
    )?;
    Ok(written)
}

/// Frames of the coherence GIFs, and the turn per frame.
const COHERENCE_FRAMES: usize = 48;
const COHERENCE_STEP_DEG: f32 = 2.0;

/// `hatching-coherence-NAME.gif`: the object turning 2° per frame while the camera dollies
/// in by 2× and back, hatched in screen space (left, the paper: the strokes stay on the
/// screen, the surface slides beneath) and surface space (right, the default: the strokes
/// move with the surface at constant density); and a strip of every 12th frame.
fn coherence_gif(
    ctx: &GpuContext,
    dir: &Path,
    name: &str,
    tam: &TonalArtMap,
) -> anyhow::Result<Vec<PathBuf>> {
    let mesh = if name == "knot" {
        demo_knot()
    } else {
        npr_geometry::load_obj(crate::fixture_mesh(&format!("{name}.obj")))?
    };
    let (w, h) = (320u32, 240u32);
    let (camera0, world_from_object) = framing_camera(&mesh, w as f32 / h as f32);
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 1.6, 1.2),
        center: Vec3::ZERO,
        radius: 1.05,
    };
    let directions = demo_directions(name, &mesh);
    let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh)?;
    let rigs = StrokeSpace::ALL
        .into_iter()
        .map(|space| {
            let period = npr_hatching::DEFAULT_ANCHOR_PERIOD;
            rig(ctx, tam, (space, period), &gpu_mesh, &directions, (w, h))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let mut frames = Vec::with_capacity(COHERENCE_FRAMES);
    for t in 0..COHERENCE_FRAMES {
        // Distance: twice the framing distance → the framing distance → back (a 2× dolly).
        let phase = (t as f32 / COHERENCE_FRAMES as f32 * std::f32::consts::TAU).cos();
        let camera = Camera::look_at(
            camera0.eye * 2f32.powf(0.5 + 0.5 * phase),
            Vec3::ZERO,
            w as f32 / h as f32,
        );
        let turn = Mat4::from_rotation_y((t as f32 * COHERENCE_STEP_DEG).to_radians());
        let mut tiles = Vec::new();
        for r in &rigs {
            r.object
                .update(&ctx.queue, &uniforms(turn * world_from_object));
            r.frame.set_view(&ctx.queue, &camera, &light);
            tiles.push(r.frame.render_hatched(
                &ctx.device,
                &ctx.queue,
                &[(&gpu_mesh, &r.object)],
            )?);
        }
        frames.push(sheet(&tiles, 2));
    }
    let mut written = Vec::new();
    let strip: Vec<_> = frames.iter().step_by(12).cloned().collect();
    save(
        &sheet(&strip, 1),
        &dir.join(format!("hatching-coherence-{name}-strip.png")),
        &mut written,
    )?;
    let gif_path = dir.join(format!("hatching-coherence-{name}.gif"));
    npr_app::output::save_gif(&gif_path, &frames, 80)?;
    written.push(gif_path);
    Ok(written)
}

/// The Fig. 3-like scene: ground plane, and six objects; a directional light with shadows.
fn scene_fig3() -> (Vec<Item>, Camera, ShadowLight) {
    let mut items = Vec::new();
    let plane = generate::plane(9.0, 7.0, 8, 8);
    let dirs = vec![Vec3::new(1.0, 0.0, 0.35); plane.positions.len()];
    items.push(Item {
        mesh: plane,
        world_from_object: Mat4::IDENTITY,
        directions: dirs,
    });
    let mut add = |name: &str, mesh: Mesh, m: Mat4| {
        let directions = demo_directions(name, &mesh);
        items.push(Item {
            mesh,
            world_from_object: m,
            directions,
        });
    };
    add(
        "sphere",
        generate::icosphere(4, 0.8),
        Mat4::from_translation(Vec3::new(-2.2, 0.8, 0.6)),
    );
    add(
        "torus",
        generate::torus(0.9, 0.35, 96, 48),
        Mat4::from_translation(Vec3::new(0.2, 0.35, 1.4)),
    );
    add(
        "cylinder",
        generate::cylinder(0.5, 1.8, 64, 16, true),
        Mat4::from_translation(Vec3::new(2.3, 0.9, -0.4)),
    );
    add(
        "knot",
        demo_knot(),
        Mat4::from_translation(Vec3::new(0.0, 1.3, -1.3)) * Mat4::from_scale(Vec3::splat(0.8)),
    );
    add(
        "ellipsoid",
        generate::ellipsoid(0.9, 0.5, 0.6, 24),
        Mat4::from_translation(Vec3::new(-1.4, 0.5, -1.8)),
    );
    let camera = Camera::look_at(
        Vec3::new(1.5, 4.2, 7.0),
        Vec3::new(0.0, 0.4, 0.0),
        960.0 / 600.0,
    );
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(-1.2, 2.0, 0.9),
        center: Vec3::new(0.0, 0.5, 0.0),
        radius: 5.5,
    };
    (items, camera, light)
}

/// The size of the Fig. 4 scene, as in the paper.
const FIG4_SIZE: (u32, u32) = (1280, 480);

/// `world_from_object` placing `mesh` scaled to bounding radius `radius`, centred over
/// (x, z) and resting on the ground plane y = 0.
fn on_ground(mesh: &Mesh, radius: f32, x: f32, z: f32, turn_deg: f32) -> Mat4 {
    let (_, unit) = framing_camera(mesh, 1.0);
    let bottom = mesh
        .positions
        .iter()
        .map(|p| unit.transform_point3(*p).y)
        .fold(f32::MAX, f32::min);
    Mat4::from_translation(Vec3::new(x, -bottom * radius, z))
        * Mat4::from_scale(Vec3::splat(radius))
        * Mat4::from_rotation_y(turn_deg.to_radians())
        * unit
}

/// The Fig. 4-like complex scene (the paper: "a complex 3-D scene with many triangles",
/// about 1,100,000 at 1280×480): a row of objects on a ground plane, the bunny and Spot
/// among dense procedural ones; a directional light with shadows over the whole row.
fn scene_fig4() -> anyhow::Result<(Vec<Item>, Camera, ShadowLight)> {
    let plane = generate::plane(16.0, 7.0, 16, 8);
    let dirs = vec![Vec3::new(1.0, 0.0, 0.35); plane.positions.len()];
    let mut items = vec![Item {
        mesh: plane,
        world_from_object: Mat4::IDENTITY,
        directions: dirs,
    }];
    let bunny = npr_geometry::load_obj(crate::fixture_mesh("stanford-bunny.obj"))?;
    let spot = npr_geometry::load_obj(crate::fixture_mesh("spot.obj"))?;
    let knot = generate::torus_knot(&generate::TorusKnot {
        p: 2,
        q: 3,
        major_radius: 1.0,
        minor_radius: 0.4,
        tube_radius: 0.15,
        segments: 1800,
        tube_segments: 200,
    });
    let objects: Vec<(&str, Mesh, f32, f32, f32, f32)> = vec![
        (
            "cylinder",
            generate::cylinder(0.5, 1.8, 256, 64, true),
            1.0,
            -6.0,
            0.2,
            0.0,
        ),
        ("stanford-bunny", bunny, 1.2, -3.7, -0.3, 20.0),
        (
            "torus",
            generate::torus(1.0, 0.4, 400, 200),
            1.1,
            -1.2,
            0.6,
            0.0,
        ),
        ("knot", knot, 1.3, 1.3, -0.5, 0.0),
        ("spot", spot, 1.1, 3.8, 0.4, -35.0),
        ("sphere", generate::icosphere(6, 1.0), 0.9, 6.0, -0.2, 0.0),
    ];
    for (name, mesh, radius, x, z, turn) in objects {
        let world_from_object = on_ground(&mesh, radius, x, z, turn);
        let directions = demo_directions(name, &mesh);
        items.push(Item {
            mesh,
            world_from_object,
            directions,
        });
    }
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.8, 7.4),
        Vec3::new(0.0, 0.9, 0.0),
        FIG4_SIZE.0 as f32 / FIG4_SIZE.1 as f32,
    );
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 2.0, 1.1),
        center: Vec3::new(0.0, 0.8, 0.0),
        radius: 8.0,
    };
    Ok((items, camera, light))
}

/// A 2-D flow: a uniform stream past two counter-rotating vortices; tone from speed.
pub fn flow_inputs(w: u32, h: u32) -> anyhow::Result<HatchInputs> {
    let mut dir = Vec::with_capacity((w * h) as usize);
    let mut mag = Vec::with_capacity((w * h) as usize);
    let vortices = [
        (Vec2::new(0.32, 0.45), 1.0f32),
        (Vec2::new(0.68, 0.58), -1.0),
    ];
    for y in 0..h {
        for x in 0..w {
            // Screen axes, y up, in units of the height.
            let p = Vec2::new(x as f32 + 0.5, h as f32 - y as f32 - 0.5) / h as f32;
            let mut v = Vec2::new(0.25, 0.0);
            for (c, s) in vortices {
                let d = p - c;
                let r2 = d.length_squared() + 0.004;
                v += s * 0.08 * Vec2::new(-d.y, d.x) / r2;
            }
            dir.push([v.x, v.y]);
            mag.push(v.length());
        }
    }
    Ok(HatchInputs::from_flow(w, h, &dir, &mag, 3.0)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The issue-22 gallery figure renders: both tiles have ink on the object, and the
    /// default field's strokes differ from the paper's rule.
    #[test]
    fn cad_directions_figure_renders() {
        let Some(ctx) = npr_gpu::testing::context_or_skip("cad_directions_figure_renders") else {
            return;
        };
        let dir = std::env::temp_dir().join(format!("npr-cad-figure-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let pen = TonalArtMap::generate(&TamParams::pen()).unwrap();
        let written = cad_directions(ctx, &dir, &pen).unwrap();
        assert_eq!(written.len(), 3, "{written:?}");
        let tile = |name: &str| image::open(dir.join(name)).unwrap().to_luma8();
        let (raw, smooth) = (
            tile("hatching-directions-cad-raw.png"),
            tile("hatching-directions-cad-smooth.png"),
        );
        let dark = |im: &image::GrayImage| im.pixels().filter(|p| p.0[0] < 128).count();
        assert!(dark(&raw) > 2000 && dark(&smooth) > 2000);
        let differ = raw
            .pixels()
            .zip(smooth.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert!(differ > 2000, "{differ} pixels differ");
        eprintln!("cad figure in {}", dir.display());
    }
}
