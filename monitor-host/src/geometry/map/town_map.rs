//! A town's OpenDRIVE map: read, checked, indexed; the projections of points onto its lanes.

use super::clearance::Clearance;
use super::network::Network;
use super::projection::{Candidate, Index};
use super::road::{road_id_key, Road};
use std::path::Path;

use super::error::MapError;
use super::lane::{LaneRef, LaneSpan, Projection, TIE_TOLERANCE};

/// A town's OpenDRIVE map, ready for projections.
#[derive(Debug, Clone)]
pub struct Map {
    pub(super) file: String,
    pub(super) roads: Vec<Road>,
    pub(super) net: Network,
    pub(super) index: Index,
    pub(super) clearance: Clearance,
}

impl Map {
    /// Reads and checks a map file.
    ///
    /// ```
    /// use monitor_host::geometry::map::Map;
    /// let err = Map::load(std::path::Path::new("no/such/Town01.xodr")).unwrap_err();
    /// assert!(err.to_string().contains("Town01.xodr"));
    /// ```
    pub fn load(path: &Path) -> Result<Map, MapError> {
        let file = path.display().to_string();
        // The guarded reader: regular files only, at most 1 GiB (a FIFO never blocks).
        let kind = crate::input::read::FileKind::Map;
        let bytes = crate::input::read::read_input(path, kind).map_err(|source| MapError::Io {
            file: file.clone(),
            source,
        })?;
        let text = String::from_utf8(bytes).map_err(|e| MapError::Xml {
            file: file.clone(),
            message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        })?;
        Map::parse(&text, &file)
    }

    /// Builds a map from the XML text of an OpenDRIVE file; `file` names it in errors.
    ///
    /// ```
    /// use monitor_host::geometry::map::Map;
    /// let err = Map::parse("<OpenDRIVE><road id=\"7\" length=\"-1\"/></OpenDRIVE>", "t.xodr");
    /// assert_eq!(err.unwrap_err().to_string(), "t.xodr: road 7: negative length -1");
    /// ```
    pub fn parse(xml: &str, file: &str) -> Result<Map, MapError> {
        let parsed = super::xodr::parse(xml, file)?;
        let net = Network::build(&parsed.roads, &parsed.junctions);
        let index = Index::build(&parsed.roads, &net);
        let clearance = Clearance::build(&index, &parsed.roads, &net);
        Ok(Map {
            file: file.to_string(),
            roads: parsed.roads,
            net,
            index,
            clearance,
        })
    }

    /// The file the map was read from.
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert_eq!(map.file(), "empty.xodr");
    /// ```
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The OpenDRIVE id of road `road` (an index, as in [`LaneRef::road`]).
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert_eq!(map.road_id(0), "");  // out of range: empty
    /// ```
    pub fn road_id(&self, road: u32) -> &str {
        self.roads.get(road as usize).map_or("", |r| r.id.as_str())
    }

    /// Number of lanes (driving lanes of positive width, per lane section) in the network.
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert_eq!(map.lane_count(), 0);
    /// ```
    pub fn lane_count(&self) -> usize {
        self.net.nodes.len()
    }

