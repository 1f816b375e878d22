//! The clearance of each lane piece: a radius around its chord within which the projection's
//! lane is known without a search. It lets [`super::Projector`] answer most frames of a drive
//! with one chord distance (and, for the exact foot, the Newton solve on a handful of pieces of
//! one lane) instead of a grid search, with the same answer bit for bit.
//!
//! For piece P of lane N, `sep(P)` bounds from below the distance from P's chord to every piece
//! Q that is neither P nor one of P's [`NEIGHBOURS`] on each side along N: the distance between
//! the two chords less Q's slack (every point of Q lies within its slack of its chord, the same
//! bound the grid search prunes with). If a point p lies within `r` of P's chord, then
//! - the lane N is at most `r + slack(P)` away (P's curve passes within its slack of every chord
//!   point), and
//! - every such Q is at least `sep(P) - r` away.
//!
//! So when `2 r < sep(P) - slack(P) - TIE_TOLERANCE - MARGIN`, no other lane is within the tie
//! tolerance of N (the search would return N alone), and N's nearest point lies on P or its
//! neighbours. [`Clearance::radius`] is that bound on `r`. `MARGIN` covers floating-point
//! rounding of the distances (nanometres) ten-thousandfold.

use std::sync::atomic::{AtomicU64, Ordering};

use super::lane::TIE_TOLERANCE;
use super::network::Network;
use super::projection::{seg_dist, Index};
use super::road::Road;

/// Pieces of the same lane on each side of P that the fast path solves itself (so they do not
/// count against P's clearance; they touch P): with 2 m pieces, the nearest piece of P's own
/// lane that counts is 2 m away. (Two on each side gave a larger radius but cost more per frame
/// than the searches it saved.)
pub(crate) const NEIGHBOURS: usize = 1;
/// `sep(P)` is looked for up to this distance (m); a piece with nothing nearer gets this. The
/// second piece along the lane is never farther than 2 m (a piece is at most 2 m long), so a
/// larger cap would only widen the search.
const SEP_CAP: f64 = 2.5;
/// Rounding allowance (m) on the certificate.
const MARGIN: f64 = 1e-5;

/// A radius not computed yet (a NaN no computation yields).
const NOT_YET: u64 = u64::MAX;

/// Per piece (in the index's order): its lane's pieces along `s`, its clearance radius
/// (computed on first use: a drive touches few of a town's pieces); per lane: its width when no
/// record changes it.
#[derive(Debug, Default)]
pub(crate) struct Clearance {
    /// The pieces of each lane in `s` order: `by_node[node_start[n]..node_start[n + 1]]`.
    by_node: Vec<u32>,
    node_start: Vec<u32>,
    /// Position of each piece in `by_node`.
    pos: Vec<u32>,
    /// Certified radius per piece (negative: none), as f64 bits, [`NOT_YET`] until needed.
    /// Threads sharing the map may both compute one: they store the same value.
    radius: Vec<AtomicU64>,
    /// Per lane: its width, when every width record of the lane is the same constant.
    const_width: Vec<Option<f64>>,
}

impl Clearance {
    pub fn build(index: &Index, roads: &[Road], net: &Network) -> Clearance {
        let pieces = &index.pieces;
        let n_nodes = net.nodes.len();
        let mut node_start = vec![0u32; n_nodes + 1];
        for p in pieces {
            node_start[p.node as usize + 1] += 1;
        }
        for n in 1..node_start.len() {
            node_start[n] += node_start[n - 1];
        }
        let mut order: Vec<u32> = (0..pieces.len() as u32).collect();
        order.sort_by(|&a, &b| {
            let (pa, pb) = (&pieces[a as usize], &pieces[b as usize]);
            pa.node.cmp(&pb.node).then(pa.s_a.total_cmp(&pb.s_a))
        });
        let by_node = order;
        let mut pos = vec![0u32; pieces.len()];
        for (i, &k) in by_node.iter().enumerate() {
            pos[k as usize] = i as u32;
        }
        Clearance {
            by_node,
            node_start,
            pos,
            radius: (0..pieces.len()).map(|_| AtomicU64::new(NOT_YET)).collect(),
            const_width: net
                .nodes
                .iter()
                .map(|n| {
                    let road = &roads[n.road as usize];
                    let (side, i) = road.sections[n.section as usize].find(n.lane)?;
                    let recs = &side[i].widths.0;
                    let a = recs.first()?.a;
                    let flat = recs
                        .iter()
                        .all(|r| r.a == a && r.b == 0.0 && r.c == 0.0 && r.d == 0.0);
                    (flat && a.is_finite()).then_some(a)
                })
                .collect(),
        }
    }

    /// The pieces P and its neighbours along its lane (the ones the fast path solves).
    pub fn near(&self, k: u32, node: u32) -> &[u32] {
        let (lo, hi) = (
            self.node_start[node as usize] as usize,
            self.node_start[node as usize + 1] as usize,
        );
        let at = self.pos[k as usize] as usize;
        &self.by_node[at.saturating_sub(NEIGHBOURS).max(lo)..(at + NEIGHBOURS + 1).min(hi)]
    }

