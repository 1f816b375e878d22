//! The lane network (docs/SCORE.md §14.3): every driving lane of positive width, one node per lane
//! and lane section, linked in driving direction by successor/predecessor links within a road,
//! between roads, and through junction connections. Lane changes are not edges.

use std::collections::HashMap;

use super::gauss;
use super::road::{Contact, Junction, Road, RoadLink};

/// Longest step in `s` between the stored knots of a lane (m).
pub(crate) const KNOT_STEP: f64 = 2.0;

/// A driving lane within one lane section.
#[derive(Debug, Clone)]
pub(crate) struct Node {
    pub road: u32,
    pub section: u32,
    pub lane: i32,
    pub s0: f64,
    pub s1: f64,
    /// Drives along increasing `s` (right lanes under right-hand traffic).
    pub forward: bool,
    /// Nodes reachable at this lane's end in driving direction.
    pub successors: Vec<u32>,
    /// `(s, centre-line 2-D length from s0)` at the knots: every record start inside the
    /// section (see [`Road::breakpoints`]) and steps of at most [`KNOT_STEP`] between them.
    pub knots: Vec<[f64; 2]>,
}

impl Node {
    /// Centre-line length of the whole lane section.
    pub fn length(&self) -> f64 {
        self.knots.last().map_or(0.0, |k| k[1])
    }
}

/// The nodes and the lookup from (road, section, lane id).
#[derive(Debug, Clone, Default)]
pub(crate) struct Network {
    pub nodes: Vec<Node>,
    pub by_lane: HashMap<(u32, u32, i32), u32>,
}

/// 2-D speed of the centre line per unit of `s`.
#[inline]
pub(crate) fn speed(road: &Road, sec: usize, lane: i32, s: f64) -> f64 {
    let c = road.centre(sec, lane, s);
    c.d1[0].hypot(c.d1[1])
}

impl Network {
    pub fn build(roads: &[Road], junctions: &[Junction]) -> Network {
        let mut net = Network::default();
        for (ri, road) in roads.iter().enumerate() {
            for (si, sec) in road.sections.iter().enumerate() {
                // A section reaching outside the road is cut to it.
                let (s0, s1) = (sec.s0.max(0.0), sec.s1.min(road.length));
                if s1.is_nan() || s1 <= s0 {
                    continue;
                }
                let n = ((s1 - s0) / KNOT_STEP).ceil().max(1.0) as usize;
                for lane in sec.left.iter().chain(sec.right.iter()) {
                    if !lane.driving {
                        continue;
                    }
                    let positive = (0..=2 * n).any(|h| {
                        let s = s0 + (s1 - s0) * h as f64 / (2 * n) as f64;
                        road.lane_width(si, lane.id, s)[0] > 0.0
                    });
                    if !positive {
                        continue;
                    }
                    let mut cuts = vec![s0];
                    cuts.extend(road.breakpoints(si, lane.id));
                    cuts.push(s1);
                    let mut knots = vec![[s0, 0.0]];
                    let mut len = 0.0;
                    for w in cuts.windows(2) {
                        let (a, b) = (w[0], w[1]);
                        let m = ((b - a) / KNOT_STEP).ceil().max(1.0) as usize;
                        let mut prev = a;
                        for i in 1..=m {
                            let s = if i == m {
                                b
                            } else {
                                a + (b - a) * i as f64 / m as f64
                            };
                            len += gauss::integrate(prev, s, |u| speed(road, si, lane.id, u));
                            knots.push([s, len]);
                            prev = s;
                        }
                    }
                    let idx = net.nodes.len() as u32;
                    net.by_lane.insert((ri as u32, si as u32, lane.id), idx);
                    net.nodes.push(Node {
                        road: ri as u32,
                        section: si as u32,
                        lane: lane.id,
                        s0,
                        s1,
                        forward: (lane.id < 0) != road.left_hand,
                        successors: Vec::new(),
                        knots,
                    });
                }
            }
        }
        net.link(roads, junctions);
        net
    }

    /// The node of lane `lane` in the section of `road` at its `contact` end, if that node is
    /// entered (or left) there in driving direction: a lane entered at a road's start drives
    /// forward, one entered at its end drives backward.
    fn at_end(
        &self,
        roads: &[Road],
        road: usize,
        contact: Contact,
        lane: i32,
        forward_needed: bool,
    ) -> Option<u32> {
        let sec = match contact {
            Contact::Start => 0,
            Contact::End => roads[road].sections.len().checked_sub(1)?,
        };
        let n = *self.by_lane.get(&(road as u32, sec as u32, lane))?;
        (self.nodes[n as usize].forward == forward_needed).then_some(n)
    }

