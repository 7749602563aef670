//! `[specular] search`: the highlights' `N = H` search on the GPU (`CentreSearchPass`),
//! with the regions grown (`RegionPass`) and the receivers walked there (`ReceiverPass`,
//! drawn indirectly), draws the frames
//! the CPU's setup draws, on a walking Fox, frame by frame with its
//! tracking (ids, fades), and the frame's statistics say where it ran.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::root;

use npr_app::animation::{Animated, Playback};
use npr_app::engine::Renderer;
use npr_app::model::Model;
use npr_app::preset::{Effect, Preset, SearchPreset};
use npr_app::view::View;
use npr_gpu::testing::context_or_skip;

/// Six frames of the Fox's walk (every fourth of its first clip), posed frame by frame,
/// with the highlights' setup `search`: each frame's statistics and image.
fn walk(
    ctx: &npr_gpu::GpuContext,
    search: SearchPreset,
) -> Vec<(npr_app::engine::FrameStats, image::RgbaImage)> {
    play(ctx, "Fox.glb", search)
}

/// [`walk`] on another animated fixture.
fn play(
    ctx: &npr_gpu::GpuContext,
    file: &str,
    search: SearchPreset,
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
    preset.specular.search = search;
    preset.specular.sigma = 0.85;
    let view = View::new(&preset, &animated.framing(), size, 0.0);
    let mut renderer = Renderer::new(&ctx.device, &ctx.queue, frames[0].clone(), size).unwrap();
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

#[test]
fn the_gpu_search_draws_the_cpu_frames_on_a_walking_model() {
    let Some(ctx) = context_or_skip("the_gpu_search_draws_the_cpu_frames_on_a_walking_model")
    else {
        return;
    };
    let render_all = |search| walk(ctx, search);
    let cpu = render_all(SearchPreset::Cpu);
    let gpu = render_all(SearchPreset::Gpu);
    let auto = render_all(SearchPreset::Auto);
    let (mut shown, mut one_wait) = (0, 0);
    for (i, ((c, ci), (g, gi))) in cpu.iter().zip(&gpu).enumerate() {
        assert!(
            !c.search_on_gpu && g.search_on_gpu,
            "frame {i}: where the search ran"
        );
        assert!(
            !c.receivers_on_gpu && g.receivers_on_gpu,
            "frame {i}: where the receivers were walked"
        );
        assert!(
            !c.regions_on_gpu && g.regions_on_gpu,
            "frame {i}: where the regions were grown"
        );
        // One wait where the regions grew from the GPU's seeds in the search's
        // submission, two where the update's seeds had a peak.
        assert!(
            c.gpu_waits == 0 && (1..=2).contains(&g.gpu_waits),
            "frame {i}: {} and {} waits",
            c.gpu_waits,
            g.gpu_waits
        );
        one_wait += usize::from(g.gpu_waits == 1);
        // The GPU walk's count arrives one frame late: the CPU's of the frame before.
        if i > 0 {
            let before = cpu[i - 1].0.receiver_faces;
            assert!(before > 0, "frame {}: no receivers", i - 1);
            let off = g.receiver_faces.abs_diff(before) as f64 / before as f64;
            assert!(
                off <= 0.005,
                "frame {i}: the GPU walk read back {} faces for frame {}, the CPU {before}",
                g.receiver_faces,
                i - 1
            );
        }
        assert_eq!(c.highlights, g.highlights, "frame {i}: highlight counts");
        let worst = ci
            .as_raw()
            .iter()
            .zip(gi.as_raw())
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap();
        assert!(
            worst <= 1,
            "frame {i}: the GPU search's frame differs by {worst}/255; {}",
            npr_gpu::testing::image_failure("gpu-search-frame", ci, gi)
        );
        shown += c.highlights;
    }
    assert!(shown >= 6, "only {shown} highlights over the walk");
    // The search, its peaks (the walking Fox has four bright facets without an `N = H`
    // point in every frame) and the regions in one submission.
    eprintln!("{one_wait} of {} GPU frames waited once", gpu.len());
    assert_eq!(one_wait, gpu.len(), "GPU frames that waited twice");
    // `auto` keeps one path for the model, whichever it timed faster.
    let on_gpu = auto[0].0.search_on_gpu;
    assert!(auto.iter().all(|(s, _)| s.search_on_gpu == on_gpu));
    // ... and walks the receivers where it searches, from its second frame.
    assert!(auto[1..].iter().all(|(s, _)| s.receivers_on_gpu == on_gpu));
}

/// A walk that overflows its first capacity (a fine sphere's one highlight crosses more
/// than the default's faces on the first GPU frame, which has no CPU walk to size it
/// from) is cut short in that frame, and grown for the frames after its counts arrive,
/// which then draw the CPU's frame.
#[test]
fn a_gpu_walk_that_overflowed_is_grown_for_the_next_frames() {
    let Some(ctx) = context_or_skip("a_gpu_walk_that_overflowed_is_grown_for_the_next_frames")
    else {
        return;
    };
    let mesh = npr_geometry::generate::icosphere(7, 1.0);
    assert!(mesh.triangle_count() > 16 * npr_specular::DEFAULT_WALK_CAPACITY);
    let model = Model::from_mesh("sphere", mesh);
    let size = (200, 150);
    let render_all = |search: SearchPreset| {
        let mut preset = Preset {
            effect: Effect::Specular,
            ..Preset::default()
        };
        preset.specular.search = search;
        preset.specular.abstraction = 0.0;
        preset.specular.sigma = 0.8;
        let view = View::new(&preset, &model.framing, size, 0.0);
        let mut renderer = Renderer::new(&ctx.device, &ctx.queue, model.clone(), size).unwrap();
        (0..3)
            .map(|_| {
                let stats = renderer
                    .render(&ctx.device, &ctx.queue, &preset, &view)
                    .unwrap();
                (stats, renderer.read(&ctx.device, &ctx.queue).unwrap())
            })
            .collect::<Vec<_>>()
    };
    let cpu = render_all(SearchPreset::Cpu);
    let gpu = render_all(SearchPreset::Gpu);
    let longest = cpu[0].0.receiver_faces;
    assert!(
        longest > npr_specular::DEFAULT_WALK_CAPACITY,
        "the sphere's highlight receives only {longest} faces: it does not overflow"
    );
    let worst = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap()
    };
    assert!(gpu.iter().all(|(s, _)| s.receivers_on_gpu));
    assert!(
        worst(&cpu[0].1, &gpu[0].1) > 16,
        "the first GPU walk was not cut short"
    );
    for i in 1..3 {
        let w = worst(&cpu[i].1, &gpu[i].1);
        assert!(
            w <= 1,
            "frame {i} after the walk grew differs by {w}/255; {}",
            npr_gpu::testing::image_failure("gpu-walk-grown", &cpu[i].1, &gpu[i].1)
        );
    }
    // The count read back for the grown walk is the CPU's.
    let off = gpu[2].0.receiver_faces.abs_diff(cpu[1].0.receiver_faces);
    assert!(off as f64 <= 0.005 * longest as f64, "{off} faces apart");
}

/// `search = "gpu-frame"`: the whole frame's highlights made on the GPU, nothing read
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
    let render_all = |search| play(ctx, file, search);
    let cpu = render_all(SearchPreset::Cpu);
    let gpu = render_all(SearchPreset::GpuFrame);
    let mut worst_flip = 0f64;
    for (i, ((c, ci), (g, gi))) in cpu.iter().zip(&gpu).enumerate() {
        assert!(
            g.search_on_gpu && g.regions_on_gpu && g.receivers_on_gpu && g.gpu_waits == 0,
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
