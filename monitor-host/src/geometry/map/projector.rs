//! Projection of a drive's consecutive points (a route's frames): the previous frame's lane
//! piece bounds the search, and inside its clearance (see `clearance.rs`) answers without one.

use std::sync::Arc;

use super::clearance::NEIGHBOURS;
use super::lane::{Projection, TIE_TOLERANCE};
use super::projection::{nearest_on, seg_dist2, Candidate};
use super::town_map::Map;

/// Projects consecutive points (a route's frames) faster. The previous answer's lane piece
/// first: when the point lies within that piece's clearance (or a neighbouring piece's of the
/// same lane), no other lane can be nearest or tied, so the answer is the exact nearest point of
/// that lane, solved on the piece and its neighbours alone; otherwise the grid search, starting
/// from that piece's distance as a bound. Either way the result is [`Map::project`]'s, bit for
/// bit.
///
/// ```
/// use monitor_host::geometry::map::{Map, Projector};
/// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
/// let mut projector = Projector::new(&map);
/// assert_eq!(projector.project(0.0, 0.0, 0.0), map.project(0.0, 0.0, 0.0));
/// ```
#[derive(Debug)]
pub struct Projector<'m> {
    map: MapRef<'m>,
    hint: Option<u32>,
    scratch: Vec<Candidate>,
    shortcuts: u64,
}

/// The map a projector reads: borrowed (a run's maps, shared by its worker threads) or held
/// (a live monitor that outlives the code that loaded its map).
#[derive(Debug, Clone)]
enum MapRef<'m> {
    Borrowed(&'m Map),
    Shared(Arc<Map>),
}

impl std::ops::Deref for MapRef<'_> {
    type Target = Map;
    fn deref(&self) -> &Map {
        match self {
            MapRef::Borrowed(m) => m,
            MapRef::Shared(m) => m,
        }
    }
}

impl Projector<'static> {
    /// A projector holding its map (for a front end that keeps it across calls, such as a live
    /// monitor); the same answers as [`Projector::new`].
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, Projector};
    /// let map = std::sync::Arc::new(Map::parse("<OpenDRIVE/>", "empty.xodr")?);
    /// assert!(Projector::shared(map).project(0.0, 0.0, 0.0).is_none());
    /// # Ok::<(), monitor_host::geometry::map::MapError>(())
    /// ```
    pub fn shared(map: Arc<Map>) -> Self {
        Projector {
            map: MapRef::Shared(map),
            hint: None,
            scratch: Vec::with_capacity(8),
            shortcuts: 0,
        }
    }
}

impl<'m> Projector<'m> {
    /// A projector over `map` with no history.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, Projector};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// let _p = Projector::new(&map);
    /// ```
    pub fn new(map: &'m Map) -> Self {
        Projector {
            map: MapRef::Borrowed(map),
            hint: None,
            scratch: Vec::with_capacity(8),
            shortcuts: 0,
        }
    }

