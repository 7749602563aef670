//! A frame's regions seeded on the GPU (`RegionPass::prepare_tracked`, `tracking.wgsl`):
//! the search's centres matched with the last update's highlights and grown in the
//! search's submission, against the CPU's own update (its search, peaks, matching and
//! growth) on the same frames: the GPU seeds exactly the update's seeds (the GPU's peaks
//! adopted), in its order, on every frame, and the highlights are the CPU's, ids, fades
//! and footprints, with one wait a frame.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, HighlightCentre, LightEye};
use npr_gpu::{FrameId, GpuContext};
use npr_specular::{
    CentreSearchPass, HighlightSet, RegionPass, SearchInput, TrackStatus, TrackedInput,
    TrackedRegions,
};

mod common;
use common::{bounding_radius, fixture, same_highlights};

/// One frame on the GPU path: the search and the tracked growth recorded in one encoder,
/// one submission, both read back; then the update on them.
struct GpuFrames {
    search_pass: CentreSearchPass,
    region_pass: RegionPass,
    search: npr_specular::SearchObject,
    regions: npr_specular::RegionObject,
    frame: FrameId,
    /// Whether the search looks for the peaks.
    peaks: bool,
}

impl GpuFrames {
    fn new(ctx: &GpuContext, set: &HighlightSet) -> Self {
        Self::with(ctx, set, None)
    }

    /// With a list of `capacity` accepted faces and no peaks, where given.
    fn with(ctx: &GpuContext, set: &HighlightSet, capacity: Option<usize>) -> Self {
        let search_pass = CentreSearchPass::new(&ctx.device);
        let region_pass = RegionPass::new(&ctx.device);
        let search = match capacity {
            None => search_pass.create_object_with_peaks(&ctx.device, set),
            Some(c) => search_pass.create_object_with_capacity(&ctx.device, set.search(), c),
        }
        .unwrap();
        let regions = region_pass.create_object(&ctx.device, set).unwrap();
        Self {
            search_pass,
            region_pass,
            search,
            regions,
            frame: FrameId::default(),
            peaks: capacity.is_none(),
        }
    }

