//! Speed probe (development aid): `cargo run --release -p npr-geometry --example speed`.
#![allow(clippy::unwrap_used, missing_docs)]
use npr_geometry::*;
use std::time::Instant;

fn main() {
    let (nu, nv) = generate::torus_segments_for(2.0, 0.7, 100_000);
    let m = generate::torus(2.0, 0.7, nu, nv);
    let mut tw = vec![];
    let mut tt = vec![];
    let mut tf = vec![];
    for _ in 0..15 {
        let t0 = Instant::now();
        let w = weld(&m);
        let t1 = Instant::now();
        let topo = Topology::new(&w);
        let t2 = Instant::now();
        let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
        let t3 = Instant::now();
        std::hint::black_box(f);
        tw.push((t1 - t0).as_secs_f64());
        tt.push((t2 - t1).as_secs_f64());
        tf.push((t3 - t2).as_secs_f64());
    }
    for v in [&mut tw, &mut tt, &mut tf] {
        v.sort_by(f64::total_cmp);
    }
    println!(
        "median: weld {:.4} topo {:.4} field {:.4}; min: topo {:.4} field {:.4}",
        tw[7], tt[7], tf[7], tt[0], tf[0]
    );
}
