//! CPU twins of the shading functions in `shaders/common.wgsl` and `base_shading.wgsl`,
//! used by tests to check what the GPU draws.

use glam::Vec3;

/// Blinn-Phong, Lee & Choi Eq. (2)–(3): `k_a·d + d·c·(N·L) + s·c·k_s·(N·H)^n`, with
/// `H = (L+V)/|L+V|` and the specular term zero where `N·L ≤ 0`. Mirrors WGSL
/// `blinn_phong`. `n`, `l`, `v` unit vectors.
#[allow(clippy::too_many_arguments)]
pub fn blinn_phong(
    n: Vec3,
    l: Vec3,
    v: Vec3,
    diffuse: Vec3,
    k_s: f32,
    specular: Vec3,
    exponent: f32,
    light_color: Vec3,
    ambient: Vec3,
) -> Vec3 {
    let n_dot_l = n.dot(l).max(0.0);
    let spec = if n_dot_l > 0.0 {
        k_s * n.dot((l + v).normalize_or_zero()).max(0.0).powf(exponent)
    } else {
        0.0
    };
    diffuse * ambient + diffuse * light_color * n_dot_l + specular * light_color * spec
}

pub use crate::color::{linear_to_srgb, srgb_to_linear};

/// A linear colour as the 8-bit sRGB bytes an `Rgba8UnormSrgb` target stores.
pub fn to_srgb8(c: Vec3) -> [u8; 3] {
    let q = |x: f32| (linear_to_srgb(x) * 255.0).round() as u8;
    [q(c.x), q(c.y), q(c.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for i in 0..=255u8 {
            let c = f32::from(i) / 255.0;
            let back = linear_to_srgb(srgb_to_linear(c));
            assert!((back - c).abs() < 1e-5, "{i}");
        }
    }

    #[test]
    fn highlight_peaks_where_n_equals_h() {
        let l = Vec3::new(1.0, 0.0, 1.0).normalize();
        let v = Vec3::new(-1.0, 0.0, 1.0).normalize();
        let h = (l + v).normalize();
        let shade = |n: Vec3| {
            blinn_phong(
                n,
                l,
                v,
                Vec3::ZERO,
                1.0,
                Vec3::ONE,
                50.0,
                Vec3::ONE,
                Vec3::ZERO,
            )
            .x
        };
        assert!((shade(h) - 1.0).abs() < 1e-5, "{}", shade(h));
        assert!(shade(Vec3::new(0.2, 0.0, 1.0).normalize()) < shade(h));
        assert_eq!(shade(-l), 0.0);
    }
}
