//! `npr render --svg`: the hatching of a real model as an SVG for pen plotters, with its
//! layers, inside the page's margins, the same bytes whatever the file's name, and bad
//! input refused with one line and no file.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use npr_gpu::testing::context_or_skip;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("npr-app-pen-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn npr(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_npr"))
        .args(args)
        .output()
        .unwrap()
}

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
