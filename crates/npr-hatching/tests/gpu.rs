//! GPU tests of the hatching pass and its inputs against the CPU reference and analytic
//! expectations. Each test fails when no adapter exists, unless `NPR_SKIP_GPU=1` asks to
//! skip (see `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_gpu::{Camera, FrameId, GpuMesh, ObjectUniforms, TargetFormats, testing};
use npr_hatching::{
    BlendMode, CpuHatcher, HatchError, HatchFrame, HatchFrameSettings, HatchInputs, HatchParams,
    HatchView, SceneSettings, ShadowLight, StrokeSpace, TamParams, TamStyle, TonalArtMap,
    VsmSettings, hatch_image_gpu,
};
use std::f32::consts::PI;

/// Per-channel comparison of two sRGB images: (mean absolute difference in code values,
/// fraction of pixels whose largest channel difference exceeds 2 code values).
fn compare(a: &image::RgbaImage, b: &image::RgbaImage) -> (f64, f64) {
    assert_eq!(a.dimensions(), b.dimensions());
    let (mut sum, mut bad) = (0u64, 0usize);
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..3)
            .map(|c| (i32::from(p[c]) - i32::from(q[c])).unsigned_abs())
            .max()
            .unwrap_or(0);
        sum += u64::from(d);
        if d > 2 {
            bad += 1;
        }
    }
    let n = (a.width() * a.height()) as f64;
    (sum as f64 / n, bad as f64 / n)
}

/// GPU = CPU on the same inputs: a tone ramp with a swirling θ field, both styles, all
/// three modes, a coloured ink and paper, short strokes (`stroke_length`) on for pen. Bound: mean |difference| ≤ 0.25 code values and
/// at most 0.5 % of pixels differing by more than 2 code values (float rounding, e.g.
/// fused multiply-adds, can move a rotated coordinate across a texel edge).
#[test]
fn gpu_hatching_equals_cpu_reference() {
    let Some(ctx) = testing::context_or_skip("gpu_hatching_equals_cpu_reference") else {
        return;
    };
    let (w, h) = (320u32, 240u32);
    let inputs = HatchInputs::from_fn(w, h, |x, y| {
        let tone = x / w as f32;
        let theta = 0.02 * x + 0.015 * y + (0.03 * y).sin();
        (tone, theta)
    })
    .unwrap()
    // Turn rate rising down the image: 0 to 0.15 rad/pixel (StrokeLength's calm 0.02 and
    // busy 0.1 in between).
    .with_turn(
        (0..w * h)
            .map(|i| 0.15 * (i / w) as f32 / h as f32)
            .collect(),
    )
    .unwrap();
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        let tam = TonalArtMap::generate(&TamParams::for_style(style)).unwrap();
        for (mode, space) in BlendMode::ALL
            .into_iter()
            .flat_map(|m| StrokeSpace::ALL.map(|s| (m, s)))
        {
            let params = HatchParams {
                mode,
                space,
                bins: 18,
                stroke_scale: 1.5,
                ink: [0.05, 0.02, 0.1],
                paper: [0.95, 0.9, 0.8],
                // Short strokes on for the pen map: the turn field below spans calm,
                // blended and all-short pixels.
                stroke_length: (style == TamStyle::Pen).then(Default::default),
            };
            let gpu = hatch_image_gpu(&ctx.device, &ctx.queue, &inputs, &tam, &params).unwrap();
            let cpu = CpuHatcher::new(&tam, &params)
                .unwrap()
                .hatch_rgba8(&inputs)
                .unwrap();
            let (mean, frac) = compare(&gpu, &cpu);
            eprintln!(
                "{style:?} {mode:?} {space:?}: mean |Δ| {mean:.4}, pixels > 2: {:.4} %",
                frac * 100.0
            );
            // The surface space reads the map filtered: the GPU's sampler weighs texels
            // with a few sub-texel bits (8 on lavapipe), the CPU in f32.
            let bound = match space {
                StrokeSpace::Screen => 0.25,
                StrokeSpace::Surface => 0.5,
            };
            assert!(
                mean <= bound && frac <= 0.005,
                "{style:?} {mode:?} {space:?}: mean {mean}, fraction {frac}; {}",
                npr_gpu::testing::image_failure(&format!("hatch-{style:?}-{mode:?}"), &cpu, &gpu)
            );
        }
    }
}

/// Analytic stroke directions for a sphere: the projection of the world y axis onto the
/// tangent plane (the meridian direction, a principal direction of the sphere).
fn meridian_directions(mesh: &npr_geometry::Mesh) -> Vec<Vec3> {
    mesh.normals
        .iter()
        .map(|n| (Vec3::Y - *n * n.dot(Vec3::Y)).normalize_or_zero())
        .collect()
}

