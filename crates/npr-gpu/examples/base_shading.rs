//! npr-gpu's base shadings, the ground every technique draws over: Phong, Gouraud and cel
//! (with ink outlines, `npr_gpu::outline`, as cartoons are drawn) of the procedural
//! fixtures and the real meshes in `fixtures/meshes/`, `base-MESH-MODEL.png` each and the
//! sheet `base-shading-sheet.png`.
//!
//! `cargo run --release -p npr-gpu --example base_shading -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

use glam::Vec3;
use npr_geometry::{Mesh, generate};
use npr_gpu::figures::{fixture_mesh, framing_camera, out_dir, paste, save};
use npr_gpu::snapshot::{BaseScene, render_base};
use npr_gpu::{GpuContext, GpuMesh, Light, ObjectUniforms, ShadingModel};

/// The procedural meshes, plus the real meshes from `fixtures/meshes/`.
fn meshes() -> Result<Vec<(String, Mesh)>, Box<dyn std::error::Error>> {
    let mut meshes = vec![
        ("sphere".to_string(), generate::icosphere(4, 1.0)),
        ("torus".to_string(), generate::torus(1.0, 0.4, 96, 48)),
        (
            "ellipsoid".to_string(),
            generate::ellipsoid(1.2, 0.8, 0.6, 24),
        ),
        (
            "cylinder".to_string(),
            generate::cylinder(0.6, 1.6, 64, 16, true),
        ),
        ("knot".to_string(), generate::paper_knot()),
    ];
    for name in ["spot.obj", "stanford-bunny.obj"] {
        let file = fixture_mesh(name);
        let mesh = npr_geometry::load_obj(&file)
            .map_err(|e| format!("loading {}: {e}", file.display()))?;
        meshes.push((name.trim_end_matches(".obj").to_string(), mesh));
    }
    Ok(meshes)
}

/// Base shadings (Phong, Gouraud, cel with outlines) of every demo mesh, one PNG each
/// and a sheet.
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = out_dir()?;
    let ctx = GpuContext::new()?;
    const TILE: u32 = 320;
    let meshes = meshes()?;
    let models = ShadingModel::ALL;
    let mut sheet = image::RgbaImage::new(TILE * models.len() as u32, TILE * meshes.len() as u32);
    let light = Light::directional(Vec3::new(1.0, 1.5, 2.0));
    for (row, (name, mesh)) in meshes.iter().enumerate() {
        let gpu = GpuMesh::upload(&ctx.device, mesh)?;
        let (camera, world_from_object) = framing_camera(mesh, 1.0);
        let object = ObjectUniforms::new(
            world_from_object,
            Vec3::new(0.75, 0.45, 0.3),
            0.5,
            Vec3::ONE,
            40.0,
        );
        let scene = BaseScene {
            objects: &[(&gpu, object)],
            camera,
            light,
            clear: [1.0, 1.0, 1.0, 1.0],
        };
        for (col, model) in models.iter().enumerate() {
            let mut image = render_base(&ctx.device, &ctx.queue, &scene, *model, TILE, TILE)?;
            if *model == ShadingModel::Cel {
                // Cel shading with ink outlines (npr_gpu::outline), as cartoons are drawn.
                let objects = [(&gpu, world_from_object)];
                let settings = npr_gpu::outline::OutlineSettings::default();
                image = npr_gpu::outline::outline_image(
                    &ctx.device,
                    &ctx.queue,
                    &image,
                    &camera,
                    &objects,
                    &settings,
                )?;
            }
            let path = dir.join(format!("base-{name}-{}.png", model.name()));
            save(&image, &path)?;
            paste(&mut sheet, &image, col as u32 * TILE, row as u32 * TILE);
        }
    }
    save(&sheet, &dir.join("base-shading-sheet.png"))?;
    Ok(())
}
