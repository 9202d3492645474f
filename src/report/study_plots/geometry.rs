//! Geometry of the operating-point plots: heat-map cells around grid nodes, and the feasible
//! region's box clipped by linear constraints (a·Ω + b·V0 ≤ u), all in plot units.

use crate::report::axes::axis_range;

use super::style::Point;

/// Cell edges [lo, hi] of every node: halfway to the neighbours in sorted order, half a
/// spacing beyond the outermost nodes. A lone node gets a ±5 % cell (±1 at 0); a non-finite
/// node gets None.
pub(super) fn cell_edges(nodes: &[f64]) -> Vec<Option<(f64, f64)>> {
    let mut order: Vec<usize> = (0..nodes.len()).filter(|&i| nodes[i].is_finite()).collect();
    order.sort_by(|&a, &b| nodes[a].total_cmp(&nodes[b]));
    let mut edges = vec![None; nodes.len()];
    if let [only] = order[..] {
        edges[only] = Some(axis_range([nodes[only]], 0.0));
        return edges;
    }
    let x = |k: usize| nodes[order[k]];
    let n = order.len();
    for (k, &i) in order.iter().enumerate() {
        let lo = if k == 0 {
            x(0) - 0.5 * (x(1) - x(0))
        } else {
            0.5 * (x(k - 1) + x(k))
        };
        let hi = if k + 1 == n {
            x(n - 1) + 0.5 * (x(n - 1) - x(n - 2))
        } else {
            0.5 * (x(k) + x(k + 1))
        };
        edges[i] = Some((lo, hi));
    }
    edges
}

/// The part of the box [x0, x1] × [y0, y1] where a·x + b·y ≥ u (Sutherland–Hodgman against one
/// half-plane), or None if it has no area.
pub(super) fn clip_box_to_halfplane(
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (a, b, u): (f64, f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
    let f = |p: (f64, f64)| a * p.0 + b * p.1 - u;
    let mut poly = Vec::with_capacity(5);
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            poly.push(p);
        }
        // Strict signs: a vertex on the line is kept above and is no crossing.
        if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
            let s = fp / (fp - fq);
            poly.push((p.0 + s * (q.0 - p.0), p.1 + s * (q.1 - p.1)));
        }
    }
    let twice_area: f64 = (0..poly.len())
        .map(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            p.0 * q.1 - q.0 * p.1
        })
        .sum();
    let box_area = (x1 - x0) * (y1 - y0);
    (poly.len() >= 3 && twice_area.abs() > 1e-9 * box_area).then_some(poly)
}

/// The segment of the line a·x + b·y = u inside [x0, x1] × [y0, y1], or None if it misses.
pub(super) fn clip_line_to_box(
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (a, b, u): (f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let tol_x = 1e-9 * (x1 - x0);
    let tol_y = 1e-9 * (y1 - y0);
    let mut hits: Vec<(f64, f64)> = Vec::with_capacity(4);
    if b != 0.0 {
        for x in [x0, x1] {
            let y = (u - a * x) / b;
            if y >= y0 - tol_y && y <= y1 + tol_y {
                hits.push((x, y.clamp(y0, y1)));
            }
        }
    }
    if a != 0.0 {
        for y in [y0, y1] {
            let x = (u - b * y) / a;
            if x >= x0 - tol_x && x <= x1 + tol_x {
                hits.push((x.clamp(x0, x1), y));
            }
        }
    }
    // The two hits farthest apart (a line through a corner hits it twice).
    let mut best: Option<(Point, Point, f64)> = None;
    for (i, &p) in hits.iter().enumerate() {
        for &q in &hits[i + 1..] {
            let d = ((p.0 - q.0) / (x1 - x0)).hypot((p.1 - q.1) / (y1 - y0));
            if best.is_none_or(|(_, _, bd)| d > bd) {
                best = Some((p, q, d));
            }
        }
    }
    best.filter(|&(_, _, d)| d > 1e-9).map(|(p, q, _)| (p, q))
}

/// `[lo, hi]` in order if both are finite.
pub(super) fn finite_bounds([a, b]: [f64; 2]) -> Option<(f64, f64)> {
    (a.is_finite() && b.is_finite()).then(|| (a.min(b), a.max(b)))
}

pub(super) fn is_finite_point(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_clipped_to_a_half_plane() {
        let (bx, by) = ((0.0, 2.0), (0.0, 1.0));
        // x + y ≥ 2: the triangle (2, 0), (2, 1), (1, 1).
        let tri = clip_box_to_halfplane(bx, by, (1.0, 1.0, 2.0)).unwrap();
        assert_eq!(tri.len(), 3, "{tri:?}");
        for v in [(2.0, 0.0), (2.0, 1.0), (1.0, 1.0)] {
            assert!(tri.contains(&v), "{tri:?}");
        }
        // 0 ≥ -1 everywhere: the whole box; 0 ≥ 1 nowhere.
        assert_eq!(
            clip_box_to_halfplane(bx, by, (0.0, 0.0, -1.0))
                .unwrap()
                .len(),
            4
        );
        assert!(clip_box_to_halfplane(bx, by, (0.0, 0.0, 1.0)).is_none());
        // A constraint active only on the box's edge leaves nothing of area.
        assert!(clip_box_to_halfplane(bx, by, (1.0, 0.0, 2.0)).is_none());
        assert!(clip_box_to_halfplane(bx, by, (1.0, 0.0, 3.0)).is_none());
    }

    #[test]
    fn line_clipped_to_a_box() {
        let (bx, by) = ((0.0, 2.0), (0.0, 1.0));
        let sorted = |(p, q): ((f64, f64), (f64, f64))| if p <= q { (p, q) } else { (q, p) };
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, 1.0, 2.0)).map(sorted),
            Some(((1.0, 1.0), (2.0, 0.0)))
        );
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, 0.0, 0.5)).map(sorted),
            Some(((0.5, 0.0), (0.5, 1.0)))
        );
        assert_eq!(
            clip_line_to_box(bx, by, (0.0, 2.0, 1.0)).map(sorted),
            Some(((0.0, 0.5), (2.0, 0.5)))
        );
        // Through the corner (2, 1) and the corner (0, 0): the diagonal.
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, -2.0, 0.0)).map(sorted),
            Some(((0.0, 0.0), (2.0, 1.0)))
        );
        assert_eq!(clip_line_to_box(bx, by, (1.0, 1.0, 5.0)), None);
        // Touching a single corner is no segment.
        assert_eq!(clip_line_to_box(bx, by, (1.0, 1.0, 3.0)), None);
        assert_eq!(clip_line_to_box(bx, by, (0.0, 0.0, 1.0)), None);
    }

    #[test]
    fn cell_edges_lie_halfway_between_nodes() {
        assert_eq!(
            cell_edges(&[0.0, 1.0, 3.0]),
            vec![Some((-0.5, 0.5)), Some((0.5, 2.0)), Some((2.0, 4.0))]
        );
        // Unsorted and non-finite nodes.
        assert_eq!(
            cell_edges(&[3.0, f64::NAN, 0.0, 1.0]),
            vec![Some((2.0, 4.0)), None, Some((-0.5, 0.5)), Some((0.5, 2.0))]
        );
        assert_eq!(cell_edges(&[10.0]), vec![Some((9.5, 10.5))]);
        assert_eq!(cell_edges(&[0.0]), vec![Some((-1.0, 1.0))]);
        assert!(cell_edges(&[]).is_empty());
    }
}
