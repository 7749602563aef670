//! The smooth stroke-direction field (`npr_geometry::stroke_field`): exact on the analytic
//! torus, smooth and still curvature-aligned on a real scan, the same at any scale.

use glam::Vec3;
use npr_geometry::{
    CurvatureField, CurvatureOptions, LineFieldStats, Mesh, RenderFieldStats, StrokeField,
    StrokeFieldOptions, Topology, analytic, generate, line_angle_deg, load_obj, weld,
};
use proptest::prelude::*;

fn fit(mesh: &Mesh) -> (Topology, CurvatureField, StrokeField) {
    fit_with(mesh, &StrokeFieldOptions::default())
}

fn fit_with(mesh: &Mesh, options: &StrokeFieldOptions) -> (Topology, CurvatureField, StrokeField) {
    let topo = Topology::new(&weld(mesh));
    let field = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let smooth = StrokeField::compute(&topo, &field, options);
    (topo, field, smooth)
}

#[test]
fn torus_field_stays_on_the_exact_principal_direction() {
    let (big, small) = (2.0, 0.7);
    let (nu, nv) = generate::torus_segments_for(big, small, 10_000);
    let (topo, _, smooth) = fit(&generate::torus(big, small, nu, nv));
    let mut worst = 0.0f64;
    for (i, p) in topo.positions.iter().enumerate() {
        let exact = analytic::torus(*p, f64::from(big), f64::from(small));
        let n = smooth.normal[i];
        let a = line_angle_deg(smooth.dir_kappa_max[i], exact.dir_kappa_max.as_vec3(), n)
            .expect("defined everywhere on the torus");
        worst = worst.max(a);
    }
    assert!(worst < 0.5, "worst deviation from exact {worst}°");
}

#[test]
fn bunny_field_is_smooth_and_follows_curvature() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/meshes/stanford-bunny.obj"
    );
    let mesh = load_obj(path).unwrap();
    let (topo, field, smooth) = fit(&mesh);
    let raw = LineFieldStats::measure(&topo, &field, &field.dir_kappa_max, 30.0);
    let s = LineFieldStats::measure(&topo, &field, &smooth.dir_kappa_max, 30.0);
    eprintln!(
        "raw {raw:?}\nsmooth {s:?}\niterations {} residual {}",
        smooth.iterations, smooth.relative_residual
    );
    assert!(s.jump_edge_share <= 0.02, "{s:?}");
    assert!(s.aniso_dev_deg <= 10.0, "{s:?}");
    assert!(s.jump_edge_share < raw.jump_edge_share);
}

#[test]
fn uniform_scale_changes_nothing() {
    let mesh = generate::ellipsoid(1.0, 0.6, 0.4, 16);
    let mut scaled = mesh.clone();
    scaled.positions.iter_mut().for_each(|p| *p *= 37.0);
    let (_, _, a) = fit(&mesh);
    let (_, _, b) = fit(&scaled);
    for (i, (x, y)) in a.dir_kappa_max.iter().zip(&b.dir_kappa_max).enumerate() {
        if a.strength[i] > 0.05 {
            let d = line_angle_deg(*x, *y, a.normal[i]).unwrap();
            assert!(d < 0.5, "vertex {i}: {d}°");
        }
    }
}

#[test]
fn disconnected_pieces_are_solved_independently() {
    // A torus and, far away, a sphere (no anisotropic vertex): the torus keeps its exact
    // field, the sphere's stays weak (its hatching falls back to a fixed axis).
    let mut a = generate::torus(1.0, 0.35, 48, 24);
    let b = generate::icosphere(2, 0.5);
    let base = a.positions.len() as u32;
    a.positions
        .extend(b.positions.iter().map(|p| *p + Vec3::new(5.0, 0.0, 0.0)));
    a.normals.extend(&b.normals);
    a.uvs.extend(&b.uvs);
    a.indices.extend(b.indices.iter().map(|i| i + base));
    let (topo, _, s) = fit(&a);
    for (i, p) in topo.positions.iter().enumerate() {
        if p.x > 3.0 {
            assert!(s.strength[i] < 0.1, "sphere vertex {i}: {}", s.strength[i]);
        } else {
            let exact = analytic::torus(*p, 1.0, 0.35).dir_kappa_max.as_vec3();
            let d = line_angle_deg(s.dir_kappa_max[i], exact, s.normal[i]).unwrap();
            assert!(d < 0.5, "torus vertex {i}: {d}°");
        }
    }
}

#[test]
fn crease_split_cuts_only_creases() {
    // A capped cylinder: its two rims are 90° creases, each rim vertex gets a second copy;
    // the side's own edges (22.5°) are not cut.
    let mesh = generate::cylinder(1.0, 2.0, 16, 4, true);
    let topo = Topology::new(&weld(&mesh));
    let split = topo.split_creases(50.0);
    assert_eq!(split.topology.vertex_count(), topo.vertex_count() + 2 * 16);
    assert_eq!(split.topology.triangles.len(), topo.triangles.len());
    for (f, t) in split.topology.triangles.iter().enumerate() {
        for (k, &v) in t.iter().enumerate() {
            assert_eq!(split.original[v as usize], topo.triangles[f][k]);
        }
    }
    // A rim that closes into one loop of 8 edges or more is cut at any length (a small
    // hole's or boss's rim, not a scan's noise).
    let count = |topo: &Topology, angle: f32, min: f32| {
        topo.crease_edges(angle, min).iter().filter(|&&c| c).count()
    };
    assert_eq!(count(&topo, 50.0, 1e3), 2 * 16);
    // Other lines only when at least as long as asked: a hexagonal prism's rims, above a
    // crease angle of 70° (its sides meet at 60°), are loops of 6 edges, each 6 long.
    let hexagon = Topology::new(&weld(&generate::cylinder(1.0, 2.0, 6, 4, true)));
    assert_eq!(count(&hexagon, 70.0, 0.0), 2 * 6);
    assert_eq!(count(&hexagon, 70.0, 5.9), 2 * 6);
    assert_eq!(count(&hexagon, 70.0, 6.1), 0);
    assert_eq!(
        hexagon
            .split_creases_longer_than(70.0, 6.1)
            .topology
            .vertex_count(),
        hexagon.vertex_count()
    );
    // Above the crease angle nothing is cut, and the numbering is kept.
    let whole = topo.split_creases(91.0);
    assert_eq!(whole.topology.triangles, topo.triangles);
    assert_eq!(whole.topology.positions, topo.positions);
}