    /// The frame's search and tracked regions, read back after one submission.
    fn run(
        &mut self,
        ctx: &GpuContext,
        set: &HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> (npr_specular::SearchSolutions, TrackedRegions) {
        self.frame = self.frame.next();
        let input = SearchInput {
            frame: self.frame,
            search: set.search(),
            light_eye,
            world_from_object,
        };
        let searched = self
            .search_pass
            .prepare_with_peaks(
                &ctx.queue,
                &mut self.search,
                &input,
                self.peaks.then_some(set.global.sigma),
            )
            .unwrap();
        let tracked = TrackedInput {
            frame: self.frame,
            set,
            light_eye,
            world_from_object,
            search: (&self.search, &searched),
        };
        let grown = self
            .region_pass
            .prepare_tracked(&ctx.queue, &mut self.regions, &tracked)
            .unwrap();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.search_pass
            .record(&mut encoder, &self.search, &searched)
            .unwrap();
        self.region_pass
            .record(&mut encoder, &self.regions, &grown)
            .unwrap();
        ctx.queue.submit([encoder.finish()]);
        let pending = self
            .regions
            .map_tracked(&ctx.device, &ctx.queue, &grown)
            .unwrap();
        let solved = self.search.read(&ctx.device, &searched).unwrap();
        (solved, pending.wait(&ctx.device).unwrap())
    }
}

/// A light turning over the object while it turns too, eye fixed.
fn turn(radius: f32, step: usize) -> (LightEye, Mat4) {
    let a = step as f32 * 0.12;
    let light_eye = LightEye::Positions {
        light: Vec3::new(
            2.0 * radius * a.cos(),
            1.5 * radius,
            2.0 * radius * a.sin() + radius,
        ),
        eye: Vec3::new(0.0, 0.2 * radius, 3.0 * radius),
    };
    (light_eye, Mat4::from_rotation_y(0.1 * a))
}

#[test]
fn regions_seeded_on_the_gpu_are_the_cpu_updates_regions() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("regions_seeded_on_the_gpu_are_the_cpu_updates_regions")
    else {
        return;
    };
    let options = CurvatureOptions::default();
    let meshes = [
        ("spot", fixture("spot.obj")),
        ("bunny", fixture("stanford-bunny.obj")),
        ("torus", npr_geometry::generate::torus(1.0, 0.35, 64, 32)),
    ];
    let (mut seeded, mut with_peaks, mut shown) = (0, 0, 0);
    let (mut worst_footprint, mut worst_whole) = (0.0f32, 0.0f32);
    for (name, mesh) in &meshes {
        let mut cpu = HighlightSet::new(mesh, &options).unwrap();
        let mut gpu = HighlightSet::new(mesh, &options).unwrap();
        let radius = bounding_radius(mesh);
        let mut frames = GpuFrames::new(ctx, &gpu);
        for step in 0..14 {
            let (light_eye, world) = turn(radius, step);
            let (solved, tracked) = frames.run(ctx, &gpu, (light_eye, world));
            assert!(
                solved.complete(),
                "{name} frame {step}: the list overflowed"
            );
            let want = cpu.update(light_eye, world).to_vec();
            let mut take = |_: &HighlightSet, seeds: &[(npr_geometry::HighlightCentre, f32)]| {
                tracked.for_seeds(seeds)
            };
            let got = gpu
                .update_from_search(light_eye, world, &solved, Some(&mut take))
                .to_vec();
            let stats = gpu.stats();
            // The GPU's seeds, peaks included, are the update's on every frame.
            assert!(
                stats.regions_on_gpu || stats.centres + stats.peaks == 0,
                "{name} frame {step}: the GPU's seeds {:?} ({:?}) are not the update's",
                tracked.seeds,
                tracked.status
            );
            assert!(
                solved.peaks.is_some(),
                "{name} frame {step}: no peaks looked for"
            );
            seeded += 1;
            with_peaks += usize::from(stats.peaks > 0);
            // The same faces won: whole regions' footprints within rounding. The pieces
            // of a long bent region are cut along it face by face on the GPU, a whole
            // patch at a time by the set's grower (`region::split`): 1.5e-3 of the
            // radius on the bunny.
            let at = format!("{name} frame {step}");
            let e = same_highlights(&got, &want, radius, &at);
            worst_footprint = worst_footprint.max(e);
            assert!(
                e <= 3e-3,
                "{at}: footprints differ by {e:.2e} of the radius"
            );
            for (g, w) in got.iter().zip(&want).filter(|(g, _)| g.piece == 0) {
                let d = (g.projector.half_extent - w.projector.half_extent).abs();
                worst_whole = worst_whole.max(d.max_element() / radius);
            }
            assert!(
                worst_whole <= 2e-5,
                "{at}: whole regions' footprints differ by {worst_whole:.2e} of the radius"
            );
            shown += got.len();
        }
    }
    eprintln!(
        "{seeded} frames grown from the GPU's seeds, {with_peaks} of them with peaks; {shown} highlights, footprints within {worst_footprint:.2e} of the radius, \
         whole regions' within {worst_whole:.2e}"
    );
    assert!(shown >= 30, "only {shown} highlights");
    assert!(with_peaks >= 10, "only {with_peaks} frames with peaks");
}

