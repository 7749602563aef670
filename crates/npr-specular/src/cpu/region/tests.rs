//! The moments, the sub-grid, and the growth with whole patches and on the exact
//! sub-grid against face by face.

use super::classify::{SUB, for_sub_triangles, grid_index, grid_points};
use super::fit::Moments;
use super::*;
use npr_geometry::{HighlightCentre, HighlightSearch};

/// The bunny scan of the fixtures.
fn bunny() -> npr_geometry::Mesh {
    let path = format!(
        "{}/../../fixtures/meshes/stanford-bunny.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    npr_geometry::load_obj(&path).unwrap()
}

/// `mesh`'s topology and highlight search, and the centre and radius of its bounds.
fn prepared(mesh: &npr_geometry::Mesh) -> (Topology, HighlightSearch, Vec3, f32) {
    use npr_geometry::{CurvatureField, CurvatureOptions};
    let (welded, topo, field) = CurvatureField::for_mesh(mesh, &CurvatureOptions::default());
    let search = HighlightSearch::for_mesh(mesh, &welded, &topo, &field);
    let (lo, hi) = topo.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    (topo, search, (lo + hi) * 0.5, (hi - lo).length() * 0.5)
}

/// A point light and eye around the object at angle `a`.
fn point_light(a: f32) -> LightEye {
    LightEye::Positions {
        light: Vec3::new(20.0 * a.cos(), 30.0, 20.0 * a.sin()),
        eye: Vec3::new(3.0 * (a + 0.4).sin(), 0.5, 3.0 * (a + 0.4).cos()),
    }
}

/// The growth frame of `topo` with `search`'s normals.
fn frame_of<'a>(
    topo: &'a Topology,
    search: &'a HighlightSearch,
    world_from_object: Mat4,
    light_eye: LightEye,
) -> RegionFrame<'a> {
    RegionFrame {
        topology: topo,
        normals: search.normals(),
        world_from_object,
        light_eye,
    }
}

/// Regions `a` and `b` grown with and without whole patches agree: the same faces,
/// footprint to float precision and normal cone (or the same non-fit).
fn assert_same_region(a: Region, b: Region, what: &str) {
    match (a, b) {
        (Region::Fit(p, n), Region::Fit(q, m)) => {
            assert_eq!(n, m, "faces of {what}");
            let size = p.half_extent.max_element();
            assert!(
                (p.region_area - q.region_area).abs() <= 1e-4 * p.region_area,
                "{what}: {p:?} vs {q:?}"
            );
            assert!(
                (p.half_extent - q.half_extent).abs().max_element() <= 1e-3 * size,
                "{what}: {p:?} vs {q:?}"
            );
            assert!(
                (p.offset - q.offset).length() <= 1e-3 * size,
                "{what}: {p:?} vs {q:?}"
            );
            assert_eq!(p.normal_cone_cos, q.normal_cone_cos, "{what}");
        }
        (a, b) => assert_eq!(a, b, "{what}"),
    }
}