/// A hatching frame of `size` for `tam`, with `vsm` and the default anchor period.
fn hatch_frame(
    ctx: &npr_gpu::GpuContext,
    tam: &TonalArtMap,
    vsm: VsmSettings,
    size: (u32, u32),
) -> HatchFrame {
    let settings = HatchFrameSettings {
        tam: tam.clone(),
        scene: SceneSettings {
            vsm,
            ..Default::default()
        },
    };
    HatchFrame::new(
        &ctx.device,
        &ctx.queue,
        TargetFormats::default(),
        &settings,
        size,
    )
    .unwrap()
}

/// One still view (anchor clock 0) as submission `frame`.
fn still<'a>(
    frame: u64,
    camera: &'a Camera,
    light: &'a ShadowLight,
    params: &'a HatchParams,
) -> HatchView<'a> {
    HatchView {
        frame: FrameId(frame),
        clock: 0,
        camera,
        light,
        params,
    }
}

/// The whole frame on the GPU (VSM, G-buffer, hatching) equals the CPU reference applied
/// to the G-buffer read back (same bound as above), the G-buffer's θ on the sphere's
/// central column is the meridian's screen direction (vertical, π/2, within 2°), and the
/// tone there follows Lambert's law for the unshadowed front (within 0.03).
#[test]
fn scene_frame_matches_cpu_on_its_gbuffer() {
    let Some(ctx) = testing::context_or_skip("scene_frame_matches_cpu_on_its_gbuffer") else {
        return;
    };
    let (w, h) = (200u32, 160u32);
    let mesh = npr_geometry::generate::icosphere(4, 1.0);
    let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let params = HatchParams::default();
    let mut frame = hatch_frame(ctx, &tam, VsmSettings::default(), (w, h));
    // Diffuse only, so tone = ambient + N·L.
    let object_uniforms = ObjectUniforms::new(Mat4::IDENTITY, Vec3::ONE, 0.0, Vec3::ZERO, 1.0);
    let mut object = frame
        .create_object(&ctx.device, &gpu_mesh, &meridian_directions(&mesh))
        .unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, w as f32 / h as f32);
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(0.0, 0.0, 1.0),
        center: Vec3::ZERO,
        radius: 1.5,
    };
    let view = still(0, &camera, &light, &params);
    let objects = &mut [(&mut object, &object_uniforms)];
    let hatched = frame
        .render_hatched(&ctx.device, &ctx.queue, &view, objects)
        .unwrap();
    let gbuffer = frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
    let cpu = CpuHatcher::new(&tam, &params)
        .unwrap()
        .hatch_rgba8(&gbuffer)
        .unwrap();
    let (mean, frac) = compare(&hatched, &cpu);
    eprintln!(
        "scene frame: mean |Δ| {mean:.4}, pixels > 2: {:.4} %",
        frac * 100.0
    );
    assert!(
        mean <= 0.25 && frac <= 0.005,
        "mean {mean}, fraction {frac}"
    );
    // Central column, rows over the sphere's middle: the meridian is vertical on screen.
    let x = w / 2;
    let inv = camera.clip_from_world().inverse();
    for y in (h / 2 - 30..h / 2 + 30).step_by(5) {
        let i = (y * w + x) as usize;
        let theta = gbuffer.theta()[i];
        assert!(
            (theta - PI / 2.0).abs() < 2f32.to_radians(),
            "row {y}: θ {theta}"
        );
        // Analytic tone: ray through the pixel centre, hit point normal, N·L + ambient.
        let ndc = Vec3::new(
            (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
            1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            0.0,
        );
        let near = inv.project_point3(ndc);
        let far = inv.project_point3(ndc.with_z(1.0));
        let d = (far - near).normalize();
        let o = camera.eye;
        let b = o.dot(d);
        let t = -b - (b * b - (o.length_squared() - 1.0)).sqrt();
        let n = (o + d * t).normalize();
        let expected = 0.1 + n.z.max(0.0);
        let tone = gbuffer.tone()[i];
        assert!(
            (tone - expected.min(1.0)).abs() < 0.03,
            "row {y}: tone {tone} vs {expected}"
        );
    }
    // Background is paper: tone 1.
    assert_eq!(gbuffer.tone()[0], 1.0);
}

