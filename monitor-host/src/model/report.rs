//! The report model (docs/SCORE.md §13): the run's rows and its aggregates, typed until a
//! rendering ([`crate::report::json`], [`crate::report::csv`], [`crate::report::table`]) turns it
//! into text. Field order is the JSON report's key order. [`assemble`] aggregates the rows
//! [`crate::route::row::route_rows`] built; [`Report::group`] adds the breakdown by group.

use serde::{Deserialize, Serialize};

use crate::aggregate::aggregates::{Aggregates, Scores};
use crate::aggregate::bench2drive::Bench2Drive;
use crate::aggregate::groups::{groups, GroupBy, Groups, NeedsLabels};
use crate::aggregate::summary::{summarize, Summary};
use crate::input::duplicates::{Dropped, Kept};
use crate::input::labels::Labels;
use crate::input::route_set::{route_set_id, RouteSetId, RunRouteSet};
use crate::input::stored::InputReport;
use crate::input::warning::Warning;
use crate::pipeline::outcome::{RouteOutcome, RouteState};
use crate::provenance::Provenance;
use crate::route::row::{counted_routes, row_name, RouteReport};
use crate::settings::Settings;

/// The report's schema name.
pub const SCHEMA: &str = "sds-report/1";

/// The whole report: written by its `Serialize` ([`crate::report::json`]) and read back by its
/// `Deserialize` ([`Report::read`]), field for field.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Report {
    /// `sds-report/1`.
    #[serde(deserialize_with = "schema_name")]
    pub schema: crate::named::Name,
    /// `physical`, `b2d-legacy` or `autoware`.
    #[serde(deserialize_with = "profile_name")]
    pub profile: crate::named::Name,
    /// Every threshold and default.
    pub config: Settings,
    /// Every results file read, with the figures it stores beside the computed ones (docs/SCORE.md §14.1),
    /// and the route set's fingerprint (docs/SCORE.md §13).
    pub inputs: ReportInputs,
    /// Under `route_subset: found`, the route set actually scored: the route XML's routes that
    /// have a record. Absent for the whole XML (or without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub route_subset: Option<SubsetReport>,
    /// Copies of duplicated routes left out by `duplicates: first|last|newest` (docs/SCORE.md §14.1).
    pub dropped: Vec<Dropped>,
    /// Per route, in input order.
    #[serde(deserialize_with = "rows")]
    pub routes: Vec<RouteReport>,
    /// Aggregates.
    pub summary: Summary,
    /// The breakdown by group (docs/SCORE.md §10.2), when asked for ([`Report::group`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub groups: Option<Groups>,
    /// Every warning of the run, the per-route ones included (as printed on stderr).
    pub warnings: Vec<Warning>,
    /// Every input file of the run (results files, route XML, located telemetry files), for
    /// front ends that must never write over an input. Not part of the JSON report.
    #[serde(skip)]
    pub files_read: Vec<std::path::PathBuf>,
    /// The route set of `--routes` (members, missing routes), for the tables and comparisons.
    #[serde(skip)]
    pub route_set: Option<RunRouteSet>,
}

name_field!(schema_name, [SCHEMA]);
name_field!(
    profile_name,
    monitor_core::Profile::ALL.map(monitor_core::Profile::name)
);

/// The rows read back, each with what it states once put back ([`RouteReport`]).
fn rows<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<RouteReport>, D::Error> {
    let mut rows = Vec::<RouteReport>::deserialize(d)?;
    for r in &mut rows {
        r.restore();
    }
    Ok(rows)
}

/// The report's `inputs`: the files read and the route set's fingerprint.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ReportInputs {
    /// Every results file read, with its stored and computed figures (docs/SCORE.md §14.1).
    #[serde(default)]
    pub files: Vec<InputReport>,
    /// The counted routes' fingerprint (`{"routes", "sha256"}`, docs/SCORE.md §13).
    pub route_set: RouteSetId,
    /// The `sds` version, settings hash, input files' sha256 and size, host (docs/SCORE.md §13.2). A
    /// report written before provenance reads back with an empty one.
    #[serde(default)]
    pub provenance: Provenance,
    /// A merged report's parts (docs/SCORE.md §13.2): each part's file, sha256, `sds` version and inputs;
    /// absent for `sds score`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parts: Option<Vec<crate::model::parts::PartInputs>>,
}

