//! [`RegionGrower`]: the breadth-first growth of all seeds' regions at once, taking whole
//! patches where bounds allow, and the face-by-face regrowth where regions met.

use super::fit::{Moments, best_overlap_scale};
use super::measure::VertexCache;
use super::patches::RegionPatches;
use super::split::{needs_split, split_bent};
use super::{Footprint, MAX_PIECES, MAX_REGION_FACES, Region, RegionCounts, RegionFrame};
use glam::{Mat3, Vec3};
use npr_geometry::{HighlightCentre, Topology};
use std::collections::VecDeque;

/// Reusable per-mesh scratch of [`RegionGrower`]: per-frame vertex values and face
/// ownership, generation-stamped so nothing is cleared per frame.
#[derive(Clone, Debug, Default)]
pub struct RegionGrower {
    pub(super) frame: u32,
    /// Per vertex, its values this frame (one cache line each: a face reads three).
    pub(super) vertices: Vec<VertexCache>,
    face_visit: Vec<u32>,
    queue: VecDeque<(u32, u32)>,
    /// Faces classified whole (inside or outside) and on the sub-grid, last frame.
    pub(super) counts: RegionCounts,
    /// Per face or whole patch taken this frame: its seed, the face (or the patch, with
    /// [`PATCH_BIT`]) and its share of the seed's moments (a bent region's pieces are cut
    /// from them).
    taken: Vec<(u32, u32, Moments)>,
    /// Whole patches ([`RegionGrower::with_patches`]) and, per patch, the frame it was
    /// decided in.
    patches: Option<std::sync::Arc<RegionPatches>>,
    patch_stamp: Vec<u32>,
    /// Stamp of the current growth pass in `face_visit` and `patch_stamp` (a frame may
    /// make several: [`RegionGrower::grow_all`]).
    stamp: u32,
    /// Per face stamped with patches, the seed that reached it; and the pairs of seeds
    /// whose growths touched (a seed reached a face another had).
    face_seed: Vec<u32>,
    meetings: Vec<(u32, u32)>,
    /// Per seed, whether the current pass grows it; the first pass's stamp while seeds
    /// are regrown (else 0), and the kept seeds whose faces a regrowth reached.
    regrow: Vec<bool>,
    first_stamp: u32,
    conflicts: Vec<u32>,
    /// Per seed, whether it may take whole patches in the current pass, and whether its
    /// growth touched another's this frame; per face, the last frame in which a region
    /// that touched another held it.
    whole: Vec<bool>,
    touched: Vec<bool>,
    face_hint: Vec<u32>,
    /// Pieces of bent regions ([`RegionGrower::pieces`]), and each seed's range of them.
    pub(super) pieces: Vec<Footprint>,
    pub(super) piece_ranges: Vec<std::ops::Range<usize>>,
    /// Per seed and per piece, the scale of its moment ellipse that overlaps its region
    /// best ([`RegionGrower::overlap_scale`]).
    scales: Vec<f32>,
    piece_scales: Vec<f32>,
    /// Indices into `taken`, grouped by seed (scratch of the fits).
    by_seed: Vec<u32>,
    /// Scratch of [`split_bent`].
    along: Vec<(f32, u32)>,
    /// Tests: sample every face on the finest sub-grid with `H` computed at each point
    /// (the reference the classification is compared with).
    #[cfg(test)]
    pub(super) exact: bool,
}

impl RegionGrower {
    /// A grower that takes whole patches of faces where it can ([`RegionPatches`], built
    /// for the mesh and the normals of the frames it will grow on).
    pub fn with_patches(patches: RegionPatches) -> Self {
        Self {
            patches: Some(std::sync::Arc::new(patches)),
            ..Self::default()
        }
    }

    /// Tests: a grower that samples every face on the finest sub-grid with `H` computed
    /// at each point (the reference the classification is compared with).
    #[cfg(test)]
    pub(super) fn exact() -> Self {
        Self {
            exact: true,
            ..Self::default()
        }
    }

