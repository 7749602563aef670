//! What the hatching paper's figure examples share: scenes of objects with stroke
//! directions, and one renderer (hatched images with the pen or pencil, the Phong + VSM
//! baseline, ink outlines on our own figures).
//!
//! Stroke directions: the smooth line field fitted to the direction of maximum principal
//! curvature (`npr_hatching::figures::directions`), falling back to the parallels `y × n`
//! on umbilic and flat objects (a sphere, the ground plane).
// Each example uses part of this module.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::figures::{framing_camera, save, sheet};
use npr_gpu::{Camera, GpuContext, GpuMesh, ObjectUniforms};
use npr_hatching::figures::{directions, directions_from};
use npr_hatching::{
    DirectionSource, HatchFrame, HatchFrameSettings, HatchParams, HatchView, SceneSettings,
    ShadowLight, TonalArtMap,
};
use std::path::Path;

/// An example's error.
pub type Error = Box<dyn std::error::Error>;

/// One object of a scene.
pub struct Item {
    pub mesh: Mesh,
    pub world_from_object: Mat4,
    pub directions: Vec<Vec3>,
}

/// Objects, camera and light.
pub struct Scene {
    pub items: Vec<Item>,
    pub camera: Camera,
    pub light: ShadowLight,
}

/// Whether a figure gets ink outlines (`npr_gpu::outline`): on for our own figures, off
/// for those that reproduce the paper's.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Outlines {
    Paper,
    On,
}

/// Renders `scene` hatched with `tam` and each `params` (and, `with_phong`, the Phong +
/// VSM baseline last), with outlines over the hatched images when asked.
pub fn render(
    ctx: &GpuContext,
    scene: &Scene,
    tam: &TonalArtMap,
    params: &[HatchParams],
    with_phong: bool,
    outlines: Outlines,
    (w, h): (u32, u32),
) -> Result<Vec<image::RgbaImage>, Error> {
    let settings = HatchFrameSettings {
        tam: tam.clone(),
        scene: SceneSettings::default(),
    };
    let formats = npr_gpu::TargetFormats::default();
    let mut frame = HatchFrame::new(&ctx.device, &ctx.queue, formats, &settings, (w, h))?;
    let (mut meshes, mut gpu) = (Vec::new(), Vec::new());
    for item in &scene.items {
        let mesh = GpuMesh::upload(&ctx.device, &item.mesh)?;
        let uniforms = ObjectUniforms::new(
            item.world_from_object,
            Vec3::splat(0.9),
            0.35,
            Vec3::ONE,
            24.0,
        );
        let object = frame.create_object(&ctx.device, &mesh, &item.directions)?;
        meshes.push(mesh);
        gpu.push((object, uniforms));
    }
    let outlined: Vec<(&GpuMesh, Mat4)> = meshes
        .iter()
        .zip(&scene.items)
        .map(|(m, item)| (m, item.world_from_object))
        .collect();
    let mut out = Vec::new();
    // Every image is one still frame (clock 0): the same anchors, a new submission each.
    let mut frame_id = npr_gpu::FrameId::default();
    let phong = HatchParams::default();
    let last = with_phong.then_some(&phong);
    for (p, is_phong) in params
        .iter()
        .map(|p| (p, false))
        .chain(last.map(|p| (p, true)))
    {
        frame_id = frame_id.next();
        let view = HatchView {
            frame: frame_id,
            clock: 0,
            camera: &scene.camera,
            light: &scene.light,
            params: p,
        };
        let mut pairs: Vec<_> = gpu.iter_mut().map(|(o, u)| (o, &*u)).collect();
        if is_phong {
            out.push(frame.render_phong(&ctx.device, &ctx.queue, &view, &mut pairs)?);
            continue;
        }
        let mut image = frame.render_hatched(&ctx.device, &ctx.queue, &view, &mut pairs)?;
        if outlines == Outlines::On {
            image = npr_gpu::outline::outline_image(
                &ctx.device,
                &ctx.queue,
                &image,
                &scene.camera,
                &outlined,
                &npr_gpu::outline::OutlineSettings::default(),
            )?;
        }
        out.push(image);
    }
    Ok(out)
}

