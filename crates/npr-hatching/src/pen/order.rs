//! Plotter-side line work on page polylines (mm): joining ends, simplification
//! (Ramer–Douglas–Peucker) and the drawing order (nearest end first, strokes reversed
//! where that helps, then 2-opt), which keeps pen-up travel short.

use super::streamlines::Polyline;
use std::collections::HashMap;

/// Distance between two points.
pub(crate) fn dist(a: [f32; 2], b: [f32; 2]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Length of a polyline.
pub(crate) fn length(l: &Polyline) -> f32 {
    l.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// Joins polylines end to end wherever an end lies within `tol` of another's (reversing
/// one where needed), in a fixed order.
pub(crate) fn merge_ends(lines: Vec<Polyline>, tol: f32) -> Vec<Polyline> {
    let lines: Vec<Polyline> = lines.into_iter().filter(|l| !l.is_empty()).collect();
    if tol <= 0.0 {
        return lines;
    }
    let cell = |p: [f32; 2]| ((p[0] / tol).floor() as i64, (p[1] / tol).floor() as i64);
    let mut ends: HashMap<(i64, i64), Vec<(usize, bool)>> = HashMap::new();
    for (i, l) in lines.iter().enumerate() {
        ends.entry(cell(l[0])).or_default().push((i, false));
        ends.entry(cell(l[l.len() - 1]))
            .or_default()
            .push((i, true));
    }
    let mut used = vec![false; lines.len()];
    // The unused line with an end within tol of p (and which end), lowest index first.
    let find = |p: [f32; 2], used: &[bool]| -> Option<(usize, bool)> {
        let (cx, cy) = cell(p);
        let mut best: Option<(usize, bool)> = None;
        for dy in -1..=1 {
            for dx in -1..=1 {
                for &(j, at_end) in ends.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let q = if at_end {
                        lines[j][lines[j].len() - 1]
                    } else {
                        lines[j][0]
                    };
                    if !used[j] && dist(p, q) <= tol && best.is_none_or(|b| (j, at_end) < b) {
                        best = Some((j, at_end));
                    }
                }
            }
        }
        best
    };
    let mut out = Vec::new();
    for i in 0..lines.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let mut chain = lines[i].clone();
        for _ in 0..2 {
            while let Some((j, at_end)) = find(chain[chain.len() - 1], &used) {
                used[j] = true;
                let mut next = lines[j].clone();
                if at_end {
                    next.reverse();
                }
                chain.extend_from_slice(&next[1..]);
            }
            chain.reverse();
        }
        out.push(chain);
    }
    out
}

/// The polyline with every point dropped that lies within `tol` of the simplified line.
pub(crate) fn simplify(l: &Polyline, tol: f32) -> Polyline {
    if l.len() <= 2 || tol <= 0.0 {
        return l.clone();
    }
    let mut keep = vec![false; l.len()];
    keep[0] = true;
    keep[l.len() - 1] = true;
    let mut stack = vec![(0, l.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let (pa, pb) = (l[a], l[b]);
        let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
        let len = (dx * dx + dy * dy).sqrt();
        let mut worst = (0.0f32, a);
        for (k, p) in l.iter().enumerate().take(b).skip(a + 1) {
            let d = if len > 0.0 {
                ((p[0] - pa[0]) * dy - (p[1] - pa[1]) * dx).abs() / len
            } else {
                dist(*p, pa)
            };
            if d > worst.0 {
                worst = (d, k);
            }
        }
        if worst.0 > tol {
            keep[worst.1] = true;
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        }
    }
    l.iter()
        .zip(&keep)
        .filter(|(_, k)| **k)
        .map(|(p, _)| *p)
        .collect()
}

/// The drawing order: from the page's corner, always the stroke with the nearest end
/// next (drawn from that end), then 2-opt moves (reversing a run of strokes) while they
/// shorten the travel.
pub(crate) fn order(lines: Vec<Polyline>) -> Vec<Polyline> {
    let mut left: Vec<Option<Polyline>> = lines.into_iter().map(Some).collect();
    let mut out = Vec::with_capacity(left.len());
    let mut at = [0.0f32, 0.0];
    for _ in 0..left.len() {
        let mut best: Option<(f32, usize, bool)> = None;
        for (i, l) in left.iter().enumerate() {
            let Some(l) = l else { continue };
            for (rev, p) in [(false, l[0]), (true, l[l.len() - 1])] {
                let d = dist(at, p);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, i, rev));
                }
            }
        }
        let Some((_, i, rev)) = best else { break };
        if let Some(mut l) = left[i].take() {
            if rev {
                l.reverse();
            }
            at = l[l.len() - 1];
            out.push(l);
        }
    }
    two_opt(&mut out);
    out
}

/// Reverses runs `i..=j` of the strokes (each stroke reversed too) while that shortens the
/// pen-up travel; runs up to 1,000 strokes long, at most 20 sweeps.
fn two_opt(lines: &mut [Polyline]) {
    let n = lines.len();
    let start = |l: &Polyline| l[0];
    let end = |l: &Polyline| l[l.len() - 1];
    for _ in 0..20 {
        let mut improved = false;
        for i in 1..n {
            for j in i + 1..n.min(i + 1000) {
                let before = end(&lines[i - 1]);
                let next = lines.get(j + 1).map(start);
                let old =
                    dist(before, start(&lines[i])) + next.map_or(0.0, |s| dist(end(&lines[j]), s));
                let new =
                    dist(before, end(&lines[j])) + next.map_or(0.0, |s| dist(start(&lines[i]), s));
                if new + 1e-4 < old {
                    lines[i..=j].reverse();
                    for l in &mut lines[i..=j] {
                        l.reverse();
                    }
                    improved = true;
                }
            }
        }
        if !improved {
            break;
        }
    }
}
