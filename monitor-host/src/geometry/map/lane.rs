//! The lane facts a projection answers with: which lane, where on it, how tied.

/// Lanes whose centre lines lie within this distance (m) of the nearest one are *tied*.
pub const TIE_TOLERANCE: f64 = 1e-3;

/// A driving lane in one lane section: the road (an index into the map, see [`Map::road_id`](super::Map::road_id)),
/// the lane section's index in the road, and the OpenDRIVE lane id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LaneRef {
    /// Index of the road in the map (file order).
    pub road: u32,
    /// Index of the lane section in the road.
    pub section: u32,
    /// OpenDRIVE lane id (negative: right of the reference line).
    pub lane: i32,
}

/// The projection of a point onto the lane network.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// The lane (among tied lanes: the smallest road id, then the smallest lane id).
    pub lane: LaneRef,
    /// Road `s` of the nearest point.
    pub s: f64,
    /// The lane's width there (m).
    pub width: f64,
    /// 2-D distance from the point to the nearest point (m).
    pub distance_2d: f64,
    /// 3-D distance, with the road's elevation, that chose the lane (m).
    pub distance_3d: f64,
    /// The lane belongs to a junction road (`junction` attribute not -1).
    pub junction: bool,
    /// The nearest point, CARLA x/y.
    pub foot: [f64; 2],
    /// Height of the nearest point (the road's elevation at `s`).
    pub foot_z: f64,
    /// How many lanes are tied (within [`TIE_TOLERANCE`] of the nearest distance), this one
    /// included.
    pub tied: usize,
}

/// One lane of the network (a driving lane of positive width in one lane section).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneSpan {
    /// The lane.
    pub lane: LaneRef,
    /// Road `s` where the lane section starts.
    pub s0: f64,
    /// Road `s` where it ends.
    pub s1: f64,
    /// Centre-line length (m, 2-D).
    pub length: f64,
    /// The lane drives along increasing `s`.
    pub forward: bool,
    /// The road belongs to a junction.
    pub junction: bool,
}
