//! §3.3.2 culling by representative normals and §3.3.3 blending per bin.
//!
//! Proxy face normals are binned by their polar angles into an `N × N` grid (the paper's
//! Fig. 5: θ = angle from +z in `[0, π]`, φ = azimuth in `(−π, π]`), and the index buffer
//! is sorted by bin so that each bin is one contiguous draw range (the paper's `N × N`
//! matrix of positions, §3.3.2). Per frame, each bin is classified against each reference
//! camera with its *representative normal* only: `N²` dot products instead of one per face.
//!
//! The paper tests the representative normal alone (and accepts "some error where the view
//! direction is exactly perpendicular"): [`Culling::Representative`], the cell's centre
//! direction against the direction to the camera. Ours ([`Culling::Conservative`]) also
//! keeps the half-angle of the cone that holds each bin's faces' normals and the
//! perspective spread of the object seen from the camera; a bin is culled only when *every*
//! face in it is back-facing, so culling never removes a visible face.

use crate::WarpError;
use glam::Vec3;
use npr_geometry::Mesh;
use std::ops::Range;

/// The largest accepted bins-per-axis N (`N² = 65,536` ranges).
pub const MAX_BINS_PER_AXIS: u32 = 256;

/// One bin of the `N × N` grid: its draw range and the cone of its face normals.
#[derive(Clone, Debug, PartialEq)]
pub struct Bin {
    /// Range in [`NormalBins::indices`] (a multiple of 3 wide; empty for an empty bin).
    pub indices: Range<u32>,
    /// The representative normal (§3.3.2): the unit area-weighted mean of the bin's face
    /// normals, or the cell's centre direction when the bin is empty.
    pub normal: Vec3,
    /// The largest angle between [`Bin::normal`] and a face normal of the bin, radians.
    pub half_angle_rad: f32,
    /// The paper's representative vector (§3.3.2, Fig. 5): the centre direction of the
    /// bin's `(θ, φ)` cell, whatever faces it holds.
    pub cell_normal: Vec3,
}

/// Proxy faces binned by normal (§3.3.2): the index buffer sorted by bin, one range per bin.
#[derive(Clone, Debug)]
pub struct NormalBins {
    /// Bins per polar axis, N (the grid has `N × N` bins).
    pub per_axis: u32,
    /// The proxy's triangle indices reordered so each bin's faces are contiguous.
    pub indices: Vec<u32>,
    /// `N × N` bins, row-major by θ then φ; bin `b` is drawn with instance index `b`.
    pub bins: Vec<Bin>,
    /// Object-space centre of the proxy's bounding sphere.
    pub centre: Vec3,
    /// Radius of that sphere (≥ the distance of every vertex from `centre`).
    pub radius: f32,
}

/// Whether the faces of a bin face a camera (§3.3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Facing {
    /// Every face of the bin is front-facing.
    Front,
    /// Every face of the bin is back-facing: the bin is culled for that camera.
    Back,
    /// Some faces may face the camera and some may not.
    Mixed,
}

impl Facing {
    /// `true` unless the bin is certainly back-facing.
    pub fn may_see(self) -> bool {
        self != Facing::Back
    }
}

/// The grid cell of a unit normal: `θ = acos(z)` in `[0, π]` split into N rows,
/// `φ = atan2(y, x)` in `(−π, π]` split into N columns (§3.3.2, Fig. 5). A zero or
/// non-finite normal goes to bin 0.
pub fn bin_of_normal(normal: Vec3, per_axis: u32) -> u32 {
    let n = per_axis.max(1);
    let Some(u) = normal.try_normalize() else {
        return 0;
    };
    let theta = u.z.clamp(-1.0, 1.0).acos();
    let phi = u.y.atan2(u.x);
    let row = ((theta / std::f32::consts::PI) * n as f32).floor() as i64;
    let col = (((phi + std::f32::consts::PI) / std::f32::consts::TAU) * n as f32).floor() as i64;
    let clamp = |v: i64| v.clamp(0, i64::from(n) - 1) as u32;
    clamp(row) * n + clamp(col)
}

