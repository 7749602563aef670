//! GPU tests of the pass contract (`npr_gpu::pass`): two prepares of one object in one
//! submission stay distinct, and `draw` refuses state prepared for another frame, object
//! or pass. Each test fails when no adapter exists, unless `NPR_SKIP_GPU=1` asks to skip
//! (see `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_gpu::snapshot::{BaseScene, render_base};
use npr_gpu::{
    BaseInput, BaseSettings, BaseShading, Camera, FrameId, FrameUniforms, GpuMesh, Light,
    ObjectUniforms, OffscreenTarget, PassError, ShadingModel, TargetFormats, readback_rgba,
    testing,
};

const SIZE: u32 = 96;

fn scene() -> (Camera, Light) {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.0);
    (camera, Light::directional(Vec3::new(1.0, 1.5, 2.0)))
}

fn pose(x: f32) -> ObjectUniforms {
    ObjectUniforms::default_material(Mat4::from_translation(Vec3::new(x, 0.0, 0.0)))
}

/// One object drawn at two poses into two targets, both prepared before one submit: each
/// image equals a render of that pose alone (the old setters wrote one buffer, so both
/// showed the last pose), and the two differ.
#[test]
fn two_poses_of_one_object_in_one_submission_give_two_images() {
    let Some(ctx) = testing::context_or_skip("two_poses_of_one_object_in_one_submission") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let mesh = GpuMesh::upload(d, &npr_geometry::generate::icosphere(3, 1.0)).unwrap();
    let (camera, light) = scene();
    let view = FrameUniforms::new(&camera, &light);
    let pass = BaseShading::new(d, q, TargetFormats::default(), &BaseSettings::default());
    let mut object = pass.create_object(d, &mesh);
    let frame = FrameId::default();
    let poses = [pose(-1.2), pose(1.2)];
    let prepared: Vec<_> = poses
        .iter()
        .map(|p| {
            let input = BaseInput {
                frame,
                view: &view,
                object: p,
                model: ShadingModel::Phong,
            };
            pass.prepare(q, &mut object, &input).unwrap()
        })
        .collect();
    assert_ne!(prepared[0].slot(), prepared[1].slot());
    let targets = [0, 1].map(|_| OffscreenTarget::new(d, SIZE, SIZE).unwrap());
    let mut encoder = d.create_command_encoder(&Default::default());
    for (target, p) in targets.iter().zip(&prepared) {
        let mut rpass = target.begin_clear_pass(&mut encoder, [0.0, 0.0, 0.0, 1.0]);
        pass.draw(&mut rpass, &object, p).unwrap();
    }
    q.submit(Some(encoder.finish()));
    let images = targets.map(|t| readback_rgba(d, q, &t.color).unwrap());
    assert_ne!(images[0], images[1], "two poses drew one image");
    for (image, p) in images.iter().zip(&poses) {
        let alone = render_base(
            d,
            q,
            &BaseScene {
                objects: &[(&mesh, *p)],
                camera,
                light,
                clear: [0.0, 0.0, 0.0, 1.0],
            },
            ShadingModel::Phong,
            SIZE,
            SIZE,
        )
        .unwrap();
        let worst = image
            .pixels()
            .zip(alone.pixels())
            .flat_map(|(a, b)| (0..4).map(move |c| a[c].abs_diff(b[c])))
            .max()
            .unwrap_or(0);
        assert!(
            worst <= 1,
            "a pose drawn with another differs by {worst}; {}",
            npr_gpu::testing::image_failure("contract-two-poses", &alone, image)
        );
    }
}

/// `draw` refuses a ticket of an earlier frame, of another object and of another pass
/// with a typed error, and records nothing then.
#[test]
fn draw_refuses_stale_or_foreign_state() {
    let Some(ctx) = testing::context_or_skip("draw_refuses_stale_or_foreign_state") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let mesh = GpuMesh::upload(d, &npr_geometry::generate::icosphere(2, 1.0)).unwrap();
    let (camera, light) = scene();
    let view = FrameUniforms::new(&camera, &light);
    let pass = BaseShading::new(d, q, TargetFormats::default(), &BaseSettings::default());
    let other_pass = BaseShading::new(d, q, TargetFormats::default(), &BaseSettings::default());
    let mut object = pass.create_object(d, &mesh);
    let mut other_object = pass.create_object(d, &mesh);
    let mut foreign_object = other_pass.create_object(d, &mesh);
    let at_origin = ObjectUniforms::default_material(Mat4::IDENTITY);
    let input = |frame| BaseInput {
        frame,
        view: &view,
        object: &at_origin,
        model: ShadingModel::Phong,
    };
    let old = pass.prepare(q, &mut object, &input(FrameId(1))).unwrap();
    let new = pass.prepare(q, &mut object, &input(FrameId(2))).unwrap();
    let others = pass
        .prepare(q, &mut other_object, &input(FrameId(2)))
        .unwrap();
    assert_eq!(
        pass.prepare(q, &mut foreign_object, &input(FrameId(2))),
        Err(PassError::ForeignObject)
    );
    let foreign = other_pass
        .prepare(q, &mut foreign_object, &input(FrameId(2)))
        .unwrap();
    let target = OffscreenTarget::new(d, SIZE, SIZE).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    {
        let mut rpass = target.begin_clear_pass(&mut encoder, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(
            pass.draw(&mut rpass, &object, &old),
            Err(PassError::Stale {
                prepared: 1,
                current: 2
            })
        );
        assert_eq!(
            pass.draw(&mut rpass, &object, &others),
            Err(PassError::ForeignPrepared)
        );
        assert_eq!(
            pass.draw(&mut rpass, &object, &foreign),
            Err(PassError::ForeignPrepared)
        );
        assert_eq!(
            pass.draw(&mut rpass, &foreign_object, &foreign),
            Err(PassError::ForeignObject)
        );
        pass.draw(&mut rpass, &object, &new).unwrap();
    }
    q.submit(Some(encoder.finish()));
    // The one accepted draw is there: the sphere covers the centre.
    let image = readback_rgba(d, q, &target.color).unwrap();
    assert!(
        image.get_pixel(SIZE / 2, SIZE / 2)[0] > 0,
        "the current ticket drew"
    );
}
