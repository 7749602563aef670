//! The highlights match the light they stylize. GPU tests of the fidelity
//! measurement (`npr_specular::fidelity`) at a small resolution, on the sphere and a real
//! mesh, for the default sizing against the paper's; CPU tests of frame coherence on the
//! bunny turning and of the §3.4 controls on top of the measured footprints.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use glam::{Mat4, Vec2, Vec3};
use npr_geometry::{CurvatureOptions, LightEye, Mesh, generate};
use npr_gpu::{GpuMesh, testing};
use npr_specular::fidelity::{
    Coherence, FidelityRig, FidelityScore, standard_views, surface_at_scale, unit_sphere_transform,
};
use npr_specular::{HighlightSet, HighlightSizing, ProjectorControls};

fn fixture(name: &str) -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/meshes")
        .join(name);
    npr_geometry::load_obj(path).unwrap()
}

/// Scores `mesh` over 3 eyes × 2 lights at 200×150 with `sizing`.
fn score(ctx: &npr_gpu::GpuContext, mesh: &Mesh, sizing: HighlightSizing) -> FidelityScore {
    score_views(ctx, mesh, sizing, 3, (200, 150))
}

/// Scores `mesh` over `eyes` eyes × 2 lights at `w × h` with `sizing`.
fn score_views(
    ctx: &npr_gpu::GpuContext,
    mesh: &Mesh,
    sizing: HighlightSizing,
    eyes: usize,
    (w, h): (u32, u32),
) -> FidelityScore {
    let rig = FidelityRig::new(&ctx.device, &ctx.queue, w, h).unwrap();
    let mut set = HighlightSet::new(mesh, &CurvatureOptions::default()).unwrap();
    set.tuning.sizing = sizing;
    let gpu = GpuMesh::upload(&ctx.device, &surface_at_scale(mesh, &set)).unwrap();
    let views = standard_views(unit_sphere_transform(mesh), eyes, w as f32 / h as f32);
    let scores: Vec<_> = views
        .iter()
        .map(|v| {
            rig.score(&ctx.device, &ctx.queue, (&gpu, &mesh.indices), &mut set, v)
                .unwrap()
        })
        .collect();
    FidelityScore::pool(&scores)
}

#[test]
fn highlights_cover_the_region_they_stylize() {
    let Some(ctx) = testing::context_or_skip("highlights_cover_the_region_they_stylize") else {
        return;
    };
    let sphere = generate::icosphere(4, 1.0);
    let ours = score(ctx, &sphere, HighlightSizing::Region);
    let paper = score(ctx, &sphere, HighlightSizing::Paper);
    eprintln!("sphere: ours {ours:?}\n        paper {paper:?}");
    assert!(ours.precision >= 0.85 && ours.recall >= 0.85, "{ours:?}");
    assert!(ours.stretch_max <= 4.0, "{ours:?}");
    assert_eq!(ours.count_within, ours.views, "{ours:?}");
    // The measurement can fail: the paper's capped Eq. (8) misses half the region.
    assert!(paper.recall < 0.7, "{paper:?}");

    let spot = fixture("spot.obj");
    let ours = score(ctx, &spot, HighlightSizing::Region);
    eprintln!("spot: ours {ours:?}");
    assert!(ours.precision >= 0.7 && ours.recall >= 0.7, "{ours:?}");
    assert!(ours.stretch_max <= 4.0, "{ours:?}");
}

