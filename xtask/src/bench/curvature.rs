//! `cargo xtask bench curvature`: speed and accuracy of the curvature field
//! on analytic meshes, irregular and noisy variants, and the real meshes in
//! `fixtures/meshes`; a method comparison (paper / clipped / corrected) on the 10k
//! torus; the per-frame N = H highlight-centre search; and the same field measured on
//! the GPU (`npr_gpu::CurvaturePass`, [`super::curvature_gpu`]) beside the CPU's.
//!
//! Errors are relative to the mesh's largest true |k| (percent); the direction error is
//! the angle between the computed and true k_max directions (degrees), left out at
//! (near-)umbilic vertices where the true direction is undefined.

use std::path::Path;
use std::time::Instant;

use glam::{Mat4, Vec3};
use npr_geometry::analytic::{self, Principal};
use npr_geometry::{
    CurvatureField, CurvatureMethod, CurvatureOptions, CurvatureRadius, HighlightSearch, LightEye,
    Mesh, Topology, generate, weld,
};

use super::table::{Cell, Table, emit};
use npr_geometry::stats::{median, quantile};

type Truth = Box<dyn Fn(Vec3) -> Principal>;

struct Case {
    name: String,
    mesh: Mesh,
    truth: Option<Truth>,
}

fn p95(v: &[f64]) -> f64 {
    quantile(v.iter().copied(), 0.95)
}

/// Median wall time of `runs` runs of topology + field, the field of the last run, and
/// the median of the field alone.
fn timed(
    mesh: &Mesh,
    opts: &CurvatureOptions,
    runs: usize,
) -> (f64, f64, Topology, CurvatureField) {
    let welded = weld(mesh);
    let (mut total, mut field_only) = (Vec::new(), Vec::new());
    let mut last = None;
    for _ in 0..runs.max(1) {
        let t0 = Instant::now();
        let topo = Topology::new(&welded);
        let t1 = Instant::now();
        let f = CurvatureField::compute(&topo, opts);
        let t2 = Instant::now();
        total.push((t2 - t0).as_secs_f64());
        field_only.push((t2 - t1).as_secs_f64());
        last = Some((topo, f));
    }
    let (topo, f) = last.unwrap_or_default();
    (median(total), median(field_only), topo, f)
}

struct Errors {
    kmin: (f64, f64),
    kmax: (f64, f64),
    dir: f64,
    invalid: usize,
}

fn errors(topo: &Topology, f: &CurvatureField, truth: &Truth) -> Errors {
    let t: Vec<Principal> = topo.positions.iter().map(|&p| truth(p)).collect();
    let kref = t
        .iter()
        .map(|a| a.kappa_max.abs().max(a.kappa_min.abs()))
        .fold(0.0, f64::max);
    let (mut en, mut ex, mut ed) = (Vec::new(), Vec::new(), Vec::new());
    let mut invalid = 0;
    for (v, a) in t.iter().enumerate() {
        if !f.valid[v] {
            invalid += 1;
            continue;
        }
        en.push((f64::from(f.kappa_min[v]) - a.kappa_min).abs() / kref * 100.0);
        ex.push((f64::from(f.kappa_max[v]) - a.kappa_max).abs() / kref * 100.0);
        if a.kappa_max - a.kappa_min > 0.05 * kref {
            ed.push(analytic::axis_angle_deg(
                f.dir_kappa_max[v].as_dvec3(),
                a.dir_kappa_max,
            ));
        }
    }
    Errors {
        kmin: (median(en.iter().copied()), p95(&en)),
        kmax: (median(ex.iter().copied()), p95(&ex)),
        dir: median(ed),
        invalid,
    }
}

fn torus_case(name: &str, vertices: usize, jitter: f32, noise: f32) -> Case {
    let (big_r, r) = (2.0f32, 0.7f32);
    let (nu, nv) = generate::torus_segments_for(big_r, r, vertices);
    let mut mesh = generate::torus_jittered(big_r, r, nu, nv, jitter, 7);
    if noise > 0.0 {
        mesh = generate::displace_along_normals(&mesh, noise * r, 11);
    }
    Case {
        name: name.to_string(),
        mesh,
        truth: Some(Box::new(move |p| {
            analytic::torus(p, f64::from(big_r), f64::from(r))
        })),
    }
}

const ERROR_COLUMNS: [&str; 6] = [
    "kmin_err_pct_median",
    "kmin_err_pct_p95",
    "kmax_err_pct_median",
    "kmax_err_pct_p95",
    "dir_err_deg_median",
    "invalid_vertices",
];

