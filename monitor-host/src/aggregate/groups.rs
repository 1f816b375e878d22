//! Breakdown groups (docs/SCORE.md §10.2): the routes counted in the aggregates, grouped by
//! scenario type, family, town, weather or a label map of routes; each group gets every §8.1
//! and §8.2 aggregate over its own routes (N = its routes) and its `infraction_routes`, and the
//! `combined` row holds the same over all routes.
//!
//! ```
//! use monitor_host::aggregate::groups::{groups, GroupBy, Labels};
//! let (g, warnings) = groups(&[], 0, GroupBy::Town, None).unwrap();
//! assert!(g.rows.is_empty() && warnings.is_empty());
//! assert_eq!(g.by, "town");
//! // Families and route labels need their label map.
//! assert!(groups(&[], 0, GroupBy::Family, None).is_err());
//! assert_eq!(groups(&[], 0, GroupBy::Route, None).unwrap_err().option, "labels");
//! ```

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::aggregate::aggregates::Aggregates;
pub use crate::input::labels::Labels;
use crate::input::route_set::parse_route_id;
use crate::input::warning::Warning;
use crate::route::row::{counted_routes, RouteReport};

named_enum! {
    /// What to group the breakdown by; its name is the group column's heading (`scenario`,
    /// `family`, `town`, `weather`, `route`) and every front end's spelling.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum GroupBy {
        /// Scenario type.
        Scenario = "scenario",
        /// Scenario family (a label map of scenario types is required).
        Family = "family",
        /// Town.
        Town = "town",
        /// Weather (the weather id, or its labels from a label map).
        Weather = "weather",
        /// A label map of routes (required), keyed by route id in any of the forms of
        /// [`route_label_key`]: a difficulty split, a train/test split, ...
        Route = "route",
    }
}

impl GroupBy {
    /// The option of `sds score` that gives the label map this grouping cannot do without
    /// (`--families`, `--labels`); `None` when the grouping works without one.
    pub fn required_labels(self) -> Option<&'static str> {
        match self {
            GroupBy::Family => Some("families"),
            GroupBy::Route => Some("labels"),
            GroupBy::Scenario | GroupBy::Town | GroupBy::Weather => None,
        }
    }

    /// Checks that a label map is given (`given`) when this grouping needs one.
    ///
    /// # Errors
    /// [`NeedsLabels`], naming the option of the missing map.
    pub fn check_labels(self, given: bool) -> Result<(), NeedsLabels> {
        match self.required_labels() {
            Some(option) if !given => Err(NeedsLabels {
                by: self.name(),
                option,
            }),
            _ => Ok(()),
        }
    }
}

/// The key under which a route label map labels `route_id`: the first of its forms the map has,
/// most specific first: `RouteScenario_1711_rep0` (one repetition), `RouteScenario_1711`, then
/// the route XML id `1711` (every repetition). A route id of another form is looked up whole.
/// `None` when the map has none of them.
///
/// ```
/// use monitor_host::aggregate::groups::{route_label_key, Labels};
/// let mut m = Labels::new();
/// m.insert("1711".into(), vec!["hard".into()]);
/// m.insert("RouteScenario_1711_rep1".into(), vec!["test".into()]);
/// assert_eq!(route_label_key("RouteScenario_1711_rep0", &m), Some("1711"));
/// assert_eq!(route_label_key("RouteScenario_1711_rep1", &m), Some("RouteScenario_1711_rep1"));
/// assert_eq!(route_label_key("RouteScenario_17_rep0", &m), None);
/// ```
pub fn route_label_key<'a>(route_id: &'a str, labels: &Labels) -> Option<&'a str> {
    let mut forms = vec![route_id];
    if let (Some((xml_id, _)), Some(rep)) = (parse_route_id(route_id), route_id.rfind("_rep")) {
        forms.extend([&route_id[..rep], xml_id]);
    }
    forms.into_iter().find(|f| labels.contains_key(*f))
}

/// The group of routes whose key is unknown (a missing route's weather, a record without town).
pub const UNKNOWN: &str = "(unknown)";
/// The group of routes whose key has no label in the label map.
pub const UNMAPPED: &str = "(unmapped)";
/// How many keys without a label the warning names.
const UNMAPPED_SHOWN: usize = 5;

/// Grouping needs a label map it was not given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("group_by = {by} needs its label map ({option})")]
pub struct NeedsLabels {
    /// The grouping.
    pub by: &'static str,
    /// The option that gives the map.
    pub option: &'static str,
}

/// One group of the breakdown.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupRow {
    /// The group's key or label.
    pub label: String,
    /// The keys a weather label map put in this group (the weather ids of `ClearNoon`), when
    /// they are not just the label; absent otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keys: Vec<String>,
    /// Its aggregates (N = its routes).
    #[serde(flatten)]
    pub aggregates: Aggregates,
}

name_field!(by_name, GroupBy::NAMES);

