//! Outlines as vector lines: the mesh's silhouette edges (between a face turned to the eye
//! and one turned away, and open boundary edges) and its creases (faces meeting at more
//! than the crease angle), projected into the view and kept where the depth buffer shows
//! them (hidden parts removed). The visible silhouettes also cut the hatching strokes.

use super::streamlines::Polyline;
use glam::{Mat4, Vec3};
use npr_geometry::Mesh;
use npr_gpu::Camera;

/// What the outline tracing needs of the view.
#[derive(Clone, Copy, Debug)]
pub struct OutlineView<'a> {
    /// The camera of the view.
    pub camera: &'a Camera,
    /// The model's placement.
    pub world_from_object: Mat4,
    /// View size in pixels.
    pub size: (u32, u32),
    /// The view's depth buffer (`[0, 1]` device depth, rows top to bottom; 1 where
    /// nothing was drawn).
    pub depth: &'a [f32],
    /// Faces meeting at more than this angle (degrees) make a crease line.
    pub crease_deg: f32,
}

/// The visible outline segments of a mesh in one view, and which pixels its visible
/// silhouettes cover.
pub(crate) struct Outlines {
    pub silhouettes: Vec<Polyline>,
    pub creases: Vec<Polyline>,
    /// Pixels within one pixel of a visible silhouette.
    pub cuts: Vec<bool>,
}

/// One projected point: pixel position and linear view depth.
#[derive(Clone, Copy)]
struct Projected {
    px: [f32; 2],
    depth: f32,
}

/// The outlines of `mesh` seen in `view`.
pub(crate) fn outlines(mesh: &Mesh, view: &OutlineView<'_>) -> Outlines {
    let welded = npr_geometry::weld(mesh);
    let world: Vec<Vec3> = welded
        .positions
        .iter()
        .map(|&p| view.world_from_object.transform_point3(p))
        .collect();
    let faces = &welded.indices;
    let normals: Vec<Vec3> = faces
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| world[v as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let front: Vec<bool> = faces
        .iter()
        .zip(&normals)
        .map(|(t, n)| n.dot(view.camera.eye - world[t[0] as usize]) > 0.0)
        .collect();
    let clip = view.camera.clip_from_world();
    let (w, h) = (view.size.0 as f32, view.size.1 as f32);
    let projected: Vec<Option<Projected>> = world
        .iter()
        .map(|&p| {
            let c = clip * p.extend(1.0);
            (c.w > 1e-6).then(|| Projected {
                px: [(c.x / c.w + 1.0) * 0.5 * w, (1.0 - c.y / c.w) * 0.5 * h],
                depth: c.w,
            })
        })
        .collect();
    let crease_cos = view.crease_deg.to_radians().cos();
    let mut out = Outlines {
        silhouettes: Vec::new(),
        creases: Vec::new(),
        cuts: vec![false; (view.size.0 * view.size.1) as usize],
    };
    for (a, b, f, g) in edges(faces) {
        let kind = match g {
            None => front[f].then_some(true),
            Some(g) if front[f] != front[g] => Some(true),
            Some(g) if (front[f] || front[g]) && normals[f].dot(normals[g]) < crease_cos => {
                Some(false)
            }
            _ => None,
        };
        let (Some(silhouette), Some(pa), Some(pb)) =
            (kind, projected[a as usize], projected[b as usize])
        else {
            continue;
        };
        for run in visible_runs(pa, pb, view) {
            if silhouette {
                mark_cuts(&mut out.cuts, view.size, &run);
                out.silhouettes.push(run);
            } else {
                out.creases.push(run);
            }
        }
    }
    out
}

/// Each edge once, with its one or two faces, in a fixed order.
fn edges(faces: &[[u32; 3]]) -> Vec<(u32, u32, usize, Option<usize>)> {
    let mut half: Vec<(u32, u32, usize)> = faces
        .iter()
        .enumerate()
        .flat_map(|(f, t)| {
            (0..3).map(move |k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                (a.min(b), a.max(b), f)
            })
        })
        .collect();
    half.sort_unstable();
    let mut out = Vec::with_capacity(half.len() / 2 + 1);
    let mut i = 0;
    while i < half.len() {
        let (a, b, f) = half[i];
        let mut j = i + 1;
        while j < half.len() && (half[j].0, half[j].1) == (a, b) {
            j += 1;
        }
        // Two faces make a manifold edge; an edge of more is drawn against its first two.
        let g = (j > i + 1).then(|| half[i + 1].2);
        if a != b {
            out.push((a, b, f, g));
        }
        i = j;
    }
    out
}

