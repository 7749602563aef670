//! The sRGB transfer function, as `Rgba8UnormSrgb` targets apply it: the CPU references
//! of the technique crates use it to produce the bytes a GPU pass writes.

/// sRGB encoding of one linear channel (the transfer function of `Rgba8UnormSrgb`).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding of one channel.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
