//! The simplified proxy mesh (§3.2): the geometry onto which the reference images are
//! projected. Built once per mesh with a quadric-error simplifier (meshoptimizer, through
//! the `meshopt` crate; its pure-Rust port `meshopt-rs` on wasm32), where the paper used
//! VripPack (§4).
//!
//! The proxy may be *inflated* along its vertex normals by a multiple of the simplifier's
//! achieved error, so that its silhouette covers the full mesh's: the warp pass discards
//! the extra fragments where both references show background, so a slightly larger proxy
//! costs a few pixels and closes the holes a smaller one would leave (beyond the paper).

use crate::WarpError;
use glam::Vec3;
use npr_geometry::Mesh;

/// A simplified proxy of a full-detail mesh, with the error the simplifier reports.
#[derive(Clone, Debug)]
pub struct Proxy {
    /// The proxy, compacted (only referenced vertices), with smooth area-weighted normals
    /// and zero uvs. Its positions are the *uninflated* simplified surface.
    pub mesh: Mesh,
    /// The requested fraction of triangles to keep, in `(0, 1]` (the paper's 5 %, 2 %, ...
    /// are 0.05, 0.02).
    pub ratio_requested: f32,
    /// Triangles of the full mesh.
    pub source_triangles: usize,
    /// The simplifier's achieved error relative to the mesh extent (meshoptimizer's
    /// `result_error`: a distance divided by the largest bounding-box side).
    pub error_relative: f32,
    /// The same error in object units (`error_relative × meshopt::simplify_scale`).
    pub error_object: f32,
    /// For each proxy vertex, the render vertex of the full mesh it stands on (the first
    /// of its welded group). The simplifier only collapses edges onto existing vertices,
    /// so a posed full mesh poses the proxy exactly: see [`Proxy::posed`].
    pub source_vertices: Vec<u32>,
}

impl Proxy {
    /// Simplifies `mesh` to about `ratio` of its triangles (§3.2, §4: the paper's 5 %, 2 %,
    /// 1 % for the Bunny, 1 %, 0.4 %, 0.09 % for the Dragon, 0.6 %, 0.2 %, 0.07 % for the
    /// Buddha). Render vertices that share a position (uv seams) are welded first so seams
    /// do not block collapses. No error bound is imposed: the triangle count is the target.
    ///
    /// # Errors
    /// [`WarpError::RatioOutOfRange`] for a ratio outside `(0, 1]`,
    /// [`WarpError::InvalidMesh`] for a mesh breaking its invariants,
    /// [`WarpError::EmptyMesh`] for a mesh without triangles,
    /// [`WarpError::SimplifiedAway`] when nothing is left.
    pub fn simplify(mesh: &Mesh, ratio: f32) -> Result<Self, WarpError> {
        if !(ratio.is_finite() && ratio > 0.0 && ratio <= 1.0) {
            return Err(WarpError::RatioOutOfRange(ratio));
        }
        validate(mesh)?;
        let welded = npr_geometry::weld(mesh);
        let positions: Vec<[f32; 3]> = welded.positions.iter().map(|p| p.to_array()).collect();
        let indices: Vec<u32> = welded.indices.iter().flatten().copied().collect();
        let triangles = indices.len() / 3;
        let target_indices = ((triangles as f64 * f64::from(ratio)).round() as usize).max(1) * 3;
        let (simplified, error_relative) = if target_indices >= indices.len() {
            (indices.clone(), 0.0)
        } else {
            simplify_indices(&indices, &positions, target_indices)
        };
        if simplified.len() < 3 {
            return Err(WarpError::SimplifiedAway { triangles, ratio });
        }
        let scale = simplify_scale(&positions);
        // The first render vertex of each welded vertex (render order is first-use order).
        let mut first_render = vec![u32::MAX; positions.len()];
        for (r, &w) in welded.render_to_welded.iter().enumerate().rev() {
            first_render[w as usize] = r as u32;
        }
        // Compact: keep referenced vertices only, in first-use order.
        let mut remap = vec![u32::MAX; positions.len()];
        let mut out = Mesh::default();
        let mut source_vertices = Vec::new();
        for &i in &simplified {
            let slot = &mut remap[i as usize];
            if *slot == u32::MAX {
                *slot = out.positions.len() as u32;
                out.positions.push(welded.positions[i as usize]);
                source_vertices.push(first_render[i as usize]);
            }
            out.indices.push(*slot);
        }
        with_area_normals(&mut out);
        out.uvs = vec![glam::Vec2::ZERO; out.positions.len()];
        Ok(Self {
            mesh: out,
            ratio_requested: ratio,
            source_triangles: mesh.triangle_count(),
            error_relative,
            error_object: error_relative * scale,
            source_vertices,
        })
    }