/// The report's `groups` (docs/SCORE.md §13).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Groups {
    /// The grouping's name.
    #[serde(deserialize_with = "by_name")]
    pub by: crate::named::Name,
    /// One row per group, in key order (numbers by value), `(unmapped)` and `(unknown)` last.
    pub rows: Vec<GroupRow>,
    /// The same aggregates over all counted routes.
    pub combined: Aggregates,
}

/// The route's group keys: one, or several when its label is a list. `Err(key)` when a label
/// map is used and has no label for `key`.
fn keys(route: &RouteReport, by: GroupBy, labels: Option<&Labels>) -> Result<Vec<String>, String> {
    let scenario = || {
        route
            .scenario_type
            .clone()
            .or_else(|| route.ability.as_ref().map(|a| a.scenario_type.clone()))
    };
    let key = match by {
        GroupBy::Scenario | GroupBy::Family => scenario(),
        GroupBy::Town => route.town.clone(),
        GroupBy::Weather => route.weather_id.clone(),
        GroupBy::Route => route.route_id.clone(),
    };
    let Some(key) = key else {
        return Ok(vec![UNKNOWN.into()]);
    };
    let Some(map) = labels else {
        return Ok(vec![key]);
    };
    let found = match by {
        GroupBy::Route => route_label_key(&key, map),
        _ => Some(key.as_str()),
    };
    match found.and_then(|k| map.get(k)) {
        Some(l) if !l.is_empty() => Ok(l.clone()),
        _ => Err(key),
    }
}

/// Row order: numbers by value, then text, then `(unmapped)`, then `(unknown)`.
fn order(label: &str) -> (u8, u64, &str) {
    match label {
        UNMAPPED => (3, 0, label),
        UNKNOWN => (4, 0, label),
        _ => match label.parse::<u64>() {
            Ok(n) if label.bytes().all(|b| b.is_ascii_digit()) => (0, n, label),
            _ => (1, 0, label),
        },
    }
}

/// The breakdown of `routes` by `by` (docs/SCORE.md §10.2): foreign routes are left out; a route counts in
/// every group its key maps to; `combined_n` is the run's N (the combined row's denominator).
/// `labels` maps keys to labels (required for [`GroupBy::Family`] and [`GroupBy::Route`]);
/// keys it does not map go to `(unmapped)`, with a warning naming the first few (by route:
/// their route ids). A route without the key is in `(unknown)`.
///
/// # Errors
/// [`NeedsLabels`] for [`GroupBy::Family`] or [`GroupBy::Route`] without a label map.
pub fn groups(
    routes: &[RouteReport],
    combined_n: usize,
    by: GroupBy,
    labels: Option<&Labels>,
) -> Result<(Groups, Vec<Warning>), NeedsLabels> {
    by.check_labels(labels.is_some())?;
    let counted: Vec<&RouteReport> = counted_routes(routes).collect();
    let mut members: BTreeMap<String, Vec<&RouteReport>> = BTreeMap::new();
    let mut unmapped_keys: Vec<String> = Vec::new();
    let mut unmapped_routes = 0;
    // Under a weather label map, the ids behind each label (the table lists them).
    let mut keys_of: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for r in &counted {
        if let (GroupBy::Weather, Some(map), Some(id)) = (by, labels, &r.weather_id) {
            for l in map.get(id).into_iter().flatten() {
                let ks = keys_of.entry(l.clone()).or_default();
                if !ks.contains(id) {
                    ks.push(id.clone());
                }
            }
        }
        let ks = keys(r, by, labels).unwrap_or_else(|key| {
            unmapped_routes += 1;
            if !unmapped_keys.contains(&key) {
                unmapped_keys.push(key);
            }
            vec![UNMAPPED.into()]
        });
        for k in ks {
            let list = members.entry(k).or_default();
            // A list label naming one group twice still counts the route once there.
            if !list.last().is_some_and(|last| std::ptr::eq(*last, *r)) {
                list.push(r);
            }
        }
    }
    let mut rows: Vec<GroupRow> = members
        .into_iter()
        .map(|(label, rs)| {
            let mut keys = keys_of.remove(&label).unwrap_or_default();
            keys.sort_by(|a, b| order(a).cmp(&order(b)));
            if keys.len() == 1 && keys[0] == label {
                keys.clear();
            }
            GroupRow {
                aggregates: Aggregates::over(&rs, rs.len()),
                label,
                keys,
            }
        })
        .collect();
    rows.sort_by(|a, b| order(&a.label).cmp(&order(&b.label)));
    let mut warnings = Vec::new();
    if unmapped_routes > 0 {
        unmapped_keys.truncate(UNMAPPED_SHOWN);
        warnings.push(Warning::Unmapped {
            by: by.name(),
            keys: unmapped_keys,
            routes: unmapped_routes,
        });
    }
    Ok((
        Groups {
            by: by.name(),
            rows,
            combined: Aggregates::over(&counted, combined_n.max(counted.len())),
        },
        warnings,
    ))
}