fn error_cells(e: Option<&Errors>, directions: bool) -> Vec<Cell> {
    match e {
        Some(e) => vec![
            Cell::Num(e.kmin.0, 3),
            Cell::Num(e.kmin.1, 3),
            Cell::Num(e.kmax.0, 3),
            Cell::Num(e.kmax.1, 3),
            if directions {
                Cell::Num(e.dir, 4)
            } else {
                Cell::Empty
            },
            e.invalid.into(),
        ],
        None => vec![Cell::Empty; 6],
    }
}

/// Runs the curvature benchmarks and prints (and optionally writes) their tables.
pub fn run(json: Option<&Path>) -> anyhow::Result<()> {
    println!(
        "curvature benchmark: {} rayon threads; corrected form at r = 3 mean edge lengths unless stated",
        rayon_threads()
    );
    let cases = cases()?;
    let bar = super::progress(2 * cases.len() as u64 + 9 + 3, "curvature");
    let main = field_table(&cases, &bar);
    let methods = method_table(&bar);
    let search = search_table(&bar)?;
    // The GPU table needs an adapter; without one the CPU tables are still written.
    let mut tables = vec![main, methods, search];
    match npr_gpu::GpuContext::new() {
        Ok(ctx) => {
            let mut gpu = super::curvature_gpu::table();
            for case in &cases {
                bar.set_message(format!("GPU: {}", case.name));
                gpu.push(super::curvature_gpu::row(&ctx, &case.name, &case.mesh)?);
                bar.inc(1);
            }
            tables.push(gpu);
        }
        Err(e) => println!("curvature benchmark: no GPU table ({e})"),
    }
    bar.finish_and_clear();

    emit(&tables, json)
}

/// The main table's meshes: analytic, jittered and noisy, the fixtures, the 1.1M knot.
fn cases() -> anyhow::Result<Vec<Case>> {
    let mut cases = vec![
        Case {
            name: "icosphere R=1 (10k)".into(),
            mesh: generate::icosphere(5, 1.0),
            truth: Some(Box::new(|_| Principal {
                kappa_max: 1.0,
                kappa_min: 1.0,
                dir_kappa_max: glam::DVec3::X,
            })),
        },
        torus_case("torus R=2 r=0.7 (10k)", 10_000, 0.0, 0.0),
        torus_case("torus R=2 r=0.7 (100k)", 100_000, 0.0, 0.0),
        Case {
            name: "ellipsoid 2x1.2x0.8 (20k)".into(),
            mesh: generate::ellipsoid(2.0, 1.2, 0.8, 45),
            truth: Some(Box::new(|p| analytic::ellipsoid(p, 2.0, 1.2, 0.8))),
        },
        torus_case(
            "torus 10k, jittered 0.25 cell along surface",
            10_000,
            0.25,
            0.0,
        ),
        torus_case(
            "torus 10k, normal noise ±0.2% of r (±1.6% of edge)",
            10_000,
            0.0,
            0.002,
        ),
        torus_case(
            "torus 100k, normal noise ±0.2% of r (±5% of edge)",
            100_000,
            0.0,
            0.002,
        ),
    ];
    for (name, file) in [
        ("stanford bunny (scan, holes)", "stanford-bunny.obj"),
        ("spot", "spot.obj"),
    ] {
        cases.push(Case {
            name: name.into(),
            mesh: npr_geometry::load_obj(crate::fixture_mesh(file))?,
            truth: None,
        });
    }
    cases.push(Case {
        name: "torus knot (1.1M triangles)".into(),
        mesh: generate::benchmark_knot(),
        truth: None,
    });
    Ok(cases)
}

/// Fills the main table: time and error of the default (corrected) field on each case.
fn field_table(cases: &[Case], bar: &indicatif::ProgressBar) -> Table {
    let mut columns = vec![
        "mesh",
        "vertices",
        "triangles",
        "radius_world",
        "time_s_median",
        "field_only_s_median",
        "vertices_per_s",
    ];
    columns.extend(ERROR_COLUMNS);
    let mut main = Table::new(
        "curvature field (corrected, r = 3 mean edge lengths; time = topology + field)",
        &columns,
    );
    let opts = CurvatureOptions::default();
    for c in cases {
        bar.set_message(c.name.clone());
        let runs = if c.mesh.triangle_count() > 500_000 {
            3
        } else {
            7
        };
        let (t, tf, topo, f) = timed(&c.mesh, &opts, runs);
        let e = c.truth.as_ref().map(|tr| errors(&topo, &f, tr));
        let mut row: Vec<Cell> = vec![
            c.name.clone().into(),
            topo.vertex_count().into(),
            topo.face_count().into(),
            Cell::Num(f64::from(f.radius_world), 5),
            Cell::Num(t, 4),
            Cell::Num(tf, 4),
            Cell::Num(topo.vertex_count() as f64 / t, 0),
        ];
        row.extend(error_cells(e.as_ref(), !c.name.starts_with("icosphere")));
        main.push(row);
        bar.inc(1);
    }
    main
}

