//! The per-mesh highlight set: built once from a mesh's curvature field, updated per
//! frame from light, eye and object transform (§3 of the specular paper), with frame
//! coherence beyond the paper (§6 leaves splitting and merging open):
//!
//! - centres move continuously inside triangles (barycentric solve, §3.1), never snapping
//!   to vertices;
//! - each frame's centres are matched to the previous frame's by distance on the object,
//!   so a highlight keeps its identity and its controls;
//! - new highlights fade in and lost ones fade out over [`crate::HighlightTuning::fade_frames`]
//!   updates instead of popping;
//! - projectors are sized, by default, to the region `N·H ≥ σ` measured on the mesh
//!   ([`HighlightSizing::Region`], [`crate::cpu::region`]), the regions of all centres grown at
//!   once so that one region holding several centres is shared out; a centre on another's
//!   face or with a tiny region is suppressed, and a footprint's area changes by at most
//!   [`crate::HighlightTuning::max_area_change`] per update;
//! - with the paper's sizing, two projectors claiming the same region (one's centre
//!   inside the central half of the other's frustum) are merged into the older one;
//! - a merged or suppressed highlight fades out like a lost one.

mod centres;
mod matching;

mod mesh;
mod peaks;
mod pose;
mod receivers;
mod regions;
pub(crate) use peaks::vertex_neighbours;
pub(crate) use receivers::ReceiverRule;

use crate::cpu::region::{Footprint, Region, RegionCounts, RegionGrower, RegionPatches};
use crate::cpu::visibility::{VisibilityScratch, face_slack};
use crate::projector::eq8_footprint;
use crate::{HighlightControls, Projector, ProjectorControls, SpecularError};
use glam::{Mat4, Vec3};
pub(crate) use mesh::mean_scale;
use mesh::{bounding_radius, check, corner_normals, face_turn};
use npr_geometry::{
    CoherenceStats, CurvatureField, CurvatureOptions, HighlightCentre, HighlightSearch, LightEye,
    Mesh, SearchCoherence, Topology,
};
use std::collections::HashMap;
use std::ops::Range;
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// One highlight of the current frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Highlight {
    /// Stable identity across frames (matched by [`HighlightSet::update`]).
    pub id: u64,
    /// The `N = H` centre this frame (or the last one seen, while fading out).
    pub centre: HighlightCentre,
    /// Its projector (Eq. (7) over [`Highlight::footprint`], with the composed controls).
    pub projector: Projector,
    /// Its footprint before the controls (Eq. (8)'s or the measured region's, see
    /// [`HighlightSizing`]); kept while the highlight fades out.
    pub footprint: Footprint,
    /// The controls it was built with (global ∘ per-highlight).
    pub controls: ProjectorControls,
    /// Opacity in [0, 1]: ramps up when the highlight appears, down when it is lost.
    pub opacity: f32,
    /// Whether the centre was found this frame (false while fading out).
    pub found: bool,
    /// Its receiver faces: a range into [`HighlightSet::receiver_faces`].
    pub receivers: Range<usize>,
    /// The per-pixel facing falloff ([`HighlightBoundary::Smooth`]): cosines between the
    /// interpolated normal and the projector's axis where the highlight's alpha is 0 (x)
    /// and where it is whole (y); `(−3, −2)` (never reached) where there is none.
    pub falloff_cos: glam::Vec2,
    /// Up to four highlights (indices into this frame's [`HighlightSet::highlights`])
    /// whose footprints overlap this one's, neither edited by the user: the pass splits
    /// the pixels they share (each goes to the ellipse it lies deepest in), so a pixel is
    /// covered by one highlight unless the user placed two there. `u32::MAX` for none.
    pub shared_with: [u32; 4],
    /// 0 for a highlight itself; `i ≥ 1` for the i-th piece of a long bent highlight,
    /// drawn in its place (same id, centre, controls and opacity; its own footprint,
    /// projector and receivers; see [`crate::cpu::region::RegionGrower::pieces`]). The §3.4
    /// edits move, turn and scale the pieces as one group about the whole's centre.
    pub piece: u8,
    /// How many pieces are drawn in this highlight's place (0: it is drawn itself; it
    /// then has no receivers, its projector is the whole region's ellipse, what picking
    /// and matching use).
    pub pieces: u8,
    /// Whether the centre is the maximum of `N·H` of a bright region that holds no
    /// `N = H` point (beyond the paper, `set::peaks`) rather than an `N = H` point.
    pub peak: bool,
}

