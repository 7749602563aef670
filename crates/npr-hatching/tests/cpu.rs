//! CPU tests of the tonal art maps and the per-pixel hatching function (no GPU needed):
//! tone reproduction, stroke orientation (structure tensor), seams across partitions
//! (Fig. 1), nesting, tiling and typed errors.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use npr_hatching::{
    BlendMode, CpuHatcher, HatchError, HatchInputs, HatchParams, StrokeSpace, TamParams, TamStyle,
    TonalArtMap,
};
use std::f32::consts::PI;
use std::sync::OnceLock;

fn tam(style: TamStyle) -> &'static TonalArtMap {
    static PEN: OnceLock<TonalArtMap> = OnceLock::new();
    static PENCIL: OnceLock<TonalArtMap> = OnceLock::new();
    let cell = match style {
        TamStyle::Pen => &PEN,
        TamStyle::Pencil => &PENCIL,
    };
    cell.get_or_init(|| TonalArtMap::generate(&TamParams::for_style(style)).unwrap())
}

fn mean(v: &[f32]) -> f32 {
    v.iter().map(|&x| f64::from(x)).sum::<f64>() as f32 / v.len() as f32
}

/// Nesting (Praun et al. 2001 §4.1) of every map the crate generates: the defaults of
/// both styles and other sizes, tone counts and seeds.
#[test]
fn every_tam_nests() {
    let mut maps = vec![tam(TamStyle::Pen).clone(), tam(TamStyle::Pencil).clone()];
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        for (size, tones, seed) in [(64, 6, 1), (128, 12, 7), (32, 32, 99)] {
            maps.push(
                TonalArtMap::generate(&TamParams {
                    size,
                    tones,
                    seed,
                    ..TamParams::for_style(style)
                })
                .unwrap(),
            );
        }
    }
    for m in &maps {
        assert_eq!(
            m.nesting_violation(),
            None,
            "{:?} size {} tones {}",
            m.style(),
            m.size(),
            m.tones()
        );
        assert!(m.tones() >= 6);
        // Slice 0 is paper; measured coverage follows the targets (within 1 % ink).
        for i in 0..m.tones() {
            let (c, t) = (m.coverage(i).unwrap(), m.target_coverage(i));
            assert!(
                (c - t).abs() <= 0.01,
                "{:?} slice {i}: {c} vs {t}",
                m.style()
            );
        }
    }
}

/// Tileable: the ink change across the wrap-around edge (last column → first, last row →
/// first) is no outlier: at most the largest change between interior neighbours.
#[test]
fn tam_slices_tile() {
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        let m = tam(style);
        let n = m.size() as usize;
        for i in 1..m.tones() {
            let s = m.slice(i).unwrap();
            let at = |x: usize, y: usize| f32::from(s[(y % n) * n + (x % n)]) / 255.0;
            let col_diff =
                |x: usize| (0..n).map(|y| (at(x + 1, y) - at(x, y)).abs()).sum::<f32>() / n as f32;
            let row_diff =
                |y: usize| (0..n).map(|x| (at(x, y + 1) - at(x, y)).abs()).sum::<f32>() / n as f32;
            let max_col = (0..n - 1).map(col_diff).fold(0.0, f32::max);
            let max_row = (0..n - 1).map(row_diff).fold(0.0, f32::max);
            assert!(col_diff(n - 1) <= max_col, "{style:?} slice {i} columns");
            assert!(row_diff(n - 1) <= max_row, "{style:?} slice {i} rows");
        }
    }
}

/// Tone: for constant tone and direction, mean ink coverage = 1 − tone (clamped to the
/// map's darkest slice) within 0.02, and per pixel (so also on average) monotonic over
/// the whole tone range, for both styles and all three modes.
#[test]
fn coverage_matches_tone_and_is_monotonic() {
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        let m = tam(style);
        for mode in BlendMode::ALL {
            let params = HatchParams {
                mode,
                ..Default::default()
            };
            let h = CpuHatcher::new(m, &params).unwrap();
            let mut previous: Option<Vec<f32>> = None;
            for k in 0..=40 {
                let tone = 1.0 - k as f32 / 40.0;
                let inputs = HatchInputs::constant(256, 256, tone, 0.37).unwrap();
                let cov = h.hatch_coverage(&inputs).unwrap();
                let expected = (1.0 - tone).min(m.max_coverage());
                let got = mean(&cov);
                assert!(
                    (got - expected).abs() <= 0.02,
                    "{style:?} {mode:?} tone {tone}: coverage {got}, expected {expected}"
                );
                if let Some(prev) = &previous {
                    assert!(
                        cov.iter().zip(prev).all(|(c, p)| *c >= *p - 1e-6),
                        "{style:?} {mode:?} tone {tone}: coverage decreased somewhere"
                    );
                }
                previous = Some(cov);
            }
        }
    }
}

