//! GPU posing (`npr_gpu::posing`) against the CPU reference, `Rig::pose_mesh`: every
//! skinned, morphing and procedural rig of the fixtures, at several clip times, through a
//! shuffled vertex order; positions within 1e-5 of the bounding radius, normals within
//! 0.05°. Two poses of one object recorded into one submission stay distinct. Each test
//! fails when no adapter exists, unless `NPR_SKIP_GPU=1` asks to skip (see
//! `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::Vec3;
use npr_geometry::Mesh;
use npr_geometry::animation::{Pose, Rig};
use npr_gpu::{FrameId, GpuError, GpuMesh, PassError, PoseInput, PosingPass, testing};

fn fixture(name: &str) -> Rig {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/meshes")
        .join(name);
    npr_geometry::io::load(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .rig
        .unwrap_or_else(|| panic!("{name} has no rig"))
}

/// Every rig the tests pose: the three glTF fixtures and the procedural ones.
fn rigs() -> Vec<(&'static str, Rig)> {
    use npr_geometry::generate;
    vec![
        ("Fox.glb", fixture("Fox.glb")),
        ("SimpleSkin.gltf", fixture("SimpleSkin.gltf")),
        ("MorphStressTest.gltf", fixture("MorphStressTest.gltf")),
        ("bent tube", generate::bent_tube(0.3, 2.0, 1.5, 24, 32).rig),
        (
            "stretched sphere",
            generate::stretched_sphere(1.6, 1.0, 0.7, 12).rig,
        ),
        ("twisted bar", generate::twisted_bar(0.5, 3.0, 24).rig),
    ]
}

/// A fixed shuffle of `0..n` (where the rig's vertex `v` sits in the uploaded mesh).
fn shuffled(n: usize) -> Vec<u32> {
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut state = 0x9e37_79b9_u32;
    for i in (1..n).rev() {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        order.swap(i, state as usize % (i + 1));
    }
    order
}

/// `mesh` with vertex `v` moved to `order[v]`.
fn reorder(mesh: &Mesh, order: &[u32]) -> Mesh {
    let mut out = mesh.clone();
    for (v, &o) in order.iter().enumerate() {
        out.positions[o as usize] = mesh.positions[v];
        out.normals[o as usize] = mesh.normals[v];
        if let Some(uv) = mesh.uvs.get(v) {
            out.uvs[o as usize] = *uv;
        }
    }
    out.indices = mesh.indices.iter().map(|&i| order[i as usize]).collect();
    out
}

/// The vertex buffer, copied into a readback buffer recorded into `encoder`.
fn copy_out(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    mesh: &GpuMesh,
) -> wgpu::Buffer {
    testing::copy_for_readback(device, encoder, &mesh.vertex_buffer)
}

/// Positions and normals of a [`copy_out`] buffer.
fn read_vertices(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Vec<(Vec3, Vec3)> {
    let data = testing::read_mapped(device, buffer);
    let floats: &[f32] = bytemuck::cast_slice(&data);
    floats
        .chunks_exact(8)
        .map(|c| (Vec3::new(c[0], c[1], c[2]), Vec3::new(c[3], c[4], c[5])))
        .collect()
}

fn radius(mesh: &Mesh) -> f32 {
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    0.5 * (hi - lo).length()
}

/// The worst position error over the radius and the worst normal angle (degrees) of the
/// GPU pose `gpu` (in `order`) against the CPU pose `cpu`.
fn errors(cpu: &Mesh, gpu: &[(Vec3, Vec3)], order: &[u32]) -> (f32, f32) {
    let r = radius(cpu).max(f32::MIN_POSITIVE);
    let mut worst = (0.0f32, 0.0f32);
    for (v, &o) in order.iter().enumerate() {
        let (p, n) = gpu[o as usize];
        worst.0 = worst.0.max((p - cpu.positions[v]).length() / r);
        let cos = n
            .normalize_or_zero()
            .dot(cpu.normals[v].normalize_or_zero());
        worst.1 = worst.1.max(cos.clamp(-1.0, 1.0).acos().to_degrees());
    }
    worst
}

/// The poses each rig is checked at: the bind pose and three moments of each clip.
fn poses(rig: &Rig) -> Vec<(String, Pose)> {
    let mut out = vec![("bind".to_string(), rig.bind_pose())];
    for (c, clip) in rig.clips().iter().enumerate() {
        for f in [0.0, 0.37, 0.81] {
            let t = clip.start() + f * clip.duration();
            out.push((format!("clip {c} at {t:.3} s"), rig.sample(clip, t)));
        }
    }
    out
}

#[test]
fn gpu_posing_equals_the_cpu_reference_on_every_rig() {
    let Some(ctx) = testing::context_or_skip("gpu_posing_equals_the_cpu_reference") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let pass = PosingPass::new(d);
    let mut frame = FrameId::default();
    let mut checked = 0;
    for (name, rig) in rigs() {
        let bind = rig.pose_mesh(&rig.bind_pose());
        let order = shuffled(rig.vertex_count());
        let mesh = GpuMesh::upload(d, &reorder(&bind, &order)).unwrap();
        let mut object = pass.create_object(d, &mesh, &rig, Some(&order)).unwrap();
        let poses = poses(&rig);
        let mut worst = (0.0f32, 0.0f32);
        assert!(poses.len() > 1 || rig.clips().is_empty(), "{name}: no clip");
        for (what, pose) in poses {
            frame = frame.next();
            let prepared = pass
                .prepare(q, &mut object, &PoseInput { frame, pose: &pose })
                .unwrap();
            let mut encoder = d.create_command_encoder(&Default::default());
            pass.record(&mut encoder, &object, &prepared).unwrap();
            let read = copy_out(d, &mut encoder, &mesh);
            q.submit([encoder.finish()]);
            let gpu = read_vertices(d, &read);
            let cpu = rig.pose_mesh(&pose);
            let (position, normal) = errors(&cpu, &gpu, &order);
            assert!(
                position <= 1e-5,
                "{name}, {what}: position error {position:.2e} of the radius (bound 1e-5)"
            );
            assert!(
                normal <= 0.05,
                "{name}, {what}: normal {normal:.4}° from the CPU pose (bound 0.05°)"
            );
            worst = (worst.0.max(position), worst.1.max(normal));
            checked += 1;
        }
        eprintln!(
            "{name}: worst position {:.2e} of the radius, normal {:.4}°{}",
            worst.0,
            worst.1,
            if object.recomputes_normals() {
                " (recomputed)"
            } else {
                ""
            }
        );
    }
    assert!(checked >= 6 * 2, "only {checked} poses checked");
}

/// Two poses of one object prepared and recorded into one submission, each followed by a
/// copy of the vertex buffer: each copy equals its own CPU pose, so the second prepare did
/// not overwrite the first's matrices.
#[test]
fn two_poses_in_one_submission_stay_distinct() {
    let Some(ctx) = testing::context_or_skip("two_poses_in_one_submission_stay_distinct") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let rig = fixture("Fox.glb");
    let clip = &rig.clips()[1];
    let (a, b) = (
        rig.sample(clip, 0.1),
        rig.sample(clip, 0.45 * clip.duration()),
    );
    let bind = rig.pose_mesh(&rig.bind_pose());
    let mesh = GpuMesh::upload(d, &bind).unwrap();
    let pass = PosingPass::new(d);
    let mut object = pass.create_object(d, &mesh, &rig, None).unwrap();
    let frame = FrameId::default().next();
    let pa = pass
        .prepare(q, &mut object, &PoseInput { frame, pose: &a })
        .unwrap();
    let pb = pass
        .prepare(q, &mut object, &PoseInput { frame, pose: &b })
        .unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &object, &pa).unwrap();
    let ra = copy_out(d, &mut encoder, &mesh);
    pass.record(&mut encoder, &object, &pb).unwrap();
    let rb = copy_out(d, &mut encoder, &mesh);
    q.submit([encoder.finish()]);
    let identity: Vec<u32> = (0..rig.vertex_count() as u32).collect();
    let (ga, gb) = (read_vertices(d, &ra), read_vertices(d, &rb));
    let (ca, cb) = (rig.pose_mesh(&a), rig.pose_mesh(&b));
    assert!(errors(&ca, &ga, &identity).0 <= 1e-5, "first pose");
    assert!(errors(&cb, &gb, &identity).0 <= 1e-5, "second pose");
    let moved = errors(&ca, &gb, &identity).0;
    assert!(
        moved > 1e-3,
        "the two poses are alike ({moved:.2e}): not a test"
    );
}

#[test]
fn stale_tickets_and_mismatched_meshes_are_refused() {
    let Some(ctx) = testing::context_or_skip("stale_tickets_and_mismatched_meshes") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let rig = fixture("SimpleSkin.gltf");
    let bind = rig.pose_mesh(&rig.bind_pose());
    let mesh = GpuMesh::upload(d, &bind).unwrap();
    let pass = PosingPass::new(d);
    let mut object = pass.create_object(d, &mesh, &rig, None).unwrap();
    let pose = rig.bind_pose();
    let f1 = FrameId::default().next();
    let old = pass
        .prepare(
            q,
            &mut object,
            &PoseInput {
                frame: f1,
                pose: &pose,
            },
        )
        .unwrap();
    pass.prepare(
        q,
        &mut object,
        &PoseInput {
            frame: f1.next(),
            pose: &pose,
        },
    )
    .unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    assert!(matches!(
        pass.record(&mut encoder, &object, &old),
        Err(GpuError::Pass(PassError::Stale { .. }))
    ));
    let other = PosingPass::new(d);
    assert!(matches!(
        other.prepare(
            q,
            &mut object,
            &PoseInput {
                frame: f1,
                pose: &pose
            }
        ),
        Err(GpuError::Pass(PassError::ForeignObject))
    ));
    let sphere = GpuMesh::upload(d, &npr_geometry::generate::icosphere(2, 1.0)).unwrap();
    assert!(matches!(
        pass.create_object(d, &sphere, &rig, None),
        Err(GpuError::InvalidMesh(_))
    ));
    let n = rig.vertex_count() as u32;
    let doubled: Vec<u32> = (0..n).map(|v| v.min(n - 2)).collect();
    let err = pass
        .create_object(d, &mesh, &rig, Some(&doubled))
        .unwrap_err();
    assert!(err.to_string().contains("vertex order"), "{err}");
}