/// The route set of `route_subset: found`, as the report states it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubsetReport {
    /// `found`.
    #[serde(deserialize_with = "subset_name")]
    pub subset: crate::named::Name,
    /// Routes in the set (the route XML's routes with a record).
    pub routes: usize,
    /// Routes of the whole route XML.
    pub of: usize,
}

name_field!(subset_name, ["found"]);

impl SubsetReport {
    /// The sentence the tables print under their figures.
    pub fn note(&self) -> String {
        format!(
            "route set: the {} of the route XML's {} routes that have a record (route_subset = \
             found); the others are left out, not counted as 0",
            self.routes, self.of
        )
    }
}

/// What a run read besides its routes: the pieces of the report that are not per-route.
#[derive(Clone, Debug, Default)]
pub struct RunFacts {
    /// N (docs/SCORE.md §14.1).
    pub n: usize,
    /// The route set, when `--routes` was given.
    pub route_set: Option<RunRouteSet>,
    /// The inputs and their stored figures.
    pub inputs: Vec<InputReport>,
    /// Copies left out by the duplicates policy.
    pub dropped: Vec<Dropped>,
    /// Per duplicated route id, the copy kept and why.
    pub kept: Vec<Kept>,
    /// Run-level warnings.
    pub warnings: Vec<Warning>,
    /// Where the run comes from (docs/SCORE.md §13.2).
    pub provenance: Provenance,
}

/// Builds the report from the run's rows (from [`crate::route::row::route_rows`]: the outcomes'
/// rows in input order, then the missing routes') and the outcomes behind them: the summary
/// (docs/SCORE.md §10), Bench2Drive's metrics (docs/SCORE.md §10.1), and every per-route warning added to the run's
/// warnings, naming its route. The figures come from the rows alone ([`assemble_rows`]).
pub fn assemble(
    routes: Vec<RouteReport>,
    outcomes: &[RouteOutcome],
    settings: &Settings,
    facts: RunFacts,
) -> Report {
    let mut report = assemble_rows(routes, settings, facts);
    report.files_read = outcomes
        .iter()
        .flat_map(|o| o.files_read.iter().cloned())
        .collect();
    report
}

/// The report of `routes` (in the report's order: records in input order, then the missing
/// routes in route-XML order): every aggregate is computed from the rows alone, so that
/// [`crate::merge`] builds a merged report with the very code `sds score` uses (docs/SCORE.md §13.2).
pub fn assemble_rows(mut routes: Vec<RouteReport>, settings: &Settings, facts: RunFacts) -> Report {
    for k in facts.kept {
        if let Some(r) = routes
            .iter_mut()
            .find(|r| r.source.as_ref() == Some(&k.source))
        {
            r.kept = Some(k);
        }
    }
    let mut warnings = facts.warnings;
    for r in &routes {
        let route = row_name(r);
        warnings.extend(r.warnings.iter().map(|w| Warning::Route {
            route: route.clone(),
            warning: Box::new(w.clone()),
        }));
    }
    let counted: Vec<&RouteReport> = counted_routes(&routes).collect();
    warnings.extend(protocol_warnings(&counted, settings));
    let scores = Scores::over(&counted, facts.n);
    let mut summary = summarize(&routes, scores, facts.n);
    let all = Aggregates::over(&counted, summary.routes.max(counted.len()));
    let ability_missing = routes
        .iter()
        .filter(|r| r.state == RouteState::Missing)
        .filter_map(|r| r.route_id.clone())
        .collect();
    summary.protocols = all.protocols.clone();
    let mut b2d = Bench2Drive::new(&all, &routes, ability_missing);
    b2d.ability_rule = settings.ability_rule.name();
    summary.bench2drive = Some(b2d);
    Report {
        schema: SCHEMA,
        profile: settings.core.profile.name(),
        config: settings.clone(),
        inputs: ReportInputs {
            files: facts.inputs,
            route_set: route_set_id(counted.iter().filter_map(|r| r.route_id.as_deref())),
            provenance: facts.provenance,
            parts: None,
        },
        route_subset: facts.route_set.as_ref().and_then(|s| {
            s.subset_of.map(|of| SubsetReport {
                subset: "found",
                routes: s.len(),
                of,
            })
        }),
        dropped: facts.dropped,
        routes,
        summary,
        groups: None,
        warnings,
        files_read: Vec::new(),
        route_set: facts.route_set,
    }
}

