//! `npr render` end to end: every effect on real models in every format shows the object,
//! the specular image equals the library's own snapshot helper, turntables and GIFs have
//! their frames, and bad input gets one line and no output file.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::{gif_frames, npr, out_dir, root};

use npr_app::engine::{self, Renderer};
use npr_app::model::Model;
use npr_app::preset::{Effect, Preset};
use npr_app::view::View;
use npr_gpu::testing::context_or_skip;
use std::path::{Path, PathBuf};

/// Share of pixels that differ from the background (the top-left pixel), and the centre
/// of their bounding box in [0, 1]².
fn object_coverage(img: &image::RgbaImage) -> (f64, [f64; 2]) {
    let bg = *img.get_pixel(0, 0);
    let (mut n, mut lo, mut hi) = (0usize, [u32::MAX; 2], [0u32; 2]);
    for (x, y, p) in img.enumerate_pixels() {
        let d =
            p.0.iter()
                .zip(bg.0)
                .map(|(a, b)| a.abs_diff(b))
                .max()
                .unwrap_or(0);
        if d > 24 {
            n += 1;
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x), hi[1].max(y)];
        }
    }
    let (w, h) = img.dimensions();
    let share = n as f64 / f64::from(w * h);
    let centre = [
        f64::from(lo[0] + hi[0]) / 2.0 / f64::from(w),
        f64::from(lo[1] + hi[1]) / 2.0 / f64::from(h),
    ];
    (share, centre)
}

/// Spot as a GLB of two meshes on two nodes: a parent with translation, rotation and
/// scale holding half the triangles, and a child (inheriting it) holding the rest.
fn multi_node_glb(mesh: &npr_geometry::Mesh) -> Vec<u8> {
    use npr_geometry::io::write::{glb_container, glb_primitive};
    let half = mesh.indices.len() / 6 * 3;
    let part = |r: std::ops::Range<usize>| npr_geometry::Mesh {
        indices: mesh.indices[r].to_vec(),
        ..mesh.clone()
    };
    let (a, b) = (part(0..half), part(half..mesh.indices.len()));
    let mut bin = Vec::new();
    let (v0, a0, p0) = glb_primitive(&a, &mut bin, 0);
    let (v1, a1, p1) = glb_primitive(&b, &mut bin, v0.len());
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"children":[1],"translation":[5,-2,1],"rotation":[0,0.3826834,0,0.9238795],"scale":[3,3,3]}},{{"mesh":1}}],"meshes":[{{"primitives":[{p0}]}},{{"primitives":[{p1}]}}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        [a0, a1].concat().join(","),
        [v0, v1].concat().join(","),
        bin.len()
    );
    glb_container(&json, Some(&bin))
}

/// An OBJ, a binary PLY scan (the bunny) and a multi-node GLB (Spot), the latter two
/// written into `dir`.
/// `npr render MODEL --effect E --size SIZE --out OUT` (for warp, a 36-frame turntable
/// in 10° steps, a reference every 10 frames); asserts success and returns the image to
/// look at (for warp, frame 1: a warped one).
fn render_effect(model: &Path, effect: Effect, size: &str, out: &Path) -> PathBuf {
    let mut args = vec![
        "render",
        model.to_str().unwrap(),
        "--effect",
        effect.name(),
        "--size",
        size,
        "--out",
        out.to_str().unwrap(),
    ];
    if effect == Effect::Warp {
        args.extend(["--turntable", "36", "--json", "/dev/null"]);
    }
    let o = npr(&args);
    assert!(
        o.status.success(),
        "{} {}: {}",
        model.display(),
        effect.name(),
        String::from_utf8_lossy(&o.stderr)
    );
    if effect == Effect::Warp {
        npr_app::output::frame_path(out, 1)
    } else {
        out.to_path_buf()
    }
}

