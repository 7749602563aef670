//! GPU tests of the antialiased (4× MSAA) warp path: the multisampled full render against
//! the single-sample one (interiors equal, rims between background and object, coverage
//! conserved), the multisampled warp at a reference pose against the multisampled full
//! render there, and sample-count mismatches returned as errors instead of wgpu's.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_gpu::{
    COLOR_FORMAT, Camera, DEPTH_FORMAT, GpuContext, GpuMesh, OffscreenTarget, TargetFormats,
    readback_rgba, testing::context_or_skip,
};
use npr_warp::{
    Antialiasing, Antialiasing::Msaa4, BasePass, Departures, FullRenderer, MsaaTarget, PhongBase,
    Proxy, ReferenceDraw, ReferenceFrame, Turntable, WarpError, Warper, compare,
    metrics::flip_mean,
};

mod common;
use common::{CLEAR, SIZE, knot, light, material};

fn path() -> Turntable {
    Turntable {
        camera: Camera::look_at(Vec3::new(0.0, 1.2, 3.6), Vec3::ZERO, 1.0),
        normalize: Mat4::from_scale(Vec3::splat(0.6)),
        deg_per_frame: 1.0,
        offsets: vec![Vec3::ZERO],
        orbit_camera: false,
    }
}

/// The full render of `mesh` at frame `t` of [`path`] with `aa`.
fn full(ctx: &GpuContext, mesh: &GpuMesh, t: f32, aa: Antialiasing) -> image::RgbaImage {
    let (d, q) = (&ctx.device, &ctx.queue);
    let scene = path().pose(t);
    let mut renderer = FullRenderer::new(d, q, aa.references(TargetFormats::default()));
    let input = npr_warp::FullInput {
        frame: npr_gpu::FrameId(0),
        camera: &scene.camera,
        world_from_objects: &scene.objects,
        light: &light(),
        material: &material(),
    };
    renderer.prepare(q, mesh, &input).unwrap();
    let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    if aa.is_multisampled() {
        let ms = MsaaTarget::new(d, SIZE, SIZE, aa.references(TargetFormats::default())).unwrap();
        renderer
            .record_msaa(&mut encoder, &ms, &target.color_view, CLEAR)
            .unwrap();
    } else {
        let (c, z) = (&target.color_view, &target.depth_view);
        renderer.record(&mut encoder, c, z, CLEAR).unwrap();
    }
    q.submit(Some(encoder.finish()));
    readback_rgba(d, q, &target.color).unwrap()
}

/// Whether every pixel of the 3 × 3 block around (x, y) is object (`Some(true)`) or
/// background (`Some(false)`) in `img`; `None` for a mixed block or the border.
fn block(img: &image::RgbaImage, x: u32, y: u32) -> Option<bool> {
    if x == 0 || y == 0 || x + 1 >= img.width() || y + 1 >= img.height() {
        return None;
    }
    let mut seen = [false; 2];
    for yy in y - 1..=y + 1 {
        for xx in x - 1..=x + 1 {
            seen[usize::from(img.get_pixel(xx, yy)[3] > 0)] = true;
        }
    }
    match seen {
        [false, true] => Some(true),
        [true, false] => Some(false),
        _ => None,
    }
}