    /// The face patches its whole patches are made of ([`RegionPatches`]), when it has them:
    /// the §4.2 search uses the same ones.
    pub(crate) fn patch_clusters(&self) -> Option<&crate::cpu::visibility::FaceClusters> {
        self.patches.as_deref().map(|p| &p.clusters)
    }

    /// Starts a frame of up to `seeds` seeds: forgets the vertex values and face marks of
    /// the last one.
    fn begin_frame(&mut self, topology: &Topology, seeds: usize) {
        let (nv, nf) = (topology.vertex_count(), topology.face_count());
        if self.vertices.len() != nv || self.face_visit.len() != nf {
            #[cfg(test)]
            let exact = self.exact;
            let patches = self.patches.take();
            *self = Self {
                patches,
                vertices: vec![VertexCache::default(); nv],
                face_visit: vec![0; nf],
                ..Self::default()
            };
            #[cfg(test)]
            {
                self.exact = exact;
            }
        }
        self.frame = self.frame.wrapping_add(1);
        if self.frame == 0 {
            self.vertices.fill(VertexCache::default());
            self.frame = 1;
        }
        // A frame makes at most one pass per seed and one more: never wrap within one.
        if self.stamp >= u32::MAX - seeds as u32 - 2 {
            self.face_visit.fill(0);
            self.patch_stamp.fill(0);
            self.stamp = 0;
        }
        self.next_stamp();
    }

    /// A new stamp for the faces and patches a growth pass reaches.
    fn next_stamp(&mut self) {
        self.stamp += 1;
    }

    /// The scale (≤ 1) of seed `k`'s fitted footprint, or of its `piece`-th piece
    /// ([`RegionGrower::pieces`]), at which that ellipse overlaps the region best
    /// (intersection over union, `best_overlap_scale` in `fit.rs`) in the last
    /// [`RegionGrower::grow_all`]; 1 for an unknown seed. Kept apart from the footprint,
    /// which is the moments' own (the same whether faces were taken one by one or in
    /// whole patches; the scale, estimated from the pieces taken, may differ by a
    /// fraction of a percent between the two).
    pub fn overlap_scale(&self, k: usize, piece: Option<usize>) -> f32 {
        match piece {
            None => self.scales.get(k).copied(),
            Some(i) => self
                .piece_ranges
                .get(k)
                .and_then(|r| self.piece_scales.get(r.start + i))
                .copied(),
        }
        .unwrap_or(1.0)
    }

    /// How the faces of the last [`RegionGrower::grow_all`] were classified.
    pub fn counts(&self) -> RegionCounts {
        self.counts
    }

