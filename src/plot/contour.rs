//! Contour lines of a gridded field by marching squares.
//!
//! The grid has nodes `(x[i], y[j])` with values `z[j·nx + i]`; `None` (or a non-finite value)
//! marks a failed point. Each quad of four neighbouring nodes is treated on its own: an edge
//! whose end values straddle the level gets one vertex, placed by linear interpolation *in data
//! coordinates* along that edge, `x = x_a + t (x_b − x_a)` with `t = (L − z_a)/(z_b − z_a)`.
//! So a field that is linear along each grid line (`x + y`, `x·y`) has its vertices exactly on
//! the level set, whatever the axis scales. A quad with a failed corner gets no segment:
//! nothing is ever interpolated across a failed point. Saddle quads (four crossed edges) are
//! resolved by the mean of the four corners. Segments are then joined into polylines through
//! the edges they share.

use std::collections::HashMap;

/// An edge of the grid: `(vertical, i, j)`; horizontal edges join `(i,j)–(i+1,j)`, vertical
/// ones `(i,j)–(i,j+1)`.
type EdgeKey = (bool, usize, usize);

/// The corners of quad `(i, j)` in order c0 (i,j), c1 (i+1,j), c2 (i+1,j+1), c3 (i,j+1),
/// and the edges e0..e3 (bottom, right, top, left) with their end corners.
const EDGES: [(usize, usize); 4] = [(0, 1), (1, 2), (3, 2), (0, 3)];

fn edge_key(i: usize, j: usize, e: usize) -> EdgeKey {
    match e {
        0 => (false, i, j),
        1 => (true, i + 1, j),
        2 => (false, i, j + 1),
        _ => (true, i, j),
    }
}

/// The level-`level` contour of the grid as polylines in data coordinates. Closed loops end
/// with their first point repeated. Lengths must match (`z.len() == x.len()·y.len()`);
/// mismatched input gives no lines.
pub(crate) fn contour_lines(
    x: &[f64],
    y: &[f64],
    z: &[Option<f64>],
    level: f64,
) -> Vec<Vec<(f64, f64)>> {
    let (nx, ny) = (x.len(), y.len());
    if nx < 2 || ny < 2 || z.len() != nx * ny || !level.is_finite() {
        return Vec::new();
    }
    let at = |i: usize, j: usize| z[j * nx + i].filter(|v| v.is_finite());
    let mut points: HashMap<EdgeKey, (f64, f64)> = HashMap::new();
    let mut segments: Vec<(EdgeKey, EdgeKey)> = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let nodes = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let vals = nodes.map(|(a, b)| at(a, b));
            let [Some(v0), Some(v1), Some(v2), Some(v3)] = vals else {
                continue; // a failed corner: no contour through this quad
            };
            let v = [v0, v1, v2, v3];
            let above = v.map(|z| z >= level);
            let crossed: Vec<usize> = (0..4)
                .filter(|&e| above[EDGES[e].0] != above[EDGES[e].1])
                .collect();
            for &e in &crossed {
                let (a, b) = (EDGES[e].0, EDGES[e].1);
                let t = (level - v[a]) / (v[b] - v[a]);
                let (pa, pb) = (
                    (x[nodes[a].0], y[nodes[a].1]),
                    (x[nodes[b].0], y[nodes[b].1]),
                );
                let p = (pa.0 + t * (pb.0 - pa.0), pa.1 + t * (pb.1 - pa.1));
                points.insert(edge_key(i, j, e), p);
            }
            let key = |e: usize| edge_key(i, j, e);
            match crossed.as_slice() {
                [a, b] => segments.push((key(*a), key(*b))),
                [_, _, _, _] => {
                    // saddle: cut off the corners whose side differs from the centre's
                    let centre = (v0 + v1 + v2 + v3) / 4.0 >= level;
                    for (c, (ea, eb)) in [(0, (0, 3)), (1, (0, 1)), (2, (1, 2)), (3, (2, 3))] {
                        if above[c] != centre {
                            segments.push((key(ea), key(eb)));
                        }
                    }
                }
                _ => {}
            }
        }
    }
    join(&segments)
        .into_iter()
        .map(|keys| keys.iter().filter_map(|k| points.get(k).copied()).collect())
        .collect()
}

