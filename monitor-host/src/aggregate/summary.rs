//! The run's summary (docs/SCORE.md §10, docs/SCORE.md §13): the §8.1 scores over N and the counts
//! behind them (routes found, missing, foreign; problems).

use serde::{Deserialize, Serialize};

use crate::aggregate::aggregates::Scores;
use crate::aggregate::bench2drive::Bench2Drive;
use crate::pipeline::outcome::{RouteState, TelemetryState};
use crate::route::row::RouteReport;

/// Benchmark aggregates (docs/SCORE.md §9).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Summary {
    /// N (docs/SCORE.md §14.1): `--expected-routes`, else the route set's size, else the routes
    /// kept.
    pub routes: usize,
    /// Routes found in the input and counted (foreign routes are not).
    pub routes_found: usize,
    /// Members of the route set without a record (each counts as 0 / failed).
    pub missing: usize,
    /// Records whose route is not in the route set (left out of every aggregate).
    pub foreign: usize,
    /// The §8.1 scores over N ([`Scores::over`]).
    #[serde(flatten)]
    pub scores: Scores,
    /// Routes whose recorded penalty disagrees with their infractions.
    pub penalty_mismatches: Vec<String>,
    /// Routes whose telemetry is missing or invalid.
    pub telemetry_problems: usize,
    /// Invalid records.
    pub invalid_records: usize,
    /// Routes where streaming and batch disagreed (must be empty).
    pub batch_disagreements: Vec<String>,
    /// Bench2Drive's own metrics (docs/SCORE.md §10.1); filled in by [`crate::model::report::assemble`], which
    /// knows the route set.
    pub bench2drive: Option<Bench2Drive>,
    /// Every asked scoring protocol's aggregates (docs/PROTOCOLS.md, docs/SCORE.md §13); absent when none is asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocols: Option<crate::route::protocol::aggregate::ProtocolScores>,
}

/// The run's summary: the §8.1 `scores` (over N, computed by [`Scores::over`] from the counted
/// routes' rows), with the counts of the rows behind them (`all`: every row of the report, in
/// its order; missing routes of the route set are in N, foreign routes left out). From rows
/// alone, so that a merge of reports (docs/SCORE.md §13.2) computes it as `sds score` does.
pub fn summarize(all: &[RouteReport], scores: Scores, n: usize) -> Summary {
    let found: Vec<&RouteReport> = all
        .iter()
        .filter(|r| !matches!(r.state, RouteState::Foreign | RouteState::Missing))
        .collect();
    // A row has a record exactly when it has a status (an invalid record has none).
    let with_record = || found.iter().filter(|r| r.status.is_some());
    Summary {
        routes: n,
        routes_found: found.len(),
        missing: all
            .iter()
            .filter(|r| r.state == RouteState::Missing)
            .count(),
        foreign: all
            .iter()
            .filter(|r| r.state == RouteState::Foreign)
            .count(),
        scores,
        penalty_mismatches: crate::route::row::counted_routes(all)
            .filter(|r| r.penalty_check.as_ref().is_some_and(|p| !p.agrees))
            .filter_map(|r| r.route_id.clone())
            .collect(),
        telemetry_problems: with_record()
            .filter(|r| r.telemetry != TelemetryState::Ok)
            .count(),
        invalid_records: found.iter().filter(|r| r.status.is_none()).count(),
        batch_disagreements: with_record()
            .filter(|r| r.batch_agrees == Some(false))
            .filter_map(|r| r.route_id.clone())
            .collect(),
        bench2drive: None,
        protocols: None,
    }
}
