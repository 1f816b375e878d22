//! The route set of a run and its N (docs/SCORE.md §14.1): which routes the benchmark
//! holds (from `--routes`), which of them have no record (*missing*), which records are not
//! part of it (*foreign*), and the denominator N of every aggregate.
//!
//! ```
//! use monitor_host::input::route_set::{route_set, benchmark_size};
//! use monitor_host::input::route_xml::parse_route_xml;
//! let xml = parse_route_xml(r#"<routes>
//!   <route id="1" town="Town01"><waypoints><position x="0" y="0" z="0"/></waypoints>
//!     <scenarios><scenario name="Accident_1" type="Accident"/></scenarios></route>
//!   <route id="2" town="Town02"><waypoints><position x="0" y="0" z="0"/></waypoints></route>
//! </routes>"#)?;
//! let set = route_set(&xml, ["RouteScenario_1_rep0", "RouteScenario_9_rep0"]);
//! assert_eq!(set.members, ["RouteScenario_1_rep0", "RouteScenario_2_rep0"]);
//! assert_eq!(set.missing[0].route_id, "RouteScenario_2_rep0");
//! assert_eq!(set.missing[0].town.as_deref(), Some("Town02"));
//! assert!(!set.contains("RouteScenario_9_rep0"));
//! assert_eq!(benchmark_size(None, Some(&set), 1), 2);
//! # Ok::<(), monitor_host::RouteError>(())
//! ```

use std::collections::{BTreeSet, HashMap, HashSet};

use crate::input::route_xml::RouteSet;

named_enum! {
    /// Which routes of the route XML make the route set **\[decision\]** (the setting's
    /// value: `all` or `found`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
    pub enum RouteSubset {
        /// Every route of the XML: a route without a record is missing and counts as 0
        /// (default; Bench2Drive's fixed 220).
        #[default]
        All = "all",
        /// The XML's routes that have a record (a debug run of 20 routes is scored over 20;
        /// its abilities and groups too).
        Found = "found",
    }
}

/// A member of the route set without any record: it counts as 0 / failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MissingRoute {
    /// `RouteScenario_<id>_rep<k>`.
    pub route_id: String,
    /// The XML route id.
    pub xml_id: String,
    /// The XML's `town` (`None` when empty).
    pub town: Option<String>,
    /// The XML's scenario type.
    pub scenario_type: Option<String>,
}

/// The route set of a run given a route XML.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunRouteSet {
    /// Every member, in XML order (repetitions of one id in increasing k).
    pub members: Vec<String>,
    /// Members without a record, in XML order.
    pub missing: Vec<MissingRoute>,
    /// Under [`RouteSubset::Found`]: the XML's routes (with their repetitions) before the routes
    /// without a record were left out; `None` for the whole XML.
    pub subset_of: Option<usize>,
    lookup: HashSet<String>,
}

impl RunRouteSet {
    /// True when the route id is a member.
    pub fn contains(&self, route_id: &str) -> bool {
        self.lookup.contains(route_id)
    }

    /// Size of the set.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when the XML has no route.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }
}

/// The fingerprint of a run's route set (docs/SCORE.md §13, the report's
/// `inputs.route_set`): how many routes are counted, and the SHA-256 of their ids sorted
/// byte-wise and joined with `\n`, so two reports show at a glance whether they ran the same
/// routes.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct RouteSetId {
    /// Counted route ids.
    pub routes: usize,
    /// SHA-256 (lowercase hex) of the sorted ids joined with `\n`.
    pub sha256: String,
}

/// The [`RouteSetId`] of these route ids (in any order).
///
/// ```
/// use monitor_host::input::route_set::route_set_id;
/// let id = route_set_id(["RouteScenario_2_rep0", "RouteScenario_10_rep0"]);
/// assert_eq!(id.routes, 2);
/// assert_eq!(id, route_set_id(["RouteScenario_10_rep0", "RouteScenario_2_rep0"]));
/// // SHA-256 of "" (no route).
/// assert_eq!(route_set_id(Vec::<&str>::new()).sha256,
///            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
/// ```
pub fn route_set_id<'a>(ids: impl IntoIterator<Item = &'a str>) -> RouteSetId {
    use sha2::{Digest, Sha256};
    let mut ids: Vec<&str> = ids.into_iter().collect();
    ids.sort_unstable_by(|a, b| a.as_bytes().cmp(b.as_bytes()));
    let digest = Sha256::digest(ids.join("\n").as_bytes());
    RouteSetId {
        routes: ids.len(),
        sha256: digest.iter().map(|b| format!("{b:02x}")).collect(),
    }
}

