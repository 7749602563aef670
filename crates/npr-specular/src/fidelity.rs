//! How well the highlights match the light they stylize: the paper sizes each projector
//! (Eq. (8)) so that its footprint is the region `N·H ≥ σ`; this module measures it on
//! the GPU, for `cargo xtask bench specular-fidelity` and the fidelity tests.
//!
//! Per view, two masks are rendered and read back:
//! - the `N·H ≥ σ` mask: the base pass as Blinn-Phong with exponent 1, no diffuse and no
//!   ambient (so a pixel holds `N·H` where `N·L > 0`, Eq. (2)–(3)), on the mesh's own
//!   normals (the ones the search uses), thresholded at σ;
//! - the projected-highlight mask: the highlight pass over a black base, every projector
//!   drawing [`crate::textures::footprint`] (the ellipse inscribed in its square, so no
//!   texture margin counts against the sizing).
//!
//! Scores: precision (share of highlight pixels inside the `N·H ≥ σ` mask), recall (share
//! of `N·H ≥ σ` pixels covered), the count of highlights seen (each drawn with its own
//! tint code) against the count of `N·H ≥ σ` blobs, both larger than [`MIN_BLOB_PX`],
//! and the worst stretch `1/cos` of the projected texture on a receiving triangle.

use crate::snapshot::{HighlightScene, Renderer};
use crate::{HighlightSet, SpecularError};
use glam::{Mat3, Mat4, Vec3};
use npr_geometry::LightEye;
use npr_gpu::{Camera, GpuMesh, Light, ObjectUniforms, ShadingModel};

/// Blobs of the `N·H ≥ σ` mask at most this many pixels are not counted.
pub const MIN_BLOB_PX: usize = 20;

/// One view: camera, light direction and object transform.
#[derive(Clone, Copy, Debug)]
pub struct FidelityView {
    /// The perspective eye.
    pub camera: Camera,
    /// Direction towards the (far, directional) light, world space.
    pub to_light: Vec3,
    /// Object → world.
    pub world_from_object: Mat4,
}

/// The pixel counts and highlight numbers of one view.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViewScore {
    /// Pixels covered by a projected highlight.
    pub highlight_px: usize,
    /// Pixels with `N·H ≥ σ`.
    pub region_px: usize,
    /// Pixels in both.
    pub both_px: usize,
    /// Highlights drawn (the set's count, occluded ones included).
    pub highlights: usize,
    /// Highlights seen: those covering more than [`MIN_BLOB_PX`] pixels of the image
    /// (what compares with [`ViewScore::blobs`]: a highlight hidden behind the mesh, e.g.
    /// on a torus's inner ring, is not seen).
    pub visible_highlights: usize,
    /// `N·H ≥ σ` blobs larger than [`MIN_BLOB_PX`].
    pub blobs: usize,
    /// Worst `1/cos` between a receiving triangle's normal and its projector's axis.
    pub stretch_max: f32,
}

/// Scores over several views: pixel counts pooled, counts as medians.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FidelityScore {
    /// Share of highlight pixels inside the `N·H ≥ σ` mask (1 when nothing is drawn).
    pub precision: f64,
    /// Share of `N·H ≥ σ` pixels covered by a highlight (1 when there are none).
    pub recall: f64,
    /// Median count of highlights seen per view ([`ViewScore::visible_highlights`]).
    pub highlights_median: f64,
    /// Median count of highlights drawn per view.
    pub drawn_median: f64,
    /// Median blob count per view.
    pub blobs_median: f64,
    /// Largest stretch over all views.
    pub stretch_max: f32,
    /// Views where the count of highlights seen was within ±50 % of the blob count.
    pub count_within: usize,
    /// Views measured.
    pub views: usize,
}

impl FidelityScore {
    /// Pools per-view scores.
    pub fn pool(views: &[ViewScore]) -> Self {
        let sum = |f: fn(&ViewScore) -> usize| views.iter().map(f).sum::<usize>() as f64;
        let (hl, region, both) = (
            sum(|v| v.highlight_px),
            sum(|v| v.region_px),
            sum(|v| v.both_px),
        );
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 1.0 };
        Self {
            precision: ratio(both, hl),
            recall: ratio(both, region),
            highlights_median: npr_geometry::stats::median(
                views.iter().map(|v| v.visible_highlights as f64),
            ),
            drawn_median: npr_geometry::stats::median(views.iter().map(|v| v.highlights as f64)),
            blobs_median: npr_geometry::stats::median(views.iter().map(|v| v.blobs as f64)),
            stretch_max: views.iter().map(|v| v.stretch_max).fold(0.0, f32::max),
            count_within: views
                .iter()
                .filter(|v| v.visible_highlights.abs_diff(v.blobs) as f64 <= 0.5 * v.blobs as f64)
                .count(),
            views: views.len(),
        }
    }
}

