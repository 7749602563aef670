//! The regions `N·H ≥ σ` grown and fitted on the GPU ([`RegionPass`], `regions.wgsl`)
//! against the CPU growth (the reference, [`RegionGrower::grow_all`], what
//! [`HighlightSet::update`] sizes highlights with) on the same frame and seeds: the same
//! outcome per seed, the same faces won on at least 99.5 % of the faces, the same
//! moment ellipse (within 1e-3 of the bounding radius, areas within 0.5 %), overlap
//! scale (within 2e-3) and pieces of long bent regions, over
//! directional and point lights, rigid, non-uniformly scaled and sheared transforms,
//! procedural surfaces and the scanned and CAD fixtures, with seeds that share a region.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat2, Vec2};
use npr_geometry::{CurvatureOptions, HighlightCentre, Topology};
use npr_gpu::FrameId;
use npr_specular::cpu::region::{Footprint, Region, RegionFrame, RegionGrower, RegionPatches};
use npr_specular::{HighlightSet, ProjectorControls, gpu::RegionInput, gpu::RegionPass};

mod common;
use common::{bounding_radius, frames, meshes};

/// The face `steps` faces away from `face` (breadth first), or the farthest reached.
fn face_away(topology: &Topology, face: u32, steps: usize) -> u32 {
    let mut seen = std::collections::HashSet::from([face]);
    let mut level = vec![face];
    for _ in 0..steps {
        let next: Vec<u32> = level
            .iter()
            .flat_map(|&f| topology.face_neighbours(f as usize).iter().copied())
            .filter(|g| seen.insert(*g))
            .collect();
        if next.is_empty() {
            break;
        }
        level = next;
    }
    level[0]
}

/// The ellipse's second-moment matrix `R diag(h²) Rᵀ` (the same for either choice of
/// axes) and its centre.
fn ellipse(fp: &Footprint) -> (Mat2, Vec2) {
    let r = Mat2::from_angle(fp.rotate_rad);
    let d = Mat2::from_diagonal(fp.half_extent * fp.half_extent);
    (r * d * r.transpose(), fp.offset)
}

/// How far the overlap scale may differ: both bin the same faces over 128 radii, the
/// CPU in `f64`, the GPU in `f32` and fixed point.
const SCALE_TOLERANCE: f32 = 2e-3;

/// How far a piece may lie from the CPU's, as a fraction of the bounding radius. The CPU
/// cuts between faces sorted along the axis; the GPU finds each cut's bin of 1,024 along
/// it from their areas, then orders that bin's faces one by one, so the pieces hold the
/// same faces and differ by rounding alone.
const PIECE_TOLERANCE: f32 = 1e-4;

/// The GPU's pieces of seed `s` against the CPU's: the same count, each piece's ellipse
/// (`R diag(h²) Rᵀ`, relative to r²) and centre (relative to r) within
/// [`PIECE_TOLERANCE`], areas within 0.5 % and scales within [`SCALE_TOLERANCE`]; the
/// worst distance,
/// or `None` when the CPU did not split the region.
fn compare_pieces(
    at: &str,
    radius: f32,
    grower: &RegionGrower,
    s: usize,
    g: &npr_specular::gpu::GpuRegion,
) -> Option<f32> {
    let cpu = grower.pieces(s);
    assert_eq!(cpu.len(), g.pieces().len(), "{at}: pieces");
    if cpu.is_empty() {
        return None;
    }
    let mut worst = 0f32;
    for (p, (a, b)) in cpu.iter().zip(g.pieces()).enumerate() {
        let ((ma, ca), (mb, cb)) = (ellipse(a), ellipse(b));
        let shape = (ma - mb)
            .to_cols_array()
            .iter()
            .fold(0f32, |m, d| m.max(d.abs()))
            / (radius * radius);
        let centre = ca.distance(cb) / radius;
        worst = worst.max(shape).max(centre);
        assert!(
            shape <= PIECE_TOLERANCE && centre <= PIECE_TOLERANCE,
            "{at} piece {p}: {b:?} against the CPU's {a:?}"
        );
        assert!(
            (a.region_area - b.region_area).abs() <= 5e-3 * a.region_area,
            "{at} piece {p}: area {} against {}",
            b.region_area,
            a.region_area
        );
        let (cs, gs) = (grower.overlap_scale(s, Some(p)), g.piece_scales[p]);
        assert!(
            (cs - gs).abs() <= SCALE_TOLERANCE,
            "{at} piece {p}: scale {gs} against {cs}"
        );
    }
    Some(worst)
}