/// The light of a single framed object.
pub fn single_light() -> ShadowLight {
    ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 1.6, 1.2),
        center: Vec3::ZERO,
        radius: 1.05,
    }
}

/// `mesh` alone, framed at 4:3, with its default stroke directions.
pub fn single(mesh: Mesh) -> Scene {
    let (camera, world_from_object) = framing_camera(&mesh, 4.0 / 3.0);
    let directions = directions(&mesh);
    Scene {
        items: vec![Item {
            mesh,
            world_from_object,
            directions,
        }],
        camera,
        light: single_light(),
    }
}

/// A mesh of `fixtures/meshes/NAME.obj`.
pub fn fixture(name: &str) -> Result<Mesh, Error> {
    let file = npr_gpu::figures::fixture_mesh(&format!("{name}.obj"));
    Ok(npr_geometry::load_obj(&file).map_err(|e| format!("loading {}: {e}", file.display()))?)
}

/// The Fig. 3-like scene: ground plane, and six objects; a directional light with shadows.
pub fn scene_fig3() -> Scene {
    let mut items = Vec::new();
    let plane = generate::plane(9.0, 7.0, 8, 8);
    let dirs = vec![Vec3::new(1.0, 0.0, 0.35); plane.positions.len()];
    items.push(Item {
        mesh: plane,
        world_from_object: Mat4::IDENTITY,
        directions: dirs,
    });
    let mut add = |mesh: Mesh, m: Mat4| {
        let directions = directions(&mesh);
        items.push(Item {
            mesh,
            world_from_object: m,
            directions,
        });
    };
    add(
        generate::icosphere(4, 0.8),
        Mat4::from_translation(Vec3::new(-2.2, 0.8, 0.6)),
    );
    add(
        generate::torus(0.9, 0.35, 96, 48),
        Mat4::from_translation(Vec3::new(0.2, 0.35, 1.4)),
    );
    add(
        generate::cylinder(0.5, 1.8, 64, 16, true),
        Mat4::from_translation(Vec3::new(2.3, 0.9, -0.4)),
    );
    add(
        npr_hatching::figures::knot(),
        Mat4::from_translation(Vec3::new(0.0, 1.3, -1.3)) * Mat4::from_scale(Vec3::splat(0.8)),
    );
    add(
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
    Scene {
        items,
        camera,
        light,
    }
}

/// `STEM.png` in `dir`: `mesh` hatched with the pen and outlines, the paper's rule (raw
/// principal directions, `STEM-principal.png`) beside the default field
/// (`STEM-smooth.png`), turned by `turn` after framing.
///
/// # Errors
/// A GPU or write error.
pub fn directions_sheet(
    ctx: &GpuContext,
    dir: &Path,
    pen: &TonalArtMap,
    (mesh, turn): (&Mesh, Mat4),
    stem: &str,
) -> Result<(), Error> {
    let mut tiles = Vec::new();
    for source in [DirectionSource::Principal, DirectionSource::default()] {
        let mut scene = single(mesh.clone());
        let item = &mut scene.items[0];
        item.directions = directions_from(&item.mesh, &source);
        item.world_from_object = turn * item.world_from_object;
        let params = [HatchParams::default()];
        let imgs = render(ctx, &scene, pen, &params, false, Outlines::On, (640, 480))?;
        save(&imgs[0], &dir.join(format!("{stem}-{}.png", source.name())))?;
        tiles.extend(imgs);
    }
    save(&sheet(&tiles, 2), &dir.join(format!("{stem}.png")))?;
    Ok(())
}

/// `hatching-directions-cad.png`: the procedural CAD parts
/// (`npr_geometry::generate::cad_parts`), pen with outlines, the paper's rule (raw
/// principal directions) beside the default field (cut at creases, straight on flat
/// faces), turned to show top and side faces.
///
/// # Errors
/// A GPU or write error.
pub fn cad_directions(ctx: &GpuContext, dir: &Path, pen: &TonalArtMap) -> Result<(), Error> {
    let turn = Mat4::from_rotation_x(0.45) * Mat4::from_rotation_y(-0.5);
    let parts = generate::cad_parts();
    directions_sheet(ctx, dir, pen, (&parts, turn), "hatching-directions-cad")
}
