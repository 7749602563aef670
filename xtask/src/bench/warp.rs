//! `cargo xtask bench warp`: the warping paper's Tables 1–3 on our meshes and adapter.
//!
//! Park & Ihm, "Post-Rendering 3D Warping using Projective Texture" (KIISE 2002): full
//! render vs warped frames for k = 10, 20, 30, 40 and three proxy ratios per mesh, each
//! with the paper's path ([`Departures::PAPER`], JSON `mode` = `paper`) and ours (`ours`),
//! the quality of every measured warped frame against the full render at its pose, the
//! ablation of each of our departures alone (added to the paper's path, removed from ours),
//! Table 3 (objects sharing one reference pair), the fill floor and the ceiling
//! `k·FULL / (FULL + k·FILL)`, the effect of the bin count N, and spreading the reference
//! over the frames between.
//!
//! Sizes are kept small for a two-core software adapter: 512 × 512 frames, five sampled
//! frames per segment of k (timings are medians of 3 runs of each sampled frame, averaged
//! over the frames; quality is measured on the same frames). The object stays fixed; the
//! camera orbits it at 1°/frame under a world-fixed light.
//!
//! Tables 1–2 run every row with each of the three antialiasing settings (JSON
//! `antialiasing`: `none`; `msaa4`: full render, references and warp all 4× MSAA;
//! `msaa4-blend`: full render and references 4× MSAA, the warp one sample per pixel with its
//! rim blended by the references' coverage; each resolve inside the timed work), each
//! warped frame compared with the full render of the same antialiasing, by PSNR
//! and by mean FLIP over the object's pixels (`flip_mean`); the amortized time counts the
//! reference's own measured cost (`ref_ms`, its resolves included). The other tables are
//! single-sample.
//!
//! Knobs for experiments (not for the reported numbers): `NPR_WARP_BENCH_ONLY=<part of a
//! mesh name>` (`moving`: the moving-model table's only), `NPR_WARP_BENCH_AA=none|msaa4|msaa4-blend` (one antialiasing only),
//! `NPR_WARP_BENCH_QUICK=1` (middle ratio, k = 10 and 20, ablation only),
//! `NPR_WARP_BENCH_RATIO`, `NPR_WARP_BENCH_DUMP=<dir>` (full, warped and difference images
//! of every measured frame).

use super::table::{Cell, Table, emit};
use super::warp_tables::Tables;
use glam::Vec3;
use npr_geometry::stats::median;
use npr_gpu::{GpuContext, TargetFormats};
use npr_warp::rig::{
    CLEAR, DEG_PER_FRAME, Rig, Variant, WarpModel as BenchMesh, path_for, warp_models as meshes,
};
use npr_warp::{
    Antialiasing, Departure, Departures, Proxy, ReferenceFrame, SceneView, Turntable, WarpMode,
    WarpSchedule, WarpSequence, compare, metrics::flip_mean,
};
use std::path::{Path, PathBuf};
use std::time::Instant;

const SIZE: u32 = 512;
const KS: [u32; 4] = [10, 20, 30, 40];
/// Bins per axis used unless a table varies it.
const BINS: u32 = 16;
/// The camera orbits the fixed object (light fixed in the world, as post-rendering
/// warping's camera-motion use).
const ORBIT: bool = true;
/// The two ends every "ours vs paper" row compares.
const MODES: [(Departures, &str); 2] = [(Departures::PAPER, "paper"), (Departures::OURS, "ours")];