    /// Grows the regions `N·H ≥ σ` of all `seeds` (centre in world frame as the search
    /// returns it, and its σ) at once, breadth-first from their faces, so that a region
    /// holding several centres is shared between them (each face goes to the centre that
    /// reaches it first), and fits each part's footprint. A seed whose face an earlier
    /// seed already holds is [`Region::Covered`].
    ///
    /// With [`RegionGrower::with_patches`] the growth takes a whole patch of faces at once
    /// where bounds prove every point of it inside the region (its moments summed from
    /// per-patch tensors, [`RegionPatches`]), and goes down to faces only near the
    /// boundary: the same faces and footprint as face by face for one region (tested).
    /// Where regions meet, which centre a face goes to depends on the order faces are
    /// reached in, and a whole patch is reached at once: the seeds whose growths touched
    /// another's are grown again face by face, and the others keep their patches. That
    /// is exact: a growth that touches no other visits the same faces either way, and
    /// breadth-first growths that never touch do not change each other (checked after the
    /// regrowth; a seed it touches is regrown too). The result equals face by face for
    /// all seeds at once (tested).
    pub fn grow_all(
        &mut self,
        f: &RegionFrame<'_>,
        seeds: &[(HighlightCentre, f32)],
    ) -> Vec<Region> {
        let topo = f.topology;
        self.begin_frame(topo, seeds.len());
        let mut out = vec![Region::Empty; seeds.len()];
        let m3 = Mat3::from_mat4(f.world_from_object);
        if m3.determinant().abs() <= f32::MIN_POSITIVE {
            return out;
        }
        let normal_from_object = m3.inverse().transpose();
        let patches = self.usable_patches(topo, m3);
        let patches = patches.as_deref();
        let mut parts: Vec<Part> = seeds.iter().map(|s| Part::new(s.0, s.1)).collect();
        self.begin_growth(seeds, patches.is_some());
        let ctx = GrowContext {
            frame: *f,
            normal_from_object,
            scale: m3.determinant().abs().cbrt(),
            linear: glam::DMat3::from_cols(
                m3.x_axis.as_dvec3(),
                m3.y_axis.as_dvec3(),
                m3.z_axis.as_dvec3(),
            ),
            translation: f.world_from_object.w_axis.truncate().as_dvec3(),
        };
        self.grow_pass(seeds, &ctx, patches, &mut out, &mut parts);
        if !self.meetings.is_empty() && self.counts.patches > 0 {
            self.regrow_met(seeds, &ctx, &mut out, &mut parts);
        }
        // A growth cut short by the face budget depends on the order of the whole
        // frame's growth: face by face for all seeds then (a mesh facing the light whole).
        let total: usize = parts.iter().map(|p| p.faces).sum();
        if total >= MAX_REGION_FACES && self.counts.patches > 0 {
            let patches = self.patches.take();
            let out = self.grow_all(f, seeds);
            self.patches = patches;
            self.counts.regrown = seeds.len();
            return out;
        }
        if let Some(p) = patches {
            self.hint_touched(p);
            self.patch_cones(p, f, normal_from_object, &mut parts);
        }
        self.fit_parts(&parts, &mut out);
        out
    }

    /// The whole patches this frame may take: only under a similarity (`m3`, the
    /// object → world linear part) and for this mesh; sizes their per-patch and per-face
    /// marks.
    fn usable_patches(
        &mut self,
        topo: &Topology,
        m3: Mat3,
    ) -> Option<std::sync::Arc<RegionPatches>> {
        // Whole patches only under a similarity (cones keep their angles) and for this mesh.
        let patches = self.patches.clone().filter(|p| {
            p.clusters.face_count == topo.face_count()
                && crate::cpu::visibility::is_similarity(m3, 1e-5)
        });
        if let Some(p) = &patches {
            if self.patch_stamp.len() != p.patches.len() {
                self.patch_stamp = vec![0; p.patches.len()];
            }
            if self.face_seed.len() != topo.face_count() {
                self.face_seed = vec![0; topo.face_count()];
                self.face_hint = vec![0; topo.face_count()];
            }
        }
        patches
    }

    /// Clears the last frame's counts, taken faces, pieces and meetings for `seeds`, all
    /// grown in the first pass, and decides which may take whole patches (`patches`:
    /// whether this frame has them).
    fn begin_growth(&mut self, seeds: &[(HighlightCentre, f32)], patches: bool) {
        self.counts = RegionCounts::default();
        self.taken.clear();
        self.pieces.clear();
        self.piece_ranges.clear();
        self.piece_ranges.resize(seeds.len(), 0..0);
        self.meetings.clear();
        self.regrow.clear();
        self.regrow.resize(seeds.len(), true);
        self.first_stamp = 0;
        // A seed that starts where a region that met another lay last frame most likely
        // meets one again: it grows face by face from the start.
        let last = self.frame.wrapping_sub(1);
        self.touched.clear();
        self.touched.resize(seeds.len(), false);
        self.whole.clear();
        self.whole.extend(seeds.iter().map(|s| {
            patches
                && self
                    .face_hint
                    .get(s.0.face as usize)
                    .is_none_or(|&h| h != last || last == 0)
        }));
    }

