//! The nearest frame to a position, fast: a 2-d tree over the frames' locations, with the exact
//! answer of the plain scan (docs/SCORE.md §6): the smallest distance `min` over every frame,
//! then the earliest frame whose distance is within `tie` of it, if `min <= max_dist`.
//!
//! Distances are the scan's own `sqrt(dx² + dy²)` in f64, and every pruning bound is computed
//! with the same formula on a coordinate difference that is never larger than the true one
//! (rounding is monotone), so no frame the scan would pick is ever pruned: the answer is
//! bit-identical (property test `nearest_index_matches_the_scan` in
//! `tests/tests/it/parsers_never_panic.rs` against the old quadratic scan). A query costs
//! O(log frames) on real routes instead of O(frames); building costs O(frames log frames).
//!
//! ```
//! use monitor_host::geometry::nearest::NearestIndex;
//! let locs = [[0.0, 0.0], [5.0, 0.0], [5.0005, 0.0], [5.0, 0.0]];
//! let index = NearestIndex::new(&locs);
//! assert_eq!(index.nearest(5.0006, 0.0, 1.0, 1e-3), Some(1)); // 1, 2, 3 tie: the earliest
//! assert_eq!(index.nearest(7.5, 0.0, 1.0, 1e-3), None); // 2.4995 m away
//! ```

/// The distance formula of the scan.
#[inline]
fn dist(dx: f64, dy: f64) -> f64 {
    (dx * dx + dy * dy).sqrt()
}

/// A 2-d tree over frame locations, stored implicitly: the node of the range `lo..hi` is at
/// `lo + (hi - lo) / 2`, its children are the ranges on either side, split on the axis along
/// which the range is widest. Each node keeps the bounding box of its subtree (the lower bound
/// of every distance in it) and its earliest frame index.
#[derive(Clone, Debug)]
pub struct NearestIndex {
    /// `(x, y, frame index)`, finite locations only, in tree order.
    points: Vec<(f64, f64, usize)>,
    /// Per node: the smallest frame index in its subtree.
    min_index: Vec<usize>,
    /// Per node: the bounding box of its subtree, `[x_min, x_max, y_min, y_max]`.
    bbox: Vec<[f64; 4]>,
}

/// A subtree: the range of tree positions it covers.
#[derive(Clone, Copy)]
struct Range {
    lo: usize,
    hi: usize,
}

impl Range {
    fn node(self) -> Option<usize> {
        (self.lo < self.hi).then(|| self.lo + (self.hi - self.lo) / 2)
    }
}

impl NearestIndex {
    /// Builds the index in O(frames log frames); frames with a non-finite coordinate are left
    /// out (the scan never picks them either).
    pub fn new(locations: &[[f64; 2]]) -> Self {
        let mut points: Vec<(f64, f64, usize)> = locations
            .iter()
            .enumerate()
            .filter(|(_, p)| p[0].is_finite() && p[1].is_finite())
            .map(|(i, p)| (p[0], p[1], i))
            .collect();
        let n = points.len();
        let mut index = NearestIndex {
            points: Vec::new(),
            min_index: vec![usize::MAX; n],
            bbox: vec![[0.0; 4]; n],
        };
        build(&mut points, &mut index, Range { lo: 0, hi: n });
        index.points = points;
        index
    }

    /// The frame nearest to (x, y) as [`crate::pipeline::align::nearest_frame`] defines it:
    /// `None` without frames, for a non-finite query, or when the smallest distance exceeds
    /// `max_dist` (inclusive: exactly `max_dist` aligns); otherwise the earliest frame within
    /// `tie` of the smallest distance.
    pub fn nearest(&self, x: f64, y: f64, max_dist: f64, tie: f64) -> Option<usize> {
        if !(x.is_finite() && y.is_finite()) || self.points.is_empty() {
            return None;
        }
        let all = Range {
            lo: 0,
            hi: self.points.len(),
        };
        let mut min = f64::INFINITY;
        self.smallest(x, y, all, &mut min);
        if min
            .partial_cmp(&max_dist)
            .is_none_or(|o| o == std::cmp::Ordering::Greater)
        {
            return None;
        }
        let mut best = usize::MAX;
        self.earliest(x, y, min, tie, all, &mut best);
        (best != usize::MAX).then_some(best)
    }

