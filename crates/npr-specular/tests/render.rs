//! GPU tests of the highlight pass against the CPU model of the same projector: the
//! rendered highlight's centroid, orientation, area and translation. Skips with a printed
//! reason without an adapter, fails under `cargo xtask test` (see `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, Mesh, generate};
use npr_gpu::{GpuMesh, testing};
use npr_specular::snapshot::{HighlightScene, Renderer, light_eye_along};
use npr_specular::{HighlightSet, HighlightShape, ProjectorControls};

const SIZE: u32 = 256;

struct Shot {
    /// Highlight pixels (x, y) with weights.
    pixels: Vec<(Vec2, f32)>,
    /// The projector's centre projected by the camera, in pixels.
    centre_px: Vec2,
    /// The projector's u axis projected, unit, in pixel space (y down).
    axis_u_px: Vec2,
}

fn shoot(
    ctx: &npr_gpu::GpuContext,
    renderer: &Renderer,
    mesh: &Mesh,
    gpu: &GpuMesh,
    controls: ProjectorControls,
) -> Shot {
    let mut set = HighlightSet::new(mesh, &CurvatureOptions::default()).unwrap();
    set.tuning.controls = controls;
    set.tuning.size_cap_radius = Some(10.0);
    let (le, camera, light) = light_eye_along(Vec3::Z, 4.0, 1.0);
    set.update(le, Mat4::IDENTITY);
    assert_eq!(set.highlights().len(), 1);
    let scene = HighlightScene::on_black(gpu, &mesh.indices, &set, camera, light);
    let image = renderer.render(&ctx.device, &ctx.queue, &scene).unwrap();
    let to_px = |p: Vec3| {
        let ndc = camera.clip_from_world().project_point3(p);
        Vec2::new(
            (ndc.x + 1.0) * 0.5 * SIZE as f32,
            (1.0 - ndc.y) * 0.5 * SIZE as f32,
        )
    };
    let h = &set.highlights()[0];
    let c = h.projector.centre_world;
    let centre_px = to_px(c);
    let axis_u_px = (to_px(c + h.projector.axis_u * 0.05) - centre_px).normalize();
    let pixels = image
        .enumerate_pixels()
        .filter(|(_, _, p)| p.0[0] >= 128)
        .map(|(x, y, p)| {
            (
                Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
                f32::from(p.0[0]) / 255.0,
            )
        })
        .collect();
    Shot {
        pixels,
        centre_px,
        axis_u_px,
    }
}

fn centroid(s: &Shot) -> Vec2 {
    let w: f32 = s.pixels.iter().map(|p| p.1).sum();
    s.pixels.iter().map(|(p, k)| *p * *k).sum::<Vec2>() / w
}

/// Orientation (radians, modulo π) of the pixels' principal axis.
fn orientation(s: &Shot) -> f32 {
    let c = centroid(s);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for (p, w) in &s.pixels {
        let d = *p - c;
        xx += w * d.x * d.x;
        xy += w * d.x * d.y;
        yy += w * d.y * d.y;
    }
    0.5 * (2.0 * xy).atan2(xx - yy)
}

/// Signed difference of two axis orientations, wrapped to (−π/2, π/2].
fn angle_diff(a: f32, b: f32) -> f32 {
    use std::f32::consts::PI;
    let d = (a - b).rem_euclid(PI);
    if d > PI / 2.0 { d - PI } else { d }
}