#[test]
fn msaa_full_render_matches_the_aliased_one_inside_and_blends_at_the_rim() {
    let Some(ctx) =
        context_or_skip("msaa_full_render_matches_the_aliased_one_inside_and_blends_at_the_rim")
    else {
        return;
    };
    let aa = Antialiasing::Msaa4;
    aa.check(&ctx.adapter, &ctx.device, COLOR_FORMAT, DEPTH_FORMAT)
        .unwrap();
    let mesh = GpuMesh::upload(&ctx.device, &knot()).unwrap();
    let one = full(ctx, &mesh, 0.0, Antialiasing::None);
    let four = full(ctx, &mesh, 0.0, aa);
    let (mut interior, mut interior_off, mut rim, mut partial) = (0usize, 0usize, 0usize, 0usize);
    let (mut area_one, mut area_four) = (0.0f64, 0.0f64);
    for (x, y, p) in four.enumerate_pixels() {
        let o = one.get_pixel(x, y);
        area_one += f64::from(u8::from(o[3] > 0));
        area_four += f64::from(p[3]) / 255.0;
        match block(&one, x, y) {
            // Deep inside (3 × 3 object in the aliased render): shaded at the pixel centre
            // in both, so equal up to the resolve's rounding.
            Some(true) => {
                interior += 1;
                assert_eq!(p[3], 255, "interior alpha at ({x}, {y})");
                if (0..3).any(|c| p[c].abs_diff(o[c]) > 1) {
                    interior_off += 1;
                }
            }
            // Far outside: background in both.
            Some(false) => assert_eq!(p.0, [0, 0, 0, 0], "background at ({x}, {y})"),
            None => {
                rim += 1;
                // A rim pixel is the object's colour times its coverage (the background is
                // transparent black): alpha in 0..=255, colour not above the object's
                // brightest neighbour (but for a partly covered pixel shaded at its centre,
                // off its triangle, as MSAA does: a little extrapolated highlight).
                if p[3] > 0 && p[3] < 255 {
                    partial += 1;
                }
                let brightest = (x.saturating_sub(1)..=(x + 1).min(SIZE - 1))
                    .flat_map(|xx| {
                        (y.saturating_sub(1)..=(y + 1).min(SIZE - 1)).map(move |yy| (xx, yy))
                    })
                    .map(|(xx, yy)| *one.get_pixel(xx, yy))
                    .fold([0u8; 3], |m, q| {
                        [m[0].max(q[0]), m[1].max(q[1]), m[2].max(q[2])]
                    });
                for c in 0..3 {
                    assert!(
                        p[c] <= brightest[c].saturating_add(16),
                        "rim ({x}, {y}) channel {c}: {} above {}",
                        p[c],
                        brightest[c]
                    );
                }
            }
        }
    }
    eprintln!(
        "interior {interior} ({interior_off} off by > 1), rim {rim} ({partial} partial), \
         area {area_one} aliased vs {area_four:.1} msaa"
    );
    assert!(interior > 5000);
    // Interiors: at most 4 % of pixels off by more than 1; those lie on the knot's inner
    // silhouettes (where it passes in front of itself), edges MSAA smooths too.
    assert!(
        interior_off * 25 <= interior,
        "{interior_off} of {interior}"
    );
    // The 3-pixel band around the outline holds its partly covered pixels.
    assert!(partial * 8 > rim, "{partial} of {rim}");
    // Coverage is conserved: the summed alpha is the aliased area within 1 %.
    assert!(
        (area_four - area_one).abs() < 0.01 * area_one,
        "{area_four} vs {area_one}"
    );
    // Both renders differ only at the rim, which FLIP sees.
    let flip = flip_mean(&one, &four).unwrap();
    assert!(flip > 0.0 && flip < 0.2, "{flip}");
}

