//! The frame's highlights made into projectors on the GPU ([`ProjectorPass`],
//! `projectors.wgsl`) against the CPU's update ([`HighlightSet::update`], the reference)
//! on the same frames: the same highlights (ids, found, peak, pieces, opacities, centres
//! within 1e-4 of the radius, footprints) and the same records for the highlight pass
//! (Eq. (9)'s map, axes, falloff, tint, layer, who shares a region), frame after frame,
//! from the CPU's table of its last update and from the GPU's own table (nothing read
//! back between frames), with the user's edits and with the paper's sizing.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, LightEye};
use npr_gpu::{FrameId, GpuContext};
use npr_specular::{
    HighlightSet, HighlightSizing, gpu::CentreSearchPass, gpu::GpuFrame, gpu::GpuFrameStatus,
    gpu::ProjectorInput, gpu::ProjectorPass, gpu::RegionPass, gpu::TrackedInput,
    gpu::projector_gpu,
};

mod common;
use common::{bounding_radius, fixture, record_gap, turn};

/// The passes and objects of one mesh's frames on the GPU.
struct Frames {
    search_pass: CentreSearchPass,
    region_pass: RegionPass,
    projector_pass: ProjectorPass,
    search: npr_specular::gpu::SearchObject,
    regions: npr_specular::gpu::RegionObject,
    projectors: npr_specular::gpu::ProjectorObject,
    frame: FrameId,
}

impl Frames {
    fn new(ctx: &GpuContext, set: &HighlightSet) -> Self {
        let search_pass = CentreSearchPass::new(&ctx.device);
        let region_pass = RegionPass::new(&ctx.device);
        let projector_pass = ProjectorPass::new(&ctx.device);
        Self {
            search: search_pass
                .create_object_with_peaks(&ctx.device, set)
                .unwrap(),
            regions: region_pass.create_object(&ctx.device, set).unwrap(),
            projectors: projector_pass.create_object(&ctx.device),
            search_pass,
            region_pass,
            projector_pass,
            frame: FrameId::default(),
        }
    }

    /// One frame in one submission: the search, the regions seeded from its centres
    /// (matched with `set`'s last update, or with the GPU's own table where `own_table`),
    /// the projectors; then read back.
    fn run(
        &mut self,
        ctx: &GpuContext,
        set: &HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
        own_table: bool,
    ) -> GpuFrame {
        self.frame = self.frame.next();
        let searched = self
            .search_pass
            .prepare_for_set(
                &ctx.queue,
                &mut self.search,
                (set, self.frame),
                (light_eye, world_from_object),
            )
            .unwrap();
        let tracked = TrackedInput {
            frame: self.frame,
            set,
            light_eye,
            world_from_object,
            search: (&self.search, &searched),
        };
        let grown = if own_table {
            let table = self.projectors.table().clone();
            self.region_pass.prepare_tracked_on_table(
                &ctx.queue,
                &mut self.regions,
                &tracked,
                (&table, npr_specular::gpu::TRACKED_SEEDS),
            )
        } else {
            self.region_pass
                .prepare_tracked(&ctx.queue, &mut self.regions, &tracked)
        }
        .unwrap();
        let projected = self
            .projector_pass
            .prepare(
                &ctx.queue,
                &mut self.projectors,
                &ProjectorInput {
                    frame: self.frame,
                    set,
                    world_from_object,
                    regions: (&self.regions, &grown),
                    search: (&self.search, &searched),
                    normal_maps: &[false; 8],
                },
            )
            .unwrap();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.search_pass
            .record(&mut encoder, &self.search, &searched)
            .unwrap();
        self.region_pass
            .record(&mut encoder, &self.regions, &grown)
            .unwrap();
        self.projector_pass
            .record(&mut encoder, &self.projectors, &projected)
            .unwrap();
        ctx.queue.submit([encoder.finish()]);
        self.projectors
            .map_frame(&ctx.device, &ctx.queue)
            .wait(&ctx.device)
            .unwrap()
    }
}

#[derive(Default)]
struct Tally {
    frames: usize,
    highlights: usize,
    faded: usize,
    pieces: usize,
    shared: usize,
    worst_record: f32,
    worst_centre: f32,
}

