//! The `N = H` search on the GPU ([`CentreSearchPass`], `centre_search.wgsl`) against
//! the CPU search ([`HighlightSearch::find`], the reference) on the same frame: the same
//! centres within 1e-4 of the mesh's bounding radius, for directional and point lights,
//! rigid, non-uniformly scaled and sheared transforms, on procedural surfaces and the
//! scanned fixtures. (The highlights made from the GPU's centres are the CPU's:
//! `backends.rs`.)
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, HighlightCentre, LightEye, generate};
use npr_gpu::{FrameId, GpuContext};
use npr_specular::{HighlightSet, gpu::CentreSearchPass, gpu::SearchInput, gpu::SearchSolutions};

mod common;
use common::{bounding_radius, fixture, frames, meshes};

/// The GPU search of one frame: its accepted faces.
fn gpu_solutions(
    ctx: &GpuContext,
    pass: &CentreSearchPass,
    set: &HighlightSet,
    (light_eye, world_from_object): (LightEye, Mat4),
    frame: FrameId,
) -> SearchSolutions {
    let mut object = pass.create_object(&ctx.device, set.search()).unwrap();
    let input = SearchInput {
        frame,
        search: set.search(),
        light_eye,
        world_from_object,
    };
    let prepared = pass.prepare(&ctx.queue, &mut object, &input).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &object, &prepared).unwrap();
    ctx.queue.submit([encoder.finish()]);
    object.read(&ctx.device, &prepared).unwrap()
}

/// Largest distance from a centre of `a` to its nearest in `b` (object space), and
/// whether the two have as many centres.
fn farthest(a: &[HighlightCentre], b: &[HighlightCentre]) -> f32 {
    a.iter()
        .map(|c| {
            b.iter()
                .map(|d| d.position_object.distance(c.position_object))
                .fold(f32::INFINITY, f32::min)
        })
        .fold(0.0, f32::max)
}

#[test]
fn the_gpu_search_finds_the_cpu_centres() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("the_gpu_search_finds_the_cpu_centres")
    else {
        return;
    };
    let pass = CentreSearchPass::new(&ctx.device);
    let meshes = meshes();
    let mut frame = FrameId(1);
    let (mut total, mut worst_all, mut merged_pairs) = (0, 0.0f32, 0);
    let mut worst_gap = CentreGap::default();
    // Clusters solved and tested under directional lights (where the cluster rejection
    // applies under any transform).
    let (mut solved_clusters, mut tested_clusters) = (0, 0);
    for (name, mesh) in &meshes {
        let set = HighlightSet::new(mesh, &CurvatureOptions::default()).unwrap();
        let radius = bounding_radius(mesh);
        for (k, (light_eye, world)) in frames(radius).into_iter().enumerate() {
            let cpu = set.search().find(light_eye, world);
            let exhaustive = set.search().find_exhaustive(light_eye, world);
            let solved = gpu_solutions(ctx, &pass, &set, (light_eye, world), frame);
            frame = frame.next();
            assert!(solved.complete(), "{name} frame {k}: list overflowed");
            let gpu = set.search().centres_from_solutions(&solved.faces, world);
            // The GPU's own merge (`cs_merge`) keeps the very entries the CPU's merge of
            // the same list keeps, in its order, and its centres (`cs_centres`) are the
            // CPU's at those points.
            let merged = solved.centres.as_ref().expect("merged on the GPU");
            let key = |c: &HighlightCentre| (c.face, c.alpha, c.beta);
            assert_eq!(
                merged.iter().map(key).collect::<Vec<_>>(),
                gpu.iter().map(key).collect::<Vec<_>>(),
                "{name} frame {k}: the GPU's merge"
            );
            for (g, c) in merged.iter().zip(&gpu) {
                let gap = centre_gap(g, c, radius, &set);
                worst_gap = worst_gap.max(gap);
                assert!(
                    gap.le(&CENTRE_BOUNDS),
                    "{name} frame {k}: a GPU centre off the CPU's at its point: {gap:?}"
                );
            }
            merged_pairs += solved.faces.len() - merged.len();
            let worst = farthest(&cpu, &gpu).max(farthest(&gpu, &cpu)) / radius;
            assert!(
                gpu.len() == cpu.len() && worst <= 1e-4,
                "{name} frame {k}: {} GPU centres against {} CPU ({} exhaustive), worst {worst:.2e} of the radius",
                gpu.len(),
                cpu.len(),
                exhaustive.len()
            );
            total += cpu.len();
            worst_all = worst_all.max(worst);
            if matches!(light_eye, LightEye::Directions { .. }) {
                let count = set.search().triangles().len().div_ceil(64);
                eprintln!(
                    "{name} frame {k}: {} of {count} clusters solved",
                    solved.clusters_solved
                );
                solved_clusters += solved.clusters_solved;
                tested_clusters += count;
            }
        }
    }
    eprintln!(
        "{total} centres over every mesh and frame, the GPU's within {worst_all:.2e} of the radius"
    );
    assert!(
        total >= 40,
        "only {total} centres over every mesh and frame"
    );
    eprintln!("{merged_pairs} accepted faces merged away on the GPU; centres within {worst_gap:?}");
    assert!(
        merged_pairs > 0,
        "no frame had a centre found twice to merge"
    );
    // The same centres with most clusters skipped whole: under a directional light a
    // cluster's faces are solved only where its normal cone comes near H.
    eprintln!("{solved_clusters} of {tested_clusters} clusters solved under directional lights");
    assert!(
        tested_clusters > 0 && solved_clusters * 2 <= tested_clusters,
        "{solved_clusters} of {tested_clusters} clusters solved under directional lights"
    );
}

