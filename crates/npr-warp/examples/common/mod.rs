//! What the warping paper's figure examples share: the tile size and the compositing of
//! transparent frames over white.
// Each example uses part of this module.
#![allow(dead_code)]

/// An example's error.
pub type Error = Box<dyn std::error::Error>;

/// Side of a figure tile in pixels.
pub const TILE: u32 = 320;

/// Composites an image with transparent background over white.
pub fn on_white(img: &image::RgbaImage) -> image::RgbaImage {
    image::RgbaImage::from_fn(img.width(), img.height(), |x, y| {
        let p = img.get_pixel(x, y);
        let a = u32::from(p[3]);
        let c = |i: usize| ((u32::from(p[i]) * a + 255 * (255 - a)) / 255) as u8;
        image::Rgba([c(0), c(1), c(2), 255])
    })
}