    /// The regrowth after a first pass in which regions met (see
    /// [`RegionGrower::grow_all`]).
    fn regrow_met(
        &mut self,
        seeds: &[(HighlightCentre, f32)],
        ctx: &GrowContext<'_>,
        out: &mut [Region],
        parts: &mut [Part],
    ) {
        // Regions met: grow the seeds that touched another's again, face by face,
        // until the regrown growths touch no growth kept from the first pass.
        self.first_stamp = self.stamp;
        self.regrow.fill(false);
        for &(a, b) in &self.meetings {
            self.regrow[a as usize] = true;
            self.regrow[b as usize] = true;
        }
        loop {
            let regrow = std::mem::take(&mut self.regrow);
            self.taken.retain(|t| !regrow[t.0 as usize]);
            for (k, s) in seeds.iter().enumerate() {
                if regrow[k] {
                    out[k] = Region::Empty;
                    parts[k] = Part::new(s.0, s.1);
                }
            }
            self.regrow = regrow;
            self.whole.fill(false);
            self.conflicts.clear();
            self.next_stamp();
            self.grow_pass(seeds, ctx, None, out, parts);
            if self.conflicts.is_empty() {
                self.counts.regrown = self.regrow.iter().filter(|r| **r).count();
                break;
            }
            for k in std::mem::take(&mut self.conflicts) {
                self.regrow[k as usize] = true;
            }
        }
    }

    /// Stamps the faces the touched seeds took, face by face or in whole patches of `p`.
    fn hint_touched(&mut self, p: &RegionPatches) {
        // The faces of regions that met another are hinted for the next frame.
        for &(k, item, _) in &self.taken {
            if !self.touched[k as usize] {
                continue;
            }
            if item & PATCH_BIT == 0 {
                self.face_hint[item as usize] = self.frame;
            } else {
                let c = &p.clusters.clusters[(item & !PATCH_BIT) as usize];
                for &g in &p.clusters.faces[c.faces.clone()] {
                    self.face_hint[g as usize] = self.frame;
                }
            }
        }
    }

    /// Narrows each part's normal cone to the whole patches `p` it took.
    fn patch_cones(
        &mut self,
        p: &RegionPatches,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        parts: &mut [Part],
    ) {
        // Whole patches' normal cones: the exact smallest cos over their vertices where
        // the patch's bound does not already clear the part's cone.
        let topo = f.topology;
        let mut t = 0;
        while t < self.taken.len() {
            let (k, item, _) = self.taken[t];
            t += 1;
            if item & PATCH_BIT == 0 {
                continue;
            }
            let c = (item & !PATCH_BIT) as usize;
            let part = &parts[k as usize];
            let n = part.frame.0;
            if p.patches[c].cone_bound(normal_from_object, n) >= part.cone {
                continue;
            }
            let mut cone = part.cone;
            for &g in &p.clusters.faces[p.clusters.clusters[c].faces.clone()] {
                for v in topo.triangles[g as usize] {
                    cone = cone.min(self.vertex(f, normal_from_object, v as usize).1.dot(n));
                }
            }
            parts[k as usize].cone = cone;
        }
    }