#[test]
fn a_search_of_another_mesh_is_refused() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_search_of_another_mesh_is_refused") else {
        return;
    };
    let pass = CentreSearchPass::new(&ctx.device);
    let options = CurvatureOptions::default();
    let torus = HighlightSet::new(&generate::torus(1.0, 0.35, 32, 16), &options).unwrap();
    let sphere = HighlightSet::new(&generate::icosphere(3, 1.0), &options).unwrap();
    let mut object = pass.create_object(&ctx.device, torus.search()).unwrap();
    let input = SearchInput {
        frame: FrameId(1),
        search: sphere.search(),
        light_eye: LightEye::Directions {
            to_light: Vec3::Y,
            to_eye: Vec3::Z,
        },
        world_from_object: Mat4::IDENTITY,
    };
    let e = pass.prepare(&ctx.queue, &mut object, &input);
    assert!(
        matches!(e, Err(npr_specular::SpecularError::Mismatch(_))),
        "{e:?}"
    );
    // A light opposite the eye has no half vector: nothing is found, nothing fails.
    let input = SearchInput {
        search: torus.search(),
        light_eye: LightEye::Directions {
            to_light: Vec3::Z,
            to_eye: -Vec3::Z,
        },
        ..input
    };
    let prepared = pass.prepare(&ctx.queue, &mut object, &input).unwrap();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pass.record(&mut encoder, &object, &prepared).unwrap();
    ctx.queue.submit([encoder.finish()]);
    let solved = object.read(&ctx.device, &prepared).unwrap();
    assert_eq!(solved.accepted, 0);
}

