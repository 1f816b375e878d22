//! The parts of an OpenDRIVE road this tool uses, in f64 and OpenDRIVE's frame: the reference
//! line, elevation, lane offset, lane sections with their lanes, and the links between roads.

use super::cubic::Piecewise;
use super::reference_line::ReferenceLine;

/// Which end of a road a link meets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Contact {
    Start,
    End,
}

/// A road's `<predecessor>` or `<successor>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RoadLink {
    Road { road: usize, contact: Contact },
    Junction { junction: usize },
}

/// One `<lane>` of a lane section (not the centre lane).
#[derive(Debug, Clone)]
pub(crate) struct Lane {
    pub id: i32,
    /// `type="driving"`.
    pub driving: bool,
    /// Width records, starts relative to the section start (`sOffset`).
    pub widths: Piecewise,
    pub predecessor: Option<i32>,
    pub successor: Option<i32>,
}

/// One `<laneSection>`, covering `[s0, s1)` (the road's last one includes its end).
#[derive(Debug, Clone)]
pub(crate) struct LaneSection {
    pub s0: f64,
    pub s1: f64,
    /// Lanes 1, 2, ... (left of the reference line), by increasing id.
    pub left: Vec<Lane>,
    /// Lanes -1, -2, ... (right), by decreasing id.
    pub right: Vec<Lane>,
}

impl LaneSection {
    /// The lanes on the side of `id`, and the position of lane `id` among them.
    pub fn find(&self, id: i32) -> Option<(&[Lane], usize)> {
        let side = if id > 0 { &self.left } else { &self.right };
        side.iter().position(|l| l.id == id).map(|i| (&side[..], i))
    }
}

/// One `<road>`.
#[derive(Debug, Clone)]
pub(crate) struct Road {
    pub id: String,
    pub length: f64,
    /// The `junction` attribute when it is not `-1`.
    pub junction: Option<String>,
    pub reference: ReferenceLine,
    pub elevation: Piecewise,
    pub lane_offset: Piecewise,
    pub sections: Vec<LaneSection>,
    pub predecessor: Option<RoadLink>,
    pub successor: Option<RoadLink>,
    /// `rule="LHT"`: left lanes drive along increasing s.
    pub left_hand: bool,
}

/// One junction `<connection>`.
#[derive(Debug, Clone)]
pub(crate) struct Connection {
    pub incoming: usize,
    pub connecting: usize,
    pub contact: Contact,
    /// `(from, to)` lane ids.
    pub lane_links: Vec<(i32, i32)>,
}

/// One `<junction>`.
#[derive(Debug, Clone)]
pub(crate) struct Junction {
    pub connections: Vec<Connection>,
}

/// Order of road ids for tie-breaking: numeric ids by value, before any other id, which sort
/// bytewise.
pub(crate) fn road_id_key(id: &str) -> (u8, i64, &str) {
    match id.parse::<i64>() {
        Ok(n) => (0, n, ""),
        Err(_) => (1, 0, id),
    }
}
