//! Breakdown groups (`SDS-SPEC.md` v1.2 §8.3): the routes counted in the aggregates, grouped by
//! scenario type, family, town or weather; each group gets every §8.1 and §8.2 aggregate over
//! its own routes (N = its routes) and its `infraction_routes`, and the `combined` row holds
//! the same over all routes.
//!
//! ```
//! use monitor_host::aggregate::groups::{groups, GroupBy, Labels};
//! let (g, warnings) = groups(&[], 0, GroupBy::Town, None).unwrap();
//! assert!(g.rows.is_empty() && warnings.is_empty());
//! assert_eq!(g.by, "town");
//! // Families need their label map.
//! assert!(groups(&[], 0, GroupBy::Family, None).is_err());
//! ```

use std::collections::BTreeMap;

use serde::Serialize;

use crate::aggregate::aggregates::Aggregates;
use crate::report::model::{counted_routes, RouteReport};
use crate::warning::Warning;

/// What to group the breakdown by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupBy {
    /// Scenario type.
    Scenario,
    /// Scenario family (a label map of scenario types is required).
    Family,
    /// Town.
    Town,
    /// Weather (the weather id, or its labels from a label map).
    Weather,
}

impl GroupBy {
    /// The group column's heading: `scenario`, `family`, `town`, `weather`.
    pub fn name(self) -> &'static str {
        match self {
            GroupBy::Scenario => "scenario",
            GroupBy::Family => "family",
            GroupBy::Town => "town",
            GroupBy::Weather => "weather",
        }
    }
}

/// Labels of scenario types (families) or weather ids, read by
/// [`crate::input::labels::read_labels`]; a key may have several labels.
pub type Labels = BTreeMap<String, Vec<String>>;

/// The group of routes whose key is unknown (a missing route's weather, a record without town).
pub const UNKNOWN: &str = "(unknown)";
/// The group of routes whose key has no label in the label map.
pub const UNMAPPED: &str = "(unmapped)";
/// How many keys without a label the warning names.
const UNMAPPED_SHOWN: usize = 5;

/// Grouping needs a label map it was not given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("--group-by {by} needs its label map ({option} FILE)")]
pub struct NeedsLabels {
    /// The grouping.
    pub by: &'static str,
    /// The option that gives the map.
    pub option: &'static str,
}

/// One group of the breakdown.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GroupRow {
    /// The group's key or label.
    pub label: String,
    /// Its aggregates (N = its routes).
    #[serde(flatten)]
    pub aggregates: Aggregates,
}

/// The report's `groups` (§10.1).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Groups {
    /// The grouping's name.
    pub by: &'static str,
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
    };
    let Some(key) = key else {
        return Ok(vec![UNKNOWN.into()]);
    };
    match labels {
        None => Ok(vec![key]),
        Some(map) => match map.get(&key) {
            Some(l) if !l.is_empty() => Ok(l.clone()),
            _ => Err(key),
        },
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

/// The breakdown of `routes` by `by` (§8.3): foreign routes are left out; a route counts in
/// every group its key maps to; `combined_n` is the run's N (the combined row's denominator).
/// `labels` maps keys to labels (required for [`GroupBy::Family`]); keys it does not map go
/// to `(unmapped)`, with a warning.
///
/// # Errors
/// [`NeedsLabels`] for [`GroupBy::Family`] without a label map.
pub fn groups(
    routes: &[RouteReport],
    combined_n: usize,
    by: GroupBy,
    labels: Option<&Labels>,
) -> Result<(Groups, Vec<Warning>), NeedsLabels> {
    if by == GroupBy::Family && labels.is_none() {
        return Err(NeedsLabels {
            by: by.name(),
            option: "--families",
        });
    }
    let counted: Vec<&RouteReport> = counted_routes(routes).collect();
    let mut members: BTreeMap<String, Vec<&RouteReport>> = BTreeMap::new();
    let mut unmapped_keys: Vec<String> = Vec::new();
    let mut unmapped_routes = 0;
    for r in &counted {
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
        .map(|(label, rs)| GroupRow {
            aggregates: Aggregates::over(&rs, rs.len()),
            label,
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