/// Dominant stroke orientation of a coverage patch from the structure tensor, as θ
/// (counter-clockwise from +x on screen, y up), in [0, π).
/// Gaussian smoothing (σ = 1.5 px, separable, clamped edges) before differentiating, as
/// the structure tensor's derivative-of-Gaussian prescribes; without it the staircase of
/// nearest-texel strokes biases the orientation towards 45°.
fn smooth(cov: &[f32], w: usize, h: usize) -> Vec<f32> {
    let k: Vec<f32> = (-4i32..=4)
        .map(|i| (-(i * i) as f32 / (2.0 * 1.5 * 1.5)).exp())
        .collect();
    let ks: f32 = k.iter().sum();
    let pass = |src: &[f32], dx: usize, dy: usize| -> Vec<f32> {
        let mut out = vec![0f32; w * h];
        for y in 0..h {
            for x in 0..w {
                let mut acc = 0f32;
                for (j, kv) in k.iter().enumerate() {
                    let o = j as i32 - 4;
                    let xx = (x as i32 + o * dx as i32).clamp(0, w as i32 - 1) as usize;
                    let yy = (y as i32 + o * dy as i32).clamp(0, h as i32 - 1) as usize;
                    acc += kv * src[yy * w + xx];
                }
                out[y * w + x] = acc / ks;
            }
        }
        out
    };
    pass(&pass(cov, 1, 0), 0, 1)
}

fn stroke_orientation(cov: &[f32], w: usize, h: usize) -> f32 {
    let cov = smooth(cov, w, h);
    let (mut jxx, mut jxy, mut jyy) = (0f64, 0f64, 0f64);
    for y in 5..h - 5 {
        for x in 5..w - 5 {
            let gx = f64::from(cov[y * w + x + 1] - cov[y * w + x - 1]);
            // Screen y up: the row above is +y.
            let gy = f64::from(cov[(y - 1) * w + x] - cov[(y + 1) * w + x]);
            jxx += gx * gx;
            jxy += gx * gy;
            jyy += gy * gy;
        }
    }
    // Orientation of the dominant gradient; strokes run perpendicular to it.
    let phi = 0.5 * (2.0 * jxy).atan2(jxx - jyy) as f32;
    (phi + PI / 2.0).rem_euclid(PI)
}

fn angle_diff(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(PI);
    d.min(PI - d)
}

/// Direction: the structure-tensor orientation of a 160² patch matches θ within half a
/// bin (Δθ/2 = 5.6° at 16 bins) for 60 values of θ over [0, π), for both styles (pen at a
/// tone without cross-hatching), blended and offset partition; cut-and-paste matches its
/// quantized θ^q within the same bound.
#[test]
fn stroke_orientation_follows_theta() {
    let params = HatchParams::default();
    let half_bin = params.bin_width_rad() / 2.0;
    for (style, tone) in [(TamStyle::Pen, 0.75), (TamStyle::Pencil, 0.6)] {
        for mode in BlendMode::ALL {
            let h = CpuHatcher::new(tam(style), &HatchParams { mode, ..params }).unwrap();
            let mut worst = 0f32;
            for k in 0..60 {
                let theta = (k as f32 + 0.3) * PI / 60.0;
                let inputs = HatchInputs::constant(160, 160, tone, theta).unwrap();
                let cov = h.hatch_coverage(&inputs).unwrap();
                let got = stroke_orientation(&cov, 160, 160);
                // Cut-and-paste draws the quantized direction θ^q (Eq. (1)) by design.
                let want = if mode == BlendMode::CutAndPaste {
                    (theta / params.bin_width_rad()).round() * params.bin_width_rad()
                } else {
                    theta
                };
                let err = angle_diff(got, want);
                worst = worst.max(err);
                assert!(
                    err <= half_bin,
                    "{style:?} {mode:?}: θ {:.2}° measured {:.2}° (error {:.2}°, half bin {:.2}°)",
                    theta.to_degrees(),
                    got.to_degrees(),
                    err.to_degrees(),
                    half_bin.to_degrees()
                );
            }
            eprintln!(
                "{style:?} {mode:?}: worst orientation error {:.2}°",
                worst.to_degrees()
            );
        }
    }
}

/// The seam score of a hatched image whose θ varies along x: for each pair of
/// neighbouring columns, the mean absolute coverage change down the column, divided by
/// the same quantity averaged over the columns 3..=12 to either side (the local texture's
/// own variation); the score is the largest such ratio. A partition boundary of
/// cut-and-paste (§3.1) is a column where unrelated texture meets: a spike.
fn seam_score(cov: &[f32], w: usize, h: usize) -> f32 {
    let cols: Vec<f32> = (0..w - 1)
        .map(|x| {
            (0..h)
                .map(|y| (cov[y * w + x + 1] - cov[y * w + x]).abs())
                .sum::<f32>()
                / h as f32
        })
        .collect();
    (12..cols.len() - 12)
        .map(|x| {
            let around: f32 = (3..=12).map(|o| cols[x - o] + cols[x + o]).sum::<f32>() / 20.0;
            cols[x] / around.max(1e-6)
        })
        .fold(0.0, f32::max)
}