/// The cluster rejection never drops a centre: on a thin tube (the paper's knot, whose
/// clusters are wide), a jittered torus and the bunny, 24 random directional lights and
/// 12 random point lights near the mesh each give the GPU the CPU's centres.
#[test]
fn skipped_clusters_never_hold_a_centre() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("skipped_clusters_never_hold_a_centre")
    else {
        return;
    };
    let pass = CentreSearchPass::new(&ctx.device);
    let mut rng = npr_geometry::rng::XorShift64::new(0x5eed_c105);
    let mut unit = || {
        let mut v = || rng.next_f64() as f32 * 2.0 - 1.0;
        Vec3::new(v(), v(), v()).normalize_or(Vec3::Y)
    };
    let mut frame = FrameId(1);
    let (mut centres, mut skipped) = (0, 0);
    for mesh in [
        generate::paper_knot(),
        generate::torus_jittered(1.0, 0.35, 48, 24, 0.3, 11),
        fixture("stanford-bunny.obj"),
    ] {
        let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let radius = bounding_radius(&mesh);
        let mut object = pass.create_object(&ctx.device, set.search()).unwrap();
        for k in 0..36 {
            let light_eye = if k < 24 {
                LightEye::Directions {
                    to_light: unit(),
                    to_eye: unit(),
                }
            } else {
                LightEye::Positions {
                    light: unit() * radius * 1.6,
                    eye: unit() * radius * 2.5,
                }
            };
            let world = Mat4::IDENTITY;
            let input = SearchInput {
                frame,
                search: set.search(),
                light_eye,
                world_from_object: world,
            };
            frame = frame.next();
            let solved = pass
                .search_now(&ctx.device, &ctx.queue, &mut object, &input)
                .unwrap();
            let cpu = set.search().find_exhaustive(light_eye, world);
            let gpu = set.search().centres_from_solutions(&solved.faces, world);
            let worst = farthest(&cpu, &gpu).max(farthest(&gpu, &cpu)) / radius;
            assert!(
                gpu.len() == cpu.len() && worst <= 1e-4,
                "light {k}: {} GPU centres against {} CPU, worst {worst:.2e}",
                gpu.len(),
                cpu.len()
            );
            centres += cpu.len();
            skipped += object.cluster_count() - solved.clusters_solved;
        }
    }
    eprintln!("{centres} centres, {skipped} clusters skipped over 108 lights");
    assert!(
        centres >= 100 && skipped > 0,
        "{centres} centres, {skipped} skipped"
    );
}

/// The GPU's merge where it has most to do: half vectors along vertex normals of a sphere
/// (every face around the vertex accepts the one centre), and egg-crate fields of bumps
/// with fewer and more centres than the merge keeps ([`npr_specular::gpu::MAX_MERGED`]), where
/// the list comes back unmerged for the CPU.
#[test]
fn the_gpu_merges_what_the_cpu_merges_and_says_when_it_cannot() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "the_gpu_merges_what_the_cpu_merges_and_says_when_it_cannot",
    ) else {
        return;
    };
    let pass = CentreSearchPass::new(&ctx.device);
    let options = CurvatureOptions::default();
    let sphere = generate::icosphere(3, 1.0);
    let set = HighlightSet::new(&sphere, &options).unwrap();
    let mut object = pass.create_object(&ctx.device, set.search()).unwrap();
    let key = |c: &HighlightCentre| (c.face, c.alpha, c.beta);
    let (mut merged_away, mut frame) = (0, FrameId(1));
    for v in (0..sphere.vertex_count()).step_by(37) {
        let n = sphere.normals[v].normalize();
        let light_eye = LightEye::Directions {
            to_light: n,
            to_eye: n,
        };
        let input = SearchInput {
            frame,
            search: set.search(),
            light_eye,
            world_from_object: Mat4::IDENTITY,
        };
        frame = frame.next();
        let solved = pass
            .search_now(&ctx.device, &ctx.queue, &mut object, &input)
            .unwrap();
        let cpu = set
            .search()
            .centres_from_solutions(&solved.faces, Mat4::IDENTITY);
        let merged = solved.centres.expect("a few centres merge on the GPU");
        let merged: Vec<_> = merged.iter().map(key).collect();
        assert_eq!(
            merged,
            cpu.iter().map(key).collect::<Vec<_>>(),
            "vertex {v}"
        );
        merged_away += solved.faces.len() - merged.len();
    }
    eprintln!("{merged_away} faces merged away at the sphere's vertices");
    assert!(merged_away >= 10, "{merged_away} faces merged away");

    // An egg-crate height field seen from above: a centre at every crest, trough and
    // saddle, eight a period². At no abstraction, so that the set's normals keep them.
    // Five periods a side: 200 centres, merged on the GPU; thirteen: 1,352, more than
    // the merge keeps.
    let overhead = LightEye::Directions {
        to_light: Vec3::Z,
        to_eye: Vec3::Z,
    };
    let mut branches = [false; 2];
    for periods in [5, 13] {
        let crate_mesh = common::egg_crate(periods, 8);
        let set = HighlightSet::with_abstraction(&crate_mesh, &options, 0.0).unwrap();
        let mut object = pass
            .create_object_with_capacity(&ctx.device, set.search(), 1 << 13)
            .unwrap();
        let input = SearchInput {
            frame,
            search: set.search(),
            light_eye: overhead,
            world_from_object: Mat4::IDENTITY,
        };
        frame = frame.next();
        let solved = pass
            .search_now(&ctx.device, &ctx.queue, &mut object, &input)
            .unwrap();
        assert!(solved.complete());
        let cpu = set
            .search()
            .centres_from_solutions(&solved.faces, Mat4::IDENTITY);
        eprintln!(
            "egg crate of {periods}²: {} faces, {} centres",
            solved.faces.len(),
            cpu.len()
        );
        assert!(cpu.len() >= 6 * periods * periods, "{} centres", cpu.len());
        branches[usize::from(cpu.len() > npr_specular::gpu::MAX_MERGED)] = true;
        if cpu.len() <= npr_specular::gpu::MAX_MERGED {
            let merged = solved.centres.expect("merged on the GPU");
            let merged: Vec<_> = merged.iter().map(key).collect();
            assert_eq!(merged, cpu.iter().map(key).collect::<Vec<_>>());
        } else {
            assert_eq!(solved.centres, None, "more centres than the merge keeps");
        }
    }
    assert_eq!(
        branches, [true; 2],
        "one field under the merge's limit, one over"
    );
}