/// The default abstraction of [`HighlightSet::new`], in units of the bounding-sphere
/// radius: a cartoon scale (see [`HighlightSet::with_abstraction`]).
pub const DEFAULT_ABSTRACTION: f32 = 0.05;

static NEXT_NORMALS_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// No per-pixel falloff: every cosine is above both ends.
pub const NO_FALLOFF: glam::Vec2 = glam::Vec2::new(-3.0, -2.0);

/// A highlight to show this frame, as matched: (id, centre, found, previous highlight
/// index).
type Entry = (u64, HighlightCentre, bool, Option<usize>);

/// Where a highlight's drawn boundary comes from, besides its texture's own edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HighlightBoundary {
    /// Beyond the paper (default): the §4.2 search decides *which* connected surface
    /// receives; the normal limit of [`HighlightSizing::Region`] (the region's normal
    /// cone widened by [`crate::HighlightTuning::receiver_cone_margin_rad`], at most
    /// [`crate::HighlightTuning::receiver_min_cos`]) is a falloff on the interpolated normal, smooth
    /// per pixel ([`Highlight::falloff_cos`]), so edges follow the surface, not its
    /// triangles. The cone follows the projector as drawn: a §3.4 translation widens it
    /// by the normal's turn over that distance (`|t| · max |κ|`), a rotation or a scale by
    /// the turn over the edited footprint's half extents, so an edit is never cut to the
    /// unedited footprint. The ramp is never narrower than the interpolated normal's
    /// typical turn across one face either side, so on a coarse mesh it does not end
    /// within a triangle.
    #[default]
    Smooth,
    /// The normal limit per face: a face outside the cone is not a receiver (the
    /// behaviour before the smooth falloff; edges step along triangles).
    PerFace,
    /// §4.2 alone: connected faces with `N·N_max > 0`, no normal limit (the reference an
    /// edit's completeness is measured against).
    Unrestricted,
}

/// Per-frame statistics of [`HighlightSet::update`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateStats {
    /// Centres found by the N = H search.
    pub centres: usize,
    /// Centres of bright regions without an `N = H` point, at their maximum of `N·H`
    /// ([`HighlightSizing::Region`]; see `set::peaks`).
    pub peaks: usize,
    /// Highlights drawn (found + fading).
    pub highlights: usize,
    /// Receiver faces over all highlights.
    pub receiver_faces: usize,
    /// Projectors merged away because they claimed another's region.
    pub merged: usize,
    /// Wall time of the N = H search, microseconds.
    pub search_us: f64,
    /// Wall time of the search for bright regions without an `N = H` point (`set::peaks`),
    /// microseconds (0 for the paper's sizing).
    pub peaks_us: f64,
    /// What the frame-coherent search did ([`npr_geometry::SearchCoherence`]).
    pub search: CoherenceStats,
    /// Wall time of the §4.2 visibility searches, microseconds.
    pub visibility_us: f64,
    /// Wall time of the region growth and fit ([`HighlightSizing::Region`]),
    /// microseconds (0 for the paper's sizing).
    pub region_us: f64,
    /// How the region growth classified the faces it looked at.
    pub region_faces: RegionCounts,
}

/// How projectors are sized.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HighlightSizing {
    /// The paper: Eq. (8), `s = min(2r, 2/|κ| · sqrt(1 − σ²))` per principal direction,
    /// centred on the `N = H` point; receivers need only `N·N_max > 0` (§4.2).
    Paper,
    /// Beyond the paper (default): the footprint is fitted to the region `N·H ≥ σ`
    /// measured on the mesh ([`crate::cpu::region`]), offset to its centroid and turned to its
    /// axes; a centre whose region another highlight already claims, or whose region is
    /// smaller than [`crate::HighlightTuning::min_region_area`], is suppressed; receivers must also
    /// lie within [`crate::HighlightTuning::receiver_min_cos`] of the projector's axis.
    #[default]
    Region,
}