/// Scanned and modelled characters at the default settings: recall ≥ 0.75 at precision
/// ≥ 0.85, and the §3.4 edits keep ≥ 95 % of what §4.2 alone would draw. Spot and the Fox
/// were looked at while the region fit was chosen; the hammer (a raw scan) and the
/// bunny's light at other views than the bench's are not. The paper's Eq. (8) fails the
/// same bar, so the check can fail.
#[test]
fn scanned_meshes_keep_recall_at_precision_and_whole_edits_at_the_defaults() {
    let Some(ctx) = testing::context_or_skip("scanned_meshes_keep_recall_at_precision") else {
        return;
    };
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/meshes");
    let mut failures = Vec::new();
    for name in ["spot.obj", "Fox.glb", "hammer.obj", "stanford-bunny.obj"] {
        let mesh = npr_geometry::io::load(dir.join(name)).unwrap().mesh;
        let s = score_views(ctx, &mesh, HighlightSizing::default(), 6, (320, 240));
        eprintln!("{name}: {s:?}");
        if !(s.precision >= 0.85 && s.recall >= 0.75 && s.edit_completeness >= 0.95) {
            failures.push(format!(
                "{name}: precision {:.3}, recall {:.3}, edits {:.3}",
                s.precision, s.recall, s.edit_completeness
            ));
        }
        if name == "spot.obj" {
            let paper = score_views(ctx, &mesh, HighlightSizing::Paper, 6, (320, 240));
            assert!(paper.recall < 0.75 || paper.precision < 0.85, "{paper:?}");
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// On a coarse mesh the interpolated normal turns by more across one triangle
/// than the smooth falloff's fixed ramp (the cone margin), so the falloff ended within a
/// few pixels, a hard cut of the texture that §4.2 alone would draw on, and the §3.4
/// edits lost area to it. The ramp now spans at least the normal's turn across a face.
#[test]
fn coarse_meshes_fade_their_highlights_instead_of_cutting_them() {
    let Some(ctx) = testing::context_or_skip("coarse_meshes_fade_their_highlights") else {
        return;
    };
    // Before: cut 0.016, edits 0.930.
    let knot = generate::torus_knot(&generate::TorusKnot::trefoil(0.3, 48, 8));
    let s = score(ctx, &knot, HighlightSizing::Region);
    eprintln!("coarse knot: {s:?}");
    assert!(s.cut_boundary_share <= 0.005, "{s:?}");
    // Before: edits 0.892.
    let torus = generate::torus(1.0, 0.45, 12, 6);
    let s = score(ctx, &torus, HighlightSizing::Region);
    eprintln!("coarse torus: {s:?}");
    assert!(s.edit_completeness >= 0.95, "{s:?}");
    assert!(s.cut_boundary_share <= 0.005, "{s:?}");
}

/// The bunny turning in 1° steps (120 here; `cargo xtask bench specular-fidelity` turns it
/// 360°): no highlight appears or vanishes without its fade, and no footprint changes area
/// by more than 30 % between consecutive frames.
#[test]
fn the_turning_bunny_fades_and_keeps_its_footprints() {
    let bunny = fixture("stanford-bunny.obj");
    let mut set = HighlightSet::new(&bunny, &CurvatureOptions::default()).unwrap();
    let base = unit_sphere_transform(&bunny);
    let le = LightEye::Positions {
        light: Vec3::new(0.4, 0.7, 1.0).normalize() * 1e4,
        eye: Vec3::new(0.9, 0.6, 2.4).normalize() * 2.3,
    };
    let mut c = Coherence::new(set.tuning.fade_frames);
    let mut seen = 0;
    for deg in 0..120 {
        set.update(le, Mat4::from_rotation_y((deg as f32).to_radians()) * base);
        seen += set.highlights().len();
        c.step(&set);
    }
    eprintln!("bunny turning: {c:?}");
    assert!(seen > 120, "too few highlights to test: {seen}");
    assert_eq!((c.pops_in, c.pops_out), (0, 0), "{c:?}");
    assert!(c.area_change_max <= 0.3, "{c:?}");
    // The check can fail: without fades every change pops.
    set.tuning.fade_frames = 0;
    set.reset();
    let mut popping = Coherence::new(6);
    for deg in 0..120 {
        set.update(le, Mat4::from_rotation_y((deg as f32).to_radians()) * base);
        popping.step(&set);
    }
    assert!(popping.pops_in + popping.pops_out > 0, "{popping:?}");
}

/// §3.4: translate, rotate and scale act on top of the measured footprint.
#[test]
fn controls_act_on_the_measured_footprint() {
    let mut set =
        HighlightSet::new(&generate::icosphere(4, 1.0), &CurvatureOptions::default()).unwrap();
    let le = LightEye::Directions {
        to_light: Vec3::new(0.3, 0.4, 1.0).normalize(),
        to_eye: Vec3::Z,
    };
    let plain = set.update(le, Mat4::IDENTITY)[0].clone();
    assert_eq!(set.tuning.sizing, HighlightSizing::Region);
    assert!(plain.footprint.region_area > 0.0);
    set.tuning.controls = ProjectorControls {
        translate: Vec2::new(0.1, -0.05),
        rotate_rad: 0.4,
        scale: Vec2::new(2.0, 0.5),
        ..Default::default()
    };
    set.reset();
    let h = set.update(le, Mat4::IDENTITY)[0].clone();
    let (p0, p) = (&plain.projector, &h.projector);
    let want = p0.half_extent * Vec2::new(2.0, 0.5);
    assert!(
        (p.half_extent - want).length() < 1e-4,
        "{:?} vs {want}",
        p.half_extent
    );
    assert!((p.axis_u.dot(p0.axis_u) - 0.4f32.cos()).abs() < 1e-4);
    let e_max = h.centre.dir_kappa_max;
    let e_min = h.centre.normal_world.cross(e_max);
    let moved = p.centre_world - p0.centre_world;
    assert!(
        (moved - (e_max * 0.1 - e_min * 0.05)).length() < 1e-4,
        "{moved}"
    );
}