/// Wall time of `f` (which submits) plus waiting for the GPU, in ms.
fn timed(ctx: &GpuContext, f: impl FnOnce()) -> f64 {
    let t = Instant::now();
    f();
    let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
    t.elapsed().as_secs_f64() * 1e3
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Frames sampled inside a segment of length k (never the reference frames themselves).
fn sampled_steps(k: u32) -> Vec<u32> {
    let mut v: Vec<u32> = [1, k / 4, k / 2, (3 * k) / 4, k - 1]
        .into_iter()
        .filter(|&f| f >= 1 && f < k)
        .collect();
    v.dedup();
    v
}

/// Submits `enc` and waits for the GPU to idle; returns ms.
fn submit_ms(ctx: &GpuContext, enc: wgpu::CommandEncoder) -> f64 {
    timed(ctx, || {
        ctx.queue.submit(Some(enc.finish()));
    })
}

/// Full render of `scene` into the rig's target; returns ms (submit to idle).
fn full_ms(rig: &mut Rig<'_>, scene: &SceneView) -> anyhow::Result<f64> {
    let enc = rig.record_full(scene)?;
    Ok(submit_ms(rig.ctx, enc))
}

/// A reference of object 0 at `scene` into `slot`, resolves included; returns ms.
fn reference_ms(
    rig: &mut Rig<'_>,
    slot: &mut ReferenceFrame,
    scene: &SceneView,
) -> anyhow::Result<f64> {
    let enc = rig.record_reference(slot, scene)?;
    Ok(submit_ms(rig.ctx, enc))
}

/// One warped frame of `objects` (object i at `scene.object(i)`); returns ms, bins
/// blended and triangles drawn.
fn warp_ms(
    rig: &Rig<'_>,
    refs: [&ReferenceFrame; 2],
    objects: &mut [Variant],
    scene: &SceneView,
    s: f32,
    mode: WarpMode,
) -> (f64, usize, usize) {
    let (d, q) = (&rig.ctx.device, &rig.ctx.queue);
    let pair = rig.pass.bind_pair(d, refs);
    let mut blended = 0;
    let mut tris = 0;
    // Each call is one submission of its own.
    static SUBMISSIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let frame = npr_gpu::FrameId(SUBMISSIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed));
    let ms = timed(rig.ctx, || {
        let prepared: Vec<_> = objects
            .iter_mut()
            .enumerate()
            .filter_map(|(i, o)| {
                let now = scene.object(i);
                let input = npr_warp::WarpInput {
                    frame,
                    pair: &pair,
                    now: &now,
                    s,
                    settings: &o.settings,
                    mode,
                };
                rig.pass.prepare(q, &mut o.object, &input).ok()
            })
            .collect();
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut rpass = rig.begin_clear_pass(&mut enc, CLEAR);
            for (o, p) in objects.iter().zip(&prepared) {
                let _ = rig.pass.draw(&mut rpass, &o.object, p);
            }
        }
        q.submit(Some(enc.finish()));
        for (o, p) in objects.iter().zip(&prepared) {
            if let Ok(plan) = o.object.plan(&rig.pass, p) {
                blended += plan.bins_blended;
                tris += plan.triangles_drawn;
            }
        }
    });
    (ms, blended, tris)
}

/// Quality and timing of the warped frames of one segment of length k.
struct SegmentResult {
    warp_ms: f64,
    fill_ms: f64,
    psnr_mean: f64,
    psnr_worst: f64,
    ssim_mean: f64,
    flip_mean: f64,
    flip_worst: f64,
    blended_bins: f64,
    tris_drawn: f64,
}

/// Full renders already made, by (k, frame, objects).
type Fulls = std::collections::HashMap<(u32, u32, usize), image::RgbaImage>;

