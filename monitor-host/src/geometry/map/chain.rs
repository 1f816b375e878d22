//! Junction gaps filled by the map (docs/SCORE.md §14.3): the shortest chain of driving lanes,
//! in driving direction and without lane changes, from P's projection to Q's projection, drawn
//! as chords of at most [`PIECE_MAX`] m of centre-line length.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::lane::LaneRef;
use super::town_map::Map;

/// A chain may be at most `CHAIN_FACTOR * |PQ| + CHAIN_EXTRA` m long.
pub const CHAIN_FACTOR: f64 = 3.0;
/// See [`CHAIN_FACTOR`].
pub const CHAIN_EXTRA: f64 = 20.0;
/// Longest piece of the filled gap, in centre-line length (m).
pub const PIECE_MAX: f64 = 0.5;

/// One lane of a chain, driven from `s_from` to `s_to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Leg {
    pub node: u32,
    pub s_from: f64,
    pub s_to: f64,
}

#[derive(Debug, Clone, Copy)]
enum Came {
    Start(usize),
    Through(u32),
}

/// Total order for f64 costs in the heap.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cost(f64);
impl Eq for Cost {}
impl PartialOrd for Cost {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Cost {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl Map {
    /// Length along node `n` in driving direction from its entry to road `s`.
    fn position(&self, n: u32, s: f64) -> f64 {
        let node = &self.net.nodes[n as usize];
        let l = self.net.length_to(&self.roads, n, s);
        if node.forward {
            l
        } else {
            node.length() - l
        }
    }

    fn node_of(&self, lane: &LaneRef) -> Option<u32> {
        self.net
            .by_lane
            .get(&(lane.road, lane.section, lane.lane))
            .copied()
    }

    /// The shortest chain from P's to Q's projection (CARLA x, y, z), at most `limit` m long.
    pub(crate) fn shortest_chain(
        &self,
        p: [f64; 3],
        q: [f64; 3],
        limit: f64,
    ) -> Option<(f64, Vec<Leg>)> {
        let starts: Vec<(u32, f64)> = self
            .project_tied(p[0], p[1], p[2])
            .iter()
            .filter_map(|pr| Some((self.node_of(&pr.lane)?, pr.s)))
            .collect();
        let ends: Vec<(u32, f64)> = self
            .project_tied(q[0], q[1], q[2])
            .iter()
            .filter_map(|pr| Some((self.node_of(&pr.lane)?, pr.s)))
            .collect();
        if starts.is_empty() || ends.is_empty() {
            return None;
        }
        let nodes = &self.net.nodes;
        // (total, start rank, end rank, legs)
        let mut best: Option<(f64, usize, usize, Vec<Leg>)> = None;
        let offer = |total: f64,
                     i: usize,
                     j: usize,
                     legs: &dyn Fn() -> Vec<Leg>,
                     best: &mut Option<(f64, usize, usize, Vec<Leg>)>| {
            if total > limit {
                return;
            }
            let better = match best {
                None => true,
                Some((t, bi, bj, _)) => (total, i, j) < (*t, *bi, *bj),
            };
            if better {
                *best = Some((total, i, j, legs()));
            }
        };
        let mut entry: Vec<Option<(f64, usize, Came)>> = vec![None; nodes.len()];
        let mut heap = BinaryHeap::new();
        for (i, &(n, s)) in starts.iter().enumerate() {
            let pos = self.position(n, s);
            for (j, &(m, sq)) in ends.iter().enumerate() {
                let posq = self.position(m, sq);
                if m == n && posq >= pos {
                    offer(
                        posq - pos,
                        i,
                        j,
                        &|| {
                            vec![Leg {
                                node: n,
                                s_from: s,
                                s_to: sq,
                            }]
                        },
                        &mut best,
                    );
                }
            }
            let rest = nodes[n as usize].length() - pos;
            for &m in &nodes[n as usize].successors {
                let e = &mut entry[m as usize];
                if e.is_none_or(|(c, k, _)| (rest, i) < (c, k)) {
                    *e = Some((rest, i, Came::Start(i)));
                    heap.push(Reverse((Cost(rest), m)));
                }
            }
        }
        while let Some(Reverse((Cost(c), m))) = heap.pop() {
            let Some((cm, rank, _)) = entry[m as usize] else {
                continue;
            };
            if c > cm || c > limit || best.as_ref().is_some_and(|b| c > b.0) {
                if c > limit || best.as_ref().is_some_and(|b| c > b.0) {
                    break;
                }
                continue;
            }
            for (j, &(n, sq)) in ends.iter().enumerate() {
                if n == m {
                    let total = c + self.position(n, sq);
                    offer(
                        total,
                        rank,
                        j,
                        &|| self.legs(&starts, &entry, m, sq),
                        &mut best,
                    );
                }
            }
            let through = c + nodes[m as usize].length();
            for &k in &nodes[m as usize].successors {
                let e = &mut entry[k as usize];
                if e.is_none_or(|(ck, rk, _)| (through, rank) < (ck, rk)) {
                    *e = Some((through, rank, Came::Through(m)));
                    heap.push(Reverse((Cost(through), k)));
                }
            }
        }
        best.map(|(t, _, _, legs)| (t, legs))
    }