#[derive(Default)]
struct Tally {
    seeds: usize,
    fitted: usize,
    faces_cpu: usize,
    faces_differ: usize,
    shared: usize,
    worst_scale: f32,
    split: usize,
    worst_piece: f32,
}

#[test]
fn the_gpu_regions_are_the_cpu_regions() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("the_gpu_regions_are_the_cpu_regions") else {
        return;
    };
    let pass = RegionPass::new(&ctx.device);
    let sigma = ProjectorControls::default().sigma;
    let mut frame = FrameId(1);
    let mut all = Tally::default();
    for (name, mesh) in meshes() {
        let radius = bounding_radius(&mesh);
        let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let topology = set.topology();
        let normals = set.search().normals();
        // Face by face, as the GPU grows: the set's grower takes whole patches where it can,
        // with the same faces and ellipse (`region::tests`), but it cuts bent regions and
        // bins their radii a patch at a time.
        let mut grower = RegionGrower::default();
        let mut object = pass.create_object(&ctx.device, &set).unwrap();
        let mut tally = Tally::default();
        for (k, (light_eye, world)) in frames(radius).into_iter().enumerate() {
            let centres = set.search().find(light_eye, world);
            let mut seeds: Vec<(HighlightCentre, f32)> =
                centres.iter().map(|c| (*c, sigma)).collect();
            // A second seed a few faces from the first, in its region: the two share it.
            if let Some(&(first, _)) = seeds.first() {
                let near = HighlightCentre {
                    face: face_away(topology, first.face, 3),
                    ..first
                };
                seeds.push((near, sigma));
            }
            let region_frame = RegionFrame {
                topology,
                normals,
                world_from_object: world,
                light_eye,
            };
            let cpu = grower.grow_all(&region_frame, &seeds);
            let input = RegionInput {
                frame,
                set: &set,
                seeds: &seeds,
                light_eye,
                world_from_object: world,
            };
            frame = frame.next();
            let gpu = pass
                .grow_now(&ctx.device, &ctx.queue, &mut object, &input)
                .unwrap();
            assert_eq!(gpu.len(), seeds.len(), "{name} frame {k}");
            for (s, (c, g)) in cpu.iter().zip(&gpu).enumerate() {
                let at = format!("{name} frame {k} seed {s}");
                assert!(!g.overflowed, "{at}: the growth overflowed");
                tally.seeds += 1;
                match (c, &g.region) {
                    (Region::Fit(a, fa), Region::Fit(b, fb)) => {
                        tally.fitted += 1;
                        tally.faces_cpu += fa;
                        tally.faces_differ += fa.abs_diff(*fb);
                        if s + 1 == seeds.len() && *fa > 0 {
                            tally.shared += 1;
                        }
                        if fa != fb {
                            // The faces won differ (a tie the two break apart): the
                            // count below bounds how often.
                            continue;
                        }
                        let ((ma, ca), (mb, cb)) = (ellipse(a), ellipse(b));
                        let scale = radius * radius;
                        let worst = (ma - mb)
                            .to_cols_array()
                            .iter()
                            .fold(0f32, |m, d| m.max(d.abs()));
                        assert!(
                            worst <= 2e-3 * scale,
                            "{at}: ellipse {a:?} against the CPU's {b:?}"
                        );
                        assert!(
                            ca.distance(cb) <= 1e-3 * radius,
                            "{at}: centre {ca} against {cb}"
                        );
                        let area = (a.region_area - b.region_area).abs();
                        assert!(
                            area <= 5e-3 * a.region_area.abs() + 1e-7 * scale,
                            "{at}: area {} against {}",
                            b.region_area,
                            a.region_area
                        );
                        assert!(
                            (a.normal_cone_cos - b.normal_cone_cos).abs() <= 1e-3,
                            "{at}: cone {} against {}",
                            b.normal_cone_cos,
                            a.normal_cone_cos
                        );
                        let piece = compare_pieces(&at, radius, &grower, s, g);
                        if let Some(worst) = piece {
                            tally.split += 1;
                            tally.worst_piece = tally.worst_piece.max(worst);
                        }
                        let (cs, gs) = (grower.overlap_scale(s, None), g.overlap_scale);
                        tally.worst_scale = tally.worst_scale.max((cs - gs).abs());
                        assert!(
                            (cs - gs).abs() <= SCALE_TOLERANCE,
                            "{at}: overlap scale {gs} against the CPU's {cs}"
                        );
                    }
                    (c, g) => assert_eq!(c, g, "{at}"),
                }
            }
        }
        let differ = tally.faces_differ as f64 / tally.faces_cpu.max(1) as f64;
        eprintln!(
            "{name}: {} seeds, {} fitted, {} faces, {:.3} % won apart, {} shared seeds, \
             overlap scales within {:.2e}, {} split (pieces within {:.2e} of the radius)",
            tally.seeds,
            tally.fitted,
            tally.faces_cpu,
            100.0 * differ,
            tally.shared,
            tally.worst_scale,
            tally.split,
            tally.worst_piece
        );
        assert!(tally.fitted > 0, "{name}: no region fitted in any frame");
        assert!(
            differ <= 0.005,
            "{name}: {:.3} % of faces won apart",
            100.0 * differ
        );
        all.fitted += tally.fitted;
        all.faces_cpu += tally.faces_cpu;
        all.shared += tally.shared;
        all.split += tally.split;
    }
    assert!(
        all.split >= 5,
        "only {} regions split into pieces",
        all.split
    );
    assert!(all.fitted >= 30, "only {} regions fitted", all.fitted);
    assert!(
        all.faces_cpu >= 5_000,
        "only {} region faces",
        all.faces_cpu
    );
    assert!(all.shared >= 5, "only {} seeds shared a region", all.shared);
}