    fn link(&mut self, roads: &[Road], junctions: &[Junction]) {
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for (ni, node) in self.nodes.iter().enumerate() {
            let ni = ni as u32;
            let road = &roads[node.road as usize];
            let r = node.road as usize;
            let k = node.section as usize;
            let last = road.sections.len() - 1;
            let Some((side, i)) = road.sections[k].find(node.lane) else {
                continue;
            };
            let lane = &side[i];
            // Exit end and entry end of this lane in driving direction.
            let (exit_link, exit_lane, exit_inner, entry_link, entry_lane, entry_inner) =
                if node.forward {
                    (
                        road.successor,
                        lane.successor,
                        (k < last).then(|| k + 1),
                        road.predecessor,
                        lane.predecessor,
                        k.checked_sub(1),
                    )
                } else {
                    (
                        road.predecessor,
                        lane.predecessor,
                        k.checked_sub(1),
                        road.successor,
                        lane.successor,
                        (k < last).then(|| k + 1),
                    )
                };
            // Leaving: into the next section, the linked road, or a junction's connecting road.
            match (exit_inner, exit_lane) {
                (Some(next), Some(id)) => {
                    if let Some(&m) = self.by_lane.get(&(node.road, next as u32, id)) {
                        if self.nodes[m as usize].forward == node.forward {
                            edges.push((ni, m));
                        }
                    }
                }
                (Some(_), None) => {}
                (None, _) => match exit_link {
                    Some(RoadLink::Road { road: r2, contact }) => {
                        if let Some(id) = exit_lane {
                            if let Some(m) =
                                self.at_end(roads, r2, contact, id, contact == Contact::Start)
                            {
                                edges.push((ni, m));
                            }
                        }
                    }
                    Some(RoadLink::Junction { junction }) => {
                        for c in junctions[junction]
                            .connections
                            .iter()
                            .filter(|c| c.incoming == r)
                        {
                            for &(from, to) in &c.lane_links {
                                if from == node.lane {
                                    if let Some(m) = self.at_end(
                                        roads,
                                        c.connecting,
                                        c.contact,
                                        to,
                                        c.contact == Contact::Start,
                                    ) {
                                        edges.push((ni, m));
                                    }
                                }
                            }
                        }
                    }
                    None => {}
                },
            }
            // Entering: from the previous section or the linked road (a junction's connecting
            // roads link to their outgoing roads themselves).
            match (entry_inner, entry_lane) {
                (Some(prev), Some(id)) => {
                    if let Some(&m) = self.by_lane.get(&(node.road, prev as u32, id)) {
                        if self.nodes[m as usize].forward == node.forward {
                            edges.push((m, ni));
                        }
                    }
                }
                (Some(_), None) => {}
                (None, _) => {
                    if let (Some(RoadLink::Road { road: r2, contact }), Some(id)) =
                        (entry_link, entry_lane)
                    {
                        // The source leaves at `contact`: at a road's end it drives forward.
                        if let Some(m) =
                            self.at_end(roads, r2, contact, id, contact == Contact::End)
                        {
                            edges.push((m, ni));
                        }
                    }
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        for (a, b) in edges {
            self.nodes[a as usize].successors.push(b);
        }
    }

    /// Centre-line length from the node's `s0` to `s` (2-D).
    pub fn length_to(&self, roads: &[Road], n: u32, s: f64) -> f64 {
        let node = &self.nodes[n as usize];
        let s = s.clamp(node.s0, node.s1);
        let i = node
            .knots
            .partition_point(|k| k[0] <= s)
            .clamp(1, node.knots.len())
            - 1;
        let [sk, lk] = node.knots[i];
        if s == sk {
            return lk;
        }
        let road = &roads[node.road as usize];
        lk + gauss::integrate(sk, s, |u| speed(road, node.section as usize, node.lane, u))
    }

    /// The `s` whose centre-line length from `s0` is `len`.
    pub fn s_at_length(&self, roads: &[Road], n: u32, len: f64) -> f64 {
        let node = &self.nodes[n as usize];
        let i = node
            .knots
            .partition_point(|k| k[1] <= len)
            .clamp(1, node.knots.len().max(2) - 1)
            - 1;
        let ([sa, la], [sb, lb]) = (node.knots[i], node.knots[(i + 1).min(node.knots.len() - 1)]);
        if lb <= la {
            return sa;
        }
        let road = &roads[node.road as usize];
        let mut s = sa + (sb - sa) * (len - la) / (lb - la);
        for _ in 0..20 {
            let f = la
                + gauss::integrate(sa, s, |u| speed(road, node.section as usize, node.lane, u))
                - len;
            let d = speed(road, node.section as usize, node.lane, s);
            if d <= 0.0 {
                break;
            }
            let next = (s - f / d).clamp(sa, sb);
            let done = (next - s).abs() < 1e-12;
            s = next;
            if done {
                break;
            }
        }
        s
    }
}