/// Highlights of one mesh. See the module docs.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct HighlightSet {
    pub(crate) topology: Topology,
    pub(crate) search: HighlightSearch,
    coherence: SearchCoherence,
    pub(crate) radius_object: f32,
    /// The settings each update reads (σ and the other controls, sizing, fades,
    /// matching, receivers, the change limit): [`crate::HighlightTuning`].
    pub tuning: crate::HighlightTuning,
    pub(crate) per_highlight: HashMap<u64, HighlightControls>,
    pub(crate) highlights: Vec<Highlight>,
    pub(crate) receiver_faces: Vec<u32>,
    /// Per face: largest angle between its normal and its corners' render normals.
    face_slack: Vec<[f32; 2]>,
    /// The interpolated normal's typical turn across one face (the median over faces of
    /// the largest angle between two of its corners' render normals), radians: the
    /// smooth falloff is never narrower than twice this (see [`HighlightBoundary::Smooth`]).
    pub(crate) face_turn: f32,
    /// Per render vertex: the normal at the set's scale (empty from `from_parts`).
    render_normals: Vec<Vec3>,
    abstraction: f32,
    /// The abstraction's diffusion steps, fixed at build ([`HighlightSet::repose`]
    /// keeps them).
    diffusion_steps: usize,
    /// The curvature's ball radius (world units) at build, which a repose keeps.
    ball_radius: f32,
    normals_id: u64,
    scratch: VisibilityScratch,
    /// Region growth; its face patches serve the §4.2 search too.
    grower: RegionGrower,
    pub(crate) radius_bound: f32,
    pub(crate) next_id: u64,
    /// Whether an update has run since the set was made or reset: from then on a new
    /// highlight fades in, even after a frame that showed none.
    pub(crate) tracking: bool,
    stats: UpdateStats,
    peak_scratch: peaks::PeakScratch,
}

impl HighlightSet {
    /// Builds the set for a render mesh at the default abstraction
    /// ([`DEFAULT_ABSTRACTION`]): welds it, builds the topology and the curvature field
    /// with `options`. See [`HighlightSet::with_abstraction`].
    ///
    /// # Errors
    /// [`SpecularError::EmptyMesh`] when the mesh has no usable triangle.
    pub fn new(mesh: &Mesh, options: &CurvatureOptions) -> Result<Self, SpecularError> {
        Self::with_abstraction(mesh, options, DEFAULT_ABSTRACTION)
    }

    /// Builds the set for a render mesh seeing its surface at scale `abstraction`, in
    /// units of the mesh's bounding-sphere radius (beyond the paper). At 0 the N = H
    /// search, the regions and the per-pixel falloff work on the mesh's own normals (the
    /// ones it is shaded with, [`npr_geometry::NormalSource::Mesh`]): one highlight per
    /// bump of a scan, faithful to `N·H ≥ σ` on the raw surface. Above 0 they work on the
    /// curvature field smoothed over that scale ([`CurvatureField::at_scale`]): small
    /// bumps cancel, limbs keep their shape, and a scan shows a few clean highlights per
    /// form. Negative or non-finite values count as 0.
    ///
    /// # Errors
    /// [`SpecularError::EmptyMesh`] when the mesh has no usable triangle.
    pub fn with_abstraction(
        mesh: &Mesh,
        options: &CurvatureOptions,
        abstraction: f32,
    ) -> Result<Self, SpecularError> {
        let (welded, topology, field) = CurvatureField::for_mesh(mesh, options);
        Self::from_field(mesh, (&welded, topology), &field, (abstraction, None))
    }

