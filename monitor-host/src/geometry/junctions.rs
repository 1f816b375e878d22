//! Which samples of a route's dense route lie in a junction (`SDS-SPEC.md` v1.2 §1.4, §8.2):
//! the input of the Traffic_Signs junction credit. It needs the town's OpenDRIVE map; without
//! one the answer is the reason it is unknown, and the credit stays undecided.
//!
//! ```
//! use monitor_host::geometry::junctions::TownMaps;
//! use monitor_host::input::route_xml::RouteRef;
//! let maps = TownMaps::new(None);
//! let route = RouteRef { id: "1".into(), town: "Town12".into(), ..RouteRef::default() };
//! let why = maps.junction_samples(&route, "Town12", 8.0).unwrap_err();
//! assert_eq!(why, "no map for Town12 (no --maps folder given)");
//! ```

use std::path::PathBuf;

use crate::aggregate::ability::JunctionSamples;
use crate::input::route_xml::RouteRef;

/// The maps of a run: a `--maps` folder, or none.
#[derive(Debug, Default)]
pub struct TownMaps {
    dir: Option<PathBuf>,
}

impl TownMaps {
    /// The maps in `dir` (§1.4's lookup), or no maps.
    pub fn new(dir: Option<PathBuf>) -> Self {
        TownMaps { dir }
    }

    /// The junction flags of `route`'s dense route on the map of `town`, or why they are not
    /// known. `gap_max` decides which XML segments are junction gaps (§1.3).
    pub fn junction_samples(&self, route: &RouteRef, town: &str, gap_max: f64) -> JunctionSamples {
        let _ = (route, gap_max);
        match &self.dir {
            None => Err(format!("no map for {town} (no --maps folder given)")),
            Some(dir) => Err(format!(
                "no map for {town}: reading OpenDRIVE maps from {} is not available in this build",
                dir.display()
            )),
        }
    }
}
