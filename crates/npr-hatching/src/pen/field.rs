//! The per-pixel inputs of the vector hatching, sampled between pixel centres: the stroke
//! orientation θ (an axis, not a vector: θ and θ + π are one direction, so it is
//! interpolated on the doubled angle), the darkness level of each layer, and where
//! strokes may not go (off the object, or across a silhouette).

use crate::HatchInputs;

/// The stroke orientation, levels and cut map of one view.
pub(crate) struct Field {
    pub width: usize,
    pub height: usize,
    /// `(cos 2θ, sin 2θ)` per pixel (a zero vector off the object).
    doubled: Vec<[f32; 2]>,
    /// The darkness each pixel should get, `1 − tone`, quantized to the levels.
    pub darkness: Vec<f32>,
    /// Pixels a stroke may cross: on the object and not on a silhouette.
    pub open: Vec<bool>,
}

impl Field {
    /// The field of `inputs` over the pixels `mask` covers, with the pixels of `cuts`
    /// closed, and darkness quantized to `levels` steps.
    pub(crate) fn new(inputs: &HatchInputs, mask: &[bool], cuts: &[bool], levels: u32) -> Self {
        let (width, height) = (inputs.width() as usize, inputs.height() as usize);
        let levels = levels.max(1) as f32;
        let n = width * height;
        let on = |i: usize| mask.get(i).copied().unwrap_or(false);
        let doubled = (0..n)
            .map(|i| {
                if on(i) {
                    let t = 2.0 * inputs.theta()[i];
                    [t.cos(), t.sin()]
                } else {
                    [0.0, 0.0]
                }
            })
            .collect();
        let darkness = (0..n)
            .map(|i| {
                if on(i) {
                    ((1.0 - inputs.tone()[i]) * levels).round() / levels
                } else {
                    0.0
                }
            })
            .collect();
        let open = (0..n)
            .map(|i| on(i) && !cuts.get(i).copied().unwrap_or(false))
            .collect();
        Self {
            width,
            height,
            doubled,
            darkness,
            open,
        }
    }

    /// The pixel holding the point `(x, y)` (pixel units, y down), if inside.
    pub(crate) fn pixel(&self, p: [f32; 2]) -> Option<usize> {
        let (x, y) = (p[0].floor(), p[1].floor());
        if x < 0.0 || y < 0.0 || x >= self.width as f32 || y >= self.height as f32 {
            return None;
        }
        Some(y as usize * self.width + x as usize)
    }

    /// Whether a stroke may pass `p`.
    pub(crate) fn is_open(&self, p: [f32; 2]) -> bool {
        self.pixel(p).is_some_and(|i| self.open[i])
    }

    /// The darkness at `p` (0 outside).
    pub(crate) fn darkness_at(&self, p: [f32; 2]) -> f32 {
        self.pixel(p).map_or(0.0, |i| self.darkness[i])
    }

    /// The unit stroke direction at `p` in pixel units (y down), turned by `turn` (0 for
    /// the hatching, π/2 for the cross-hatching), oriented along `along`; `None` where the
    /// field vanishes. Bilinear on the doubled angle between the four pixel centres.
    pub(crate) fn direction(&self, p: [f32; 2], turn: f32, along: [f32; 2]) -> Option<[f32; 2]> {
        let (fx, fy) = (p[0] - 0.5, p[1] - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let mut sum = [0.0f32; 2];
        for (dx, dy, w) in [
            (0, 0, (1.0 - tx) * (1.0 - ty)),
            (1, 0, tx * (1.0 - ty)),
            (0, 1, (1.0 - tx) * ty),
            (1, 1, tx * ty),
        ] {
            let (x, y) = (x0 as i64 + dx, y0 as i64 + dy);
            if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
                continue;
            }
            let d = self.doubled[y as usize * self.width + x as usize];
            sum[0] += w * d[0];
            sum[1] += w * d[1];
        }
        let len = (sum[0] * sum[0] + sum[1] * sum[1]).sqrt();
        if len < 1e-3 {
            return None;
        }
        let theta = 0.5 * sum[1].atan2(sum[0]) + turn;
        // θ counter-clockwise from +x with y up: (cos θ, −sin θ) in the y-down grid.
        let v = [theta.cos(), -theta.sin()];
        Some(if v[0] * along[0] + v[1] * along[1] < 0.0 {
            [-v[0], -v[1]]
        } else {
            v
        })
    }
}
