//! Where an update's regions come from: the CPU's grower ([`RegionGrower::grow_all`](crate::region::RegionGrower::grow_all)) or
//! the caller's GPU growth ([`crate::RegionPass`], through [`RegionsOnGpu`]), and the
//! overlap scales and pieces of whichever grew them.

use super::{Entry, HighlightSet, HighlightSizing};
use crate::region::{Region, RegionFrame};
use glam::Mat4;
use npr_geometry::{HighlightCentre, LightEye};

/// Grows an update's regions elsewhere (the GPU, [`crate::RegionPass`]): given the set
/// and the seeds (centre, σ) in the order [`RegionGrower::grow_all`](crate::region::RegionGrower::grow_all) would take them, one
/// [`crate::GpuRegion`] per seed, or `None` to leave them to the CPU.
pub type RegionsOnGpu<'a> =
    &'a mut dyn FnMut(&HighlightSet, &[(HighlightCentre, f32)]) -> Option<Vec<crate::GpuRegion>>;

impl HighlightSet {
    /// The regions of the found centres in `next` ([`HighlightSizing::Region`]; none for
    /// the paper's sizing), grown all at once in `next`'s order: by `on_gpu` when given
    /// and it returns one region per seed, else by the CPU's grower.
    pub(super) fn grow_regions(
        &mut self,
        next: &[Entry],
        light_eye: LightEye,
        world_from_object: Mat4,
        on_gpu: Option<RegionsOnGpu<'_>>,
    ) -> Vec<Region> {
        self.gpu_regions.clear();
        self.regions_grown_on_gpu = false;
        match self.sizing {
            HighlightSizing::Paper => Vec::new(),
            HighlightSizing::Region => {
                let seeds: Vec<(HighlightCentre, f32)> = next
                    .iter()
                    .filter(|e| e.2)
                    .map(|e| (e.1, self.controls_of(e.0).sigma))
                    .collect();
                if let Some(grow) = on_gpu {
                    if seeds.is_empty() {
                        self.regions_grown_on_gpu = true;
                        return Vec::new();
                    }
                    if let Some(grown) = grow(self, &seeds).filter(|g| g.len() == seeds.len()) {
                        let regions = grown.iter().map(|g| g.region).collect();
                        self.gpu_regions = grown;
                        self.regions_grown_on_gpu = true;
                        return regions;
                    }
                }
                let frame = RegionFrame {
                    topology: &self.topology,
                    normals: self.search.normals(),
                    world_from_object,
                    light_eye,
                };
                self.grower.grow_all(&frame, &seeds)
            }
        }
    }

    /// The overlap scale of seed `k`'s region (or of its `piece`-th piece) this update:
    /// the GPU's where it grew them, else the grower's.
    pub(super) fn region_scale(&self, k: usize, piece: Option<usize>) -> f32 {
        match self.gpu_regions.get(k) {
            Some(g) => piece.map_or(g.overlap_scale, |i| {
                g.piece_scales.get(i).copied().unwrap_or(1.0)
            }),
            None => self.grower.overlap_scale(k, piece),
        }
    }

    /// The pieces of seed `k`'s region this update (see [`RegionGrower::pieces`](crate::region::RegionGrower::pieces)).
    pub(super) fn region_pieces(&self, k: usize) -> &[crate::Footprint] {
        match self.gpu_regions.get(k) {
            Some(g) => g.pieces(),
            None => self.grower.pieces(k),
        }
    }
}
