//! The pen-plotter hatching on analytic inputs: spacing by tone, strokes along θ, tone
//! after rasterising the strokes, no stroke across a gap in the object, byte-identical SVG,
//! its layers, and the bad inputs.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use npr_hatching::HatchInputs;
use npr_hatching::pen::{Page, PenDrawing, PenSettings, Polyline, to_svg, trace};

fn inputs(
    w: u32,
    h: u32,
    tone: impl Fn(u32, u32) -> f32,
    theta: impl Fn(u32, u32) -> f32,
) -> HatchInputs {
    let (mut t, mut a) = (Vec::new(), Vec::new());
    for y in 0..h {
        for x in 0..w {
            t.push(tone(x, y));
            a.push(theta(x, y));
        }
    }
    HatchInputs::new(w, h, &t, &a).unwrap()
}

fn settings(pen_px: f32) -> PenSettings {
    PenSettings {
        min_length_px: 4.0,
        ..PenSettings::for_pen(pen_px, 1.0)
    }
}

/// Strokes crossing the vertical line `x`.
fn crossings(lines: &[Polyline], x: f32) -> Vec<f32> {
    let mut ys = Vec::new();
    for l in lines {
        for w in l.windows(2) {
            let (a, b) = (w[0], w[1]);
            if (a[0] - x) * (b[0] - x) < 0.0 {
                let t = (x - a[0]) / (b[0] - a[0]);
                ys.push(a[1] + t * (b[1] - a[1]));
            }
        }
    }
    ys.sort_by(f32::total_cmp);
    ys
}

#[test]
fn spacing_follows_the_tone_within_20_percent() {
    let (w, h) = (240, 240);
    for tone in [0.875, 0.75, 0.625, 0.5] {
        let input = inputs(w, h, |_, _| tone, |_, _| 0.0);
        let mask = vec![true; (w * h) as usize];
        let s = settings(1.5);
        let d = trace(&input, &mask, None, &s).unwrap();
        let target = s.pen_px / (1.0 - tone);
        for x in [60.37, 120.37, 180.37] {
            let ys = crossings(&d.hatching, x);
            let gaps: Vec<f32> = ys.windows(2).map(|p| p[1] - p[0]).collect();
            let mean = gaps.iter().sum::<f32>() / gaps.len() as f32;
            eprintln!("tone {tone}: spacing {mean:.2} px against {target:.2}");
            assert!(
                (mean / target - 1.0).abs() <= 0.2,
                "tone {tone} at x {x}: spacing {mean} px, target {target}"
            );
        }
        assert!(
            d.cross_hatching.is_empty(),
            "no cross-hatching at tone {tone}"
        );
    }
}

#[test]
fn strokes_run_along_theta_within_5_degrees() {
    let (w, h) = (200, 160);
    let theta = |x: u32, y: u32| 0.2 + 0.004 * x as f32 + 0.002 * y as f32;
    let input = inputs(w, h, |_, _| 0.4, theta);
    let mask = vec![true; (w * h) as usize];
    let d = trace(&input, &mask, None, &settings(1.5)).unwrap();
    let (mut worst, mut n) = (0.0f32, 0);
    for l in &d.hatching {
        for seg in l.windows(2).step_by(7) {
            let (a, b) = (seg[0], seg[1]);
            let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            let expected = theta(m[0] as u32, m[1] as u32);
            // y down on screen: a stroke at θ runs along (cos θ, −sin θ).
            let got = (-(b[1] - a[1])).atan2(b[0] - a[0]);
            let mut diff = (got - expected).rem_euclid(std::f32::consts::PI);
            diff = diff.min(std::f32::consts::PI - diff);
            worst = worst.max(diff.to_degrees());
            n += 1;
        }
    }
    assert!(n > 200, "only {n} samples");
    assert!(worst <= 5.0, "a stroke turns {worst}° off θ");
}

