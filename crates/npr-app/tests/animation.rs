//! `npr render --animation/--time/--frames` and `npr pose` on the Fox (a skinned glTF
//! triangle soup with three clips): the clip is found or refused with one line, the
//! frames move, and the posed mesh written equals the library's CPU posing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{gif_frames, npr, out_dir, root};
use npr_gpu::testing::context_or_skip;

fn fox() -> String {
    root()
        .join("fixtures/meshes/Fox.glb")
        .to_string_lossy()
        .into_owned()
}

fn files(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn unknown_clips_and_bad_requests_are_one_line_and_write_nothing() {
    let dir = out_dir("anim-bad");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let svg = dir.join("x.svg");
    let svg = svg.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &["--animation", "Jump"],
            "Fox.glb has no clip \"Jump\"; its clips: Survey, Walk, Run",
        ),
        (
            &["--animation", "3"],
            "Fox.glb has no clip 3; its clips: Survey, Walk, Run",
        ),
        (
            &["--frames", "4", "--turntable", "4"],
            "--frames and --turntable do not go together",
        ),
        (&["--frames", "4", "--fps", "0"], "--fps 0: a rate above 0"),
        (
            &["--effect", "hatching-pen", "--frames", "4", "--svg", svg],
            "not drawn as SVG frames yet",
        ),
    ];
    let model = fox();
    for (extra, said) in cases {
        let mut args = vec!["render", model.as_str(), "--out", out];
        args.extend_from_slice(extra);
        let o = npr(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        let errors: Vec<&str> = stderr
            .lines()
            .filter(|l| l.starts_with("npr: error:"))
            .collect();
        assert!(!o.status.success(), "{extra:?}: {stderr}");
        assert_eq!(errors.len(), 1, "{extra:?}: {stderr}");
        assert!(errors[0].contains(said), "{extra:?}: {stderr}");
        assert!(files(&dir).is_empty(), "{extra:?} wrote {:?}", files(&dir));
    }
    // The preset's [animation] clip is used when the command line names none.
    let preset = std::env::temp_dir().join(format!("npr-anim-{}.toml", std::process::id()));
    std::fs::write(&preset, "[animation]\nclip = \"Trot\"\n").unwrap();
    let o = npr(&[
        "render",
        &model,
        "--preset",
        preset.to_str().unwrap(),
        "--out",
        out,
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && stderr.contains("Fox.glb has no clip \"Trot\""),
        "{stderr}"
    );
    let _ = std::fs::remove_file(&preset);
    assert!(files(&dir).is_empty());
    // A model without clips: any clip named is refused, none is the model as loaded.
    let bunny = root().join("fixtures/meshes/stanford-bunny.obj");
    let obj = dir.join("x.obj");
    let o = npr(&[
        "pose",
        bunny.to_str().unwrap(),
        "--animation",
        "Walk",
        "--out",
        obj.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && stderr.contains("stanford-bunny.obj has no clip \"Walk\"; it has no clips"),
        "{stderr}"
    );
    assert!(files(&dir).is_empty());
}

/// `npr pose` writes the library's CPU pose of the clip, in the file's units and scene
/// space: the same positions as `Rig::pose_mesh` of `Rig::sample`, different from the bind
/// pose, and the bind pose with `--animation none`.
#[test]
fn pose_writes_the_posed_mesh_in_the_files_space() {
    let dir = out_dir("anim-pose");
    let loaded = npr_geometry::io::load(fox()).unwrap();
    let rig = loaded.rig.expect("the Fox is rigged");
    let walk = rig.clip_named("Walk").unwrap();
    let expected = rig.pose_mesh(&rig.sample(walk, 0.3));
    let bind = rig.pose_mesh(&rig.bind_pose());
    let radius = bind
        .positions
        .iter()
        .map(|p| p.length())
        .fold(0.0f32, f32::max);
    for (choice, ext) in [("Walk", "obj"), ("1", "ply")] {
        let path = dir.join(format!("fox.{ext}"));
        let o = npr(&[
            "pose",
            &fox(),
            "--animation",
            choice,
            "--time",
            "0.3",
            "--out",
            path.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let back = npr_geometry::io::load(&path).unwrap().mesh;
        assert_eq!(back.indices.len(), expected.indices.len());
        // The written file is welded on reading: compare point sets through the triangles.
        let tri = |m: &npr_geometry::Mesh, t: usize| m.positions[m.indices[t] as usize];
        let worst = (0..expected.indices.len())
            .map(|t| tri(&back, t).distance(tri(&expected, t)))
            .fold(0.0f32, f32::max);
        assert!(
            worst <= 1e-5 * radius,
            "{choice}: {worst} from the library's pose"
        );
        let moved = (0..bind.indices.len())
            .map(|t| tri(&back, t).distance(tri(&bind, t)))
            .fold(0.0f32, f32::max);
        assert!(
            moved > 0.01 * radius,
            "{choice}: the pose does not move ({moved})"
        );
    }
    let path = dir.join("bind.obj");
    let o = npr(&[
        "pose",
        &fox(),
        "--animation",
        "none",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let back = npr_geometry::io::load(&path).unwrap().mesh;
    let tri = |m: &npr_geometry::Mesh, t: usize| m.positions[m.indices[t] as usize];
    let worst = (0..bind.indices.len())
        .map(|t| tri(&back, t).distance(tri(&bind, t)))
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-5 * radius, "bind pose: {worst}");
}

/// `--frames N --fps F` writes N numbered frames of the clip, the camera still: frames
/// half a clip apart differ (the Fox walks), and with looping the frame one whole clip
/// after the first shows the first pose again.
#[test]
fn frames_play_the_clip_with_the_camera_still() {
    if context_or_skip("frames_play_the_clip_with_the_camera_still").is_none() {
        return;
    }
    let dir = out_dir("anim-frames");
    let out = dir.join("walk.png");
    let loaded = npr_geometry::io::load(fox()).unwrap();
    let duration = loaded.rig.unwrap().clip_named("Walk").unwrap().duration();
    // Five frames a quarter of the clip apart: frame 2 is half way, frame 4 one clip on.
    let fps = 4.0 / duration;
    let o = npr(&[
        "render",
        &fox(),
        "--effect",
        "phong",
        "--size",
        "160x120",
        "--animation",
        "Walk",
        "--frames",
        "5",
        "--fps",
        &fps.to_string(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        files(&dir),
        [
            "walk_0000.png",
            "walk_0001.png",
            "walk_0002.png",
            "walk_0003.png",
            "walk_0004.png"
        ]
    );
    let img = |i: usize| {
        image::open(dir.join(format!("walk_{i:04}.png")))
            .unwrap()
            .to_rgba8()
    };
    let differ = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 8))
            .count()
    };
    let (f0, f2, f4) = (img(0), img(2), img(4));
    assert!(
        differ(&f0, &f2) > 100,
        "half a clip apart the Fox has moved"
    );
    // Frame 4 is at t = duration, which loops back to t = 0 (to within float rounding
    // of t; the pose there is the first key's).
    assert!(
        differ(&f0, &f4) < differ(&f0, &f2) / 10,
        "one clip apart: the same pose"
    );
}

/// A pose set in place (`Renderer::set_pose`: vertices written into the uploaded buffers,
/// surface data taken again) draws what a renderer built on that pose draws: the same
/// image for the shadings and the screen-space hatching, and for the highlights the same
/// highlights with their centres within 1e-3 of the model's size (the reposed set keeps
/// tracking, so fades may differ, and the scales it was built with).
#[test]
fn a_pose_set_in_place_draws_what_a_fresh_renderer_draws() {
    let Some(ctx) = context_or_skip("a_pose_set_in_place_draws_what_a_fresh_renderer_draws") else {
        return;
    };
    use npr_app::animation::{Animated, ClipChoice, Playback, resolve_clip};
    use npr_app::engine::Renderer;
    use npr_app::preset::{Effect, Preset, SpacePreset};
    let fox = npr_app::model::Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let clip = resolve_clip(&fox, &ClipChoice::Name("Walk".into())).unwrap();
    let animated = Animated::new(fox, clip, Playback::default()).unwrap();
    let (a, b) = (animated.frame(0), animated.frame(10));
    let size = (320, 240);
    for effect in [
        Effect::Phong,
        Effect::Cel,
        Effect::HatchingPen,
        Effect::Specular,
    ] {
        let mut preset = Preset {
            effect,
            ..Preset::default()
        };
        preset.hatching.space = SpacePreset::Screen;
        preset.output.width = size.0;
        preset.output.height = size.1;
        let view = npr_app::view::View::new(&preset, &animated.framing(), size, 0.0);
        let mut fresh = Renderer::new(ctx, b.clone(), size).unwrap();
        fresh
            .render(&ctx.device, &ctx.queue, &preset, &view)
            .unwrap();
        let want = fresh.read(&ctx.device, &ctx.queue).unwrap();
        let mut moved = Renderer::new(ctx, a.clone(), size).unwrap();
        moved
            .render(&ctx.device, &ctx.queue, &preset, &view)
            .unwrap();
        let before = moved.read(&ctx.device, &ctx.queue).unwrap();
        moved.set_pose(&ctx.queue, b.clone()).unwrap();
        moved
            .render(&ctx.device, &ctx.queue, &preset, &view)
            .unwrap();
        let got = moved.read(&ctx.device, &ctx.queue).unwrap();
        let differ = |x: &image::RgbaImage, y: &image::RgbaImage| {
            x.pixels()
                .zip(y.pixels())
                .filter(|(p, q)| p.0.iter().zip(q.0).any(|(u, v)| u.abs_diff(v) > 2))
                .count()
        };
        assert!(
            differ(&before, &want) > 200,
            "{effect:?}: the two poses look alike"
        );
        if effect == Effect::Specular {
            let centres = |r: &Renderer| {
                let mut c: Vec<[i64; 3]> = r
                    .highlight_set()
                    .unwrap()
                    .highlights()
                    .iter()
                    .filter(|h| h.found)
                    .map(|h| {
                        h.centre
                            .position_object
                            .to_array()
                            .map(|x| (x * 1e3).round() as i64)
                    })
                    .collect();
                c.sort_unstable();
                c
            };
            // A pose keeps the scales its set was built with (`HighlightSet::repose`: the
            // curvature's ball in world units, the abstraction's steps), a fresh renderer
            // takes this pose's own: the same highlights, their centres within 1e-3 of the
            // model's size.
            let (got, want) = (centres(&moved), centres(&fresh));
            let size = animated.framing().radius;
            assert_eq!(
                got.len(),
                want.len(),
                "highlight centres: {got:?} and {want:?}"
            );
            for (g, w) in got.iter().zip(&want) {
                let apart = g
                    .iter()
                    .zip(w)
                    .map(|(x, y)| (x - y).abs() as f32 / 1e3)
                    .fold(0.0f32, f32::max);
                assert!(
                    apart <= 1e-3 * size,
                    "highlight centres {apart} apart (model radius {size}): {got:?} and {want:?}"
                );
            }
        } else {
            assert_eq!(
                differ(&got, &want),
                0,
                "{effect:?}: set_pose against a fresh renderer"
            );
        }
    }
    // Another mesh is refused, and the renderer keeps drawing.
    let bunny = npr_app::model::Model::bunny().unwrap();
    let mut r = Renderer::new(ctx, a, size).unwrap();
    assert!(r.set_pose(&ctx.queue, bunny).is_err());
}

/// Where every vertex is bound to one joint (the procedural bent tube: each ring to its
/// own joint, weight 1), the rest pose's stroke field carried through the skinning is the
/// field computed on the pose (median within 1°); on the Fox, whose joints blend, it
/// stays close (median within 10°).
#[test]
fn carried_directions_match_the_recomputed_field_where_parts_move_rigidly() {
    use npr_app::animation::{Animated, Playback};
    use npr_app::preset::DirectionPreset;
    let median_deviation = |animated: &Animated, t: f32| {
        let which = DirectionPreset::default();
        let rest = animated.rest_directions(which);
        let model = animated.model_at(t);
        let carried = animated.carried_directions(&rest, t, &model);
        let exact = npr_hatching::stroke_directions(
            &model.mesh,
            &npr_hatching::DirectionSource::default(),
            npr_hatching::StrokeDirection::KappaMax,
            &npr_geometry::CurvatureOptions::default(),
            glam::Vec3::Y,
        );
        let mut dev: Vec<f64> = exact
            .iter()
            .zip(&carried)
            .zip(&model.mesh.normals)
            .filter_map(|((a, b), n)| npr_geometry::line_angle_deg(*a, *b, *n))
            .collect();
        assert!(
            dev.len() > model.mesh.positions.len() / 2,
            "directions defined"
        );
        dev.sort_by(f64::total_cmp);
        dev[dev.len() / 2]
    };
    let tube = npr_geometry::generate::bent_tube(0.3, 2.0, std::f32::consts::FRAC_PI_2, 32, 48);
    let mut model = npr_app::model::Model::from_mesh("tube", tube.mesh);
    model.rig = Some(tube.rig);
    let animated = Animated::new(model, Some(0), Playback::default()).unwrap();
    let tube_dev = median_deviation(&animated, 1.0);
    assert!(tube_dev <= 1.0, "bent tube: {tube_dev}°");
    let fox = npr_app::model::Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let walk = fox
        .rig
        .as_ref()
        .unwrap()
        .clips()
        .iter()
        .position(|c| c.name() == Some("Walk"));
    let animated = Animated::new(fox, walk, Playback::default()).unwrap();
    let fox_dev = median_deviation(&animated, 0.3);
    assert!(fox_dev <= 10.0, "Fox: {fox_dev}°");
}

/// On the walking Fox, a highlight's projector frame never turns by more than 45° from
/// one frame to the next while it keeps its id (where its principal curvatures differ by
/// at least 10 %: at an umbilic the frame is undefined), and highlights keep their ids
/// across poses.
#[test]
fn projector_frames_do_not_flip_on_the_moving_model() {
    let Some(ctx) = context_or_skip("projector_frames_do_not_flip_on_the_moving_model") else {
        return;
    };
    use npr_app::animation::{Animated, ClipChoice, Playback, resolve_clip};
    use npr_app::engine::Renderer;
    use npr_app::preset::{Effect, Preset};
    use std::collections::HashMap;
    let fox = npr_app::model::Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let clip = resolve_clip(&fox, &ClipChoice::Name("Walk".into())).unwrap();
    let animated = Animated::new(fox, clip, Playback::default()).unwrap();
    let size = (320, 240);
    let mut preset = Preset {
        effect: Effect::Specular,
        ..Preset::default()
    };
    preset.output.width = size.0;
    preset.output.height = size.1;
    let view = npr_app::view::View::new(&preset, &animated.framing(), size, 0.0);
    let mut r = Renderer::new(ctx, animated.frame(0), size).unwrap();
    // Keyed by the highlight, its piece and how many pieces it has: a long bent highlight
    // is drawn as pieces (`Highlight::piece`), each with its own projector, and a piece
    // is the same part of the band only while the count stays.
    let mut last: HashMap<(u64, u8, u8), (glam::Vec3, glam::Vec3)> = HashMap::new();
    let (mut pairs, mut worst) = (0usize, 0.0f64);
    for i in 0..45 {
        if i > 0 {
            r.set_pose(&ctx.queue, animated.frame(i)).unwrap();
        }
        r.render(&ctx.device, &ctx.queue, &preset, &view).unwrap();
        let mut now = HashMap::new();
        for h in r.highlight_set().unwrap().highlights() {
            let (kmax, kmin) = (h.centre.kappa_max, h.centre.kappa_min);
            if !h.found || (kmax - kmin).abs() < 0.1 * kmax.abs().max(kmin.abs()) {
                continue;
            }
            let (u, n) = (h.projector.axis_u, h.projector.normal);
            let key = (h.id, h.piece, h.pieces);
            if let Some(&(u0, n0)) = last.get(&key) {
                let angle = npr_geometry::line_angle_deg(u0, u, n0 + n).unwrap_or(0.0);
                worst = worst.max(angle);
                pairs += 1;
            }
            now.insert(key, (u, n));
        }
        last = now;
    }
    eprintln!("{pairs} frame pairs of a kept highlight; worst turn {worst:.1}°");
    assert!(
        pairs >= 20,
        "highlights keep their ids across poses ({pairs} pairs)"
    );
    assert!(
        worst <= 45.0,
        "a projector frame turned by {worst:.1}° between two frames"
    );
}

/// Highlights on a moving body pop no more than on the same body's rigid turn, and their
/// footprints' area changes stay within the set's per-frame limit:
/// the Fox walking and the procedural bent tube bending, 90 frames of the clip at 30 fps
/// against 90 one-degree steps of its rest pose turning, under the same light and eye
/// (`npr_specular::fidelity::{pose_coherence, turntable_coherence}`, the measures of
/// `bench specular-fidelity`'s turning table).
#[test]
fn highlights_pop_no_more_on_the_clip_than_on_the_turntable() {
    use npr_app::animation::{Animated, Playback};
    use npr_geometry::{CurvatureOptions, LightEye};
    use npr_specular::HighlightSet;
    use npr_specular::fidelity::{pose_coherence, turntable_coherence};
    const FRAMES: usize = 90;
    let mut tube = {
        let r = npr_geometry::generate::bent_tube(0.3, 2.0, 1.5, 24, 32);
        npr_app::model::Model::from_mesh("bent tube", r.mesh)
    };
    tube.rig = Some(npr_geometry::generate::bent_tube(0.3, 2.0, 1.5, 24, 32).rig);
    let fox = npr_app::model::Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let options = CurvatureOptions::default();
    for (model, clip) in [(fox, 1), (tube, 0)] {
        let name = model.name.clone();
        let rig = model.rig.clone().unwrap();
        let rest = rig.pose_mesh(&rig.bind_pose());
        let animated = Animated::new(model, Some(clip), Playback::default()).unwrap();
        let (camera, world) = npr_gpu::figures::framing_camera(&rest, 4.0 / 3.0);
        let le = LightEye::Positions {
            light: glam::Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
            eye: camera.eye,
        };
        let mut set = HighlightSet::new(&rest, &options).unwrap();
        let turn = turntable_coherence(&mut set, le, world, FRAMES, 1.0);
        let poses = (0..FRAMES).map(|i| animated.posed_mesh(i));
        let clip = pose_coherence(&mut set, le, world, poses, &options).unwrap();
        eprintln!(
            "{name}: turn pops {}+{} area {:.3}; clip pops {}+{} area {:.3}",
            turn.pops_in,
            turn.pops_out,
            turn.area_change_max,
            clip.pops_in,
            clip.pops_out,
            clip.area_change_max
        );
        assert_eq!(clip.frames, FRAMES);
        assert!(
            clip.pops_in <= turn.pops_in && clip.pops_out <= turn.pops_out,
            "{name}: the clip pops {}+{} against the turn's {}+{}",
            clip.pops_in,
            clip.pops_out,
            turn.pops_in,
            turn.pops_out
        );
        // A walk at 30 fps moves far more per frame than a 1° turn, so its footprints
        // reach the set's per-frame area limit where the turn may stay below it; the
        // limit must hold on the moving body as on the turn.
        let cap = set.tuning.max_area_change;
        assert!(
            clip.area_change_max <= turn.area_change_max.max(cap) + 1e-3,
            "{name}: a footprint's area jumps {:.3} on the clip, {:.3} on the turn, limit {cap}",
            clip.area_change_max,
            turn.area_change_max
        );
    }
}

/// `[animation] posing = "gpu"`: the frames drawn from the vertices the GPU posed match
/// those drawn from the CPU pose (the Fox walking, four frames, in the shadings, the
/// hatching and the highlights), and a pose differs from the first.
#[test]
fn gpu_posing_draws_what_cpu_posing_draws() {
    let Some(ctx) = context_or_skip("gpu_posing_draws_what_cpu_posing_draws") else {
        return;
    };
    use npr_app::animation::{Animated, ClipChoice, Playback, resolve_clip};
    use npr_app::preset::{Effect, Posing, Preset};
    let fox = npr_app::model::Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let clip = resolve_clip(&fox, &ClipChoice::Name("Walk".into())).unwrap();
    let animated = Animated::new(fox, clip, Playback::default()).unwrap();
    for effect in [Effect::Phong, Effect::HatchingPen, Effect::Specular] {
        let mut frames = Vec::new();
        for posing in [Posing::Cpu, Posing::Gpu] {
            let mut preset = Preset {
                effect,
                ..Preset::default()
            };
            preset.animation.posing = posing;
            preset.output.width = 240;
            preset.output.height = 180;
            let mut images = Vec::new();
            npr_app::render::render_clip_frames(
                ctx,
                &animated,
                &preset,
                (4, false),
                &mut |_, image, _| {
                    images.push(image);
                    Ok(())
                },
            )
            .unwrap();
            frames.push(images);
        }
        let differing = |x: &image::RgbaImage, y: &image::RgbaImage| {
            x.pixels()
                .zip(y.pixels())
                .filter(|(p, q)| p.0.iter().zip(q.0).any(|(u, v)| u.abs_diff(v) > 8))
                .count()
        };
        let total = (240 * 180) as f64;
        for (i, (cpu, gpu)) in frames[0].iter().zip(&frames[1]).enumerate() {
            let share = differing(cpu, gpu) as f64 / total;
            assert!(
                share <= 0.002,
                "{effect:?} frame {i}: {:.3} % of pixels differ between CPU and GPU posing",
                100.0 * share
            );
        }
        assert!(
            differing(&frames[1][0], &frames[1][3]) > 100,
            "{effect:?}: the GPU-posed frames do not move"
        );
    }
}

/// `npr render MODEL --effect warp --animation Walk --frames 24 --gif`: the warp plays the
/// clip, references posed at their own moments and the proxy posed with the Fox
/// (`npr_warp::deform`), and every warped frame stays close to the full render of its
/// pose.
#[test]
fn the_warp_plays_the_clip() {
    if context_or_skip("the_warp_plays_the_clip").is_none() {
        return;
    }
    let dir = out_dir("anim-warp");
    let gif = dir.join("walk.gif");
    let json = dir.join("walk.json");
    let o = npr(&[
        "render",
        &fox(),
        "--effect",
        "warp",
        "--size",
        "200x150",
        "--animation",
        "Walk",
        "--frames",
        "24",
        "--gif",
        "--out",
        gif.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let frames = gif_frames(&gif);
    assert_eq!(frames.len(), 24);
    // Frames 0 and 10 are both references (full renders, k = 10) of other moments.
    assert_ne!(
        frames[0].buffer().as_raw(),
        frames[10].buffer().as_raw(),
        "the Fox walks"
    );
    let rows: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let psnr: Vec<f64> = rows
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|r| r["psnr_db"].as_f64())
        .collect();
    // A reference every k frames: the others are warped, each measured against the full
    // render of its pose (measured 28-34 dB at 800x600; npr-warp's tests/deforming.rs
    // compares the posed proxy with the rigid assumption).
    assert!(psnr.len() >= 20, "{psnr:?}");
    assert!(psnr.iter().all(|p| *p > 24.0), "{psnr:?}");
}
