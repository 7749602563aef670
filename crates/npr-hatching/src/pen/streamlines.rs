//! Evenly spaced streamlines of a varying density (B. Jobard and W. Lefer, "Creating
//! evenly-spaced streamlines of arbitrary density", Visualization in Scientific
//! Computing 1997): each stroke is traced along the stroke field from a seed until it
//! leaves the object, meets a silhouette or comes closer to another stroke than a share
//! of the local separation; new seeds are taken one separation to either side of each
//! stroke, then from a scan of the whole view. The separation follows the tone: the
//! hatching's tone levels become spacing levels.

use super::field::Field;

/// A polyline in view pixels (y down).
pub type Polyline = Vec<[f32; 2]>;

/// How one layer of strokes is spaced and turned.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layer {
    /// Added to the stroke angle θ: 0 for the hatching, π/2 for the cross-hatching.
    pub turn: f32,
    /// Whether this is the cross-hatching layer (drawn only past `cross_from`).
    pub cross: bool,
}

/// The spacing rules shared by both layers.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spacing {
    pub pen_px: f32,
    pub cross_from: f32,
    /// A stroke stops when another is closer than `test_ratio ×` the separation.
    pub test_ratio: f32,
    pub step_px: f32,
    pub min_length_px: f32,
}

impl Spacing {
    /// The ink share one layer gives to reach `darkness`: alone up to `cross_from`; past
    /// it, two crossing layers of share `c` each cover `1 − (1 − c)²`.
    pub(crate) fn coverage(&self, darkness: f32, layer: Layer) -> f32 {
        if darkness <= 0.0 {
            0.0
        } else if darkness <= self.cross_from {
            if layer.cross { 0.0 } else { darkness }
        } else {
            1.0 - (1.0 - darkness.min(1.0)).sqrt()
        }
    }

    /// The separation between strokes of `layer` at `darkness` (pen width over the
    /// coverage), `None` where the layer draws nothing.
    pub(crate) fn separation(&self, darkness: f32, layer: Layer) -> Option<f32> {
        let c = self.coverage(darkness, layer);
        (c > 1e-4).then(|| self.pen_px / c.min(1.0))
    }
}

/// Points of finished strokes, bucketed for "is any within r of p".
struct Grid {
    cell: f32,
    cols: usize,
    rows: usize,
    cells: Vec<Vec<[f32; 2]>>,
}

impl Grid {
    fn new(width: usize, height: usize, cell: f32) -> Self {
        let cols = (width as f32 / cell).ceil().max(1.0) as usize;
        let rows = (height as f32 / cell).ceil().max(1.0) as usize;
        Self {
            cell,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
        }
    }

    fn cell_of(&self, p: [f32; 2]) -> (usize, usize) {
        let cx = ((p[0] / self.cell).floor().max(0.0) as usize).min(self.cols - 1);
        let cy = ((p[1] / self.cell).floor().max(0.0) as usize).min(self.rows - 1);
        (cx, cy)
    }

    fn insert(&mut self, p: [f32; 2]) {
        let (cx, cy) = self.cell_of(p);
        self.cells[cy * self.cols + cx].push(p);
    }