/// Seams (Fig. 1): with θ sweeping slowly across the image (several bin boundaries), the
/// worst column-to-column discontinuity is clearly lower with blending (§3.2) and with
/// the offset partition (§3.3) than with cut-and-paste alone (§3.1): asserted ordering
/// cut-and-paste > 1.25 × blended and > 1.25 × offset partition (measured: pen about
/// 3.1 vs 1.2 and 1.3; pencil, whose grain varies everywhere, about 1.7 vs 1.2).
#[test]
fn blending_and_offset_partition_hide_seams() {
    let (w, h) = (512usize, 512usize);
    let inputs =
        HatchInputs::from_fn(w as u32, h as u32, |x, _| (0.6, 0.1 + 0.9 * x / w as f32)).unwrap();
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        let score = |mode| {
            let h2 = CpuHatcher::new(
                tam(style),
                &HatchParams {
                    mode,
                    ..Default::default()
                },
            )
            .unwrap();
            seam_score(&h2.hatch_coverage(&inputs).unwrap(), w, h)
        };
        let cut = score(BlendMode::CutAndPaste);
        let blended = score(BlendMode::Blended);
        let offset = score(BlendMode::OffsetPartition);
        eprintln!("{style:?}: seam score cut {cut:.2}, blended {blended:.2}, offset {offset:.2}");
        assert!(
            cut > 1.25 * blended,
            "{style:?}: cut {cut} blended {blended}"
        );
        assert!(cut > 1.25 * offset, "{style:?}: cut {cut} offset {offset}");
    }
}

/// Bad inputs are typed errors, never panics; NaN tone and θ are sanitized.
#[test]
fn bad_inputs_are_typed_errors() {
    let m = tam(TamStyle::Pen);
    assert!(matches!(
        CpuHatcher::new(
            m,
            &HatchParams {
                bins: 4,
                ..Default::default()
            }
        ),
        Err(HatchError::InvalidParams { .. })
    ));
    assert!(matches!(
        HatchInputs::constant(0, 0, 0.5, 0.0),
        Err(HatchError::InvalidSize { .. })
    ));
    assert!(matches!(
        HatchInputs::from_flow(4, 4, &[[1.0, 0.0]; 15], &[1.0; 16], 1.0),
        Err(HatchError::LengthMismatch { .. })
    ));
    let inputs = HatchInputs::new(
        4,
        1,
        &[f32::NAN, f32::INFINITY, -1.0, 0.5],
        &[f32::NAN, f32::NEG_INFINITY, 1e30, -1e30],
    )
    .unwrap();
    let h = CpuHatcher::new(m, &HatchParams::default()).unwrap();
    let cov = h.hatch_coverage(&inputs).unwrap();
    assert!(cov.iter().all(|c| c.is_finite() && (0.0..=1.0).contains(c)));
    // Out-of-range pixel coordinates and tones in the per-pixel function do not panic.
    for v in [f32::NAN, f32::INFINITY, -1e9, 1e9] {
        let c = h.coverage(v, v, 0.5, 1.0);
        assert!(c.is_finite());
    }
}

/// 2-D flow visualisation (§5): strokes follow a circular flow field: the orientation
/// measured in each quadrant patch matches the field's direction at its centre within a
/// bin.
#[test]
fn flow_field_strokes_follow_the_field() {
    let n = 384usize;
    let c = n as f32 / 2.0;
    let mut dir = Vec::new();
    let mut mag = Vec::new();
    for y in 0..n {
        for x in 0..n {
            // Screen axes (y up): a vortex around the centre.
            let (px, py) = (x as f32 + 0.5 - c, c - (y as f32 + 0.5));
            dir.push([-py, px]);
            mag.push(0.4);
        }
    }
    let inputs = HatchInputs::from_flow(n as u32, n as u32, &dir, &mag, 1.0).unwrap();
    let h = CpuHatcher::new(tam(TamStyle::Pen), &HatchParams::default()).unwrap();
    let cov = h.hatch_coverage(&inputs).unwrap();
    let patch = 64usize;
    for (cx, cy) in [
        (96usize, 96usize),
        (288, 96),
        (96, 288),
        (288, 288),
        (192, 40),
    ] {
        let mut p = Vec::with_capacity(patch * patch);
        for y in cy - patch / 2..cy + patch / 2 {
            for x in cx - patch / 2..cx + patch / 2 {
                p.push(cov[y * n + x]);
            }
        }
        let got = stroke_orientation(&p, patch, patch);
        let (px, py) = (cx as f32 - c, c - cy as f32);
        let want = px.atan2(-py).rem_euclid(PI);
        let err = angle_diff(got, want);
        assert!(
            err <= HatchParams::default().bin_width_rad(),
            "patch ({cx},{cy}): {:.1}° vs {:.1}°",
            got.to_degrees(),
            want.to_degrees()
        );
    }
}

