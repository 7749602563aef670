//! The region `N·H ≥ σ` a highlight stylizes, measured on the mesh (beyond the paper).
//!
//! Eq. (8) sizes a projector from the principal curvatures at the centre: exact on a
//! sphere, but on a real mesh κ is noisy and the region is not an ellipse, so the paper's
//! footprint misses most of it (recall 0.37–0.80 measured by `cargo xtask bench
//! specular-fidelity`). Here the region itself is grown over the mesh from the centre's
//! face, on the normals the `N = H` search uses (the shaded ones), with `H` per vertex
//! from the light and eye: each face is clipped to the linear interpolant of
//! `N·H − σ ≥ 0`, projected onto the projector's plane (e_max, e_min) and its area
//! moments summed. The footprint is the ellipse with the same moments: centred at the
//! region's centroid, half extent `2·sqrt(variance)` along each axis (a uniform ellipse of
//! half axis `a` has variance `a²/4`), turned towards the moments' own axes when the
//! region is clearly anisotropic.

use glam::{Mat3, Mat4, Vec2, Vec3};
use npr_geometry::{HighlightCentre, LightEye, Topology};
use std::collections::VecDeque;

/// A projector's footprint before the §3.4 controls: the ellipse inscribed in its square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Half extents along the (rotated) `e_max` and `e_min` axes, world units.
    pub half_extent: Vec2,
    /// Offset of the footprint's centre from the `N = H` point along (`e_max`, `e_min`),
    /// world units (zero for Eq. (8)).
    pub offset: Vec2,
    /// Rotation of the footprint's axes about the normal from (`e_max`, `e_min`), radians
    /// (zero for Eq. (8)).
    pub rotate_rad: f32,
    /// Area of the region measured (projected onto the projector plane), world units²;
    /// zero for Eq. (8).
    pub region_area: f32,
    /// Smallest `cos` between the region's normals and the projector's axis (the
    /// region's normal cone; receivers beyond it cannot be in the region); −1 when not
    /// measured (Eq. (8)).
    pub normal_cone_cos: f32,
}

impl Default for Footprint {
    fn default() -> Self {
        Self {
            half_extent: Vec2::ZERO,
            offset: Vec2::ZERO,
            rotate_rad: 0.0,
            region_area: 0.0,
            normal_cone_cos: -1.0,
        }
    }
}

/// What growing a centre's region found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// The centre's face is an earlier centre's: the highlight would stylize a region
    /// another one covers.
    Covered,
    /// The linear interpolant of `N·H − σ` is negative at every vertex of the centre's
    /// face: the region is smaller than a triangle (or absent).
    Empty,
    /// The fitted footprint and the number of faces the region touches.
    Fit(Footprint, usize),
}

/// Reusable per-mesh scratch of [`RegionGrower`]: per-frame vertex values and face
/// ownership, generation-stamped so nothing is cleared per frame.
#[derive(Clone, Debug, Default)]
pub struct RegionGrower {
    frame: u32,
    /// Per vertex, its values this frame (one cache line each: a face reads three).
    vertices: Vec<VertexCache>,
    face_visit: Vec<u32>,
    queue: VecDeque<(u32, u32)>,
    /// Faces classified whole (inside or outside) and on the sub-grid, last frame.
    counts: RegionCounts,
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
    pieces: Vec<Footprint>,
    piece_ranges: Vec<std::ops::Range<usize>>,
    /// Scratch of [`split_bent`].
    along: Vec<(f32, u32)>,
    /// Tests: sample every face on the finest sub-grid with `H` computed at each point
    /// (the reference the classification is compared with).
    #[cfg(test)]
    exact: bool,
}

/// How [`RegionGrower::grow_all`] classified the faces it looked at in its last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegionCounts {
    /// Faces proved inside the region from their vertices alone (added whole).
    pub inside: usize,
    /// Faces proved outside from their vertices alone (skipped).
    pub outside: usize,
    /// Faces the boundary crosses, clipped once by their vertex values.
    pub linear: usize,
    /// Faces the boundary may cross where the field is curved, clipped on the sub-grid.
    pub grid: usize,
    /// Patches taken whole ([`RegionPatches`]) and the faces in them.
    pub patches: usize,
    /// Faces in the patches taken whole.
    pub patch_faces: usize,
    /// Seeds grown again face by face because their regions met another's (so shared out
    /// as without patches).
    pub regrown: usize,
}

/// Everything of the current frame the growth needs.
#[derive(Clone, Copy, Debug)]
pub struct RegionFrame<'a> {
    /// The mesh (object space).
    pub topology: &'a Topology,
    /// Unit vertex normals the search uses, object space.
    pub normals: &'a [Vec3],
    /// Object → world.
    pub world_from_object: Mat4,
    /// Light and eye, world space.
    pub light_eye: LightEye,
}

/// A region is split into pieces along its length ([`RegionGrower::pieces`]) when its
/// moment ellipse is this much larger than the region (an ellipse region reads 1, a
/// rectangle 1.05; a band that bends reads more: the ellipse covers the inside of the
/// bend) ...
pub const SPLIT_AREA_RATIO: f32 = 1.3;
/// ... and the ellipse is at least this elongated.
pub const SPLIT_ELONGATION: f32 = 2.5;
/// Most pieces a region is split into.
pub const MAX_PIECES: usize = 6;

/// Largest number of faces one region may visit (a flat mesh facing the light would
/// otherwise be walked whole every frame; the fit of a truncated region is still its best).
const MAX_REGION_FACES: usize = 200_000;

impl RegionGrower {
    /// A grower that takes whole patches of faces where it can ([`RegionPatches`], built
    /// for the mesh and the normals of the frames it will grow on).
    pub fn with_patches(patches: RegionPatches) -> Self {
        Self {
            patches: Some(std::sync::Arc::new(patches)),
            ..Self::default()
        }
    }