/// The parts of the segment `a`–`b` the depth buffer shows, sampled every half pixel.
fn visible_runs(a: Projected, b: Projected, view: &OutlineView<'_>) -> Vec<Polyline> {
    let (dx, dy) = (b.px[0] - a.px[0], b.px[1] - a.px[1]);
    let len = (dx * dx + dy * dy).sqrt();
    let n = (2.0 * len).ceil().max(1.0) as usize;
    let mut runs = Vec::new();
    let mut current: Option<([f32; 2], [f32; 2])> = None;
    for k in 0..=n {
        let t = k as f32 / n as f32;
        let p = [a.px[0] + t * dx, a.px[1] + t * dy];
        // 1/w is affine in screen space: interpolate it, not the depth.
        let depth = 1.0 / ((1.0 - t) / a.depth + t / b.depth);
        if shown(p, depth, view) {
            current = Some(current.map_or((p, p), |(s, _)| (s, p)));
        } else if let Some((s, e)) = current.take() {
            runs.push(vec![s, e]);
        }
    }
    if let Some((s, e)) = current {
        runs.push(vec![s, e]);
    }
    runs.retain(|r| r[0] != r[1]);
    runs
}

/// Whether a point at linear depth `depth` is in front of what the depth buffer holds
/// around pixel `p` (the farthest of its 3 × 3 neighbours, so a silhouette against what is
/// behind it counts as shown), within 0.5 % of its depth.
fn shown(p: [f32; 2], depth: f32, view: &OutlineView<'_>) -> bool {
    let (w, h) = (view.size.0 as i64, view.size.1 as i64);
    let (x, y) = (p[0].floor() as i64, p[1].floor() as i64);
    if x < 0 || y < 0 || x >= w || y >= h {
        return false;
    }
    let (near, far) = (view.camera.near, view.camera.far);
    let mut farthest = 0.0f32;
    for yy in (y - 1).max(0)..=(y + 1).min(h - 1) {
        for xx in (x - 1).max(0)..=(x + 1).min(w - 1) {
            let z = view
                .depth
                .get((yy * w + xx) as usize)
                .copied()
                .unwrap_or(1.0);
            if z >= 1.0 {
                return true;
            }
            // Device depth of the directx-style perspective back to view distance.
            let linear = far * near / (far - z * (far - near));
            farthest = farthest.max(linear);
        }
    }
    depth <= farthest * 1.005 + 1e-6
}

/// Marks the pixels within one pixel of the segment `run`.
fn mark_cuts(cuts: &mut [bool], size: (u32, u32), run: &Polyline) {
    let (w, h) = (size.0 as i64, size.1 as i64);
    let (a, b) = (run[0], run[run.len() - 1]);
    let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let n = (2.0 * len).ceil().max(1.0) as usize;
    for k in 0..=n {
        let t = k as f32 / n as f32;
        let (x, y) = (
            (a[0] + t * (b[0] - a[0])).floor() as i64,
            (a[1] + t * (b[1] - a[1])).floor() as i64,
        );
        for yy in (y - 1).max(0)..=(y + 1).min(h - 1) {
            for xx in (x - 1).max(0)..=(x + 1).min(w - 1) {
                cuts[(yy * w + xx) as usize] = true;
            }
        }
    }
}
