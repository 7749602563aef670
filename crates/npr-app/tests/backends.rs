//! `[specular] backend`: each setting runs its highlight backend through the app's
//! renderer and says so, and the GPU backend (the whole frame as compute passes, the pose
//! included) draws the frames the CPU backend draws on walking and morphing models, frame
//! by frame with their tracking (ids, fades).
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::root;

use npr_app::animation::{Animated, Playback};
use npr_app::engine::Renderer;
use npr_app::model::Model;
use npr_app::preset::{BackendPreset, Effect, Preset};
use npr_app::view::View;
use npr_gpu::testing::context_or_skip;

/// Six frames of the Fox's walk (every fourth of its first clip), posed frame by frame,
/// on the highlight backend `backend`: each frame's statistics and image.
fn walk(
    ctx: &npr_gpu::GpuContext,
    backend: BackendPreset,
) -> Vec<(npr_app::engine::FrameStats, image::RgbaImage)> {
    play(ctx, "Fox.glb", backend)
}

/// [`walk`] on another animated fixture.
fn play(
    ctx: &npr_gpu::GpuContext,
    file: &str,
    backend: BackendPreset,
) -> Vec<(npr_app::engine::FrameStats, image::RgbaImage)> {
    let model = Model::load(&root().join("fixtures/meshes").join(file)).unwrap();
    let animated = Animated::new(model, Some(0), Playback::default()).unwrap();
    let size = (240, 180);
    let frames: Vec<Model> = (0..6).map(|i| animated.frame(4 * i)).collect();
    let mut preset = Preset {
        effect: Effect::Specular,
        turn_deg: 30.0,
        ..Preset::default()
    };
    preset.specular.backend = backend;
    preset.specular.sigma = 0.85;
    let view = View::new(&preset, &animated.framing(), size, 0.0);
    let mut renderer = Renderer::new(ctx, frames[0].clone(), size).unwrap();
    frames
        .iter()
        .map(|m| {
            renderer.set_pose(&ctx.queue, m.clone()).unwrap();
            let stats = renderer
                .render(&ctx.device, &ctx.queue, &preset, &view)
                .unwrap();
            (stats, renderer.read(&ctx.device, &ctx.queue).unwrap())
        })
        .collect()
}

/// `[specular] backend`: each setting runs the backend it names, end to end through the
/// app's renderer, and the frame's statistics say which ran and why; `auto` on this
/// machine's software adapter gives the CPU by the rule (the rule's other branches are
/// `npr_specular::setup::backend`'s unit tests), and draws the CPU's frames.
#[test]
fn each_backend_setting_runs_its_backend_and_says_why() {
    let Some(ctx) = context_or_skip("each_backend_setting_runs_its_backend_and_says_why") else {
        return;
    };
    let software = ctx.is_software();
    let cpu = walk(ctx, BackendPreset::Cpu);
    let gpu = walk(ctx, BackendPreset::Gpu);
    let auto = walk(ctx, BackendPreset::Auto);
    for (i, (((c, ci), (g, _)), (a, ai))) in cpu.iter().zip(&gpu).zip(&auto).enumerate() {
        let said = |s: &npr_app::engine::FrameStats| s.backend.clone().unwrap_or_default();
        assert_eq!(said(c), "cpu (the setting)", "frame {i}");
        assert_eq!(said(g), "gpu (the setting)", "frame {i}");
        if software {
            assert!(
                said(a).starts_with("cpu (software adapter "),
                "frame {i}: auto said {}",
                said(a)
            );
            assert_eq!(
                ci.as_raw(),
                ai.as_raw(),
                "frame {i}: auto drew another frame"
            );
        } else {
            assert!(said(a).starts_with("gpu (GPU "), "frame {i}: {}", said(a));
        }
        assert!(c.highlights > 0, "frame {i}: no highlight");
    }
}

/// `backend = "gpu"`: the whole frame's highlights made on the GPU, nothing read
/// back on the frame's path, the pose's curvature and tables too, draws the CPU's frames
/// on the walking Fox (its pose taken every frame) within the FLIP bound the GPU setup is
/// held to, and the set sees each frame's highlights one frame late (the panel's and
/// picking's view): the CPU's of the frame before.
#[test]
fn a_frame_made_wholly_on_the_gpu_draws_the_cpu_frames_on_a_walking_model() {
    let Some(ctx) =
        context_or_skip("a_frame_made_wholly_on_the_gpu_draws_the_cpu_frames_on_a_walking_model")
    else {
        return;
    };
    // The skinned Fox, and a morphed model never used for tuning (its targets stretch
    // it by a tenth).
    for file in ["Fox.glb", "MorphStressTest.gltf"] {
        frames_match(ctx, file);
    }
}

fn frames_match(ctx: &npr_gpu::GpuContext, file: &str) {
    let render_all = |backend| play(ctx, file, backend);
    let cpu = render_all(BackendPreset::Cpu);
    let gpu = render_all(BackendPreset::Gpu);
    let mut worst_flip = 0f64;
    for (i, ((c, ci), (g, gi))) in cpu.iter().zip(&gpu).enumerate() {
        assert_eq!(
            g.backend.as_deref(),
            Some("gpu (the setting)"),
            "{file} frame {i}: {g:?}"
        );
        if i > 0 {
            assert_eq!(
                g.highlights,
                cpu[i - 1].0.highlights,
                "{file} frame {i}: the highlights read back are the frame before's"
            );
        }
        // The pose's curvature is measured on the GPU with the first pose's ball
        // (`npr_gpu::CurvaturePass`), the CPU's with each pose's: the images differ by
        // that much, not by the setup.
        let flip = npr_gpu::testing::flip_mean(ci, gi).expect("object pixels");
        worst_flip = worst_flip.max(flip);
        assert!(
            flip <= 0.05,
            "{file} frame {i}: the GPU's frame is {flip:.4} from the CPU's (FLIP); {}",
            npr_gpu::testing::image_failure("gpu-frame-walk", ci, gi)
        );
        // FLIP's mean over the object barely sees a few highlights drawn from the last
        // pose's tables (0.004 on this walk); the pixels they leave far off do (70–300 a
        // frame; none here when the pose is taken).
        let off = ci
            .pixels()
            .zip(gi.pixels())
            .filter(|(a, b)| a.0.iter().zip(b.0.iter()).any(|(x, y)| x.abs_diff(*y) > 16))
            .count();
        assert!(
            off * 2000 <= ci.pixels().len(),
            "{file} frame {i}: {off} pixels off by more than 16/255; {}",
            npr_gpu::testing::image_failure("gpu-frame-walk", ci, gi)
        );
        assert!(
            g.pose_on_gpu || i == 0,
            "{file} frame {i}: the pose was taken on the CPU"
        );
        assert!(c.highlights > 0, "{file} frame {i}: no highlight");
    }
    eprintln!("gpu-frame on {file}, posed on the GPU: FLIP at most {worst_flip:.4}");
}