/// Ink per pixel of a drawing's strokes of width `pen_px`, 4 × 4 samples per pixel.
fn ink(d: &PenDrawing, pen_px: f32) -> Vec<f32> {
    let (w, h) = (d.size.0 as usize, d.size.1 as usize);
    let sub = 4usize;
    let mut hit = vec![false; w * h * sub * sub];
    let r = 0.5 * pen_px;
    for l in d.hatching.iter().chain(&d.cross_hatching) {
        for seg in l.windows(2) {
            let (a, b) = (seg[0], seg[1]);
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            let steps = (len * 8.0).ceil().max(1.0) as usize;
            for k in 0..=steps {
                let t = k as f32 / steps as f32;
                let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                let (x0, x1) = (
                    ((p[0] - r) * sub as f32).floor() as i64,
                    ((p[0] + r) * sub as f32).ceil() as i64,
                );
                let (y0, y1) = (
                    ((p[1] - r) * sub as f32).floor() as i64,
                    ((p[1] + r) * sub as f32).ceil() as i64,
                );
                for sy in y0.max(0)..y1.min((h * sub) as i64) {
                    for sx in x0.max(0)..x1.min((w * sub) as i64) {
                        let c = [
                            (sx as f32 + 0.5) / sub as f32,
                            (sy as f32 + 0.5) / sub as f32,
                        ];
                        if (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) <= r * r {
                            hit[sy as usize * w * sub + sx as usize] = true;
                        }
                    }
                }
            }
        }
    }
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let mut n = 0;
            for sy in 0..sub {
                for sx in 0..sub {
                    n += usize::from(hit[(y * sub + sy) * w * sub + x * sub + sx]);
                }
            }
            n as f32 / (sub * sub) as f32
        })
        .collect()
}

#[test]
fn a_tone_ramp_is_drawn_tone_true() {
    // Tone from 0.95 on the left to 0.15 on the right: single hatching, then crossed.
    let (w, h) = (240, 120);
    let tone = |x: u32, _| 0.95 - 0.8 * x as f32 / (w - 1) as f32;
    let input = inputs(w, h, tone, |_, _| 0.6);
    let mask = vec![true; (w * h) as usize];
    let pen = 1.5;
    let d = trace(&input, &mask, None, &settings(pen)).unwrap();
    assert!(!d.cross_hatching.is_empty());
    let ink = ink(&d, pen);
    // Column means over the middle rows, blurred over 16 columns (about the widest
    // spacing), against the tone the strokes were spaced for.
    let col: Vec<f32> = (0..w as usize)
        .map(|x| (20..100).map(|y| ink[y * w as usize + x]).sum::<f32>() / 80.0)
        .collect();
    let mut err = 0.0;
    let mut n = 0;
    for x in 16..(w as usize - 16) {
        let blurred = col[x - 8..x + 8].iter().sum::<f32>() / 16.0;
        let target = 1.0 - (x - 8..x + 8).map(|c| tone(c as u32, 0)).sum::<f32>() / 16.0;
        err += (blurred - target).abs();
        n += 1;
    }
    let mean = err / n as f32;
    eprintln!("mean tone error {mean:.3}");
    assert!(mean <= 0.06, "mean tone error {mean}");
}

#[test]
fn no_stroke_crosses_a_gap_in_the_object() {
    let (w, h) = (160, 100);
    let input = inputs(w, h, |_, _| 0.3, |_, _| 0.1);
    let mask: Vec<bool> = (0..w * h).map(|i| !(78..82).contains(&(i % w))).collect();
    let d = trace(&input, &mask, None, &settings(1.5)).unwrap();
    assert!(!d.hatching.is_empty() && !d.cross_hatching.is_empty());
    for l in d.hatching.iter().chain(&d.cross_hatching) {
        let left = l.iter().any(|p| p[0] < 78.0);
        let right = l.iter().any(|p| p[0] >= 82.0);
        assert!(!(left && right), "a stroke crosses the gap");
        assert!(l.iter().all(|p| !(78.0..82.0).contains(&p[0])));
    }
}

fn drawing() -> PenDrawing {
    let (w, h) = (120, 90);
    let input = inputs(
        w,
        h,
        |x, y| 0.2 + 0.006 * (x + y) as f32,
        |x, _| 0.01 * x as f32,
    );
    let mask: Vec<bool> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 - 60.0, (i / w) as f32 - 45.0);
            x * x + y * y < 40.0 * 40.0
        })
        .collect();
    trace(&input, &mask, None, &settings(1.2)).unwrap()
}

#[test]
fn the_same_drawing_gives_the_same_bytes() {
    let page = Page::named("a4").unwrap();
    let a = to_svg(&drawing(), &page).unwrap();
    let b = to_svg(&drawing(), &page).unwrap();
    assert!(a.len() > 1000);
    assert_eq!(a, b);
}