#[test]
fn msaa_warp_at_a_reference_pose_matches_the_msaa_full_render() {
    let Some(ctx) = context_or_skip("msaa_warp_at_a_reference_pose_matches_the_msaa_full_render")
    else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let mesh = knot();
    let gpu = GpuMesh::upload(d, &mesh).unwrap();
    let proxy = Proxy::simplify(&mesh, 0.05).unwrap();
    let mut errors = Vec::new();
    for aa in Antialiasing::ALL {
        let mut warper = Warper::new(
            d,
            q,
            &proxy,
            Departures::OURS,
            0.6,
            (SIZE, SIZE),
            (
                aa.references(TargetFormats::default()),
                aa.warp_target(TargetFormats::default()),
            ),
        )
        .unwrap();
        assert_eq!(warper.antialiasing(), aa);
        let mut base = PhongBase::new(
            &gpu,
            light(),
            material(),
            aa.references(TargetFormats::default()),
        );
        let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
        let mut encoder = d.create_command_encoder(&Default::default());
        for t in [0.0, 10.0] {
            let pose = path().pose(t).object(0);
            warper
                .record_reference(d, q, &mut encoder, &mut base, npr_gpu::FrameId(0), &pose)
                .unwrap();
        }
        q.submit(Some(encoder.finish()));
        // The reference itself equals the full render with the same antialiasing.
        let full0 = full(ctx, &gpu, 0.0, aa);
        let reference = readback_rgba(d, q, &warper.references()[0].color).unwrap();
        let same = compare(&full0, &reference);
        assert!(
            same.max_abs_diff <= 1,
            "{aa:?} reference vs full: {same:?}; {}",
            npr_gpu::testing::image_failure(&format!("msaa-{aa:?}-reference"), &full0, &reference)
        );
        // The warp at each reference pose reproduces it.
        for (t, s) in [(0.0, 0.0), (10.0, 1.0)] {
            let pose = path().pose(t).object(0);
            let mut encoder = d.create_command_encoder(&Default::default());
            let (c, z) = (&target.color_view, &target.depth_view);
            warper
                .record_warp(q, &mut encoder, (c, z), npr_gpu::FrameId(1), &pose, s)
                .unwrap();
            q.submit(Some(encoder.finish()));
            let warped = readback_rgba(d, q, &target.color).unwrap();
            let fullt = full(ctx, &gpu, t, aa);
            let quality = compare(&fullt, &warped);
            let flip = flip_mean(&fullt, &warped).unwrap();
            if let Ok(dir) = std::env::var("NPR_WARP_TEST_OUT") {
                let name = format!("{dir}/msaa-{}-t{t}", aa.name());
                fullt.save(format!("{name}-full.png")).unwrap();
                warped.save(format!("{name}-warp.png")).unwrap();
                npr_warp::metrics::difference_image(&fullt, &warped, 4.0)
                    .save(format!("{name}-diff.png"))
                    .unwrap();
            }
            eprintln!("{aa:?} at t = {t}: {quality:?}, FLIP {flip:.4}");
            assert!(quality.pixels > 5000);
            // The blended warp is one sample per pixel: where the proxy passes in front of
            // itself its edges alias (measured 33 dB against 40 dB multisampled).
            assert!(quality.psnr_db > 31.0, "{aa:?} t {t}: {quality:?}");
            assert!(flip < 0.02, "{aa:?} t {t}: FLIP {flip}");
            errors.push((aa, quality.psnr_db, flip));
        }
    }
    // Off the reference poses the MSAA warp is measured by the benchmark; here it is
    // enough that at them it is as faithful to its full render as the aliased warp is to
    // its own (within 3 dB), whose silhouette it no longer snaps to whole pixels.
    let mean = |a: Antialiasing| {
        let v: Vec<f64> = errors.iter().filter(|e| e.0 == a).map(|e| e.1).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    assert!(
        mean(Antialiasing::Msaa4) > mean(Antialiasing::None) - 3.0,
        "{errors:?}"
    );
}

/// Runs `record` on a fresh encoder inside a validation error scope and returns its result
/// with the validation error wgpu reports when the encoder is finished, if any.
fn validated<T>(
    ctx: &GpuContext,
    record: impl FnOnce(&mut wgpu::CommandEncoder) -> T,
) -> (T, Option<wgpu::Error>) {
    let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let out = record(&mut encoder);
    let _ = encoder.finish();
    (out, pollster::block_on(scope.pop()))
}

#[test]
fn sample_count_mismatches_are_typed_errors_not_wgpu_validation_errors() {
    let Some(ctx) =
        context_or_skip("sample_count_mismatches_are_typed_errors_not_wgpu_validation_errors")
    else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let mesh = knot();
    let gpu = GpuMesh::upload(d, &mesh).unwrap();
    let proxy = Proxy::simplify(&mesh, 0.05).unwrap();
    let pose = path().pose(0.0).object(0);
    let one_sample = || PhongBase::new(&gpu, light(), material(), TargetFormats::default());
    let mismatch = |r: Result<(), WarpError>, got, expected| match r {
        Err(WarpError::SampleCountMismatch {
            got: g,
            expected: e,
            ..
        }) => assert_eq!((g, e), (got, expected)),
        other => panic!("expected a sample-count mismatch {got} vs {expected}, got {other:?}"),
    };

    // What recording did before the check: the one-sample base's pipelines in the
    // reference's 4x pass, which wgpu rejects (a validation error; uncaptured, a panic).
    let reference =
        ReferenceFrame::new(d, SIZE, SIZE, Msaa4.references(TargetFormats::default())).unwrap();
    let ms = MsaaTarget::new(d, SIZE, SIZE, Msaa4.references(TargetFormats::default())).unwrap();
    let mut base = one_sample();
    let draw = ReferenceDraw {
        frame: npr_gpu::FrameId(0),
        pose: &pose,
        slot: 0,
        slice: 0,
        slices: 1,
    };
    let ((), old) = validated(ctx, |encoder| {
        base.prepare(d, q, &draw);
        let mut pass = ms.begin_pass(encoder, &reference.color_view, Some(CLEAR));
        base.draw(&mut pass, &draw);
    });
    assert!(
        old.is_some(),
        "wgpu accepted a 1-sample pipeline in a 4x pass"
    );

    // Now: the reference checks the base pass first and records nothing.
    let mut warper = Warper::new(
        d,
        q,
        &proxy,
        Departures::OURS,
        0.6,
        (SIZE, SIZE),
        (
            Msaa4.references(TargetFormats::default()),
            Msaa4.warp_target(TargetFormats::default()),
        ),
    )
    .unwrap();
    let (r, err) = validated(ctx, |e| {
        warper.record_reference(d, q, e, &mut base, npr_gpu::FrameId(0), &pose)
    });
    mismatch(r, 1, 4);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(warper.references_recorded(), 0);
    // The other way round: a 4x base for a one-sample warper.
    let mut plain = Warper::new(
        d,
        q,
        &proxy,
        Departures::OURS,
        0.6,
        (SIZE, SIZE),
        (TargetFormats::default(), TargetFormats::default()),
    )
    .unwrap();
    let mut base4 = PhongBase::new(
        &gpu,
        light(),
        material(),
        Msaa4.references(TargetFormats::default()),
    );
    assert_eq!(base4.sample_count(), 4);
    let (r, err) = validated(ctx, |e| {
        plain.record_reference(d, q, e, &mut base4, npr_gpu::FrameId(0), &pose)
    });
    mismatch(r, 4, 1);
    assert!(err.is_none(), "{err:?}");
    // A matching base records with no validation error.
    let mut reference = reference;
    let (r, err) = validated(ctx, |e| {
        reference.record(
            d,
            q,
            e,
            &mut base4,
            &ReferenceDraw::whole(npr_gpu::FrameId(0), &pose, 0),
            CLEAR,
        )
    });
    r.unwrap();
    assert!(err.is_none(), "{err:?}");

    // The full renderer: 4x into a one-sample target, and one-sample into a 4x target.
    let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
    let full4 = FullRenderer::new(d, q, Msaa4.references(TargetFormats::default()));
    let (c, z) = (&target.color_view, &target.depth_view);
    let (r, err) = validated(ctx, |e| full4.record(e, c, z, CLEAR));
    mismatch(r, 1, 4);
    assert!(err.is_none(), "{err:?}");
    let full1 = FullRenderer::new(d, q, TargetFormats::default());
    let (r, err) = validated(ctx, |e| full1.record_msaa(e, &ms, c, CLEAR));
    mismatch(r, 4, 1);
    assert!(err.is_none(), "{err:?}");
    // The warp into a multisampled colour target (it resolves into, or draws, one sample).
    let (r, err) = validated(ctx, |e| {
        warper
            .record_warp(
                q,
                e,
                (&ms.color_view, &ms.depth_view),
                npr_gpu::FrameId(0),
                &pose,
                0.0,
            )
            .map(|_| ())
    });
    mismatch(r, 4, 1);
    assert!(err.is_none(), "{err:?}");
}

#[test]
fn antialiasing_names_round_trip() {
    for aa in Antialiasing::ALL {
        assert_eq!(Antialiasing::from_name(aa.name()), Some(aa));
    }
    assert_eq!(Antialiasing::from_name("msaa8"), None);
    assert_eq!(Antialiasing::default(), Antialiasing::None);
    assert_eq!(Antialiasing::Msaa4.sample_count(), 4);
}