/// Variance shadow map: a sphere over a plane, lit at 45°, seen from above. Compared with
/// the same frame without shadows, at least 1,000 pixels (the shadow on the plane, about
/// 2,000 px expected) get darker by more than 0.3 in tone, and none gets lighter by more
/// than 0.02.
#[test]
fn vsm_darkens_the_shadowed_plane() {
    let Some(ctx) = testing::context_or_skip("vsm_darkens_the_shadowed_plane") else {
        return;
    };
    let (w, h) = (160u32, 160u32);
    let sphere = npr_geometry::generate::icosphere(3, 0.5);
    let plane = npr_geometry::generate::plane(4.0, 4.0, 4, 4);
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 5.0, 0.01), Vec3::ZERO, 1.0);
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(1.0, 1.0, 0.0),
        center: Vec3::ZERO,
        radius: 3.0,
    };
    let mut tones = Vec::new();
    for enabled in [true, false] {
        let vsm = VsmSettings {
            enabled,
            size: 512,
            ..Default::default()
        };
        let mut frame = hatch_frame(ctx, &tam, vsm, (w, h));
        let mut objs = Vec::new();
        for (mesh, m) in [
            (&sphere, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0))),
            (&plane, Mat4::IDENTITY),
        ] {
            let g = GpuMesh::upload(&ctx.device, mesh).unwrap();
            let u = ObjectUniforms::new(m, Vec3::ONE, 0.0, Vec3::ZERO, 1.0);
            let dirs = vec![Vec3::X; mesh.positions.len()];
            let o = frame.create_object(&ctx.device, &g, &dirs).unwrap();
            objs.push((g, o, u));
        }
        let params = HatchParams::default();
        let view = still(0, &camera, &light, &params);
        let mut refs: Vec<_> = objs.iter_mut().map(|(_, o, u)| (o, &*u)).collect();
        frame
            .render_hatched(&ctx.device, &ctx.queue, &view, &mut refs)
            .unwrap();
        tones.push(frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap());
    }
    let (on, off) = (tones[0].tone(), tones[1].tone());
    let darker = on.iter().zip(off).filter(|(a, b)| **a < **b - 0.3).count();
    let lighter = on.iter().zip(off).filter(|(a, b)| **a > **b + 0.02).count();
    eprintln!("VSM: {darker} pixels darker by > 0.3, {lighter} lighter");
    assert!(darker >= 1000, "{darker}");
    assert_eq!(lighter, 0);
}

/// Typed errors and no panics on the GPU side: wrong direction count, bad parameters,
/// zero sizes, NaN directions.
#[test]
fn gpu_bad_inputs_are_typed_errors() {
    let Some(ctx) = testing::context_or_skip("gpu_bad_inputs_are_typed_errors") else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pencil()).unwrap();
    assert!(matches!(
        npr_hatching::hatch_image_gpu(
            &ctx.device,
            &ctx.queue,
            &HatchInputs::from_fn(8, 8, |x, _| (x, 0.0)).unwrap(),
            &tam,
            &HatchParams {
                bins: 30,
                ..Default::default()
            },
        ),
        Err(HatchError::InvalidParams { .. })
    ));
    assert!(matches!(
        npr_hatching::GBuffer::new(&ctx.device, 0, 10),
        Err(HatchError::InvalidSize { .. })
    ));
    let mut frame = hatch_frame(ctx, &tam, VsmSettings::default(), (64, 48));
    let mesh = npr_geometry::generate::icosphere(2, 1.0);
    let g = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let u = ObjectUniforms::default_material(Mat4::IDENTITY);
    assert!(matches!(
        frame.create_object(&ctx.device, &g, &[Vec3::X; 3]),
        Err(HatchError::LengthMismatch { .. })
    ));
    let nan = vec![Vec3::NAN; mesh.positions.len()];
    let mut o = frame.create_object(&ctx.device, &g, &nan).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 64.0 / 48.0);
    let light = ShadowLight::Directional {
        towards_light: Vec3::Z,
        center: Vec3::ZERO,
        radius: 1.0,
    };
    let params = HatchParams::default();
    let view = still(0, &camera, &light, &params);
    let img = frame
        .render_hatched(&ctx.device, &ctx.queue, &view, &mut [(&mut o, &u)])
        .unwrap();
    assert_eq!(img.dimensions(), (64, 48));
    let gb = frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
    assert!(
        gb.theta().iter().all(|t| *t == 0.0),
        "NaN directions give θ = 0"
    );
}