fn models(dir: &Path) -> Vec<PathBuf> {
    let bunny = npr_geometry::io::load(root().join("fixtures/meshes/stanford-bunny.obj"))
        .unwrap()
        .mesh;
    let spot = npr_geometry::io::load(root().join("fixtures/meshes/spot.obj"))
        .unwrap()
        .mesh;
    let ply = dir.join("bunny-binary.ply");
    std::fs::write(
        &ply,
        npr_geometry::io::write::ply(
            &bunny,
            npr_geometry::io::write::PlyEncoding::BinaryLittleEndian,
        ),
    )
    .unwrap();
    let glb = dir.join("spot-two-nodes.glb");
    std::fs::write(&glb, multi_node_glb(&spot)).unwrap();
    // The GLB loads whole: both nodes' triangles.
    let loaded = npr_geometry::io::load(&glb).unwrap();
    assert_eq!(loaded.mesh.triangle_count(), spot.triangle_count());
    vec![root().join("fixtures/meshes/spot.obj"), ply, glb]
}

#[test]
fn every_effect_shows_the_object_on_every_model() {
    let Some(_) = context_or_skip("every_effect_shows_the_object_on_every_model") else {
        return;
    };
    let dir = out_dir("effects");
    for model in models(&dir) {
        for effect in Effect::ALL {
            let out = dir.join(format!(
                "{}-{}.png",
                model.file_stem().unwrap().to_string_lossy(),
                effect.name()
            ));
            let out = render_effect(&model, effect, "160x120", &out);
            let img = image::open(&out).unwrap().to_rgba8();
            assert_eq!(img.dimensions(), (160, 120));
            let (share, centre) = object_coverage(&img);
            // A framed model fills a good part of the image, around its centre.
            assert!(
                (0.05..0.9).contains(&share),
                "{} {}: object covers {share}",
                model.display(),
                effect.name()
            );
            assert!(
                (centre[0] - 0.5).abs() < 0.2 && (centre[1] - 0.5).abs() < 0.2,
                "{} {}: object centred at {centre:?}",
                model.display(),
                effect.name()
            );
        }
    }
}

#[test]
fn specular_equals_the_library_snapshot_helper() {
    let Some(ctx) = context_or_skip("specular_equals_the_library_snapshot_helper") else {
        return;
    };
    let model = Model::load(&root().join("fixtures/meshes/spot.obj")).unwrap();
    let mut preset = Preset {
        effect: Effect::Specular,
        turn_deg: 40.0,
        ..Preset::default()
    };
    preset.specular.shape = "star".into();
    preset.specular.sigma = 0.85;
    let size = (200, 150);
    let view = View::new(&preset, &model.framing, size, 0.0);

    // The library's own path: a set, its controls, one snapshot render.
    let mut set = npr_specular::HighlightSet::with_abstraction(
        &model.mesh,
        &npr_geometry::CurvatureOptions {
            radius: npr_geometry::CurvatureRadius::EdgeLengths(preset.specular.smoothing_edges),
            ..Default::default()
        },
        preset.specular.abstraction,
    )
    .unwrap();
    let layer = engine::builtin_shape("star").unwrap().layer();
    engine::apply_controls(
        &mut set,
        &preset,
        layer,
        engine::anchor_reach(&model.framing),
    );
    set.update(view.light_eye(), view.world_from_object);
    assert!(
        !set.highlights().is_empty(),
        "the view must show highlights"
    );
    let gpu_mesh = npr_gpu::GpuMesh::upload(&ctx.device, &model.mesh).unwrap();
    let expected = npr_specular::snapshot::render(
        &ctx.device,
        &ctx.queue,
        &npr_specular::snapshot::HighlightScene {
            mesh: &gpu_mesh,
            indices: &model.mesh.indices,
            set: &set,
            object: engine::object_uniforms(&preset, view.world_from_object),
            camera: view.camera,
            light: view.light,
            base: engine::shading_model(&preset),
            highlights: true,
            clear: engine::clear_color(&preset),
        },
        size.0,
        size.1,
    )
    .unwrap();

    let mut renderer = Renderer::new(ctx, model, size).unwrap();
    let stats = renderer
        .render(&ctx.device, &ctx.queue, &preset, &view)
        .unwrap();
    let got = renderer.read(&ctx.device, &ctx.queue).unwrap();
    assert_eq!(stats.highlights, set.highlights().len());
    let worst = got
        .as_raw()
        .iter()
        .zip(expected.as_raw())
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap();
    assert!(
        worst <= 1,
        "app and snapshot differ by {worst}/255; {}",
        npr_gpu::testing::image_failure("app-highlight-snapshot", &expected, &got)
    );
    // And the highlights are really there: without them the image differs.
    let mut base_only = preset.clone();
    base_only.effect = Effect::Phong;
    base_only.base.ks = preset.specular.base_ks;
    renderer
        .render(&ctx.device, &ctx.queue, &base_only, &view)
        .unwrap();
    let plain = renderer.read(&ctx.device, &ctx.queue).unwrap();
    let changed = got
        .pixels()
        .zip(plain.pixels())
        .filter(|(a, b)| a.0 != b.0)
        .count();
    assert!(changed > 20, "highlights changed only {changed} pixels");
}

