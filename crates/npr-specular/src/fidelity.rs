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
//!
//! Shapes, not only pixels:
//! - `overlap_share`: pixels covered by two or more projectors ÷ pixels covered by any
//!   (a third render, every highlight at opacity 1/4: one layer reads 0.25, two 0.44);
//! - `cut_boundary_share`: over every highlight's boundary pixels, the share where the
//!   drawn highlight ends with a hard step (its alpha falls by ≥ 1/2 to the next pixel)
//!   although its texture continues there (alpha ≥ 1/2) when projected with §4.2 alone
//!   ([`HighlightBoundary::Unrestricted`]: connected surface facing the projector). Such
//!   a pixel is on visible, connected surface by construction, so silhouettes never
//!   count; a crease (a jump of the interpolated normal) would, and the shapes measured
//!   have none;
//! - edit completeness: the largest highlight, translated by a half extent along
//!   `e_max`, turned 45° and grown 1.5×, each drawn ÷ the same edited texture drawn with
//!   §4.2 alone.

use crate::snapshot::{HighlightScene, Renderer};

mod coherence;
mod gpu_setup;
use crate::{HighlightBoundary, HighlightControls, HighlightSet, SpecularError};
pub use coherence::{
    Coherence, pose_coherence, pose_coherence_with, turntable_coherence, turntable_coherence_with,
};
use glam::{Mat3, Mat4, Vec3};
pub use gpu_setup::GpuSetup;
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
    /// Pixels covered by two or more highlights; `None` where not measured (frames
    /// whose projectors the GPU builds and draws, [`GpuSetup::whole_frame`], carry the
    /// GPU's own fades, so no frame of every highlight at opacity 1/4 is made).
    pub overlap_px: Option<usize>,
    /// Boundary pixels of the highlights drawn.
    pub boundary_px: usize,
    /// Boundary pixels where a highlight is cut (see the module docs).
    pub cut_px: usize,
    /// Drawn ÷ unrestricted area of the largest highlight translated, turned and grown;
    /// `None` without a highlight.
    pub edits: Option<[f32; 3]>,
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
    /// Pixels covered by two or more highlights ÷ pixels covered by any (pooled); `None`
    /// where a view's was not measured ([`ViewScore::overlap_px`]).
    pub overlap_share: Option<f64>,
    /// Cut boundary pixels ÷ boundary pixels (pooled).
    pub cut_boundary_share: f64,
    /// Median over views and the three edits of drawn ÷ unrestricted area (1 without
    /// highlights).
    pub edit_completeness: f64,
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
        let edits: Vec<f64> = views
            .iter()
            .filter_map(|v| v.edits)
            .flatten()
            .map(f64::from)
            .collect();
        Self {
            overlap_share: views
                .iter()
                .map(|v| v.overlap_px)
                .sum::<Option<usize>>()
                .map(|o| ratio(o as f64, hl)),
            cut_boundary_share: ratio(sum(|v| v.cut_px), sum(|v| v.boundary_px)),
            edit_completeness: if edits.is_empty() {
                1.0
            } else {
                npr_geometry::stats::median(edits)
            },
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

/// `mesh` with the normals its highlight set sees ([`HighlightSet::render_normals`], at
/// the set's abstraction scale): the surface whose `N·H ≥ σ` region the highlights
/// stylize, what [`FidelityRig::score`] measures against. `mesh` unchanged when the set
/// has no normals for it.
pub fn surface_at_scale(mesh: &npr_geometry::Mesh, set: &HighlightSet) -> npr_geometry::Mesh {
    let mut out = mesh.clone();
    if set.render_normals().len() == mesh.positions.len() {
        out.normals = set.render_normals().to_vec();
    }
    out
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
    npr_gpu::cpu_twin::srgb_to_linear(f32::from(c) / 255.0)
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
    /// scores it at the set's global σ. `mesh` is the render mesh with the normals the set
    /// sees ([`surface_at_scale`]): the `N·H ≥ σ` mask is rendered with them.
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
        self.score_with(device, queue, mesh, set, view, None)
    }

    /// [`FidelityRig::score`] with every update and highlight frame of the measure set up
    /// on the GPU by `gpu` (made for `set` and `mesh`), or on the CPU without it.
    ///
    /// # Errors
    /// Readback failure, or a GPU pass's error.
    pub fn score_with(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: (&GpuMesh, &[u32]),
        set: &mut HighlightSet,
        view: &FidelityView,
        gpu: Option<&mut GpuSetup>,
    ) -> Result<ViewScore, SpecularError> {
        set.reset();
        let light_eye = LightEye::Positions {
            light: view.to_light * 1e4,
            eye: view.camera.eye,
        };
        let w = view.world_from_object;
        let gpu = std::cell::RefCell::new(gpu);
        let update = |set: &mut HighlightSet| -> Result<(), SpecularError> {
            let r = match gpu.borrow_mut().as_deref_mut() {
                Some(g) => g.update(device, queue, set, (light_eye, w)),
                None => {
                    set.update(light_eye, w);
                    Ok(())
                }
            };
            if std::env::var_os("SCRATCH").is_some() {
                eprintln!(
                    "UPD {} b {:?}: {:?}",
                    gpu.borrow().is_some(),
                    set.tuning.boundary,
                    set.highlights()
                        .iter()
                        .filter(|h| h.peak)
                        .map(|h| (
                            h.id,
                            format!("{:.3}", h.projector.centre_world.z),
                            h.opacity,
                            h.found
                        ))
                        .collect::<Vec<_>>()
                );
            }
            r
        };
        update(set)?;
        let sigma = set.tuning.controls.sigma;
        // Phong with k_s, specular colour and exponent 1 and no diffuse: N·H where N·L > 0;
        // all zero: a black base for the highlight pass.
        let render = |set: &HighlightSet, k_s: f32, highlights: bool| {
            let object = ObjectUniforms::new(w, Vec3::ZERO, k_s, Vec3::splat(k_s), 1.0);
            let scene = scene(mesh, set, view, object, highlights);
            match gpu.borrow_mut().as_deref_mut() {
                Some(g) if highlights => g.render(device, queue, &self.renderer, &scene),
                _ => self.renderer.render(device, queue, &scene),
            }
        };
        let n_dot_h = render(set, 1.0, false)?;
        // Each highlight's tint codes its index in (g, b) / r, so that overlapping
        // highlights stay apart; r alone is the coverage (tint r = 1).
        let ids: Vec<u64> = set.highlights().iter().map(|h| h.id).collect();
        let drawn = coded(set, &ids, |set| render(set, 0.0, true))?;
        let region: Vec<bool> = n_dot_h.pixels().map(|p| linear(p.0[0]) >= sigma).collect();
        let mut own = vec![0usize; 256];
        for &(code, alpha) in &drawn {
            if alpha >= 0.5 {
                own[code] += 1;
            }
        }
        let highlight: Vec<bool> = drawn.iter().map(|p| p.1 >= 0.5).collect();
        let count = |m: &[bool]| m.iter().filter(|b| **b).count();
        let both = region
            .iter()
            .zip(&highlight)
            .filter(|(a, b)| **a && **b)
            .count();
        // Overlaps: every highlight at opacity 1/4 (not for frames whose projectors the
        // GPU builds and draws: they carry the GPU's own fades).
        let own_fades = gpu.borrow().is_some();
        let overlap_px = if own_fades {
            None
        } else {
            let layered = drawn_as(set, |_| (Vec3::ONE, 0.25), |set| render(set, 0.0, true))?;
            Some(layered.pixels().filter(|p| linear(p.0[0]) >= 0.34).count())
        };
        // Cuts: the same highlights with §4.2 alone.
        let (boundary_px, cut_px) = {
            let boundary = set.tuning.boundary;
            set.tuning.boundary = HighlightBoundary::Unrestricted;
            update(set)?;
            let unrestricted = coded(set, &ids, |set| render(set, 0.0, true))?;
            set.tuning.boundary = boundary;
            update(set)?;
            cuts(&drawn, &unrestricted, self.width as usize)
        };
        // Edits of the largest highlight.
        let largest = (0..ids.len()).max_by_key(|&k| own.get(k % 256).copied().unwrap_or(0));
        let edits = match largest {
            Some(k) if own.get(k).is_some_and(|n| *n > MIN_BLOB_PX) => {
                let id = ids[k];
                let half = set.highlights()[k].projector.half_extent;
                let mut ratios = [0f32; 3];
                let edits = [
                    HighlightControls {
                        translate: glam::Vec2::new(half.x, 0.0),
                        ..Default::default()
                    },
                    HighlightControls {
                        rotate_rad: 45f32.to_radians(),
                        ..Default::default()
                    },
                    HighlightControls {
                        scale: glam::Vec2::splat(1.5),
                        ..Default::default()
                    },
                ];
                let boundary = set.tuning.boundary;
                let area = |set: &mut HighlightSet| -> Result<usize, SpecularError> {
                    update(set)?;
                    let px = coded(set, &ids, |set| render(set, 0.0, true))?;
                    Ok(px.iter().filter(|p| p.0 == k % 256 && p.1 >= 0.5).count())
                };
                for (ratio, edit) in ratios.iter_mut().zip(edits) {
                    *set.controls_mut(id) = edit;
                    set.tuning.boundary = boundary;
                    let got = area(set)?;
                    set.tuning.boundary = HighlightBoundary::Unrestricted;
                    let want = area(set)?;
                    *ratio = if want > 0 {
                        got as f32 / want as f32
                    } else {
                        1.0
                    };
                }
                *set.controls_mut(id) = HighlightControls::default();
                set.tuning.boundary = boundary;
                update(set)?;
                Some(ratios)
            }
            _ => None,
        };
        Ok(ViewScore {
            highlight_px: count(&highlight),
            region_px: count(&region),
            both_px: both,
            highlights: set.highlights().iter().filter(|h| h.piece == 0).count(),
            visible_highlights: own.iter().filter(|n| **n > MIN_BLOB_PX).count(),
            blobs: blobs(&region, self.width as usize, MIN_BLOB_PX),
            stretch_max: match gpu.borrow_mut().as_deref_mut() {
                Some(g) => g.stretch_max(device, queue, set)?,
                None => stretch_max(set, w),
            },
            overlap_px,
            boundary_px,
            cut_px,
            edits,
        })
    }
}