/// The centre direction of grid cell `bin`.
pub fn cell_centre(bin: u32, per_axis: u32) -> Vec3 {
    let n = per_axis.max(1);
    let (row, col) = (bin / n, bin % n);
    let theta = (row as f32 + 0.5) / n as f32 * std::f32::consts::PI;
    let phi = (col as f32 + 0.5) / n as f32 * std::f32::consts::TAU - std::f32::consts::PI;
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

impl NormalBins {
    /// Bins the faces of `mesh` into an `N × N` grid of normal directions and sorts the
    /// index buffer by bin (§3.3.2). Degenerate faces (no normal) go to bin 0. Built once.
    ///
    /// # Errors
    /// [`WarpError::ZeroBins`] for N = 0, [`WarpError::TooManyBins`] above
    /// [`MAX_BINS_PER_AXIS`], [`WarpError::EmptyMesh`] / [`WarpError::InvalidMesh`] for a
    /// mesh without triangles or breaking its invariants.
    pub fn build(mesh: &Mesh, per_axis: u32) -> Result<Self, WarpError> {
        if per_axis == 0 {
            return Err(WarpError::ZeroBins(per_axis));
        }
        if per_axis > MAX_BINS_PER_AXIS {
            return Err(WarpError::TooManyBins(per_axis));
        }
        crate::proxy::validate(mesh)?;
        let count = (per_axis * per_axis) as usize;
        let faces: Vec<([u32; 3], Vec3)> = mesh
            .triangles()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                (t, (b - a).cross(c - a))
            })
            .collect();
        let face_bin: Vec<u32> = faces
            .iter()
            .map(|(_, n)| bin_of_normal(*n, per_axis))
            .collect();
        let mut order: Vec<usize> = (0..faces.len()).collect();
        order.sort_by_key(|&f| face_bin[f]);
        let mut indices = Vec::with_capacity(faces.len() * 3);
        let mut sums = vec![Vec3::ZERO; count];
        let mut starts = vec![u32::MAX; count];
        let mut ends = vec![0u32; count];
        for &f in &order {
            let b = face_bin[f] as usize;
            let at = indices.len() as u32;
            if starts[b] == u32::MAX {
                starts[b] = at;
            }
            indices.extend_from_slice(&faces[f].0);
            ends[b] = indices.len() as u32;
            sums[b] += faces[f].1;
        }
        let mut bins: Vec<Bin> = (0..count)
            .map(|b| {
                let range = if starts[b] == u32::MAX {
                    // An empty bin: an empty range at the next bin's start (keeps order).
                    0..0
                } else {
                    starts[b]..ends[b]
                };
                Bin {
                    indices: range,
                    normal: sums[b]
                        .try_normalize()
                        .unwrap_or_else(|| cell_centre(b as u32, per_axis)),
                    half_angle_rad: 0.0,
                    cell_normal: cell_centre(b as u32, per_axis),
                }
            })
            .collect();
        // Empty bins get an empty range placed where they sit in the sorted order.
        let mut cursor = 0u32;
        for bin in &mut bins {
            if bin.indices.is_empty() {
                bin.indices = cursor..cursor;
            } else {
                cursor = bin.indices.end;
            }
        }
        for (f, (_, n)) in faces.iter().enumerate() {
            let bin = &mut bins[face_bin[f] as usize];
            if let Some(u) = n.try_normalize() {
                let angle = u.dot(bin.normal).clamp(-1.0, 1.0).acos();
                bin.half_angle_rad = bin.half_angle_rad.max(angle);
            } else {
                // A degenerate face faces nothing; let its bin be drawn whenever any face
                // could be (a cone of π/2 keeps it out of neither test wrongly).
                bin.half_angle_rad = bin.half_angle_rad.max(std::f32::consts::FRAC_PI_2);
            }
        }
        let (centre, radius) = crate::proxy::bounding_sphere(&mesh.positions);
        Ok(Self {
            per_axis,
            indices,
            bins,
            centre,
            radius,
        })
    }

    /// Number of bins, `N²`.
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    /// `true` when there are no bins (never, after a successful [`NormalBins::build`]).
    pub fn is_empty(&self) -> bool {
        self.bins.is_empty()
    }

    /// The proxy mesh with its indices in bin order (upload this one).
    pub fn sorted_mesh(&self, proxy: &Mesh) -> Mesh {
        Mesh {
            indices: self.indices.clone(),
            ..proxy.clone()
        }
    }

    /// How bin `b` faces a camera at `eye_object` (object space), §3.3.2, conservatively:
    /// with `v` the unit direction from the bounding-sphere centre to the eye and
    /// `δ = half_angle + asin(radius / distance)` (the bin's normal cone plus the spread of
    /// view directions over the object), the bin is [`Facing::Back`] when
    /// `angle(normal, v) > 90° + δ`, [`Facing::Front`] when `angle(normal, v) < 90° − δ`.
    /// An eye inside the bounding sphere gives [`Facing::Mixed`] for every bin.
    pub fn facing(&self, b: usize, eye_object: Vec3) -> Facing {
        let Some(bin) = self.bins.get(b) else {
            return Facing::Back;
        };
        let to_eye = eye_object - self.centre;
        let d = to_eye.length();
        if d.is_nan() || d <= self.radius || !d.is_finite() {
            return Facing::Mixed;
        }
        let spread = (self.radius / d).clamp(0.0, 1.0).asin();
        let delta = bin.half_angle_rad + spread;
        let angle = bin.normal.dot(to_eye / d).clamp(-1.0, 1.0).acos();
        let right = std::f32::consts::FRAC_PI_2;
        if angle > right + delta {
            Facing::Back
        } else if angle < right - delta {
            Facing::Front
        } else {
            Facing::Mixed
        }
    }
}

