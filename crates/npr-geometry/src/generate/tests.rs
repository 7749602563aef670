//! Generator tests: counts, seams that weld, winding that agrees with the normals.

use super::*;
use crate::weld;

#[test]
fn counts_and_seams_weld() {
    let t = torus(2.0, 0.7, 30, 12);
    assert_eq!(weld(&t).positions.len(), 360);
    assert_eq!(t.triangle_count(), 720);
    let s = icosphere(2, 1.0);
    assert_eq!(s.positions.len(), 162);
    assert_eq!(s.triangle_count(), 320);
    assert_eq!(weld(&s).positions.len(), 162);
    let k = paper_knot();
    assert_eq!(k.triangle_count(), 2880);
    assert_eq!(weld(&k).positions.len(), 1440);
    let u = uv_sphere(1.0, 16, 8);
    assert_eq!(weld(&u).positions.len(), 16 * 7 + 2);
    assert_eq!(u.triangle_count(), 16 * 7 * 2);
    let c = cylinder(1.0, 2.0, 16, 4, true);
    assert_eq!(weld(&c).positions.len(), 16 * 5 + 2);
    for m in [
        t,
        s,
        k,
        u,
        c,
        plane(1.0, 1.0, 3, 3),
        ellipsoid(2.0, 1.2, 0.8, 4),
    ] {
        m.validate().unwrap();
    }
}

#[test]
fn winding_agrees_with_normals() {
    for m in [
        torus(2.0, 0.7, 30, 12),
        paper_knot(),
        ellipsoid(2.0, 1.2, 0.8, 5),
    ] {
        for t in m.triangles() {
            let p = t.map(|i| m.positions[i as usize]);
            let g = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(g.dot(m.normals[t[0] as usize]) > 0.0);
        }
    }
}