#[test]
fn a_turntable_gif_has_its_frames_and_json_its_rows() {
    let Some(_) = context_or_skip("a_turntable_gif_has_its_frames_and_json_its_rows") else {
        return;
    };
    let dir = out_dir("gif");
    let gif = dir.join("spot.gif");
    let json = dir.join("spot.json");
    let model = root().join("fixtures/meshes/spot.obj");
    let o = npr(&[
        "render",
        model.to_str().unwrap(),
        "--effect",
        "specular",
        "--size",
        "96x72",
        "--turntable",
        "6",
        "--gif",
        "--out",
        gif.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let frames = gif_frames(&gif);
    assert_eq!(frames.len(), 6);
    // The model turns: consecutive frames differ.
    assert_ne!(frames[0].buffer().as_raw(), frames[1].buffer().as_raw());
    let rows: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 6);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["frame"], i);
        assert!(r["setup_us"].as_f64().unwrap() > 0.0);
        assert!(r["triangles"].as_u64().unwrap() > 20_000);
        assert!(r["highlights"].is_u64() && r["receiver_faces"].is_u64());
    }

    // Without --gif: numbered frames beside --out.
    let out = dir.join("frames/spot.png");
    let o = npr(&[
        "render",
        model.to_str().unwrap(),
        "--size",
        "64x48",
        "--turntable",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for i in 0..3 {
        assert!(dir.join(format!("frames/spot_{i:04}.png")).exists());
    }
    assert!(!dir.join("frames/spot_0003.png").exists());
}

#[test]
fn bad_input_gets_one_line_and_no_output() {
    let dir = out_dir("bad");
    let garbage = dir.join("garbage.obj");
    std::fs::write(&garbage, b"\x00\x01\x02 not an obj at all f 1 2 99\n").unwrap();
    let bad_preset = dir.join("bad.toml");
    std::fs::write(&bad_preset, "[camera]\ndistance = -1\n").unwrap();
    let spot = root().join("fixtures/meshes/spot.obj");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "render".into(),
                dir.join("missing.obj").display().to_string(),
            ],
            "missing.obj",
        ),
        (
            vec!["render".into(), garbage.display().to_string()],
            "garbage.obj",
        ),
        (
            vec![
                "render".into(),
                spot.display().to_string(),
                "--preset".into(),
                bad_preset.display().to_string(),
            ],
            "distance",
        ),
        (
            vec!["render".into(), spot.display().to_string(), "--gif".into()],
            "--turntable",
        ),
    ];
    for (args, names) in cases {
        let out = dir.join("out.png");
        let mut args = args.clone();
        args.extend(["--out".into(), out.display().to_string()]);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = npr(&refs);
        assert!(!o.status.success(), "{args:?} succeeded");
        let stderr = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("npr: error:"))
            .collect();
        assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
        assert!(lines[0].contains(names), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} left {}", out.display());
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(Result::ok)
            .filter(|e| e.file_name().to_string_lossy().ends_with(".partial"))
            .collect();
        assert!(leftovers.is_empty(), "{args:?} left partial files");
    }
}