#[test]
fn the_svg_has_three_inkscape_layers_of_strokes_only() {
    let svg = to_svg(&drawing(), &Page::named("a4").unwrap()).unwrap();
    // A landscape view on a landscape A4.
    assert!(svg.contains("width=\"297mm\" height=\"210mm\" viewBox=\"0 0 297 210\""));
    let mut depth = 0;
    let mut top = Vec::new();
    for tag in svg.split('<').skip(1) {
        let name: String = tag
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '/' || *c == '?')
            .collect();
        match name.as_str() {
            "?xml" => {}
            "svg" => depth += 1,
            "/svg" => depth -= 1,
            "g" => {
                assert_eq!(depth, 1, "a layer inside another element");
                top.push(tag.to_string());
                depth += 1;
            }
            "/g" => depth -= 1,
            "polyline" => assert_eq!(depth, 2, "a stroke outside a layer"),
            other => panic!("unexpected element <{other}>"),
        }
    }
    let labels: Vec<&str> = top
        .iter()
        .map(|g| {
            g.split("inkscape:label=\"")
                .nth(1)
                .and_then(|s| s.split('"').next())
                .unwrap()
        })
        .collect();
    assert_eq!(labels, ["1 hatching", "2 cross-hatching", "3 outlines"]);
    assert!(
        top.iter()
            .all(|g| g.contains("inkscape:groupmode=\"layer\"")
                && g.contains("fill=\"none\"")
                && g.contains("stroke-width=\"0.3\""))
    );
}

#[test]
fn bad_pages_pens_and_inputs_are_typed_errors() {
    let d = drawing();
    let small = Page {
        size_mm: (15.0, 40.0),
        ..Page::default()
    };
    assert!(
        to_svg(&d, &small)
            .unwrap_err()
            .to_string()
            .contains("margins")
    );
    for pen in [0.0, -0.3, f32::NAN] {
        let page = Page {
            pen_mm: pen,
            ..Page::default()
        };
        assert!(to_svg(&d, &page).unwrap_err().to_string().contains("pen"));
    }
    assert!(Page::named("a9").is_err());
    assert_eq!(Page::named("200x150mm").unwrap().size_mm, (150.0, 200.0));
    let input = inputs(8, 8, |_, _| 0.5, |_, _| 0.0);
    assert!(trace(&input, &[true; 10], None, &settings(1.0)).is_err());
    assert!(trace(&input, &[true; 64], None, &settings(0.0)).is_err());
}

/// Outline pieces whose ends lie within the pen's width are joined on the page, and what
/// is still under 1 mm after that is left out; hatching pieces are joined only within the
/// merge distance, and never dropped by length here.
#[test]
fn outline_specks_are_joined_or_left_out() {
    let page = Page::default();
    let size = (200, 100);
    let (mm_per_px, _) = page.fit(size);
    let px = |mm: f32| mm / mm_per_px;
    // Along y = 50: a 0.6 mm piece, a gap of 0.2 mm (under the 0.3 mm pen), another
    // 0.6 mm piece; far from them, a lone 0.5 mm speck.
    let a = vec![[10.0, 50.0], [10.0 + px(0.6), 50.0]];
    let b = vec![[10.0 + px(0.8), 50.0], [10.0 + px(1.4), 50.0]];
    let speck = vec![[150.0, 20.0], [150.0 + px(0.5), 20.0]];
    let drawing = PenDrawing {
        size,
        hatching: vec![a.clone(), b.clone(), speck.clone()],
        cross_hatching: Vec::new(),
        outlines: vec![a, b, speck],
        silhouettes: 3,
    };
    let [hatching, _, outlines] = npr_hatching::pen::page_layers(&drawing, &page);
    assert_eq!(
        hatching.len(),
        3,
        "hatching pieces stay apart: {hatching:?}"
    );
    assert_eq!(
        outlines.len(),
        1,
        "one joined outline, no speck: {outlines:?}"
    );
    let length: f32 = outlines[0]
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum();
    assert!(
        (length - 1.4).abs() < 0.01,
        "joined across the gap: {length} mm"
    );
    assert_eq!(
        npr_hatching::pen::plot_stats(&npr_hatching::pen::page_layers(&drawing, &page))
            .short_strokes,
        3,
        "the three hatching pieces under 1 mm are still counted"
    );
}