/// Renders `set` with each highlight tinted by the code of its id's position in `ids`
/// ((g, b) / r, r = 1) at opacity 1, and decodes each pixel to (code, alpha). The codes
/// are the drawn highlights' tints, and for a frame the GPU makes again while it draws
/// ([`GpuSetup::whole_frame`]) also the user's own tints of those ids, restored after.
fn coded(
    set: &mut HighlightSet,
    ids: &[u64],
    render: impl Fn(&HighlightSet) -> Result<image::RgbaImage, SpecularError>,
) -> Result<Vec<(usize, f32)>, SpecularError> {
    let code = |c: usize| (c % 16) as f32 / 15.0;
    let tint = |k: usize| Vec3::new(1.0, code(k), code(k / 16));
    let code_of = |id: u64| ids.iter().position(|i| *i == id).unwrap_or(255);
    let own: Vec<Option<HighlightControls>> = ids.iter().map(|&id| set.own_controls(id)).collect();
    let global = set.tuning.controls.tint.max(Vec3::splat(1e-6));
    for (k, (&id, c)) in ids.iter().zip(&own).enumerate() {
        let mut c = c.unwrap_or_default();
        c.tint = tint(k) / global;
        set.set_own_controls(id, Some(c));
    }
    let image = drawn_as(set, |h| (tint(code_of(h.id)), 1.0), render);
    for (&id, c) in ids.iter().zip(own) {
        set.set_own_controls(id, c);
    }
    let image = image?;
    Ok(image
        .pixels()
        .map(|p| {
            let [r, g, b] = [p.0[0], p.0[1], p.0[2]].map(linear);
            let decode = |c: f32| (c / r.max(1e-6) * 15.0).round().clamp(0.0, 15.0) as usize;
            (decode(g) + 16 * decode(b), r)
        })
        .collect())
}