    /// [`HighlightSet::with_abstraction`] on a curvature field measured elsewhere (one
    /// entry per vertex of `welded`, the weld of `mesh`, whose topology is `topology`),
    /// with the abstraction's diffusion steps given (a repose keeps the built pose's) or
    /// `None` for those of the abstraction on this mesh.
    pub(crate) fn from_field(
        mesh: &Mesh,
        (welded, topology): (&npr_geometry::Welded, Topology),
        field: &CurvatureField,
        (abstraction, steps): (f32, Option<usize>),
    ) -> Result<Self, SpecularError> {
        check(&topology, field)?;
        let abstraction = if abstraction.is_finite() {
            abstraction.max(0.0)
        } else {
            0.0
        };
        let mesh_normals = mesh.normals.len() == mesh.positions.len();
        let mut diffusion = 0;
        let (search, render_normals) = if abstraction > 0.0 {
            let sigma = abstraction * bounding_radius(&topology);
            diffusion = steps.unwrap_or_else(|| CurvatureField::scale_steps(&topology, sigma));
            // Smooth the normals the mesh is shaded with, where it has them.
            let mut shaded = field.clone();
            if let Some(normals) = npr_geometry::welded_mesh_normals(mesh, welded) {
                for ((n, own), valid) in shaded.normal.iter_mut().zip(normals).zip(&field.valid) {
                    if *valid && own != Vec3::ZERO {
                        *n = own;
                    }
                }
            }
            // A pose (its steps given) signs its principal directions as the measured
            // ones, as a pose made on the GPU does; a set built at rest keeps the solver's
            // signs, which its figures were measured with (Spot's edit completeness
            // 0.954 against 0.934 with the measured signs).
            let scaled = match steps {
                Some(_) => shaded.at_steps(&topology, diffusion),
                None => shaded.at_scale(&topology, sigma),
            };
            let search = HighlightSearch::new(&topology, &scaled);
            let normals = search.normals();
            let render = welded
                .render_to_welded
                .iter()
                .map(|&w| normals.get(w as usize).copied().unwrap_or(Vec3::ZERO))
                .collect();
            (search, render)
        } else {
            let search = HighlightSearch::for_mesh(mesh, welded, &topology, field);
            let render = if mesh_normals {
                mesh.normals.clone()
            } else {
                let normals = search.normals();
                welded
                    .render_to_welded
                    .iter()
                    .map(|&w| normals.get(w as usize).copied().unwrap_or(Vec3::ZERO))
                    .collect()
            };
            (search, render)
        };
        // The normals a fragment interpolates, per face corner.
        let corners: Vec<Vec3> = mesh
            .indices
            .iter()
            .take(3 * topology.face_count())
            .map(|&i| {
                render_normals
                    .get(i as usize)
                    .copied()
                    .unwrap_or(Vec3::ZERO)
            })
            .collect();
        let mut set = Self::with_search(topology, field, search);
        set.face_slack = face_slack(&set.topology, &corners);
        set.face_turn = face_turn(&corners);
        set.render_normals = render_normals;
        set.abstraction = abstraction;
        set.diffusion_steps = diffusion;
        Ok(set)
    }

    /// Builds the set from a topology and its curvature field (one entry per welded
    /// vertex), searching on the field's normals. Faces keep the render mesh's triangle
    /// order.
    ///
    /// # Errors
    /// [`SpecularError::EmptyMesh`] when no face is usable;
    /// [`SpecularError::Mismatch`] when the field and topology differ in vertex count.
    pub fn from_parts(topology: Topology, field: &CurvatureField) -> Result<Self, SpecularError> {
        check(&topology, field)?;
        let search = HighlightSearch::new(&topology, field);
        let corners = corner_normals(&topology, search.normals());
        let mut set = Self::with_search(topology, field, search);
        set.face_slack = face_slack(&set.topology, &corners);
        set.face_turn = face_turn(&corners);
        Ok(set)
    }

    fn with_search(topology: Topology, field: &CurvatureField, search: HighlightSearch) -> Self {
        let radius_bound = bounding_radius(&topology);
        let grower = RegionGrower::with_patches(RegionPatches::new(&topology, search.normals()));
        Self {
            radius_object: field.radius_world.max(0.15 * radius_bound),
            ball_radius: field.radius_world,
            diffusion_steps: 0,
            topology,
            search,
            coherence: SearchCoherence::default(),
            tuning: crate::HighlightTuning::default(),
            per_highlight: HashMap::new(),
            highlights: Vec::new(),
            receiver_faces: Vec::new(),
            face_slack: Vec::new(),
            face_turn: 0.0,
            render_normals: Vec::new(),
            abstraction: 0.0,
            normals_id: NEXT_NORMALS_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            scratch: VisibilityScratch::default(),
            grower,
            radius_bound,
            next_id: 0,
            tracking: false,
            stats: UpdateStats::default(),
            peak_scratch: peaks::PeakScratch::default(),
        }
    }

