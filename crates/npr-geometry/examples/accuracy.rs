//! Quick accuracy and speed probe (development aid): `cargo run --release -p npr-geometry --example accuracy`.
#![allow(clippy::unwrap_used, missing_docs)]
use npr_geometry::*;
use std::time::Instant;

fn stats(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    (v[v.len() / 2], v[(v.len() * 95 / 100).min(v.len() - 1)])
}

fn main() {
    let k: f32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(3.0);
    for &(n, jit, noise) in &[
        (10_000usize, 0.0f32, 0.0f32),
        (100_000, 0.0, 0.0),
        (10_000, 0.25, 0.0),
        (10_000, 0.0, 0.002),
    ] {
        let (nu, nv) = generate::torus_segments_for(2.0, 0.7, n);
        let mut m = generate::torus_jittered(2.0, 0.7, nu, nv, jit, 7);
        if noise > 0.0 {
            m = generate::displace_along_normals(&m, noise * 0.7, 9);
        }
        for method in [
            CurvatureMethod::Paper,
            CurvatureMethod::Clipped,
            CurvatureMethod::Corrected,
        ] {
            let w = weld(&m);
            let t0 = Instant::now();
            let topo = Topology::new(&w);
            let t1 = Instant::now();
            let f = CurvatureField::compute(
                &topo,
                &CurvatureOptions {
                    method,
                    radius: CurvatureRadius::EdgeLengths(k),
                },
            );
            let t2 = Instant::now();
            let kref = 1.0 / 0.7f64;
            let (mut ex, mut en, mut ed) = (vec![], vec![], vec![]);
            for v in 0..topo.vertex_count() {
                let a = analytic::torus(topo.positions[v], 2.0, 0.7);
                ex.push((f.kappa_max[v] as f64 - a.kappa_max).abs() / kref * 100.0);
                en.push((f.kappa_min[v] as f64 - a.kappa_min).abs() / kref * 100.0);
                ed.push(analytic::axis_angle_deg(
                    f.dir_kappa_max[v].as_dvec3(),
                    a.dir_kappa_max,
                ));
            }
            let (a, b, c) = (stats(ex), stats(en), stats(ed));
            println!(
                "n={} jit={jit} noise={noise} {:9} topo {:.4}s field {:.4}s kmax {:.3}/{:.3}% kmin {:.3}/{:.3}% dir {:.4}°",
                topo.vertex_count(),
                method.name(),
                (t1 - t0).as_secs_f64(),
                (t2 - t1).as_secs_f64(),
                a.0,
                a.1,
                b.0,
                b.1,
                c.0
            );
        }
    }
}
