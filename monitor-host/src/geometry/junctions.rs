//! Which samples of a route's dense route lie in a junction (docs/SCORE.md §14.3, docs/SCORE.md §10.1):
//! the input of the Traffic_Signs junction credit. It needs the town's OpenDRIVE map (from the
//! run's [`TownMaps`], loaded once before replay); without one the answer is the reason it is
//! unknown, and the credit stays undecided.
//!
//! ```
//! use monitor_host::geometry::junctions::junction_samples;
//! use monitor_host::geometry::town_maps::TownMaps;
//! use monitor_host::input::route_xml::RouteRef;
//! let maps = TownMaps::load(None, ["Town12".to_string()])?;
//! let route = RouteRef { id: "1".into(), town: "Town12".into(), ..RouteRef::default() };
//! let why = junction_samples(&maps, &route, "Town12", 8.0).unwrap_err();
//! assert_eq!(why, "no map for Town12 (no maps folder given)");
//! # Ok::<(), monitor_host::geometry::map::MapError>(())
//! ```

use crate::geometry::map::dense_route;
use crate::geometry::town_maps::TownMaps;
use crate::input::route_xml::RouteRef;

/// Which samples of a route's dense route (docs/SCORE.md §14.3) lie in a junction, in order; or why they are
/// not known (no map for the town, ...). The input of the junction credit.
pub type JunctionSamples = Result<Vec<bool>, String>;

/// The junction flags of `route`'s dense route on the map of `town`, or why they are not
/// known. `gap_max` decides which XML segments are junction gaps (docs/SCORE.md §2.3).
///
/// # Errors
/// Why the town has no map (no `--maps` folder, or where the map was looked for).
pub fn junction_samples(
    maps: &TownMaps,
    route: &RouteRef,
    town: &str,
    gap_max: f64,
) -> JunctionSamples {
    let map = maps.get(town)?;
    Ok(dense_route(&route.waypoints_3d(), gap_max, Some(map))
        .iter()
        .map(|s| s.in_junction == Some(true))
        .collect())
}