/// Peaks of bright parts of any size: a dense knot under the bench's light, whose parts
/// `N·H ≥ σ` hold over 8,192 vertices in a frame (the most a single invocation once
/// filled, beyond which the frame's peaks were left to the CPU). The parts are joined
/// over all vertices at once (`cs_join_bright`): the GPU's peaks are the CPU update's,
/// and every frame is seeded on the GPU.
#[test]
fn peaks_of_large_bright_parts_are_found_on_the_gpu() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("peaks_of_large_bright_parts_are_found_on_the_gpu")
    else {
        return;
    };
    let knot = npr_geometry::generate::TorusKnot::trefoil(0.15, 1800, 130);
    let mesh = npr_geometry::generate::torus_knot(&knot);
    let options = CurvatureOptions::default();
    let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
    let mut gpu = HighlightSet::new(&mesh, &options).unwrap();
    // Wide highlights: larger parts.
    cpu.global.sigma = 0.8;
    gpu.global.sigma = 0.8;
    let radius = bounding_radius(&mesh);
    let mut frames = GpuFrames::new(ctx, &gpu);
    let (mut peaks, mut most_bright) = (0, 0);
    for step in 0..4 {
        let world = Mat4::from_rotation_y((step as f32 * 3.0).to_radians());
        let light_eye = LightEye::Positions {
            light: Vec3::new(0.4, 0.7, 1.0).normalize() * 50.0 * radius,
            eye: Vec3::new(0.0, 0.0, 3.0 * radius),
        };
        // The bright vertices, as the peaks count them (object space: a rotation).
        let topology = gpu.topology();
        let object_from_world = world.inverse();
        let bright = topology
            .positions
            .iter()
            .zip(gpu.search().normals())
            .filter(|(p, n)| {
                let LightEye::Positions { light, eye } = light_eye else {
                    unreachable!()
                };
                let l = (object_from_world.transform_point3(light) - **p).normalize();
                let e = (object_from_world.transform_point3(eye) - **p).normalize();
                n.dot((l + e).normalize()) >= gpu.global.sigma
            })
            .count();
        most_bright = most_bright.max(bright);
        let (solved, tracked) = frames.run(ctx, &gpu, (light_eye, world));
        let want = cpu.update(light_eye, world).to_vec();
        let mut take = |_: &HighlightSet, seeds: &[(npr_geometry::HighlightCentre, f32)]| {
            tracked.for_seeds(seeds)
        };
        let got = gpu
            .update_from_search(light_eye, world, &solved, Some(&mut take))
            .to_vec();
        let at = format!("frame {step} ({bright} bright vertices)");
        let found = solved.peaks.as_ref().map(Vec::len);
        assert_eq!(found, Some(cpu.stats().peaks), "{at}: peaks");
        assert!(gpu.stats().regions_on_gpu, "{at}: not seeded on the GPU");
        same_highlights(&got, &want, radius, &at);
        peaks += cpu.stats().peaks;
    }
    assert!(most_bright > 8192, "only {most_bright} bright vertices");
    assert!(peaks >= 1, "no peak in any frame");
}

/// Highlights the user sized apart (their own σ, as the panel edits them) grow their
/// regions among the others' at their own σ: a face one of them reached and did not take
/// is closed to the others on the GPU as on the CPU. `SetupOnGpu` seeds and grows them
/// in its one submission and gives the CPU update's highlights.
#[test]
fn highlights_of_their_own_sigma_are_grown_on_the_gpu_as_on_the_cpu() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "highlights_of_their_own_sigma_are_grown_on_the_gpu_as_on_the_cpu",
    ) else {
        return;
    };
    let options = CurvatureOptions::default();
    let (mut edited, mut frames_seen) = (0, 0);
    for mesh in [fixture("spot.obj"), fixture("stanford-bunny.obj")] {
        let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
        let mut gpu = HighlightSet::new(&mesh, &options).unwrap();
        let radius = bounding_radius(&mesh);
        let mut setup = npr_specular::SetupOnGpu::new(&ctx.device, &gpu).unwrap();
        for step in 0..8 {
            let frame = turn(radius, step);
            // From the second frame on, every other highlight tighter or wider.
            if step > 0 {
                let ids: Vec<u64> = cpu.highlights().iter().map(|h| h.id).collect();
                for (i, id) in ids.into_iter().enumerate() {
                    let sigma = Some(if i % 2 == 0 { 0.97 } else { 0.8 });
                    cpu.controls_mut(id).sigma = sigma;
                    gpu.controls_mut(id).sigma = sigma;
                    edited += 1;
                }
            }
            let want = cpu.update(frame.0, frame.1).to_vec();
            let waits = setup
                .update((&ctx.device, &ctx.queue), &mut gpu, frame)
                .unwrap();
            assert!(waits.is_some(), "frame {step}: not searched on the GPU");
            assert!(
                gpu.stats().regions_on_gpu,
                "frame {step}: the regions were grown on the CPU"
            );
            let at = format!("frame {step}");
            same_highlights(gpu.highlights(), &want, radius, &at);
            for (g, w) in gpu
                .highlights()
                .iter()
                .zip(&want)
                .filter(|(g, _)| g.piece == 0)
            {
                let d = (g.projector.half_extent - w.projector.half_extent).abs();
                assert!(
                    d.max_element() <= 2e-5 * radius,
                    "{at}: highlight {} {:?} against the CPU's {:?}",
                    g.id,
                    g.projector.half_extent,
                    w.projector.half_extent
                );
            }
            frames_seen += 1;
        }
    }
    assert!(edited >= 20, "only {edited} highlights edited");
    assert!(frames_seen == 16);
}