/// Join segments sharing an edge into chains of edge keys (open chains first from their ends,
/// then closed loops, which repeat their first key at the end).
fn join(segments: &[(EdgeKey, EdgeKey)]) -> Vec<Vec<EdgeKey>> {
    let mut by_key: HashMap<EdgeKey, Vec<usize>> = HashMap::new();
    for (s, (a, b)) in segments.iter().enumerate() {
        by_key.entry(*a).or_default().push(s);
        by_key.entry(*b).or_default().push(s);
    }
    let mut used = vec![false; segments.len()];
    let mut chains = Vec::new();
    let mut starts: Vec<EdgeKey> = segments
        .iter()
        .flat_map(|(a, b)| [*a, *b])
        .filter(|k| by_key.get(k).is_some_and(|v| v.len() == 1))
        .collect();
    // then any remaining segment starts a closed loop
    starts.extend(segments.iter().map(|(a, _)| *a));
    for start in starts {
        let mut chain = vec![start];
        let mut cur = start;
        while let Some(&s) = by_key.get(&cur).and_then(|v| v.iter().find(|&&s| !used[s])) {
            used[s] = true;
            let (a, b) = segments[s];
            cur = if a == cur { b } else { a };
            chain.push(cur);
        }
        if chain.len() >= 2 {
            chains.push(chain);
        }
    }
    chains
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize, x0: f64, x1: f64, log: bool) -> (Vec<f64>, Vec<f64>) {
        let f = |k: usize, n: usize| {
            let t = k as f64 / (n - 1) as f64;
            if log {
                x0 * (x1 / x0).powf(t)
            } else {
                x0 + t * (x1 - x0)
            }
        };
        (
            (0..nx).map(|i| f(i, nx)).collect(),
            (0..ny).map(|j| f(j, ny)).collect(),
        )
    }

    fn field(x: &[f64], y: &[f64], f: impl Fn(f64, f64) -> f64) -> Vec<Option<f64>> {
        y.iter()
            .flat_map(|&yj| x.iter().map(move |&xi| (xi, yj)))
            .map(|(a, b)| Some(f(a, b)))
            .collect()
    }

    #[test]
    fn sum_contour_vertices_lie_on_the_level_line() {
        let (x, y) = grid(13, 9, 0.0, 3.0, false);
        let z = field(&x, &y, |a, b| a + b);
        for level in [0.7, 1.5, 3.0, 4.9] {
            let lines = contour_lines(&x, &y, &z, level);
            // x + y = L is one straight line across the grid: one open chain
            assert_eq!(lines.len(), 1, "level {level}");
            for (a, b) in &lines[0] {
                assert!((a + b - level).abs() < 1e-12 * level.max(1.0), "{a}+{b}");
            }
            assert!(lines[0].len() >= 2);
        }
    }

    #[test]
    fn product_contour_on_log_grid_is_exact() {
        let (x, y) = grid(20, 15, 0.1, 100.0, true);
        let z = field(&x, &y, |a, b| a * b);
        for level in [0.05, 1.0, 37.0, 2000.0] {
            let lines = contour_lines(&x, &y, &z, level);
            assert!(!lines.is_empty());
            for p in lines.iter().flatten() {
                assert!((p.0 * p.1 / level - 1.0).abs() < 1e-12, "{p:?}");
            }
        }
    }

    #[test]
    fn circle_is_one_closed_loop() {
        let (x, y) = grid(41, 41, -2.0, 2.0, false);
        let z = field(&x, &y, |a, b| a * a + b * b);
        let lines = contour_lines(&x, &y, &z, 1.0);
        assert_eq!(lines.len(), 1);
        let l = &lines[0];
        assert_eq!(l.first(), l.last());
        // vertices within the chord error of the unit circle
        assert!(l.iter().all(|p| (p.0.hypot(p.1) - 1.0).abs() < 0.01));
    }

    #[test]
    fn failed_points_stop_the_contour() {
        let (x, y) = grid(11, 11, 0.0, 10.0, false);
        let mut z = field(&x, &y, |a, _| a);
        let bad = 5 * 11 + 4; // node (4, 5)
        z[bad] = None;
        let lines = contour_lines(&x, &y, &z, 4.5);
        // the level line x = 4.5 is cut where the quads touching (4, 5) are skipped
        assert_eq!(lines.len(), 2);
        for p in lines.iter().flatten() {
            assert!((p.0 - 4.5).abs() < 1e-12);
            assert!(
                !(p.1 > 4.0 && p.1 < 6.0),
                "segment through a failed quad at {p:?}"
            );
        }
        z[bad] = Some(f64::NAN);
        assert_eq!(contour_lines(&x, &y, &z, 4.5).len(), 2);
        assert!(contour_lines(&x, &y, &z[1..], 4.5).is_empty());
    }
}

#[cfg(test)]
mod props {
    use super::contour_lines;
    use proptest::prelude::*;

    fn increasing(steps: &[f64], start: f64) -> Vec<f64> {
        // partial sums of positive steps: any strictly increasing grid
        let mut v = vec![start];
        for s in steps {
            let last = v[v.len() - 1];
            v.push(last + s);
        }
        v
    }

    proptest! {
        /// A field linear in x and y, on any increasing grid: every vertex lies on the level.
        #[test]
        fn linear_field_vertices_are_exact(
            dx in prop::collection::vec(0.01f64..2.0, 1..12),
            dy in prop::collection::vec(0.01f64..2.0, 1..12),
            a in -3.0f64..3.0, b in -3.0f64..3.0, t in 0.0f64..1.0,
        ) {
            let (x, y) = (increasing(&dx, -1.0), increasing(&dy, 0.5));
            let f = |p: (f64, f64)| a * p.0 + b * p.1;
            let z: Vec<Option<f64>> = y.iter()
                .flat_map(|&q| x.iter().map(move |&p| Some(f((p, q)))))
                .collect();
            let (lo, hi) = z.iter().flatten().fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
            let level = lo + t * (hi - lo);
            let scale = 1.0 + a.abs() * x[x.len() - 1].abs().max(1.0) + b.abs() * y[y.len() - 1].abs();
            for p in contour_lines(&x, &y, &z, level).iter().flatten() {
                prop_assert!((f(*p) - level).abs() <= 1e-12 * scale, "{:?}: {} vs {}", p, f(*p), level);
            }
        }
    }
}