impl NormalBins {
    /// How bin `b` faces a camera at `eye_object` by the paper's test (§3.3.2): the sign of
    /// the representative vector ([`Bin::cell_normal`]) against the direction from the
    /// bounding-sphere centre to the eye, nothing else. Never [`Facing::Mixed`], so faces
    /// near the silhouette may be culled while visible (the error the paper accepts).
    pub fn facing_representative(&self, b: usize, eye_object: Vec3) -> Facing {
        let Some(bin) = self.bins.get(b) else {
            return Facing::Back;
        };
        if bin.cell_normal.dot(eye_object - self.centre) > 0.0 {
            Facing::Front
        } else {
            Facing::Back
        }
    }

    /// How bin `b` faces a camera at `eye_object` under `culling`.
    pub fn facing_by(&self, b: usize, eye_object: Vec3, culling: Culling) -> Facing {
        match culling {
            Culling::Representative => self.facing_representative(b, eye_object),
            Culling::Conservative => self.facing(b, eye_object),
        }
    }
}

/// How a bin is tested against a reference camera (§3.3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Culling {
    /// The paper: the representative vector alone ([`NormalBins::facing_representative`]).
    Representative,
    /// Ours: culled only when every face of the bin is back-facing ([`NormalBins::facing`]).
    Conservative,
}

/// The shape of the §3.3.3 opacity ramp over the bins both references see.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ramp {
    /// The paper: reference 0's opacity falls linearly from 1 at the boundary where
    /// reference 1 stops seeing the bin to 0 at the boundary where reference 0 stops:
    /// `w0 = a0 / (a0 + a1)` with `a_i = asin(n · v_i)` the elevation of reference i's
    /// direction above the bin's plane (linear in angle along the arc between boundaries),
    /// `n` the representative vector.
    LinearAngle,
    /// Ours: `w0 = r0 / (r0 + r1)` with `r_i = max(cos(n, v_i) + sin δ_i, ε)`, `n` the bin's
    /// mean normal and `δ_i` its cone plus the object's spread (bins at a grazing angle
    /// keep a small weight).
    CosineRatio,
}

/// Which pass draws a range of bins (§3.3.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DrawKind {
    /// Seen (or ramped fully) by reference 0: one reference lookup.
    Single0,
    /// Seen (or ramped fully) by reference 1.
    Single1,
    /// Seen by both: both drawn and blended with the bin's opacity ramp.
    Blend,
}

/// One draw of the warp pass: a range of the sorted index buffer. Blended draws cover one
/// bin (its weight is read by instance index); single-reference draws merge runs of
/// adjacent bins.
#[derive(Clone, Debug, PartialEq)]
pub struct BinDraw {
    /// Which pass.
    pub kind: DrawKind,
    /// Range in the sorted index buffer.
    pub indices: Range<u32>,
    /// The instance index to draw with (the bin, for [`DrawKind::Blend`]).
    pub instance: u32,
}