/// The GPU's frame against the CPU's update of the same frame.
fn compare(gpu: &GpuFrame, cpu: &HighlightSet, radius: f32, at: &str, tally: &mut Tally) {
    assert_eq!(gpu.status, GpuFrameStatus::Built, "{at}");
    let wholes: Vec<_> = cpu.highlights().iter().filter(|h| h.piece == 0).collect();
    assert_eq!(gpu.highlights.len(), wholes.len(), "{at}: highlight counts");
    for (g, c) in gpu.highlights.iter().zip(&wholes) {
        assert_eq!(
            (g.id, g.found, g.peak, g.pieces),
            (c.id, c.found, c.peak, c.pieces),
            "{at}"
        );
        assert!((g.opacity - c.opacity).abs() <= 1e-5, "{at}: opacity");
        let d = g.centre.position_world.distance(c.centre.position_world) / radius;
        tally.worst_centre = tally.worst_centre.max(d);
        assert!(d <= 1e-4, "{at}: highlight {} moved {d:.2e} r", g.id);
        let e = (g.footprint.half_extent - c.footprint.half_extent)
            .abs()
            .max_element();
        assert!(
            e <= 1e-4 * radius,
            "{at}: footprint {:?} against {:?}",
            g.footprint,
            c.footprint
        );
        tally.faded += usize::from(c.opacity < 1.0);
        tally.pieces += usize::from(c.pieces > 0);
    }
    assert_eq!(
        gpu.projectors.len(),
        cpu.highlights().len(),
        "{at}: projectors"
    );
    for (k, (g, h)) in gpu.projectors.iter().zip(cpu.highlights()).enumerate() {
        let want = projector_gpu(h, h.controls.texture_layer.min(7), false);
        let gap = record_gap(g, &want);
        // A piece of a long bent region is cut along it face by face on the GPU, a whole
        // patch at a time by the set's grower (`region::split`): its footprint may differ
        // by 1.5e-3 of the radius, a few percent of the piece.
        if h.piece == 0 {
            tally.worst_record = tally.worst_record.max(gap);
        }
        let bound = if h.piece == 0 { 2e-3 } else { 6e-2 };
        assert!(
            gap <= bound,
            "{at}: projector {k} {g:?} against the CPU's {want:?}"
        );
        assert_eq!(g.neighbours, want.neighbours, "{at}: projector {k} shares");
        tally.shared += usize::from(want.neighbours[0] != u32::MAX);
    }
    tally.frames += 1;
    tally.highlights += wholes.len();
}

fn meshes() -> Vec<(&'static str, npr_geometry::Mesh)> {
    vec![
        ("spot", fixture("spot.obj")),
        ("bunny", fixture("stanford-bunny.obj")),
        ("torus", npr_geometry::generate::torus(1.0, 0.35, 64, 32)),
    ]
}

/// Each frame from the CPU's table of its last update: the GPU's frame is the CPU
/// update's; then frame after frame from the GPU's own table, nothing read back between.
#[test]
fn projectors_built_on_the_gpu_are_the_cpu_updates() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("projectors_built_on_the_gpu_are_the_cpu_updates")
    else {
        return;
    };
    let options = CurvatureOptions::default();
    for own_table in [false, true] {
        let mut tally = Tally::default();
        for (name, mesh) in meshes() {
            let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
            let radius = bounding_radius(&mesh);
            let mut frames = Frames::new(ctx, &cpu);
            for step in 0..14 {
                let frame = turn(radius, step);
                let gpu = frames.run(ctx, &cpu, frame, own_table);
                cpu.update(frame.0, frame.1);
                let at = format!("{name} frame {step} (own table: {own_table})");
                compare(&gpu, &cpu, radius, &at, &mut tally);
            }
        }
        eprintln!(
            "own table {own_table}: {} frames, {} highlights ({} fading, {} in pieces), {} \
             sharing; records within {:.2e}, centres within {:.2e} r",
            tally.frames,
            tally.highlights,
            tally.faded,
            tally.pieces,
            tally.shared,
            tally.worst_record,
            tally.worst_centre
        );
        assert!(
            tally.highlights >= 60,
            "only {} highlights",
            tally.highlights
        );
        assert!(tally.faded >= 5, "only {} fading", tally.faded);
        assert!(tally.pieces >= 1, "no highlight in pieces");
    }
}

/// The user's edits (moved, turned, scaled, their own σ, tint and texture) and the
/// paper's sizing (Eq. (8), suppression of a projector inside an older one's) are
/// applied on the GPU as on the CPU, frame after frame from the GPU's own table.
#[test]
fn edits_and_the_papers_sizing_are_the_cpus_on_the_gpu() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("edits_and_the_papers_sizing_are_the_cpus_on_the_gpu")
    else {
        return;
    };
    let options = CurvatureOptions::default();
    let mesh = fixture("spot.obj");
    let radius = bounding_radius(&mesh);
    for sizing in [HighlightSizing::Region, HighlightSizing::Paper] {
        let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
        cpu.tuning.sizing = sizing;
        cpu.tuning.controls.rotate_rad = 0.2;
        let mut frames = Frames::new(ctx, &cpu);
        let mut tally = Tally::default();
        let mut edited = 0;
        for step in 0..10 {
            if step == 2 {
                let ids: Vec<u64> = cpu.highlights().iter().map(|h| h.id).collect();
                for (i, id) in ids.into_iter().enumerate() {
                    let c = cpu.controls_mut(id);
                    match i % 3 {
                        0 => {
                            c.translate = Vec2::new(0.01, -0.02) * radius;
                            c.scale = Vec2::new(1.3, 0.8);
                        }
                        1 => {
                            c.rotate_rad = 0.7;
                            c.sigma = Some(0.8);
                            c.texture_layer = Some(2);
                        }
                        _ => c.tint = Vec3::new(1.0, 0.5, 0.25),
                    }
                    edited += 1;
                }
            }
            let frame = turn(radius, step);
            let gpu = frames.run(ctx, &cpu, frame, true);
            cpu.update(frame.0, frame.1);
            compare(
                &gpu,
                &cpu,
                radius,
                &format!("{sizing:?} frame {step}"),
                &mut tally,
            );
        }
        eprintln!(
            "{sizing:?}: {} highlights, {edited} edited, records within {:.2e}",
            tally.highlights, tally.worst_record
        );
        assert!(edited >= 3, "only {edited} edited");
    }
}
