//! Profiling aid (development): `HighlightSet::update` over the specular bench's turning
//! sequence on one core, `cargo run --release -p npr-specular --example setup_profile -- MESH [FRAMES]`.
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::type_complexity
)]
use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, LightEye};
use npr_specular::HighlightSet;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mesh = match args.get(1).map(String::as_str) {
        Some("knot1m") => npr_geometry::generate::benchmark_knot(),
        Some(p) => npr_geometry::io::load(p).unwrap().mesh,
        None => panic!("MESH"),
    };
    // NPR_REORDER=1: triangles and vertices reordered for locality first (as `npr` loads).
    let mesh = if std::env::var_os("NPR_REORDER").is_some() {
        npr_geometry::locality::reorder_for_locality(&mesh).mesh
    } else {
        mesh
    };
    let frames: usize = args.get(2).map_or(60, |s| s.parse().unwrap());
    // Normalise like the bench's framing: centre and unit radius.
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(l, h), p| (l.min(*p), h.max(*p)));
    let c = (lo + hi) * 0.5;
    let r = (hi - lo).length() * 0.5;
    let world_from_normalized = Mat4::from_scale(Vec3::splat(1.0 / r)) * Mat4::from_translation(-c);
    let eye = Vec3::new(0.0, 0.0, 3.0);
    let to_light = Vec3::new(0.4, 0.7, 1.0).normalize();
    let t0 = Instant::now();
    // NPR_ABSTRACTION=A: the set's abstraction scale (default: the library's).
    let abstraction = std::env::var("NPR_ABSTRACTION")
        .ok()
        .and_then(|a| a.parse().ok())
        .unwrap_or(npr_specular::DEFAULT_ABSTRACTION);
    let mut set =
        HighlightSet::with_abstraction(&mesh, &CurvatureOptions::default(), abstraction).unwrap();
    eprintln!(
        "build {:.1} ms, {} faces",
        t0.elapsed().as_secs_f64() * 1e3,
        mesh.indices.len() / 3
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut rows = Vec::new();
    // Faces measured one by one and patches taken whole, summed over the frames (a
    // count that, unlike time, does not vary from run to run).
    let (mut measured, mut whole) = (0usize, 0usize);
    pool.install(|| {
        for frame in 0..frames + 3 {
            let w =
                Mat4::from_rotation_y((frame as f32 * 3.0).to_radians()) * world_from_normalized;
            let le = LightEye::Positions {
                light: to_light * 50.0,
                eye,
            };
            let t = Instant::now();
            set.update(le, w);
            let us = t.elapsed().as_secs_f64() * 1e6;
            let s = set.stats();
            if frame >= 3 {
                rows.push((
                    us,
                    s.search_us,
                    s.region_us,
                    s.visibility_us,
                    s.highlights,
                    s.receiver_faces,
                ));
                let c = s.region_faces;
                measured += c.inside + c.outside + c.linear + c.grid;
                whole += c.patches;
                if frame == 30 || std::env::var_os("COUNTS").is_some() {
                    eprintln!("{:?}", s.region_faces);
                }
                if std::env::var_os("VERBOSE").is_some() {
                    eprintln!(
                        "{frame}: {us:.0} us search {:.0} {:?}",
                        s.search_us, s.search
                    );
                }
            }
        }
    });
    let med = |f: &dyn Fn(&(f64, f64, f64, f64, usize, usize)) -> f64| {
        let mut v: Vec<f64> = rows.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!("faces measured {measured}, patches taken whole {whole}");
    println!(
        "total {:.1} us | search {:.1} | region {:.1} | visibility {:.1} | highlights {} | receivers {}",
        med(&|r| r.0),
        med(&|r| r.1),
        med(&|r| r.2),
        med(&|r| r.3),
        med(&|r| r.4 as f64),
        med(&|r| r.5 as f64)
    );
}
