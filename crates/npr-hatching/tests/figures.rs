//! The figure examples' shared code (`examples/common/mod.rs`, included here as a module)
//! renders: the CAD-parts directions figure of the gallery.
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../examples/common/mod.rs"]
mod common;

use npr_hatching::{TamParams, TonalArtMap};

/// Both tiles have ink on the object, and the default field's strokes differ from the
/// paper's rule.
#[test]
fn cad_directions_figure_renders() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("cad_directions_figure_renders") else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("npr-cad-figure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pen = TonalArtMap::generate(&TamParams::pen()).unwrap();
    common::cad_directions(ctx, &dir, &pen).unwrap();
    let tile = |name: &str| image::open(dir.join(name)).unwrap().to_luma8();
    let (raw, smooth) = (
        tile("hatching-directions-cad-raw.png"),
        tile("hatching-directions-cad-smooth.png"),
    );
    assert!(dir.join("hatching-directions-cad.png").is_file());
    let dark = |im: &image::GrayImage| im.pixels().filter(|p| p.0[0] < 128).count();
    assert!(dark(&raw) > 2000 && dark(&smooth) > 2000);
    let differ = raw
        .pixels()
        .zip(smooth.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 2000, "{differ} pixels differ");
    eprintln!("cad figure in {}", dir.display());
}