    /// The face patches its whole patches are made of ([`RegionPatches`]), when it has them:
    /// the §4.2 search uses the same ones.
    pub(crate) fn patch_clusters(&self) -> Option<&crate::visibility::FaceClusters> {
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

    /// World position, unit world normal and `N·H` of vertex `v` (cached for the frame).
    #[inline]
    fn vertex(
        &mut self,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        v: usize,
    ) -> (Vec3, Vec3, f32) {
        if self.vertices[v].frame != self.frame {
            self.compute_vertex(f, normal_from_object, v);
        }
        let c = &self.vertices[v];
        (c.world, c.normal, c.nh)
    }

    #[inline(never)]
    fn compute_vertex(&mut self, f: &RegionFrame<'_>, normal_from_object: Mat3, v: usize) {
        let p = f
            .world_from_object
            .transform_point3(f.topology.positions[v]);
        let n = (normal_from_object * f.normals.get(v).copied().unwrap_or(Vec3::ZERO))
            .normalize_or_zero();
        // H and, for a point light and eye, the distances to them and |L̂ + V̂| (one
        // square root each).
        let (h, dist) = match f.light_eye {
            LightEye::Positions { light, eye } => {
                let (l, e) = (light - p, eye - p);
                let (dl, de) = (l.length(), e.length());
                let s = l / dl + e / de;
                let ds = s.length();
                let h = if dl > 0.0 && de > 0.0 && ds > 0.0 && ds.is_finite() {
                    s / ds
                } else {
                    half_vector(f.light_eye, p)
                };
                (h, [dl, de, ds])
            }
            LightEye::Directions { .. } => (half_vector(f.light_eye, p), [0.0; 3]),
        };
        let nh = n.dot(h);
        self.vertices[v] = VertexCache {
            frame: self.frame,
            nh: if nh.is_finite() { nh } else { -1.0 },
            world: p,
            normal: n,
            h,
            dist,
        };
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
        // Whole patches only under a similarity (cones keep their angles) and for this mesh.
        let patches = self
            .patches
            .clone()
            .filter(|p| p.clusters.face_count == topo.face_count() && is_similarity(m3));
        if let Some(p) = &patches {
            if self.patch_stamp.len() != p.patches.len() {
                self.patch_stamp = vec![0; p.patches.len()];
            }
            if self.face_seed.len() != topo.face_count() {
                self.face_seed = vec![0; topo.face_count()];
                self.face_hint = vec![0; topo.face_count()];
            }
        }
        let patches = patches.as_deref();
        let mut parts: Vec<Part> = seeds.iter().map(|s| Part::new(s.0, s.1)).collect();
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
            patches.is_some()
                && self
                    .face_hint
                    .get(s.0.face as usize)
                    .is_none_or(|&h| h != last || last == 0)
        }));
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
                self.grow_pass(seeds, &ctx, None, &mut out, &mut parts);
                if self.conflicts.is_empty() {
                    self.counts.regrown = self.regrow.iter().filter(|r| **r).count();
                    break;
                }
                for k in std::mem::take(&mut self.conflicts) {
                    self.regrow[k as usize] = true;
                }
            }
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
        // The faces of regions that met another are hinted for the next frame.
        if let Some(p) = patches {
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
        // Whole patches' normal cones: the exact smallest cos over their vertices where
        // the patch's bound does not already clear the part's cone.
        let mut t = 0;
        while t < self.taken.len() {
            let (k, item, _) = self.taken[t];
            t += 1;
            let (Some(p), true) = (patches, item & PATCH_BIT != 0) else {
                continue;
            };
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
        for (k, part) in parts.iter().enumerate() {
            if out[k] == Region::Empty && part.faces > 0 {
                if let Some(fp) = part.moments.footprint() {
                    let fp = Footprint {
                        normal_cone_cos: part.cone,
                        ..fp
                    };
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
                        self.piece_ranges[k] = start..self.pieces.len();
                    }
                }
            }
        }
        out
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

    /// Measures face `fi` against seed `part`'s region: its moments and the smallest cos
    /// of its normals (where in the region) with the axis, or `None` when the region does
    /// not take it (facing away, degenerate or outside; the growth stops there).
    fn measure(
        &mut self,
        f: &RegionFrame<'_>,
        normal_from_object: Mat3,
        fi: usize,
        part: &Part,
    ) -> Option<(Moments, f32)> {
        let topo = f.topology;
        let (n, e_u, e_v) = part.frame;
        if topo.is_degenerate(fi) || (normal_from_object * topo.face_normals[fi]).dot(n) <= 0.0 {
            return None;
        }
        let tri = topo.triangles[fi];
        let vs = [
            self.vertex(f, normal_from_object, tri[0] as usize),
            self.vertex(f, normal_from_object, tri[1] as usize),
            self.vertex(f, normal_from_object, tri[2] as usize),
        ];
        let (sigma, origin) = (part.sigma, part.origin);
        let project = |p: Vec3| {
            let q = p - origin;
            Vec2::new(q.dot(e_u), q.dot(e_v))
        };
        let dists = [
            self.vertices[tri[0] as usize].dist,
            self.vertices[tri[1] as usize].dist,
            self.vertices[tri[2] as usize].dist,
        ];
        // Longest edge, world units, from the cached vertices (one square root).
        let reach = vs[0]
            .0
            .distance_squared(vs[1].0)
            .max(vs[1].0.distance_squared(vs[2].0))
            .max(vs[2].0.distance_squared(vs[0].0))
            .sqrt();
        let class = classify(f.light_eye, &vs, &dists, reach, sigma);
        #[cfg(test)]
        let class = if self.exact {
            FaceClass::Grid {
                steps: SUB,
                delta: f32::INFINITY,
            }
        } else {
            class
        };
        let mut face = Moments::default();
        let vertex_cone = || vs.iter().fold(1f32, |m, v| m.min(v.1.dot(n)));
        match class {
            FaceClass::Outside => {
                self.counts.outside += 1;
                None
            }
            FaceClass::Inside => {
                // The whole face: its moments at once; the normalised interpolant's
                // cos with the axis is at least the vertices' smallest.
                self.counts.inside += 1;
                let [a, b, c] = vs.map(|v| project(v.0));
                face.add_triangle(a, b, c);
                Some((face, vertex_cone()))
            }
            FaceClass::Linear => {
                self.counts.linear += 1;
                let tri = vs.map(|v| (project(v.0), v.2 - sigma));
                if tri.iter().all(|t| t.1 < 0.0) {
                    return None;
                }
                face.add_clipped(tri);
                Some((face, vertex_cone()))
            }
            FaceClass::Grid { steps, delta } => {
                // The face on a sub-grid of `steps` per edge, as the GPU shades it:
                // interpolated and normalised normal, H at the point (interpolated
                // from the vertices' where it turns little over the face: its
                // departure from linear is then second order); `N·H − σ` linear on
                // each sub-triangle.
                self.counts.grid += 1;
                let hs = [
                    self.vertices[tri[0] as usize].h,
                    self.vertices[tri[1] as usize].h,
                    self.vertices[tri[2] as usize].h,
                ];
                let qs = [project(vs[0].0), project(vs[1].0), project(vs[2].0)];
                let exact_h = delta > EXACT_H_TURN;
                // With H interpolated, u = Σ bᵢNᵢ and h = Σ bⱼHⱼ give
                // u·h = bᵀ(Nᵢ·Hⱼ)b and |u|² = bᵀ(Nᵢ·Nⱼ)b: nine and six dots per face
                // instead of vector work per point.
                let (n0, n1, n2) = (vs[0].1, vs[1].1, vs[2].1);
                let nh = [
                    [n0.dot(hs[0]), n0.dot(hs[1]), n0.dot(hs[2])],
                    [n1.dot(hs[0]), n1.dot(hs[1]), n1.dot(hs[2])],
                    [n2.dot(hs[0]), n2.dot(hs[1]), n2.dot(hs[2])],
                ];
                let (g01, g12, g20) = (n0.dot(n1), n1.dot(n2), n2.dot(n0));
                let nn = [
                    [n0.length_squared(), g01, g20],
                    [g01, n1.length_squared(), g12],
                    [g20, g12, n2.length_squared()],
                ];
                let na = [n0.dot(n), n1.dot(n), n2.dot(n)];
                let mut grid = [(Vec2::ZERO, 0f32); GRID_POINTS];
                let mut any = false;
                let mut cone = 1f32;
                let inv = 1.0 / steps as f32;
                for (g, (i, j)) in grid_points(steps).enumerate() {
                    let (b1, b2) = (i as f32 * inv, j as f32 * inv);
                    let b = [1.0 - b1 - b2, b1, b2];
                    let quad = |m: &[[f32; 3]; 3]| {
                        b[0] * (b[0] * m[0][0] + b[1] * m[0][1] + b[2] * m[0][2])
                            + b[1] * (b[0] * m[1][0] + b[1] * m[1][1] + b[2] * m[1][2])
                            + b[2] * (b[0] * m[2][0] + b[1] * m[2][1] + b[2] * m[2][2])
                    };
                    let len2 = quad(&nn);
                    let inv_len = if len2 > 0.0 { len2.sqrt().recip() } else { 0.0 };
                    let d = if exact_h {
                        let p = vs[0].0 * b[0] + vs[1].0 * b[1] + vs[2].0 * b[2];
                        let u = vs[0].1 * b[0] + vs[1].1 * b[1] + vs[2].1 * b[2];
                        u.dot(half_vector(f.light_eye, p)) * inv_len - sigma
                    } else {
                        quad(&nh) * inv_len - sigma
                    };
                    let d = if d.is_finite() { d } else { -1.0 };
                    if d >= 0.0 {
                        any = true;
                        cone = cone.min((b[0] * na[0] + b[1] * na[1] + b[2] * na[2]) * inv_len);
                    }
                    grid[g] = (qs[0] * b[0] + qs[1] * b[1] + qs[2] * b[2], d);
                }
                if !any {
                    return None;
                }
                for_sub_triangles(steps, |a, b, c| {
                    face.add_clipped([grid[a], grid[b], grid[c]]);
                });
                Some((face, cone))
            }
        }
    }

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

/// Marks a queue or taken entry as a patch (else a face).
const PATCH_BIT: u32 = 1 << 31;

/// Per-frame quantities of a growth that whole patches need.
struct GrowContext<'a> {
    frame: RegionFrame<'a>,
    normal_from_object: Mat3,
    /// The similarity's scale.
    scale: f32,
    /// Its linear part and translation, double precision.
    linear: glam::DMat3,
    translation: glam::DVec3,
}