/// Spot light: a plane lit by a spot light 3 units straight above it with a 20° cone
/// (full strength within 15°), a small sphere in the beam, seen obliquely so that the
/// shadow is visible. Inside the cone and away from the shadow the tone is lit (> 0.5);
/// outside the cone it is the ambient term (0.1 ± 0.02); the sphere casts a shadow: at
/// least 200 pixels of the beam darker than 0.3.
#[test]
fn spot_light_cone_and_shadow() {
    let Some(ctx) = testing::context_or_skip("spot_light_cone_and_shadow") else {
        return;
    };
    let (w, h) = (160u32, 160u32);
    let plane = npr_geometry::generate::plane(6.0, 6.0, 8, 8);
    let sphere = npr_geometry::generate::icosphere(3, 0.25);
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let mut frame = hatch_frame(ctx, &tam, VsmSettings::default(), (w, h));
    let mut objs = Vec::new();
    for (mesh, m) in [
        (&plane, Mat4::IDENTITY),
        (&sphere, Mat4::from_translation(Vec3::new(0.3, 1.5, 0.0))),
    ] {
        let g = GpuMesh::upload(&ctx.device, mesh).unwrap();
        let u = ObjectUniforms::new(m, Vec3::ONE, 0.0, Vec3::ZERO, 1.0);
        let dirs = vec![Vec3::X; mesh.positions.len()];
        let o = frame.create_object(&ctx.device, &g, &dirs).unwrap();
        objs.push((g, o, u));
    }
    let camera = Camera::look_at(Vec3::new(4.0, 5.0, 0.01), Vec3::ZERO, 1.0);
    let light = ShadowLight::Spot {
        position: Vec3::new(0.0, 3.0, 0.0),
        target: Vec3::ZERO,
        outer_angle_rad: 20f32.to_radians(),
        inner_angle_rad: 15f32.to_radians(),
        range: 10.0,
    };
    let params = HatchParams::default();
    let view = still(0, &camera, &light, &params);
    let mut refs: Vec<_> = objs.iter_mut().map(|(_, o, u)| (o, &*u)).collect();
    frame
        .render_hatched(&ctx.device, &ctx.queue, &view, &mut refs)
        .unwrap();
    let g = frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
    let inv = camera.clip_from_world().inverse();
    let (mut lit, mut dark_in_beam, mut outside) = (0, 0, Vec::new());
    for y in 0..h {
        for x in 0..w {
            // The plane point under pixel (x, y).
            let ndc = |z: f32| {
                Vec3::new(
                    (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                    z,
                )
            };
            let (a, b) = (inv.project_point3(ndc(0.0)), inv.project_point3(ndc(1.0)));
            let p = a + (b - a) * (a.y / (a.y - b.y));
            let r = p.length();
            let tone = g.tone()[(y * w + x) as usize];
            // Cone radius on the plane: 3 tan 15° = 0.80 (full), 3 tan 20° = 1.09 (zero).
            // Shadow centre on the plane: (0.6, 0, 0), radius ≈ 0.5; the sphere itself hides
            // the plane around (−1.3, 0, 0) from this camera.
            let in_shadow = (p - Vec3::new(0.6, 0.0, 0.0)).length() < 0.65;
            let behind_sphere = (p - Vec3::new(-1.3, 0.0, 0.0)).length() < 0.7;
            if r < 0.7 && !in_shadow {
                assert!(tone > 0.5, "lit pixel ({x}, {y}) at {p}: tone {tone}");
                lit += 1;
            }
            if r < 0.7 && tone < 0.3 {
                dark_in_beam += 1;
            }
            if r > 1.2 && r < 2.5 && !behind_sphere {
                outside.push(tone);
            }
        }
    }
    eprintln!("spot: {lit} lit pixels checked, {dark_in_beam} shadowed in the beam");
    assert!(lit > 200);
    assert!(dark_in_beam >= 200, "{dark_in_beam}");
    assert!(
        outside.iter().all(|t| (t - 0.1).abs() <= 0.02),
        "outside the cone"
    );
}

/// Switching style on a live frame ([`HatchFrame::set_tam`], pen → pencil) gives what the
/// CPU reference draws with the pencil map on the same G-buffer (same bound as above).
#[test]
fn switching_style_rebinds_the_map() {
    let Some(ctx) = testing::context_or_skip("switching_style_rebinds_the_map") else {
        return;
    };
    let (w, h) = (128u32, 96u32);
    let pen = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let pencil = TonalArtMap::generate(&TamParams::pencil()).unwrap();
    let params = HatchParams::default();
    let mut frame = hatch_frame(ctx, &pen, VsmSettings::default(), (w, h));
    let mesh = npr_geometry::generate::icosphere(3, 1.0);
    let g = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let u = ObjectUniforms::default_material(Mat4::IDENTITY);
    let mut o = frame
        .create_object(&ctx.device, &g, &meridian_directions(&mesh))
        .unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 3.5), Vec3::ZERO, w as f32 / h as f32);
    let light = ShadowLight::Directional {
        towards_light: Vec3::new(1.0, 1.0, 1.0),
        center: Vec3::ZERO,
        radius: 1.2,
    };
    frame.set_tam(&ctx.device, &ctx.queue, &pencil).unwrap();
    let view = still(0, &camera, &light, &params);
    let img = frame
        .render_hatched(&ctx.device, &ctx.queue, &view, &mut [(&mut o, &u)])
        .unwrap();
    let gb = frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
    let cpu = CpuHatcher::new(&pencil, &params)
        .unwrap()
        .hatch_rgba8(&gb)
        .unwrap();
    let (mean, frac) = compare(&img, &cpu);
    assert!(
        mean <= 0.25 && frac <= 0.005,
        "mean {mean}, fraction {frac}"
    );
}