/// Fills the method comparison on the 10k torus: paper, clipped, corrected at r = 2, 3, 4.
fn method_table(bar: &indicatif::ProgressBar) -> Table {
    let mut columns = vec!["method", "radius_edges", "time_s_median", "vertices_per_s"];
    columns.extend(ERROR_COLUMNS);
    let mut methods = Table::new("method comparison, torus R=2 r=0.7 (10k)", &columns);
    let torus = torus_case("", 10_000, 0.0, 0.0);
    for method in [
        CurvatureMethod::Paper,
        CurvatureMethod::Clipped,
        CurvatureMethod::Corrected,
    ] {
        for k in [2.0f32, 3.0, 4.0] {
            let opts = CurvatureOptions {
                method,
                radius: CurvatureRadius::EdgeLengths(k),
            };
            let runs = if method == CurvatureMethod::Clipped {
                3
            } else {
                7
            };
            let (t, _, topo, f) = timed(&torus.mesh, &opts, runs);
            let e = torus.truth.as_ref().map(|tr| errors(&topo, &f, tr));
            let mut row: Vec<Cell> = vec![
                method.name().into(),
                Cell::Num(f64::from(k), 1),
                Cell::Num(t, 4),
                Cell::Num(topo.vertex_count() as f64 / t, 0),
            ];
            row.extend(error_cells(e.as_ref(), true));
            methods.push(row);
            bar.inc(1);
        }
    }
    methods
}

/// Fills the per-frame N = H search table (§3.1): a light circling the object.
fn search_table(bar: &indicatif::ProgressBar) -> anyhow::Result<Table> {
    let mut search = Table::new(
        "highlight centres (N = H, Eq. (4)-(6)), point light circling, 64 frames",
        &[
            "mesh",
            "triangles",
            "centres_min",
            "centres_max",
            "find_us_median",
            "find_us_max",
        ],
    );
    let mut search_meshes = vec![
        (
            "paper knot (2,880 faces)".to_string(),
            generate::paper_knot(),
        ),
        (
            "icosphere (20k faces)".to_string(),
            generate::icosphere(5, 1.0),
        ),
    ];
    search_meshes.push((
        "stanford bunny".to_string(),
        npr_geometry::load_obj(crate::fixture_mesh("stanford-bunny.obj"))?,
    ));
    for (name, mesh) in &search_meshes {
        let topo = Topology::new(&weld(mesh));
        let f = CurvatureField::compute(&topo, &CurvatureOptions::default());
        let s = HighlightSearch::new(&topo, &f);
        let (lo, hi) = bounds(&topo.positions);
        let (centre, size) = ((lo + hi) * 0.5, (hi - lo).length());
        let eye = centre + Vec3::new(0.0, 0.0, 2.0 * size);
        let (mut times, mut counts) = (Vec::new(), Vec::new());
        for k in 0..64 {
            let a = k as f32 * std::f32::consts::TAU / 64.0;
            let light = centre + size * Vec3::new(1.5 * a.cos(), 1.0, 1.5 * a.sin() + 1.0);
            let t0 = Instant::now();
            let c = s.find(LightEye::Positions { light, eye }, Mat4::IDENTITY);
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            counts.push(c.len());
        }
        search.push(vec![
            name.clone().into(),
            topo.face_count().into(),
            counts.iter().copied().min().unwrap_or(0).into(),
            counts.iter().copied().max().unwrap_or(0).into(),
            Cell::Num(median(times.iter().copied()), 1),
            Cell::Num(times.iter().copied().fold(0.0, f64::max), 1),
        ]);
        bar.inc(1);
    }
    Ok(search)
}

fn bounds(p: &[Vec3]) -> (Vec3, Vec3) {
    p.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &q| (lo.min(q), hi.max(q)),
    )
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}
