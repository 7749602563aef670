//! An update's regions, grown by the CPU's grower
//! ([`RegionGrower::grow_all`](crate::cpu::region::RegionGrower::grow_all)), and their overlap
//! scales and pieces.

use super::{Entry, HighlightSet, HighlightSizing};
use crate::cpu::region::{Region, RegionFrame};
use glam::Mat4;
use npr_geometry::{HighlightCentre, LightEye};

impl HighlightSet {
    /// The regions of the found centres in `next` ([`HighlightSizing::Region`]; none for
    /// the paper's sizing), grown all at once in `next`'s order by the CPU's grower.
    pub(super) fn grow_regions(
        &mut self,
        next: &[Entry],
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> Vec<Region> {
        match self.tuning.sizing {
            HighlightSizing::Paper => Vec::new(),
            HighlightSizing::Region => {
                let seeds: Vec<(HighlightCentre, f32)> = next
                    .iter()
                    .filter(|e| e.2)
                    .map(|e| (e.1, self.controls_of(e.0).sigma))
                    .collect();
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

    /// The overlap scale of seed `k`'s region (or of its `piece`-th piece) this update.
    pub(super) fn region_scale(&self, k: usize, piece: Option<usize>) -> f32 {
        self.grower.overlap_scale(k, piece)
    }

    /// The pieces of seed `k`'s region this update (see [`RegionGrower::pieces`](crate::cpu::region::RegionGrower::pieces)).
    pub(super) fn region_pieces(&self, k: usize) -> &[crate::Footprint] {
        self.grower.pieces(k)
    }
}