#[test]
fn outlines_draw_ink_on_the_silhouette_over_any_effect() {
    let Some(ctx) = context_or_skip("outlines_draw_ink_on_the_silhouette_over_any_effect") else {
        return;
    };
    let model = Model::from_mesh("sphere", npr_geometry::generate::icosphere(4, 1.0));
    let size = (160, 120);
    let mut renderer = Renderer::new(ctx, model.clone(), size).unwrap();
    for effect in [Effect::Phong, Effect::Cel, Effect::HatchingPen] {
        let mut preset = Preset {
            effect,
            ..Preset::default()
        };
        let view = View::new(&preset, &model.framing, size, 0.0);
        renderer
            .render(&ctx.device, &ctx.queue, &preset, &view)
            .unwrap();
        let plain = renderer.read(&ctx.device, &ctx.queue).unwrap();
        preset.outline.enabled = true;
        renderer
            .render(&ctx.device, &ctx.queue, &preset, &view)
            .unwrap();
        let lined = renderer.read(&ctx.device, &ctx.queue).unwrap();
        // Pixels on the sphere's projected rim (within 2 px of it) turn dark; the centre
        // of the disc stays as it was.
        let centre = view.to_pixel(glam::Vec3::ZERO, size).unwrap();
        let rim_px = {
            let eye = view.camera.eye;
            let d = eye.length();
            let r_world = (d * d - 1.0).sqrt() / d; // tangent circle radius
            let side = eye.cross(glam::Vec3::Y).normalize();
            let p = eye * (1.0 / (d * d)) + side * r_world;
            (view.to_pixel(p, size).unwrap() - centre).length()
        };
        let (mut rim_dark, mut rim_n, mut inner_changed, mut inner_n) = (0, 0, 0, 0);
        for (x, y, p) in lined.enumerate_pixels() {
            let r = (glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - centre).length();
            let luma = (u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2])) / 3;
            if (r - rim_px).abs() < 1.0 {
                rim_n += 1;
                rim_dark += usize::from(luma < 80);
            } else if r < 0.5 * rim_px {
                inner_n += 1;
                inner_changed += usize::from(p.0 != plain.get_pixel(x, y).0);
            }
        }
        assert!(
            rim_dark as f64 > 0.8 * rim_n as f64,
            "{}: {rim_dark}/{rim_n} rim pixels dark",
            effect.name()
        );
        assert!(
            (inner_changed as f64) < 0.02 * inner_n as f64,
            "{}: {inner_changed}/{inner_n} inner pixels changed",
            effect.name()
        );
    }
}

