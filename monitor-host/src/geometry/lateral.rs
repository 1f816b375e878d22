//! The lateral error of a drive against its reference polyline (docs/SCORE.md §3): the
//! straight segments between consecutive route waypoints, followed with a bounded forward
//! search that re-acquires the route after a gap in the telemetry or a late start.
//!
//! ```
//! use monitor_host::geometry::lateral::LateralTracker;
//! use monitor_host::input::route_xml::parse_route_xml;
//!
//! let set = parse_route_xml(r#"<routes><route id="7" town="Town01"><waypoints>
//!     <position x="0" y="0" z="0"/><position x="2" y="0" z="0"/>
//!     <position x="30" y="0" z="0"/><position x="32" y="0" z="0"/>
//!   </waypoints></route></routes>"#)?;
//! let route = set.get("7").expect("route 7");
//! let mut tracker = LateralTracker::new(route, 8.0, 10.0);
//! assert_eq!(tracker.next([1.0, 0.5]), Some(0.5));   // beside segment 0
//! assert_eq!(tracker.next([15.0, 1.0]), None);       // beside the 28 m junction gap
//! assert_eq!(tracker.next([31.0, -0.25]), Some(0.25));
//! # Ok::<(), monitor_host::input::route_xml::RouteError>(())
//! ```

use std::borrow::Cow;

use crate::input::route_xml::RouteRef;

/// Follows a drive along a route's reference polyline and yields the lateral error per frame
/// (docs/SCORE.md §3).
///
/// Bounded forward search: the matched segment index `m` starts at 0; for each frame the
/// candidates are the segments `j >= m` whose start lies at most `lookahead` metres of route length
/// beyond the end of segment `m`. The nearest candidate (distance to the clamped segment) wins,
/// a later segment only if strictly nearer; `m` moves to it, also onto a junction gap (a segment
/// strictly longer than `gap_max`), where the lateral error is unknown. Re-acquisition
/// ([`LateralTracker::reacquire_with_point`]) drops the window for one frame.
///
/// Distances are computed in f64 relative to the segment start. The route's cumulative length is
/// computed once, in [`LateralTracker::new`]; each frame costs O(candidates). A run of identical
/// consecutive waypoints (zero-length segments, all at one point, so at one distance) counts as
/// one candidate: only its first segment can win, a later one being never strictly nearer.
/// Without this, 100,000 repeated waypoints made every frame scan all of them.
#[derive(Debug, Clone)]
pub struct LateralTracker<'a> {
    waypoints: Cow<'a, [[f64; 2]]>,
    /// `cum[i]` = route length from waypoint 0 to waypoint i (summed in order).
    cum: Vec<f64>,
    /// `after[j]`: the next candidate after segment `j` (the end of its run of zero-length
    /// segments, or `j + 1`).
    after: Vec<usize>,
    m: usize,
    gap_max: f64,
    lookahead: f64,
    evaluations: u64,
}

impl<'a> LateralTracker<'a> {
    /// A tracker at the start of `route` (spec defaults: `gap_max = 8.0`, `lookahead = 10.0`).
    pub fn new(route: &'a RouteRef, gap_max: f64, lookahead: f64) -> Self {
        Self::with(Cow::Borrowed(&route.waypoints[..]), gap_max, lookahead)
    }

