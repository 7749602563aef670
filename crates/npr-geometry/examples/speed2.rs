//! Speed probe 2 (development aid).
#![allow(clippy::unwrap_used, missing_docs)]
use npr_geometry::*;
use std::time::Instant;

fn main() {
    let (nu, nv) = generate::torus_segments_for(2.0, 0.7, 100_000);
    let m = generate::torus(2.0, 0.7, nu, nv);
    let topo = Topology::new(&weld(&m));
    let k: f32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(3.0);
    let rads = if k > 0.0 {
        vec![CurvatureRadius::EdgeLengths(k)]
    } else {
        vec![CurvatureRadius::World(1e-4)]
    };
    for rad in rads {
        let mut t = vec![];
        for _ in 0..11 {
            let t0 = Instant::now();
            let f = CurvatureField::compute(
                &topo,
                &CurvatureOptions {
                    method: CurvatureMethod::Corrected,
                    radius: rad,
                },
            );
            t.push(t0.elapsed().as_secs_f64());
            std::hint::black_box(f);
        }
        t.sort_by(f64::total_cmp);
        println!("{rad:?}: min {:.4} med {:.4}", t[0], t[5]);
    }
}