#[test]
fn every_file_of_the_bad_corpus_gets_one_line_through_npr_render() {
    let dir = out_dir("corpus");
    let bad = root().join("fixtures/bad");
    let expected = std::fs::read_to_string(bad.join("expected.txt")).unwrap();
    let mut n = 0;
    for line in expected.lines().filter(|l| !l.trim().is_empty()) {
        let (file, kind) = line.split_once(' ').unwrap();
        let out = dir.join(format!("{file}.png"));
        let o = npr(&[
            "render",
            bad.join(file).to_str().unwrap(),
            "--size",
            "32x32",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{file} rendered");
        let stderr = String::from_utf8_lossy(&o.stderr);
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("npr: error:"))
            .collect();
        assert_eq!(errors.len(), 1, "{file}: {stderr}");
        assert!(errors[0].contains(file), "{file} ({kind}): {}", errors[0]);
        assert!(!stderr.contains("panicked"), "{file}: {stderr}");
        assert!(!out.exists(), "{file}: an output was written");
        // The library gives the kind the corpus expects.
        let e = npr_app::model::Model::load(&bad.join(file)).unwrap_err();
        match e {
            npr_app::AppError::Load { source, .. } => assert_eq!(source.kind(), kind, "{file}"),
            e => panic!("{file}: {e}"),
        }
        n += 1;
    }
    assert!(n >= 20, "only {n} bad files");
}

#[test]
fn degenerate_non_manifold_and_disconnected_meshes_render() {
    let Some(_) = context_or_skip("degenerate_non_manifold_and_disconnected_meshes_render") else {
        return;
    };
    let dir = out_dir("messy");
    // Two disconnected tetrahedra, a zero-area face, a duplicate vertex, and three
    // triangles sharing one edge (non-manifold).
    let obj = "\
v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
v 3 0 0\nv 4 0 0\nv 3 1 0\nv 3 0 1\n\
v 1 0 0\nv 2 0 0\n\
v 0 -1 0\nv 0 0 -1\nv -1 0 0\n\
f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n\
f 5 7 6\nf 5 6 8\nf 5 8 7\nf 6 7 8\n\
f 1 2 10\nf 2 9 1\n\
f 1 2 11\nf 1 2 12\nf 2 1 13\n";
    let path = dir.join("messy.obj");
    std::fs::write(&path, obj).unwrap();
    for effect in Effect::ALL {
        let out = render_effect(
            &path,
            effect,
            "96x72",
            &dir.join(format!("{}.png", effect.name())),
        );
        let (share, _) = object_coverage(&image::open(&out).unwrap().to_rgba8());
        assert!(share > 0.01, "{}: nothing drawn ({share})", effect.name());
    }
}

#[test]
fn warp_turntables_render_with_every_antialiasing() {
    let Some(_) = context_or_skip("warp_turntables_render_with_every_antialiasing") else {
        return;
    };
    let dir = out_dir("warp-aa");
    let model = root().join("fixtures/meshes/spot.obj");
    let mut coverages = Vec::new();
    for aa in ["none", "msaa4", "msaa4-blend"] {
        // An old preset without the key still loads (the default, none).
        let text = if aa == "none" {
            "effect = \"warp\"\n[warp]\nk = 4\n".to_string()
        } else {
            format!("effect = \"warp\"\n[warp]\nk = 4\nantialiasing = \"{aa}\"\n")
        };
        let preset = dir.join(format!("{aa}.toml"));
        std::fs::write(&preset, text).unwrap();
        let out = dir.join(format!("{aa}/spot.png"));
        let json = dir.join(format!("{aa}.json"));
        let o = npr(&[
            "render",
            model.to_str().unwrap(),
            "--preset",
            preset.to_str().unwrap(),
            "--size",
            "128x96",
            "--turntable",
            "6",
            "--out",
            out.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{aa}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let rows: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        // Warped frames carry their PSNR against the full render (with the same
        // antialiasing); six frames a turn are 60° apart, so the bar only says the warp
        // shows the model.
        let psnr: Vec<f64> = rows
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|r| r["psnr_db"].as_f64())
            .collect();
        assert!(!psnr.is_empty(), "{aa}: no warped frame");
        assert!(psnr.iter().all(|p| *p > 12.0), "{aa}: {psnr:?}");
        let frame = image::open(npr_app::output::frame_path(&out, 1))
            .unwrap()
            .into_rgba8();
        coverages.push(object_coverage(&frame).0);
    }
    // Every setting shows the object, about equally large.
    for c in &coverages {
        assert!(
            *c > 0.05 && (c - coverages[0]).abs() < 0.2 * coverages[0],
            "{coverages:?}"
        );
    }
}

/// Turntable frame `i` of `frames` of `preset` rendered in full independently of the
/// app's renderer, through the crates' public API: npr-gpu's base shading with
/// `antialiasing`'s sample count, multisampled into npr-warp's `MsaaTarget` and resolved
/// (one sample: a plain pass).
fn independent_full_frame(
    ctx: &npr_gpu::GpuContext,
    model: &Model,
    preset: &Preset,
    frames: u32,
    i: u32,
    antialiasing: npr_warp::Antialiasing,
) -> image::RgbaImage {
    use npr_gpu::{BaseShading, FrameUniforms, GpuMesh, TargetFormats};
    let (device, queue) = (&ctx.device, &ctx.queue);
    let size = (preset.output.width, preset.output.height);
    let view = View::new(
        preset,
        &model.framing,
        size,
        360.0 * i as f32 / frames as f32,
    );
    let mesh = GpuMesh::upload(device, &model.mesh).unwrap();
    let formats = antialiasing.references(TargetFormats::default());
    let shades: Vec<[u8; 4]> = preset
        .base
        .cel_bands
        .iter()
        .map(|&g| [g, g, g, 255])
        .collect();
    let settings = npr_gpu::BaseSettings {
        ramp: npr_gpu::toon_ramp(256, &shades),
    };
    let base = BaseShading::new(device, queue, formats, &settings);
    let mut object = base.create_object(device, &mesh);
    let view_uniforms = FrameUniforms::new(&view.camera, &view.light);
    let object_uniforms = engine::object_uniforms(preset, view.world_from_object);
    let input = npr_gpu::BaseInput {
        frame: npr_gpu::FrameId::default(),
        view: &view_uniforms,
        object: &object_uniforms,
        model: engine::shading_model(preset),
    };
    let prepared = base.prepare(queue, &mut object, &input).unwrap();
    let target = npr_gpu::OffscreenTarget::new(device, size.0, size.1).unwrap();
    let msaa = npr_warp::MsaaTarget::new(
        device,
        size.0,
        size.1,
        antialiasing.references(TargetFormats::default()),
    )
    .unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let clear = engine::clear_color(preset);
        let mut pass = if antialiasing.is_multisampled() {
            msaa.begin_pass(&mut encoder, &target.color_view, Some(clear))
        } else {
            target.begin_clear_pass(&mut encoder, clear)
        };
        base.draw(&mut pass, &object, &prepared).unwrap();
    }
    queue.submit(Some(encoder.finish()));
    npr_gpu::readback_rgba(device, queue, &target.color).unwrap()
}

/// Pixels of `aa` (an antialiased frame) that differ from `one` (the same frame with one
/// sample per pixel), as (total, blended): blended are those `one` leaves as background
/// but `aa` partly covers, strictly between the background and the object (nearer the
/// background than the object pixels of `one` next to them).
fn rim_pixels(one: &image::RgbaImage, aa: &image::RgbaImage) -> (usize, usize) {
    let bg = *one.get_pixel(0, 0);
    let dist = |p: &image::Rgba<u8>| p.0.iter().zip(bg.0).map(|(a, b)| a.abs_diff(b)).max();
    let (w, h) = one.dimensions();
    let around = |x: u32, y: u32| {
        let (x0, y0) = (x.saturating_sub(1), y.saturating_sub(1));
        let (x1, y1) = ((x + 1).min(w - 1), (y + 1).min(h - 1));
        (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| (x, y)))
    };
    let (mut total, mut blended) = (0, 0);
    for (x, y, p) in aa.enumerate_pixels() {
        let q = one.get_pixel(x, y);
        if p == q {
            continue;
        }
        total += 1;
        if *q == bg {
            let object = around(x, y)
                .filter(|&(u, v)| *one.get_pixel(u, v) != bg)
                .map(|(u, v)| dist(one.get_pixel(u, v)))
                .max()
                .flatten();
            if object.is_some_and(|o| dist(p) < Some(o)) {
                blended += 1;
            }
        }
    }
    (total, blended)
}

