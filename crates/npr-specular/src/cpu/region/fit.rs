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
            fit_scale: 1.0,
        };
        (half.min_element() > 0.0 && fp.offset.is_finite() && half.is_finite()).then_some(fp)
    }
}

/// Bins of [`best_overlap_scale`] over the moment ellipse's normalised radius `[0, 1]`.
const OVERLAP_BINS: usize = 128;

/// The scale `s ≤ 1` of the moment ellipse `fp` (about its centre) that fits the region
/// (beyond the paper), from the region's pieces `items` (faces clipped to it, or whole
/// patches, each spread along the radius by its own second moments): the ellipse of the
/// region's own area where at least half of that ellipse lies in the region, else the
/// scale of the largest intersection over union. A region that is an ellipse keeps 1.
pub(super) fn best_overlap_scale<'a>(
    fp: &Footprint,
    items: impl Iterator<Item = &'a Moments>,
) -> f32 {
    let h = fp.half_extent.as_dvec2();
    if h.min_element().is_nan() || h.min_element() <= 0.0 {
        return 1.0;
    }
    let (sn, cs) = f64::from(fp.rotate_rad).sin_cos();
    let centre = fp.offset.as_dvec2();
    let mut bins = [0f64; OVERLAP_BINS];
    let mut total = 0.0;
    let n = OVERLAP_BINS as f64;
    for m in items.filter(|m| m.area > 0.0) {
        let c = glam::DVec2::new(m.first[0] / m.area, m.first[1] / m.area);
        let d = c - centre;
        let (u, v) = (d.x * cs + d.y * sn, d.y * cs - d.x * sn);
        let q = glam::DVec2::new(u / h.x, v / h.y);
        let r = q.length();
        total += m.area;
        // The piece's own extent along the radius, from its second moments (a uniform
        // spread of the same variance): a boundary face's centroid lies inside the
        // boundary by about half its width, which would read as spill.
        let g = q.normalize_or_zero() / h;
        let g = glam::DVec2::new(g.x * cs - g.y * sn, g.x * sn + g.y * cs);
        let cxx = m.second[0] / m.area - c.x * c.x;
        let cxy = m.second[1] / m.area - c.x * c.y;
        let cyy = m.second[2] / m.area - c.y * c.y;
        let var = (g.x * g.x * cxx + 2.0 * g.x * g.y * cxy + g.y * g.y * cyy).max(0.0);
        let half = 3f64.sqrt() * var.sqrt();
        let (lo, hi) = ((r - half) * n, (r + half) * n);
        if (hi - lo).is_nan() || hi - lo <= 1e-9 {
            if r < 1.0 {
                bins[((r * n) as usize).min(OVERLAP_BINS - 1)] += m.area;
            }
            continue;
        }
        let density = m.area / (hi - lo);
        let first = if lo < 0.0 { 0 } else { lo as usize };
        for (k, bin) in bins.iter_mut().enumerate().skip(first) {
            let (a, b) = (k as f64, k as f64 + 1.0);
            if a >= hi {
                break;
            }
            // What falls below radius 0 lies on the other side of the centre, at −r.
            let folded = (b.min(-lo) - a).max(0.0);
            *bin += density * ((b.min(hi) - a.max(lo)).max(0.0) + folded);
        }
    }
    // A piece of a split region is fitted against its own share of the area (the
    // other pieces' faces inside its ellipse still count as region).
    let total = f64::from(fp.region_area).min(total);
    let ellipse = std::f64::consts::PI * h.x * h.y;
    if total.is_nan() || total <= 0.0 || !ellipse.is_finite() {
        return 1.0;
    }
    // The ellipse of the region's own area, where most of it lies in the region: of all
    // shapes with the same second moments the ellipse has the largest area, so a region
    // that is not an ellipse has a moment ellipse larger than itself, which spills past
    // it by the difference. Shrunk to the region's area it keeps the moments' shape and
    // axes.
    let s_area = (total / ellipse).sqrt().min(1.0);
    let inside_within = |s: f64| {
        let x = s * OVERLAP_BINS as f64;
        let full = (x as usize).min(OVERLAP_BINS);
        let part = bins.get(full).map_or(0.0, |b| b * (x - full as f64));
        bins[..full].iter().sum::<f64>() + part
    };
    if inside_within(s_area) >= 0.25 * total {
        return s_area as f32;
    }
    // Else (a ring, a crescent: its area lies away from its centroid) the scale of the
    // largest intersection over union, at each bin's outer edge (the last is the moment
    // ellipse itself), which reaches the band where the ellipse of its area would fall
    // into the hole.
    let mut best = (f64::NEG_INFINITY, 1.0);
    let mut inside = 0.0;
    for (k, a) in bins.iter().enumerate() {
        inside += a;
        let s = (k + 1) as f64 / OVERLAP_BINS as f64;
        let inside = inside.min(total);
        let iou = inside / (total + ellipse * s * s - inside);
        if iou > best.0 {
            best = (iou, s);
        }
    }
    best.1 as f32
}

impl Footprint {
    /// The same ellipse scaled by `s` about its centre.
    pub(crate) fn scaled(self, s: f32) -> Footprint {
        if s > 0.0 && s < 1.0 {
            Footprint {
                half_extent: self.half_extent * s,
                fit_scale: self.fit_scale * s,
                ..self
            }
        } else {
            self
        }
    }
}
