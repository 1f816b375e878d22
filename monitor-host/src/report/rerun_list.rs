//! The rerun list (`SDS-SPEC.md` v1.4 §13): the routes to run again, one per line in the route
//! XML's id form with the reason after a tab, so that a Leaderboard `--routes-subset` can read
//! the ids (`cut -f1 rerun.tsv | paste -sd,`). What users did by deleting records from the
//! results JSON by hand before `RESUME=1`.
//!
//! ```
//! use monitor_host::report::rerun_list::{crashed_status, xml_id};
//! assert!(crashed_status("Failed - TickRuntime"));
//! assert!(crashed_status("Failed - Simulation crashed"));
//! assert!(!crashed_status("Failed - Agent got blocked"));
//! assert_eq!(xml_id("RouteScenario_24785_rep0"), "24785");
//! assert_eq!(xml_id("my_route"), "my_route");
//! ```

use crate::model::report::Report;
use crate::pipeline::outcome::RouteState;

/// Why a route is run again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RerunReason {
    /// A member of the route set without a record.
    Missing,
    /// The evaluator or the agent crashed (its status says so).
    Crashed,
    /// The record is invalid.
    InvalidRecord,
}

impl RerunReason {
    /// `missing`, `crashed` or `invalid record`.
    pub fn name(self) -> &'static str {
        match self {
            RerunReason::Missing => "missing",
            RerunReason::Crashed => "crashed",
            RerunReason::InvalidRecord => "invalid record",
        }
    }
}

/// A status that says the run crashed rather than the agent drove badly: the Leaderboard's
/// `Failed - Simulation crashed`, `Failed - Agent crashed`, `Failed - Agent couldn't be set up`,
/// `Failed - Agent took too long to set up`, Bench2Drive's `Failed - TickRuntime`, and a
/// record left `Started`. `Failed - Agent got blocked` and the timeouts are the agent's doing.
pub fn crashed_status(status: &str) -> bool {
    let s = status.to_ascii_lowercase();
    s.contains("crash")
        || s.contains("tickruntime")
        || s.contains("set up")
        || s.trim() == "started"
}

/// `RouteScenario_<id>_rep<k>` → `<id>` (the route set's own reading of an id,
/// [`crate::input::route_set::parse_route_id`]); any other id unchanged.
pub fn xml_id(route_id: &str) -> &str {
    crate::input::route_set::parse_route_id(route_id).map_or(route_id, |(id, _)| id)
}

/// The routes of `report` to run again, in report order, one per route XML id (the first
/// reason met): missing routes, crashed ones, invalid records that name their route.
pub fn rerun_routes(report: &Report) -> Vec<(String, RerunReason)> {
    let mut out: Vec<(String, RerunReason)> = Vec::new();
    for r in &report.routes {
        let reason = match (&r.state, &r.status) {
            (RouteState::Missing, _) => RerunReason::Missing,
            (RouteState::Foreign, _) => continue,
            (RouteState::Invalid(_), None) => RerunReason::InvalidRecord,
            (_, Some(s)) if crashed_status(s) => RerunReason::Crashed,
            _ => continue,
        };
        let Some(id) = r.route_id.as_deref() else {
            continue;
        };
        let id = xml_id(id).to_string();
        if !out.iter().any(|(o, _)| *o == id) {
            out.push((id, reason));
        }
    }
    out
}

/// The rerun list as text: `<id>\t<reason>\n` per route.
pub fn rerun_list(report: &Report) -> String {
    rerun_routes(report)
        .into_iter()
        .map(|(id, why)| format!("{id}\t{}\n", why.name()))
        .collect()
}