/// Measures the sampled frames of one segment of length k warped with `objects` (their
/// variants' mode is the first's); with `fill`, also the fill floor and FLIP.
fn segment(
    rig: &mut Rig<'_>,
    path: &Turntable,
    k: u32,
    objects: &mut [Variant],
    fill: bool,
    fulls: &mut Fulls,
) -> anyhow::Result<SegmentResult> {
    let mut flips = Vec::new();
    let mode = objects.first().map_or(WarpMode::DepthTested, |o| o.mode);
    let (r0, r1) = (
        rig.reference(&path.pose(0.0))?,
        rig.reference(&path.pose(k as f32))?,
    );
    let (mut warp, mut fills_ms, mut psnr, mut ssim, mut blended, mut tris) =
        (vec![], vec![], vec![], vec![], vec![], vec![]);
    for f in sampled_steps(k) {
        let scene = path.pose(f as f32);
        let s = f as f32 / k as f32;
        let key = (k, f, objects.len());
        if let std::collections::hash_map::Entry::Vacant(slot) = fulls.entry(key) {
            slot.insert(rig.full(&scene)?);
        }
        let mut runs = Vec::new();
        for _ in 0..3 {
            let (ms, b, t) = warp_ms(rig, [&r0, &r1], objects, &scene, s, mode);
            runs.push(ms);
            blended.push(b as f64);
            tris.push(t as f64);
        }
        warp.push(median(runs));
        let img = rig.image()?;
        if let Some(full) = fulls.get(&key) {
            let q = compare(full, &img);
            if let Ok(dir) = std::env::var("NPR_WARP_BENCH_DUMP") {
                let stem = format!("{dir}/k{k}-f{f}-n{}-{mode:?}", objects.len());
                full.save(format!("{stem}-full.png"))?;
                img.save(format!("{stem}-warp.png"))?;
                npr_warp::metrics::difference_image(full, &img, 4.0)
                    .save(format!("{stem}-diff.png"))?;
            }
            psnr.push(q.psnr_db);
            ssim.push(q.ssim);
            if fill {
                flips.extend(flip_mean(full, &img));
            }
        }
        if fill {
            let fills: Vec<f64> = (0..3)
                .map(|_| warp_ms(rig, [&r0, &r1], objects, &scene, s, WarpMode::Fill).0)
                .collect();
            fills_ms.push(median(fills));
        }
    }
    Ok(SegmentResult {
        warp_ms: mean(&warp),
        fill_ms: mean(&fills_ms),
        psnr_mean: mean(&psnr),
        psnr_worst: psnr.iter().copied().fold(f64::INFINITY, f64::min),
        ssim_mean: mean(&ssim),
        flip_mean: if flips.is_empty() {
            f64::NAN
        } else {
            mean(&flips)
        },
        flip_worst: flips.iter().copied().fold(f64::NAN, f64::max),
        blended_bins: mean(&blended),
        tris_drawn: mean(&tris),
    })
}

/// Ablation rows: the paper's path, the paper's path plus each departure alone, ours, and
/// ours minus each departure alone (the coverage lookup cannot leave the depth test, which
/// needs it). Each row: (variant name, departure, departures).
fn ablation_rows() -> Vec<(String, &'static str, Departures)> {
    let mut rows = vec![("paper".to_string(), "", Departures::PAPER)];
    for d in Departure::ALL {
        rows.push((
            format!("paper + {}", d.name()),
            d.name(),
            Departures::PAPER.with(d, true),
        ));
    }
    rows.push(("ours".to_string(), "", Departures::OURS));
    for d in Departure::ALL {
        if d == Departure::Coverage {
            continue;
        }
        rows.push((
            format!("ours - {}", d.name()),
            d.name(),
            Departures::OURS.with(d, false),
        ));
    }
    rows
}

/// One antialiasing setting's rig and its measured costs.
struct AaRig<'a> {
    /// The antialiasing.
    aa: Antialiasing,
    /// The rig rendering with it.
    rig: Rig<'a>,
    /// FULL: the full render, ms.
    full_ms: f64,
    /// REF: a reference (the same draw plus, multisampled, its depth resolve), ms.
    ref_ms: f64,
    /// The full renders made so far.
    fulls: Fulls,
}