/// How the warp decides and blends per bin; see [`plan`]. [`PlanSettings::paper`] is the
/// paper's §3.3.2–§3.3.3; `Default` is ours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanSettings {
    /// Width of the §3.3.3 opacity ramp, in `(0, 1]`: 1 blends across the whole overlap as
    /// the paper does; smaller values give bins whose ramp is beyond the band a single
    /// reference (cheaper, fragment-bound adapters), keeping the ramp around equal weight.
    pub blend_band: f32,
    /// The shape of the ramp (paper: [`Ramp::LinearAngle`]).
    pub ramp: Ramp,
    /// How bins are culled against the references (paper: [`Culling::Representative`]).
    pub culling: Culling,
    /// Draw bins that face the current camera but neither reference (disocclusion, §3.4)
    /// with the reference nearer in time (ours); off, they are culled as the paper's
    /// per-reference culling implies.
    pub draw_unseen: bool,
    /// Also weight each reference by its distance in time from the current frame
    /// (`1 − s` and `s`); with it the warp at a reference pose reproduces that reference.
    pub temporal_weight: bool,
    /// Skip bins back-facing for the current camera (they would be culled by the
    /// rasterizer anyway; skipping saves their vertex work).
    pub cull_current: bool,
    /// Apply §3.3.2 culling against the references; off, every bin is blended (for
    /// measuring what culling saves).
    pub cull_references: bool,
}

impl Default for PlanSettings {
    fn default() -> Self {
        Self {
            blend_band: 0.5,
            ramp: Ramp::CosineRatio,
            culling: Culling::Conservative,
            draw_unseen: true,
            temporal_weight: true,
            cull_current: true,
            cull_references: true,
        }
    }
}

impl PlanSettings {
    /// The paper's §3.3.2–§3.3.3: representative-vector culling, the linear ramp from
    /// boundary to boundary over the whole overlap, no time term, bins neither reference
    /// sees culled. (Bins back-facing for the current camera are skipped as the rasterizer
    /// would cull them anyway; that changes no pixel.)
    pub fn paper() -> Self {
        Self {
            blend_band: 1.0,
            ramp: Ramp::LinearAngle,
            culling: Culling::Representative,
            draw_unseen: false,
            temporal_weight: false,
            cull_current: true,
            cull_references: true,
        }
    }

    /// Checks the ranges: `blend_band` in `(0, 1]`.
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] naming the bad value.
    pub fn validate(&self) -> Result<(), WarpError> {
        if !(self.blend_band > 0.0 && self.blend_band <= 1.0) {
            return Err(WarpError::InvalidSetting(format!(
                "blend_band {} is outside (0, 1]",
                self.blend_band
            )));
        }
        Ok(())
    }
}

/// Per-frame decisions for every bin: draws and the per-bin opacity of reference 0 and 1.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BinPlan {
    /// The draws, in index-buffer order within each kind.
    pub draws: Vec<BinDraw>,
    /// Per bin `[w0, w1, 0, 0]`: opacity of reference 0 and 1 (w0 + w1 = 1 where drawn).
    pub weights: Vec<[f32; 4]>,
    /// Bins culled (back-facing for the current camera or for both references and the
    /// current camera).
    pub bins_culled: usize,
    /// Bins drawn with one reference.
    pub bins_single: usize,
    /// Bins drawn with both, blended.
    pub bins_blended: usize,
    /// Triangles submitted.
    pub triangles_drawn: usize,
}

