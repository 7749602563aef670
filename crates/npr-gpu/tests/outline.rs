//! GPU tests of the outline pass (`npr_gpu::outline`): the GPU lines equal the CPU rule on
//! the read-back G-buffer, and a sphere's silhouette is the analytic circle.
//! Each test skips with a printed reason when no adapter exists, except under
//! `cargo xtask test` where that is a failure (see `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::generate;
use npr_gpu::outline::{NormalDepthPass, NormalDepthTarget, OutlineSettings, outline_mask_cpu};
use npr_gpu::{Camera, GpuContext, GpuMesh, testing};

/// Renders `objects`, reads the G-buffer back and draws black outlines over white.
/// Returns (G-buffer, GPU line mask).
fn render(
    ctx: &GpuContext,
    objects: &[(&GpuMesh, Mat4)],
    camera: &Camera,
    settings: &OutlineSettings,
    (w, h): (u32, u32),
) -> (Vec<[f32; 4]>, Vec<bool>) {
    let (device, queue) = (&ctx.device, &ctx.queue);
    let gbuffer = NormalDepthTarget::new(device, w, h).unwrap();
    let prepass = NormalDepthPass::new(device, queue);
    let frame = npr_gpu::FrameId::default();
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut bound = Vec::new();
    for (mesh, m) in objects {
        let mut object = prepass.create_object(device, mesh);
        let input = npr_gpu::outline::NormalDepthInput {
            frame,
            camera,
            world_from_object: *m,
        };
        let prepared = prepass.prepare(queue, &mut object, &input).unwrap();
        bound.push((object, prepared));
    }
    let list: Vec<_> = bound.iter().map(|(o, p)| (o, p)).collect();
    prepass.record(&mut encoder, &gbuffer, &list).unwrap();
    queue.submit(Some(encoder.finish()));
    let g = gbuffer.read(device, queue).unwrap();
    // The lines over white, drawn by the same helper users call.
    let white = image::RgbaImage::from_pixel(w, h, image::Rgba([255; 4]));
    let img =
        npr_gpu::outline::outline_image(device, queue, &white, camera, objects, settings).unwrap();
    let mask = img.pixels().map(|p| p[0] < 128).collect();
    (g, mask)
}

/// GPU and CPU differ only where a float comparison lands within rounding of its
/// threshold: allowed, 0.5 % of the line pixels.
fn assert_masks_agree(gpu: &[bool], cpu: &[bool]) {
    let lines = cpu.iter().filter(|&&b| b).count();
    let diff = gpu.iter().zip(cpu).filter(|(a, b)| a != b).count();
    eprintln!("{lines} line pixels, {diff} differ");
    assert!(lines > 100, "only {lines} line pixels");
    assert!(
        diff * 200 <= lines,
        "{diff} pixels differ of {lines} line pixels"
    );
}

#[test]
fn sphere_silhouette_is_the_analytic_circle() {
    let Some(ctx) = testing::context_or_skip("sphere_silhouette_is_the_analytic_circle") else {
        return;
    };
    let (w, h) = (256u32, 256u32);
    let mesh = GpuMesh::upload(&ctx.device, &generate::icosphere(5, 1.0)).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0);
    let settings = OutlineSettings {
        width_px: 1.0,
        ..Default::default()
    };
    let (g, gpu) = render(ctx, &[(&mesh, Mat4::IDENTITY)], &camera, &settings, (w, h));
    let cpu = outline_mask_cpu(w, h, &g, &settings).unwrap();
    assert_masks_agree(&gpu, &cpu);

    // Silhouette of a unit sphere seen from distance 4: angular radius asin(1/4).
    let radius_px = (0.25f32.asin().tan() / (camera.fov_y_rad * 0.5).tan()) * h as f32 * 0.5;
    let mut sectors = [false; 64];
    for y in 0..h {
        for x in 0..w {
            if !gpu[(y * w + x) as usize] {
                continue;
            }
            let (dx, dy) = (
                x as f32 + 0.5 - w as f32 * 0.5,
                y as f32 + 0.5 - h as f32 * 0.5,
            );
            let r = (dx * dx + dy * dy).sqrt();
            assert!(
                (r - radius_px).abs() <= 1.0,
                "line pixel ({x}, {y}) at {r} px, circle {radius_px} px"
            );
            let a = dy.atan2(dx) + std::f32::consts::PI;
            sectors[((a / std::f32::consts::TAU * 64.0) as usize).min(63)] = true;
        }
    }
    assert!(
        sectors.iter().all(|&s| s),
        "the circle is not closed: {sectors:?}"
    );
}

#[test]
fn gpu_outlines_match_the_cpu_rule_on_a_scene() {
    let Some(ctx) = testing::context_or_skip("gpu_outlines_match_the_cpu_rule_on_a_scene") else {
        return;
    };
    let (w, h) = (240u32, 180u32);
    let torus = GpuMesh::upload(&ctx.device, &generate::torus(1.0, 0.35, 64, 32)).unwrap();
    let cylinder =
        GpuMesh::upload(&ctx.device, &generate::cylinder(0.4, 1.2, 32, 4, true)).unwrap();
    let objects = [
        (&torus, Mat4::from_rotation_x(0.6)),
        (&cylinder, Mat4::from_translation(Vec3::new(0.9, 0.2, -0.8))),
    ];
    let camera = Camera::look_at(Vec3::new(0.5, 1.5, 3.5), Vec3::ZERO, w as f32 / h as f32);
    for settings in [
        OutlineSettings::default(),
        OutlineSettings {
            width_px: 1.0,
            crease_angle_deg: 30.0,
            ..Default::default()
        },
    ] {
        let (g, gpu) = render(ctx, &objects, &camera, &settings, (w, h));
        let cpu = outline_mask_cpu(w, h, &g, &settings).unwrap();
        assert_masks_agree(&gpu, &cpu);
    }
}