#[test]
fn rendered_highlight_matches_the_projector_model() {
    let Some(ctx) = testing::context_or_skip("rendered_highlight_matches_the_projector_model")
    else {
        return;
    };
    let mesh = generate::icosphere(5, 1.0);
    let gpu = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let renderer = Renderer::new(&ctx.device, &ctx.queue, SIZE, SIZE).unwrap();
    let disc = ProjectorControls {
        texture_layer: HighlightShape::Disc.layer(),
        ..Default::default()
    };

    // Centroid within 2 px of the projected centre.
    let base = shoot(ctx, &renderer, &mesh, &gpu, disc);
    assert!(
        base.pixels.len() > 200,
        "{} highlight pixels",
        base.pixels.len()
    );
    let off = centroid(&base).distance(base.centre_px);
    assert!(off <= 2.0, "centroid {off:.2} px from the projected centre");

    // Area scales with the square of the scale control (±10 %).
    let scaled = shoot(
        ctx,
        &renderer,
        &mesh,
        &gpu,
        ProjectorControls {
            scale: Vec2::splat(1.5),
            ..disc
        },
    );
    let ratio = scaled.pixels.len() as f32 / base.pixels.len() as f32;
    assert!(
        (ratio / 2.25 - 1.0).abs() <= 0.10,
        "area ratio {ratio:.3}, want 2.25"
    );

    // Translation moves the centroid along the projected e_max.
    let moved = shoot(
        ctx,
        &renderer,
        &mesh,
        &gpu,
        ProjectorControls {
            translate: Vec2::new(0.15, 0.0),
            ..disc
        },
    );
    let d = centroid(&moved) - centroid(&base);
    assert!(d.length() > 5.0, "moved only {:.2} px", d.length());
    let along = d.normalize().dot(base.axis_u_px);
    assert!(
        along > 0.98,
        "moved along {d:?}, e_max on screen {:?}",
        base.axis_u_px
    );

    // A directional texture turns with the rotation control (±3°).
    let streak = ProjectorControls {
        texture_layer: HighlightShape::Streak.layer(),
        scale: Vec2::splat(1.3),
        ..Default::default()
    };
    let a0 = orientation(&shoot(ctx, &renderer, &mesh, &gpu, streak));
    assert!(
        angle_diff(a0, base.axis_u_px.y.atan2(base.axis_u_px.x)).abs() < 3f32.to_radians(),
        "streak not along e_max"
    );
    for deg in [20.0f32, 45.0, 70.0] {
        let turned = shoot(
            ctx,
            &renderer,
            &mesh,
            &gpu,
            ProjectorControls {
                rotate_rad: deg.to_radians(),
                ..streak
            },
        );
        let a = orientation(&turned);
        // Counter-clockwise seen from outside is counter-clockwise on screen, which is a
        // negative angle in pixel coordinates (y down).
        let got = -angle_diff(a, a0).to_degrees();
        assert!(
            (got - deg).abs() <= 3.0,
            "rotated {deg}°, measured {got:.2}°"
        );
    }
}

/// The highlight is drawn only where the base surface is (depth LessEqual): an occluder
/// in front hides it.
#[test]
fn highlight_respects_base_depth() {
    let Some(ctx) = testing::context_or_skip("highlight_respects_base_depth") else {
        return;
    };
    let sphere = generate::icosphere(4, 1.0);
    // A small quad-like plate in front of the highlight centre.
    let mut plate = generate::plane(0.6, 0.6, 2, 2);
    let m = Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    for p in &mut plate.positions {
        *p = m.transform_point3(*p);
    }
    // Its shading normals turned 45° away from the light: it only occludes. Facing the
    // light it would be a bright region of its own (N·H ≥ σ over the plate, without an
    // N = H point on its constant normals) and get its own highlight.
    let away = glam::Mat3::from_rotation_x(std::f32::consts::FRAC_PI_4);
    for n in &mut plate.normals {
        *n = away * (glam::Mat3::from_mat4(m) * *n);
    }
    let mut mesh = sphere.clone();
    let off = mesh.positions.len() as u32;
    mesh.positions.extend(&plate.positions);
    mesh.normals.extend(&plate.normals);
    mesh.uvs.extend(&plate.uvs);
    mesh.indices.extend(plate.indices.iter().map(|i| i + off));
    let gpu = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let renderer = Renderer::new(&ctx.device, &ctx.queue, SIZE, SIZE).unwrap();
    let with = shoot(ctx, &renderer, &mesh, &gpu, ProjectorControls::default());
    let gpu_sphere = GpuMesh::upload(&ctx.device, &sphere).unwrap();
    let without = shoot(
        ctx,
        &renderer,
        &sphere,
        &gpu_sphere,
        ProjectorControls::default(),
    );
    assert!(without.pixels.len() > 200);
    assert!(
        with.pixels.len() < without.pixels.len() / 20,
        "occluded highlight still shows {} of {} pixels",
        with.pixels.len(),
        without.pixels.len()
    );
}
