//! A long bent region split into pieces along its length, each fitted to its own
//! faces ([`RegionGrower::pieces`]).

use super::fit::Moments;
use super::grow::RegionGrower;
use super::{Footprint, MAX_PIECES, SPLIT_AREA_RATIO, SPLIT_ELONGATION};
use glam::Vec2;

/// Whether a region fitted by `whole` is a long bent band to split ([`split_bent`]).
pub(super) fn needs_split(whole: &Footprint) -> bool {
    let h = whole.half_extent;
    let ellipse = std::f32::consts::PI * h.x * h.y;
    let elongation = h.max_element() / h.min_element().max(f32::MIN_POSITIVE);
    ellipse > SPLIT_AREA_RATIO * whole.region_area && elongation >= SPLIT_ELONGATION
}

/// Appends to `out` the pieces of the region of seed `k` fitted by `whole` (see
/// [`RegionGrower::pieces`]), from the moments of its faces and whole patches (cut
/// between them: a patch is a few faces); nothing when it needs none.
///
/// `along` is scratch: the faces' and patches' positions along the axis with their index
/// in `taken` (sorted as keys, not as moments: a 1.1M-face band holds tens of thousands).
pub(super) fn split_bent(
    whole: &Footprint,
    k: u32,
    taken: &[(u32, u32, Moments)],
    along: &mut Vec<(f32, u32)>,
    out: &mut Vec<Footprint>,
) {
    if !needs_split(whole) {
        return;
    }
    let h = whole.half_extent;
    let elongation = h.max_element() / h.min_element().max(f32::MIN_POSITIVE);
    let count = ((elongation / 1.5).round() as usize).clamp(2, MAX_PIECES);
    let (s, c) = whole.rotate_rad.sin_cos();
    let axis = if h.x >= h.y {
        Vec2::new(c, s)
    } else {
        Vec2::new(-s, c)
    };
    along.clear();
    along.extend(
        taken
            .iter()
            .enumerate()
            .filter(|(_, (seed, _, m))| *seed == k && m.area > 0.0)
            .map(|(i, (_, _, m))| {
                let centroid =
                    Vec2::new((m.first[0] / m.area) as f32, (m.first[1] / m.area) as f32);
                ((centroid - whole.offset).dot(axis), i as u32)
            }),
    );
    // By position, then by index: the order a stable sort of the moments would give.
    along.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let total: f64 = along.iter().map(|&(_, i)| taken[i as usize].2.area).sum();
    let start = out.len();
    let mut piece = Moments::default();
    let mut cut = 1;
    // The area of the band up to and with this face: a piece closes where it reaches the
    // next `cut / count` of the whole (the piece's own area would make each piece longer
    // than the last).
    let mut done = 0.0;
    for &(_, i) in along.iter() {
        let m = &taken[i as usize].2;
        piece.add(m);
        done += m.area;
        // An item that reaches two shares (a whole patch in a small band) closes both;
        // the empty piece has no footprint and is left out.
        while done >= total * cut as f64 / count as f64 - 1e-12 * total && cut < count {
            out.extend(piece.footprint());
            piece = Moments::default();
            cut += 1;
        }
    }
    out.extend(piece.footprint());
    for p in &mut out[start..] {
        p.normal_cone_cos = whole.normal_cone_cos;
    }
    if out.len() - start < 2 {
        out.truncate(start);
    }
}

impl RegionGrower {
    /// The pieces seed `k`'s region was split into by the last [`RegionGrower::grow_all`]
    /// (beyond the paper): empty for a region its moment ellipse fits; for a long bent
    /// band (ellipse [`SPLIT_AREA_RATIO`] × larger than the region, [`SPLIT_ELONGATION`]
    /// × longer than wide), up to [`MAX_PIECES`] footprints of equal area along its
    /// length, each fitted to its own faces, in the same frame as the whole's, so that
    /// several projectors follow the band where one ellipse cannot.
    pub fn pieces(&self, k: usize) -> &[Footprint] {
        self.piece_ranges
            .get(k)
            .and_then(|r| self.pieces.get(r.clone()))
            .unwrap_or(&[])
    }
}
