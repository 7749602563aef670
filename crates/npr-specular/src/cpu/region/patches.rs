//! [`RegionPatches`]: connected patches of a mesh's faces with the bounds and moment
//! tensors that let a growth take a whole patch at once.

#[cfg(doc)]
use super::RegionGrower;
use super::fit::Moments;
use super::grow::{GrowContext, Part};
use glam::{Mat3, Vec3};
use npr_geometry::{LightEye, Topology};

/// Faces per patch of [`RegionPatches`] (at most): small enough that most of a
/// highlight's interior is whole patches on a 70k-face scan, large enough that a
/// million-face region is a few hundred. A [`crate::HighlightSet`]'s §4.2 search walks the
/// same patches.
pub const REGION_PATCH_FACES: usize = 16;

/// Connected patches of a mesh's faces ([`crate::cpu::visibility::FaceClusters`] of
/// [`REGION_PATCH_FACES`]) with what [`RegionGrower::grow_all`] needs to take one whole
/// (beyond the paper): the cones of its vertex and face normals, and its area moments as
/// tensors in object space, from which the moments of its projection onto any plane
/// under any similarity follow exactly. Built once per mesh and normal field.
#[derive(Clone, Debug, Default)]
pub struct RegionPatches {
    pub(super) clusters: crate::cpu::visibility::FaceClusters,
    pub(super) patches: Vec<PatchBounds>,
}

/// One patch's bounds and moment tensors (object space, about `centre`).
#[derive(Clone, Copy, Debug)]
pub(super) struct PatchBounds {
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
        let clusters =
            crate::cpu::visibility::FaceClusters::with_size(topology, REGION_PATCH_FACES);
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
    pub(super) fn whole(&self, c: usize, ctx: &GrowContext<'_>, part: &Part) -> Option<Moments> {
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
        let h = ctx.frame.light_eye.half_vector(centre);
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
    pub(super) fn cone_bound(&self, normal_from_object: Mat3, n: Vec3) -> f32 {
        let axis = (normal_from_object * self.normal_axis).normalize_or_zero();
        let cos = axis.dot(n).clamp(-1.0, 1.0);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (ss, cs) = self.normal_spread;
        cos * cs - sin * ss - PATCH_MARGIN
    }
}

/// Float slack of the whole-patch tests (cosine units).
const PATCH_MARGIN: f32 = 1e-4;