    /// Every lane of the network, in map order.
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.lanes().is_empty());
    /// ```
    pub fn lanes(&self) -> Vec<LaneSpan> {
        self.net
            .nodes
            .iter()
            .map(|n| LaneSpan {
                lane: LaneRef {
                    road: n.road,
                    section: n.section,
                    lane: n.lane,
                },
                s0: n.s0,
                s1: n.s1,
                length: n.length(),
                forward: n.forward,
                junction: self.roads[n.road as usize].junction.is_some(),
            })
            .collect()
    }

    /// The exact projection of CARLA point `(x, y, z)` onto the lane network; `None` for a map
    /// without driving lanes or a non-finite point.
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.project(1.0, 2.0, 0.0).is_none());
    /// ```
    pub fn project(&self, x: f64, y: f64, z: f64) -> Option<Projection> {
        let mut scratch = Vec::with_capacity(8);
        self.project_with(x, y, z, None, &mut scratch)
            .map(|(p, _)| p)
    }

    /// Every lane whose centre line lies within `margin` (m, 3-D) of the nearest one, nearest
    /// first (ties: road id, lane id). With `margin = TIE_TOLERANCE` these are the tied lanes.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, TIE_TOLERANCE};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.project_within(0.0, 0.0, 0.0, TIE_TOLERANCE).is_empty());
    /// ```
    pub fn project_within(&self, x: f64, y: f64, z: f64, margin: f64) -> Vec<Projection> {
        let mut out = Vec::new();
        let p = [x, -y, z];
        self.index
            .search(&self.roads, &self.net, &p, margin.max(0.0), None, &mut out);
        let mut all: Vec<Projection> = self
            .dedup(&mut out)
            .iter()
            .map(|c| self.describe(c, &p, 1))
            .collect();
        let n = all.len();
        for a in &mut all {
            a.tied = n;
        }
        all.sort_by(|a, b| {
            a.distance_3d
                .total_cmp(&b.distance_3d)
                .then_with(|| self.tie_order(&a.lane, &b.lane))
        });
        all
    }

    /// The lanes tied for nearest (within [`TIE_TOLERANCE`]), in tie-break order: smallest road
    /// id, then smallest lane id.
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.project_tied(0.0, 0.0, 0.0).is_empty());
    /// ```
    pub fn project_tied(&self, x: f64, y: f64, z: f64) -> Vec<Projection> {
        let mut all = self.project_within(x, y, z, TIE_TOLERANCE);
        all.sort_by(|a, b| self.tie_order(&a.lane, &b.lane));
        all
    }

    fn tie_order(&self, a: &LaneRef, b: &LaneRef) -> std::cmp::Ordering {
        road_id_key(self.road_id(a.road))
            .cmp(&road_id_key(self.road_id(b.road)))
            .then(a.lane.cmp(&b.lane))
            .then(a.section.cmp(&b.section))
    }

    /// Removes the copies of one point found at a lane section boundary (the end of one
    /// section is the start of the next: the later section holds it).
    fn dedup<'c>(&self, cands: &'c mut Vec<Candidate>) -> &'c [Candidate] {
        let nodes = &self.net.nodes;
        let mut i = 0;
        while i < cands.len() {
            let a = cands[i];
            let na = &nodes[a.node as usize];
            let dup = cands.iter().any(|b| {
                let nb = &nodes[b.node as usize];
                nb.road == na.road
                    && nb.section > na.section
                    && (b.s - a.s).abs() < 1e-9
                    && (b.d - a.d).abs() < 1e-9
            });
            if dup {
                cands.swap_remove(i);
            } else {
                i += 1;
            }
        }
        cands
    }

    pub(super) fn describe(&self, c: &Candidate, p: &[f64; 3], tied: usize) -> Projection {
        let node = &self.net.nodes[c.node as usize];
        let road = &self.roads[node.road as usize];
        let sec = node.section as usize;
        let piece = &self.index.pieces[c.piece as usize];
        let sel = 0.5 * (piece.s_a + piece.s_b);
        let (at, width) = road.centre_point_and_width_in(sec, node.lane, c.s, sel);
        Projection {
            lane: LaneRef {
                road: node.road,
                section: node.section,
                lane: node.lane,
            },
            s: c.s,
            width,
            distance_2d: (at[0] - p[0]).hypot(at[1] - p[1]),
            distance_3d: c.d,
            junction: road.junction.is_some(),
            foot: [at[0], -at[1]],
            foot_z: at[2],
            tied,
        }
    }

    /// Projection with an optional hint piece; returns the piece that held the answer.
    pub(super) fn project_with(
        &self,
        x: f64,
        y: f64,
        z: f64,
        hint: Option<u32>,
        scratch: &mut Vec<Candidate>,
    ) -> Option<(Projection, u32)> {
        let p = [x, -y, z];
        self.index
            .search(&self.roads, &self.net, &p, TIE_TOLERANCE, hint, scratch);
        let cands = self.dedup(scratch);
        let chosen = cands.iter().min_by(|a, b| {
            let (na, nb) = (
                &self.net.nodes[a.node as usize],
                &self.net.nodes[b.node as usize],
            );
            self.tie_order(
                &LaneRef {
                    road: na.road,
                    section: na.section,
                    lane: na.lane,
                },
                &LaneRef {
                    road: nb.road,
                    section: nb.section,
                    lane: nb.lane,
                },
            )
        })?;
        let nearest = cands.iter().min_by(|a, b| a.d.total_cmp(&b.d))?.piece;
        Some((self.describe(chosen, &p, cands.len()), nearest))
    }

    /// The centre point of `lane` at road `s`, CARLA x/y.
    pub(super) fn centre_carla(&self, lane: &LaneRef, s: f64) -> [f64; 2] {
        let road = &self.roads[lane.road as usize];
        let p = road.centre(lane.section as usize, lane.lane, s).p;
        [p[0], -p[1]]
    }

    /// The centre point of `lane` at road `s` (CARLA x, y, z), or `None` if the lane is not in
    /// the map.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, LaneRef};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.lane_point(&LaneRef { road: 0, section: 0, lane: -1 }, 0.0).is_none());
    /// ```
    pub fn lane_point(&self, lane: &LaneRef, s: f64) -> Option<[f64; 3]> {
        let road = self.roads.get(lane.road as usize)?;
        let sec = road.sections.get(lane.section as usize)?;
        sec.find(lane.lane)?;
        let p = road.centre(lane.section as usize, lane.lane, s).p;
        Some([p[0], -p[1], p[2]])
    }

    /// The lane section holding road `s` of road `road` and the lane there, as a [`LaneRef`].
    ///
    /// ```
    /// # use monitor_host::geometry::map::Map;
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.lane_at("1", -1, 0.0).is_none());
    /// ```
    pub fn lane_at(&self, road_id: &str, lane: i32, s: f64) -> Option<LaneRef> {
        let (ri, road) = self
            .roads
            .iter()
            .enumerate()
            .find(|(_, r)| r.id == road_id)?;
        let sec = road.section_at(s);
        road.sections.get(sec)?.find(lane)?;
        Some(LaneRef {
            road: ri as u32,
            section: sec as u32,
            lane,
        })
    }

    /// The width of `lane` at road `s`.
    ///
    /// ```
    /// # use monitor_host::geometry::map::{Map, LaneRef};
    /// # let map = Map::parse("<OpenDRIVE/>", "empty.xodr").unwrap();
    /// assert!(map.lane_width(&LaneRef { road: 0, section: 0, lane: -1 }, 0.0).is_none());
    /// ```
    pub fn lane_width(&self, lane: &LaneRef, s: f64) -> Option<f64> {
        let road = self.roads.get(lane.road as usize)?;
        road.sections.get(lane.section as usize)?.find(lane.lane)?;
        Some(road.lane_width(lane.section as usize, lane.lane, s)[0])
    }
}