/// The sign convention of θ: a quad facing the camera (world x right, y up on screen)
/// with stroke direction (1, 1, 0) gets θ = π/4 (counter-clockwise from +x, y up), and
/// (1, −1, 0) gets 3π/4, within 1° at the centre.
#[test]
fn gbuffer_theta_is_counter_clockwise_on_screen() {
    let Some(ctx) = testing::context_or_skip("gbuffer_theta_is_counter_clockwise_on_screen") else {
        return;
    };
    let (w, h) = (96u32, 64u32);
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let mut frame = hatch_frame(ctx, &tam, VsmSettings::default(), (w, h));
    // The xz plane turned to face +z.
    let plane = npr_geometry::generate::plane(2.0, 2.0, 2, 2);
    let m = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let g = GpuMesh::upload(&ctx.device, &plane).unwrap();
    let u = ObjectUniforms::default_material(m);
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, w as f32 / h as f32);
    let light = ShadowLight::Directional {
        towards_light: Vec3::Z,
        center: Vec3::ZERO,
        radius: 1.5,
    };
    for (dir_world, want) in [
        (Vec3::new(1.0, 1.0, 0.0), PI / 4.0),
        (Vec3::new(1.0, -1.0, 0.0), 3.0 * PI / 4.0),
    ] {
        let d = m.inverse().transform_vector3(dir_world);
        let mut o = frame
            .create_object(&ctx.device, &g, &vec![d; plane.positions.len()])
            .unwrap();
        let params = HatchParams::default();
        let view = still(0, &camera, &light, &params);
        frame
            .render_hatched(&ctx.device, &ctx.queue, &view, &mut [(&mut o, &u)])
            .unwrap();
        let gb = frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
        let theta = gb.theta()[(h / 2 * w + w / 2) as usize];
        assert!(
            (theta - want).abs() < 1f32.to_radians(),
            "{dir_world}: θ {theta}, want {want}"
        );
        // θ = 0 (the background) would fail above, so the quad was drawn.
    }
}

/// A sphere rig for the coherence tests: unit sphere at the origin, meridian strokes,
/// a 256² frame in `space`, the given anchor period.
struct SphereRig {
    frame: HatchFrame,
    object: npr_hatching::HatchObject,
    params: HatchParams,
    /// Displayed frames so far: each render is the next one (frame id and anchor clock).
    clock: u64,
    /// The sphere at rest and its upload (posed in place by [`SphereRig::render_posed`]).
    mesh: npr_geometry::Mesh,
    gpu_mesh: GpuMesh,
}

const RIG: u32 = 256;

fn sphere_rig(
    ctx: &npr_gpu::GpuContext,
    tam: &TonalArtMap,
    space: npr_hatching::StrokeSpace,
    period: u32,
) -> SphereRig {
    let mesh = npr_geometry::generate::icosphere(5, 1.0);
    let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
    let params = HatchParams {
        space,
        ..Default::default()
    };
    let settings = HatchFrameSettings {
        tam: tam.clone(),
        scene: SceneSettings {
            anchor_period: period,
            ..Default::default()
        },
    };
    let formats = TargetFormats::default();
    let frame = HatchFrame::new(&ctx.device, &ctx.queue, formats, &settings, (RIG, RIG)).unwrap();
    let object = frame
        .create_object(&ctx.device, &gpu_mesh, &meridian_directions(&mesh))
        .unwrap();
    SphereRig {
        frame,
        object,
        params,
        clock: 0,
        mesh,
        gpu_mesh,
    }
}

fn sphere_uniforms(world_from_object: Mat4) -> ObjectUniforms {
    ObjectUniforms::new(world_from_object, Vec3::splat(0.6), 0.0, Vec3::ZERO, 1.0)
}

fn sphere_light() -> ShadowLight {
    ShadowLight::Directional {
        towards_light: Vec3::new(-0.5, 0.4, 1.0),
        center: Vec3::ZERO,
        radius: 1.5,
    }
}

impl SphereRig {
    /// The next displayed frame's image, with the rig's parameters.
    fn render_image(
        &mut self,
        ctx: &npr_gpu::GpuContext,
        camera: &Camera,
        turn_rad: f32,
    ) -> image::RgbaImage {
        self.render_at(ctx, camera, Mat4::from_rotation_y(turn_rad))
    }

    /// The next displayed frame with the sphere at `world_from_object`.
    fn render_at(
        &mut self,
        ctx: &npr_gpu::GpuContext,
        camera: &Camera,
        world_from_object: Mat4,
    ) -> image::RgbaImage {
        let clock = self.clock;
        self.clock += 1;
        let light = sphere_light();
        let view = HatchView {
            frame: FrameId(clock),
            clock,
            camera,
            light: &light,
            params: &self.params,
        };
        let u = sphere_uniforms(world_from_object);
        self.frame
            .render_hatched(
                &ctx.device,
                &ctx.queue,
                &view,
                &mut [(&mut self.object, &u)],
            )
            .unwrap()
    }

    /// The next frame with the turn applied to the vertices themselves (a deforming mesh:
    /// the pose written into the uploaded buffer, new directions written, the object's
    /// transform the identity) rather than to the object's transform.
    fn render_posed(
        &mut self,
        ctx: &npr_gpu::GpuContext,
        camera: &Camera,
        turn_rad: f32,
    ) -> Vec<f32> {
        let turn = glam::Quat::from_rotation_y(turn_rad);
        let mut posed = self.mesh.clone();
        for (p, n) in posed.positions.iter_mut().zip(&mut posed.normals) {
            *p = turn * *p;
            *n = turn * *n;
        }
        self.gpu_mesh.write_vertices(&ctx.queue, &posed).unwrap();
        let dirs = meridian_directions(&posed);
        self.frame
            .write_directions(&ctx.queue, &self.object, &dirs)
            .unwrap();
        npr_hatching::coherence::ink_image(&self.render_at(ctx, camera, Mat4::IDENTITY))
    }

