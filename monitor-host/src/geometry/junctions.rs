//! Which samples of a route's dense route lie in a junction (`SDS-SPEC.md` v1.2 §1.4, §8.2):
//! the input of the Traffic_Signs junction credit. It needs the town's OpenDRIVE map; without
//! one the answer is the reason it is unknown, and the credit stays undecided. Maps are loaded
//! once per town, and only for the routes that need one.
//!
//! ```
//! use monitor_host::geometry::junctions::TownMaps;
//! use monitor_host::input::route_xml::RouteRef;
//! let maps = TownMaps::new(None);
//! let route = RouteRef { id: "1".into(), town: "Town12".into(), ..RouteRef::default() };
//! let why = maps.junction_samples(&route, "Town12", 8.0).unwrap_err();
//! assert_eq!(why, "no map for Town12 (no --maps folder given)");
//! ```

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::PathBuf;
use std::rc::Rc;

use crate::aggregate::ability::JunctionSamples;
use crate::geometry::map::{dense_route, Map, MapDir, MapError};
use crate::input::route_xml::RouteRef;

/// A town's map: loaded, absent from the folder, or broken.
#[derive(Debug)]
enum Loaded {
    Map(Rc<Map>),
    Absent(String),
    Broken(MapError),
}

/// The maps of a run: a `--maps` folder, or none. Each town's map is loaded at its first use.
#[derive(Debug, Default)]
pub struct TownMaps {
    dir: Option<MapDir>,
    towns: RefCell<HashMap<String, Loaded>>,
}

impl TownMaps {
    /// The maps in `dir` (§1.4's lookup), or no maps.
    pub fn new(dir: Option<PathBuf>) -> Self {
        TownMaps {
            dir: dir.map(MapDir::new),
            towns: RefCell::default(),
        }
    }

    fn load(&self, town: &str) -> Result<Rc<Map>, String> {
        let Some(dir) = &self.dir else {
            return Err(format!("no map for {town} (no --maps folder given)"));
        };
        let mut towns = self.towns.borrow_mut();
        let loaded = towns
            .entry(town.to_string())
            .or_insert_with(|| match dir.find(town) {
                None => Loaded::Absent(format!(
                    "no map for {town} in {} (looked for {})",
                    dir.dir().display(),
                    dir.candidates(town)
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
                Some(path) => match Map::load(&path) {
                    Ok(map) => Loaded::Map(Rc::new(map)),
                    Err(e) => Loaded::Broken(e),
                },
            });
        match loaded {
            Loaded::Map(m) => Ok(Rc::clone(m)),
            Loaded::Absent(why) => Err(why.clone()),
            Loaded::Broken(e) => Err(e.to_string()),
        }
    }

    /// The junction flags of `route`'s dense route on the map of `town`, or why they are not
    /// known. `gap_max` decides which XML segments are junction gaps (§1.3).
    pub fn junction_samples(&self, route: &RouteRef, town: &str, gap_max: f64) -> JunctionSamples {
        let map = self.load(town)?;
        Ok(dense_route(&route.waypoints_3d(), gap_max, Some(&map))
            .iter()
            .map(|s| s.in_junction == Some(true))
            .collect())
    }

    /// A map that was found but could not be read (the first, by town name): a run must not
    /// fall back silently from a broken map (§1.4).
    pub fn into_broken(self) -> Option<MapError> {
        let mut towns: Vec<(String, Loaded)> = self.towns.into_inner().into_iter().collect();
        towns.sort_by(|a, b| a.0.cmp(&b.0));
        towns.into_iter().find_map(|(_, l)| match l {
            Loaded::Broken(e) => Some(e),
            _ => None,
        })
    }
}