    /// The proxy posed as `source`, a pose of the full mesh it was simplified from (the
    /// same render vertices, moved by skinning or morphing): each proxy vertex takes its
    /// [`Proxy::source_vertices`] position, and the normals are recomputed on the posed
    /// faces. The proxy's skin is the full mesh's, restricted to the vertices it kept, so
    /// it moves with the same joints and morph weights (beyond the paper, whose §3.3.1
    /// proxy is rigid). The simplifier's error is kept: it was measured on the mesh the
    /// proxy was simplified from.
    ///
    /// # Errors
    /// [`WarpError::PoseMismatch`] when `source` has fewer vertices than the proxy's
    /// source map needs, or a non-finite position where the proxy reads it.
    pub fn posed(&self, source: &Mesh) -> Result<Self, WarpError> {
        if self.source_vertices.len() != self.mesh.positions.len() {
            return Err(WarpError::PoseMismatch(format!(
                "a source map of {} vertices for a proxy of {}",
                self.source_vertices.len(),
                self.mesh.positions.len()
            )));
        }
        let mut mesh = self.mesh.clone();
        for (p, &v) in mesh.positions.iter_mut().zip(&self.source_vertices) {
            match source.positions.get(v as usize) {
                Some(q) if q.is_finite() => *p = *q,
                Some(q) => {
                    return Err(WarpError::PoseMismatch(format!(
                        "source vertex {v} is at {q}, not a finite position"
                    )));
                }
                None => {
                    return Err(WarpError::PoseMismatch(format!(
                        "a pose of {} vertices for a proxy of a mesh with more than {v}",
                        source.positions.len()
                    )));
                }
            }
        }
        with_area_normals(&mut mesh);
        Ok(Self {
            mesh,
            ratio_requested: self.ratio_requested,
            source_triangles: self.source_triangles,
            error_relative: self.error_relative,
            error_object: self.error_object,
            source_vertices: self.source_vertices.clone(),
        })
    }

    /// Triangles of the proxy.
    pub fn triangles(&self) -> usize {
        self.mesh.triangle_count()
    }

    /// Achieved fraction of the source triangles.
    pub fn ratio_achieved(&self) -> f32 {
        self.triangles() as f32 / self.source_triangles.max(1) as f32
    }

    /// The inflation this crate uses by default: 0.75 × the achieved error (object units).
    /// A larger inflation covers more of the full mesh's silhouette but widens the rim the
    /// depth test must reject; on the benchmark's bunny (2 %) mean PSNR at k = 10 measured
    /// 27.6 dB at 0.375×, 28.1 dB at 0.75×, 26.6 dB at 1.5× the error.
    pub fn suggested_inflation(&self) -> f32 {
        0.75 * self.error_object
    }

    /// A depth-test tolerance in object units for a proxy inflated by `inflation_object`:
    /// the proxy may lie up to its error plus the inflation off the true surface (twice, for
    /// margin), plus 0.2 % of the radius for depth precision. (The warp adds each reference
    /// texel's depth extent at the point's angle on top.)
    pub fn suggested_depth_tolerance(&self, inflation_object: f32) -> f32 {
        let (_, radius) = bounding_sphere(&self.mesh.positions);
        2.0 * (self.error_object + inflation_object) + 0.002 * radius
    }

    /// The proxy moved `distance_object` along its (smooth) vertex normals. With a distance
    /// a little above [`Proxy::error_object`] the proxy's silhouette covers the full
    /// mesh's, so the warp leaves no background holes at the silhouette (beyond the paper).
    pub fn inflated(&self, distance_object: f32) -> Mesh {
        let mut m = self.mesh.clone();
        for (p, n) in m.positions.iter_mut().zip(&self.mesh.normals) {
            *p += *n * distance_object;
        }
        m
    }
}

/// Sets `mesh.normals` to its smooth area-weighted vertex normals.
fn with_area_normals(mesh: &mut Mesh) {
    let triangles: Vec<[u32; 3]> = mesh.triangles().collect();
    mesh.normals = npr_geometry::mesh::welded_area_normals(&mesh.positions, &triangles);
}

