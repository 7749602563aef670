//! Fixture images owned by this crate (toon ramps), generated from code. `cargo xtask
//! fixtures` writes them to `fixtures/`; a test checks the committed files match.

use crate::toon_ramp;

/// `(file name, image)` for every fixture of this crate.
pub fn all() -> Vec<(&'static str, image::RgbaImage)> {
    let ramp = |texels: Vec<[u8; 4]>| {
        let w = texels.len() as u32;
        image::RgbaImage::from_raw(w, 1, texels.into_iter().flatten().collect()).unwrap_or_default()
    };
    vec![
        ("ramp-toon3.png", ramp(crate::default_ramp())),
        (
            "ramp-toon4-warm.png",
            ramp(toon_ramp(
                256,
                &[
                    [70, 40, 40, 255],
                    [150, 100, 80, 255],
                    [220, 180, 140, 255],
                    [255, 245, 225, 255],
                ],
            )),
        ),
        (
            "ramp-toon2.png",
            ramp(toon_ramp(
                256,
                &[[110, 110, 120, 255], [255, 255, 255, 255]],
            )),
        ),
    ]
}