/// Splits `RouteScenario_<id>_rep<k>` into (`<id>`, k).
pub fn parse_route_id(route_id: &str) -> Option<(&str, u64)> {
    let rest = route_id.strip_prefix("RouteScenario_")?;
    let (id, rep) = rest.rsplit_once("_rep")?;
    Some((id, rep.parse().ok()?))
}

/// The route set: every `RouteScenario_<id>_rep<k>` for each route id of the XML and each
/// repetition k found among that id's records (rep0 when it has none); `records` are the
/// route ids of the records kept.
pub fn route_set<'a>(xml: &RouteSet, records: impl IntoIterator<Item = &'a str>) -> RunRouteSet {
    let records: Vec<&str> = records.into_iter().collect();
    let mut reps: HashMap<&str, BTreeSet<u64>> = HashMap::new();
    for id in &records {
        if let Some((xml_id, k)) = parse_route_id(id) {
            reps.entry(xml_id).or_default().insert(k);
        }
    }
    let have: HashSet<&str> = records.iter().copied().collect();
    let mut set = RunRouteSet::default();
    let mut seen = HashSet::new();
    for r in xml.iter() {
        if !seen.insert(r.id.as_str()) {
            continue; // a duplicate XML id: its first route counts
        }
        let ks: Vec<u64> = reps
            .get(r.id.as_str())
            .map_or_else(|| vec![0], |s| s.iter().copied().collect());
        for k in ks {
            let route_id = format!("RouteScenario_{}_rep{k}", r.id);
            if !have.contains(route_id.as_str()) {
                set.missing.push(MissingRoute {
                    route_id: route_id.clone(),
                    xml_id: r.id.clone(),
                    town: (!r.town.is_empty()).then(|| r.town.clone()),
                    scenario_type: r.scenario_type.clone(),
                });
            }
            set.lookup.insert(route_id.clone());
            set.members.push(route_id);
        }
    }
    set
}

/// The route set restricted by `subset`: under [`RouteSubset::Found`], only the members that
/// have a record (no missing route), remembering the size of the whole set.
///
/// ```
/// use monitor_host::input::route_set::{route_set, route_subset, RouteSubset};
/// use monitor_host::input::route_xml::parse_route_xml;
/// let xml = parse_route_xml(r#"<routes>
///   <route id="1" town="T"><waypoints><position x="0" y="0" z="0"/></waypoints></route>
///   <route id="2" town="T"><waypoints><position x="0" y="0" z="0"/></waypoints></route>
/// </routes>"#)?;
/// let set = route_subset(route_set(&xml, ["RouteScenario_1_rep0"]), RouteSubset::Found);
/// assert_eq!((set.members.len(), set.missing.len(), set.subset_of), (1, 0, Some(2)));
/// # Ok::<(), monitor_host::RouteError>(())
/// ```
pub fn route_subset(mut set: RunRouteSet, subset: RouteSubset) -> RunRouteSet {
    if subset == RouteSubset::All {
        return set;
    }
    let all = set.members.len();
    let missing: HashSet<String> = set.missing.drain(..).map(|m| m.route_id).collect();
    set.members.retain(|m| !missing.contains(m));
    set.lookup.retain(|m| !missing.contains(m));
    set.subset_of = Some(all);
    set
}

/// N (docs/SCORE.md §14.1): `expected` (`--expected-routes`) if given, else the size of the route
/// set if there is one, else the number of routes kept (`counted`).
pub fn benchmark_size(expected: Option<usize>, set: Option<&RunRouteSet>, counted: usize) -> usize {
    expected.or(set.map(RunRouteSet::len)).unwrap_or(counted)
}