    /// Whether a stored point lies within `r` of `p`.
    fn near(&self, p: [f32; 2], r: f32) -> bool {
        let reach = (r / self.cell).ceil() as usize;
        let (cx, cy) = self.cell_of(p);
        let r2 = r * r;
        for y in cy.saturating_sub(reach)..=(cy + reach).min(self.rows - 1) {
            for x in cx.saturating_sub(reach)..=(cx + reach).min(self.cols - 1) {
                for q in &self.cells[y * self.cols + x] {
                    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                    if dx * dx + dy * dy < r2 {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// The strokes of one layer over `field`.
pub(crate) fn trace_layer(field: &Field, spacing: &Spacing, layer: Layer) -> Vec<Polyline> {
    let min_sep = field
        .darkness
        .iter()
        .filter_map(|&d| spacing.separation(d, layer))
        .fold(f32::INFINITY, f32::min);
    if !min_sep.is_finite() {
        return Vec::new();
    }
    let mut grid = Grid::new(
        field.width,
        field.height,
        (min_sep * spacing.test_ratio).max(2.0),
    );
    let mut strokes = Vec::new();
    let mut queue = std::collections::VecDeque::new();
    // The scan: candidate seeds every half minimum separation, row by row.
    let scan_step = (0.5 * min_sep).max(1.0);
    let mut y = 0.5 * scan_step;
    while y < field.height as f32 {
        let mut x = 0.5 * scan_step;
        while x < field.width as f32 {
            queue.push_back([x, y]);
            while let Some(seed) = queue.pop_front() {
                if let Some(line) = trace_from(field, &grid, spacing, layer, seed) {
                    side_seeds(field, spacing, layer, &line, &mut queue);
                    for &p in &line {
                        grid.insert(p);
                    }
                    strokes.push(line);
                }
            }
            x += scan_step;
        }
        y += scan_step;
    }
    strokes
}

/// The stroke through `seed`, if the seed is free (no stroke within one separation) and
/// the stroke is long enough.
fn trace_from(
    field: &Field,
    grid: &Grid,
    spacing: &Spacing,
    layer: Layer,
    seed: [f32; 2],
) -> Option<Polyline> {
    if !field.is_open(seed) {
        return None;
    }
    let sep = spacing.separation(field.darkness_at(seed), layer)?;
    if grid.near(seed, sep) {
        return None;
    }
    let start = field.direction(seed, layer.turn, [1.0, 0.0])?;
    let forward = integrate(field, grid, spacing, layer, seed, start);
    let backward = integrate(field, grid, spacing, layer, seed, [-start[0], -start[1]]);
    let mut line: Polyline = backward.into_iter().rev().collect();
    line.push(seed);
    line.extend(forward);
    let length = (line.len() - 1) as f32 * spacing.step_px;
    (length >= spacing.min_length_px).then_some(line)
}

/// Steps (midpoint rule) from `p` along `along` until a stop condition; the points after
/// `p`.
fn integrate(
    field: &Field,
    grid: &Grid,
    spacing: &Spacing,
    layer: Layer,
    mut p: [f32; 2],
    mut along: [f32; 2],
) -> Vec<[f32; 2]> {
    let h = spacing.step_px;
    let max_steps = (4 * (field.width + field.height)) as f32 / h;
    let mut out = Vec::new();
    while (out.len() as f32) < max_steps {
        let Some(v1) = field.direction(p, layer.turn, along) else {
            break;
        };
        let mid = [p[0] + 0.5 * h * v1[0], p[1] + 0.5 * h * v1[1]];
        let Some(v2) = field.direction(mid, layer.turn, v1) else {
            break;
        };
        let q = [p[0] + h * v2[0], p[1] + h * v2[1]];
        if !field.is_open(q) {
            break;
        }
        let Some(sep) = spacing.separation(field.darkness_at(q), layer) else {
            break;
        };
        if grid.near(q, spacing.test_ratio * sep) {
            break;
        }
        out.push(q);
        along = v2;
        p = q;
    }
    out
}

/// Seeds one separation to either side of `line`, about every half separation along it.
fn side_seeds(
    field: &Field,
    spacing: &Spacing,
    layer: Layer,
    line: &Polyline,
    queue: &mut std::collections::VecDeque<[f32; 2]>,
) {
    let mut since = f32::INFINITY;
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        since += len;
        let Some(sep) = spacing.separation(field.darkness_at(a), layer) else {
            continue;
        };
        if since < 0.5 * sep || len <= 0.0 {
            continue;
        }
        since = 0.0;
        let n = [-dy / len, dx / len];
        for s in [1.0, -1.0] {
            queue.push_back([a[0] + s * sep * n[0], a[1] + s * sep * n[1]]);
        }
    }
}
