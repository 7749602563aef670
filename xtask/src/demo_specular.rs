//! Specular demo figures (the specular paper's Fig. 2, 4, 5, 6, 7, 8, and the paper's
//! highlight sizing beside ours) into `target/demo/`.

use crate::demo::framing_camera;
use anyhow::Context;
use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, CurvatureRadius, LightEye, Mesh, generate};
use npr_gpu::{
    BaseShading, COLOR_FORMAT, DEPTH_FORMAT, FrameUniforms, GpuContext, GpuMesh, Light,
    ObjectUniforms, OffscreenTarget, ShadingModel, TargetFormats, readback_rgba,
};
use npr_specular::snapshot::{HighlightScene, Renderer};
use npr_specular::{
    FrameInput, HighlightPass, HighlightSet, HighlightShape, ProjectorControls, UpAxis,
};
use std::path::{Path, PathBuf};

const TILE: u32 = 360;

struct Subject {
    name: String,
    mesh: Mesh,
    gpu: GpuMesh,
    set: HighlightSet,
    world_from_normalized: Mat4,
}

/// `smoothing`: curvature ball radius in mean edge lengths (scanned meshes carry bumps
/// that a larger ball smooths into fewer, calmer highlights).
fn subject(ctx: &GpuContext, name: &str, mesh: Mesh, smoothing: f32) -> anyhow::Result<Subject> {
    let gpu = GpuMesh::upload(&ctx.device, &mesh)?;
    let options = CurvatureOptions {
        radius: CurvatureRadius::EdgeLengths(smoothing),
        ..CurvatureOptions::default()
    };
    let set = HighlightSet::new(&mesh, &options)?;
    let (_, world_from_normalized) = framing_camera(&mesh, 1.0);
    Ok(Subject {
        name: name.to_string(),
        mesh,
        gpu,
        set,
        world_from_normalized,
    })
}

/// Draws highlights on every face (no §4.2 restriction): the wrong projection of the
/// paper's Fig. 5(a), through [`HighlightPass::draw_list_unrestricted`].
struct Unrestricted {
    base: BaseShading,
    pass: HighlightPass,
    target: OffscreenTarget,
}

impl Unrestricted {
    fn new(ctx: &GpuContext) -> anyhow::Result<Self> {
        let (d, q) = (&ctx.device, &ctx.queue);
        Ok(Self {
            base: BaseShading::new(d, q, TargetFormats::default()),
            pass: HighlightPass::new(d, q, COLOR_FORMAT, DEPTH_FORMAT)?,
            target: OffscreenTarget::new(d, TILE, TILE)?,
        })
    }

    fn render(
        &self,
        ctx: &GpuContext,
        scene: &HighlightScene<'_>,
    ) -> anyhow::Result<image::RgbaImage> {
        let (d, q) = (&ctx.device, &ctx.queue);
        let frame = FrameUniforms::new(&scene.camera, &scene.light);
        self.base.set_frame(q, &frame);
        let object = self.base.create_object(d, &scene.object);
        let mut draw = self.pass.create_draw(d, scene.mesh);
        let list = HighlightPass::draw_list_unrestricted(scene.set, scene.indices);
        let input = FrameInput {
            mesh: scene.mesh,
            indices: scene.indices,
            set: scene.set,
            frame: &frame,
            object: &scene.object,
        };
        self.pass.prepare_with_list(d, q, &mut draw, &input, &list);
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut rpass = self.target.begin_clear_pass(&mut enc, scene.clear);
            self.base.draw(&mut rpass, scene.base, &object, scene.mesh);
            self.pass.draw(&mut rpass, &draw);
        }
        q.submit(Some(enc.finish()));
        Ok(readback_rgba(d, q, &self.target.color)?)
    }
}

