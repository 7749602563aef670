//! Speed probe (development aid): `cargo run --release -p npr-geometry --example speed`.
//! `SPEED_RUNS=1` runs once (for callgrind), `SPEED_TOPO_ONLY=1` skips the field; the field's checksum is printed so that
//! two builds can be compared for identical output.
#![allow(clippy::unwrap_used, missing_docs)]
use npr_geometry::*;
use std::time::Instant;

fn main() {
    let (nu, nv) = generate::torus_segments_for(2.0, 0.7, 100_000);
    let m = generate::torus(2.0, 0.7, nu, nv);
    let mut tw = vec![];
    let mut tt = vec![];
    let mut tf = vec![];
    let runs: usize = std::env::var("SPEED_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(15)
        .max(1);
    let topo_only = std::env::var_os("SPEED_TOPO_ONLY").is_some();
    let mut last = None;
    for _ in 0..runs {
        let t0 = Instant::now();
        let w = weld(&m);
        let t1 = Instant::now();
        let topo = Topology::new(&w);
        let t2 = Instant::now();
        let f = if topo_only {
            CurvatureField::default()
        } else {
            CurvatureField::compute(&topo, &CurvatureOptions::default())
        };
        let t3 = Instant::now();
        last = Some(std::hint::black_box((topo, f)));
        tw.push((t1 - t0).as_secs_f64());
        tt.push((t2 - t1).as_secs_f64());
        tf.push((t3 - t2).as_secs_f64());
    }
    let mut ts: Vec<f64> = tt.iter().zip(&tf).map(|(a, b)| a + b).collect();
    for v in [&mut tw, &mut tt, &mut tf, &mut ts] {
        v.sort_by(f64::total_cmp);
    }
    println!(
        "median: weld {:.4} topo {:.4} field {:.4} topo+field {:.4}; min: topo {:.4} field {:.4} topo+field {:.4}",
        tw[runs / 2],
        tt[runs / 2],
        tf[runs / 2],
        ts[runs / 2],
        tt[0],
        tf[0],
        ts[0]
    );
    let (topo, f) = last.unwrap();
    println!("checksum {:016x}", checksum(&topo, &f));
}

/// FNV-1a over the bits of the topology's derived arrays and the field.
fn checksum(t: &Topology, f: &CurvatureField) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |x: u32| {
        h ^= u64::from(x);
        h = h.wrapping_mul(0x100_0000_01b3);
    };
    for v in t.face_normals.iter().chain(&t.vertex_normals) {
        v.to_array().iter().for_each(|x| eat(x.to_bits()));
    }
    t.face_areas
        .iter()
        .chain(&t.dihedral)
        .for_each(|x| eat(x.to_bits()));
    t.edges.iter().flatten().for_each(|&x| eat(x));
    t.face_edges.iter().flatten().for_each(|&x| eat(x));
    for e in 0..t.edges.len() {
        t.edge_faces(e).iter().for_each(|&x| eat(x));
    }
    for v in 0..t.vertex_count() {
        t.vertex_faces(v).iter().for_each(|&x| eat(x));
    }
    for g in 0..t.face_count() {
        t.face_neighbours(g).iter().for_each(|&x| eat(x));
    }
    eat(t.mean_edge_length.to_bits());
    for v in f
        .normal
        .iter()
        .chain(&f.dir_kappa_max)
        .chain(&f.dir_kappa_min)
    {
        v.to_array().iter().for_each(|x| eat(x.to_bits()));
    }
    f.kappa_max
        .iter()
        .chain(&f.kappa_min)
        .for_each(|x| eat(x.to_bits()));
    f.valid.iter().for_each(|&x| eat(u32::from(x)));
    h
}