/// More centres than a tracked frame has room for: none grown, and the status says so.
#[test]
fn a_frame_of_too_many_centres_is_not_seeded() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_frame_of_too_many_centres_is_not_seeded")
    else {
        return;
    };
    // A field of bumps seen from above: each crest, trough and saddle one centre, 200 of
    // them (see `gpu_search.rs`).
    let mesh = common::egg_crate(5, 8);
    let set = HighlightSet::with_abstraction(&mesh, &CurvatureOptions::default(), 0.0).unwrap();
    let mut frames = GpuFrames::new(ctx, &set);
    let overhead = LightEye::Directions {
        to_light: Vec3::Z,
        to_eye: Vec3::Z,
    };
    let (solved, tracked) = frames.run(ctx, &set, (overhead, Mat4::IDENTITY));
    let centres = solved.centres.expect("merged").len();
    assert!(centres > npr_specular::TRACKED_SEEDS, "{centres} centres");
    assert_eq!(tracked.status, TrackStatus::TooMany);
    assert!(tracked.seeds.is_empty() && tracked.regions.is_empty());
}

/// `SetupOnGpu` with the paper's sizing (Eq. (8): no regions, no peaks) gives the CPU
/// update's highlights, waiting once, frame after frame.
#[test]
fn the_gpu_setup_with_the_papers_sizing_is_the_cpu_update() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("the_gpu_setup_with_the_papers_sizing_is_the_cpu_update")
    else {
        return;
    };
    let mesh = fixture("spot.obj");
    let options = CurvatureOptions::default();
    let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
    let mut gpu = HighlightSet::new(&mesh, &options).unwrap();
    cpu.sizing = npr_specular::HighlightSizing::Paper;
    gpu.sizing = npr_specular::HighlightSizing::Paper;
    let radius = bounding_radius(&mesh);
    let mut setup = npr_specular::SetupOnGpu::new(&ctx.device, &gpu).unwrap();
    let mut shown = 0;
    for step in 0..6 {
        let frame = turn(radius, step);
        let want = cpu.update(frame.0, frame.1).to_vec();
        let waits = setup
            .update((&ctx.device, &ctx.queue), &mut gpu, frame)
            .unwrap();
        assert_eq!(waits, Some(1), "frame {step}");
        let e = same_highlights(gpu.highlights(), &want, radius, &format!("frame {step}"));
        assert!(
            e <= 1e-3,
            "frame {step}: footprints differ by {e:.2e} of the radius"
        );
        shown += want.len();
    }
    assert!(shown >= 6, "only {shown} highlights");
}