/// The run-level warnings of the scoring protocols (docs/PROTOCOLS.md v1.4): how many records were
/// regrouped on Bench2Drive's min-speed grid, and the `f2d` successes that did not finish.
fn protocol_warnings(counted: &[&RouteReport], settings: &Settings) -> Vec<Warning> {
    use crate::route::protocol::min_speed::MinSpeedGrid;
    use crate::route::protocol::Protocol;
    let mut out = Vec::new();
    let regrouping: Vec<&'static str> = settings
        .protocols
        .iter()
        .filter(|p| matches!(p, Protocol::Lb20 | Protocol::Lb21 | Protocol::LeadNds))
        .map(|p| p.id())
        .collect();
    let graded: Vec<MinSpeedGrid> = counted.iter().filter_map(|r| r.min_speed_grid).collect();
    let regrouped = graded.iter().filter(|g| **g == MinSpeedGrid::B2d20).count();
    if !regrouping.is_empty() && regrouped > 0 {
        out.push(Warning::MinSpeedRegrouped {
            records: regrouped,
            of: graded.len(),
            setting: settings.min_speed_grid.name(),
            protocols: regrouping,
        });
    }
    let unfinished: Vec<String> = counted
        .iter()
        .filter(|r| {
            let f2d = r.protocols.as_ref().and_then(|p| p.get(Protocol::F2d));
            f2d.is_some_and(|s| s.success && s.penalty.is_some())
                && (r.score_route.is_some_and(|rc| rc < 100.0)
                    || r.status.as_deref().is_some_and(|s| s.starts_with("Failed")))
        })
        .map(|r| row_name(r))
        .collect();
    if !unfinished.is_empty() {
        out.push(Warning::F2dUnfinished { routes: unfinished });
    }
    out
}

impl Report {
    /// Adds the breakdown by `by` (docs/SCORE.md §10.2) to the report (`groups`), and its warnings. Label
    /// maps come from [`crate::input::labels::read_labels`] (or are built in code).
    ///
    /// ```
    /// use monitor_host::aggregate::groups::{GroupBy, Labels};
    /// use monitor_host::{demo, score_run, Inputs, Settings};
    /// let dir = tempfile::tempdir()?;
    /// let run = demo::write(dir.path())?;
    /// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
    /// let mut report = score_run(&inputs, &Settings::default())?;
    /// // A train/test split of the routes, by XML id.
    /// let split: Labels = ["900001", "900002"]
    ///     .iter()
    ///     .map(|id| (id.to_string(), vec!["test".to_string()]))
    ///     .chain([("RouteScenario_900003_rep0".to_string(), vec!["train".to_string()])])
    ///     .collect();
    /// report.group(GroupBy::Route, Some(&split))?;
    /// let g = report.groups.as_ref().unwrap();
    /// let n: Vec<(&str, usize)> =
    ///     g.rows.iter().map(|r| (r.label.as_str(), r.aggregates.routes)).collect();
    /// assert_eq!(n, [("test", 2), ("train", 1), ("(unmapped)", report.routes.len() - 3)]);
    /// assert!(report.group(GroupBy::Route, None).is_err()); // a route grouping needs its map
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`NeedsLabels`] when `by` needs a label map that `labels` does not give.
    pub fn group(&mut self, by: GroupBy, labels: Option<&Labels>) -> Result<(), NeedsLabels> {
        let (g, warnings) = groups(&self.routes, self.summary.routes, by, labels)?;
        self.warnings.extend(warnings);
        self.groups = Some(g);
        Ok(())
    }

    /// The routes that make the run's exit status fail: the invalid ones (an invalid record,
    /// or telemetry missing or invalid without `allow_missing_telemetry`). Missing and foreign
    /// routes are reported, not problems.
    pub fn problem_routes(&self) -> impl Iterator<Item = &RouteReport> {
        self.routes
            .iter()
            .filter(|r| matches!(r.state, RouteState::Invalid(_)))
    }

    /// True when no counted route of the run has telemetry (the report then says so once, in
    /// [`Warning::NoTelemetry`], instead of once per route).
    pub fn no_telemetry(&self) -> bool {
        self.warnings
            .iter()
            .any(|w| matches!(w, Warning::NoTelemetry { .. }))
    }

    /// True when the report has a problem a front end must signal (exit status 3 of `sds`):
    /// no route at all, a problem route, or a streaming/batch disagreement.
    pub fn has_problems(&self) -> bool {
        self.routes.is_empty()
            || self.problem_routes().next().is_some()
            || !self.summary.batch_disagreements.is_empty()
    }
}