    /// Chooses the normal field of the `N = H` solve (default: the curvature-blended field,
    /// which keeps centres gliding at a steady speed; `Linear` is the paper's Eq. (4)).
    pub fn set_interpolation(&mut self, interpolation: npr_geometry::NormalInterpolation) {
        self.search.interpolation = interpolation;
    }

    /// The mesh topology (faces in render-triangle order).
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Per-highlight controls of highlight `id` (created from the defaults on first use;
    /// they persist while the highlight is matched from frame to frame).
    pub fn controls_mut(&mut self, id: u64) -> &mut HighlightControls {
        self.per_highlight.entry(id).or_default()
    }

    /// The current highlights.
    pub fn highlights(&self) -> &[Highlight] {
        &self.highlights
    }

    /// The current highlights, for this crate's measurements (e.g. per-highlight tints).
    #[cfg(any(test, feature = "test-support"))]
    pub(crate) fn highlights_mut(&mut self) -> &mut [Highlight] {
        &mut self.highlights
    }

    /// The scale the set sees its surface at, in units of the bounding-sphere radius (see
    /// [`HighlightSet::with_abstraction`]).
    pub fn abstraction(&self) -> f32 {
        self.abstraction
    }

    /// Per render vertex, the unit normal at the set's scale: what the search, the regions
    /// and the per-pixel falloff see (the mesh's own at abstraction 0). Empty for a set
    /// built [`HighlightSet::from_parts`] (it knows no render vertices).
    pub fn render_normals(&self) -> &[Vec3] {
        &self.render_normals
    }

    /// Identifies this set's [`HighlightSet::render_normals`] (unique per built set), so
    /// a pass uploads them once.
    pub fn normals_id(&self) -> u64 {
        self.normals_id
    }

    /// Receiver faces of all highlights; each [`Highlight::receivers`] is a range of it.
    pub fn receiver_faces(&self) -> &[u32] {
        &self.receiver_faces
    }

    /// Per face, (cos, sin) of its slack angle ([`crate::cpu::visibility::face_slack`]).
    pub(crate) fn face_slack(&self) -> &[[f32; 2]] {
        &self.face_slack
    }

    /// Statistics of the last update.
    pub fn stats(&self) -> UpdateStats {
        self.stats
    }

    /// Forgets all highlights (the next update starts fresh, without fades).
    pub fn reset(&mut self) {
        self.highlights.clear();
        self.receiver_faces.clear();
        self.tracking = false;
    }

    /// Per-frame update (§3): the N = H search, matching with the previous frame, fades,
    /// merging, projectors (Eq. (7)–(8)) and receiver faces (§4.2). Non-finite or zero
    /// light/eye input yields no highlights rather than NaN.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    pub fn update(&mut self, light_eye: LightEye, world_from_object: Mat4) -> &[Highlight] {
        let (centres, search_us) = self.search_centres(light_eye, world_from_object);
        self.update_with(light_eye, world_from_object, (centres, search_us))
    }

    fn update_with(
        &mut self,
        light_eye: LightEye,
        world_from_object: Mat4,
        (mut centres, search_us): (Vec<HighlightCentre>, f64),
    ) -> &[Highlight] {
        let found = centres.len();
        let peaks_start = Instant::now();
        if self.tuning.sizing == HighlightSizing::Region
            && valid_input(light_eye, world_from_object)
        {
            let peaks = self.peak_centres(&centres, light_eye, world_from_object);
            centres.extend(peaks);
        }
        let peaks_us = peaks_start.elapsed().as_secs_f64() * 1e6;
        let scale = mean_scale(world_from_object);
        let radius_world = self.tuning.size_cap_radius.unwrap_or(self.radius_object) * scale;
        // Pieces are made afresh from their highlight each frame.
        let mut previous = std::mem::take(&mut self.highlights);
        previous.retain(|h| h.piece == 0);
        let next = self.match_centres(
            &previous,
            (&centres, found),
            radius_world,
            scale,
            world_from_object,
        );
        let region_start = Instant::now();
        let regions = self.grow_regions(&next, light_eye, world_from_object);
        let region_us = region_start.elapsed().as_secs_f64() * 1e6;
        let (mut kept, merged) = self.footprints(
            next,
            (&previous, &centres[found..]),
            regions,
            radius_world,
            scale,
        );
        let visibility_start = Instant::now();
        self.find_receivers(&mut kept, world_from_object);
        self.share_regions(&mut kept);
        let live: std::collections::HashSet<u64> = kept.iter().map(|h| h.id).collect();
        self.per_highlight.retain(|id, _| live.contains(id));
        self.stats = UpdateStats {
            centres: found,
            peaks: centres.len() - found,
            highlights: kept.iter().filter(|h| h.piece == 0).count(),
            receiver_faces: self.receiver_faces.len(),
            merged,
            search_us,
            peaks_us,
            search: self.coherence.stats(),
            visibility_us: visibility_start.elapsed().as_secs_f64() * 1e6,
            region_us,
            region_faces: self.grower.counts(),
        };
        self.highlights = kept;
        self.tracking = true;
        &self.highlights
    }

