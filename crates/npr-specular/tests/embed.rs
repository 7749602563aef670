//! The README's embedding example (`examples/embed.rs`, included here as a module) draws
//! the highlight where the analytic model puts it, on each highlight backend: a unit
//! sphere with the point light at the eye on +z has `N = H` at (0, 0, 1), which projects
//! to the image centre.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod embed;

use glam::Vec3;
use npr_gpu::testing;
use npr_specular::{Backend, BackendSetting};

#[test]
fn embed_example_draws_the_highlight_at_n_equals_h() {
    let Some(ctx) = testing::context_or_skip("embed_example_draws_the_highlight_at_n_equals_h")
    else {
        return;
    };
    let adapter = ctx.adapter.get_info();
    for (setting, backend) in [
        (BackendSetting::Cpu, Backend::Cpu),
        (BackendSetting::Gpu, Backend::Gpu),
    ] {
        let gpu = (&ctx.device, &ctx.queue);
        let ([with, without], hl) = embed::render_sphere(gpu, (&adapter, setting), SIZE).unwrap();
        assert_eq!(hl.setup_object.backend(), backend);
        if backend == Backend::Cpu {
            // The CPU side: one highlight, centred on the analytic N = H point (the GPU
            // backend's set sees its frame one frame late, after this one).
            let set = hl.setup_object.set();
            assert_eq!(set.highlights().len(), 1);
            let c = set.highlights()[0].projector.centre_world;
            assert!(c.distance(Vec3::Z) < 0.02, "centre {c}");
        }
        highlight_at_the_centre(&with, &without, backend);
    }
}

const SIZE: u32 = 256;

/// The pixels the pass changed lie on the sphere, centred on the `N = H` point.
fn highlight_at_the_centre(with: &image::RgbaImage, without: &image::RgbaImage, backend: Backend) {
    // The GPU side: the pixels the pass changed, weighted by how much.
    let (mut sum, mut weight, mut count, mut far) = (glam::Vec2::ZERO, 0.0f32, 0, 0);
    let centre = glam::Vec2::splat(SIZE as f32 / 2.0);
    for (x, y, p) in with.enumerate_pixels() {
        let q = without.get_pixel(x, y);
        let d = (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap_or(0);
        if d > 4 {
            let at = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            sum += at * f32::from(d);
            weight += f32::from(d);
            count += 1;
            // The sphere's silhouette is 91 px from the centre (asin(1/4) in a 40° view).
            if at.distance(centre) > 92.0 {
                far += 1;
            }
        }
    }
    assert!(count > 100, "{backend}: {count} highlight pixels");
    assert_eq!(far, 0, "{backend}: pixels changed off the sphere");
    let off = (sum / weight).distance(centre);
    assert!(
        off <= 2.0,
        "{backend}: highlight centroid {off:.2} px from the N = H point"
    );
}