    /// Fits the footprint of each seed's part that grew (into `out`, unless covered) and
    /// splits the long bent ones ([`split_bent`]).
    fn fit_parts(&mut self, parts: &[Part], out: &mut [Region]) {
        self.scales.clear();
        self.scales.resize(parts.len(), 1.0);
        self.piece_scales.clear();
        self.piece_scales.resize(MAX_PIECES * parts.len(), 1.0);
        // The taken faces and patches by seed (a counting sort of their indices), so that
        // each seed's fit reads its own.
        let mut offsets = vec![0u32; parts.len() + 1];
        for t in &self.taken {
            offsets[t.0 as usize + 1] += 1;
        }
        for k in 0..parts.len() {
            offsets[k + 1] += offsets[k];
        }
        let mut fill = offsets.clone();
        self.by_seed.clear();
        self.by_seed.resize(self.taken.len(), 0);
        for (i, t) in self.taken.iter().enumerate() {
            self.by_seed[fill[t.0 as usize] as usize] = i as u32;
            fill[t.0 as usize] += 1;
        }
        for (k, part) in parts.iter().enumerate() {
            if out[k] == Region::Empty && part.faces > 0 {
                if let Some(fp) = part.moments.footprint() {
                    let fp = Footprint {
                        normal_cone_cos: part.cone,
                        ..fp
                    };
                    let own = offsets[k] as usize..offsets[k + 1] as usize;
                    let items = || {
                        self.by_seed[own.clone()]
                            .iter()
                            .map(|&i| &self.taken[i as usize].2)
                    };
                    self.scales[k] = best_overlap_scale(&fp, items());
                    out[k] = Region::Fit(fp, part.faces);
                    if needs_split(&fp) {
                        let start = self.pieces.len();
                        split_bent(
                            &fp,
                            k as u32,
                            &self.taken,
                            &mut self.along,
                            &mut self.pieces,
                        );
                        for p in start..self.pieces.len() {
                            self.piece_scales[p] = best_overlap_scale(&self.pieces[p], items());
                        }
                        self.piece_ranges[k] = start..self.pieces.len();
                    }
                }
            }
        }
    }

    /// One breadth-first growth of the seeds marked in `self.regrow` (with whole patches
    /// where `patches` is given), into `out` and `parts`; faces are stamped with
    /// `self.stamp`. The other seeds' parts stay as they are and count against the face
    /// budget.
    fn grow_pass(
        &mut self,
        seeds: &[(HighlightCentre, f32)],
        ctx: &GrowContext<'_>,
        patches: Option<&RegionPatches>,
        out: &mut [Region],
        parts: &mut [Part],
    ) {
        let f = &ctx.frame;
        let topo = f.topology;
        self.queue.clear();
        for (k, (centre, _)) in seeds.iter().enumerate() {
            let start = centre.face as usize;
            if !self.regrow[k] || start >= topo.face_count() || !parts[k].valid {
                continue;
            }
            self.check_conflict(start);
            if self.face_visit[start] == self.stamp {
                out[k] = Region::Covered;
                continue;
            }
            self.face_visit[start] = self.stamp;
            if let Some(s) = self.face_seed.get_mut(start) {
                *s = k as u32;
            }
            // A seed's own patch is measured face by face (its face is taken already).
            if let Some(p) = patches {
                let c = p.clusters.cluster_of[start];
                if c != u32::MAX {
                    self.patch_stamp[c as usize] = self.stamp;
                }
            }
            self.queue.push_back((start as u32, k as u32));
        }
        let mut total: usize = parts
            .iter()
            .zip(&self.regrow)
            .filter(|(_, r)| !**r)
            .map(|(p, _)| p.faces)
            .sum();
        while total < MAX_REGION_FACES {
            let Some((item, k)) = self.queue.pop_front() else {
                break;
            };
            if item & PATCH_BIT != 0 {
                // A patch taken whole: go on from its outside neighbours.
                let Some(p) = patches else { continue };
                let c = &p.clusters.clusters[(item & !PATCH_BIT) as usize];
                for &b in &p.clusters.outside[c.outside.clone()] {
                    self.enter(b, k, parts, ctx, patches, &mut total);
                }
                continue;
            }
            let fi = item as usize;
            let Some((face, cone)) =
                self.measure(f, ctx.normal_from_object, fi, &parts[k as usize])
            else {
                continue;
            };
            let part = &mut parts[k as usize];
            part.cone = part.cone.min(cone);
            part.moments.add(&face);
            part.faces += 1;
            self.taken.push((k, item, face));
            total += 1;
            if total >= MAX_REGION_FACES {
                break;
            }
            for &nb in topo.face_neighbours(fi) {
                self.enter(nb, k, parts, ctx, patches, &mut total);
            }
        }
    }

    /// In a regrowth, notes the seed kept from the first pass that reached face `g` there.
    #[inline]
    fn check_conflict(&mut self, g: usize) {
        if self.first_stamp != 0 && self.face_visit[g] == self.first_stamp {
            let s = self.face_seed[g];
            if !self.regrow[s as usize] {
                self.conflicts.push(s);
            }
        }
    }