    /// Footprints, opacities and pieces of the highlights in `next` (fades, suppression,
    /// the paper's merging), and how many were merged away; `peaks` are this frame's
    /// centres of bright regions without an `N = H` point.
    fn footprints(
        &self,
        next: Vec<Entry>,
        (previous, peaks): (&[Highlight], &[HighlightCentre]),
        regions: Vec<Region>,
        radius_world: f32,
        scale: f32,
    ) -> (Vec<Highlight>, usize) {
        let step = if self.tuning.fade_frames == 0 {
            1.0
        } else {
            1.0 / self.tuning.fade_frames as f32
        };
        // Only the first update of a sequence shows its highlights at once; after a frame
        // without any, new ones still fade in.
        let first_frame = !self.tracking;
        let mut regions = regions.into_iter().enumerate();
        let min_area = self.tuning.min_region_area * (self.radius_bound * scale).powi(2);
        let mut merged = 0;
        let mut kept: Vec<Highlight> = Vec::with_capacity(next.len());
        for (id, centre, found, prev) in next {
            let before = prev.map(|i| &previous[i]);
            let controls = self.controls_of(id);
            let mut seed = None;
            let mut footprint = match (found, self.tuning.sizing) {
                (false, _) => before.map(|h| h.footprint),
                (true, HighlightSizing::Paper) => {
                    Some(eq8_footprint(&centre, controls.sigma, radius_world))
                }
                (true, HighlightSizing::Region) => match regions.next() {
                    Some((k, Region::Fit(fp, _))) => {
                        seed = Some(k);
                        let fp = fp.scaled(self.region_scale(k, None));
                        (fp.region_area >= min_area).then_some(fp)
                    }
                    _ => None,
                },
            };
            // The paper's sizing: two projectors claiming the same region (one's centre
            // inside the central half of the other's frustum) keep the older one (the
            // measured regions are shared out between their centres instead).
            if let Some(fp) =
                footprint.filter(|_| found && self.tuning.sizing == HighlightSizing::Paper)
            {
                let clash = kept.iter().any(|k| {
                    let limit = 0.5
                        * k.projector
                            .half_extent
                            .min_element()
                            .min(fp.half_extent.min_element());
                    k.found && k.centre.position_world.distance(centre.position_world) < limit
                });
                if clash {
                    footprint = None;
                }
            }
            let shown = before.map_or(0.0, |h| h.opacity);
            let (footprint, opacity, found) = match (footprint, found) {
                (Some(fp), true) => {
                    let fp = match before {
                        Some(h) => limit_change(&h.footprint, fp, self.tuning.max_area_change),
                        _ => fp,
                    };
                    let opacity = if first_frame {
                        1.0
                    } else {
                        (shown + step).min(1.0)
                    };
                    (fp, opacity, true)
                }
                (Some(fp), false) => (fp, shown - step, false),
                (None, _) => {
                    // Suppressed: a highlight already shown fades out with its last
                    // footprint; a new one never appears.
                    if found {
                        merged += 1;
                    }
                    match before {
                        Some(h) => (h.footprint, shown - step, false),
                        None => continue,
                    }
                }
            };
            if opacity <= 0.0 || footprint.half_extent.min_element() <= 0.0 {
                continue;
            }
            let Some(mut h) = self.make(id, centre, controls, footprint, opacity, found) else {
                continue;
            };
            h.peak = if found {
                peaks.contains(&centre)
            } else {
                before.is_some_and(|b| b.peak)
            };
            let pieces = match seed {
                Some(k) if found => self.region_pieces(k),
                _ => &[],
            };
            let mut drawn = Vec::with_capacity(pieces.len());
            for (i, piece) in pieces.iter().enumerate() {
                let piece = seed.map_or(*piece, |k| piece.scaled(self.region_scale(k, Some(i))));
                let edited = group_edit(&footprint, &piece, &controls);
                if let Some(mut p) = self.make(id, centre, controls, edited, opacity, found) {
                    p.footprint = piece;
                    p.peak = h.peak;
                    p.piece = (drawn.len() + 1) as u8;
                    drawn.push(p);
                }
            }
            h.pieces = drawn.len() as u8;
            kept.push(h);
            kept.extend(drawn);
        }
        (kept, merged)
    }