/// Whether a linear map is a similarity (orthogonal columns of one length).
fn is_similarity(m: Mat3) -> bool {
    let cols = [m.x_axis, m.y_axis, m.z_axis];
    let k = cols[0].length();
    k > 0.0
        && cols.iter().all(|c| (c.length() - k).abs() <= 1e-5 * k)
        && cols[0].dot(cols[1]).abs() <= 1e-5 * k * k
        && cols[1].dot(cols[2]).abs() <= 1e-5 * k * k
        && cols[2].dot(cols[0]).abs() <= 1e-5 * k * k
}

/// Faces per patch of [`RegionPatches`] (at most): small enough that most of a
/// highlight's interior is whole patches on a 70k-face scan, large enough that a
/// million-face region is a few hundred. A [`crate::HighlightSet`]'s §4.2 search walks the
/// same patches.
pub const REGION_PATCH_FACES: usize = 16;

/// Connected patches of a mesh's faces ([`crate::visibility::FaceClusters`] of
/// [`REGION_PATCH_FACES`]) with what [`RegionGrower::grow_all`] needs to take one whole
/// (beyond the paper): the cones of its vertex and face normals, and its area moments as
/// tensors in object space, from which the moments of its projection onto any plane
/// under any similarity follow exactly. Built once per mesh and normal field.
#[derive(Clone, Debug, Default)]
pub struct RegionPatches {
    clusters: crate::visibility::FaceClusters,
    patches: Vec<PatchBounds>,
}

/// One patch's bounds and moment tensors (object space, about `centre`).
#[derive(Clone, Copy, Debug)]
struct PatchBounds {
    /// Unit axis of its vertex normals' cone, and sin and cos of the cone's half angle.
    normal_axis: Vec3,
    normal_spread: (f32, f32),
    /// Unit axis of its face normals' cone and sin of the cone's half angle.
    face_axis: Vec3,
    face_sin: f32,
    centre: Vec3,
    radius: f32,
    usable: bool,
    /// `Σ v_f` with `v_f` a face's vector area.
    area: glam::DVec3,
    /// `first[k] = Σ v_f[k] c_f`, `c_f` the face's centroid.
    first: [glam::DVec3; 3],
    /// `second[k] = Σ v_f[k] K_f`, `K_f = (Σ pᵢpᵢᵀ + P Pᵀ)/12` per unit area (`P = Σ pᵢ`),
    /// as (xx, xy, xz, yy, yz, zz).
    second: [[f64; 6]; 3],
}

