//! GPU curvature (`npr_gpu::curvature`) against the CPU reference,
//! `CurvatureField::for_mesh` with the default options (the corrected form of Lee & Choi
//! Eq. (1), a ball of 3 mean edge lengths), on the same frame: an icosphere, a torus, the
//! bunny, and the Fox posed at a clip time (and that pose computed on the GPU by
//! `PosingPass`, measured from the same vertex buffer). Curvatures within 1e-3 of the
//! mesh's robust largest |κ| (the 99th percentile of max(|κmax|, |κmin|) over valid
//! vertices, which is smaller than the true largest, so the bound is stricter); normals
//! within 0.05°; principal directions within 0.5° where the principal curvatures differ
//! (|κmax − κmin| > 10 % of max(|κmax|, |κmin|)); the same vertices valid. Each test fails
//! when no adapter exists, unless `NPR_SKIP_GPU=1` asks to skip (see `npr_gpu::testing`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::Vec3;
use npr_geometry::{CurvatureField, CurvatureOptions, CurvatureRadius, Mesh};
use npr_gpu::{
    CurvatureInput, CurvatureObject, CurvaturePass, FrameId, GpuError, GpuMesh, PoseInput,
    PosingPass, testing,
};

fn fixture(name: &str) -> npr_geometry::io::Loaded {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/meshes")
        .join(name);
    npr_geometry::io::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn read_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Vec<u8> {
    testing::read_mapped(device, buffer)
}

/// The output copied into a readback buffer recorded into `encoder`.
fn copy_out(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    object: &CurvatureObject,
) -> wgpu::Buffer {
    testing::copy_for_readback(device, encoder, object.output())
}

/// The worst errors of a GPU field against the CPU's.
type Errors = npr_geometry::FieldDifference;

fn errors(cpu: &CurvatureField, gpu: &CurvatureField) -> Errors {
    assert_eq!(cpu.len(), gpu.len(), "entry counts");
    cpu.difference(gpu)
}

fn check(name: &str, e: &Errors) {
    eprintln!(
        "{name}: |Δκ| ≤ {:.2e} of the robust largest |κ| {:.4} (largest {:.4}), normal ≤ {:.1e}°, \
         directions ≤ {:.1e}° at {} of {} vertices, {} validity differences",
        e.kappa,
        e.scale.0,
        e.scale.1,
        e.normal_deg,
        e.direction_deg,
        e.directions_checked,
        e.vertices,
        e.validity
    );
    assert!(e.scale.0 > 0.0, "{name}: no curvature to compare");
    assert_eq!(e.validity, 0, "{name}: validity differs");
    assert!(
        e.kappa <= 1e-3,
        "{name}: curvature off by {:.2e} of the largest |κ| (bound 1e-3)",
        e.kappa
    );
    assert!(
        e.normal_deg <= 0.05,
        "{name}: normal {:.4}° off (bound 0.05°)",
        e.normal_deg
    );
    assert!(
        e.direction_deg <= 0.5,
        "{name}: principal directions {:.4}° off (bound 0.5°)",
        e.direction_deg
    );
}

/// Measures `mesh` (uploaded as `gpu`) on the GPU and returns the decoded field.
fn measure(
    ctx: &npr_gpu::GpuContext,
    pass: &CurvaturePass,
    object: &mut CurvatureObject,
    frame: FrameId,
) -> CurvatureField {
    let (d, q) = (&ctx.device, &ctx.queue);
    let prepared = pass.prepare(q, object, &CurvatureInput { frame }).unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    pass.record(&mut encoder, object, &prepared).unwrap();
    let read = copy_out(d, &mut encoder, object);
    q.submit([encoder.finish()]);
    object.decode(&read_buffer(d, &read))
}

fn compare(ctx: &npr_gpu::GpuContext, pass: &CurvaturePass, name: &str, mesh: &Mesh) -> Errors {
    let gpu_mesh = GpuMesh::upload(&ctx.device, mesh).unwrap();
    let mut object = pass
        .create_object(&ctx.device, &gpu_mesh, mesh, CurvatureRadius::default())
        .unwrap();
    let mut frame = FrameId::default().next();
    let gpu = measure(ctx, pass, &mut object, frame);
    // The time of a measurement with its readback, for the record (no bound).
    let mut times: Vec<f64> = (0..3)
        .map(|_| {
            frame = frame.next();
            let start = std::time::Instant::now();
            measure(ctx, pass, &mut object, frame);
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    eprintln!(
        "{name}: {} welded vertices, {} ball entries; record + submit + readback {:.2} ms (median of 3)",
        object.welded_vertex_count(),
        object.ball_entries(),
        times[1]
    );
    let (_, _, cpu) = CurvatureField::for_mesh(mesh, &CurvatureOptions::default());
    assert_eq!(object.radius_world(), cpu.radius_world, "{name}: radius");
    let e = errors(&cpu, &gpu);
    check(name, &e);
    e
}

fn fox_pose() -> (npr_geometry::animation::Rig, npr_geometry::animation::Pose) {
    let rig = fixture("Fox.glb").rig.expect("the Fox has a rig");
    let pose = rig.sample(&rig.clips()[1], 0.4);
    (rig, pose)
}

#[test]
fn gpu_curvature_equals_the_cpu_reference() {
    let Some(ctx) = testing::context_or_skip("gpu_curvature_equals_the_cpu_reference") else {
        return;
    };
    let pass = CurvaturePass::new(&ctx.device);
    use npr_geometry::generate;
    let (rig, pose) = fox_pose();
    let meshes = [
        ("icosphere(4, 1)", generate::icosphere(4, 1.0)),
        ("torus(1, 0.45, 96, 48)", generate::torus(1.0, 0.45, 96, 48)),
        ("torus(1, 0.35, 48, 24)", generate::torus(1.0, 0.35, 48, 24)),
        ("bunny", fixture("stanford-bunny.obj").mesh),
        ("Fox, clip 1 at 0.4 s", rig.pose_mesh(&pose)),
    ];
    for (name, mesh) in &meshes {
        let e = compare(ctx, &pass, name, mesh);
        assert!(
            e.directions_checked > 0 || name.starts_with("icosphere"),
            "{name}: no direction compared"
        );
    }
}

/// The Fox posed by `PosingPass` into its vertex buffer and measured from that buffer in
/// the same submission, against the CPU field of that same frame: the positions the GPU
/// posed, read back (the object's ball lists come from the CPU pose, which welds the same).
#[test]
fn a_mesh_posed_on_the_gpu_is_measured_from_its_own_buffer() {
    let Some(ctx) = testing::context_or_skip("a_mesh_posed_on_the_gpu_is_measured") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let (rig, pose) = fox_pose();
    let bind = rig.pose_mesh(&rig.bind_pose());
    let posed = rig.pose_mesh(&pose);
    let gpu_mesh = GpuMesh::upload(d, &bind).unwrap();
    let posing = PosingPass::new(d);
    let mut posed_object = posing.create_object(d, &gpu_mesh, &rig, None).unwrap();
    let pass = CurvaturePass::new(d);
    let mut object = pass
        .create_object(d, &gpu_mesh, &posed, CurvatureRadius::default())
        .unwrap();
    let frame = FrameId::default().next();
    let pp = posing
        .prepare(q, &mut posed_object, &PoseInput { frame, pose: &pose })
        .unwrap();
    let pc = pass
        .prepare(q, &mut object, &CurvatureInput { frame })
        .unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    posing.record(&mut encoder, &posed_object, &pp).unwrap();
    pass.record(&mut encoder, &object, &pc).unwrap();
    let read = copy_out(d, &mut encoder, &object);
    let size = gpu_mesh.vertex_buffer.size();
    let vertices = d.create_buffer(&wgpu::BufferDescriptor {
        label: Some("curvature test vertices"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(&gpu_mesh.vertex_buffer, 0, &vertices, 0, size);
    q.submit([encoder.finish()]);
    let gpu = object.decode(&read_buffer(d, &read));
    let bytes = read_buffer(d, &vertices);
    let floats: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
    let mut frame_mesh = posed.clone();
    for (p, c) in frame_mesh.positions.iter_mut().zip(floats.chunks_exact(8)) {
        *p = Vec3::new(c[0], c[1], c[2]);
    }
    let (_, _, cpu) = CurvatureField::for_mesh(&frame_mesh, &CurvatureOptions::default());
    check("Fox posed on the GPU", &errors(&cpu, &gpu));
    // Not a test unless the pose moved the curvature.
    let (_, _, at_bind) = CurvatureField::for_mesh(&bind, &CurvatureOptions::default());
    let moved = errors(&cpu, &at_bind);
    assert!(
        moved.kappa > 1e-2,
        "the pose hardly changes the curvature ({:.2e}): not a test",
        moved.kappa
    );
}

#[test]
fn mismatched_meshes_and_stale_tickets_are_refused() {
    let Some(ctx) = testing::context_or_skip("curvature_mismatched_meshes") else {
        return;
    };
    let (d, q) = (&ctx.device, &ctx.queue);
    let pass = CurvaturePass::new(d);
    let sphere = npr_geometry::generate::icosphere(2, 1.0);
    let other = npr_geometry::generate::icosphere(1, 1.0);
    let gpu_mesh = GpuMesh::upload(d, &sphere).unwrap();
    assert!(matches!(
        pass.create_object(d, &gpu_mesh, &other, CurvatureRadius::default()),
        Err(GpuError::InvalidMesh(_))
    ));
    let mut object = pass
        .create_object(d, &gpu_mesh, &sphere, CurvatureRadius::default())
        .unwrap();
    let f1 = FrameId::default().next();
    let old = pass
        .prepare(q, &mut object, &CurvatureInput { frame: f1 })
        .unwrap();
    pass.prepare(q, &mut object, &CurvatureInput { frame: f1.next() })
        .unwrap();
    let mut encoder = d.create_command_encoder(&Default::default());
    assert!(matches!(
        pass.record(&mut encoder, &object, &old),
        Err(GpuError::Pass(npr_gpu::PassError::Stale { .. }))
    ));
    let foreign = CurvaturePass::new(d);
    assert!(matches!(
        foreign.prepare(q, &mut object, &CurvatureInput { frame: f1 }),
        Err(GpuError::Pass(npr_gpu::PassError::ForeignObject))
    ));
}