#[test]
fn a_growth_past_its_capacity_stops_there_and_says_so() {
    let Some(ctx) =
        npr_gpu::testing::context_or_skip("a_growth_past_its_capacity_stops_there_and_says_so")
    else {
        return;
    };
    let pass = RegionPass::new(&ctx.device);
    let mesh = npr_geometry::generate::ellipsoid(0.7, 1.4, 1.0, 24);
    let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let (light_eye, world) = frames(bounding_radius(&mesh))[0];
    let sigma = ProjectorControls::default().sigma;
    let seeds: Vec<_> = set
        .search()
        .find(light_eye, world)
        .into_iter()
        .map(|c| (c, sigma))
        .collect();
    let input = RegionInput {
        frame: FrameId(1),
        set: &set,
        seeds: &seeds,
        light_eye,
        world_from_object: world,
    };
    let grow = |capacity| {
        let mut object = pass
            .create_object_with_capacity(&ctx.device, &set, capacity)
            .unwrap();
        pass.grow_now(&ctx.device, &ctx.queue, &mut object, &input)
            .unwrap()
    };
    let whole = grow(usize::MAX);
    let (k, faces) = whole
        .iter()
        .enumerate()
        .filter_map(|(k, g)| match g.region {
            Region::Fit(_, n) => Some((k, n)),
            _ => None,
        })
        .max_by_key(|(_, n)| *n)
        .expect("a region");
    assert!(!whole[k].overflowed && faces > 40, "{faces} faces");
    let cut = grow(faces / 4);
    assert!(cut[k].overflowed, "{:?}", cut[k]);
    assert!(cut[k].walked as usize <= faces / 4, "{:?}", cut[k]);
    match cut[k].region {
        Region::Fit(_, n) => assert!(n <= faces / 4, "{n} faces won"),
        other => panic!("{other:?}"),
    }
}

/// A ring: the top of a torus (axis y) lit and seen about along its axis, grown from one
/// centre,
/// is a region whose centroid lies in the hole. Its moment ellipse is fitted at the scale
/// of the largest intersection over union, from the radial bins, the same on the GPU.
#[test]
fn a_ring_region_is_fitted_as_the_cpu_fits_it() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("a_ring_region_is_fitted_as_the_cpu_fits_it")
    else {
        return;
    };
    let mesh = npr_geometry::generate::torus(1.0, 0.35, 96, 32);
    let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
    let light_eye = npr_geometry::LightEye::Directions {
        // Off the axis (`H` 8.5° from it): along it, `N = H` holds on the whole top circle,
        // a parabolic line, and the search finds no isolated centre.
        to_light: glam::Vec3::new(0.3, 1.0, 0.0).normalize(),
        to_eye: glam::Vec3::Y,
    };
    let world = glam::Mat4::IDENTITY;
    let first = set.search().find(light_eye, world)[0];
    let seeds = [(first, ProjectorControls::default().sigma)];
    let (topology, normals) = (set.topology(), set.search().normals());
    let mut grower = RegionGrower::with_patches(RegionPatches::new(topology, normals));
    let frame = RegionFrame {
        topology,
        normals,
        world_from_object: world,
        light_eye,
    };
    let cpu = grower.grow_all(&frame, &seeds);
    let pass = RegionPass::new(&ctx.device);
    let mut object = pass.create_object(&ctx.device, &set).unwrap();
    let input = RegionInput {
        frame: FrameId(1),
        set: &set,
        seeds: &seeds,
        light_eye,
        world_from_object: world,
    };
    let gpu = pass
        .grow_now(&ctx.device, &ctx.queue, &mut object, &input)
        .unwrap();
    let (Region::Fit(a, fa), Region::Fit(b, fb)) = (cpu[0], gpu[0].region) else {
        panic!("{:?} against {:?}", cpu[0], gpu[0]);
    };
    eprintln!(
        "ring: {fa} faces, offset {}, scale {} on the CPU, {} on the GPU",
        a.offset.length(),
        grower.overlap_scale(0, None),
        gpu[0].overlap_scale
    );
    assert_eq!(fa, fb);
    // The centroid in the hole, a major radius from the centre.
    assert!(a.offset.length() > 0.8, "{a:?}");
    assert!(b.offset.distance(a.offset) < 1e-3);
    let (cs, gs) = (grower.overlap_scale(0, None), gpu[0].overlap_scale);
    assert!(
        (cs - gs).abs() <= 1.0 / 128.0 + 1e-3,
        "{gs} against the CPU's {cs}"
    );
}