    fn render(&mut self, ctx: &npr_gpu::GpuContext, camera: &Camera, turn_rad: f32) -> Vec<f32> {
        npr_hatching::coherence::ink_image(&self.render_image(ctx, camera, turn_rad))
    }
}

/// Analytic mean screen motion (pixels, y down) of the unit sphere's visible surface over
/// the `n × n` tile at `(x0, y0)` when it turns by `d_rad` about +y: ray-cast each pixel
/// centre, turn the hit point, project it.
fn sphere_tile_motion(camera: &Camera, x0: u32, y0: u32, n: u32, d_rad: f32) -> [f32; 2] {
    let m = camera.clip_from_world();
    let inv = m.inverse();
    let turn = Mat4::from_rotation_y(d_rad);
    let (mut sx, mut sy) = (0.0, 0.0);
    for y in y0..y0 + n {
        for x in x0..x0 + n {
            let px = [x as f32 + 0.5, y as f32 + 0.5];
            let ndc = Vec3::new(
                px[0] / RIG as f32 * 2.0 - 1.0,
                1.0 - px[1] / RIG as f32 * 2.0,
                0.0,
            );
            let near = inv.project_point3(ndc);
            let d = (inv.project_point3(ndc.with_z(1.0)) - near).normalize();
            let o = camera.eye;
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 1.0);
            assert!(disc > 0.0, "tile pixel ({x}, {y}) misses the sphere");
            let hit = o + d * (-b - disc.sqrt());
            let q = m.project_point3(turn.transform_point3(hit));
            sx += (q.x * 0.5 + 0.5) * RIG as f32 - px[0];
            sy += (0.5 - q.y * 0.5) * RIG as f32 - px[1];
        }
    }
    let k = (n * n) as f32;
    [sx / k, sy / k]
}

fn tile(img: &[f32], x0: u32, y0: u32, n: u32) -> Vec<f32> {
    (0..n * n)
        .map(|i| img[((y0 + i / n) * RIG + x0 + i % n) as usize])
        .collect()
}

/// On a sphere turning 2° per frame, the hatching pattern's phase-correlation
/// shift over a central 64² tile follows the analytic surface motion to within 25 % of it
/// in surface space (every frame pair over two anchor periods); the paper's screen space
/// does not (its pattern stays put, an error of about 100 %). The coherent frame also
/// matches the CPU reference on its G-buffer with anchors mid-cross-fade.
#[test]
fn surface_hatching_follows_a_turning_sphere() {
    let Some(ctx) = testing::context_or_skip("surface_hatching_follows_a_turning_sphere") else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0);
    let step = 2f32.to_radians();
    let (x0, y0, n) = (RIG / 2 - 32, RIG / 2 - 32, 64);
    let expected = sphere_tile_motion(&camera, x0, y0, n, step);
    assert!(expected[0] > 2.0, "surface motion {expected:?}");
    for space in npr_hatching::StrokeSpace::ALL {
        let mut rig = sphere_rig(ctx, &tam, space, npr_hatching::DEFAULT_ANCHOR_PERIOD);
        let mut prev = rig.render(ctx, &camera, 0.0);
        let mut worst = 0.0f32;
        for t in 1..=8 {
            let ink = rig.render(ctx, &camera, step * t as f32);
            let d = npr_hatching::coherence::phase_correlation(
                &tile(&prev, x0, y0, n),
                &tile(&ink, x0, y0, n),
                n as usize,
            )
            .unwrap();
            let err = (d[0] - expected[0]).hypot(d[1] - expected[1]);
            eprintln!("{space:?} frame {t}: pattern {d:?}, surface {expected:?}");
            worst = worst.max(err / expected[0].hypot(expected[1]));
            if space == npr_hatching::StrokeSpace::Surface && t == 6 {
                // Mid-fade (weight 1/2 at period 4): GPU = CPU reference on the G-buffer.
                let gb = rig.frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
                let w = gb.anchors().unwrap()[(RIG * RIG / 2 + RIG / 2) as usize].weight_b;
                assert!(w > 0.2 && w < 0.8, "weight {w}");
                let params = rig.params;
                let cpu = CpuHatcher::new(&tam, &params)
                    .unwrap()
                    .hatch_rgba8(&gb)
                    .unwrap();
                let gpu = image::RgbaImage::from_raw(
                    RIG,
                    RIG,
                    ink.iter()
                        .flat_map(|i| {
                            let v = ((1.0 - i) * 255.0).round() as u8;
                            [v, v, v, 255]
                        })
                        .collect(),
                )
                .unwrap();
                let (mean, frac) = compare(&gpu, &cpu);
                assert!(
                    mean <= 0.25 && frac <= 0.005,
                    "mean {mean}, fraction {frac}"
                );
            }
            prev = ink;
        }
        eprintln!("{space:?}: worst relative error {worst:.3}");
        match space {
            npr_hatching::StrokeSpace::Surface => assert!(worst <= 0.25, "{worst}"),
            npr_hatching::StrokeSpace::Screen => assert!(worst > 0.75, "{worst}"),
        }
    }
}