#[test]
fn moments_of_a_square_and_its_clipped_half() {
    let mut m = Moments::default();
    let (a, b, c, d) = (
        Vec2::new(-1.0, -1.0),
        Vec2::new(1.0, -1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(-1.0, 1.0),
    );
    m.add_triangle(a, b, c);
    m.add_triangle(a, c, d);
    assert!((m.area - 4.0).abs() < 1e-9);
    // Var of a uniform [−1, 1] is 1/3.
    assert!((m.second[0] / m.area - 1.0 / 3.0).abs() < 1e-9);
    assert!(m.second[1].abs() < 1e-9);
    // Clip by x ≥ 0: values = x.
    let mut h = Moments::default();
    h.add_clipped([(a, a.x), (b, b.x), (c, c.x)]);
    h.add_clipped([(a, a.x), (c, c.x), (d, d.x)]);
    assert!((h.area - 2.0).abs() < 1e-6, "{}", h.area);
    assert!((h.first[0] / h.area - 0.5).abs() < 1e-6);
}

#[test]
fn the_sub_grid_tiles_the_face_once() {
    for steps in 1..=SUB {
        let mut area = 0.0;
        let mut count = 0;
        let pts: Vec<Vec2> = grid_points(steps)
            .map(|(i, j)| Vec2::new(i as f32, j as f32))
            .collect();
        assert_eq!(pts.len(), (steps + 1) * (steps + 2) / 2);
        for (g, (i, j)) in grid_points(steps).enumerate() {
            assert_eq!(grid_index(steps, i, j), g);
        }
        for_sub_triangles(steps, |a, b, c| {
            let t = 0.5 * (pts[b] - pts[a]).perp_dot(pts[c] - pts[a]);
            assert!(t > 0.0, "orientation");
            area += t;
            count += 1;
        });
        assert_eq!(count, steps * steps);
        assert!((area - 0.5 * (steps * steps) as f32).abs() < 1e-4);
    }
}

#[test]
fn an_ellipse_gets_its_own_half_axes() {
    // A polygonal ellipse of half axes 3 × 1, turned by 0.5 rad.
    let mut m = Moments::default();
    let k = 720;
    let (s, c) = 0.5f32.sin_cos();
    let pt = |i: usize| {
        let t = i as f32 / k as f32 * std::f32::consts::TAU;
        let (x, y) = (3.0 * t.cos(), t.sin());
        Vec2::new(x * c - y * s, x * s + y * c) + Vec2::new(0.2, -0.1)
    };
    for i in 0..k {
        m.add_triangle(Vec2::new(0.2, -0.1), pt(i), pt(i + 1));
    }
    let fp = m.footprint().unwrap();
    assert!((fp.rotate_rad - 0.5).abs() < 1e-3, "{fp:?}");
    assert!(
        (fp.half_extent - Vec2::new(3.0, 1.0)).length() < 1e-2,
        "{fp:?}"
    );
    assert!((fp.offset - Vec2::new(0.2, -0.1)).length() < 1e-4, "{fp:?}");
}

#[test]
fn whole_patches_take_the_faces_and_moments_face_by_face_takes() {
    // The same region grown with whole patches (moments from the patch tensors) and
    // face by face: the same faces, the same footprint to float precision, the same
    // normal cone, on a scan (the bunny), a sphere and a torus, point light and eye,
    // several views and a scaled, turned object, one seed at a time.
    let bunny = bunny();
    let sphere = npr_geometry::generate::icosphere(5, 1.0);
    let torus = npr_geometry::generate::torus(1.0, 0.45, 120, 48);
    let (mut compared, mut whole) = (0, 0);
    for mesh in [bunny, sphere, torus] {
        let (topo, search, c, r) = prepared(&mesh);
        let mut faces = RegionGrower::default();
        let mut patches = RegionGrower::with_patches(RegionPatches::new(&topo, search.normals()));
        for k in 0..6 {
            let a = k as f32 * 1.1;
            let world = Mat4::from_rotation_y(a)
                * Mat4::from_scale(Vec3::splat(1.7 / r))
                * Mat4::from_translation(-c);
            let light_eye = if k % 3 == 2 {
                LightEye::Directions {
                    to_light: Vec3::new(a.cos(), 1.0, a.sin()),
                    to_eye: Vec3::Z,
                }
            } else {
                point_light(a)
            };
            let frame = frame_of(&topo, &search, world, light_eye);
            for centre in search.find(light_eye, world) {
                for sigma in [0.9, 0.97] {
                    let seed = [(centre, sigma)];
                    let x = faces.grow_all(&frame, &seed);
                    let y = patches.grow_all(&frame, &seed);
                    whole += patches.counts().patches;
                    assert_same_region(x[0], y[0], "the seed");
                    assert_eq!(faces.pieces(0).len(), patches.pieces(0).len(), "pieces");
                    compared += usize::from(matches!(x[0], Region::Fit(..)));
                }
            }
        }
    }
    assert!(compared >= 20, "{compared} regions compared");
    assert!(whole >= 100, "{whole} patches taken whole");
}

#[test]
fn shared_regions_grow_with_patches_as_face_by_face() {
    // All centres at once, σ low enough that regions meet and a little different per
    // seed (so that which seed reaches a face first matters): with whole patches and
    // face by face, every seed gets the same faces, footprint and cone, on a scan (the
    // bunny) and a torus, several views. Some frames must keep some seeds' patches
    // while regrowing others (the path under test).
    let bunny = bunny();
    let torus = npr_geometry::generate::torus(1.0, 0.45, 120, 48);
    let (mut compared, mut partial, mut met) = (0, 0, 0);
    for mesh in [bunny, torus] {
        let (topo, search, c, r) = prepared(&mesh);
        let mut faces = RegionGrower::default();
        let mut patches = RegionGrower::with_patches(RegionPatches::new(&topo, search.normals()));
        for k in 0..8 {
            let a = k as f32 * 0.8;
            let world = Mat4::from_rotation_y(a)
                * Mat4::from_rotation_x(0.3 * a)
                * Mat4::from_scale(Vec3::splat(1.3 / r))
                * Mat4::from_translation(-c);
            let light_eye = point_light(a);
            let frame = frame_of(&topo, &search, world, light_eye);
            let centres = search.find(light_eye, world);
            for base in [0.6, 0.75, 0.85, 0.93] {
                let seeds: Vec<(HighlightCentre, f32)> = centres
                    .iter()
                    .enumerate()
                    .map(|(i, c)| (*c, base + 0.02 * (i % 3) as f32))
                    .collect();
                let x = faces.grow_all(&frame, &seeds);
                let y = patches.grow_all(&frame, &seeds);
                let counts = patches.counts();
                let growing = y.iter().filter(|r| matches!(r, Region::Fit(..))).count();
                if counts.regrown > 0 {
                    met += 1;
                    if counts.regrown < growing {
                        partial += 1;
                    }
                }
                for (i, (a, b)) in x.iter().zip(&y).enumerate() {
                    assert_same_region(*a, *b, &format!("seed {i} ({counts:?})"));
                    assert_eq!(faces.pieces(i).len(), patches.pieces(i).len(), "pieces");
                    compared += usize::from(matches!(a, Region::Fit(..)));
                }
            }
        }
    }
    println!("{compared} regions, {met} growths met, {partial} kept some patches");
    assert!(compared >= 100, "{compared} regions compared");
    assert!(met >= 5, "{met} growths where regions met");
    assert!(partial >= 3, "{partial} growths kept some seeds' patches");
}

#[test]
fn classified_growth_fits_what_the_exact_sub_grid_fits() {
    // The fast path (faces proved inside/outside from their vertices, linear clips,
    // coarser sub-grids, interpolated H) against every face on the finest sub-grid
    // with H at each point: the same footprints within a few percent, on a noisy
    // scan (the bunny) and a sphere, point light and near eye, several views.
    let bunny = bunny();
    let sphere = npr_geometry::generate::icosphere(4, 1.0);
    let mut fits = 0;
    for mesh in [bunny, sphere] {
        let (topo, search, c, r) = prepared(&mesh);
        let world = Mat4::from_scale(Vec3::splat(1.0 / r)) * Mat4::from_translation(-c);
        let mut fast = RegionGrower::default();
        let mut exact = RegionGrower::exact();
        for k in 0..6 {
            let a = k as f32 * 1.1;
            let light_eye = point_light(a);
            let seeds: Vec<(HighlightCentre, f32)> = search
                .find(light_eye, world)
                .into_iter()
                .map(|c| (c, 0.9))
                .collect();
            let frame = frame_of(&topo, &search, world, light_eye);
            let a = fast.grow_all(&frame, &seeds);
            let b = exact.grow_all(&frame, &seeds);
            let e = exact.counts();
            assert_eq!(e.inside + e.outside + e.linear, 0, "{e:?}");
            for (x, y) in a.iter().zip(&b) {
                match (x, y) {
                    (Region::Fit(p, _), Region::Fit(q, _)) => {
                        // Regions of a face or two are where the sub-grid itself is
                        // coarse; compare the ones that count (~20 px and up).
                        if q.region_area < 5e-4 {
                            continue;
                        }
                        fits += 1;
                        let rel = (p.region_area - q.region_area).abs() / q.region_area;
                        assert!(rel < 0.03, "area {p:?} vs {q:?}");
                        let size = q.half_extent.max_element();
                        assert!(
                            (p.half_extent - q.half_extent).abs().max_element() < 0.03 * size,
                            "extent {p:?} vs {q:?}"
                        );
                        assert!(
                            (p.offset - q.offset).length() < 0.03 * size,
                            "offset {p:?} vs {q:?}"
                        );
                        // Coarser sub-grids sample fewer normals: the cone may be
                        // narrower by a degree or two (receivers add 10°).
                        assert!(
                            p.normal_cone_cos <= q.normal_cone_cos + 0.02,
                            "cone {} vs {}",
                            p.normal_cone_cos,
                            q.normal_cone_cos
                        );
                    }
                    (Region::Fit(_, _), _) | (_, Region::Fit(_, _)) => {
                        panic!("one path fitted, the other did not: {x:?} / {y:?}")
                    }
                    _ => assert_eq!(x, y),
                }
            }
        }
        assert!(fast.counts().inside + fast.counts().outside > 0);
    }
    assert!(fits >= 10, "{fits} regions compared");
}

/// A band of 30 unit squares along x, fitted by an ellipse 5 × 1 of a region of area 5
/// (so long and bent enough to split, into `round(5 / 1.5)` = 3 pieces), is cut into
/// pieces of equal area along its length: 10 squares each. (A piece once closed at its
/// own area against the band's running share: 10, 20 and none.)
#[test]
fn a_bent_band_is_cut_into_pieces_of_equal_area() {
    use glam::Vec2;
    let whole = Footprint {
        half_extent: Vec2::new(5.0, 1.0),
        region_area: 5.0,
        ..Footprint::default()
    };
    assert!(super::split::needs_split(&whole));
    let taken: Vec<(u32, u32, Moments)> = (0..30)
        .map(|i| {
            let x = i as f32 - 15.0;
            let mut m = Moments::default();
            m.add_triangle(
                Vec2::new(x, 0.0),
                Vec2::new(x + 1.0, 0.0),
                Vec2::new(x + 1.0, 1.0),
            );
            m.add_triangle(
                Vec2::new(x, 0.0),
                Vec2::new(x + 1.0, 1.0),
                Vec2::new(x, 1.0),
            );
            (0, i, m)
        })
        .collect();
    let mut pieces = Vec::new();
    super::split::split_bent(&whole, 0, &taken, &mut Vec::new(), &mut pieces);
    let areas: Vec<f32> = pieces.iter().map(|p| p.region_area).collect();
    assert_eq!(areas.len(), 3, "{areas:?}");
    assert!(areas.iter().all(|a| (a - 10.0).abs() < 1e-4), "{areas:?}");
    // In order along the band.
    assert!(
        pieces.windows(2).all(|w| w[0].offset.x < w[1].offset.x),
        "{pieces:?}"
    );
}
