//! Breakdown groups (`SDS-SPEC.md` v1.2 §8.3): routes grouped by scenario type, family, town or
//! weather, with each group's driving score, success rate and collision rate.

use std::collections::BTreeMap;

use crate::pipeline::outcome::RouteState;
use crate::report::model::RouteReport;

/// What to group the breakdown table by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupBy {
    /// Scenario type.
    Scenario,
    /// Scenario family (from a families file; the type itself when unmapped).
    Family,
    /// Town.
    Town,
    /// Weather (labels from a weathers file; the id when unmapped).
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
/// [`crate::input::labels::read_labels`]: a key may have several labels.
pub type Labels = BTreeMap<String, Vec<String>>;

/// One group's totals; the denominator of its rates is its own route count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Group {
    /// Routes in the group.
    pub routes: usize,
    /// Σ score_composed (0 for an invalid record).
    pub composed: f64,
    /// Successes.
    pub successes: usize,
    /// Routes with at least one collision.
    pub collided: usize,
}

impl Group {
    /// Mean driving score of the group.
    pub fn driving_score(&self) -> f64 {
        self.composed / self.routes as f64
    }

    /// 100 × successes / routes.
    pub fn success_rate(&self) -> f64 {
        100.0 * self.successes as f64 / self.routes as f64
    }

    /// 100 × routes with a collision / routes.
    pub fn collision_rate(&self) -> f64 {
        100.0 * self.collided as f64 / self.routes as f64
    }
}

/// The group keys of a route: its scenario type, town, or its family / weather labels (the key
/// itself when unlabelled); `(unknown)` when the route has none.
pub fn keys(route: &RouteReport, by: GroupBy, labels: &Labels) -> Vec<String> {
    let label = |k: &String| labels.get(k).cloned().unwrap_or_else(|| vec![k.clone()]);
    match by {
        GroupBy::Scenario => route.scenario_type.clone().map(|k| vec![k]),
        GroupBy::Family => route.scenario_type.as_ref().map(label),
        GroupBy::Town => route.town.clone().map(|k| vec![k]),
        GroupBy::Weather => route.weather_id.as_ref().map(label),
    }
    .unwrap_or_else(|| vec!["(unknown)".into()])
}

/// The routes counted in the aggregates (foreign ones left out) grouped by `by`, groups in key
/// order, routes summed in input order; a route with several labels counts in each group.
///
/// ```
/// use monitor_host::aggregate::groups::{group, Group, GroupBy, Labels};
/// let groups = group(&[], GroupBy::Town, &Labels::new());
/// assert!(groups.is_empty());
/// ```
pub fn group(routes: &[RouteReport], by: GroupBy, labels: &Labels) -> BTreeMap<String, Group> {
    let mut groups: BTreeMap<String, Group> = BTreeMap::new();
    for r in routes.iter().filter(|r| r.state != RouteState::Foreign) {
        for k in keys(r, by, labels) {
            let g = groups.entry(k).or_default();
            g.routes += 1;
            g.composed += r.score_composed.unwrap_or(0.0);
            g.successes += usize::from(r.success);
            g.collided += usize::from(!r.collision_events.is_empty());
        }
    }
    groups
}