/// Classifies every bin for a frame (§3.3.2–§3.3.3). Eyes are in the proxy's object space:
/// `eye_now` of the current camera, `eye_ref` of the two reference cameras (each in the
/// object space of its reference pose), `s ∈ [0, 1]` the current frame's position between
/// the references.
///
/// Opacity (§3.3.3): `a_i` per [`PlanSettings::ramp`] ([`Ramp`]: the paper's elevation
/// angle, or ours, `max(cos(normal, v_i) + sin δ_i, ε)`), and, with `temporal_weight`,
/// `r_0 = a_0 (1 − s)`, `r_1 = a_1 s` (else `r_i = a_i`): the raw ramp is
/// `w = r_0 / (r_0 + r_1)`, sharpened to `clamp((w − ½) / band + ½, 0, 1)` (band 1: the
/// paper's full ramp). Bins seen by one reference only use it (w = 1 or 0); bins seen by
/// neither but facing the current camera (disocclusion, §3.4) use the nearer reference in
/// time with `draw_unseen`, and are culled without it.
pub fn plan(
    bins: &NormalBins,
    eye_now: Vec3,
    eye_ref: [Vec3; 2],
    s: f32,
    settings: &PlanSettings,
) -> BinPlan {
    let s = if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let band = if settings.blend_band.is_finite() {
        settings.blend_band.clamp(1e-3, 1.0)
    } else {
        1.0
    };
    let mut out = BinPlan {
        weights: vec![[0.0; 4]; bins.len()],
        ..Default::default()
    };
    let mut kinds: Vec<Option<DrawKind>> = vec![None; bins.len()];
    for (b, bin) in bins.bins.iter().enumerate() {
        if bin.indices.is_empty() {
            continue;
        }
        if settings.cull_current && bins.facing(b, eye_now) == Facing::Back {
            out.bins_culled += 1;
            continue;
        }
        let see = |i: usize| {
            !settings.cull_references || bins.facing_by(b, eye_ref[i], settings.culling).may_see()
        };
        let (see0, see1) = (see(0), see(1));
        if !see0 && !see1 && !settings.draw_unseen {
            out.bins_culled += 1;
            continue;
        }
        let elevation = |i: usize| {
            let v = (eye_ref[i] - bins.centre).normalize_or(Vec3::Z);
            bin.cell_normal.dot(v).clamp(-1.0, 1.0).asin().max(0.0)
        };
        let cos_margin = |i: usize| {
            let v = (eye_ref[i] - bins.centre).normalize_or(Vec3::Z);
            let d = (eye_ref[i] - bins.centre)
                .length()
                .max(bins.radius * 1.0001);
            let delta = bin.half_angle_rad + (bins.radius / d).clamp(0.0, 1.0).asin();
            (bin.normal.dot(v) + delta.min(std::f32::consts::FRAC_PI_2).sin()).max(1e-3)
        };
        let w0 = match (see0, see1) {
            (true, false) => 1.0,
            (false, true) => 0.0,
            (false, false) => {
                if s <= 0.5 {
                    1.0
                } else {
                    0.0
                }
            }
            (true, true) => {
                let (t0, t1) = if settings.temporal_weight {
                    (1.0 - s, s)
                } else {
                    (1.0, 1.0)
                };
                let (a0, a1) = match settings.ramp {
                    Ramp::CosineRatio => (cos_margin(0), cos_margin(1)),
                    Ramp::LinearAngle => (elevation(0), elevation(1)),
                };
                let (r0, r1) = (a0 * t0, a1 * t1);
                let raw = if r0 + r1 > 0.0 { r0 / (r0 + r1) } else { 0.5 };
                ((raw - 0.5) / band + 0.5).clamp(0.0, 1.0)
            }
        };
        out.weights[b] = [w0, 1.0 - w0, 0.0, 0.0];
        let kind = if w0 >= 1.0 {
            DrawKind::Single0
        } else if w0 <= 0.0 {
            DrawKind::Single1
        } else {
            DrawKind::Blend
        };
        match kind {
            DrawKind::Blend => out.bins_blended += 1,
            _ => out.bins_single += 1,
        }
        out.triangles_drawn += bin.indices.len() / 3;
        kinds[b] = Some(kind);
    }
    // Merge runs of adjacent single-reference bins into one draw each; blended bins are one
    // draw per bin (the instance index selects the bin's weight).
    for (b, kind) in kinds.iter().enumerate() {
        let Some(kind) = *kind else { continue };
        let range = bins.bins[b].indices.clone();
        if kind != DrawKind::Blend {
            if let Some(last) = out.draws.last_mut() {
                if last.kind == kind && last.indices.end == range.start {
                    last.indices.end = range.end;
                    continue;
                }
            }
        }
        out.draws.push(BinDraw {
            kind,
            indices: range,
            instance: b as u32,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_cells_round_trip() {
        for n in [1, 2, 5, 16] {
            for b in 0..n * n {
                assert_eq!(bin_of_normal(cell_centre(b, n), n), b, "n {n} bin {b}");
            }
        }
        assert_eq!(bin_of_normal(Vec3::ZERO, 8), 0);
        assert_eq!(bin_of_normal(Vec3::NAN, 8), 0);
        assert!(bin_of_normal(Vec3::NEG_Z, 8) < 64);
    }
}
