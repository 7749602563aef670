//! The hatching paper's Fig. 4: a complex 3-D scene with many triangles (the paper: about
//! 1,100,000 at 1280×480): a row of objects on a ground plane, the bunny and Spot among
//! dense procedural ones, a directional light with shadows over the whole row, in pen:
//! `hatching-fig4-scene-pen.png`.
//!
//! `cargo run --release -p npr-hatching --example fig4 -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

mod common;

use common::{Error, Item, Outlines, Scene, fixture, render};
use glam::{Mat4, Vec3};
use npr_geometry::{Mesh, generate};
use npr_gpu::figures::{framing_camera, out_dir, save};
use npr_gpu::{Camera, GpuContext};
use npr_hatching::{HatchParams, ShadowLight, TamParams, TonalArtMap};

/// The size of the scene, as in the paper.
const SIZE: (u32, u32) = (1280, 480);

/// `world_from_object` placing `mesh` scaled to bounding radius `radius`, centred over
/// (x, z) and resting on the ground plane y = 0.
fn on_ground(mesh: &Mesh, radius: f32, (x, z): (f32, f32), turn_deg: f32) -> Mat4 {
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

fn scene() -> Result<Scene, Error> {
    let plane = generate::plane(16.0, 7.0, 16, 8);
    let dirs = vec![Vec3::new(1.0, 0.0, 0.35); plane.positions.len()];
    let mut items = vec![Item {
        mesh: plane,
        world_from_object: Mat4::IDENTITY,
        directions: dirs,
    }];
    let knot = generate::torus_knot(&generate::TorusKnot::trefoil(0.15, 1800, 200));
    // Mesh, bounding radius, (x, z) on the ground, turn about y in degrees.
    let objects: Vec<(Mesh, f32, (f32, f32), f32)> = vec![
        (
            generate::cylinder(0.5, 1.8, 256, 64, true),
            1.0,
            (-6.0, 0.2),
            0.0,
        ),
        (fixture("stanford-bunny")?, 1.2, (-3.7, -0.3), 20.0),
        (generate::torus(1.0, 0.4, 400, 200), 1.1, (-1.2, 0.6), 0.0),
        (knot, 1.3, (1.3, -0.5), 0.0),
        (fixture("spot")?, 1.1, (3.8, 0.4), -35.0),
        (generate::icosphere(6, 1.0), 0.9, (6.0, -0.2), 0.0),
    ];
    for (mesh, radius, at, turn) in objects {
        let world_from_object = on_ground(&mesh, radius, at, turn);
        let directions = npr_hatching::figures::directions(&mesh);
        items.push(Item {
            mesh,
            world_from_object,
            directions,
        });
    }
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.8, 7.4),
        Vec3::new(0.0, 0.9, 0.0),
        SIZE.0 as f32 / SIZE.1 as f32,
    );
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(-1.0, 2.0, 1.1),
        center: Vec3::new(0.0, 0.8, 0.0),
        radius: 8.0,
    };
    Ok(Scene {
        items,
        camera,
        light,
    })
}

fn main() -> Result<(), Error> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    let pen = TonalArtMap::generate(&TamParams::pen())?;
    let scene = scene()?;
    let triangles: usize = scene.items.iter().map(|i| i.mesh.indices.len() / 3).sum();
    let params = [HatchParams::default()];
    let imgs = render(&ctx, &scene, &pen, &params, false, Outlines::Paper, SIZE)?;
    println!(
        "hatching fig4: {} objects, {triangles} triangles, {}×{}",
        scene.items.len(),
        SIZE.0,
        SIZE.1
    );
    save(&imgs[0], &dir.join("hatching-fig4-scene-pen.png"))?;
    Ok(())
}
