//! The benchmark aggregates (`SDS-SPEC.md` v1.2 §8.1): f64, summed in input order.

use serde::Serialize;

use crate::aggregate::bench2drive::Bench2Drive;
use crate::pipeline::outcome::{RouteOutcome, TelemetryState};

/// Benchmark aggregates (spec section 8).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Summary {
    /// N (spec section 1.5): `--expected-routes`, else the route set's size, else the routes
    /// kept.
    pub routes: usize,
    /// Routes found in the input and counted (foreign routes are not).
    pub routes_found: usize,
    /// Members of the route set without a record (each counts as 0 / failed).
    pub missing: usize,
    /// Records whose route is not in the route set (left out of every aggregate).
    pub foreign: usize,
    /// Routes with defined comfort.
    pub comfort_routes: usize,
    /// Σ score_composed / N.
    pub driving_score: Option<f64>,
    /// 100 × successes / N.
    pub success_rate: Option<f64>,
    /// Σ DS_safe / N; null when some route could not be scored.
    pub mean_ds_safe: Option<f64>,
    /// Mean comfort over routes with defined comfort.
    pub mean_comfort: Option<f64>,
    /// mean_ds_safe × mean_comfort.
    pub sds: Option<f64>,
    /// 100 × routes with a collision / N.
    pub collision_rate: Option<f64>,
    /// Routes whose recorded penalty disagrees with their infractions.
    pub penalty_mismatches: Vec<String>,
    /// Routes whose telemetry is missing or invalid.
    pub telemetry_problems: usize,
    /// Invalid records.
    pub invalid_records: usize,
    /// Routes where streaming and batch disagreed (must be empty).
    pub batch_disagreements: Vec<String>,
    /// Bench2Drive's own metrics (§8.2); filled in by [`crate::report::model::build`], which
    /// knows the route set.
    pub bench2drive: Option<Bench2Drive>,
}

/// Computes the aggregates over the outcomes, in input order, with denominator `n`; `missing`
/// routes of the route set add 0 to every sum. Foreign routes are left out.
pub fn summarize(all: &[RouteOutcome], n: usize, missing: usize) -> Summary {
    let outcomes: Vec<&RouteOutcome> = all.iter().filter(|o| o.counted()).collect();
    let found = outcomes.len();
    let per = |total: f64| (n > 0).then(|| total / n as f64);
    let mut composed = 0.0f64;
    let mut successes = 0usize;
    let mut ds_safe = 0.0f64;
    let mut all_scored = true;
    let mut comfort_sum = 0.0f64;
    let mut comfort_routes = 0usize;
    let mut collided = 0usize;
    for o in &outcomes {
        let Some(r) = o.record() else {
            all_scored = false;
            continue;
        };
        composed += r.score_composed;
        successes += usize::from(r.is_success());
        match o.safe {
            Some(s) => ds_safe += s.ds_safe,
            None => all_scored = false,
        }
        if let Some(c) = o.summary.and_then(|s| s.comfort_score()) {
            comfort_sum += c;
            comfort_routes += 1;
        }
        collided += usize::from(!o.events.is_empty());
    }
    let mean_ds_safe = if all_scored { per(ds_safe) } else { None };
    let mean_comfort = (comfort_routes > 0).then(|| comfort_sum / comfort_routes as f64);
    Summary {
        routes: n,
        routes_found: found,
        missing,
        foreign: all.len() - found,
        comfort_routes,
        driving_score: per(composed),
        success_rate: per(100.0 * successes as f64),
        sds: mean_ds_safe.zip(mean_comfort).map(|(d, c)| d * c),
        mean_ds_safe,
        mean_comfort,
        collision_rate: per(100.0 * collided as f64),
        penalty_mismatches: outcomes
            .iter()
            .filter(|o| o.penalty.is_some_and(|p| !p.agrees))
            .filter_map(|o| o.record().map(|r| r.route_id.clone()))
            .collect(),
        telemetry_problems: outcomes
            .iter()
            .filter(|o| o.record().is_some() && o.telemetry != TelemetryState::Ok)
            .count(),
        invalid_records: outcomes.iter().filter(|o| o.record().is_none()).count(),
        batch_disagreements: outcomes
            .iter()
            .filter(|o| o.batch_agrees == Some(false))
            .filter_map(|o| o.record().map(|r| r.route_id.clone()))
            .collect(),
        bench2drive: None,
    }
}
