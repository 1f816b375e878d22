//! The maps of a run (docs/SCORE.md §14.3): each town's OpenDRIVE map from the `--maps`
//! folder, loaded once before the routes are replayed and shared by every worker thread.
//!
//! ```
//! use monitor_host::geometry::town_maps::TownMaps;
//! let maps = TownMaps::load(None, ["Town01".to_string()])?;
//! assert_eq!(maps.get("Town01").unwrap_err(), "no map for Town01 (no maps folder given)");
//! # Ok::<(), monitor_host::geometry::map::MapError>(())
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::geometry::map::{Map, MapDir, MapError};
use crate::input::record::Record;
use crate::input::route_xml::RouteSet;

/// The town maps of a run: for each town asked for, its map or why there is none.
#[derive(Debug, Default)]
pub struct TownMaps {
    towns: BTreeMap<String, Result<Map, String>>,
    given: bool,
    files: Vec<PathBuf>,
}

impl TownMaps {
    /// Loads the map of each of `towns` (each once, in parallel) from `dir` (docs/SCORE.md §14.3's lookup).
    ///
    /// # Errors
    /// A map that was found but cannot be read (the first by town name): a run never falls
    /// back silently from a broken map. The error names the file and the element.
    pub fn load(
        dir: Option<&Path>,
        towns: impl IntoIterator<Item = String>,
    ) -> Result<TownMaps, MapError> {
        let names: Vec<String> = towns
            .into_iter()
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let Some(dir) = dir else {
            let towns = names
                .into_iter()
                .map(|t| {
                    let why = format!("no map for {t} (no maps folder given)");
                    (t, Err(why))
                })
                .collect();
            return Ok(TownMaps {
                towns,
                given: false,
                files: Vec::new(),
            });
        };
        let dir = MapDir::new(dir);
        // Per town: the map or why it is absent, or the error of a broken map.
        type Loaded = Result<Result<(Map, PathBuf), String>, MapError>;
        let loaded: Vec<(String, Loaded)> = names
            .into_par_iter()
            .map(|town| {
                let r = match dir.find(&town) {
                    None => Ok(Err(absent(&dir, &town))),
                    Some(path) => Map::load(&path).map(|m| Ok((m, path))),
                };
                (town, r)
            })
            .collect();
        let mut towns = BTreeMap::new();
        let mut files = Vec::new();
        for (town, r) in loaded {
            let r = r?.map(|(map, path)| {
                files.push(path);
                map
            });
            towns.insert(town, r);
        }
        Ok(TownMaps {
            towns,
            given: true,
            files,
        })
    }

    /// The map of `town`, or why there is none.
    ///
    /// # Errors
    /// The reason (no `--maps` folder, or where the map was looked for).
    pub fn get(&self, town: &str) -> Result<&Map, String> {
        match self.towns.get(town) {
            Some(Ok(m)) => Ok(m),
            Some(Err(why)) => Err(why.clone()),
            None if self.given => Err(format!("no map for {town} (town not loaded)")),
            None => Err(format!("no map for {town} (no maps folder given)")),
        }
    }

    /// The map files read (in town order): inputs a report must never be written over.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// A `--maps` folder was given.
    pub fn given(&self) -> bool {
        self.given
    }
}

/// The map file of `town` in the maps folder `dir` (the lookup of [`TownMaps::load`]), or why
/// there is none (where it was looked for).
///
/// ```
/// use monitor_host::geometry::town_maps::find_map;
/// let dir = tempfile::tempdir()?;
/// std::fs::write(dir.path().join("Town04.xodr"), "<OpenDRIVE/>")?;
/// assert_eq!(find_map(dir.path(), "Town04"), Ok(dir.path().join("Town04.xodr")));
/// assert!(find_map(dir.path(), "Town05").unwrap_err().starts_with("no map for Town05 in "));
/// # Ok::<(), std::io::Error>(())
/// ```
///
/// # Errors
/// The reason, naming the folder and the files looked for.
pub fn find_map(dir: &Path, town: &str) -> Result<PathBuf, String> {
    let dir = MapDir::new(dir);
    dir.find(town).ok_or_else(|| absent(&dir, town))
}

fn absent(dir: &MapDir, town: &str) -> String {
    let looked: Vec<String> = dir
        .candidates(town)
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    format!(
        "no map for {town} in {} (looked for {})",
        dir.dir().display(),
        looked.join(", ")
    )
}

/// The town a record drove in: its own `town_name`, else its route XML entry's `town`.
pub fn town_of<'a>(record: &'a Record, routes: Option<&'a RouteSet>) -> Option<&'a str> {
    record
        .town_name
        .as_deref()
        .filter(|t| !t.is_empty())
        .or_else(|| {
            let id = record.xml_id()?;
            routes?.get(id).map(|r| r.town.as_str())
        })
        .filter(|t| !t.is_empty())
}