    /// The legs of the chain that enters node `last` (best entry) and ends at `s_end`.
    fn legs(
        &self,
        starts: &[(u32, f64)],
        entry: &[Option<(f64, usize, Came)>],
        last: u32,
        s_end: f64,
    ) -> Vec<Leg> {
        let nodes = &self.net.nodes;
        let ends = |n: u32| {
            let node = &nodes[n as usize];
            if node.forward {
                (node.s0, node.s1)
            } else {
                (node.s1, node.s0)
            }
        };
        let mut legs = vec![Leg {
            node: last,
            s_from: ends(last).0,
            s_to: s_end,
        }];
        let mut at = last;
        // A chain visits at most every node once more than the start: bound the walk.
        for _ in 0..=nodes.len() {
            match entry[at as usize].map(|e| e.2) {
                Some(Came::Through(k)) => {
                    let (a, b) = ends(k);
                    legs.push(Leg {
                        node: k,
                        s_from: a,
                        s_to: b,
                    });
                    at = k;
                }
                Some(Came::Start(i)) => {
                    let (n, s) = starts[i];
                    legs.push(Leg {
                        node: n,
                        s_from: s,
                        s_to: ends(n).1,
                    });
                    break;
                }
                None => break,
            }
        }
        legs.reverse();
        legs
    }

    /// Fills the junction gap from waypoint `p` to waypoint `q` (CARLA x, y, z): the centre line
    /// of the shortest lane chain from P's projection to Q's projection, at most
    /// `3 |PQ| + 20 m` long, as points (CARLA x, y) whose consecutive chords cover at most
    /// 0.5 m of centre-line length each. `None` when no such chain exists.
    ///
    /// ```
    /// use monitor_host::geometry::map::Map;
    /// let xodr = r#"<OpenDRIVE><road id="1" length="100" junction="-1">
    ///   <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
    ///   <lanes><laneSection s="0"><center><lane id="0" type="none"/></center>
    ///     <right><lane id="-1" type="driving"><width sOffset="0" a="4" b="0" c="0" d="0"/></lane></right>
    ///   </laneSection></lanes></road></OpenDRIVE>"#;
    /// let map = Map::parse(xodr, "one-lane.xodr").unwrap();
    /// let pts = map.fill_gap([10.0, 2.0, 0.0], [30.0, 2.5, 0.0]).unwrap();
    /// assert_eq!(pts.len(), 41); // 20 m in 40 pieces of 0.5 m
    /// assert_eq!((pts[0], pts[40]), ([10.0, 2.0], [30.0, 2.0]));
    /// // Against the driving direction there is no chain.
    /// assert!(map.fill_gap([30.0, 2.0, 0.0], [10.0, 2.0, 0.0]).is_none());
    /// ```
    pub fn fill_gap(&self, p: [f64; 3], q: [f64; 3]) -> Option<Vec<[f64; 2]>> {
        let limit = CHAIN_FACTOR * (q[0] - p[0]).hypot(q[1] - p[1]) + CHAIN_EXTRA;
        let (_, legs) = self.shortest_chain(p, q, limit)?;
        let mut pts: Vec<[f64; 2]> = Vec::new();
        for leg in &legs {
            let node = &self.net.nodes[leg.node as usize];
            let lane = LaneRef {
                road: node.road,
                section: node.section,
                lane: node.lane,
            };
            let (la, lb) = (
                self.net.length_to(&self.roads, leg.node, leg.s_from),
                self.net.length_to(&self.roads, leg.node, leg.s_to),
            );
            let n = ((la - lb).abs() / PIECE_MAX - 1e-9).ceil().max(1.0) as usize;
            for k in 0..=n {
                let s = if k == 0 {
                    leg.s_from
                } else if k == n {
                    leg.s_to
                } else {
                    self.net.s_at_length(
                        &self.roads,
                        leg.node,
                        la + (lb - la) * k as f64 / n as f64,
                    )
                };
                let pt = self.centre_carla(&lane, s);
                if k == 0 {
                    if let Some(last) = pts.last() {
                        if (last[0] - pt[0]).hypot(last[1] - pt[1]) < 1e-6 {
                            continue;
                        }
                    }
                }
                pts.push(pt);
            }
        }
        Some(pts)
    }
}
