//! The per-mesh highlight set: built once from a mesh's curvature field, updated per
//! frame from light, eye and object transform (§3 of the specular paper), with frame
//! coherence beyond the paper (§6 leaves splitting and merging open):
//!
//! - centres move continuously inside triangles (barycentric solve, §3.1), never snapping
//!   to vertices;
//! - each frame's centres are matched to the previous frame's by distance on the object,
//!   so a highlight keeps its identity and its controls;
//! - new highlights fade in and lost ones fade out over [`HighlightSet::fade_frames`]
//!   updates instead of popping;
//! - two projectors claiming the same region (one's centre inside the central half of the
//!   other's frustum) are merged into the older one.

use crate::visibility::{VisibilityScratch, receivers};
use crate::{HighlightControls, Projector, ProjectorControls, SpecularError};
use glam::{Mat4, Vec3};
use npr_geometry::{
    CurvatureField, CurvatureOptions, HighlightCentre, HighlightSearch, LightEye, Mesh, Topology,
};
use std::collections::HashMap;
use std::ops::Range;

/// One highlight of the current frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Highlight {
    /// Stable identity across frames (matched by [`HighlightSet::update`]).
    pub id: u64,
    /// The `N = H` centre this frame (or the last one seen, while fading out).
    pub centre: HighlightCentre,
    /// Its projector (Eq. (7)–(8) with the composed controls).
    pub projector: Projector,
    /// The controls it was built with (global ∘ per-highlight).
    pub controls: ProjectorControls,
    /// Opacity in [0, 1]: ramps up when the highlight appears, down when it is lost.
    pub opacity: f32,
    /// Whether the centre was found this frame (false while fading out).
    pub found: bool,
    /// Its receiver faces: a range into [`HighlightSet::receiver_faces`].
    pub receivers: Range<usize>,
}

/// Per-frame statistics of [`HighlightSet::update`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateStats {
    /// Centres found by the N = H search.
    pub centres: usize,
    /// Highlights drawn (found + fading).
    pub highlights: usize,
    /// Receiver faces over all highlights.
    pub receiver_faces: usize,
    /// Projectors merged away because they claimed another's region.
    pub merged: usize,
    /// Wall time of the N = H search, microseconds.
    pub search_us: f64,
    /// Wall time of the §4.2 visibility searches, microseconds.
    pub visibility_us: f64,
}

/// Highlights of one mesh. See the module docs.
#[derive(Debug)]
pub struct HighlightSet {
    topology: Topology,
    search: HighlightSearch,
    radius_object: f32,
    /// Controls applied to every highlight (composed with per-highlight controls).
    pub global: ProjectorControls,
    per_highlight: HashMap<u64, HighlightControls>,
    /// The `r` of Eq. (8)'s cap `s ≤ 2r`, in object units. The paper uses its curvature
    /// ball radius; ours is a few edge lengths (for accuracy), which would cap every
    /// highlight at a few triangles, so `None` (the default) uses the larger of that
    /// radius and 15 % of the mesh's bounding-sphere radius.
    pub size_cap_radius: Option<f32>,
    /// Updates over which a highlight fades in or out (0 = pop).
    pub fade_frames: u32,
    /// Matching radius as a multiple of the previous frustum's larger half-extent.
    pub match_radius: f32,
    highlights: Vec<Highlight>,
    receiver_faces: Vec<u32>,
    scratch: VisibilityScratch,
    next_id: u64,
    stats: UpdateStats,
}

impl HighlightSet {
    /// Builds the set for a render mesh: welds it, builds the topology and the curvature
    /// field with `options`. The N = H search solves on the mesh's own normals (the ones
    /// it is shaded with) when it has them ([`npr_geometry::NormalSource::Mesh`]).
    ///
    /// # Errors
    /// [`SpecularError::EmptyMesh`] when the mesh has no usable triangle.
    pub fn new(mesh: &Mesh, options: &CurvatureOptions) -> Result<Self, SpecularError> {
        let (welded, topology, field) = CurvatureField::for_mesh(mesh, options);
        check(&topology, &field)?;
        let search = HighlightSearch::for_mesh(mesh, &welded, &topology, &field);
        Ok(Self::with_search(topology, &field, search))
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
        Ok(Self::with_search(topology, field, search))
    }

