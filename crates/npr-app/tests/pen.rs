//! `npr render --svg`: the hatching of a real model as an SVG for pen plotters, with its
//! layers, inside the page's margins, the same bytes whatever the file's name, and bad
//! input refused with one line and no file.
#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::{npr, out_dir, root};

use npr_gpu::testing::context_or_skip;

/// Every `points="..."` list of the layer labelled `label`, as numbers.
fn layer_points(svg: &str, label: &str) -> Vec<Vec<[f32; 2]>> {
    let Some(start) = svg.find(&format!("inkscape:label=\"{label}\"")) else {
        return Vec::new();
    };
    let body = &svg[start..svg[start..].find("</g>").map_or(svg.len(), |e| start + e)];
    body.split("points=\"")
        .skip(1)
        .map(|p| {
            p.split('"')
                .next()
                .unwrap()
                .split(' ')
                .map(|xy| {
                    let (x, y) = xy.split_once(',').unwrap();
                    [x.parse().unwrap(), y.parse().unwrap()]
                })
                .collect()
        })
        .collect()
}

#[test]
fn the_bunny_as_pen_strokes_on_a4() {
    if context_or_skip("the_bunny_as_pen_strokes_on_a4").is_none() {
        return;
    }
    let dir = out_dir("bunny");
    let bunny = root().join("fixtures/meshes/stanford-bunny.obj");
    let mut files = Vec::new();
    for name in ["bunny.svg", "another name.svg"] {
        let svg = dir.join(name);
        let o = npr(&[
            "render",
            bunny.to_str().unwrap(),
            "--effect",
            "hatching-pen",
            "--size",
            "320x240",
            "--svg",
            svg.to_str().unwrap(),
            "--page",
            "a4",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        files.push(std::fs::read_to_string(&svg).unwrap());
    }
    assert_eq!(files[0], files[1], "the bytes depend on the file's name");
    let svg = &files[0];
    assert!(svg.starts_with("<?xml"));
    assert!(
        svg.contains("width=\"297mm\" height=\"210mm\""),
        "landscape A4"
    );
    let hatching = layer_points(svg, "1 hatching");
    let outlines = layer_points(svg, "3 outlines");
    eprintln!(
        "{} hatching strokes, {} cross-hatching, {} outlines",
        hatching.len(),
        layer_points(svg, "2 cross-hatching").len(),
        outlines.len()
    );
    assert!(hatching.len() > 100, "{} hatching strokes", hatching.len());
    assert!(outlines.len() > 10, "{} outlines", outlines.len());
    // Everything inside the 10 mm margins.
    for l in hatching.iter().chain(&outlines) {
        for p in l {
            assert!(
                (9.99..=287.01).contains(&p[0]) && (9.99..=200.01).contains(&p[1]),
                "{p:?} outside the margins"
            );
        }
    }
    // No PNG: the SVG replaces it.
    assert!(!dir.join("out.png").exists());
}

#[test]
fn bad_svg_requests_get_one_line_and_no_file() {
    let dir = out_dir("bad");
    let bunny = root().join("fixtures/meshes/stanford-bunny.obj");
    let svg = dir.join("x.svg");
    let base = [
        "render",
        bunny.to_str().unwrap(),
        "--size",
        "64x48",
        "--svg",
        svg.to_str().unwrap(),
    ];
    for (extra, says) in [
        (&["--effect", "phong"][..], "--svg draws the hatching"),
        (
            &["--effect", "hatching-pen", "--page", "15x15mm"][..],
            "margins",
        ),
        (&["--effect", "hatching-pen", "--pen-mm", "0"][..], "pen"),
        (&["--effect", "hatching-pen", "--pen-mm=-0.3"][..], "pen"),
        (&["--effect", "hatching-pen", "--page", "a9"][..], "a9"),
    ] {
        let o = npr(&[&base[..], extra].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} succeeded");
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{extra:?}: {err}");
        assert!(
            lines[0].starts_with("npr: error:") && lines[0].contains(says),
            "{extra:?}: {err}"
        );
        assert!(!svg.exists(), "{extra:?} wrote a file");
    }
}

/// A segment's two ends.
type Segment = ([f32; 2], [f32; 2]);

/// Whether segments `a`–`b` and `c`–`d` cross properly (each one's ends on both sides of
/// the other).
fn cross(a: [f32; 2], b: [f32; 2], c: [f32; 2], d: [f32; 2]) -> bool {
    let side = |p: [f32; 2], q: [f32; 2], r: [f32; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0
}

#[test]
fn no_stroke_crosses_a_visible_silhouette_of_a_real_model() {
    use npr_app::engine::Renderer;
    use npr_app::model::Model;
    use npr_app::preset::{Effect, Preset};
    use npr_app::view::View;
    let Some(ctx) = context_or_skip("no_stroke_crosses_a_visible_silhouette_of_a_real_model")
    else {
        return;
    };
    let size = (480, 360);
    for (mesh, turn) in [("spot.obj", 40.0), ("stanford-bunny.obj", 200.0)] {
        let model = Model::load(&root().join("fixtures/meshes").join(mesh)).unwrap();
        let mut preset = Preset {
            effect: Effect::HatchingPen,
            ..Preset::default()
        };
        (preset.output.width, preset.output.height) = size;
        let view = View::new(&preset, &model.framing, size, turn);
        let mut r = Renderer::new(ctx, model, size).unwrap();
        r.render(&ctx.device, &ctx.queue, &preset, &view).unwrap();
        let d = r
            .pen_drawing(&ctx.device, &ctx.queue, &preset, &view, (1.5, 0.4))
            .unwrap()
            .unwrap();
        assert!(
            d.silhouettes > 20,
            "{mesh}: {} silhouette lines",
            d.silhouettes
        );
        // Silhouette segments bucketed by 8-pixel cells.
        let cell = |p: [f32; 2]| ((p[0] / 8.0) as i32, (p[1] / 8.0) as i32);
        let mut grid: std::collections::HashMap<(i32, i32), Vec<Segment>> = Default::default();
        for l in &d.outlines[..d.silhouettes] {
            for w in l.windows(2) {
                let (lo, hi) = (cell(w[0]), cell(w[1]));
                for y in lo.1.min(hi.1) - 1..=lo.1.max(hi.1) + 1 {
                    for x in lo.0.min(hi.0) - 1..=lo.0.max(hi.0) + 1 {
                        grid.entry((x, y)).or_default().push((w[0], w[1]));
                    }
                }
            }
        }
        let mut segments = 0;
        for l in d.hatching.iter().chain(&d.cross_hatching) {
            for w in l.windows(2) {
                segments += 1;
                for &(c, e) in grid.get(&cell(w[0])).into_iter().flatten() {
                    assert!(
                        !cross(w[0], w[1], c, e),
                        "{mesh}: a stroke crosses a silhouette at {:?}",
                        w[0]
                    );
                }
            }
        }
        assert!(segments > 5000, "{mesh}: {segments} stroke segments");
    }
}