/// The transform that fits `mesh` into the unit sphere at the origin (its bounding box's
/// centre to the origin, half diagonal to 1); identity for an empty mesh.
pub fn unit_sphere_transform(mesh: &npr_geometry::Mesh) -> Mat4 {
    let (lo, hi) = mesh.positions.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x > hi.x {
        return Mat4::IDENTITY;
    }
    let radius = ((hi - lo) * 0.5).length().max(1e-6);
    Mat4::from_scale(Vec3::splat(1.0 / radius)) * Mat4::from_translation(-(lo + hi) * 0.5)
}

/// The standard views of a mesh normalised to the unit sphere at the origin
/// (`world_from_object`): `count` eyes around it at distance 2.3 (alternating elevation
/// +25° / −10°), each with two lights (up-right and up-left of the eye).
pub fn standard_views(world_from_object: Mat4, count: usize, aspect: f32) -> Vec<FidelityView> {
    let mut out = Vec::with_capacity(count * 2);
    for k in 0..count {
        let az = (k as f32 / count.max(1) as f32) * std::f32::consts::TAU + 0.3;
        let el = if k % 2 == 0 { 25f32 } else { -10f32 }.to_radians();
        let dir = Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
        let camera = Camera::look_at(dir * 2.3, Vec3::ZERO, aspect);
        let right = Vec3::Y.cross(dir).normalize_or(Vec3::X);
        let up = dir.cross(right);
        for to_light in [
            (dir + 0.6 * right + 0.5 * up).normalize(),
            (dir - 0.5 * right + 0.3 * up).normalize(),
        ] {
            out.push(FidelityView {
                camera,
                to_light,
                world_from_object,
            });
        }
    }
    out
}

/// GPU state of the measurement: a renderer whose only highlight texture is the
/// footprint ellipse.
#[derive(Debug)]
pub struct FidelityRig {
    renderer: Renderer,
    width: u32,
}

/// sRGB byte → linear.
fn linear(c: u8) -> f32 {
    npr_gpu::reference::srgb_to_linear(f32::from(c) / 255.0)
}

impl FidelityRig {
    /// Creates the rig at `width × height`.
    ///
    /// # Errors
    /// A bad size.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
    ) -> Result<Self, SpecularError> {
        let renderer = Renderer::with_textures(
            device,
            queue,
            width,
            height,
            &[crate::textures::footprint(256)],
            &[false],
        )?;
        Ok(Self { renderer, width })
    }

    /// Updates `set` afresh for `view` (no fades: every highlight at full opacity) and
    /// scores it at the set's global σ.
    ///
    /// # Errors
    /// Readback failure.
    pub fn score(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: (&GpuMesh, &[u32]),
        set: &mut HighlightSet,
        view: &FidelityView,
    ) -> Result<ViewScore, SpecularError> {
        set.reset();
        set.update(
            LightEye::Positions {
                light: view.to_light * 1e4,
                eye: view.camera.eye,
            },
            view.world_from_object,
        );
        let sigma = set.global.sigma;
        let w = view.world_from_object;
        // Phong with k_s, specular colour and exponent 1 and no diffuse: N·H where N·L > 0;
        // all zero: a black base for the highlight pass.
        let render = |set: &HighlightSet, k_s: f32, highlights: bool| {
            let object = ObjectUniforms::new(w, Vec3::ZERO, k_s, Vec3::splat(k_s), 1.0);
            self.renderer
                .render(device, queue, &scene(mesh, set, view, object, highlights))
        };
        let n_dot_h = render(set, 1.0, false)?;
        // Each highlight's tint codes its index in (g, b) / r, so that overlapping
        // highlights stay apart; r alone is the coverage (tint r = 1).
        for (k, h) in set.highlights_mut().iter_mut().enumerate() {
            let code = |c: usize| (c % 16) as f32 / 15.0;
            h.controls.tint = Vec3::new(1.0, code(k), code(k / 16));
            h.opacity = 1.0;
        }
        let drawn = render(set, 0.0, true)?;
        let region: Vec<bool> = n_dot_h.pixels().map(|p| linear(p.0[0]) >= sigma).collect();
        let mut own = vec![0usize; 256];
        let highlight: Vec<bool> = drawn
            .pixels()
            .map(|p| {
                let [r, g, b] = [p.0[0], p.0[1], p.0[2]].map(linear);
                let covered = r >= 0.5;
                if covered {
                    let code = |c: f32| (c / r * 15.0).round().clamp(0.0, 15.0) as usize;
                    own[code(g) + 16 * code(b)] += 1;
                }
                covered
            })
            .collect();
        let count = |m: &[bool]| m.iter().filter(|b| **b).count();
        let both = region
            .iter()
            .zip(&highlight)
            .filter(|(a, b)| **a && **b)
            .count();
        Ok(ViewScore {
            highlight_px: count(&highlight),
            region_px: count(&region),
            both_px: both,
            highlights: set.highlights().len(),
            visible_highlights: own.iter().filter(|n| **n > MIN_BLOB_PX).count(),
            blobs: blobs(&region, self.width as usize, MIN_BLOB_PX),
            stretch_max: stretch_max(set, w),
        })
    }
}