    /// The composed controls of highlight `id` (global ∘ per-highlight).
    pub(crate) fn controls_of(&self, id: u64) -> ProjectorControls {
        self.tuning
            .controls
            .compose(&self.per_highlight.get(&id).copied().unwrap_or_default())
    }

    pub(crate) fn make(
        &self,
        id: u64,
        centre: HighlightCentre,
        controls: ProjectorControls,
        footprint: Footprint,
        opacity: f32,
        found: bool,
    ) -> Option<Highlight> {
        let projector = Projector::with_footprint(&centre, &controls, &footprint)?;
        Some(Highlight {
            id,
            centre,
            projector,
            controls,
            footprint,
            opacity,
            found,
            receivers: 0..0,
            falloff_cos: NO_FALLOFF,
            shared_with: [u32::MAX; 4],
            piece: 0,
            pieces: 0,
            peak: false,
        })
    }
}

/// Whether the light, eye and transform are finite and the directions non-zero (else a
/// frame has no highlights rather than NaN).
fn valid_input(light_eye: LightEye, world_from_object: Mat4) -> bool {
    let light_eye_ok = match light_eye {
        LightEye::Directions { to_light, to_eye } => {
            to_light.is_finite()
                && to_eye.is_finite()
                && to_light.length_squared() > 0.0
                && to_eye.length_squared() > 0.0
        }
        LightEye::Positions { light, eye } => light.is_finite() && eye.is_finite(),
    };
    light_eye_ok && world_from_object.is_finite()
}

/// `next` with each half extent kept within a factor `sqrt(1 + max_area_change)` of
/// `last` (so the area changes by at most `max_area_change` per update; ≤ 0 disables).
fn limit_change(last: &Footprint, next: Footprint, max_area_change: f32) -> Footprint {
    if max_area_change.is_nan() || max_area_change <= 0.0 || last.half_extent.min_element() <= 0.0 {
        return next;
    }
    let r = (1.0 + max_area_change).sqrt();
    let lo = last.half_extent / r;
    let hi = last.half_extent * r;
    Footprint {
        half_extent: next.half_extent.clamp(lo, hi),
        ..next
    }
}

/// A piece's footprint under the §3.4 controls applied to the whole highlight as one
/// group: its offset from the whole's centre scaled along the whole's axes and turned by
/// the rotation; the translation, its own turn and its half extents' scale are then
/// applied by [`Projector::with_footprint`] as for any footprint.
fn group_edit(whole: &Footprint, piece: &Footprint, c: &ProjectorControls) -> Footprint {
    let d = piece.offset - whole.offset;
    let (sw, cw) = whole.rotate_rad.sin_cos();
    let local = glam::Vec2::new(d.x * cw + d.y * sw, d.y * cw - d.x * sw) * c.scale.abs();
    let back = glam::Vec2::new(local.x * cw - local.y * sw, local.x * sw + local.y * cw);
    let (sr, cr) = c.rotate_rad.sin_cos();
    let turned = glam::Vec2::new(back.x * cr - back.y * sr, back.x * sr + back.y * cr);
    Footprint {
        offset: whole.offset + turned,
        ..*piece
    }
}
