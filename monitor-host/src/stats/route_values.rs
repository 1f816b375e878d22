//! Route keys and per-route values (docs/SCORE.md §10.3): a route's key is its `route_id`
//! without the `_rep<k>` suffix (the XML id); a run holding several records of one key
//! (Leaderboard repetitions) gives the key the mean over them; a model's value is the mean over
//! its seeds.
//!
//! ```
//! use monitor_host::stats::route_values::route_key;
//! assert_eq!(route_key("RouteScenario_24785_rep1"), "24785");
//! assert_eq!(route_key("my_route"), "my_route");
//! ```

use std::collections::HashMap;

use crate::input::route_set::parse_route_id;
use crate::model::report::Report;
use crate::route::row::{counted_routes, RouteReport};
use crate::settings::Protocol;

/// The metrics every comparison has, in the bootstrap's order (docs/SCORE.md §10.3: `ds`, `success`, `ds_safe`,
/// `comfort`); the asked protocols' scores follow ([`metric_names`]).
pub const METRICS: [&str; 4] = ["ds", "success", "ds_safe", "comfort"];

/// The metrics compared when `protocols` were asked: [`METRICS`], then `ds@<id>` per protocol
/// in the report's order.
///
/// ```
/// use monitor_host::stats::route_values::metric_names;
/// use monitor_host::settings::Protocol;
/// assert_eq!(metric_names(&[Protocol::Lb21]), ["ds", "success", "ds_safe", "comfort", "ds@lb2.1"]);
/// ```
pub fn metric_names(protocols: &[Protocol]) -> Vec<String> {
    METRICS
        .iter()
        .map(|m| m.to_string())
        .chain(protocols.iter().map(|p| format!("ds@{}", p.id())))
        .collect()
}

/// One key's values, in [`metric_names`] order (`None`: undefined, left out of that metric).
pub type Values = Vec<Option<f64>>;

/// The key of a route id: the id without `RouteScenario_` and `_rep<k>` (the XML id), or the
/// whole id when it is not of that form.
pub fn route_key(route_id: &str) -> &str {
    parse_route_id(route_id).map_or(route_id, |(id, _)| id)
}

/// A route's values: `ds` = `score_composed` (a missing route 0), `success` 1 or 0, `ds_safe`,
/// `comfort` = `C_route`, then each of `protocols`' score (`ds@<id>`; a route without a valid
/// record scores 0 under every protocol).
pub fn values_of(r: &RouteReport, protocols: &[Protocol]) -> Values {
    let mut v = vec![
        Some(r.score_composed.unwrap_or(0.0)),
        Some(if r.success { 1.0 } else { 0.0 }),
        r.ds_safe,
        r.comfort.score,
    ];
    v.extend(protocols.iter().map(|p| {
        r.protocols
            .as_ref()
            .and_then(|ps| ps.get(*p))
            .map(|s| s.score)
    }));
    v
}

/// Mean of several value sets (each `metrics` long), metric by metric, summed in order;
/// undefined where any is.
pub fn mean_values(all: &[Values], metrics: usize) -> Values {
    let mut out = vec![None; metrics];
    for (m, slot) in out.iter_mut().enumerate() {
        let xs: Option<Vec<f64>> = all.iter().map(|v| v.get(m).copied().flatten()).collect();
        *slot = xs
            .filter(|x| !x.is_empty())
            .map(|x| x.iter().fold(0.0, |a, b| a + b) / x.len() as f64);
    }
    out
}

/// One run's routes by key: the keys in the order of their first record in the report (records
/// in input order, then missing routes), and each key's values averaged over its records.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunValues {
    /// Keys in report order (a key at the place of its first record).
    pub order: Vec<String>,
    /// Per key, the mean over its records.
    pub values: HashMap<String, Values>,
    /// Per key, its records' route ids (for links to the run's rows).
    pub route_ids: HashMap<String, Vec<String>>,
    /// Counted routes without a route id (unreadable files): they have no key.
    pub without_id: usize,
}

/// The counted routes of `report` by key, with the scores of `protocols`.
pub fn run_values(report: &Report, protocols: &[Protocol]) -> RunValues {
    let mut out = RunValues::default();
    let mut records: HashMap<String, Vec<Values>> = HashMap::new();
    for r in counted_routes(&report.routes) {
        let Some(id) = r.route_id.as_deref() else {
            out.without_id += 1;
            continue;
        };
        let key = route_key(id).to_string();
        let list = records.entry(key.clone()).or_default();
        if list.is_empty() {
            out.order.push(key.clone());
        }
        list.push(values_of(r, protocols));
        out.route_ids.entry(key).or_default().push(id.to_string());
    }
    let metrics = METRICS.len() + protocols.len();
    out.values = records
        .into_iter()
        .map(|(k, v)| (k, mean_values(&v, metrics)))
        .collect();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repetitions_are_averaged_and_null_wins() {
        let a = vec![Some(100.0), Some(1.0), Some(80.0), Some(0.5)];
        let b = vec![Some(50.0), Some(0.0), Some(40.0), None];
        let m = mean_values(&[a, b], 4);
        assert_eq!(m, [Some(75.0), Some(0.5), Some(60.0), None]);
        assert_eq!(mean_values(&[], 4), [None; 4]);
    }
}