    /// A tracker owning its waypoints (for a front end that keeps it across calls, such as the
    /// Python `Monitor(route=...)`).
    ///
    /// ```
    /// use monitor_host::geometry::lateral::LateralTracker;
    /// let mut t = LateralTracker::owned(vec![[0.0, 0.0], [5.0, 0.0]], 8.0, 10.0);
    /// assert_eq!(t.next([1.0, 0.5]), Some(0.5));
    /// ```
    pub fn owned(
        waypoints: Vec<[f64; 2]>,
        gap_max: f64,
        lookahead: f64,
    ) -> LateralTracker<'static> {
        LateralTracker::with(Cow::Owned(waypoints), gap_max, lookahead)
    }

    fn with(waypoints: Cow<'a, [[f64; 2]]>, gap_max: f64, lookahead: f64) -> Self {
        let mut cum = Vec::with_capacity(waypoints.len());
        let mut total = 0.0f64;
        for (i, w) in waypoints.iter().enumerate() {
            if i > 0 {
                total += seg_len(waypoints[i - 1], *w);
            }
            cum.push(total);
        }
        let nseg = waypoints.len().saturating_sub(1);
        let zero = |j: usize| waypoints[j] == waypoints[j + 1];
        let mut after = vec![0; nseg];
        for j in (0..nseg).rev() {
            after[j] = if zero(j) && j + 1 < nseg && zero(j + 1) {
                after[j + 1]
            } else {
                j + 1
            };
        }
        LateralTracker {
            waypoints,
            cum,
            after,
            m: 0,
            gap_max,
            lookahead,
            evaluations: 0,
        }
    }

    /// The lateral error of a frame at `loc` (2-D), or `None` when unknown: the matched segment is
    /// a junction gap, or the route has fewer than 2 waypoints (no segment).
    pub fn next(&mut self, loc: [f64; 2]) -> Option<f64> {
        self.next_with_point(loc).map(|(d, _)| d)
    }

    /// As [`LateralTracker::next`], with the *reference point*: the nearest point of the matched
    /// segment, whose lane gives the frame's lane width with a map (docs/SCORE.md §3).
    pub fn next_with_point(&mut self, loc: [f64; 2]) -> Option<(f64, [f64; 2])> {
        self.search(loc, false)
    }

    /// As [`LateralTracker::next_with_point`], re-acquiring the reference (docs/SCORE.md §3, v1.4): the
    /// candidates are every segment `j >= m`, the whole rest of the route, for a frame after a
    /// gap in the telemetry or the first frame of telemetry that starts mid-route
    /// ([`reacquires`] says when). Ties still keep the earlier segment.
    ///
    /// ```
    /// use monitor_host::geometry::lateral::LateralTracker;
    /// // 2 m segments along x for 100 m; the drive is first seen at x = 61.
    /// let pts: Vec<[f64; 2]> = (0..=50).map(|i| [2.0 * f64::from(i), 0.0]).collect();
    /// let mut late = LateralTracker::owned(pts.clone(), 8.0, 10.0);
    /// assert_eq!(late.reacquire_with_point([61.0, 0.5]), Some((0.5, [61.0, 0.0])));
    /// // The 10 m window alone only reaches x = 14 from the start.
    /// let mut window = LateralTracker::owned(pts, 8.0, 10.0);
    /// assert!(window.next([61.0, 0.5]).unwrap() > 40.0);
    /// ```
    pub fn reacquire_with_point(&mut self, loc: [f64; 2]) -> Option<(f64, [f64; 2])> {
        self.search(loc, true)
    }

    /// The forward search of one frame: the window of `lookahead` metres beyond segment `m`, or
    /// the whole rest of the route when `rest`.
    fn search(&mut self, loc: [f64; 2], rest: bool) -> Option<(f64, [f64; 2])> {
        let nseg = self.waypoints.len().checked_sub(1)?;
        if nseg == 0 {
            return None;
        }
        let m = self.m;
        let limit = if rest {
            f64::INFINITY
        } else {
            self.cum[m + 1] + self.lookahead
        };
        let mut best = m;
        let (mut best_d, mut best_p) = self.dist_to_segment(m, loc);
        let mut j = self.after[m];
        while j < nseg && self.cum[j] <= limit {
            let (d, p) = self.dist_to_segment(j, loc);
            if d < best_d {
                best = j;
                best_d = d;
                best_p = p;
            }
            j = self.after[j];
        }
        self.m = best;
        if seg_len(self.waypoints[best], self.waypoints[best + 1]) > self.gap_max {
            None
        } else {
            Some((best_d, best_p))
        }
    }

    /// How many segment distances were computed so far (the cost of the search).
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The currently matched segment index `m` (segment `m` joins waypoints `m` and `m + 1`).
    pub fn segment(&self) -> usize {
        self.m
    }

    /// Goes back to segment `m` (a value [`LateralTracker::segment`] returned), e.g. to undo a
    /// [`LateralTracker::next`] for a frame the monitor then refused.
    pub fn set_segment(&mut self, m: usize) {
        self.m = m.min(self.waypoints.len().saturating_sub(2));
    }

    /// Route length from the first waypoint to waypoint `i` (None if out of range).
    pub fn length_to(&self, i: usize) -> Option<f64> {
        self.cum.get(i).copied()
    }

    /// Distance from `p` to the clamped segment `j`, relative to the segment start, and the
    /// nearest point.
    fn dist_to_segment(&mut self, j: usize, p: [f64; 2]) -> (f64, [f64; 2]) {
        self.evaluations += 1;
        let a = self.waypoints[j];
        let b = self.waypoints[j + 1];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let (px, py) = (p[0] - a[0], p[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (px - t * dx, py - t * dy);
        ((ex * ex + ey * ey).sqrt(), [a[0] + t * dx, a[1] + t * dy])
    }
}

/// Whether a frame at `step` re-acquires the reference (docs/SCORE.md §3, v1.4): the first frame (`previous`
/// is `None`) when its step is not 0 (telemetry that starts mid-route), or a frame whose step
/// exceeds the previous frame's by more than `reacquire_steps` (a gap in the telemetry).
///
/// ```
/// use monitor_host::geometry::lateral::reacquires;
/// assert!(!reacquires(0, None, 10));
/// assert!(reacquires(480, None, 10));
/// assert!(!reacquires(511, Some(501), 10)); // 10 steps: within the window's reach
/// assert!(reacquires(789, Some(501), 10));
/// ```
pub fn reacquires(step: u64, previous: Option<u64>, reacquire_steps: u64) -> bool {
    match previous {
        None => step != 0,
        Some(p) => step.saturating_sub(p) > reacquire_steps,
    }
}

fn seg_len(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dx * dx + dy * dy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn route(points: &[[f64; 2]]) -> RouteRef {
        RouteRef {
            id: "r".into(),
            town: "Town01".into(),
            waypoints: points.to_vec(),
            ..RouteRef::default()
        }
    }

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-12)
    }

    #[test]
    fn straight_route() {
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [6.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([0.5, 0.3]), 0.3));
        assert!(close(t.next([3.0, -1.25]), 1.25));
        assert_eq!(t.segment(), 1);
        assert!(close(t.next([5.0, 0.0]), 0.0));
        assert_eq!(t.segment(), 2);
        assert_eq!(t.length_to(3), Some(6.0));
    }

    #[test]
    fn beyond_the_end_uses_clamped_distance() {
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        // (7, 4) is 3 m past the end and 4 m to the side: distance to the end point is 5.
        assert!(close(t.next([7.0, 4.0]), 5.0));
        assert_eq!(t.segment(), 1);
        // Before the start: distance to waypoint 0, but the tracker never goes back.
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([-3.0, 4.0]), 5.0));
        assert_eq!(t.segment(), 0);
    }

    #[test]
    fn gap_segment_is_unknown_and_m_moves_onto_it() {
        // Segment 1 is 20 m long (> 8): a junction gap. Segment 2 is 2 m.
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [22.0, 0.0], [24.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([1.0, 0.5]), 0.5));
        assert_eq!(t.next([10.0, 0.5]), None);
        assert_eq!(t.segment(), 1, "m moves onto the gap");
        // From the gap, segment 2 (start 22 m <= end of gap 22 m + 10) is a candidate.
        assert!(close(t.next([23.0, 0.25]), 0.25));
        assert_eq!(t.segment(), 2);
    }

    #[test]
    fn gap_boundary_is_strict() {
        // Exactly 8 m is not a gap; 8.5 m is.
        let r = route(&[[0.0, 0.0], [8.0, 0.0], [16.5, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([4.0, 1.0]), 1.0));
        assert_eq!(t.next([12.0, 1.0]), None);
    }

    #[test]
    fn lookahead_window_is_bounded() {
        // 2 m segments along x; a frame beside segment 9 (start 18 m) is out of reach from m = 0
        // (window: starts <= 2 + 10 = 12 m), so segment 6 (start 12 m) is the farthest candidate.
        let pts: Vec<[f64; 2]> = (0..=12).map(|i| [2.0 * i as f64, 0.0]).collect();
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        // (19, 0): nearest candidate is segment 6 ending at (14, 0): 5 m away.
        assert!(close(t.next([19.0, 0.0]), 5.0));
        assert_eq!(t.segment(), 6);
        // Now the window reaches 14 + 10 = 24 m: segment 9 is a candidate and is exact.
        assert!(close(t.next([19.0, 0.0]), 0.0));
        assert_eq!(t.segment(), 9);
    }

    #[test]
    fn loop_does_not_jump_to_second_pass() {
        // A lap around a 20 m x 20 m square of 2 m segments, then a second lap shifted 0.1 m
        // north. A frame at y = 0.1 on the first pass is 0.1 m from the first pass and 0 m from the
        // second; the second pass is > 10 m of route length away, so it must not be chosen.
        let mut pts: Vec<[f64; 2]> = Vec::new();
        for lap in 0..2 {
            let dy = 0.1 * lap as f64;
            for i in 0..10 {
                pts.push([2.0 * i as f64, dy]);
            }
            for i in 0..10 {
                pts.push([20.0, 2.0 * i as f64 + dy]);
            }
            for i in 0..10 {
                pts.push([20.0 - 2.0 * i as f64, 20.0 + dy]);
            }
            for i in 0..10 {
                pts.push([0.0, 20.0 - 2.0 * i as f64 + dy]);
            }
        }
        pts.push([0.0, 0.1]);
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        for i in 0..10 {
            let d = t.next([2.0 * i as f64 + 1.0, 0.1]);
            assert!(close(d, 0.1), "{d:?}");
        }
        assert!(
            t.segment() < 10,
            "stayed on the first pass: {}",
            t.segment()
        );
        // Drive the whole first lap; at its end the tracker enters the second lap.
        for i in 0..10 {
            t.next([20.0, 2.0 * i as f64 + 1.0]);
        }
        for i in 0..10 {
            t.next([20.0 - 2.0 * i as f64 - 1.0, 20.0]);
        }
        for i in 0..10 {
            t.next([0.0, 20.0 - 2.0 * i as f64 - 1.0]);
        }
        assert_eq!(t.segment(), 39);
        // Segment 40 runs (0, 0.1) -> (2, 0.1).
        assert!(close(t.next([1.0, -0.2]), 0.3));
        assert_eq!(
            t.segment(),
            40,
            "second pass reached by driving, not by jumping"
        );
    }

    #[test]
    fn figure_eight_crossing() {
        // Route goes east along y = 0 through the crossing at (10, 0), loops north and comes back
        // south through (10, 0) on x = 10. At the crossing the first pass must be kept.
        let mut pts: Vec<[f64; 2]> = (0..=10).map(|i| [2.0 * i as f64, 0.0]).collect(); // to (20,0)
        pts.extend((1..=5).map(|i| [20.0, 2.0 * i as f64])); // to (20,10)
        pts.extend((1..=5).map(|i| [20.0 - 2.0 * i as f64, 10.0])); // to (10,10)
        pts.extend((1..=10).map(|i| [10.0, 10.0 - 2.0 * i as f64])); // south through (10,0)
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        for i in 0..5 {
            t.next([2.0 * i as f64 + 1.0, 0.0]);
        }
        // At (10, 0.5): first pass (segment 5, y = 0) and second pass (x = 10) both at <= 0.5.
        // An unbounded search would jump to the second pass (distance 0 on x = 10).
        let d = t.next([10.0, 0.5]);
        assert!(close(d, 0.5), "{d:?}");
        assert!(t.segment() <= 5, "kept the first pass: {}", t.segment());
    }

    #[test]
    fn later_segment_wins_only_if_strictly_nearer() {
        // Segments 0 and 1 share waypoint (2, 0); a point at (2, 1) is exactly 1 m from both.
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.next([2.0, 1.0]), 1.0));
        assert_eq!(t.segment(), 0, "tie keeps m");
        assert!(close(t.next([2.5, 1.0]), 1.0));
        assert_eq!(
            t.segment(),
            1,
            "strictly nearer: (2.5,1) is 1.118 from segment 0"
        );
    }

    #[test]
    fn reacquisition_searches_the_rest_of_the_route() {
        // 2 m segments along x to 100 m. From m = 0 the window reaches 12 m; re-acquiring at
        // x = 61 finds segment 30 at once, and the window then follows from there.
        let pts: Vec<[f64; 2]> = (0..=50).map(|i| [2.0 * i as f64, 0.0]).collect();
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.reacquire_with_point([61.0, 0.5]).map(|p| p.0), 0.5));
        assert_eq!(t.segment(), 30);
        assert!(close(t.next([62.5, 0.25]), 0.25));
        assert_eq!(t.segment(), 31);
        // Never backwards: re-acquiring behind m measures against segment m's clamped start.
        assert!(close(
            t.reacquire_with_point([10.0, 0.0]).map(|p| p.0),
            52.0
        ));
        assert_eq!(t.segment(), 31);
    }

    #[test]
    fn reacquisition_keeps_the_earlier_pass_on_a_tie_and_lands_on_gaps() {
        // Out along y = 0 to (20, 0), back along y = 2 to (0, 2): a point at (9, 1) is 1 m from
        // both passes; the earlier one is kept.
        let mut pts: Vec<[f64; 2]> = (0..=10).map(|i| [2.0 * i as f64, 0.0]).collect();
        pts.extend((0..=10).map(|i| [20.0 - 2.0 * i as f64, 2.0]));
        let r = route(&pts);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert!(close(t.reacquire_with_point([9.0, 1.0]).map(|p| p.0), 1.0));
        assert_eq!(t.segment(), 4);
        // Strictly nearer to the way back: it wins.
        assert!(close(t.reacquire_with_point([9.0, 1.5]).map(|p| p.0), 0.5));
        assert!(t.segment() > 10, "{}", t.segment());
        // A gap segment (40 m) far along: m moves onto it and the error is unknown.
        let r = route(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [44.0, 0.0], [46.0, 0.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        assert_eq!(t.reacquire_with_point([30.0, 0.5]), None);
        assert_eq!(t.segment(), 2);
    }

    #[test]
    fn reacquires_at_a_late_first_step_and_after_a_gap() {
        assert!(!reacquires(0, None, 10));
        assert!(
            reacquires(1, None, 10),
            "the rule is literal: a first step that is not 0"
        );
        assert!(!reacquires(11, Some(1), 10));
        assert!(reacquires(12, Some(1), 10));
        assert!(reacquires(2, Some(1), 0));
        assert!(!reacquires(u64::MAX, Some(u64::MAX - 10), 10));
        assert!(!reacquires(3, Some(5), 10), "out of order never panics");
    }

    #[test]
    fn degenerate_routes() {
        let one = route(&[[5.0, 5.0]]);
        assert_eq!(LateralTracker::new(&one, 8.0, 10.0).next([5.0, 5.0]), None);
        let none = route(&[]);
        assert_eq!(LateralTracker::new(&none, 8.0, 10.0).next([0.0, 0.0]), None);
        // Zero-length segment: distance to the point.
        let z = route(&[[1.0, 1.0], [1.0, 1.0]]);
        assert!(close(
            LateralTracker::new(&z, 8.0, 10.0).next([4.0, 5.0]),
            5.0
        ));
    }

    #[test]
    fn large_coordinates_keep_precision() {
        // 10 km from the origin: a 1 mm offset must still come out as 1 mm.
        let r = route(&[[10_000.0, -9_000.0], [10_002.0, -9_000.0]]);
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        let d = t.next([10_001.0, -9_000.001]).unwrap();
        assert!((d - 0.001).abs() < 1e-9, "{d}");
    }

    /// The search before runs of identical waypoints were skipped, as the oracle.
    fn plain(
        route: &RouteRef,
        locs: &[[f64; 2]],
        gap_max: f64,
        lookahead: f64,
    ) -> Vec<Option<f64>> {
        let w = &route.waypoints;
        let nseg = w.len() - 1;
        let mut cum = vec![0.0];
        for i in 1..w.len() {
            let t = cum[i - 1] + seg_len(w[i - 1], w[i]);
            cum.push(t);
        }
        let probe = LateralTracker::new(route, gap_max, lookahead);
        let mut probe = probe;
        let mut m = 0;
        locs.iter()
            .map(|&p| {
                let limit = cum[m + 1] + lookahead;
                let (mut best, mut best_d) = (m, probe.dist_to_segment(m, p).0);
                let mut j = m + 1;
                while j < nseg && cum[j] <= limit {
                    let d = probe.dist_to_segment(j, p).0;
                    if d < best_d {
                        (best, best_d) = (j, d);
                    }
                    j += 1;
                }
                m = best;
                (seg_len(w[best], w[best + 1]) <= gap_max).then_some(best_d)
            })
            .collect()
    }

    #[test]
    fn identical_waypoints_cost_one_candidate() {
        // A route that stops for 100,000 repeated waypoints (as a stationary scenario may write
        // them), then goes on; and repeated points scattered along it.
        let mut pts = vec![[0.0, 0.0], [2.0, 0.0]];
        pts.extend(std::iter::repeat_n([4.0, 0.0], 100_000));
        pts.extend([
            [6.0, 0.0],
            [6.0, 0.0],
            [8.0, 1.0],
            [8.0, 1.0],
            [8.0, 1.0],
            [10.0, 1.0],
        ]);
        let r = route(&pts);
        let locs: Vec<[f64; 2]> = (0..2_000).map(|i| [f64::from(i) * 0.006, 0.3]).collect();
        let mut t = LateralTracker::new(&r, 8.0, 10.0);
        let got: Vec<Option<f64>> = locs.iter().map(|&p| t.next(p)).collect();
        // At most a handful of candidates per frame (the scan took 100,000 per frame).
        assert!(
            t.evaluations() < 20 * locs.len() as u64,
            "{}",
            t.evaluations()
        );
        // Bit-identical to the plain search on a shorter copy it can finish.
        let mut short = vec![[0.0, 0.0], [2.0, 0.0]];
        short.extend(std::iter::repeat_n([4.0, 0.0], 300));
        short.extend([
            [6.0, 0.0],
            [6.0, 0.0],
            [8.0, 1.0],
            [8.0, 1.0],
            [8.0, 1.0],
            [10.0, 1.0],
        ]);
        let s = route(&short);
        let mut t = LateralTracker::new(&s, 8.0, 10.0);
        let fast: Vec<Option<f64>> = locs.iter().map(|&p| t.next(p)).collect();
        assert_eq!(fast, plain(&s, &locs, 8.0, 10.0));
        assert_eq!(got, fast);
    }
}
