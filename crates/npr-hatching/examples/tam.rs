//! The tonal art maps of the hatching paper (Kim & Lee 2008), pen and pencil, light to
//! dark: `hatching-tam-{pen,pencil}.png`.
//!
//! `cargo run --release -p npr-hatching --example tam -- [OUT_DIR]` (default
//! `target/figures`, or `NPR_FIGURES_DIR`).

use npr_gpu::figures::{out_dir, save, sheet};
use npr_hatching::{TamParams, TonalArtMap};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = out_dir()?;
    for params in [TamParams::pen(), TamParams::pencil()] {
        let tam = TonalArtMap::generate(&params)?;
        let tiles: Vec<image::RgbaImage> = (0..tam.tones())
            .filter_map(|i| tam.slice_image(i))
            .map(|g| image::DynamicImage::ImageLuma8(g).to_rgba8())
            .collect();
        let path = dir.join(format!("hatching-tam-{}.png", tam.style().name()));
        save(&sheet(&tiles, tam.tones()), &path)?;
    }
    Ok(())
}