impl RegionPatches {
    /// The patches of `topology` with the vertex `normals` the growth uses.
    pub fn new(topology: &Topology, normals: &[Vec3]) -> Self {
        use glam::DVec3;
        let clusters = crate::visibility::FaceClusters::with_size(topology, REGION_PATCH_FACES);
        let patches = clusters
            .clusters
            .iter()
            .map(|c| {
                let faces = &clusters.faces[c.faces.clone()];
                let mut sum = Vec3::ZERO;
                let mut valid = true;
                let unit = |v: u32| {
                    normals
                        .get(v as usize)
                        .copied()
                        .unwrap_or(Vec3::ZERO)
                        .normalize_or_zero()
                };
                for &g in faces {
                    for v in topology.triangles[g as usize] {
                        let n = unit(v);
                        valid &= n != Vec3::ZERO && n.is_finite();
                        sum += n;
                    }
                }
                let axis = sum.normalize_or_zero();
                let spread = faces
                    .iter()
                    .flat_map(|&g| topology.triangles[g as usize])
                    .map(|v| {
                        let n = unit(v);
                        n.cross(axis).length().atan2(n.dot(axis))
                    })
                    .fold(0f32, f32::max)
                    + 1e-4;
                let c0 = c.centre.as_dvec3();
                let (mut area, mut first, mut second) =
                    (DVec3::ZERO, [DVec3::ZERO; 3], [[0f64; 6]; 3]);
                for &g in faces {
                    let d = topology.triangles[g as usize]
                        .map(|v| topology.positions[v as usize].as_dvec3() - c0);
                    let v = 0.5 * (d[1] - d[0]).cross(d[2] - d[0]);
                    let p = d[0] + d[1] + d[2];
                    let centroid = p / 3.0;
                    // q qᵀ as (xx, xy, xz, yy, yz, zz).
                    let outer = |q: DVec3| {
                        [
                            q.x * q.x,
                            q.x * q.y,
                            q.x * q.z,
                            q.y * q.y,
                            q.y * q.z,
                            q.z * q.z,
                        ]
                    };
                    let mut kf = [0f64; 6];
                    for q in [d[0], d[1], d[2], p] {
                        for (x, y) in kf.iter_mut().zip(outer(q)) {
                            *x += y / 12.0;
                        }
                    }
                    area += v;
                    for k in 0..3 {
                        first[k] += centroid * v[k];
                        for (x, y) in second[k].iter_mut().zip(kf) {
                            *x += v[k] * y;
                        }
                    }
                }
                PatchBounds {
                    normal_axis: axis,
                    normal_spread: spread.min(std::f32::consts::PI).sin_cos(),
                    face_axis: c.axis,
                    face_sin: (c.spread + 1e-4).min(std::f32::consts::FRAC_PI_2).sin(),
                    centre: c.centre,
                    radius: c.radius,
                    usable: c.usable
                        && valid
                        && axis != Vec3::ZERO
                        && spread < std::f32::consts::FRAC_PI_2
                        && area.is_finite(),
                    area,
                    first,
                    second,
                }
            })
            .collect();
        Self { clusters, patches }
    }

    /// Patch `c`'s moments projected onto `part`'s plane, when every point of it is
    /// provably in `part`'s region (`N̂·H ≥ σ` for every interpolated normal `N̂`, within
    /// the vertex normals' cone, and every `H` over its bounding sphere) and every face
    /// faces the axis; else `None`.
    fn whole(&self, c: usize, ctx: &GrowContext<'_>, part: &Part) -> Option<Moments> {
        let p = &self.patches[c];
        let (n, e_u, e_v) = part.frame;
        if !p.usable || part.sigma.is_nan() || part.sigma < 0.0 {
            return None;
        }
        let m = ctx.normal_from_object;
        if (m * p.face_axis).normalize_or_zero().dot(n) <= p.face_sin + PATCH_MARGIN {
            return None;
        }
        let centre = ctx.frame.world_from_object.transform_point3(p.centre);
        let r = p.radius * ctx.scale;
        let h = half_vector(ctx.frame.light_eye, centre);
        // How far H turns over the patch's bounding sphere (see `classify`).
        let delta = match ctx.frame.light_eye {
            LightEye::Directions { .. } => 0.0,
            LightEye::Positions { light, eye } => {
                let turn = |d: f32| if d > 2.0 * r { r / (d - r) } else { 2.0 };
                let (l, e) = (light - centre, eye - centre);
                let ds = turn(l.length()) + turn(e.length());
                let s = (l.normalize_or_zero() + e.normalize_or_zero()).length();
                if s - ds > 1e-3 { ds / (s - ds) } else { 2.0 }
            }
        };
        let axis = (m * p.normal_axis).normalize_or_zero();
        let cos = axis.dot(h).clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (ss, cs) = p.normal_spread;
        let lowest = cos * cs - sin * ss;
        let inside = lowest - delta >= part.sigma + PATCH_MARGIN; // false for NaN
        if !inside {
            return None;
        }
        // q = A p + b on the plane, A = (e_u, e_v)ᵀ L, b = (e_u, e_v)ᵀ (M c₀ − origin).
        let (eu, ev) = (e_u.as_dvec3(), e_v.as_dvec3());
        let lt = ctx.linear.transpose();
        let (a1, a2) = (lt * eu, lt * ev);
        let w = ctx.linear * p.centre.as_dvec3() + ctx.translation - part.origin.as_dvec3();
        let (bx, by) = (w.dot(eu), w.dot(ev));
        let mk = a1.cross(a2);
        let area = mk.dot(p.area);
        let f3 = p.first[0] * mk.x + p.first[1] * mk.y + p.first[2] * mk.z;
        let mut k3 = [0f64; 6];
        for (k, &mk) in mk.to_array().iter().enumerate() {
            for (x, y) in k3.iter_mut().zip(p.second[k]) {
                *x += mk * y;
            }
        }
        let quad = |a: glam::DVec3, b: glam::DVec3| {
            a.x * (k3[0] * b.x + k3[1] * b.y + k3[2] * b.z)
                + a.y * (k3[1] * b.x + k3[3] * b.y + k3[4] * b.z)
                + a.z * (k3[2] * b.x + k3[4] * b.y + k3[5] * b.z)
        };
        let (f1, f2) = (a1.dot(f3), a2.dot(f3));
        Some(Moments {
            area,
            first: [f1 + bx * area, f2 + by * area],
            second: [
                quad(a1, a1) + 2.0 * f1 * bx + bx * bx * area,
                quad(a1, a2) + f1 * by + bx * f2 + bx * by * area,
                quad(a2, a2) + 2.0 * f2 * by + by * by * area,
            ],
        })
    }
}

impl PatchBounds {
    /// A lower bound on the cos between any of the patch's vertex normals (world) and
    /// `n`.
    fn cone_bound(&self, normal_from_object: Mat3, n: Vec3) -> f32 {
        let axis = (normal_from_object * self.normal_axis).normalize_or_zero();
        let cos = axis.dot(n).clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (ss, cs) = self.normal_spread;
        cos * cs - sin * ss - PATCH_MARGIN
    }
}