/// A deforming mesh: the sphere's vertices themselves turned 2° per frame (its pose
/// written into the uploaded mesh, its directions rewritten, its transform still). In
/// surface space the pattern follows the surface as on the rigid turn (within 25 %),
/// because each anchor holds the vertices as they were when it was taken; anchored on
/// the current vertices instead, the pattern would stay on the screen (about 100 %).
#[test]
fn surface_hatching_follows_a_deforming_mesh() {
    let Some(ctx) = testing::context_or_skip("surface_hatching_follows_a_deforming_mesh") else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0);
    let step = 2f32.to_radians();
    let (x0, y0, n) = (RIG / 2 - 32, RIG / 2 - 32, 64);
    let expected = sphere_tile_motion(&camera, x0, y0, n, step);
    let mut rig = sphere_rig(
        ctx,
        &tam,
        npr_hatching::StrokeSpace::Surface,
        npr_hatching::DEFAULT_ANCHOR_PERIOD,
    );
    let mut prev = rig.render_posed(ctx, &camera, 0.0);
    let mut worst = 0.0f32;
    for t in 1..=8 {
        let ink = rig.render_posed(ctx, &camera, step * t as f32);
        let d = npr_hatching::coherence::phase_correlation(
            &tile(&prev, x0, y0, n),
            &tile(&ink, x0, y0, n),
            n as usize,
        )
        .unwrap();
        worst = worst
            .max((d[0] - expected[0]).hypot(d[1] - expected[1]) / expected[0].hypot(expected[1]));
        eprintln!("posed frame {t}: pattern {d:?}, surface {expected:?}");
        prev = ink;
    }
    eprintln!("deforming: worst relative error {worst:.3}");
    assert!(
        worst <= 0.25,
        "the pattern slid by {worst:.3} of the surface motion"
    );
}

/// Over a 2× dolly (camera distance 6 → 3 in 24 frames, the sphere turning 1°
/// per frame), the ink coverage at constant tone and the screen-space stroke density stay
/// within 25 % in surface space; a surface texture that is never re-anchored (no
/// re-anchoring: strokes magnified with the sphere) loses more than 25 % of its density.
#[test]
fn surface_hatching_keeps_density_under_dolly() {
    let Some(ctx) = testing::context_or_skip("surface_hatching_keeps_density_under_dolly") else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let frames = 24;
    for (period, bounded) in [
        (npr_hatching::DEFAULT_ANCHOR_PERIOD, true),
        (u32::MAX, false),
    ] {
        let mut rig = sphere_rig(ctx, &tam, npr_hatching::StrokeSpace::Surface, period);
        let mut measured = Vec::new();
        for t in 0..=frames {
            let dist = 6.0 * 0.5f32.powf(t as f32 / frames as f32);
            let camera = Camera::look_at(Vec3::new(0.0, 0.0, dist), Vec3::ZERO, 1.0);
            rig.render(ctx, &camera, (t as f32).to_radians());
            if t == 0 || t == frames {
                let mut gb = rig.frame.gbuffer.read(&ctx.device, &ctx.queue).unwrap();
                let mask = rig
                    .frame
                    .gbuffer
                    .read_surface_mask(&ctx.device, &ctx.queue)
                    .unwrap();
                gb.set_tone_where(0.55, |i| mask[i]);
                let img = hatch_image_gpu(&ctx.device, &ctx.queue, &gb, &tam, &rig.params).unwrap();
                let ink = npr_hatching::coherence::ink_image(&img);
                let inside: Vec<f32> = ink
                    .iter()
                    .zip(&mask)
                    .filter(|(_, m)| **m)
                    .map(|(i, _)| *i)
                    .collect();
                let coverage = inside.iter().sum::<f32>() / inside.len() as f32;
                let density =
                    npr_hatching::coherence::stroke_density(&ink, &mask, RIG as usize).unwrap();
                measured.push((coverage, density));
            }
        }
        let (c0, d0) = measured[0];
        let (c1, d1) = measured[1];
        eprintln!("period {period}: coverage {c0:.3} → {c1:.3}, density {d0:.3} → {d1:.3}");
        assert!((c1 / c0 - 1.0).abs() <= 0.25, "coverage {c0} → {c1}");
        if bounded {
            assert!((d1 / d0 - 1.0).abs() <= 0.25, "density {d0} → {d1}");
        } else {
            assert!((d1 / d0 - 1.0).abs() > 0.25, "density {d0} → {d1}");
        }
    }
}

