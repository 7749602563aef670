//! `cargo xtask bench curvature`'s GPU table: the corrected tensor of Eq. (1) measured by
//! `npr_gpu::CurvaturePass` (two gathers over the mesh's vertex buffer, the per-vertex
//! face lists split into chunks that each fit one storage binding) against
//! `CurvatureField::compute` on the CPU (rayon), on the main table's meshes, in one run.
//!
//! `cpu_curvature_ms_median` is the CPU field on the mesh's topology (built once, as the
//! GPU's lists are); `gpu_curvature_ms_median` records both dispatches, submits and waits.
//! Agreement: `kappa_err_rel_max` is the largest |Δκ| over vertices valid in both, over
//! the largest |κ| of the CPU field; `dir_err_deg_p99` the 99th percentile of the angle
//! between the `e_max` directions where the principal curvatures differ by more than 10 %
//! of the larger.

use super::table::{Cell, Table};
use glam::Vec3;
use npr_geometry::stats::{median, quantile};
use npr_geometry::{CurvatureField, CurvatureOptions, CurvatureRadius, Mesh, Topology};
use std::time::Instant;

/// Timed repetitions per mesh (the median is reported).
const RUNS: usize = 5;

/// Largest relative κ error and the 99th-percentile direction error of `gpu` against `cpu`.
fn agreement(cpu: &CurvatureField, gpu: &CurvatureField) -> (f64, f64) {
    let scale = cpu
        .kappa_max
        .iter()
        .chain(&cpu.kappa_min)
        .zip(cpu.valid.iter().chain(&cpu.valid))
        .filter(|(_, v)| **v)
        .map(|(k, _)| k.abs())
        .fold(0.0f32, f32::max)
        .max(f32::MIN_POSITIVE);
    let mut worst = 0.0f32;
    let mut angles = Vec::new();
    for v in 0..cpu.valid.len().min(gpu.valid.len()) {
        if !(cpu.valid[v] && gpu.valid[v]) {
            continue;
        }
        let dk = (cpu.kappa_max[v] - gpu.kappa_max[v])
            .abs()
            .max((cpu.kappa_min[v] - gpu.kappa_min[v]).abs());
        worst = worst.max(dk);
        let (a, b) = (cpu.kappa_max[v], cpu.kappa_min[v]);
        if (a - b).abs() > 0.1 * a.abs().max(b.abs()) {
            let cos = cpu.dir_kappa_max[v]
                .normalize_or(Vec3::X)
                .dot(gpu.dir_kappa_max[v].normalize_or(Vec3::X))
                .abs()
                .min(1.0);
            angles.push(f64::from(cos.acos().to_degrees()));
        }
    }
    let p99 = if angles.is_empty() {
        0.0
    } else {
        quantile(angles, 0.99)
    };
    (f64::from(worst / scale), p99)
}

/// The GPU table's empty shape.
pub fn table() -> Table {
    Table::new(
        "curvature on the GPU (npr_gpu::CurvaturePass, corrected form, default radius) against the CPU, one run",
        &[
            "mesh",
            "vertices",
            "chunks",
            "cpu_curvature_ms_median",
            "gpu_curvature_ms_median",
            "gpu_vs_cpu",
            "gpu_ms_per_100k_vertices",
            "kappa_err_rel_max",
            "dir_err_deg_p99",
            "adapter",
        ],
    )
}

/// One row: `mesh` measured both ways.
///
/// # Errors
/// An upload or a pass the device refuses.
pub fn row(ctx: &npr_gpu::GpuContext, name: &str, mesh: &Mesh) -> anyhow::Result<Vec<Cell>> {
    let (d, q) = (&ctx.device, &ctx.queue);
    let options = CurvatureOptions::default();
    let topo = Topology::new(&npr_geometry::weld(mesh));
    let mut cpu_ms = Vec::new();
    let mut cpu = CurvatureField::default();
    for _ in 0..RUNS {
        let t = Instant::now();
        cpu = CurvatureField::compute(&topo, &options);
        cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let gpu_mesh = npr_gpu::GpuMesh::upload(d, mesh)?;
    let pass = npr_gpu::CurvaturePass::new(d);
    let mut object = pass.create_object(d, &gpu_mesh, mesh, CurvatureRadius::default())?;
    let mut frame = npr_gpu::FrameId::default();
    let mut gpu_ms = Vec::new();
    for _ in 0..RUNS {
        frame = frame.next();
        let t = Instant::now();
        let prepared = pass.prepare(q, &mut object, &npr_gpu::CurvatureInput { frame })?;
        let mut encoder = d.create_command_encoder(&Default::default());
        pass.record(&mut encoder, &object, &prepared)?;
        q.submit([encoder.finish()]);
        d.poll(wgpu::PollType::wait_indefinitely())?;
        gpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    // The bench's one readback, after the timing.
    let mut encoder = d.create_command_encoder(&Default::default());
    let read = npr_gpu::testing::copy_for_readback(d, &mut encoder, object.output());
    q.submit([encoder.finish()]);
    let bytes = npr_gpu::testing::read_mapped(d, &read);
    let (kappa_err, dir_err) = agreement(&cpu, &object.decode(&bytes));
    let (cpu_ms, gpu_ms) = (median(cpu_ms), median(gpu_ms));
    let vertices = object.welded_vertex_count();
    Ok(vec![
        Cell::Text(name.to_string()),
        Cell::Int(vertices as i64),
        Cell::Int(object.chunk_count() as i64),
        Cell::Num(cpu_ms, 3),
        Cell::Num(gpu_ms, 3),
        Cell::Num(gpu_ms / cpu_ms.max(1e-9), 2),
        Cell::Num(gpu_ms * 1e5 / vertices.max(1) as f64, 3),
        Cell::Num(kappa_err, 6),
        Cell::Num(dir_err, 3),
        Cell::Text(ctx.adapter.get_info().name),
    ])
}