    fn with_search(topology: Topology, field: &CurvatureField, search: HighlightSearch) -> Self {
        Self {
            radius_object: field.radius_world.max(0.15 * bounding_radius(&topology)),
            size_cap_radius: None,
            topology,
            search,
            global: ProjectorControls::default(),
            per_highlight: HashMap::new(),
            fade_frames: 6,
            match_radius: 1.0,
            highlights: Vec::new(),
            receiver_faces: Vec::new(),
            scratch: VisibilityScratch::default(),
            next_id: 0,
            stats: UpdateStats::default(),
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

    /// Receiver faces of all highlights; each [`Highlight::receivers`] is a range of it.
    pub fn receiver_faces(&self) -> &[u32] {
        &self.receiver_faces
    }

    /// Statistics of the last update.
    pub fn stats(&self) -> UpdateStats {
        self.stats
    }

    /// Forgets all highlights (the next update starts fresh, without fades).
    pub fn reset(&mut self) {
        self.highlights.clear();
        self.receiver_faces.clear();
    }

    /// Per-frame update (§3): the N = H search, matching with the previous frame, fades,
    /// merging, projectors (Eq. (7)–(8)) and receiver faces (§4.2). Non-finite or zero
    /// light/eye input yields no highlights rather than NaN.
    pub fn update(&mut self, light_eye: LightEye, world_from_object: Mat4) -> &[Highlight] {
        let valid_input = match light_eye {
            LightEye::Directions { to_light, to_eye } => {
                to_light.is_finite()
                    && to_eye.is_finite()
                    && to_light.length_squared() > 0.0
                    && to_eye.length_squared() > 0.0
            }
            LightEye::Positions { light, eye } => light.is_finite() && eye.is_finite(),
        };
        let search_start = std::time::Instant::now();
        let centres = if valid_input && world_from_object.is_finite() {
            self.search.find(light_eye, world_from_object)
        } else {
            Vec::new()
        };
        let search_us = search_start.elapsed().as_secs_f64() * 1e6;
        let scale = mean_scale(world_from_object);
        let radius_world = self.size_cap_radius.unwrap_or(self.radius_object) * scale;
        let previous = std::mem::take(&mut self.highlights);
        let mut claimed = vec![false; centres.len()];
        let mut next: Vec<Highlight> = Vec::with_capacity(centres.len() + previous.len());
        let step = if self.fade_frames == 0 {
            1.0
        } else {
            1.0 / self.fade_frames as f32
        };

        // Greedy matching, closest pairs first, in object space (rigid motion of the
        // object does not move a centre there; only lighting changes do).
        let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
        for (i, h) in previous.iter().enumerate() {
            let reach =
                self.match_radius * h.projector.half_extent.max_element() / scale.max(1e-12);
            for (j, c) in centres.iter().enumerate() {
                let d = h.centre.position_object.distance(c.position_object);
                if d <= reach.max(2.0 * self.topology.mean_edge_length) {
                    pairs.push((d, i, j));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut prev_taken = vec![false; previous.len()];
        let mut matched: Vec<(usize, usize)> = Vec::new();
        for (_, i, j) in pairs {
            if !prev_taken[i] && !claimed[j] {
                prev_taken[i] = true;
                claimed[j] = true;
                matched.push((i, j));
            }
        }
        for (i, j) in matched {
            let h = &previous[i];
            next.push(self.make(
                h.id,
                centres[j],
                (h.opacity + step).min(1.0),
                true,
                radius_world,
            ));
        }
        // Lost highlights fade out at their last point on the object, re-placed with the
        // object's current transform (the projector and the receiver search both follow
        // an object that moves while the highlight fades).
        for (i, h) in previous.iter().enumerate() {
            if !prev_taken[i] && h.opacity - step > 0.0 {
                let c = &h.centre;
                let centre = self
                    .search
                    .centre_at(c.face, c.alpha, c.beta, world_from_object)
                    .unwrap_or(h.centre);
                next.push(self.make(h.id, centre, h.opacity - step, false, radius_world));
            }
        }
        // New highlights fade in (appear at full opacity on the first frame).
        let first_frame = previous.is_empty();
        for (j, c) in centres.iter().enumerate() {
            if !claimed[j] {
                let id = self.next_id;
                self.next_id += 1;
                let opacity = if first_frame { 1.0 } else { step };
                next.push(self.make(id, *c, opacity, true, radius_world));
            }
        }
        next.retain(|h| h.projector.half_extent.min_element() > 0.0 && h.opacity > 0.0);
        // Merge projectors claiming the same region: keep the older (smaller id).
        next.sort_by_key(|h| h.id);
        let mut merged = 0;
        let mut kept: Vec<Highlight> = Vec::with_capacity(next.len());
        for h in next {
            let clash = kept.iter().any(|k| {
                let limit = 0.5
                    * k.projector
                        .half_extent
                        .min_element()
                        .min(h.projector.half_extent.min_element());
                k.found
                    && h.found
                    && k.centre.position_world.distance(h.centre.position_world) < limit
            });
            if clash {
                merged += 1;
            } else {
                kept.push(h);
            }
        }
        // Receivers (§4.2).
        let visibility_start = std::time::Instant::now();
        self.receiver_faces.clear();
        for h in &mut kept {
            let start = self.receiver_faces.len();
            receivers(
                &self.topology,
                world_from_object,
                &h.projector,
                h.centre.face,
                &mut self.scratch,
                &mut self.receiver_faces,
            );
            h.receivers = start..self.receiver_faces.len();
        }
        let live: std::collections::HashSet<u64> = kept.iter().map(|h| h.id).collect();
        self.per_highlight.retain(|id, _| live.contains(id));
        self.stats = UpdateStats {
            centres: centres.len(),
            highlights: kept.len(),
            receiver_faces: self.receiver_faces.len(),
            merged,
            search_us,
            visibility_us: visibility_start.elapsed().as_secs_f64() * 1e6,
        };
        self.highlights = kept;
        &self.highlights
    }

    fn make(
        &self,
        id: u64,
        centre: HighlightCentre,
        opacity: f32,
        found: bool,
        radius_world: f32,
    ) -> Highlight {
        let local = self.per_highlight.get(&id).copied().unwrap_or_default();
        let controls = self.global.compose(&local);
        let safe = if centre.position_world.is_finite() {
            centre.position_world
        } else {
            Vec3::ZERO
        };
        let projector = Projector::new(&centre, &controls, radius_world).unwrap_or(Projector {
            centre_world: safe,
            anchor_world: safe,
            axis_u: Vec3::X,
            axis_v: Vec3::Y,
            normal: Vec3::Z,
            half_extent: glam::Vec2::ZERO,
            half_depth: 0.0,
            clip_from_world: Mat4::ZERO,
            tex_from_world: Mat4::ZERO,
        });
        Highlight {
            id,
            centre,
            projector,
            controls,
            opacity,
            found,
            receivers: 0..0,
        }
    }
}

/// The set needs a usable face and one curvature entry per vertex.
fn check(topology: &Topology, field: &CurvatureField) -> Result<(), SpecularError> {
    if topology.face_count() == 0 || (0..topology.face_count()).all(|f| topology.is_degenerate(f)) {
        return Err(SpecularError::EmptyMesh);
    }
    if field.len() != topology.vertex_count() {
        return Err(SpecularError::Mismatch(format!(
            "{} curvature entries for {} vertices",
            field.len(),
            topology.vertex_count()
        )));
    }
    Ok(())
}

/// The mean scale `|det|^(1/3)` of a transform's linear part (1 when singular).
fn mean_scale(m: Mat4) -> f32 {
    let d = glam::Mat3::from_mat4(m).determinant().abs().cbrt();
    if d.is_finite() && d > 0.0 { d } else { 1.0 }
}

/// Radius of the bounding sphere about the box centre.
fn bounding_radius(topology: &Topology) -> f32 {
    let (lo, hi) = topology.positions.iter().filter(|p| p.is_finite()).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x > hi.x {
        0.0
    } else {
        (hi - lo).length() * 0.5
    }
}