/// What `render` gives with each highlight of `set` drawn at the (tint, opacity) `look`
/// gives it; then the set's own are given back: the next update fades on from them, not
/// from the measure's.
fn drawn_as<T>(
    set: &mut HighlightSet,
    look: impl Fn(&crate::Highlight) -> (Vec3, f32),
    render: impl FnOnce(&HighlightSet) -> T,
) -> T {
    let own: Vec<(Vec3, f32)> = set
        .highlights()
        .iter()
        .map(|h| (h.controls.tint, h.opacity))
        .collect();
    for h in set.highlights_mut() {
        (h.controls.tint, h.opacity) = look(h);
    }
    let out = render(set);
    for (h, (tint, opacity)) in set.highlights_mut().iter_mut().zip(own) {
        h.controls.tint = tint;
        h.opacity = opacity;
    }
    out
}

/// Boundary pixels of the drawn highlights, and those among them cut: a 4-neighbour
/// where the drawn highlight's alpha is lower by ≥ 1/2 (a hard step, not a falloff)
/// while the unrestricted projection of the same highlight has alpha ≥ 1/2.
fn cuts(drawn: &[(usize, f32)], unrestricted: &[(usize, f32)], width: usize) -> (usize, usize) {
    if width == 0 {
        return (0, 0);
    }
    let height = drawn.len() / width;
    let (mut boundary, mut cut) = (0, 0);
    for y in 0..height {
        for x in 0..width {
            let i = y * width + x;
            let (k, a) = drawn[i];
            if a < 0.5 {
                continue;
            }
            let neighbours = [
                (x > 0).then(|| i - 1),
                (x + 1 < width).then(|| i + 1),
                (y > 0).then(|| i - width),
                (y + 1 < height).then(|| i + width),
            ];
            let mut on_boundary = false;
            let mut is_cut = false;
            for j in neighbours.into_iter().flatten() {
                let (kj, aj) = drawn[j];
                let own = if kj == k { aj } else { 0.0 };
                if own >= 0.5 {
                    continue;
                }
                on_boundary = true;
                let (ku, au) = unrestricted[j];
                if ku == k && au >= 0.5 && a - own >= 0.5 {
                    is_cut = true;
                }
            }
            boundary += usize::from(on_boundary);
            cut += usize::from(is_cut);
        }
    }
    (boundary, cut)
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
    let faces = set.receiver_faces();
    stretch_over(set, world_from_object, |k| {
        faces[set.highlights()[k].receivers.clone()].to_vec()
    })
}

/// [`stretch_max`] over the receiver faces `receivers` gives each highlight (by index).
fn stretch_over(
    set: &HighlightSet,
    world_from_object: Mat4,
    receivers: impl Fn(usize) -> Vec<u32>,
) -> f32 {
    let drawn = set
        .highlights()
        .iter()
        .enumerate()
        .map(|(k, h)| (h.projector.normal, h.falloff_cos.x, receivers(k)));
    stretch_of(set, world_from_object, drawn)
}

/// The worst stretch over projectors given as (world normal at the centre, the falloff's
/// zero-alpha cosine, the faces they draw on).
fn stretch_of(
    set: &HighlightSet,
    world_from_object: Mat4,
    drawn: impl Iterator<Item = (Vec3, f32, Vec<u32>)>,
) -> f32 {
    let topo = set.topology();
    let normal_from_object = Mat3::from_mat4(world_from_object).inverse().transpose();
    let mut worst = 0f32;
    for (normal, zero_cos, faces) in drawn {
        for f in faces {
            let n = (normal_from_object * topo.face_normals[f as usize]).normalize_or_zero();
            let c = n.dot(normal);
            if c <= zero_cos {
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
