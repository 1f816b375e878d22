//! Whether a town's map serves a route: a map with no driving lane, or whose lanes lie far from
//! where the route's frames drove (a wrong town, a map moved or from another build), would make
//! every frame of the route look off-lane (every chunk critical) or leave it without a lateral
//! term. Such a map is not used for the route: the route falls back to the route XML, as a town
//! without a map does (docs/SCORE.md §14.3), and a warning names the map and the distance.
//!
//! The test: the median, over up to [`MAP_FIT_SAMPLES`] frames spread evenly over the route,
//! of the 2-D distance from the frame to the nearest driving lane's centre line must be at most
//! [`MAP_REACH`]. A car driving its route is within half a lane (about 2 m) of a lane centre
//! except while changing lanes or leaving the road; the median ignores those moments.
//!
//! ```
//! use monitor_host::geometry::map::Map;
//! use monitor_host::geometry::map_fit::{fit, MapFit};
//! let map = Map::parse(r#"<OpenDRIVE><road id="1" length="100" junction="-1">
//!   <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
//!   <lanes><laneSection s="0"><center><lane id="0" type="none"/></center>
//!     <right><lane id="-1" type="driving"><width sOffset="0" a="4" b="0" c="0" d="0"/></lane></right>
//!   </laneSection></lanes></road></OpenDRIVE>"#, "one-lane.xodr")?;
//! let on_lane: Vec<[f64; 3]> = (0..50).map(|x| [x as f64, 2.5, 0.0]).collect();
//! assert_eq!(fit(&map, &on_lane), MapFit::Serves);
//! let moved: Vec<[f64; 3]> = (0..50).map(|x| [x as f64, 42.0, 0.0]).collect();
//! assert_eq!(fit(&map, &moved), MapFit::TooFar { median: 40.0 });
//! let empty = Map::parse("<OpenDRIVE/>", "empty.xodr")?;
//! assert_eq!(fit(&empty, &on_lane), MapFit::NoLanes);
//! # Ok::<(), monitor_host::geometry::map::MapError>(())
//! ```

use crate::geometry::map::Map;

/// The largest median distance (m) from a route's frames to the nearest driving lane at which
/// a map still serves the route: several lane widths, far beyond a car on its road.
pub const MAP_REACH: f64 = 10.0;

/// How many frames, spread evenly over the route, are projected to judge the fit.
pub const MAP_FIT_SAMPLES: usize = 32;

/// The verdict of [`fit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapFit {
    /// The route drove on the map's lanes (or there is nothing to judge: no finite frame).
    Serves,
    /// The map has no driving lane.
    NoLanes,
    /// The frames lie this far (median, m) from the nearest driving lane.
    TooFar {
        /// The median distance (m).
        median: f64,
    },
}

/// Judges whether `map` serves a route driven through `points` (CARLA x, y, z); see the
/// module docs.
pub fn fit(map: &Map, points: &[[f64; 3]]) -> MapFit {
    if map.lane_count() == 0 {
        return MapFit::NoLanes;
    }
    let n = points.len();
    let take = n.min(MAP_FIT_SAMPLES);
    let mut d: Vec<f64> = (0..take)
        .map(|i| {
            points[if take > 1 {
                i * (n - 1) / (take - 1)
            } else {
                0
            }]
        })
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .filter_map(|p| map.project(p[0], p[1], p[2]))
        .map(|p| p.distance_2d)
        .collect();
    if d.is_empty() {
        return MapFit::Serves;
    }
    d.sort_by(f64::total_cmp);
    let median = d[(d.len() - 1) / 2];
    if median > MAP_REACH {
        MapFit::TooFar { median }
    } else {
        MapFit::Serves
    }
}