/// How a tile's highlights are drawn.
#[derive(Clone, Copy)]
enum Draw<'a> {
    /// The set's §4.2 receivers, through the snapshot renderer.
    Restricted(&'a Renderer),
    /// Every face a receiver (Fig. 5(a)).
    Unrestricted(&'a Unrestricted),
}

/// Renders one tile: base `model` (+ highlights with `controls` when given).
fn tile(
    ctx: &GpuContext,
    renderer: &Renderer,
    s: &mut Subject,
    spin: Mat4,
    model: ShadingModel,
    controls: Option<ProjectorControls>,
    phong_specular: bool,
) -> anyhow::Result<image::RgbaImage> {
    tile_with(
        ctx,
        Draw::Restricted(renderer),
        s,
        spin,
        model,
        controls,
        phong_specular,
    )
}

/// [`tile`] with a choice of receivers.
fn tile_with(
    ctx: &GpuContext,
    draw: Draw<'_>,
    s: &mut Subject,
    spin: Mat4,
    model: ShadingModel,
    controls: Option<ProjectorControls>,
    phong_specular: bool,
) -> anyhow::Result<image::RgbaImage> {
    let (camera, _) = framing_camera(&s.mesh, 1.0);
    let to_light = Vec3::new(0.4, 0.7, 1.0).normalize();
    let light = Light::directional(to_light);
    let world_from_object = spin * s.world_from_normalized;
    if let Some(c) = controls {
        s.set.global = c;
    }
    let le = LightEye::Positions {
        light: to_light * 50.0,
        eye: camera.eye,
    };
    s.set.update(le, world_from_object);
    let k_s = if phong_specular { 0.8 } else { 0.0 };
    let object = ObjectUniforms::new(
        world_from_object,
        Vec3::new(0.8, 0.35, 0.25),
        k_s,
        Vec3::ONE,
        60.0,
    );
    let scene = HighlightScene {
        mesh: &s.gpu,
        indices: &s.mesh.indices,
        set: &s.set,
        object,
        camera,
        light,
        base: model,
        highlights: controls.is_some(),
        clear: [1.0, 1.0, 1.0, 1.0],
    };
    match draw {
        Draw::Restricted(renderer) => Ok(renderer.render(&ctx.device, &ctx.queue, &scene)?),
        Draw::Unrestricted(u) => u.render(ctx, &scene),
    }
}

/// A highlight texture as a tile: the texture (straight alpha) over mid grey, scaled to
/// the tile size.
fn texture_tile(shape: HighlightShape) -> image::RgbaImage {
    let tex = npr_specular::textures::generate(shape, TILE);
    let mut out = image::RgbaImage::from_pixel(TILE, TILE, image::Rgba([96, 96, 96, 255]));
    image::imageops::overlay(&mut out, &tex, 0, 0);
    out
}

/// The tiles in one row.
fn sheet(tiles: &[image::RgbaImage]) -> image::RgbaImage {
    crate::demo::sheet(tiles, tiles.len() as u32)
}

/// Writes the specular figures; returns the files written.
pub fn run(
    ctx: &GpuContext,
    dir: &Path,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<PathBuf>> {
    progress.set_message("specular: curvature of the subjects");
    let renderer = Renderer::new(&ctx.device, &ctx.queue, TILE, TILE)?;
    let mut subjects = vec![
        subject(ctx, "knot", generate::paper_knot(), 3.0)?,
        subject(
            ctx,
            "ellipsoid",
            generate::ellipsoid(1.2, 0.8, 0.6, 24),
            3.0,
        )?,
    ];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        let mesh = npr_geometry::load_obj(crate::fixture_mesh(name))
            .with_context(|| format!("loading fixtures/meshes/{name}"))?;
        subjects.push(subject(ctx, name.trim_end_matches(".obj"), mesh, 3.0)?);
    }
    progress.inc_length(subjects.len() as u64);
    let unrestricted = Unrestricted::new(ctx)?;
    let mut written = Vec::new();
    let mut save =
        |img: &image::RgbaImage, name: &str| crate::demo::save(img, &dir.join(name), &mut written);
    let star = ProjectorControls {
        texture_layer: HighlightShape::Star.layer(),
        sigma: 0.92,
        ..Default::default()
    };
    let disc = ProjectorControls {
        texture_layer: HighlightShape::Disc.layer(),
        ..Default::default()
    };
    let normal_map = ProjectorControls {
        texture_layer: HighlightShape::NormalMap.layer(),
        shininess: 8.0,
        ..Default::default()
    };
    let spin = Mat4::from_rotation_y(0.4);
    // A Phong tile with stylized highlights only (no Phong highlight of its own).
    let phong = |s: &mut Subject, c: ProjectorControls| {
        tile(ctx, &renderer, s, spin, ShadingModel::Phong, Some(c), false)
    };
    for s in &mut subjects {
        progress.set_message(format!("specular: {}", s.name));
        // Fig. 4: original, scaled, rotated, translated.
        let fig4 = [
            star,
            ProjectorControls {
                scale: Vec2::new(1.6, 0.8),
                ..star
            },
            ProjectorControls {
                rotate_rad: 0.6,
                ..star
            },
            ProjectorControls {
                translate: Vec2::new(0.02, 0.1),
                ..star
            },
        ];
        let tiles: Vec<_> = fig4
            .iter()
            .map(|c| {
                tile(
                    ctx,
                    &renderer,
                    s,
                    spin,
                    ShadingModel::Phong,
                    Some(*c),
                    false,
                )
            })
            .collect::<anyhow::Result<_>>()?;
        save(&sheet(&tiles), &format!("specular-fig4-{}.png", s.name))?;
        // Fig. 6: Phong highlight, disc texture, normal-map texture.
        let tiles = vec![
            tile(ctx, &renderer, s, spin, ShadingModel::Phong, None, true)?,
            tile(
                ctx,
                &renderer,
                s,
                spin,
                ShadingModel::Phong,
                Some(disc),
                false,
            )?,
            tile(
                ctx,
                &renderer,
                s,
                spin,
                ShadingModel::Phong,
                Some(normal_map),
                false,
            )?,
        ];
        save(&sheet(&tiles), &format!("specular-fig6-{}.png", s.name))?;
        // Fig. 7: Gouraud and cel base shading with stylized highlights.
        let tiles = vec![
            tile(
                ctx,
                &renderer,
                s,
                spin,
                ShadingModel::Gouraud,
                Some(star),
                false,
            )?,
            tile(
                ctx,
                &renderer,
                s,
                spin,
                ShadingModel::Cel,
                Some(disc),
                false,
            )?,
        ];
        save(&sheet(&tiles), &format!("specular-fig7-{}.png", s.name))?;
        // Fig. 2: a directional texture (the streak, long along u) with up = e_min (the
        // paper's choice, Eq. (7)) and up = e_max.
        let streak = ProjectorControls {
            texture_layer: HighlightShape::Streak.layer(),
            scale: Vec2::splat(1.3),
            ..Default::default()
        };
        // Each figure starts from a fresh set, so no highlight is caught mid-fade.
        s.set.reset();
        let mut tiles = vec![texture_tile(HighlightShape::Streak)];
        for up in [UpAxis::KappaMin, UpAxis::KappaMax] {
            tiles.push(phong(s, ProjectorControls { up, ..streak })?);
        }
        save(&sheet(&tiles), &format!("specular-fig2-{}.png", s.name))?;
        // Fig. 5: a projector enlarged (2.5×; 1.5× on the scans, whose many highlights
        // would cover them) so its frustum reaches other parts of the surface: (a) every
        // face receives, (b) the §4.2 receivers only.
        let enlarge = if matches!(s.name.as_str(), "knot" | "ellipsoid") {
            2.5
        } else {
            1.5
        };
        let big = ProjectorControls {
            scale: Vec2::splat(enlarge),
            ..star
        };
        s.set.reset();
        let unrestricted_tile = tile_with(
            ctx,
            Draw::Unrestricted(&unrestricted),
            s,
            spin,
            ShadingModel::Phong,
            Some(big),
            false,
        )?;
        let restricted_tile = phong(s, big)?;
        save(
            &sheet(&[unrestricted_tile, restricted_tile]),
            &format!("specular-fig5-{}.png", s.name),
        )?;
        // Sizing: the paper's Eq. (8) against ours (the footprint fitted to the region
        // N·H ≥ σ it stylizes, `HighlightSizing::Region`).
        let sizing = crate::gallery::SIZING_SUBJECTS.contains(&s.name.as_str());
        let default_sizing = s.set.sizing;
        for (label, how) in [
            ("paper", npr_specular::HighlightSizing::Paper),
            ("ours", npr_specular::HighlightSizing::Region),
        ]
        .into_iter()
        .filter(|_| sizing)
        {
            s.set.sizing = how;
            s.set.reset();
            let img = phong(s, disc)?;
            save(&img, &format!("specular-sizing-{}-{label}.png", s.name))?;
        }
        s.set.sizing = default_sizing;
        s.set.reset();
        progress.inc(1);
    }
    progress.set_message("specular: Fig. 8, the rotating knot");
    // Fig. 8: the rotating knot as a frame strip and an animated GIF.
    let knot = &mut subjects[0];
    knot.set.reset();
    let mut frames = Vec::new();
    for step in 0..72 {
        let spin =
            Mat4::from_rotation_y((step as f32 * 5.0).to_radians()) * Mat4::from_rotation_x(0.5);
        frames.push(tile(
            ctx,
            &renderer,
            knot,
            spin,
            ShadingModel::Cel,
            Some(star),
            false,
        )?);
    }
    let strip: Vec<_> = frames.iter().step_by(9).cloned().collect();
    save(&sheet(&strip), "specular-fig8-knot-strip.png")?;
    let gif_path = dir.join("specular-fig8-knot.gif");
    npr_app::output::save_gif(&gif_path, &frames, 60)?;
    written.push(gif_path);
    Ok(written)
}