/// Makes a rig per antialiasing and measures its FULL and REF (medians of 5 after one).
fn aa_rigs<'a>(
    ctx: &'a GpuContext,
    bm: &BenchMesh,
    path: &Turntable,
    aas: &[Antialiasing],
) -> anyhow::Result<Vec<AaRig<'a>>> {
    let mut rigs = Vec::new();
    for &aa in aas {
        let mut r = Rig::with_antialiasing(ctx, &bm.mesh, SIZE, aa)?;
        full_ms(&mut r, &path.pose(0.0))?;
        let full = (0..5)
            .map(|i| full_ms(&mut r, &path.pose(i as f32)))
            .collect::<anyhow::Result<Vec<_>>>()?;
        let full = median(full);
        let mut slot = r.reference_slot()?;
        reference_ms(&mut r, &mut slot, &path.pose(0.0))?;
        let reference = (0..5)
            .map(|i| reference_ms(&mut r, &mut slot, &path.pose(i as f32)))
            .collect::<anyhow::Result<Vec<_>>>()?;
        let reference = median(reference);
        println!(
            "  {}: full render {full:.2} ms, reference {reference:.2} ms",
            aa.name()
        );
        rigs.push(AaRig {
            aa,
            rig: r,
            full_ms: full,
            ref_ms: reference,
            fulls: Fulls::new(),
        });
    }
    Ok(rigs)
}

/// What every row of one mesh shares.
struct MeshRun<'a> {
    /// The mesh.
    bm: &'a BenchMesh,
    /// The camera's orbit around it.
    path: Turntable,
    /// World units per object unit.
    world_per_object: f32,
    /// The adapter's name, for the tables.
    adapter: &'a str,
    /// When the benchmark started, for the progress lines.
    started: Instant,
}

/// Runs the benchmark and prints (and optionally writes) its tables.
///
/// `models` (default: the Fox fixture) play `clip` (default: each one's first) in the
/// moving-model table ([`super::warp_clip`]); Tables 1-3 keep their meshes. With
/// `--mesh` or `--animation`, the moving-model table alone runs.
pub fn run(json: Option<&Path>, models: &[PathBuf], clip: Option<&str>) -> anyhow::Result<()> {
    let started = Instant::now();
    let ctx = GpuContext::new()?;
    if !models.is_empty() || clip.is_some() {
        return emit(&[super::warp_clip::run(&ctx, models, clip)?], json);
    }
    let adapter = ctx.adapter.get_info().name;
    println!("bench warp: adapter {}", ctx.adapter_summary());
    println!(
        "bench warp: {SIZE}x{SIZE}, object fixed, camera orbiting it at {DEG_PER_FRAME} \
         deg/frame (light fixed in the world), N = {BINS}, sampled frames per segment {:?} \
         (k = 10)",
        sampled_steps(10)
    );
    let mut tables = Tables::new();
    let only = std::env::var("NPR_WARP_BENCH_ONLY").ok();
    let quick = std::env::var("NPR_WARP_BENCH_QUICK").is_ok_and(|v| v == "1");
    let aa_only = std::env::var("NPR_WARP_BENCH_AA").ok();
    let aas: Vec<Antialiasing> = Antialiasing::ALL
        .into_iter()
        .filter(|a| aa_only.as_ref().is_none_or(|o| o == a.name()))
        .collect();
    for bm in meshes()? {
        if only.as_ref().is_some_and(|o| !bm.name.contains(o.as_str())) {
            continue;
        }
        let tris = bm.mesh.triangle_count();
        println!("bench warp: {} ({tris} triangles)", bm.name);
        let (path, world_per_object) = path_for(&bm.mesh, vec![Vec3::ZERO], 3.3, ORBIT);
        let mut rigs = aa_rigs(&ctx, &bm, &path, &aas)?;
        let m = MeshRun {
            bm: &bm,
            path,
            world_per_object,
            adapter: &adapter,
            started,
        };
        for (ri, &ratio) in bm.ratios.iter().enumerate() {
            if quick && ri != 1 {
                continue;
            }
            let ratio = std::env::var("NPR_WARP_BENCH_RATIO")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(ratio);
            let proxy = build_proxy(&bm, ratio, &mut tables.proxy)?;
            tables_1_2(&m, &mut rigs, &proxy, ratio, quick, &mut tables.t1)?;
            // The other tables are single-sample.
            let Some(r) = rigs.iter_mut().find(|r| r.aa == Antialiasing::None) else {
                continue;
            };
            if ri != 1 {
                continue;
            }
            // The ablation, the bin count, Table 3 and spreading, at the middle ratio.
            let (rig, fulls) = (&mut r.rig, &mut r.fulls);
            ablation(&m, rig, fulls, &proxy, &mut tables.ablation)?;
            if quick {
                continue;
            }
            bin_counts(&m, rig, fulls, &proxy, &mut tables.bins)?;
            table3(rig, &bm, &proxy, &mut tables.t3, &adapter)?;
            spreading(
                &ctx,
                rig,
                &bm,
                &proxy,
                &m.path,
                world_per_object,
                &mut tables.spread,
                &adapter,
            )?;
        }
    }
    println!(
        "bench warp: done in {:.0} s. Paper (GPU anchor, Table 2, k = 10): Bunny 3.77x, \
         Dragon 8.14x, Buddha 8.39x.",
        started.elapsed().as_secs_f64()
    );
    let moving = only
        .as_ref()
        .is_none_or(|o| o == "moving")
        .then(|| super::warp_clip::run(&ctx, models, clip))
        .transpose()?;
    let t = tables;
    let mut all = vec![t.t1, t.ablation, t.bins, t.t3, t.spread, t.proxy];
    all.extend(moving);
    emit(&all, json)
}

