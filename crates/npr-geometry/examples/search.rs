//! Highlight search timing (development aid).
#![allow(clippy::unwrap_used, missing_docs)]
use glam::{Mat4, Vec3};
use npr_geometry::*;
use std::time::Instant;
fn main() {
    let knot = generate::paper_knot();
    let topo = Topology::new(&weld(&knot));
    let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
    let s = HighlightSearch::new(&topo, &f);
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let t0 = Instant::now();
    let mut n = 0;
    let mut solved = 0;
    for k in 0..5000 {
        let a = k as f32 * 0.001;
        let light = Vec3::new(3.0 * a.cos(), 2.0, 3.0 * a.sin() + 2.0);
        let c = s.find(LightEye::Positions { light, eye }, Mat4::IDENTITY);
        n += c.len();
        solved += c.len();
    }
    println!(
        "{:.2} us/frame, {} centres/frame {}",
        t0.elapsed().as_secs_f64() / 5000.0 * 1e6,
        n as f64 / 5000.0,
        solved
    );
}