    /// A lower bound of the distance from (x, y) to every point of the subtree at `node`: the
    /// scan's formula on differences never larger than a point's (rounding is monotone).
    fn bound(&self, node: usize, x: f64, y: f64) -> f64 {
        let [x0, x1, y0, y1] = self.bbox[node];
        let dx = if x < x0 {
            x0 - x
        } else if x > x1 {
            x - x1
        } else {
            0.0
        };
        let dy = if y < y0 {
            y0 - y
        } else if y > y1 {
            y - y1
        } else {
            0.0
        };
        dist(dx, dy)
    }

    fn children(r: Range, mid: usize) -> [Range; 2] {
        [
            Range { lo: r.lo, hi: mid },
            Range {
                lo: mid + 1,
                hi: r.hi,
            },
        ]
    }

    fn smallest(&self, x: f64, y: f64, r: Range, min: &mut f64) {
        let Some(mid) = r.node() else { return };
        if self.bound(mid, x, y) >= *min {
            return; // nothing nearer below
        }
        let (px, py, _) = self.points[mid];
        let d = dist(px - x, py - y);
        if d < *min {
            *min = d;
        }
        let mut kids = Self::children(r, mid)
            .map(|c| (c, c.node().map_or(f64::INFINITY, |n| self.bound(n, x, y))));
        if kids[1].1 < kids[0].1 {
            kids.swap(0, 1);
        }
        for (c, _) in kids {
            self.smallest(x, y, c, min);
        }
    }

    fn earliest(&self, x: f64, y: f64, min: f64, tie: f64, r: Range, best: &mut usize) {
        let Some(mid) = r.node() else { return };
        // Nothing earlier below, or everything below outside the tie band.
        if self.min_index[mid] >= *best || self.bound(mid, x, y) - min > tie {
            return;
        }
        let (px, py, i) = self.points[mid];
        if i < *best && dist(px - x, py - y) - min <= tie {
            *best = i;
        }
        let mut kids =
            Self::children(r, mid).map(|c| (c, c.node().map_or(usize::MAX, |n| self.min_index[n])));
        if kids[1].1 < kids[0].1 {
            kids.swap(0, 1);
        }
        for (c, _) in kids {
            self.earliest(x, y, min, tie, c, best);
        }
    }
}

/// Builds the subtree over `r` of `points` (reordered in place); returns its earliest index and
/// bounding box.
fn build(
    points: &mut [(f64, f64, usize)],
    index: &mut NearestIndex,
    r: Range,
) -> (usize, [f64; 4]) {
    let Some(mid) = r.node() else {
        return (
            usize::MAX,
            [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ],
        );
    };
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in &points[r.lo..r.hi] {
        b = [b[0].min(p.0), b[1].max(p.0), b[2].min(p.1), b[3].max(p.1)];
    }
    let k = mid - r.lo;
    if b[1] - b[0] >= b[3] - b[2] {
        points[r.lo..r.hi].select_nth_unstable_by(k, |a, c| a.0.total_cmp(&c.0));
    } else {
        points[r.lo..r.hi].select_nth_unstable_by(k, |a, c| a.1.total_cmp(&c.1));
    }
    let [left, right] = NearestIndex::children(r, mid);
    let (l, _) = build(points, index, left);
    let (rr, _) = build(points, index, right);
    let m = points[mid].2.min(l).min(rr);
    index.min_index[mid] = m;
    index.bbox[mid] = b;
    (m, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standing_still_is_logarithmic_and_earliest() {
        // 100,000 frames at one spot (a car waiting at a light): the earliest wins.
        let locs = vec![[3.0, 4.0]; 100_000];
        let index = NearestIndex::new(&locs);
        for _ in 0..10_000 {
            assert_eq!(index.nearest(3.0, 4.5, 1.0, 1e-3), Some(0));
        }
        // The same with sensor noise: a cluster of distinct points.
        let locs: Vec<[f64; 2]> = (0..100_000)
            .map(|i| {
                [
                    3.0 + f64::from(i % 317) * 1e-9,
                    4.0 + f64::from(i % 211) * 1e-9,
                ]
            })
            .collect();
        let index = NearestIndex::new(&locs);
        for _ in 0..10_000 {
            assert_eq!(index.nearest(3.0, 4.5, 1.0, 1e-3), Some(0));
        }
        assert_eq!(index.nearest(f64::NAN, 0.0, 1.0, 1e-3), None);
        assert_eq!(NearestIndex::new(&[]).nearest(0.0, 0.0, 1.0, 1e-3), None);
    }
}
