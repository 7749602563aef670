//! GPU test of §3.4 edits on a shape where the answer is known: on a unit sphere, the one
//! highlight is dragged by a footprint half extent along `e_max`, turned by 45° and grown
//! 1.5×; each time the drawn footprint (the footprint texture: the ellipse inscribed in
//! the projector's square) is compared with the same edited ellipse projected analytically
//! (a ray per pixel against the exact sphere, the projector's orthographic map, and §4.2's
//! `N·N_max > 0`): area within 5 %, centroid within 2 px.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, generate};
use npr_gpu::{GpuMesh, testing};
use npr_specular::snapshot::{HighlightScene, Renderer, light_eye_along};
use npr_specular::{HighlightBoundary, HighlightControls, HighlightSet, Projector};

const SIZE: u32 = 320;

/// Pixels (centres) and their count where the footprint is drawn (linear red ≥ 0.5).
fn drawn(image: &image::RgbaImage) -> (usize, Vec2) {
    let mut n = 0;
    let mut sum = Vec2::ZERO;
    for (x, y, p) in image.enumerate_pixels() {
        if npr_gpu::cpu_twin::srgb_to_linear(f32::from(p.0[0]) / 255.0) >= 0.5 {
            n += 1;
            sum += Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        }
    }
    (n, sum / n.max(1) as f32)
}

/// The analytic footprint: pixels whose ray hits the unit sphere at a point inside the
/// projector's ellipse (alpha ≥ 0.5 of the footprint texture: radius `1 − 1/size`) and
/// depth range, facing the projector.
fn analytic(camera: &npr_gpu::Camera, projector: &Projector, texture: u32) -> (usize, Vec2) {
    let inverse = camera.clip_from_world().inverse();
    let rim = 1.0 - 1.0 / texture as f32;
    let mut n = 0;
    let mut sum = Vec2::ZERO;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let ndc = Vec2::new(
                (x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / SIZE as f32 * 2.0,
            );
            let near = inverse.project_point3(ndc.extend(0.0));
            let far = inverse.project_point3(ndc.extend(1.0));
            let d = (far - near).normalize();
            // |near + t d|² = 1.
            let b = near.dot(d);
            let disc = b * b - (near.length_squared() - 1.0);
            if disc < 0.0 {
                continue;
            }
            let p = near + d * (-b - disc.sqrt());
            let q = projector.ndc(p);
            if q.truncate().length() <= rim
                && (0.0..=1.0).contains(&q.z)
                && p.dot(projector.normal) > 0.0
            {
                n += 1;
                sum += Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            }
        }
    }
    (n, sum / n.max(1) as f32)
}

#[test]
fn dragged_turned_and_grown_highlights_match_the_analytic_footprint() {
    let Some(ctx) = testing::context_or_skip(
        "dragged_turned_and_grown_highlights_match_the_analytic_footprint",
    ) else {
        return;
    };
    let mesh = generate::icosphere(5, 1.0);
    let gpu = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let texture = 256;
    let renderer = Renderer::with_textures(
        &ctx.device,
        &ctx.queue,
        SIZE,
        SIZE,
        &[npr_specular::textures::footprint(texture)],
        &[false],
    )
    .unwrap();
    // Light and eye from the same side, a little off the view axis so the highlight is
    // not at the image centre.
    let (le, camera, light) = light_eye_along(Vec3::new(0.2, 0.3, 1.0), 4.0, 1.0);
    let render = |set: &HighlightSet| {
        let scene = HighlightScene::on_black(&gpu, &mesh.indices, set, camera, light);
        drawn(&renderer.render(&ctx.device, &ctx.queue, &scene).unwrap())
    };

    {
        let mut set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        assert_eq!(set.tuning.boundary, HighlightBoundary::Smooth);
        set.update(le, Mat4::IDENTITY);
        assert_eq!(set.highlights().len(), 1, "one highlight on a sphere");
        let id = set.highlights()[0].id;
        let half = set.highlights()[0].projector.half_extent;
        let edits = [
            ("unedited", HighlightControls::default()),
            (
                "dragged",
                HighlightControls {
                    translate: Vec2::new(half.x, 0.0),
                    ..Default::default()
                },
            ),
            (
                "turned",
                HighlightControls {
                    rotate_rad: 45f32.to_radians(),
                    ..Default::default()
                },
            ),
            (
                "grown",
                HighlightControls {
                    scale: Vec2::splat(1.5),
                    ..Default::default()
                },
            ),
        ];
        for (name, controls) in edits {
            *set.controls_mut(id) = controls;
            set.update(le, Mat4::IDENTITY);
            let h = &set.highlights()[0];
            assert_eq!(h.id, id, "{name}: the edited highlight keeps its identity");
            let (got, got_centre) = render(&set);
            let (want, want_centre) = analytic(&camera, &h.projector, texture);
            assert!(want > 1000, "{name}: {want} px in the analytic footprint");
            let area_error = (got as f32 / want as f32 - 1.0).abs();
            println!(
                "{name}: drawn {got} px, analytic {want} px, centroid {:.2} px off",
                got_centre.distance(want_centre)
            );
            assert!(
                area_error <= 0.05,
                "{name}: drawn {got} px, analytic {want} px ({:+.1} %)",
                100.0 * (got as f32 / want as f32 - 1.0)
            );
            let off = got_centre.distance(want_centre);
            assert!(off <= 2.0, "{name}: centroid {off:.2} px off");
        }
    }
}
