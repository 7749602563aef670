//! `[specular] search`: the highlights' `N = H` search on the GPU (`CentreSearchPass`),
//! with the receivers walked there (`ReceiverPass`, drawn indirectly), draws the frames
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

#[test]
fn the_gpu_search_draws_the_cpu_frames_on_a_walking_model() {
    let Some(ctx) = context_or_skip("the_gpu_search_draws_the_cpu_frames_on_a_walking_model")
    else {
        return;
    };
    let model = Model::load(&root().join("fixtures/meshes/Fox.glb")).unwrap();
    let animated = Animated::new(model, Some(0), Playback::default()).unwrap();
    let size = (240, 180);
    let frames: Vec<Model> = (0..6).map(|i| animated.frame(4 * i)).collect();
    let render_all = |search: SearchPreset| {
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
            .collect::<Vec<_>>()
    };
    let cpu = render_all(SearchPreset::Cpu);
    let gpu = render_all(SearchPreset::Gpu);
    let auto = render_all(SearchPreset::Auto);
    let mut shown = 0;
    for (i, ((c, ci), (g, gi))) in cpu.iter().zip(&gpu).enumerate() {
        assert!(
            !c.search_on_gpu && g.search_on_gpu,
            "frame {i}: where the search ran"
        );
        assert!(
            !c.receivers_on_gpu && g.receivers_on_gpu,
            "frame {i}: where the receivers were walked"
        );
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
    // `auto` keeps one path for the model, whichever it timed faster.
    let on_gpu = auto[0].0.search_on_gpu;
    assert!(auto.iter().all(|(s, _)| s.search_on_gpu == on_gpu));
    // ... and walks the receivers where it searches, from its second frame.
    assert!(auto[1..].iter().all(|(s, _)| s.receivers_on_gpu == on_gpu));
}
