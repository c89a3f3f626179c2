//! Plot-space geometry: gap splitting and clipping of polylines, and sampling
//! of segments with rectangles (used to keep the legend off the data).

/// Axis-aligned rectangle `[x0, x1] × [y0, y1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rect {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Rect {
    /// Whether `p` lies inside (boundary included).
    pub fn contains(&self, p: (f64, f64)) -> bool {
        p.0 >= self.x0 && p.0 <= self.x1 && p.1 >= self.y0 && p.1 <= self.y1
    }

    /// Whether two rectangles overlap.
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
}

/// Whether segment `a`–`b` meets the rectangle `r` (boundary included).
pub(crate) fn segment_meets(r: &Rect, a: (f64, f64), b: (f64, f64)) -> bool {
    clip_segment(r, a, b).is_some()
}

/// Liang–Barsky clipping of segment `a`–`b` to `r`.
fn clip_segment(r: &Rect, a: (f64, f64), b: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
    Some((
        if t0 == 0.0 { a } else { at(t0) },
        if t1 == 1.0 { b } else { at(t1) },
    ))
}

fn flush(runs: &mut Vec<Vec<(f64, f64)>>, cur: &mut Vec<(f64, f64)>) {
    if cur.len() >= 2 {
        runs.push(std::mem::take(cur));
    } else {
        cur.clear();
    }
}

/// Split a polyline at non-finite points (leaving a gap) and clip it to `r`.
/// Returns the visible runs, each with at least two points.
pub(crate) fn visible_runs<I>(points: I, r: &Rect) -> Vec<Vec<(f64, f64)>>
where
    I: IntoIterator<Item = (f64, f64)>,
{
    let mut runs = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let mut prev: Option<(f64, f64)> = None;
    for p in points {
        if !(p.0.is_finite() && p.1.is_finite()) {
            flush(&mut runs, &mut cur);
            prev = None;
            continue;
        }
        if let Some(a) = prev {
            match clip_segment(r, a, p) {
                None => flush(&mut runs, &mut cur),
                Some((c0, c1)) => {
                    if cur.last() != Some(&c0) {
                        flush(&mut runs, &mut cur);
                        cur.push(c0);
                    }
                    cur.push(c1);
                    if c1 != p {
                        flush(&mut runs, &mut cur);
                    }
                }
            }
        } else if r.contains(p) {
            cur.push(p);
        }
        prev = Some(p);
    }
    flush(&mut runs, &mut cur);
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOX: Rect = Rect {
        x0: 0.0,
        x1: 10.0,
        y0: 0.0,
        y1: 10.0,
    };

    #[test]
    fn nan_splits_line() {
        let pts = [
            (0.0, 1.0),
            (1.0, 2.0),
            (2.0, f64::NAN),
            (3.0, 3.0),
            (4.0, 4.0),
        ];
        let runs = visible_runs(pts, &BOX);
        assert_eq!(
            runs,
            vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn clipping_leaves_and_reenters() {
        let pts = [(1.0, 5.0), (3.0, 15.0), (5.0, 5.0)];
        let runs = visible_runs(pts, &BOX);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(1.0, 5.0), (2.0, 10.0)]);
        assert_eq!(runs[1], vec![(4.0, 10.0), (5.0, 5.0)]);
        assert!(visible_runs([(-5.0, -5.0), (-1.0, 20.0)], &BOX).is_empty());
        let through = visible_runs([(-5.0, 5.0), (15.0, 5.0)], &BOX);
        assert_eq!(through, vec![vec![(0.0, 5.0), (10.0, 5.0)]]);
    }
}