/// Float slack of the whole-patch tests (cosine units).
const PATCH_MARGIN: f32 = 1e-4;

/// Whether a region fitted by `whole` is a long bent band to split ([`split_bent`]).
fn needs_split(whole: &Footprint) -> bool {
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
fn split_bent(
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
    for &(_, i) in along.iter() {
        let m = &taken[i as usize].2;
        piece.add(m);
        if piece.area >= total * cut as f64 / count as f64 - 1e-12 * total && cut < count {
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

/// A vertex's values in one frame of [`RegionGrower`].
#[derive(Clone, Copy, Debug, Default)]
struct VertexCache {
    /// The frame they belong to.
    frame: u32,
    /// `N_v·H(p_v)`.
    nh: f32,
    /// World position, unit world normal and unit `H(p_v)`.
    world: Vec3,
    normal: Vec3,
    h: Vec3,
    /// Distances to the light and the eye and `|L̂ + V̂|` (point light and eye; zero for
    /// directions).
    dist: [f32; 3],
}

/// One seed's growing region: its projector frame (n, e_max, e_min), origin, σ, moments.
struct Part {
    frame: (Vec3, Vec3, Vec3),
    /// Whether the centre has a frame (else it grows nothing).
    valid: bool,
    origin: Vec3,
    sigma: f32,
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

/// Sub-grid of a face: `SUB` steps per edge.
const SUB: usize = 4;
const GRID_POINTS: usize = (SUB + 1) * (SUB + 2) / 2;

/// Index of grid point (i, j) (i + j ≤ `steps`) in the order of [`grid_points`].
const fn grid_index(steps: usize, i: usize, j: usize) -> usize {
    // Row i starts after rows 0..i of steps + 1 − r points each.
    i * (2 * steps + 3 - i) / 2 + j
}

/// The points (i, j), i + j ≤ `steps`, of a face's sub-grid, row by row.
fn grid_points(steps: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..=steps).flat_map(move |i| (0..=steps - i).map(move |j| (i, j)))
}

/// Calls `f` with the grid indices of every sub-triangle of a `steps` sub-grid, in the
/// face's orientation.
fn for_sub_triangles(steps: usize, mut f: impl FnMut(usize, usize, usize)) {
    let at = |i, j| grid_index(steps, i, j);
    for i in 0..steps {
        for j in 0..steps - i {
            let (a, b, c) = (at(i, j), at(i + 1, j), at(i, j + 1));
            f(a, b, c);
            if i + j + 1 < steps {
                f(b, at(i + 1, j + 1), c);
            }
        }
    }
}

/// Where a face lies against the region `N·H ≥ σ`, from its vertices alone, and how it
/// must be measured.
#[derive(Clone, Copy, Debug, PartialEq)]
enum FaceClass {
    /// Every point is in the region: added whole.
    Inside,
    /// No point is: skipped.
    Outside,
    /// The boundary crosses it, and `N·H − σ` is linear in it to within
    /// [`LINEAR_TOLERANCE`] of its range: clipped once by the vertex values.
    Linear,
    /// The boundary may cross it and the field is too curved there (a region no bigger
    /// than a few faces): sampled on a sub-grid of `steps` per edge; `delta` bounds how
    /// far `H` turns over the face.
    Grid {
        /// Sub-grid steps per edge, 2 to [`SUB`].
        steps: usize,
        /// Bound on the turn of `H` over the face (radians, about).
        delta: f32,
    },
}

/// Above this bound on how far `H` turns over a face (near the light or the eye), the
/// sub-grid computes `H` at each point instead of interpolating the vertices'.
const EXACT_H_TURN: f32 = 0.05;

/// Largest deviation of `N·H` from the linear interpolant of its vertex values, as a
/// fraction of their range, for a face to be clipped by the vertex values alone: the
/// boundary is then placed within about 5 % of the face (the 4-step sub-grid's own
/// resolution is a quarter of it).
const LINEAR_TOLERANCE: f32 = 0.05;

/// Classifies a face (world position, unit normal and `N·H` per vertex) by bounds that
/// hold at every point of it. With `u = Σ bᵢ Nᵢ` the interpolated normal (`|u| ≤ 1`),
/// `c ≥ 0` the smallest `Nᵢ·Nⱼ` (so `|u|² = Σ bᵢbⱼ Nᵢ·Nⱼ ≥ c + (1 − c) Σ bᵢ² ≥
/// (1 + 2c)/3`) and `δ` a bound on how far `H` turns over the face:
/// - inside when `σ ≥ 0` and `min Nᵢ·Hᵢ − δ ≥ σ`, since then `u·H ≥ 0` and
///   `N̂·H = u·H/|u| ≥ u·H ≥ Σ bᵢ Nᵢ·Hᵢ − δ`;
/// - `N̂·H` departs from the interpolant `Σ bᵢ Nᵢ·Hᵢ` by the normalisation,
///   `≤ 1/|u| − 1`, and by `Σ bᵢ Nᵢ·(H(p) − Hᵢ)`, whose first-order part
///   `N₀·J Σ bᵢ (p − pᵢ)` vanishes, leaving `≤ max|Nᵢ − N₀| δ + 2δ²` (the second-order
///   part of `L̂` over a face, about `1.5 (r/d)²`, is within `2δ²`); so the face is
///   outside when `max Nᵢ·Hᵢ + ε < σ`, and the interpolant is trusted when that `ε` is
///   small against the vertex values' range.
fn classify(
    light_eye: LightEye,
    vs: &[(Vec3, Vec3, f32); 3],
    dists: &[[f32; 3]; 3],
    reach: f32,
    sigma: f32,
) -> FaceClass {
    let lo = vs[0].2.min(vs[1].2).min(vs[2].2);
    let hi = vs[0].2.max(vs[1].2).max(vs[2].2);
    let delta = match light_eye {
        LightEye::Directions { .. } => 0.0,
        LightEye::Positions { .. } => {
            // |ΔL̂| ≤ r/(d − r) for points within r (the longest edge) of a vertex at
            // distance d; Ĥ = S/|S| turns by at most |ΔS|/(|S| − |ΔS|).
            let r = reach;
            let turn = |d: f32| if d > 2.0 * r { r / (d - r) } else { 2.0 };
            let min = |k: usize| dists[0][k].min(dists[1][k]).min(dists[2][k]);
            let ds = turn(min(0)) + turn(min(1));
            let s = min(2);
            if s - ds > 1e-3 { ds / (s - ds) } else { 2.0 }
        }
    };
    let finest = FaceClass::Grid {
        steps: SUB,
        delta: f32::INFINITY,
    };
    if !delta.is_finite() || !lo.is_finite() || !hi.is_finite() {
        return finest;
    }
    // (u·H ≥ 0 there, which the first bound needs, since σ ≥ 0.)
    if sigma >= 0.0 && lo - delta >= sigma {
        return FaceClass::Inside;
    }
    let c = vs[0]
        .1
        .dot(vs[1].1)
        .min(vs[1].1.dot(vs[2].1))
        .min(vs[2].1.dot(vs[0].1));
    if c.is_nan() || c <= 0.0 {
        return FaceClass::Grid { steps: SUB, delta };
    }
    let eps = 1.0 / ((1.0 + 2.0 * c) / 3.0).sqrt() - 1.0
        + delta * ((2.0 * (1.0 - c)).max(0.0).sqrt() + 2.0 * delta);
    if hi + eps < sigma {
        FaceClass::Outside
    } else if eps <= LINEAR_TOLERANCE * (hi - lo) {
        FaceClass::Linear
    } else {
        // The interpolant's error falls as 1/steps² on a sub-grid.
        let need = (eps / (LINEAR_TOLERANCE * (hi - lo)).max(f32::MIN_POSITIVE)).sqrt();
        FaceClass::Grid {
            steps: if need <= 2.0 {
                2
            } else if need <= 3.0 {
                3
            } else {
                SUB
            },
            delta,
        }
    }
}

/// The unit half vector `H` at world point `p`.
fn half_vector(light_eye: LightEye, p: Vec3) -> Vec3 {
    match light_eye {
        LightEye::Positions { light, eye } => {
            (light - p).normalize_or_zero() + (eye - p).normalize_or_zero()
        }
        LightEye::Directions { to_light, to_eye } => {
            to_light.normalize_or_zero() + to_eye.normalize_or_zero()
        }
    }
    .normalize_or_zero()
}

/// Area moments of a planar region (area, first and second moments about the origin).
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    area: f64,
    first: [f64; 2],
    /// (xx, xy, yy)
    second: [f64; 3],
}

impl Moments {
    /// Adds another region's moments (disjoint regions).
    fn add(&mut self, other: &Moments) {
        self.area += other.area;
        for (a, b) in self.first.iter_mut().zip(&other.first) {
            *a += b;
        }
        for (a, b) in self.second.iter_mut().zip(&other.second) {
            *a += b;
        }
    }

    /// Adds a triangle (counter-clockwise seen from the normal for positive area).
    fn add_triangle(&mut self, a: Vec2, b: Vec2, c: Vec2) {
        let (a, b, c) = (a.as_dvec2(), b.as_dvec2(), c.as_dvec2());
        let area = 0.5 * (b - a).perp_dot(c - a);
        let s = a + b + c;
        self.area += area;
        self.first[0] += area * s.x / 3.0;
        self.first[1] += area * s.y / 3.0;
        // ∫ x xᵀ dA = A/12 · (Σ vᵢvᵢᵀ + s sᵀ) over a triangle.
        let k = area / 12.0;
        self.second[0] += k * (a.x * a.x + b.x * b.x + c.x * c.x + s.x * s.x);
        self.second[1] += k * (a.x * a.y + b.x * b.y + c.x * c.y + s.x * s.y);
        self.second[2] += k * (a.y * a.y + b.y * b.y + c.y * c.y + s.y * s.y);
    }

    /// Adds the part of the triangle where the linear interpolant of the values `≥ 0`.
    fn add_clipped(&mut self, tri: [(Vec2, f32); 3]) {
        let mut poly: [Vec2; 4] = [Vec2::ZERO; 4];
        let mut len = 0;
        for k in 0..3 {
            let (p, dp) = tri[k];
            let (q, dq) = tri[(k + 1) % 3];
            if dp >= 0.0 {
                poly[len] = p;
                len += 1;
            }
            if (dp >= 0.0) != (dq >= 0.0) && len < 4 {
                let t = dp / (dp - dq);
                poly[len] = p + (q - p) * t;
                len += 1;
            }
        }
        for k in 1..len.saturating_sub(1) {
            self.add_triangle(poly[0], poly[k], poly[k + 1]);
        }
    }

    /// The ellipse with these moments (see the module docs); `None` for an empty or
    /// degenerate region.
    fn footprint(&self) -> Option<Footprint> {
        if self.area.is_nan() || self.area <= 1e-20 {
            return None;
        }
        let mx = self.first[0] / self.area;
        let my = self.first[1] / self.area;
        let cxx = (self.second[0] / self.area - mx * mx).max(0.0);
        let cxy = self.second[1] / self.area - mx * my;
        let cyy = (self.second[2] / self.area - my * my).max(0.0);
        // The moments' axis nearest to e_max, within ±45°.
        let mut theta = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        let quarter = std::f64::consts::FRAC_PI_2;
        if theta > quarter / 2.0 {
            theta -= quarter;
        } else if theta < -quarter / 2.0 {
            theta += quarter;
        }
        // Turn only for a clearly anisotropic region: near-isotropic moments have unstable
        // axes, and a turning texture would flicker.
        let spread = ((cxx - cyy).powi(2) + 4.0 * cxy * cxy).sqrt() / (cxx + cyy).max(1e-30);
        let t = ((spread - 0.05) / 0.15).clamp(0.0, 1.0);
        let theta = theta * t * t * (3.0 - 2.0 * t);
        let (s, c) = theta.sin_cos();
        let var_u = cxx * c * c + 2.0 * cxy * s * c + cyy * s * s;
        let var_v = cxx * s * s - 2.0 * cxy * s * c + cyy * c * c;
        let offset = glam::DVec2::new(mx, my);
        let half = Vec2::new(
            (2.0 * var_u.max(0.0).sqrt()) as f32,
            (2.0 * var_v.max(0.0).sqrt()) as f32,
        );
        let fp = Footprint {
            half_extent: half,
            offset: offset.as_vec2(),
            rotate_rad: theta as f32,
            region_area: self.area as f32,
            normal_cone_cos: -1.0,
        };
        (half.min_element() > 0.0 && fp.offset.is_finite() && half.is_finite()).then_some(fp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use npr_geometry::HighlightSearch;

    /// The bunny scan of the fixtures.
    fn bunny() -> npr_geometry::Mesh {
        let path = format!(
            "{}/../../fixtures/meshes/stanford-bunny.obj",
            env!("CARGO_MANIFEST_DIR")
        );
        npr_geometry::load_obj(&path).unwrap()
    }

    /// `mesh`'s topology and highlight search, and the centre and radius of its bounds.
    fn prepared(mesh: &npr_geometry::Mesh) -> (Topology, HighlightSearch, Vec3, f32) {
        use npr_geometry::{CurvatureField, CurvatureOptions};
        let (welded, topo, field) = CurvatureField::for_mesh(mesh, &CurvatureOptions::default());
        let search = HighlightSearch::for_mesh(mesh, &welded, &topo, &field);
        let (lo, hi) = topo.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        (topo, search, (lo + hi) * 0.5, (hi - lo).length() * 0.5)
    }

    /// A point light and eye around the object at angle `a`.
    fn point_light(a: f32) -> LightEye {
        LightEye::Positions {
            light: Vec3::new(20.0 * a.cos(), 30.0, 20.0 * a.sin()),
            eye: Vec3::new(3.0 * (a + 0.4).sin(), 0.5, 3.0 * (a + 0.4).cos()),
        }
    }

    /// The growth frame of `topo` with `search`'s normals.
    fn frame_of<'a>(
        topo: &'a Topology,
        search: &'a HighlightSearch,
        world_from_object: Mat4,
        light_eye: LightEye,
    ) -> RegionFrame<'a> {
        RegionFrame {
            topology: topo,
            normals: search.normals(),
            world_from_object,
            light_eye,
        }
    }

    /// Regions `a` and `b` grown with and without whole patches agree: the same faces,
    /// footprint to float precision and normal cone (or the same non-fit).
    fn assert_same_region(a: Region, b: Region, what: &str) {
        match (a, b) {
            (Region::Fit(p, n), Region::Fit(q, m)) => {
                assert_eq!(n, m, "faces of {what}");
                let size = p.half_extent.max_element();
                assert!(
                    (p.region_area - q.region_area).abs() <= 1e-4 * p.region_area,
                    "{what}: {p:?} vs {q:?}"
                );
                assert!(
                    (p.half_extent - q.half_extent).abs().max_element() <= 1e-3 * size,
                    "{what}: {p:?} vs {q:?}"
                );
                assert!(
                    (p.offset - q.offset).length() <= 1e-3 * size,
                    "{what}: {p:?} vs {q:?}"
                );
                assert_eq!(p.normal_cone_cos, q.normal_cone_cos, "{what}");
            }
            (a, b) => assert_eq!(a, b, "{what}"),
        }
    }

    #[test]
    fn moments_of_a_square_and_its_clipped_half() {
        let mut m = Moments::default();
        let (a, b, c, d) = (
            Vec2::new(-1.0, -1.0),
            Vec2::new(1.0, -1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, 1.0),
        );
        m.add_triangle(a, b, c);
        m.add_triangle(a, c, d);
        assert!((m.area - 4.0).abs() < 1e-9);
        // Var of a uniform [−1, 1] is 1/3.
        assert!((m.second[0] / m.area - 1.0 / 3.0).abs() < 1e-9);
        assert!(m.second[1].abs() < 1e-9);
        // Clip by x ≥ 0: values = x.
        let mut h = Moments::default();
        h.add_clipped([(a, a.x), (b, b.x), (c, c.x)]);
        h.add_clipped([(a, a.x), (c, c.x), (d, d.x)]);
        assert!((h.area - 2.0).abs() < 1e-6, "{}", h.area);
        assert!((h.first[0] / h.area - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_sub_grid_tiles_the_face_once() {
        for steps in 1..=SUB {
            let mut area = 0.0;
            let mut count = 0;
            let pts: Vec<Vec2> = grid_points(steps)
                .map(|(i, j)| Vec2::new(i as f32, j as f32))
                .collect();
            assert_eq!(pts.len(), (steps + 1) * (steps + 2) / 2);
            for (g, (i, j)) in grid_points(steps).enumerate() {
                assert_eq!(grid_index(steps, i, j), g);
            }
            for_sub_triangles(steps, |a, b, c| {
                let t = 0.5 * (pts[b] - pts[a]).perp_dot(pts[c] - pts[a]);
                assert!(t > 0.0, "orientation");
                area += t;
                count += 1;
            });
            assert_eq!(count, steps * steps);
            assert!((area - 0.5 * (steps * steps) as f32).abs() < 1e-4);
        }
    }

    #[test]
    fn an_ellipse_gets_its_own_half_axes() {
        // A polygonal ellipse of half axes 3 × 1, turned by 0.5 rad.
        let mut m = Moments::default();
        let k = 720;
        let (s, c) = 0.5f32.sin_cos();
        let pt = |i: usize| {
            let t = i as f32 / k as f32 * std::f32::consts::TAU;
            let (x, y) = (3.0 * t.cos(), t.sin());
            Vec2::new(x * c - y * s, x * s + y * c) + Vec2::new(0.2, -0.1)
        };
        for i in 0..k {
            m.add_triangle(Vec2::new(0.2, -0.1), pt(i), pt(i + 1));
        }
        let fp = m.footprint().unwrap();
        assert!((fp.rotate_rad - 0.5).abs() < 1e-3, "{fp:?}");
        assert!(
            (fp.half_extent - Vec2::new(3.0, 1.0)).length() < 1e-2,
            "{fp:?}"
        );
        assert!((fp.offset - Vec2::new(0.2, -0.1)).length() < 1e-4, "{fp:?}");
    }

    #[test]
    fn whole_patches_take_the_faces_and_moments_face_by_face_takes() {
        // The same region grown with whole patches (moments from the patch tensors) and
        // face by face: the same faces, the same footprint to float precision, the same
        // normal cone, on a scan (the bunny), a sphere and a torus, point light and eye,
        // several views and a scaled, turned object, one seed at a time.
        let bunny = bunny();
        let sphere = npr_geometry::generate::icosphere(5, 1.0);
        let torus = npr_geometry::generate::torus(1.0, 0.45, 120, 48);
        let (mut compared, mut whole) = (0, 0);
        for mesh in [bunny, sphere, torus] {
            let (topo, search, c, r) = prepared(&mesh);
            let mut faces = RegionGrower::default();
            let mut patches =
                RegionGrower::with_patches(RegionPatches::new(&topo, search.normals()));
            for k in 0..6 {
                let a = k as f32 * 1.1;
                let world = Mat4::from_rotation_y(a)
                    * Mat4::from_scale(Vec3::splat(1.7 / r))
                    * Mat4::from_translation(-c);
                let light_eye = if k % 3 == 2 {
                    LightEye::Directions {
                        to_light: Vec3::new(a.cos(), 1.0, a.sin()),
                        to_eye: Vec3::Z,
                    }
                } else {
                    point_light(a)
                };
                let frame = frame_of(&topo, &search, world, light_eye);
                for centre in search.find(light_eye, world) {
                    for sigma in [0.9, 0.97] {
                        let seed = [(centre, sigma)];
                        let x = faces.grow_all(&frame, &seed);
                        let y = patches.grow_all(&frame, &seed);
                        whole += patches.counts().patches;
                        assert_same_region(x[0], y[0], "the seed");
                        assert_eq!(faces.pieces(0).len(), patches.pieces(0).len(), "pieces");
                        compared += usize::from(matches!(x[0], Region::Fit(..)));
                    }
                }
            }
        }
        assert!(compared >= 20, "{compared} regions compared");
        assert!(whole >= 100, "{whole} patches taken whole");
    }

    #[test]
    fn shared_regions_grow_with_patches_as_face_by_face() {
        // All centres at once, σ low enough that regions meet and a little different per
        // seed (so that which seed reaches a face first matters): with whole patches and
        // face by face, every seed gets the same faces, footprint and cone, on a scan (the
        // bunny) and a torus, several views. Some frames must keep some seeds' patches
        // while regrowing others (the path under test).
        let bunny = bunny();
        let torus = npr_geometry::generate::torus(1.0, 0.45, 120, 48);
        let (mut compared, mut partial, mut met) = (0, 0, 0);
        for mesh in [bunny, torus] {
            let (topo, search, c, r) = prepared(&mesh);
            let mut faces = RegionGrower::default();
            let mut patches =
                RegionGrower::with_patches(RegionPatches::new(&topo, search.normals()));
            for k in 0..8 {
                let a = k as f32 * 0.8;
                let world = Mat4::from_rotation_y(a)
                    * Mat4::from_rotation_x(0.3 * a)
                    * Mat4::from_scale(Vec3::splat(1.3 / r))
                    * Mat4::from_translation(-c);
                let light_eye = point_light(a);
                let frame = frame_of(&topo, &search, world, light_eye);
                let centres = search.find(light_eye, world);
                for base in [0.6, 0.75, 0.85, 0.93] {
                    let seeds: Vec<(HighlightCentre, f32)> = centres
                        .iter()
                        .enumerate()
                        .map(|(i, c)| (*c, base + 0.02 * (i % 3) as f32))
                        .collect();
                    let x = faces.grow_all(&frame, &seeds);
                    let y = patches.grow_all(&frame, &seeds);
                    let counts = patches.counts();
                    let growing = y.iter().filter(|r| matches!(r, Region::Fit(..))).count();
                    if counts.regrown > 0 {
                        met += 1;
                        if counts.regrown < growing {
                            partial += 1;
                        }
                    }
                    for (i, (a, b)) in x.iter().zip(&y).enumerate() {
                        assert_same_region(*a, *b, &format!("seed {i} ({counts:?})"));
                        assert_eq!(faces.pieces(i).len(), patches.pieces(i).len(), "pieces");
                        compared += usize::from(matches!(a, Region::Fit(..)));
                    }
                }
            }
        }
        println!("{compared} regions, {met} growths met, {partial} kept some patches");
        assert!(compared >= 100, "{compared} regions compared");
        assert!(met >= 5, "{met} growths where regions met");
        assert!(partial >= 3, "{partial} growths kept some seeds' patches");
    }

    #[test]
    fn classified_growth_fits_what_the_exact_sub_grid_fits() {
        // The fast path (faces proved inside/outside from their vertices, linear clips,
        // coarser sub-grids, interpolated H) against every face on the finest sub-grid
        // with H at each point: the same footprints within a few percent, on a noisy
        // scan (the bunny) and a sphere, point light and near eye, several views.
        let bunny = bunny();
        let sphere = npr_geometry::generate::icosphere(4, 1.0);
        let mut fits = 0;
        for mesh in [bunny, sphere] {
            let (topo, search, c, r) = prepared(&mesh);
            let world = Mat4::from_scale(Vec3::splat(1.0 / r)) * Mat4::from_translation(-c);
            let mut fast = RegionGrower::default();
            let mut exact = RegionGrower {
                exact: true,
                ..RegionGrower::default()
            };
            for k in 0..6 {
                let a = k as f32 * 1.1;
                let light_eye = point_light(a);
                let seeds: Vec<(HighlightCentre, f32)> = search
                    .find(light_eye, world)
                    .into_iter()
                    .map(|c| (c, 0.9))
                    .collect();
                let frame = frame_of(&topo, &search, world, light_eye);
                let a = fast.grow_all(&frame, &seeds);
                let b = exact.grow_all(&frame, &seeds);
                let e = exact.counts();
                assert_eq!(e.inside + e.outside + e.linear, 0, "{e:?}");
                for (x, y) in a.iter().zip(&b) {
                    match (x, y) {
                        (Region::Fit(p, _), Region::Fit(q, _)) => {
                            // Regions of a face or two are where the sub-grid itself is
                            // coarse; compare the ones that count (~20 px and up).
                            if q.region_area < 5e-4 {
                                continue;
                            }
                            fits += 1;
                            let rel = (p.region_area - q.region_area).abs() / q.region_area;
                            assert!(rel < 0.03, "area {p:?} vs {q:?}");
                            let size = q.half_extent.max_element();
                            assert!(
                                (p.half_extent - q.half_extent).abs().max_element() < 0.03 * size,
                                "extent {p:?} vs {q:?}"
                            );
                            assert!(
                                (p.offset - q.offset).length() < 0.03 * size,
                                "offset {p:?} vs {q:?}"
                            );
                            // Coarser sub-grids sample fewer normals: the cone may be
                            // narrower by a degree or two (receivers add 10°).
                            assert!(
                                p.normal_cone_cos <= q.normal_cone_cos + 0.02,
                                "cone {} vs {}",
                                p.normal_cone_cos,
                                q.normal_cone_cos
                            );
                        }
                        (Region::Fit(_, _), _) | (_, Region::Fit(_, _)) => {
                            panic!("one path fitted, the other did not: {x:?} / {y:?}")
                        }
                        _ => assert_eq!(x, y),
                    }
                }
            }
            assert!(fast.counts().inside + fast.counts().outside > 0);
        }
        assert!(fits >= 10, "{fits} regions compared");
    }
}