/// Seeds of different σ in one region (as a set grows a highlight the user sized beside
/// others): the first seed's small region is ringed by faces it reached and did not take,
/// and on the CPU's single queue those faces are closed to the seed beside it, which then
/// takes fewer faces than it would alone. The GPU walks each seed alone first, so the
/// seeds that met are walked again together (`cs_join`): the faces won are the CPU's.
#[test]
fn a_face_one_seed_reached_and_did_not_take_is_closed_to_the_others() {
    let Some(ctx) = npr_gpu::testing::context_or_skip(
        "a_face_one_seed_reached_and_did_not_take_is_closed_to_the_others",
    ) else {
        return;
    };
    let pass = RegionPass::new(&ctx.device);
    let mut frame = FrameId(1);
    let (mut faces_cpu, mut faces_differ, mut blocked) = (0usize, 0usize, 0usize);
    for (name, mesh) in meshes() {
        let radius = bounding_radius(&mesh);
        let set = HighlightSet::new(&mesh, &CurvatureOptions::default()).unwrap();
        let (topology, normals) = (set.topology(), set.search().normals());
        let mut grower = RegionGrower::default();
        let mut object = pass.create_object(&ctx.device, &set).unwrap();
        for (k, (light_eye, world)) in frames(radius).into_iter().enumerate() {
            let centres = set.search().find(light_eye, world);
            // Each centre with a tight σ, and a seed of a wide one a few faces from it.
            let mut seeds = Vec::new();
            for c in &centres {
                seeds.push((*c, 0.985));
                let near = HighlightCentre {
                    face: face_away(topology, c.face, 4),
                    ..*c
                };
                seeds.push((near, 0.8));
            }
            let region_frame = RegionFrame {
                topology,
                normals,
                world_from_object: world,
                light_eye,
            };
            let cpu = grower.grow_all(&region_frame, &seeds);
            let input = RegionInput {
                frame,
                set: &set,
                seeds: &seeds,
                light_eye,
                world_from_object: world,
            };
            frame = frame.next();
            let gpu = pass
                .grow_now(&ctx.device, &ctx.queue, &mut object, &input)
                .unwrap();
            for (s, (c, g)) in cpu.iter().zip(&gpu).enumerate() {
                let at = format!("{name} frame {k} seed {s}");
                assert!(!g.overflowed, "{at}: the growth overflowed");
                match (c, &g.region) {
                    (Region::Fit(_, fa), Region::Fit(_, fb)) => {
                        faces_cpu += fa;
                        faces_differ += fa.abs_diff(*fb);
                        // Did the CPU's queue close faces to this seed? Grown alone it
                        // takes more.
                        if s % 2 == 1 {
                            let alone = grower.grow_all(&region_frame, &seeds[s..=s]);
                            if let Region::Fit(_, n) = alone[0] {
                                blocked += usize::from(n > *fa);
                            }
                        }
                    }
                    (c, g) => assert_eq!(c, g, "{at}"),
                }
            }
        }
    }
    let differ = faces_differ as f64 / faces_cpu.max(1) as f64;
    eprintln!(
        "{blocked} seeds the CPU's queue closed faces to; {faces_cpu} faces, {:.3} % won apart",
        100.0 * differ
    );
    assert!(
        blocked >= 5,
        "only {blocked} seeds had faces closed to them"
    );
    assert!(
        differ <= 0.005,
        "{:.3} % of faces won apart",
        100.0 * differ
    );
}
