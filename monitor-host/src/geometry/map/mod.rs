//! OpenDRIVE maps (docs/SCORE.md §14.3): the lane network of a town, the exact 3-D projection of
//! a point onto it, junction gaps filled with the shortest lane chain, and the 1 m dense route.
//!
//! Everything here is f64 and takes and returns CARLA coordinates (OpenDRIVE's with y negated);
//! the flip happens inside. The reader, the geometry and the search are our own (see
//! `docs/MAPS.md` for why, and for the checks against CARLA's own map code).
//!
//! ```
//! use monitor_host::geometry::map::Map;
//! // One straight road along x with one driving lane on each side, 3.5 m wide.
//! let xodr = r#"<OpenDRIVE><road id="1" length="100" junction="-1">
//!   <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
//!   <lanes><laneSection s="0">
//!     <left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left>
//!     <center><lane id="0" type="none"/></center>
//!     <right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right>
//!   </laneSection></lanes></road></OpenDRIVE>"#;
//! let map = Map::parse(xodr, "straight.xodr").unwrap();
//! // CARLA's y is OpenDRIVE's -y: CARLA y = +2 is right of the reference line, lane -1.
//! let p = map.project(30.0, 2.0, 0.0).unwrap();
//! assert_eq!((map.road_id(p.lane.road), p.lane.lane), ("1", -1));
//! assert!((p.distance_2d - 0.25).abs() < 1e-12 && (p.width - 3.5).abs() < 1e-12);
//! assert_eq!(p.foot, [30.0, 1.75]);
//! ```

pub mod bounds;
mod chain;
mod clearance;
mod cubic;
mod dense_route;
mod error;
mod gauss;
mod lane;
mod lanes;
mod lookup;
mod network;
mod projection;
mod projector;
mod reference_line;
mod road;
mod town_map;
mod xodr;

pub use chain::{CHAIN_EXTRA, CHAIN_FACTOR, PIECE_MAX};
pub use dense_route::{dense_route, DenseSample, DENSE_CUTOFF, DENSE_STEP};
pub use error::MapError;
pub use lane::{LaneRef, LaneSpan, Projection, TIE_TOLERANCE};
pub use lookup::MapDir;
pub use projector::Projector;
pub use town_map::Map;