#[test]
fn antialiased_warp_turntables_render_full_frames_and_measure_psnr_with_it() {
    let Some(ctx) =
        context_or_skip("antialiased_warp_turntables_render_full_frames_and_measure_psnr_with_it")
    else {
        return;
    };
    let dir = out_dir("warp-aa-full");
    let model_path = root().join("fixtures/meshes/spot.obj");
    let model = Model::load(&model_path).unwrap();
    let (frames, k) = (24u32, 4u32);
    let run = |aa: &str| {
        let preset_path = dir.join(format!("{aa}.toml"));
        std::fs::write(
            &preset_path,
            format!(
                "effect = \"warp\"\n[output]\nwidth = 128\nheight = 96\n\
                 [warp]\nk = {k}\nantialiasing = \"{aa}\"\n"
            ),
        )
        .unwrap();
        let out = dir.join(format!("{aa}/spot.png"));
        let json = dir.join(format!("{aa}.json"));
        let o = npr(&[
            "render",
            model_path.to_str().unwrap(),
            "--preset",
            preset_path.to_str().unwrap(),
            "--turntable",
            &frames.to_string(),
            "--out",
            out.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ]);
        assert!(
            o.status.success(),
            "{aa}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let rows: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        let frame = |i: u32| {
            image::open(npr_app::output::frame_path(&out, i as usize))
                .unwrap()
                .into_rgba8()
        };
        let images: Vec<image::RgbaImage> = (0..frames).map(frame).collect();
        (Preset::load(&preset_path).unwrap(), rows, images)
    };
    let (none_preset, none_rows, none) = run("none");
    for aa in ["msaa4", "msaa4-blend"] {
        let antialiasing = npr_warp::Antialiasing::from_name(aa).unwrap();
        let (preset, rows, frames_aa) = run(aa);
        let rows = rows.as_array().unwrap();
        assert_eq!(rows.len(), frames as usize, "{aa}");
        let mut gaps = Vec::new();
        for i in 0..frames {
            let row = &rows[i as usize];
            let image = &frames_aa[i as usize];
            if i % k == 0 {
                // (a) A frame rendered in full is antialiased as the warp is: it equals
                // the independent multisampled full render, and along the silhouette
                // pixels the one-sample frame leaves as background are partly covered.
                assert_eq!(row["warped"], false, "{aa} frame {i}");
                let full = independent_full_frame(ctx, &model, &preset, frames, i, antialiasing);
                let diff = npr_warp::metrics::compare(&full, image);
                assert!(
                    diff.max_abs_diff <= 1,
                    "{aa} frame {i}: {} from the multisampled full render",
                    diff.max_abs_diff
                );
                let one = &none[i as usize];
                let one_full = independent_full_frame(
                    ctx,
                    &model,
                    &none_preset,
                    frames,
                    i,
                    npr_warp::Antialiasing::None,
                );
                assert!(
                    npr_warp::metrics::compare(&one_full, one).max_abs_diff <= 1,
                    "none frame {i} is not the one-sample full render"
                );
                let (total, blended) = rim_pixels(one, image);
                assert!(
                    blended >= 20,
                    "{aa} frame {i}: {blended} blended rim pixels of {total} differing"
                );
                continue;
            }
            // (b) A warped frame's PSNR is against the multisampled full render.
            assert_eq!(row["warped"], true, "{aa} frame {i}");
            let reported = row["psnr_db"].as_f64().unwrap();
            let full = independent_full_frame(ctx, &model, &preset, frames, i, antialiasing);
            let expected = npr_warp::metrics::compare(&full, image).psnr_db;
            assert!(
                (reported - expected).abs() < 0.01,
                "{aa} frame {i}: JSON PSNR {reported} dB, against the multisampled full \
                 render {expected} dB"
            );
            let one_full = independent_full_frame(
                ctx,
                &model,
                &none_preset,
                frames,
                i,
                npr_warp::Antialiasing::None,
            );
            let against_one = npr_warp::metrics::compare(&one_full, image).psnr_db;
            gaps.push(reported - against_one);
            // 60° between references: the bar only says the warp shows the model.
            assert!(reported > 15.0, "{aa} frame {i}: {reported} dB");
        }
        // The one-sample comparison would report something else: the antialiased warp
        // is nearer the multisampled full render than the one-sample one.
        assert!(
            gaps.iter().all(|g| *g > 0.1),
            "{aa}: PSNR against MSAA minus against one sample, per warped frame: {gaps:?}"
        );
    }
    // The one-sample turntable reports PSNR against the one-sample full render.
    for row in none_rows.as_array().unwrap() {
        if let Some(reported) = row["psnr_db"].as_f64() {
            let i = row["frame"].as_u64().unwrap() as u32;
            let one_full = independent_full_frame(
                ctx,
                &model,
                &none_preset,
                frames,
                i,
                npr_warp::Antialiasing::None,
            );
            let expected = npr_warp::metrics::compare(&one_full, &none[i as usize]).psnr_db;
            assert!((reported - expected).abs() < 0.01, "none frame {i}");
        }
    }
}