/// The measuring scene of `view`: a black background, Phong base with `object`'s
/// material and a light without ambient.
fn scene<'a>(
    mesh: (&'a GpuMesh, &'a [u32]),
    set: &'a HighlightSet,
    view: &FidelityView,
    object: ObjectUniforms,
    highlights: bool,
) -> HighlightScene<'a> {
    HighlightScene {
        mesh: mesh.0,
        indices: mesh.1,
        set,
        object,
        camera: view.camera,
        light: Light {
            ambient: Vec3::ZERO,
            ..Light::directional(view.to_light)
        },
        base: ShadingModel::Phong,
        highlights,
        clear: [0.0, 0.0, 0.0, 1.0],
    }
}

/// Frame coherence of a highlight sequence (see [`Coherence::step`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coherence {
    /// Highlights that appeared above one fade step of opacity (popped in).
    pub pops_in: usize,
    /// Highlights that vanished while above one fade step (popped out).
    pub pops_out: usize,
    /// Largest relative change `|A − A_prev| / A_prev` of a footprint's area (projector
    /// half extents' product) of a highlight present in consecutive frames.
    pub area_change_max: f32,
    /// Frames seen.
    pub frames: usize,
    fade_step: f32,
    previous: Vec<(u64, f32, f32)>,
}

impl Coherence {
    /// Checks a sequence against fades over `fade_frames` updates (0: no fade required).
    pub fn new(fade_frames: u32) -> Self {
        Self {
            fade_step: if fade_frames == 0 {
                1.0
            } else {
                1.0 / fade_frames as f32
            },
            ..Self::default()
        }
    }

    /// Records the set's highlights after one update. The first frame may show anything
    /// at full opacity; afterwards a highlight must appear with an opacity of at most one
    /// fade step, and disappear only after fading to it.
    pub fn step(&mut self, set: &HighlightSet) {
        let step = self.fade_step + 1e-4;
        let now: Vec<(u64, f32, f32)> = set
            .highlights()
            .iter()
            .map(|h| {
                let e = h.projector.half_extent;
                (h.id, h.opacity, e.x * e.y)
            })
            .collect();
        if self.frames > 0 {
            for &(id, opacity, area) in &now {
                match self.previous.iter().find(|p| p.0 == id) {
                    None if opacity > step => self.pops_in += 1,
                    None => {}
                    Some(&(_, _, before)) => {
                        let change = (area - before).abs() / before.max(f32::MIN_POSITIVE);
                        self.area_change_max = self.area_change_max.max(change);
                    }
                }
            }
            for &(id, opacity, _) in &self.previous {
                if opacity > step && !now.iter().any(|n| n.0 == id) {
                    self.pops_out += 1;
                }
            }
        }
        self.previous = now;
        self.frames += 1;
    }
}

/// Connected (4-neighbour) components of `mask` (row-major, `width` wide) with more than
/// `min_px` pixels.
pub fn blobs(mask: &[bool], width: usize, min_px: usize) -> usize {
    if width == 0 {
        return 0;
    }
    let height = mask.len() / width;
    let mut seen = vec![false; mask.len()];
    let mut stack = Vec::new();
    let mut count = 0;
    for start in 0..mask.len() {
        if !mask[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut size = 0;
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = (i % width, i / width);
            let mut go = |j: usize| {
                if mask[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            };
            if x > 0 {
                go(i - 1);
            }
            if x + 1 < width {
                go(i + 1);
            }
            if y > 0 {
                go(i - width);
            }
            if y + 1 < height {
                go(i + width);
            }
        }
        if size > min_px {
            count += 1;
        }
    }
    count
}

/// The worst stretch of a projected texture over every receiving triangle of `set`:
/// `1/cos` of the angle between the triangle's world normal and its projector's axis
/// (infinite for a triangle at or past 90°). Triangles whose normal is past the zero of
/// the highlight's per-pixel falloff ([`crate::Highlight::falloff_cos`]) show nothing
/// there and are not counted.
pub fn stretch_max(set: &HighlightSet, world_from_object: Mat4) -> f32 {
    let topo = set.topology();
    let normal_from_object = Mat3::from_mat4(world_from_object).inverse().transpose();
    let faces = set.receiver_faces();
    let mut worst = 0f32;
    for h in set.highlights() {
        for &f in &faces[h.receivers.clone()] {
            let n = (normal_from_object * topo.face_normals[f as usize]).normalize_or_zero();
            let c = n.dot(h.projector.normal);
            if c <= h.falloff_cos.x {
                continue;
            }
            worst = worst.max(if c > 0.0 { 1.0 / c } else { f32::INFINITY });
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blobs_count_components_above_the_size() {
        let w = 10;
        let mut m = vec![false; 100];
        for y in 0..5 {
            for x in 0..5 {
                m[y * w + x] = true; // 25 px
            }
        }
        for x in 7..10 {
            m[9 * w + x] = true; // 3 px
        }
        assert_eq!(blobs(&m, w, 20), 1);
        assert_eq!(blobs(&m, w, 2), 2);
    }
}