/// The scene frame's hatching pass (`HatchPass::record`: background not
/// shaded, one anchor outside the cross-fade) draws the image of the general pass
/// (`HatchPass::draw`: every pixel, both anchors cross-faded by the G-buffer's weight)
/// on the same G-buffer, over a whole anchor schedule (weights 1, ¾, ½, ¼, 0, …) and with
/// a coloured paper (the background is the pass's clear): at most 1 code value apart (the
/// clear's sRGB encoding against the shader's), and equal on ≥ 99.9 % of pixels.
#[test]
fn scene_pass_draws_the_general_pass_image() {
    let Some(ctx) = testing::context_or_skip("scene_pass_draws_the_general_pass_image") else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 1.0);
    for space in npr_hatching::StrokeSpace::ALL {
        let mut rig = sphere_rig(ctx, &tam, space, npr_hatching::DEFAULT_ANCHOR_PERIOD);
        rig.params = HatchParams {
            paper: [0.9, 0.8, 0.6],
            ink: [0.1, 0.05, 0.2],
            ..rig.params
        };
        // The general pass over the same G-buffer: every pixel, the G-buffer's weights.
        let mut general_source = rig
            .frame
            .hatch
            .create_object(&ctx.device, &rig.frame.gbuffer);
        let target = npr_gpu::OffscreenTarget::new(&ctx.device, RIG, RIG).unwrap();
        let mut weights = Vec::new();
        for t in 0..9 {
            weights.push(rig.frame.scene.anchor_weight(rig.clock));
            let frame = FrameId(rig.clock);
            let scene = rig.render_image(ctx, &camera, 0.03 * t as f32);
            let input = npr_hatching::HatchInput {
                frame,
                params: &rig.params,
                anchor_weight: None,
            };
            let hatch = &rig.frame.hatch;
            let prepared = hatch
                .prepare(&ctx.queue, &mut general_source, &input)
                .unwrap();
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            {
                let white = npr_gpu::wgpu::LoadOp::Clear(npr_gpu::wgpu::Color::WHITE);
                let mut pass = npr_gpu::render::begin_color_pass(
                    &mut enc,
                    "general",
                    &target.color_view,
                    white,
                );
                hatch.draw(&mut pass, &general_source, &prepared).unwrap();
            }
            ctx.queue.submit(Some(enc.finish()));
            let general = npr_gpu::readback_rgba(&ctx.device, &ctx.queue, &target.color).unwrap();
            let (mut worst, mut differ) = (0u32, 0usize);
            for (p, q) in scene.pixels().zip(general.pixels()) {
                let d = (0..4)
                    .map(|c| (i32::from(p[c]) - i32::from(q[c])).unsigned_abs())
                    .max()
                    .unwrap_or(0);
                worst = worst.max(d);
                differ += usize::from(d > 0);
            }
            let share = differ as f64 / f64::from(RIG * RIG);
            eprintln!("{space:?} frame {t}: worst {worst}, differing {share:.5}");
            assert!(
                worst <= 1 && share <= 0.001,
                "{space:?} frame {t}: {worst}, {share}"
            );
        }
        assert!(weights.contains(&0.0) && weights.contains(&1.0) && weights.contains(&0.5));
    }
}

/// The G-buffer readback that does not block (what the browser polls from frame to frame)
/// hands over what the blocking reads return, only once, and only after the copies were
/// polled to completion; the frame drawn after the copy was submitted does not leak in.
#[test]
fn polled_gbuffer_readback_equals_the_blocking_reads() {
    let Some(ctx) = testing::context_or_skip("polled_gbuffer_readback_equals_the_blocking_reads")
    else {
        return;
    };
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let mut rig = sphere_rig(ctx, &tam, npr_hatching::StrokeSpace::Surface, 16);
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 1.0);
    rig.render(ctx, &camera, 0.0);
    let (device, queue) = (&ctx.device, &ctx.queue);
    let g = &rig.frame.gbuffer;
    let (inputs, mask, depth) = (
        g.read(device, queue).unwrap(),
        g.read_surface_mask(device, queue).unwrap(),
        g.read_depth(device, queue).unwrap(),
    );
    let mut pending = g.start_read(device, queue).unwrap();
    // The next frame (turned, from nearer) is drawn after the copies were submitted.
    let near = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 1.0);
    rig.render(ctx, &near, 0.5);
    let g = &rig.frame.gbuffer;
    let mut polls = 0;
    let contents = loop {
        if let Some(c) = pending.try_take() {
            break c.unwrap();
        }
        polls += 1;
        assert!(polls < 10_000, "the readback never completed");
        device.poll(wgpu::PollType::Poll).unwrap();
    };
    assert!(
        pending.try_take().is_some_and(|r| r.is_err()),
        "taken twice"
    );
    assert!(mask.iter().any(|&m| m) && mask.iter().any(|&m| !m));
    assert_eq!(contents.mask, mask);
    assert_eq!(contents.depth, depth);
    assert_eq!(contents.inputs.interleaved(), inputs.interleaved());
    assert_eq!(contents.inputs.turn(), inputs.turn());
    assert_eq!(contents.inputs.anchors(), inputs.anchors());
    let now = g.read_depth(device, queue).unwrap();
    assert_ne!(
        now, depth,
        "the second frame differs, so the test can see a late copy"
    );
}