/// Mean length of the horizontal runs of ink (coverage > ½) in columns `x0..x1`.
fn mean_run(cov: &[f32], w: usize, x0: usize, x1: usize) -> f32 {
    let (mut runs, mut total, mut len) = (0usize, 0usize, 0usize);
    for row in cov.chunks_exact(w) {
        for &c in &row[x0..x1] {
            if c > 0.5 {
                len += 1;
            } else if len > 0 {
                runs += 1;
                total += len;
                len = 0;
            }
        }
        if len > 0 {
            runs += 1;
            total += len;
            len = 0;
        }
    }
    total as f32 / runs.max(1) as f32
}

/// With `stroke_length` on, strokes where the direction field turns fast
/// (right half, 0.5 rad/pixel) are about half as long (`shorten` = 2) as where it is calm
/// (left half); with it off both halves have the same stroke length.
#[test]
fn strokes_shorten_where_the_field_turns() {
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let (w, h) = (256usize, 256usize);
    let turn: Vec<f32> = (0..w * h)
        .map(|i| if i % w < w / 2 { 0.0 } else { 0.5 })
        .collect();
    let inputs = npr_hatching::HatchInputs::constant(w as u32, h as u32, 0.75, 0.0)
        .unwrap()
        .with_turn(turn)
        .unwrap();
    for (length, lo, hi) in [
        (None, 0.8, 1.25),
        (Some(npr_hatching::StrokeLength::default()), 0.35, 0.7),
    ] {
        let params = HatchParams {
            mode: npr_hatching::BlendMode::Blended,
            stroke_length: length,
            ..Default::default()
        };
        let cov = CpuHatcher::new(&tam, &params)
            .unwrap()
            .hatch_coverage(&inputs)
            .unwrap();
        let (calm, busy) = (mean_run(&cov, w, 0, w / 2), mean_run(&cov, w, w / 2, w));
        eprintln!("{length:?}: calm runs {calm:.1} px, busy runs {busy:.1} px");
        let r = busy / calm;
        assert!(r >= lo && r <= hi, "{length:?}: ratio {r}");
    }
    let bad = HatchParams {
        stroke_length: Some(npr_hatching::StrokeLength {
            shorten: 0.5,
            ..Default::default()
        }),
        ..Default::default()
    };
    assert!(matches!(
        CpuHatcher::new(&tam, &bad),
        Err(npr_hatching::HatchError::InvalidParams { .. })
    ));
}

/// The largest change of any pixel's coverage between consecutive steps of a slide by
/// 0.1 pixel along (1, 0.3), at tone `tone` and θ = 0.4, over a 48×48 patch.
fn largest_step(h: &CpuHatcher, tone: f32) -> f32 {
    let mut worst = 0.0f32;
    for y in 0..48 {
        for x in 0..48 {
            let at = |d: f32| h.coverage(x as f32 + 0.5 + d, y as f32 + 0.5 + 0.3 * d, tone, 0.4);
            let mut last = at(0.0);
            for i in 1..=10 {
                let c = at(0.1 * i as f32);
                worst = worst.max((c - last).abs());
                last = c;
            }
        }
    }
    worst
}

/// Surface-anchored strokes slide with their surface by fractions of a texel from frame to
/// frame: the surface space reads the map filtered, so a slide of 0.1 pixel changes no
/// pixel by more than a fraction of a stroke's contrast, where the screen space's nearest
/// read (the paper's Eq. (1) indexing) flips pixels at stroke edges (whole pixels with the
/// pen, several times the filtered step with the soft pencil).
#[test]
fn surface_strokes_slide_without_snapping() {
    for style in [TamStyle::Pen, TamStyle::Pencil] {
        let params = |space| HatchParams {
            space,
            ..Default::default()
        };
        let surface = CpuHatcher::new(tam(style), &params(StrokeSpace::Surface)).unwrap();
        let screen = CpuHatcher::new(tam(style), &params(StrokeSpace::Screen)).unwrap();
        for tone in [0.2, 0.5, 0.8] {
            let (filtered, nearest) = (largest_step(&surface, tone), largest_step(&screen, tone));
            eprintln!("{style:?} tone {tone}: {filtered:.3} filtered, {nearest:.3} nearest");
            assert!(
                filtered <= 0.25 && nearest >= 3.0 * filtered,
                "{style:?} tone {tone}: largest step {filtered:.3} filtered, {nearest:.3} nearest"
            );
        }
    }
}