    /// The certified radius of piece `k` (negative: none).
    #[inline]
    pub fn radius(&self, index: &Index, k: u32) -> f64 {
        let Some(slot) = self.radius.get(k as usize) else {
            return -1.0;
        };
        let bits = slot.load(Ordering::Relaxed);
        if bits != NOT_YET {
            return f64::from_bits(bits);
        }
        let sep = self.sep(index, k);
        let r = 0.5 * (sep - index.pieces[k as usize].slack - TIE_TOLERANCE - MARGIN);
        let r = if r.is_finite() && r > 0.0 { r } else { -1.0 };
        slot.store(r.to_bits(), Ordering::Relaxed);
        r
    }

    /// The constant width of lane `node`, if it has one.
    #[inline]
    pub fn const_width(&self, node: u32) -> Option<f64> {
        self.const_width.get(node as usize).copied().flatten()
    }

    /// `min over Q (chord distance(P, Q) - slack(Q))` over the pieces Q outside `near(P)`,
    /// capped at [`SEP_CAP`].
    fn sep(&self, index: &Index, k: u32) -> f64 {
        let pieces = &index.pieces;
        let p = &pieces[k as usize];
        let near = self.near(k, p.node);
        let mid = [0.5 * (p.a[0] + p.b[0]), 0.5 * (p.a[1] + p.b[1])];
        let half = 0.5 * (p.b[0] - p.a[0]).hypot(p.b[1] - p.a[1]);
        let mut sep = SEP_CAP;
        index.cells_within(mid, half + SEP_CAP, |dist2, reach, range| {
            // Every piece of the cell lies within `reach` of it, P within `half` of `mid`: skip
            // the cell when `dist - half - reach >= sep` (squared; MARGIN covers the rounding).
            let lim = sep + half + reach;
            if dist2 >= lim * lim {
                return;
            }
            for q in range {
                if near.contains(&q) {
                    continue;
                }
                let piece = &pieces[q as usize];
                // Midpoints first: chords `half` and `half_q` long about them are at least
                // `|mid - mid_q| - half - half_q` apart.
                let m = [
                    0.5 * (piece.a[0] + piece.b[0]) - mid[0],
                    0.5 * (piece.a[1] + piece.b[1]) - mid[1],
                ];
                let (qx, qy) = (piece.b[0] - piece.a[0], piece.b[1] - piece.a[1]);
                let half_q = 0.5 * (qx * qx + qy * qy).sqrt();
                let lim = sep + half + half_q + piece.slack;
                if m[0] * m[0] + m[1] * m[1] >= lim * lim {
                    continue;
                }
                let d = seg_seg(&p.a, &p.b, &piece.a, &piece.b) - piece.slack;
                sep = sep.min(d);
            }
        });
        sep
    }
}

/// Distance between segments `a0`–`a1` and `b0`–`b1` (3-D): the nearest points of the two
/// lines when both fall inside, else the nearest of the four end-to-segment distances (which
/// also covers parallel segments exactly).
fn seg_seg(a0: &[f64; 3], a1: &[f64; 3], b0: &[f64; 3], b1: &[f64; 3]) -> f64 {
    let ends = seg_dist(a0, b0, b1)
        .min(seg_dist(a1, b0, b1))
        .min(seg_dist(b0, a0, a1))
        .min(seg_dist(b1, a0, a1));
    let sub = |u: &[f64; 3], v: &[f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    let dot = |u: &[f64; 3], v: &[f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let (d1, d2, r) = (sub(a1, a0), sub(b1, b0), sub(a0, b0));
    let (a, b, e) = (dot(&d1, &d1), dot(&d1, &d2), dot(&d2, &d2));
    let (c, f) = (dot(&d1, &r), dot(&d2, &r));
    let denom = a * e - b * b;
    if denom > 0.0 {
        let s = (b * f - c * e) / denom;
        let t = (a * f - b * c) / denom;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            let g = [
                r[0] + s * d1[0] - t * d2[0],
                r[1] + s * d1[1] - t * d2[1],
                r[2] + s * d1[2] - t * d2[2],
            ];
            return ends.min(dot(&g, &g).sqrt());
        }
    }
    ends
}

impl Clone for Clearance {
    fn clone(&self) -> Self {
        Clearance {
            by_node: self.by_node.clone(),
            node_start: self.node_start.clone(),
            pos: self.pos.clone(),
            radius: self
                .radius
                .iter()
                .map(|r| AtomicU64::new(r.load(Ordering::Relaxed)))
                .collect(),
            const_width: self.const_width.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances() {
        let d =
            |a0: [f64; 3], a1: [f64; 3], b0: [f64; 3], b1: [f64; 3]| seg_seg(&a0, &a1, &b0, &b1);
        // Crossing in the plan, 1 m apart in height.
        assert_eq!(
            d([-1., 0., 0.], [1., 0., 0.], [0., -1., 1.], [0., 1., 1.]),
            1.0
        );
        // Parallel, overlapping: the gap between the lines.
        assert_eq!(
            d([0., 0., 0.], [2., 0., 0.], [1., 3., 0.], [3., 3., 0.]),
            3.0
        );
        // Collinear with a gap: end to end.
        assert_eq!(
            d([0., 0., 0.], [2., 0., 0.], [5., 0., 0.], [6., 0., 0.]),
            3.0
        );
        // Skew, nearest points outside: an end to the other segment.
        assert_eq!(
            d([0., 0., 0.], [1., 0., 0.], [3., -1., 0.], [3., 1., 0.]),
            2.0
        );
    }
}