#[test]
fn without_creases_and_flat_patches_the_field_is_unchanged() {
    // The rules change nothing on a smooth mesh: the default field of
    // `StrokeField::for_mesh` is the issue-11 field, bit for bit.
    let mesh = generate::torus(1.0, 0.35, 48, 24);
    let (_, _, plain) = fit_with(&mesh, &StrokeFieldOptions::curvature_only());
    let m = StrokeField::for_mesh(
        &mesh,
        &CurvatureOptions::default(),
        &StrokeFieldOptions::default(),
    );
    assert_eq!(m.field.dir_kappa_max, plain.dir_kappa_max);
    assert!(
        m.field
            .planar_patch
            .iter()
            .all(|&p| p == npr_geometry::stroke_field::NONE)
    );
}

#[test]
fn hard_edged_field_is_the_same_at_any_scale_and_position() {
    // Uniform scale and translation change no stroke line on a CAD part (the planar
    // rule's flatness test and the crease angle are dimensionless). Rotations may: the
    // planar rule is tied to the object's axes.
    let mesh = generate::box_with_hole(glam::Vec3::new(1.0, 0.4, 0.7), 0.35, 12);
    let opts = StrokeFieldOptions::default();
    let mut moved = mesh.clone();
    moved
        .positions
        .iter_mut()
        .for_each(|p| *p = *p * 23.0 + glam::Vec3::new(40.0, -7.0, 3.0));
    let a = StrokeField::for_mesh(&mesh, &CurvatureOptions::default(), &opts);
    let b = StrokeField::for_mesh(&moved, &CurvatureOptions::default(), &opts);
    for (v, (&i, &j)) in a.render_to_field.iter().zip(&b.render_to_field).enumerate() {
        let (x, y) = (
            a.field.dir_kappa_max[i as usize],
            b.field.dir_kappa_max[j as usize],
        );
        let d = line_angle_deg(x, y, moved.normals[v]).unwrap();
        assert!(d < 0.5, "vertex {v}: {d}°");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random bad meshes (out-of-range and repeated indices, NaN/inf coordinates, isolated
    /// vertices) never panic and give unit or zero directions, never NaN; their measures
    /// are finite.
    #[test]
    fn random_bad_meshes_do_not_panic(
        pts in proptest::collection::vec((-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0, 0u8..20), 0..40),
        idx in proptest::collection::vec(0u32..45, 0..120),
    ) {
        let positions: Vec<Vec3> = pts
            .iter()
            .map(|&(x, y, z, k)| match k {
                0 => Vec3::new(f32::NAN, y, z),
                1 => Vec3::new(x, f32::INFINITY, z),
                _ => Vec3::new(x, y, z),
            })
            .collect();
        let tris: Vec<[u32; 3]> = idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let topo = Topology::from_parts(positions, tris);
        let field = CurvatureField::compute(&topo, &CurvatureOptions::default());
        let s = StrokeField::compute(&topo, &field, &StrokeFieldOptions::default());
        prop_assert_eq!(s.dir_kappa_max.len(), topo.vertex_count());
        for d in &s.dir_kappa_max {
            prop_assert!(*d == Vec3::ZERO || (d.length() - 1.0).abs() < 1e-3, "{:?}", d);
        }
        let stats = LineFieldStats::measure(&topo, &field, &s.dir_kappa_max, 30.0);
        prop_assert!(stats.jump_edge_share.is_finite() && stats.aniso_dev_deg.is_finite());
        // The same soup as a render mesh, through the crease cut and back.
        let mesh = Mesh {
            normals: vec![Vec3::Y; topo.positions.len()],
            uvs: vec![glam::Vec2::ZERO; topo.positions.len()],
            positions: topo.positions.clone(),
            indices: idx[..idx.len() / 3 * 3].to_vec(),
        };
        let m = StrokeField::for_mesh(&mesh, &CurvatureOptions::default(), &StrokeFieldOptions::default());
        prop_assert_eq!(m.render_to_field.len(), mesh.positions.len());
        for d in &m.field.dir_kappa_max {
            prop_assert!(*d == Vec3::ZERO || (d.length() - 1.0).abs() < 1e-3, "{:?}", d);
        }
        let r = RenderFieldStats::measure(&mesh, &m.topology, &vec![Vec3::X; mesh.positions.len()], 30.0, 50.0);
        prop_assert!(r.jump_smooth_edge_share.is_finite());
        prop_assert!(r.planar_spread_deg.is_none_or(f64::is_finite));
    }
}