/// How far a GPU centre is from the CPU's at the same point: position (of the bounding
/// radius), normal and principal direction (degrees; the direction only where the
/// principal curvatures differ by 1 % of the mesh's largest |κ|), curvatures (of the
/// mesh's largest |κ|).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct CentreGap {
    position: f32,
    normal_deg: f32,
    direction_deg: f32,
    kappa: f32,
}

impl CentreGap {
    fn max(self, o: Self) -> Self {
        Self {
            position: self.position.max(o.position),
            normal_deg: self.normal_deg.max(o.normal_deg),
            direction_deg: self.direction_deg.max(o.direction_deg),
            kappa: self.kappa.max(o.kappa),
        }
    }

    /// Every part within `bound`'s.
    fn le(&self, bound: &Self) -> bool {
        self.position <= bound.position
            && self.normal_deg <= bound.normal_deg
            && self.direction_deg <= bound.direction_deg
            && self.kappa <= bound.kappa
    }
}

/// The bounds the issue sets the GPU's geometry: 1e-4 of the radius, 0.5°, 1e-3 of the
/// largest |κ|.
const CENTRE_BOUNDS: CentreGap = CentreGap {
    position: 1e-4,
    normal_deg: 0.5,
    direction_deg: 0.5,
    kappa: 1e-3,
};

fn centre_gap(
    g: &HighlightCentre,
    c: &HighlightCentre,
    radius: f32,
    set: &HighlightSet,
) -> CentreGap {
    let deg = |a: Vec3, b: Vec3| a.dot(b).clamp(-1.0, 1.0).acos().to_degrees();
    let kmax = set
        .search()
        .field_floats()
        .iter()
        .filter(|f| f[11] == 1.0)
        .map(|f| f[3].abs().max(f[7].abs()))
        .fold(1e-12f32, f32::max);
    let distinct = (c.kappa_max - c.kappa_min).abs() > 1e-2 * kmax;
    let position = g
        .position_world
        .distance(c.position_world)
        .max(g.position_object.distance(c.position_object));
    CentreGap {
        position: position / radius,
        normal_deg: deg(g.normal_world, c.normal_world).max(deg(g.normal_object, c.normal_object)),
        direction_deg: if distinct {
            deg(g.dir_kappa_max, c.dir_kappa_max)
        } else {
            0.0
        },
        kappa: (g.kappa_max - c.kappa_max)
            .abs()
            .max((g.kappa_min - c.kappa_min).abs())
            / kmax,
    }
}