/// Builds the proxy of `bm` at `ratio` and records the build in the proxy table.
fn build_proxy(bm: &BenchMesh, ratio: f32, table: &mut Table) -> anyhow::Result<Proxy> {
    let t = Instant::now();
    let proxy = Proxy::simplify(&bm.mesh, ratio)?;
    let simplify_ms = t.elapsed().as_secs_f64() * 1e3;
    table.push(vec![
        bm.name.clone().into(),
        Cell::Num(f64::from(ratio) * 100.0, 2),
        proxy.triangles().into(),
        Cell::Num(f64::from(proxy.error_relative), 5),
        Cell::Num(f64::from(proxy.error_object), 5),
        Cell::Num(simplify_ms, 0),
    ]);
    Ok(proxy)
}

/// Fills Tables 1–2 at one ratio: every k, mode and antialiasing, with fill and ceiling.
fn tables_1_2(
    m: &MeshRun<'_>,
    rigs: &mut [AaRig<'_>],
    proxy: &Proxy,
    ratio: f32,
    quick: bool,
    t1: &mut Table,
) -> anyhow::Result<()> {
    let tris = m.bm.mesh.triangle_count();
    for k in KS {
        if quick && k > 20 {
            continue;
        }
        for (departures, mode) in MODES {
            for a in rigs.iter_mut() {
                let (full_ms, ref_ms) = (a.full_ms, a.ref_ms);
                let mut objects =
                    [a.rig
                        .variant(proxy, departures, m.world_per_object, BINS, false)?];
                let r = segment(&mut a.rig, &m.path, k, &mut objects, true, &mut a.fulls)?;
                let schedule = WarpSchedule::new(k, false)?;
                let amortized = schedule.amortized_ms(ref_ms, r.warp_ms);
                let speedup = full_ms / amortized;
                let kf = f64::from(k);
                let ceiling = kf * full_ms / (full_ms + kf * r.fill_ms);
                t1.push(vec![
                    m.bm.name.clone().into(),
                    tris.into(),
                    Cell::Num(f64::from(ratio) * 100.0, 2),
                    proxy.triangles().into(),
                    Cell::Num(f64::from(proxy.error_relative), 5),
                    k.into(),
                    mode.into(),
                    a.aa.name().into(),
                    Cell::Num(full_ms, 2),
                    Cell::Num(ref_ms, 2),
                    Cell::Num(r.warp_ms, 2),
                    Cell::Num(amortized, 2),
                    Cell::Num(speedup, 2),
                    Cell::Num(r.fill_ms, 2),
                    Cell::Num(ceiling, 2),
                    Cell::Num(speedup / ceiling, 3),
                    measured(r.psnr_mean, 2),
                    measured(r.psnr_worst, 2),
                    measured(r.ssim_mean, 4),
                    measured(r.flip_mean, 4),
                    measured(r.flip_worst, 4),
                    m.adapter.into(),
                ]);
                println!(
                    "  ratio {ratio} k {k} {mode} {}: warp {:.2} ms, fill {:.2} ms, speedup \
                 {speedup:.2}x (ceiling {ceiling:.2}x), PSNR {:.2} / {:.2} dB, FLIP \
                 {:.4} / {:.4}, {:.0} s",
                    a.aa.name(),
                    r.warp_ms,
                    r.fill_ms,
                    r.psnr_mean,
                    r.psnr_worst,
                    r.flip_mean,
                    r.flip_worst,
                    m.started.elapsed().as_secs_f64()
                );
            }
        }
    }
    Ok(())
}

/// Fills the ablation table at k = 20, one row per [`ablation_rows`] entry.
fn ablation(
    m: &MeshRun<'_>,
    rig: &mut Rig<'_>,
    fulls: &mut Fulls,
    proxy: &Proxy,
    table: &mut Table,
) -> anyhow::Result<()> {
    let mut ends = [f64::NAN; 2];
    for (variant, departure, departures) in ablation_rows() {
        let mut objects = [rig.variant(proxy, departures, m.world_per_object, BINS, false)?];
        let r = segment(rig, &m.path, 20, &mut objects, false, fulls)?;
        // Added to the paper: gain over the paper; removed from ours: loss from ours.
        let delta = if variant == "paper" {
            ends[0] = r.psnr_mean;
            0.0
        } else if variant == "ours" {
            ends[1] = r.psnr_mean;
            r.psnr_mean - ends[0]
        } else if variant.starts_with("paper") {
            r.psnr_mean - ends[0]
        } else {
            r.psnr_mean - ends[1]
        };
        println!(
            "  ablation {variant}: warp {:.2} ms, PSNR {:.2} dB ({delta:+.2})",
            r.warp_ms, r.psnr_mean
        );
        table.push(vec![
            m.bm.name.clone().into(),
            variant.into(),
            departure.into(),
            Cell::Num(r.warp_ms, 2),
            measured(r.psnr_mean, 2),
            measured(r.psnr_worst, 2),
            measured(r.ssim_mean, 4),
            measured(delta, 2),
            m.adapter.into(),
        ]);
    }
    Ok(())
}

/// Fills the bin-count table (§3.3.2): ours at k = 10 with 2 to 32 bins per axis.
fn bin_counts(
    m: &MeshRun<'_>,
    rig: &mut Rig<'_>,
    fulls: &mut Fulls,
    proxy: &Proxy,
    table: &mut Table,
) -> anyhow::Result<()> {
    for n in [2, 4, 8, 16, 32] {
        let mut o = [rig.variant(proxy, Departures::OURS, m.world_per_object, n, false)?];
        let r = segment(rig, &m.path, 10, &mut o, false, fulls)?;
        table.push(vec![
            m.bm.name.clone().into(),
            n.into(),
            Cell::Num(r.warp_ms, 2),
            Cell::Num(r.tris_drawn, 0),
            Cell::Num(r.blended_bins, 1),
            Cell::Num(r.psnr_mean, 2),
            m.adapter.into(),
        ]);
    }
    Ok(())
}

/// Table 3: 1–4 copies sharing object 0's reference pair (the paper assumes they face
/// about the same way). Reference cost = one object's full render.
fn table3(
    rig: &mut Rig<'_>,
    bm: &BenchMesh,
    proxy: &Proxy,
    table: &mut Table,
    adapter: &str,
) -> anyhow::Result<()> {
    let k = 10;
    let mut fulls = Fulls::new();
    for n in 1..=4usize {
        let offsets: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new((i % 2) as f32 * 2.2 - 1.1, 0.0, (i / 2) as f32 * -2.2 + 1.1))
            .collect();
        let (path, world_per_object) = path_for(&bm.mesh, offsets, 7.5, ORBIT);
        let mut objects: Vec<Variant> = (0..n)
            .map(|_| rig.variant(proxy, Departures::OURS, world_per_object, BINS, false))
            .collect::<Result<_, _>>()?;
        full_ms(rig, &path.pose(0.0))?;
        let full = (0..3)
            .map(|i| full_ms(rig, &path.pose(i as f32)))
            .collect::<anyhow::Result<Vec<_>>>()?;
        let full = median(full);
        // The shared reference renders object 0 only.
        let one = SceneView {
            camera: path.camera,
            objects: vec![path.pose(0.0).objects[0]],
        };
        let ref_ms = (0..3)
            .map(|_| full_ms(rig, &one))
            .collect::<anyhow::Result<Vec<_>>>()?;
        let ref_ms = median(ref_ms);
        let r = segment(rig, &path, k, &mut objects, false, &mut fulls)?;
        let amortized = WarpSchedule::new(k, false)?.amortized_ms(ref_ms, r.warp_ms);
        table.push(vec![
            bm.name.clone().into(),
            n.into(),
            Cell::Num(full, 2),
            Cell::Num(full / n as f64, 2),
            Cell::Num(r.warp_ms, 2),
            Cell::Num(amortized, 2),
            Cell::Num(amortized / n as f64, 2),
            Cell::Num(full / amortized, 2),
            Cell::Num(r.psnr_mean, 2),
            adapter.to_string().into(),
        ]);
    }
    Ok(())
}

