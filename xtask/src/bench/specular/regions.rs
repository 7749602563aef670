//! The second table of `bench specular`: the regions `N·H ≥ σ` of each frame's centres
//! grown and fitted on the GPU (`npr_specular::gpu::RegionPass`) against the CPU growth
//! (`RegionGrower::grow_all`) of the same seeds, in the same run: the CPU growth's time,
//! the GPU's (prepare, record, submit and the wait for its 80-byte records), their ratio,
//! the share of region faces the two give to different seeds, and the growths the GPU cut
//! at its queue's length.

use super::{FRAMES, View};
use crate::bench::table::{Cell, Table};
use npr_geometry::stats::median;
use npr_geometry::{CurvatureOptions, Mesh};
use npr_gpu::{FrameId, GpuContext};
use npr_specular::cpu::region::{Region, RegionFrame, RegionGrower, RegionPatches};
use npr_specular::{HighlightSet, ProjectorControls, gpu::RegionInput, gpu::RegionPass};
use std::time::Instant;

pub(super) fn new_table(adapter: &str) -> Table {
    Table::new(
        &format!(
            "specular regions: the regions N·H ≥ σ of each frame's centres, CPU growth against \
             RegionPass, {FRAMES} frames, adapter {adapter}"
        ),
        &[
            "mesh",
            "faces",
            "seeds_median",
            "region_faces_median",
            "cpu_region_us_median",
            "gpu_region_us_median",
            "gpu_over_cpu",
            "faces_won_apart_share",
            "overflowed_growths",
            "adapter",
        ],
    )
}

/// One mesh's row.
pub(super) fn row(
    ctx: &GpuContext,
    mesh: &Mesh,
    view: &View,
    name: &str,
    adapter: &str,
) -> anyhow::Result<Vec<Cell>> {
    let set = HighlightSet::new(mesh, &CurvatureOptions::default())?;
    let sigma = ProjectorControls::default().sigma;
    let (topology, normals) = (set.topology(), set.search().normals());
    let mut grower = RegionGrower::with_patches(RegionPatches::new(topology, normals));
    let pass = RegionPass::new(&ctx.device);
    let mut object = pass.create_object(&ctx.device, &set)?;
    let (mut seeds_n, mut faces_n, mut cpu_us, mut gpu_us) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut faces, mut apart, mut overflowed) = (0usize, 0usize, 0usize);
    let mut id = FrameId::default();
    let bar = crate::bench::progress(FRAMES as u64 + 3, &format!("{name} regions"));
    for frame in 0..FRAMES + 3 {
        let (world_from_object, light_eye) = view.frame(frame);
        let seeds: Vec<_> = set
            .search()
            .find(light_eye, world_from_object)
            .into_iter()
            .map(|c| (c, sigma))
            .collect();
        let region_frame = RegionFrame {
            topology,
            normals,
            world_from_object,
            light_eye,
        };
        let t = Instant::now();
        let cpu = grower.grow_all(&region_frame, &seeds);
        let cpu_time = t.elapsed().as_secs_f64() * 1e6;
        id = id.next();
        let input = RegionInput {
            frame: id,
            set: &set,
            seeds: &seeds,
            light_eye,
            world_from_object,
        };
        let t = Instant::now();
        let gpu = pass.grow_now(&ctx.device, &ctx.queue, &mut object, &input)?;
        let gpu_time = t.elapsed().as_secs_f64() * 1e6;
        bar.inc(1);
        let won = |r: &Region| match r {
            Region::Fit(_, n) => *n,
            _ => 0,
        };
        let frame_faces: usize = cpu.iter().map(won).sum();
        if frame < 3 {
            continue;
        }
        faces += frame_faces;
        apart += cpu
            .iter()
            .zip(&gpu)
            .map(|(c, g)| won(c).abs_diff(won(&g.region)))
            .sum::<usize>();
        overflowed += gpu.iter().filter(|g| g.overflowed).count();
        seeds_n.push(seeds.len() as f64);
        faces_n.push(frame_faces as f64);
        cpu_us.push(cpu_time);
        gpu_us.push(gpu_time);
    }
    bar.finish_and_clear();
    let (c, g) = (median(cpu_us), median(gpu_us));
    Ok(vec![
        name.into(),
        (mesh.indices.len() / 3).into(),
        Cell::Num(median(seeds_n), 0),
        Cell::Num(median(faces_n), 0),
        Cell::Num(c, 1),
        Cell::Num(g, 1),
        Cell::Num(g / c.max(1e-9), 2),
        Cell::Num(apart as f64 / faces.max(1) as f64, 5),
        overflowed.into(),
        adapter.into(),
    ])
}