/// A frame the GPU cannot seed (more centres than its room) is grown in a second
/// submission by `SetupOnGpu`, and still gives the CPU update's highlights.
#[test]
fn a_frame_the_gpu_cannot_seed_is_grown_in_a_second_submission() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "a_frame_the_gpu_cannot_seed_is_grown_in_a_second_submission",
    ) else {
        return;
    };
    // 200 centres, more than a first frame's room (8).
    let mesh = common::egg_crate(5, 8);
    let options = CurvatureOptions::default();
    let mut cpu = HighlightSet::with_abstraction(&mesh, &options, 0.0).unwrap();
    let mut gpu = HighlightSet::with_abstraction(&mesh, &options, 0.0).unwrap();
    let radius = bounding_radius(&mesh);
    let mut setup = npr_specular::SetupOnGpu::new(&ctx.device, &gpu).unwrap();
    let frame = (
        LightEye::Directions {
            to_light: Vec3::Z,
            to_eye: Vec3::Z,
        },
        Mat4::IDENTITY,
    );
    let want = cpu.update(frame.0, frame.1).to_vec();
    let waits = setup
        .update((&ctx.device, &ctx.queue), &mut gpu, frame)
        .unwrap();
    assert_eq!(waits, Some(2), "grown again in a submission of its own");
    assert!(gpu.stats().regions_on_gpu, "by the GPU's region pass");
    assert!(
        want.len() > npr_specular::TRACKED_SEEDS,
        "{} highlights",
        want.len()
    );
    let e = same_highlights(gpu.highlights(), &want, radius, "egg crate");
    assert!(e <= 1e-3, "footprints differ by {e:.2e} of the radius");
}

/// Frames the GPU leaves to the CPU say so: a search without its peaks on frames with
/// peaks hands the update seeds it cannot take (its regions grown otherwise, the CPU
/// update's highlights all the same), and an overflowed list is not merged, so nothing
/// is seeded.
#[test]
fn frames_the_gpu_leaves_to_the_cpu_say_so() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("frames_the_gpu_leaves_to_the_cpu_say_so")
    else {
        return;
    };
    let mesh = fixture("spot.obj");
    let options = CurvatureOptions::default();
    let radius = bounding_radius(&mesh);
    let mut cpu = HighlightSet::new(&mesh, &options).unwrap();
    let mut gpu = HighlightSet::new(&mesh, &options).unwrap();
    // No peaks looked for (a list of the default length).
    let mut frames = GpuFrames::with(ctx, &gpu, Some(npr_specular::search_pass::DEFAULT_CAPACITY));
    let mut refused = 0;
    for step in 0..8 {
        let frame = turn(radius, step);
        let (solved, tracked) = frames.run(ctx, &gpu, frame);
        assert_eq!(solved.peaks, None, "frame {step}: no peaks looked for");
        let want = cpu.update(frame.0, frame.1).to_vec();
        let mut take =
            |_: &HighlightSet, seeds: &[(HighlightCentre, f32)]| tracked.for_seeds(seeds);
        gpu.update_from_search(frame.0, frame.1, &solved, Some(&mut take));
        let stats = gpu.stats();
        // The GPU's seeds are the update's exactly where the update has no peak.
        assert_eq!(stats.regions_on_gpu, stats.peaks == 0, "frame {step}");
        refused += usize::from(stats.peaks > 0);
        let e = same_highlights(gpu.highlights(), &want, radius, &format!("frame {step}"));
        assert!(
            e <= 1e-3,
            "frame {step}: footprints differ by {e:.2e} of the radius"
        );
    }
    assert!(refused >= 2, "only {refused} frames with peaks");
    // A list of one face overflows: not merged, nothing seeded.
    let set = HighlightSet::new(&mesh, &options).unwrap();
    let mut frames = GpuFrames::with(ctx, &set, Some(1));
    let (solved, tracked) = frames.run(ctx, &set, turn(radius, 0));
    assert!(
        !solved.complete() && solved.centres.is_none(),
        "{} accepted",
        solved.accepted
    );
    assert_eq!(tracked.status, TrackStatus::Unmerged);
    assert!(tracked.seeds.is_empty());
}
