//! The whole highlight setup on the GPU (`fidelity::GpuSetup`: the `N = H` search as a
//! compute pass feeding `HighlightSet::update_from_solutions_and_regions`, the regions
//! grown by `RegionPass`, the §4.2 receivers walked by `ReceiverPass` and drawn
//! indirectly) against the CPU setup on the same frames: the
//! highlight images within the FLIP bound the browser check holds the page to against the
//! native frame (mean 0.05 over the object's pixels), on procedural surfaces and the
//! scanned and CAD fixtures, for two lights each.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::CurvatureOptions;
use npr_gpu::{GpuMesh, ObjectUniforms};
use npr_specular::HighlightSet;
use npr_specular::fidelity::GpuSetup;
use npr_specular::snapshot::{HighlightScene, Renderer, light_eye_along};

mod common;
use common::{bounding_radius, meshes};

/// The mean FLIP a frame set up on the GPU may be from the CPU's.
const MAX_FLIP: f64 = 0.05;

#[test]
fn frames_set_up_on_the_gpu_are_the_cpu_frames_within_flip() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "frames_set_up_on_the_gpu_are_the_cpu_frames_within_flip",
    ) else {
        return;
    };
    let (w, h) = (256, 192);
    let renderer = Renderer::new(&ctx.device, &ctx.queue, w, h).unwrap();
    let mut rows = Vec::new();
    for (name, mut mesh) in meshes() {
        let centre =
            mesh.positions.iter().fold(Vec3::ZERO, |a, p| a + *p) / mesh.positions.len() as f32;
        for p in &mut mesh.positions {
            *p -= centre;
        }
        let radius = bounding_radius(&mesh);
        let gpu_mesh = GpuMesh::upload(&ctx.device, &mesh).unwrap();
        let mut cpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let mut gpu_set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let mut setup = GpuSetup::new(&ctx.device, &gpu_set, &mesh.indices).unwrap();
        for dir in [Vec3::new(0.3, 0.5, 1.0), Vec3::new(-0.6, 0.2, 0.8)] {
            let (light_eye, camera, light) =
                light_eye_along(dir, 3.0 * radius, w as f32 / h as f32);
            cpu_set.update(light_eye, Mat4::IDENTITY);
            setup
                .update(
                    &ctx.device,
                    &ctx.queue,
                    &mut gpu_set,
                    (light_eye, Mat4::IDENTITY),
                )
                .unwrap();
            assert!(!cpu_set.highlights().is_empty(), "{name}: no highlight");
            assert!(
                gpu_set.receiver_faces().is_empty(),
                "{name}: the GPU setup walked on the CPU"
            );
            assert!(
                gpu_set.stats().regions_on_gpu,
                "{name}: the GPU setup grew its regions on the CPU"
            );
            // A grey Phong base under the highlights, the background transparent, so that
            // FLIP is taken over the object's pixels.
            let scene = |set| HighlightScene {
                object: ObjectUniforms::new(Mat4::IDENTITY, Vec3::splat(0.4), 0.0, Vec3::ZERO, 1.0),
                clear: [0.0; 4],
                ..HighlightScene::on_black(&gpu_mesh, &mesh.indices, set, camera, light)
            };
            let cpu = renderer
                .render(&ctx.device, &ctx.queue, &scene(&cpu_set))
                .unwrap();
            let gpu = setup
                .render(&ctx.device, &ctx.queue, &renderer, &scene(&gpu_set))
                .unwrap();
            let flip = npr_gpu::testing::flip_mean(&cpu, &gpu).expect("object pixels");
            // The highlights must show: the frame without them is far from both.
            let mut bare = scene(&cpu_set);
            bare.highlights = false;
            let bare = renderer.render(&ctx.device, &ctx.queue, &bare).unwrap();
            let without = npr_gpu::testing::flip_mean(&cpu, &bare).expect("object pixels");
            rows.push((name, flip, without));
            assert!(
                flip <= MAX_FLIP && without > 4.0 * flip.max(1e-4),
                "{name}: the GPU setup's frame is FLIP {flip:.4} from the CPU's (bound \
                 {MAX_FLIP}), the frame without highlights {without:.4}; {}",
                npr_gpu::testing::image_failure("gpu-setup-frame", &cpu, &gpu)
            );
        }
    }
    eprintln!("mesh, FLIP to the CPU frame, FLIP of the frame without highlights: {rows:?}");
    assert_eq!(rows.len(), 2 * meshes().len());
}
