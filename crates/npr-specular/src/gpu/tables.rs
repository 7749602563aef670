//! What the GPU's frame of highlights reads of a set (`tracking.wgsl`,
//! `projectors.wgsl`): the last update's highlights as the table the GPU keeps from frame
//! to frame, and the frame's settings and controls.

use crate::cpu::set::{HighlightBoundary, HighlightSet, HighlightSizing, mean_scale};
use crate::gpu::regions::{TrackParams, TrackedRecord};
use crate::gpu::search::CentreRecord;
use crate::projector::UpAxis;
use glam::Mat4;

/// `ProjectParams` of `projectors.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ProjectParams {
    pub(crate) controls_a: [f32; 4],
    pub(crate) controls_b: [f32; 4],
    pub(crate) controls_c: [f32; 4],
    pub(crate) sizes: [f32; 4],
    pub(crate) receiver: [f32; 4],
    pub(crate) modes: [u32; 4],
    pub(crate) tracking: [f32; 4],
}

/// `ControlsRecord` of `projectors.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ControlsRecord {
    pub(crate) id_flags: [u32; 4],
    pub(crate) moves: [f32; 4],
    pub(crate) scale: [f32; 4],
    pub(crate) tint: [f32; 4],
}

fn up_index(up: UpAxis) -> u32 {
    match up {
        UpAxis::KappaMin => 0,
        UpAxis::KappaMax => 1,
    }
}

impl HighlightSet {
    /// The table of the last update's highlights (their pieces 0, in id order, as
    /// [`HighlightSet::match_centres`] takes them) for an update with
    /// `world_from_object`: each one's centre (object space), its reach and σ, its
    /// footprint, state and opacity, and its centre placed again under this transform
    /// (where a lost highlight fades out); the head holds the σ of a new highlight, the
    /// next id and whether a frame was drawn. Ids are the GPU's `u32`.
    ///
    /// With `slots` (per face its visiting slot in the GPU search) each centre keeps its
    /// slot and `cs_replace` places it again every frame; without, it is marked placed
    /// already (slot `NONE`): a table made again every frame.
    pub(crate) fn gpu_table(
        &self,
        world_from_object: Mat4,
        slots: Option<&[u32]>,
    ) -> (TrackParams, Vec<TrackedRecord>) {
        let scale = mean_scale(world_from_object);
        let radius_world = self.tuning.size_cap_radius.unwrap_or(self.radius_object) * scale;
        let table = self
            .highlights
            .iter()
            .filter(|h| h.piece == 0)
            .map(|h| {
                let c = &h.centre;
                let placed = self
                    .search
                    .centre_at(c.face, c.alpha, c.beta, world_from_object)
                    .unwrap_or(h.centre);
                let f = &h.footprint;
                let p = c.position_object;
                TrackedRecord {
                    position_reach: p.extend(self.reach(h, radius_world, scale)).to_array(),
                    sigma: [self.controls_of(h.id).sigma, 0.0, 0.0, 0.0],
                    centre: CentreRecord {
                        solution: [
                            placed.face,
                            placed.alpha.to_bits(),
                            placed.beta.to_bits(),
                            slots
                                .and_then(|s| s.get(placed.face as usize).copied())
                                .unwrap_or(u32::MAX),
                        ],
                        ..CentreRecord::of(&placed, h.peak)
                    },
                    footprint: [f.half_extent.x, f.half_extent.y, f.offset.x, f.offset.y],
                    shape: [f.rotate_rad, f.region_area, f.normal_cone_cos, f.fit_scale],
                    state: [
                        h.id as u32,
                        u32::from(h.found),
                        u32::from(h.peak),
                        u32::from(h.pieces),
                    ],
                    fade: [h.opacity, 0.0, 0.0, 0.0],
                }
            })
            .collect();
        let fresh = self
            .tuning
            .controls
            .compose(&crate::HighlightControls::default());
        let params = TrackParams {
            count: self.highlights.iter().filter(|h| h.piece == 0).count() as u32,
            sigma: fresh.sigma,
            tracking: u32::from(self.tracking),
            next_id: self.next_id as u32,
            ..TrackParams::default()
        };
        (params, table)
    }

    /// Whether the next update continues a sequence (false after [`HighlightSet::reset`]
    /// and before the first update).
    pub(crate) fn is_tracking(&self) -> bool {
        self.tracking
    }

    /// The user's own controls of highlight `id`, if any were set.
    #[cfg(any(test, feature = "test-support"))]
    pub(crate) fn own_controls(&self, id: u64) -> Option<crate::HighlightControls> {
        self.per_highlight.get(&id).copied()
    }

