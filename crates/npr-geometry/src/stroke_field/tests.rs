//! Stroke field tests on degenerate input and on an umbilic sphere.

use super::*;
use crate::{CurvatureOptions, generate, weld};

#[test]
fn degenerate_inputs_do_not_panic() {
    let empty = Topology::from_parts(Vec::new(), Vec::new());
    let f = CurvatureField::compute(&empty, &CurvatureOptions::default());
    let s = StrokeField::compute(&empty, &f, &StrokeFieldOptions::default());
    assert!(s.dir_kappa_max.is_empty());

    // A repeated-vertex face, a zero-area face, an out-of-range index, a NaN vertex,
    // an isolated vertex.
    let positions = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::splat(f32::NAN),
        Vec3::new(5.0, 5.0, 5.0),
    ];
    let tris = vec![[0, 1, 2], [0, 0, 1], [0, 1, 3], [1, 2, 4], [0, 1, 99]];
    let topo = Topology::from_parts(positions, tris);
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let s = StrokeField::compute(&topo, &f, &StrokeFieldOptions::default());
    assert_eq!(s.dir_kappa_max.len(), 6);
    assert!(s.dir_kappa_max.iter().all(|d| d.is_finite()));
    assert_eq!(s.dir_kappa_max[5], Vec3::ZERO);
}

#[test]
fn umbilic_sphere_has_a_weak_field() {
    let mesh = generate::icosphere(3, 1.0);
    let topo = Topology::new(&weld(&mesh));
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let s = StrokeField::compute(&topo, &f, &StrokeFieldOptions::default());
    assert!(
        s.strength.iter().all(|&x| x < 0.1),
        "{:?}",
        s.strength.iter().copied().fold(0.0, f32::max)
    );
}
