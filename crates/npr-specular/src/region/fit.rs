//! Area moments of a region on the projector's plane, and the ellipse with the same
//! moments: the footprint the parent module's docs describe.

use super::Footprint;
use glam::Vec2;

/// Area moments of a planar region (area, first and second moments about the origin).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Moments {
    pub(super) area: f64,
    pub(super) first: [f64; 2],
    /// (xx, xy, yy)
    pub(super) second: [f64; 3],
}

impl Moments {
    /// Adds another region's moments (disjoint regions).
    pub(super) fn add(&mut self, other: &Moments) {
        self.area += other.area;
        for (a, b) in self.first.iter_mut().zip(&other.first) {
            *a += b;
        }
        for (a, b) in self.second.iter_mut().zip(&other.second) {
            *a += b;
        }
    }

    /// Adds a triangle (counter-clockwise seen from the normal for positive area).
    pub(super) fn add_triangle(&mut self, a: Vec2, b: Vec2, c: Vec2) {
        let (a, b, c) = (a.as_dvec2(), b.as_dvec2(), c.as_dvec2());
        let area = 0.5 * (b - a).perp_dot(c - a);
        let s = a + b + c;
        self.area += area;
        self.first[0] += area * s.x / 3.0;
        self.first[1] += area * s.y / 3.0;
        // ∫ x xᵀ dA = A/12 · (Σ vᵢvᵢᵀ + s sᵀ) over a triangle.
        let k = area / 12.0;
        self.second[0] += k * (a.x * a.x + b.x * b.x + c.x * c.x + s.x * s.x);
        self.second[1] += k * (a.x * a.y + b.x * b.y + c.x * c.y + s.x * s.y);
        self.second[2] += k * (a.y * a.y + b.y * b.y + c.y * c.y + s.y * s.y);
    }

    /// Adds the part of the triangle where the linear interpolant of the values `≥ 0`.
    pub(super) fn add_clipped(&mut self, tri: [(Vec2, f32); 3]) {
        let mut poly: [Vec2; 4] = [Vec2::ZERO; 4];
        let mut len = 0;
        for k in 0..3 {
            let (p, dp) = tri[k];
            let (q, dq) = tri[(k + 1) % 3];
            if dp >= 0.0 {
                poly[len] = p;
                len += 1;
            }
            if (dp >= 0.0) != (dq >= 0.0) && len < 4 {
                let t = dp / (dp - dq);
                poly[len] = p + (q - p) * t;
                len += 1;
            }
        }
        for k in 1..len.saturating_sub(1) {
            self.add_triangle(poly[0], poly[k], poly[k + 1]);
        }
    }

    /// The ellipse with these moments (see the module docs); `None` for an empty or
    /// degenerate region.
    pub(super) fn footprint(&self) -> Option<Footprint> {
        if self.area.is_nan() || self.area <= 1e-20 {
            return None;
        }
        let mx = self.first[0] / self.area;
        let my = self.first[1] / self.area;
        let cxx = (self.second[0] / self.area - mx * mx).max(0.0);
        let cxy = self.second[1] / self.area - mx * my;
        let cyy = (self.second[2] / self.area - my * my).max(0.0);
        // The moments' axis nearest to e_max, within ±45°.
        let mut theta = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        let quarter = std::f64::consts::FRAC_PI_2;
        if theta > quarter / 2.0 {
            theta -= quarter;
        } else if theta < -quarter / 2.0 {
            theta += quarter;
        }
        // Turn only for a clearly anisotropic region: near-isotropic moments have unstable
        // axes, and a turning texture would flicker.
        let spread = ((cxx - cyy).powi(2) + 4.0 * cxy * cxy).sqrt() / (cxx + cyy).max(1e-30);
        let t = ((spread - 0.05) / 0.15).clamp(0.0, 1.0);
        let theta = theta * t * t * (3.0 - 2.0 * t);
        let (s, c) = theta.sin_cos();
        let var_u = cxx * c * c + 2.0 * cxy * s * c + cyy * s * s;
        let var_v = cxx * s * s - 2.0 * cxy * s * c + cyy * c * c;
        let offset = glam::DVec2::new(mx, my);
        let half = Vec2::new(
            (2.0 * var_u.max(0.0).sqrt()) as f32,
            (2.0 * var_v.max(0.0).sqrt()) as f32,
        );
        let fp = Footprint {
            half_extent: half,
            offset: offset.as_vec2(),
            rotate_rad: theta as f32,
            region_area: self.area as f32,
            normal_cone_cos: -1.0,
        };
        (half.min_element() > 0.0 && fp.offset.is_finite() && half.is_finite()).then_some(fp)
    }
}