    /// The exact projection of CARLA point `(x, y, z)`, as [`Map::project`].
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, Projector};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(Projector::new(&map).project(f64::NAN, 0.0, 0.0).is_none());
    /// ```
    pub fn project(&mut self, x: f64, y: f64, z: f64) -> Option<Projection> {
        let p = [x, -y, z];
        if let Some(c) = self
            .certified(&p)
            .and_then(|(k, d2)| self.on_lane(k, d2, &p))
        {
            self.shortcuts += 1;
            self.hint = Some(c.piece);
            return Some(self.map.describe(&c, &p, 1));
        }
        self.search(x, y, z)
    }

    /// The width of the lane under CARLA point `(x, y, z)`: `project(x, y, z)`'s `width`, bit
    /// for bit, without solving for the nearest point when the lane's width is one constant.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, Projector};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert_eq!(Projector::new(&map).width(1.0, 2.0, 0.0), None); // no lanes
    /// ```
    pub fn width(&mut self, x: f64, y: f64, z: f64) -> Option<f64> {
        let p = [x, -y, z];
        if let Some((k, _)) = self.certified(&p) {
            let node = self.map.index.pieces[k as usize].node;
            if let Some(w) = self.map.clearance.const_width(node) {
                self.shortcuts += 1;
                self.hint = Some(k);
                return Some(w);
            }
        }
        self.project(x, y, z).map(|p| p.width)
    }

    /// How many queries were answered inside a clearance, without a grid search.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, Projector};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert_eq!(Projector::new(&map).shortcuts(), 0);
    /// ```
    pub fn shortcuts(&self) -> u64 {
        self.shortcuts
    }

    /// The grid search, bounded by the previous answer's piece.
    fn search(&mut self, x: f64, y: f64, z: f64) -> Option<Projection> {
        let r = self.map.project_with(x, y, z, self.hint, &mut self.scratch);
        self.hint = r.map(|(_, piece)| piece);
        r.map(|(p, _)| p)
    }

    /// A piece whose clearance holds `p` (OpenDRIVE frame): the previous answer's, or one of its
    /// neighbours along its lane; with the squared distance from `p` to its chord. (Squares
    /// against the squared radius: the radius keeps a margin far above their rounding.)
    fn certified(&self, p: &[f64; 3]) -> Option<(u32, f64)> {
        let (index, clearance) = (&self.map.index, &self.map.clearance);
        let h = self.hint?;
        let node = index.pieces.get(h as usize)?.node;
        let inside = |k: u32| {
            let q = &index.pieces[k as usize];
            let r = clearance.radius(index, k);
            let d2 = seg_dist2(p, &q.a, &q.b);
            (r >= 0.0 && d2 <= r * r).then_some((k, d2))
        };
        if let Some(hit) = inside(h) {
            return Some(hit);
        }
        // Then the neighbours, nearest along the lane first (the drive moved on).
        let near = clearance.near(h, node);
        let at = near.iter().position(|&k| k == h)?;
        (1..near.len())
            .flat_map(|j| [at.checked_add(j), at.checked_sub(j)])
            .flatten()
            .filter_map(|i| near.get(i).copied())
            .find_map(inside)
    }

    /// The nearest point of piece `k`'s lane to `p` (inside `k`'s clearance): the grid search's
    /// candidate for that lane, the same pieces solved and the same tie rule (the first visited).
    fn on_lane(&self, k: u32, k_d2: f64, p: &[f64; 3]) -> Option<Candidate> {
        let (map, index) = (&*self.map, &self.map.index);
        let node = index.pieces[k as usize].node;
        let road = &map.roads[map.net.nodes[node as usize].road as usize];
        let mut best = f64::INFINITY;
        let mut chosen: Option<Candidate> = None;
        // The pieces by their squared chord distance, nearest first: its distance prunes the
        // others (the order changes nothing else: the least distance wins, ties as the search).
        let mut order = [(f64::INFINITY, u32::MAX); 2 * NEIGHBOURS + 1];
        for (slot, &q) in order.iter_mut().zip(map.clearance.near(k, node)) {
            let piece = &index.pieces[q as usize];
            let d2 = if q == k {
                k_d2
            } else {
                seg_dist2(p, &piece.a, &piece.b)
            };
            *slot = (d2, q);
        }
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        for (d2, q) in order {
            if q == u32::MAX {
                continue;
            }
            let piece = &index.pieces[q as usize];
            // The search's `chord distance - slack > best + tol`, squared, and loosened by far
            // more than its rounding: solving one piece too many changes nothing.
            let reach = best + TIE_TOLERANCE + piece.slack;
            if d2 > reach * reach * (1.0 + 1e-9) {
                continue;
            }
            let geometry = &road.reference.geometries[piece.geometry as usize];
            let (s, f) = nearest_on(geometry, piece, p, &index.ends[q as usize]);
            let d = f.sqrt();
            best = best.min(d);
            let wins = chosen.is_none_or(|c| {
                d < c.d || (d == c.d && index.visit_key(q, p) < index.visit_key(c.piece, p))
            });
            if wins {
                chosen = Some(Candidate {
                    node,
                    s,
                    d,
                    piece: q,
                });
            }
        }
        chosen
    }
}