/// Frame times of a [`WarpSequence`] over two segments with and without spreading.
#[allow(clippy::too_many_arguments)]
fn spreading(
    ctx: &GpuContext,
    rig: &mut Rig<'_>,
    bm: &BenchMesh,
    proxy: &Proxy,
    path: &Turntable,
    world_per_object: f32,
    table: &mut Table,
    adapter: &str,
) -> anyhow::Result<()> {
    let k = 10;
    let frames = 3 * k;
    let ours = Departures::OURS;
    for spread in [false, true] {
        let mut seq = WarpSequence::new(
            &ctx.device,
            &ctx.queue,
            WarpSchedule::new(k, spread)?,
            ours.settings(proxy, world_per_object),
            SIZE,
            SIZE,
            TargetFormats::default(),
        )?;
        let mut objects =
            [seq.pass()
                .create_object(&ctx.device, proxy, BINS, ours.inflation(proxy), false)?];
        let scene = |f: u32| path.pose(f as f32);
        let mut frame = |rig: &mut Rig<'_>, f: u32| -> anyhow::Result<()> {
            rig.sequence_frame(&mut seq, &mut objects, &scene, f)?;
            Ok(())
        };
        // Start-up (the first two references) is not timed.
        frame(rig, 0)?;
        let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
        let times = (1..frames)
            .map(|f| {
                let mut done = Ok(());
                let ms = timed(ctx, || done = frame(rig, f));
                done.map(|()| ms)
            })
            .collect::<anyhow::Result<Vec<f64>>>()?;
        table.push(vec![
            bm.name.clone().into(),
            if spread { "yes" } else { "no" }.into(),
            (frames - 1).into(),
            Cell::Num(mean(&times), 2),
            Cell::Num(times.iter().copied().fold(0.0, f64::max), 2),
            adapter.to_string().into(),
        ]);
    }
    Ok(())
}

/// A measured value, or an empty cell when nothing was measured (no frame compared).
fn measured(v: f64, digits: usize) -> Cell {
    if v.is_finite() {
        Cell::Num(v, digits)
    } else {
        Cell::Empty
    }
}
