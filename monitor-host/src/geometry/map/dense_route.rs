//! The dense route (docs/SCORE.md §14.3): samples every [`DENSE_STEP`] m along each pair of
//! consecutive route waypoints' piece of the reference (the straight segment, or the map chain
//! of a filled junction gap), from P up to and including the first sample closer than
//! [`DENSE_CUTOFF`] m to Q; each sample says whether it lies in a junction when a map is given.

use super::projector::Projector;
use super::town_map::Map;

/// Spacing of the dense route's samples (m).
pub const DENSE_STEP: f64 = 1.0;
/// A pair's sampling stops at the first sample closer than this to Q (m, 2-D).
pub const DENSE_CUTOFF: f64 = 2.0;

/// One sample of the dense route.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseSample {
    /// CARLA x, y.
    pub xy: [f64; 2],
    /// Whether the sample's projection lies on a junction lane; `None` without a map.
    pub in_junction: Option<bool>,
}

/// The dense route of `waypoints` (CARLA x, y, z of the route XML). A segment longer than
/// `gap_max` is a junction gap: with a map whose lane chain fills it, its piece is that chain;
/// otherwise the straight segment. The height used to choose the lane of a sample is the
/// waypoints' height interpolated along the pair.
///
/// ```
/// use monitor_host::geometry::map::dense_route;
/// let d = dense_route(&[[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [5.0, 2.5, 0.0]], 8.0, None);
/// let xs: Vec<[f64; 2]> = d.iter().map(|s| s.xy).collect();
/// // Pair 1: 0, 1, 2, 3 m (3 m is 2 m from Q: not closer), 4 m (closer: the last).
/// // Pair 2: 0 m (2.5 m from Q), 1 m (closer: the last).
/// let expected = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0], [5.0, 0.0], [5.0, 1.0]];
/// assert_eq!(xs, expected);
/// assert!(d.iter().all(|s| s.in_junction.is_none()));
/// ```
pub fn dense_route(waypoints: &[[f64; 3]], gap_max: f64, map: Option<&Map>) -> Vec<DenseSample> {
    let mut out = Vec::new();
    let mut projector = map.map(Projector::new);
    for pair in waypoints.windows(2) {
        let (p, q) = (pair[0], pair[1]);
        let straight = vec![[p[0], p[1]], [q[0], q[1]]];
        let piece = if (q[0] - p[0]).hypot(q[1] - p[1]) > gap_max {
            map.and_then(|m| m.fill_gap(p, q)).unwrap_or(straight)
        } else {
            straight
        };
        let mut cum = Vec::with_capacity(piece.len());
        let mut total = 0.0;
        cum.push(0.0);
        for w in piece.windows(2) {
            total += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            cum.push(total);
        }
        let mut seg = 0;
        let mut k = 0usize;
        loop {
            let at = k as f64 * DENSE_STEP;
            if at > total {
                break;
            }
            while seg + 2 < piece.len() && cum[seg + 1] < at {
                seg += 1;
            }
            let xy = if piece.len() < 2 {
                piece[0]
            } else {
                let (a, b) = (piece[seg], piece[seg + 1]);
                let len = cum[seg + 1] - cum[seg];
                let f = if len > 0.0 {
                    ((at - cum[seg]) / len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]
            };
            let z = if total > 0.0 {
                p[2] + (q[2] - p[2]) * at / total
            } else {
                p[2]
            };
            let in_junction = projector
                .as_mut()
                .map(|pr| pr.project(xy[0], xy[1], z).is_some_and(|x| x.junction));
            out.push(DenseSample { xy, in_junction });
            if (xy[0] - q[0]).hypot(xy[1] - q[1]) < DENSE_CUTOFF {
                break;
            }
            k += 1;
        }
    }
    out
}