    /// Face `g` reached by seed `k`'s growth: queued (stamped) unless already reached;
    /// with patches, its whole patch is taken at once when no face of it was reached and
    /// bounds prove it inside the region.
    fn enter(
        &mut self,
        g: u32,
        k: u32,
        parts: &mut [Part],
        ctx: &GrowContext<'_>,
        patches: Option<&RegionPatches>,
        total: &mut usize,
    ) {
        let gi = g as usize;
        if self.face_visit[gi] == self.stamp {
            // Growths that touch matter only where one of them took whole patches (face
            // by face growths are shared out as the reference shares them).
            let other = self.face_seed.get(gi).copied().unwrap_or(k);
            if other != k {
                self.touched[k as usize] = true;
                self.touched[other as usize] = true;
                if self.whole[k as usize] || self.whole[other as usize] {
                    self.meetings.push((other, k));
                }
            }
            return;
        }
        self.check_conflict(gi);
        self.face_visit[gi] = self.stamp;
        if let Some(s) = self.face_seed.get_mut(gi) {
            *s = k;
        }
        if let Some(p) = patches {
            let c = p.clusters.cluster_of[gi];
            // A patch is decided once per pass, at the first of its faces reached (by any
            // seed): no face of it is stamped before (faces are stamped only here, after
            // the decision, and seeds' patches are decided at the start).
            if c != u32::MAX && self.patch_stamp[c as usize] != self.stamp {
                self.patch_stamp[c as usize] = self.stamp;
                let part = &mut parts[k as usize];
                if self.whole[k as usize]
                    && let Some(m) = p.whole(c as usize, ctx, part)
                {
                    let cluster = &p.clusters.clusters[c as usize];
                    for &h in &p.clusters.faces[cluster.faces.clone()] {
                        self.face_visit[h as usize] = self.stamp;
                        self.face_seed[h as usize] = k;
                    }
                    let count = cluster.faces.len();
                    part.moments.add(&m);
                    part.faces += count;
                    *total += count;
                    self.counts.patches += 1;
                    self.counts.patch_faces += count;
                    self.taken.push((k, c | PATCH_BIT, m));
                    self.queue.push_back((c | PATCH_BIT, k));
                    return;
                }
            }
        }
        self.queue.push_back((g, k));
    }
}

/// Marks a queue or taken entry as a patch (else a face).
const PATCH_BIT: u32 = 1 << 31;

/// Per-frame quantities of a growth that whole patches need.
pub(super) struct GrowContext<'a> {
    pub(super) frame: RegionFrame<'a>,
    pub(super) normal_from_object: Mat3,
    /// The similarity's scale.
    pub(super) scale: f32,
    /// Its linear part and translation, double precision.
    pub(super) linear: glam::DMat3,
    pub(super) translation: glam::DVec3,
}

/// One seed's growing region: its projector frame (n, e_max, e_min), origin, σ, moments.
pub(super) struct Part {
    pub(super) frame: (Vec3, Vec3, Vec3),
    /// Whether the centre has a frame (else it grows nothing).
    valid: bool,
    pub(super) origin: Vec3,
    pub(super) sigma: f32,
    moments: Moments,
    faces: usize,
    cone: f32,
}

impl Part {
    /// The empty region of `centre` at `sigma`.
    fn new(centre: HighlightCentre, sigma: f32) -> Self {
        let n = centre.normal_world;
        let frame = n.try_normalize().and_then(|n| {
            let e_u = (centre.dir_kappa_max - n * n.dot(centre.dir_kappa_max)).try_normalize()?;
            Some((n, e_u, n.cross(e_u)))
        });
        Self {
            frame: frame.unwrap_or((Vec3::Z, Vec3::X, Vec3::Y)),
            valid: frame.is_some(),
            origin: centre.position_world,
            sigma,
            moments: Moments::default(),
            faces: 0,
            cone: 1.0,
        }
    }
}