    /// Sets (or, with `None`, clears) the user's own controls of highlight `id`.
    #[cfg(any(test, feature = "test-support"))]
    pub(crate) fn set_own_controls(&mut self, id: u64, controls: Option<crate::HighlightControls>) {
        match controls {
            Some(c) => {
                self.per_highlight.insert(id, c);
            }
            None => {
                self.per_highlight.remove(&id);
            }
        }
    }

    /// The σ the user set per highlight (`tracking.wgsl`'s `own_sigma`): their count, then
    /// (id, σ bits) sorted by id.
    pub(crate) fn own_sigmas(&self) -> Vec<[u32; 2]> {
        let mut own: Vec<[u32; 2]> = self
            .per_highlight
            .iter()
            .filter_map(|(&id, c)| c.sigma.map(|s| [id as u32, s.to_bits()]))
            .collect();
        own.sort_by_key(|e| e[0]);
        own.insert(0, [own.len() as u32, 0]);
        own
    }

    /// The frame's settings for the projectors built on the GPU (`ProjectParams`) and
    /// the per-highlight controls the user set, sorted by id. `normal_maps` says which
    /// texture layers are normal maps (at most 32).
    pub(crate) fn project_params(
        &self,
        world_from_object: Mat4,
        normal_maps: &[bool],
    ) -> (ProjectParams, Vec<ControlsRecord>) {
        let g = &self.tuning.controls;
        let scale = mean_scale(world_from_object);
        let radius_world = self.tuning.size_cap_radius.unwrap_or(self.radius_object) * scale;
        let min_area = self.tuning.min_region_area * (self.radius_bound * scale).powi(2);
        let step = if self.tuning.fade_frames == 0 {
            1.0
        } else {
            1.0 / self.tuning.fade_frames as f32
        };
        let bits = normal_maps
            .iter()
            .take(32)
            .enumerate()
            .fold(0u32, |b, (i, &m)| b | (u32::from(m) << i));
        let mut controls: Vec<ControlsRecord> = self
            .per_highlight
            .iter()
            .map(|(&id, c)| {
                let flags = u32::from(c.sigma.is_some())
                    | u32::from(c.texture_layer.is_some()) << 1
                    | u32::from(c.shininess.is_some()) << 2
                    | u32::from(c.up.is_some()) << 3;
                ControlsRecord {
                    id_flags: [
                        id as u32,
                        flags,
                        c.texture_layer.unwrap_or(0),
                        c.up.map_or(0, up_index),
                    ],
                    moves: [
                        c.translate.x,
                        c.translate.y,
                        c.rotate_rad,
                        c.sigma.unwrap_or(0.0),
                    ],
                    scale: [c.scale.x, c.scale.y, c.shininess.unwrap_or(0.0), 0.0],
                    tint: c.tint.extend(1.0).to_array(),
                }
            })
            .collect();
        controls.sort_by_key(|c| c.id_flags[0]);
        let params = ProjectParams {
            controls_a: [g.translate.x, g.translate.y, g.rotate_rad, g.sigma],
            controls_b: [g.scale.x, g.scale.y, g.shininess, g.texture_layer as f32],
            controls_c: g.tint.extend(up_index(g.up) as f32).to_array(),
            sizes: [radius_world, min_area, self.tuning.max_area_change, step],
            receiver: [
                self.tuning.receiver_min_cos,
                self.tuning.receiver_cone_margin_rad,
                self.face_turn,
                1.0 / scale,
            ],
            modes: [
                u32::from(self.tuning.sizing == HighlightSizing::Region),
                match self.tuning.boundary {
                    HighlightBoundary::Smooth => 0,
                    HighlightBoundary::PerFace => 1,
                    HighlightBoundary::Unrestricted => 2,
                },
                controls.len() as u32,
                bits,
            ],
            tracking: [
                self.tuning.match_radius,
                self.topology.mean_edge_length,
                scale,
                normal_maps.len().saturating_sub(1) as f32,
            ],
        };
        (params, controls)
    }

    /// Takes a frame made on the GPU (read back one frame late, [`crate::gpu::FrameOnGpu`]) as
    /// this set's last update: its highlights (their projectors built again here from
    /// their centres and footprints with this set's controls; pieces are not listed,
    /// their whole stands for them as in picking and matching), ids and next id, so that
    /// the panel, picking and a later CPU update go on from it.
    pub fn adopt_gpu_frame(&mut self, frame: &crate::gpu::GpuFrame) {
        let highlights = frame
            .highlights
            .iter()
            .filter_map(|g| {
                let controls = self.controls_of(g.id);
                let mut h = self.make(g.id, g.centre, controls, g.footprint, g.opacity, g.found)?;
                h.peak = g.peak;
                h.pieces = g.pieces;
                Some(h)
            })
            .collect();
        self.highlights = highlights;
        self.receiver_faces.clear();
        self.next_id = self.next_id.max(frame.next_id);
        self.tracking = true;
    }
}