/// meshoptimizer's attribute-free simplifier to `target_indices` with no error bound: the
/// simplified indices (into `positions`) and the achieved error relative to
/// [`simplify_scale`].
#[cfg(not(target_arch = "wasm32"))]
fn simplify_indices(
    indices: &[u32],
    positions: &[[f32; 3]],
    target_indices: usize,
) -> (Vec<u32>, f32) {
    let mut error_relative = 0.0f32;
    let simplified = meshopt::simplify_decoder(
        indices,
        positions,
        target_indices,
        f32::MAX,
        meshopt::SimplifyOptions::None,
        Some(&mut error_relative),
    );
    (simplified, error_relative)
}

/// On wasm32, meshoptimizer's pure-Rust port (no C++ toolchain targets the browser). It
/// reports no error, so the error is measured: the largest distance from a vertex of the
/// full mesh to the tangent plane of its nearest proxy vertex, relative to
/// [`simplify_scale`] (an estimate of the same quantity, not bit-equal to native).
#[cfg(target_arch = "wasm32")]
fn simplify_indices(
    indices: &[u32],
    positions: &[[f32; 3]],
    target_indices: usize,
) -> (Vec<u32>, f32) {
    let mut out = vec![0; indices.len()];
    let n = meshopt_rs::simplify::simplify(&mut out, indices, positions, target_indices, f32::MAX);
    out.truncate(n);
    let scale = simplify_scale(positions);
    if out.len() < 3 || scale <= 0.0 {
        return (out, 0.0);
    }
    let points: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    let triangles: Vec<[u32; 3]> = out.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let normals = npr_geometry::mesh::welded_area_normals(&points, &triangles);
    let mut kept: Vec<u32> = out.clone();
    kept.sort_unstable();
    kept.dedup();
    // Nearest kept vertex through a uniform grid of about one kept vertex per cell.
    let lo = points.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p));
    let cell = scale / (kept.len() as f32).cbrt().max(1.0);
    let key = |p: Vec3| ((p - lo) / cell).floor().as_ivec3();
    let mut grid: std::collections::HashMap<glam::IVec3, Vec<u32>> = Default::default();
    for &k in &kept {
        grid.entry(key(points[k as usize])).or_default().push(k);
    }
    let mut worst = 0.0f32;
    for p in &points {
        let c = key(*p);
        let mut best: Option<(f32, u32)> = None;
        // Widen the search ring until a kept vertex is found and no closer one can exist.
        for r in 0i32.. {
            for dz in -r..=r {
                for dy in -r..=r {
                    for dx in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        for &k in grid
                            .get(&(c + glam::IVec3::new(dx, dy, dz)))
                            .into_iter()
                            .flatten()
                        {
                            let d = points[k as usize].distance_squared(*p);
                            if best.is_none_or(|(b, _)| d < b) {
                                best = Some((d, k));
                            }
                        }
                    }
                }
            }
            if best.is_some_and(|(b, _)| b.sqrt() <= r as f32 * cell) || r > 64 {
                break;
            }
        }
        if let Some((_, k)) = best {
            let q = points[k as usize];
            worst = worst.max((*p - q).dot(normals[k as usize]).abs());
        }
    }
    (out, worst / scale)
}

/// meshoptimizer's simplification scale: the largest extent of the bounding box.
fn simplify_scale(positions: &[[f32; 3]]) -> f32 {
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(Vec3::from_array(*p)), hi.max(Vec3::from_array(*p))),
    );
    if positions.is_empty() {
        0.0
    } else {
        (hi - lo).max_element()
    }
}

/// Checks the invariants and that at least one triangle exists.
pub(crate) fn validate(mesh: &Mesh) -> Result<(), WarpError> {
    if mesh.indices.len() < 3 || mesh.positions.is_empty() {
        return Err(WarpError::EmptyMesh(format!(
            "{} vertices, {} indices",
            mesh.positions.len(),
            mesh.indices.len()
        )));
    }
    if mesh.uvs.is_empty() && mesh.normals.len() == mesh.positions.len() {
        let mut with_uvs = mesh.clone();
        with_uvs.uvs = vec![glam::Vec2::ZERO; mesh.positions.len()];
        with_uvs.validate()?;
    } else {
        mesh.validate()?;
    }
    Ok(())
}

/// Centre and radius of the bounding box's circumscribed sphere of `positions`
/// (`(ZERO, 0)` when empty).
pub fn bounding_sphere(positions: &[Vec3]) -> (Vec3, f32) {
    if positions.is_empty() {
        return (Vec3::ZERO, 0.0);
    }
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let c = (lo + hi) * 0.5;
    let r = positions.iter().map(|p| p.distance(c)).fold(0.0, f32::max);
    (c, r)
}
