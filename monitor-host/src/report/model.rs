//! The report model (`SDS-SPEC.md` v1.2 §10): per-route results and benchmark aggregates, typed
//! until a rendering ([`crate::report::json`], [`crate::report::csv`], [`crate::report::table`])
//! turns it into text. Field order is the JSON report's key order.
//!
//! New per-route fields go into [`RouteReport`] (and [`route_report`]); new aggregates into
//! [`crate::aggregate::aggregates::Scores`] (§8.1: the summary, groups and comparisons get them)
//! or [`crate::aggregate::aggregates::Aggregates`] (§8.2, per group and comparison).

use serde::Serialize;

use crate::aggregate::ability::{route_ability, RouteAbility};
use crate::aggregate::aggregates::{Aggregates, Scores};
use crate::aggregate::bench2drive::{route_efficiency, Bench2Drive};
use crate::aggregate::groups::{groups, GroupBy, Groups, Labels, NeedsLabels};
use crate::aggregate::stored::InputReport;
use crate::aggregate::summary::{summarize, Summary};
use crate::aggregate::trace::{collision_traces, CollisionTrace};
use crate::geometry::corridor::ReferenceKind;
use crate::geometry::junctions::junction_samples;
use crate::geometry::town_maps::TownMaps;
use crate::input::duplicates::{Dropped, Source};
use crate::input::record::{Infractions, KNOWN_LISTS, MIN_SPEED_LIST};
use crate::input::route_set::{MissingRoute, RunRouteSet};
use crate::input::route_xml::RouteSet;
use crate::pipeline::outcome::{CollisionEvent, RouteOutcome, RouteState, TelemetryState};
use crate::pipeline::step_period::DtSource;
use crate::pipeline::timeline::ChunkLog;
use crate::protocol::ability_rule::apply_rule;
use crate::protocol::route::{score_record, RouteProtocols};
use crate::settings::Settings;
use crate::warning::Warning;

/// The report's schema name.
pub const SCHEMA: &str = "sds-report/1";

/// Collision counts of a route.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct CollisionCounts {
    /// Entries of `collisions_pedestrian`.
    pub pedestrian: u32,
    /// Entries of `collisions_vehicle`.
    pub vehicle: u32,
    /// Entries of `collisions_layout` (work-zone contacts included).
    pub layout: u32,
    /// Work-zone contacts (`N_wz`).
    pub workzone: u32,
    /// Events not aligned to a frame.
    pub unaligned: u32,
    /// Aligned events exempt (standing ego).
    pub exempt: u32,
    /// `N_nodecel`.
    pub nodecel: u32,
}

/// Lateral counts of a route.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct LateralReport {
    /// Chunks, the trailing partial one included.
    pub chunks: u32,
    /// Chunks with a known excess.
    pub scored_chunks: u32,
    /// `N_anom`.
    pub anomalous: u32,
    /// `N_crit`.
    pub critical: u32,
    /// What the lateral error was measured against (§2): `map-route`, `xml`, `map-lane` or
    /// `none`; null for a route without a valid record.
    pub reference: Option<ReferenceKind>,
}

/// Comfort of a route.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct ComfortReport {
    /// Comfort chunks.
    pub chunks: u32,
    /// Comfortable chunks.
    pub comfortable: u32,
    /// `C_route`; null when undefined.
    pub score: Option<f64>,
    /// Chunks failing each bound.
    pub failed: monitor_core::FailureCounts,
}

/// The penalty re-check of a route.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PenaltyReport {
    /// Penalty recomputed from the infraction lists.
    pub recomputed: f64,
    /// Within 1e-3 of the recorded `score_penalty`.
    pub agrees: bool,
}

/// Entries per infraction list of a route: the 12 known lists in Bench2Drive's order, then any
/// unknown ones in the record's order (a JSON object).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct InfractionCounts(pub Vec<(String, usize)>);

impl InfractionCounts {
    /// The counts of a record's lists (all 12 known lists, 0 when absent).
    pub fn of(inf: Option<&Infractions>) -> Self {
        let mut v: Vec<(String, usize)> = KNOWN_LISTS
            .iter()
            .map(|n| (n.to_string(), inf.map_or(0, |i| i.list(n).len())))
            .collect();
        if let Some(i) = inf {
            v.extend(i.unknown().map(|(n, l)| (n.to_string(), l.len())));
        }
        InfractionCounts(v)
    }

    /// The count of one list (0 when absent).
    pub fn get(&self, list: &str) -> usize {
        self.0
            .iter()
            .find(|(n, _)| n == list)
            .map_or(0, |(_, c)| *c)
    }
}

impl Serialize for InfractionCounts {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(k, v)| (k, v)))
    }
}

/// One route of the report.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RouteReport {
    /// `RouteScenario_<id>_rep<k>` (null when the record has none).
    pub route_id: Option<String>,
    /// Scenario type (scenario name without `_N`).
    pub scenario_type: Option<String>,
    /// Town.
    pub town: Option<String>,
    /// Weather id.
    pub weather_id: Option<String>,
    /// Evaluator status.
    pub status: Option<String>,
    /// A success (spec section 8): completed and no infraction but minimum speed.
    pub success: bool,
    /// `scores.score_route`.
    pub score_route: Option<f64>,
    /// `scores.score_penalty`.
    pub score_penalty: Option<f64>,
    /// `scores.score_composed`.
    pub score_composed: Option<f64>,
    /// Seconds per telemetry step (spec section 1.2); null without telemetry.
    pub dt: Option<f64>,
    /// `inferred` or `config`; null without telemetry.
    pub dt_source: Option<DtSource>,
    /// Telemetry frames.
    pub frames: u32,
    /// Missing steps.
    pub gaps: u64,
    /// Entries per infraction list (all 12 lists and any unknown ones).
    pub infractions: InfractionCounts,
    /// Collision counts.
    pub collisions: CollisionCounts,
    /// Lateral counts.
    pub lateral: LateralReport,
    /// Comfort.
    pub comfort: ComfortReport,
    /// `C_route` under the `b2d-legacy` profile, whatever the run's profile (Bench2Drive's
    /// per-route smoothness, §8.2); null when undefined.
    pub smoothness: Option<f64>,
    /// Bench2Drive's efficiency of the route (§8.2); null when it has none.
    pub efficiency: Option<f64>,
    /// The abilities the route counts in (§8.2); null when the route has no route XML entry.
    pub ability: Option<RouteAbility>,
    /// `p_safe`; null when not scored.
    pub p_safe: Option<f64>,
    /// `DS_safe`; null when not scored.
    pub ds_safe: Option<f64>,
    /// The route under each asked scoring protocol (§8.4, §10.3); absent when none is asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocols: Option<RouteProtocols>,
    /// `ok`, `missing` or `invalid: <reason>`.
    pub telemetry: TelemetryState,
    /// `scored`, `missing`, `foreign` or `invalid` (spec section 10.1).
    pub state: RouteState,
    /// Why the route is invalid, or its telemetry missing or invalid; null otherwise.
    pub reason: Option<String>,
    /// The results file (as found) and record index; null for a missing route.
    pub source: Option<Source>,
    /// Collision events.
    pub collision_events: Vec<CollisionEvent>,
    /// Penalty re-check; null for an invalid record.
    pub penalty_check: Option<PenaltyReport>,
    /// The batch reference agreed with the streaming monitor; null when not replayed.
    pub batch_agrees: Option<bool>,
    /// Problems that did not stop the route from being scored.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<Warning>,
    /// The traces of its aligned collisions (§10.2): rendered as CSV and SVG files and in the
    /// HTML report, not in the JSON report.
    #[serde(skip)]
    pub traces: Vec<CollisionTrace>,
    /// The monitor's per-chunk verdicts (the HTML report's timelines); `None` when not
    /// replayed. Not in the JSON report.
    #[serde(skip)]
    pub chunks: Option<ChunkLog>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Report {
    /// `sds-report/1`.
    pub schema: &'static str,
    /// `physical` or `b2d-legacy`.
    pub profile: &'static str,
    /// Every threshold and default.
    pub config: Settings,
    /// Every results file read, with the figures it stores beside the computed ones (§1.5).
    pub inputs: Vec<InputReport>,
    /// Copies of duplicated routes left out by `duplicates: first|last` (§1.5).
    pub dropped: Vec<Dropped>,
    /// Per route, in input order.
    pub routes: Vec<RouteReport>,
    /// Aggregates.
    pub summary: Summary,
    /// The breakdown by group (§8.3), when asked for ([`Report::group`]).
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

/// Turns one outcome into its report entry.
pub fn route_report(o: &RouteOutcome) -> RouteReport {
    let rec = o.record();
    let count = |name: &str| rec.map_or(0, |r| r.infractions.list(name).len() as u32);
    let s = o.summary;
    RouteReport {
        route_id: rec.map(|r| r.route_id.clone()).or_else(|| {
            o.loaded
                .entry
                .as_ref()
                .err()
                .and_then(|e| e.route_id.clone())
        }),
        scenario_type: rec.map(|r| r.scenario_type().to_string()),
        town: rec.and_then(|r| r.town_name.clone()),
        weather_id: rec.and_then(|r| r.weather_id.clone()),
        status: rec.map(|r| r.status.clone()),
        success: rec.is_some_and(|r| r.is_success()),
        score_route: rec.map(|r| r.score_route),
        score_penalty: rec.map(|r| r.score_penalty),
        score_composed: rec.map(|r| r.score_composed),
        dt: o.period.map(|p| p.dt),
        dt_source: o.period.map(|p| p.source),
        frames: o.frames,
        gaps: o.gaps,
        infractions: InfractionCounts::of(rec.map(|r| &r.infractions)),
        collisions: CollisionCounts {
            pedestrian: count("collisions_pedestrian"),
            vehicle: count("collisions_vehicle"),
            layout: count("collisions_layout"),
            workzone: o.workzone,
            unaligned: o.events.iter().filter(|e| e.frame.is_none()).count() as u32,
            exempt: s.map_or(0, |s| s.collisions.exempt),
            nodecel: s.map_or(0, |s| s.collisions.nodecel),
        },
        lateral: LateralReport {
            reference: o.reference,
            ..s.map_or_else(LateralReport::default, |s| LateralReport {
                chunks: s.lateral.chunks,
                scored_chunks: s.lateral.scored_chunks,
                anomalous: s.lateral.anomalous,
                critical: s.lateral.critical,
                reference: None,
            })
        },
        comfort: s.map_or_else(ComfortReport::default, |s| ComfortReport {
            chunks: s.comfort.chunks,
            comfortable: s.comfort.comfortable,
            score: s.comfort_score(),
            failed: s.comfort.failed,
        }),
        smoothness: o
            .legacy_comfort
            .and_then(|c| (c.chunks > 0).then(|| f64::from(c.comfortable) / f64::from(c.chunks))),
        efficiency: rec.and_then(|r| route_efficiency(r.infractions.list(MIN_SPEED_LIST))),
        ability: None,
        p_safe: o.safe.map(|x| x.p_safe),
        ds_safe: o.safe.map(|x| x.ds_safe),
        protocols: None,
        telemetry: o.telemetry.clone(),
        reason: o
            .state()
            .reason()
            .or_else(|| o.telemetry.reason())
            .map(String::from),
        state: o.state(),
        source: Some(Source::of(&o.loaded)),
        collision_events: o.events.clone(),
        penalty_check: o.penalty.map(|p| PenaltyReport {
            recomputed: p.recomputed,
            agrees: p.agrees,
        }),
        batch_agrees: o.batch_agrees,
        warnings: o.warnings.clone(),
        traces: Vec::new(),
        chunks: o.timeline.as_ref().map(|t| t.chunks.clone()),
    }
}

/// The report entry of a missing route: scores 0, not a success, comfort undefined.
pub fn missing_report(m: &MissingRoute) -> RouteReport {
    RouteReport {
        route_id: Some(m.route_id.clone()),
        scenario_type: m.scenario_type.clone(),
        town: m.town.clone(),
        weather_id: None,
        status: None,
        success: false,
        score_route: Some(0.0),
        score_penalty: None,
        score_composed: Some(0.0),
        dt: None,
        dt_source: None,
        frames: 0,
        gaps: 0,
        infractions: InfractionCounts::of(None),
        collisions: CollisionCounts::default(),
        lateral: LateralReport::default(),
        comfort: ComfortReport::default(),
        p_safe: None,
        ds_safe: Some(0.0),
        protocols: None,
        smoothness: None,
        efficiency: None,
        ability: None,
        telemetry: TelemetryState::Missing(String::new()),
        state: RouteState::Missing,
        reason: None,
        source: None,
        collision_events: Vec::new(),
        penalty_check: None,
        batch_agrees: None,
        warnings: Vec::new(),
        traces: Vec::new(),
        chunks: None,
    }
}

/// The routes counted in the aggregates (§1.5): every route but the foreign ones, in the
/// report's order.
pub fn counted_routes(routes: &[RouteReport]) -> impl Iterator<Item = &RouteReport> {
    routes.iter().filter(|r| r.state != RouteState::Foreign)
}

/// What a run read besides its routes: the pieces of the report that are not per-route.
#[derive(Clone, Debug, Default)]
pub struct RunFacts {
    /// N (spec section 1.5).
    pub n: usize,
    /// The route set, when `--routes` was given.
    pub route_set: Option<RunRouteSet>,
    /// The inputs and their stored figures.
    pub inputs: Vec<InputReport>,
    /// Copies left out by the duplicates policy.
    pub dropped: Vec<Dropped>,
    /// Run-level warnings.
    pub warnings: Vec<Warning>,
}

/// Builds the report from the outcomes (in input order), then the missing routes (in XML
/// order), with the route XML (the abilities' scenario types, §8.2) and the towns' maps (the
/// junction credit). Every per-route warning is added to the run's warnings, naming its route.
pub fn build(
    outcomes: &[RouteOutcome],
    settings: &Settings,
    facts: RunFacts,
    xml: Option<&RouteSet>,
    maps: &TownMaps,
) -> Report {
    let missing: &[MissingRoute] = facts.route_set.as_ref().map_or(&[], |s| &s.missing);
    let mut routes: Vec<RouteReport> = outcomes.iter().map(route_report).collect();
    for (r, o) in routes.iter_mut().zip(outcomes) {
        if let (Some(t), Some(id)) = (&o.timeline, &r.route_id) {
            r.traces = collision_traces(
                id,
                t,
                &o.events,
                settings.core.decel_window,
                settings.core.decel_threshold,
            );
        }
    }
    if let Some(set) = xml {
        for (r, o) in routes.iter_mut().zip(outcomes) {
            let Some(rec) = o.record().filter(|_| o.counted()) else {
                continue;
            };
            let Some(xml) = rec.xml_id().and_then(|id| set.get(id)) else {
                continue;
            };
            let scenario = xml.scenario_type.as_deref().unwrap_or(rec.scenario_type());
            let town = rec.town_name.as_deref().unwrap_or(&xml.town);
            let samples = || junction_samples(maps, xml, town, settings.gap_max);
            let a = route_ability(rec, scenario, samples);
            r.ability = Some(apply_rule(settings.ability_rule, a, rec, samples));
        }
    }
    routes.extend(missing.iter().map(missing_report));
    if !settings.protocols.is_empty() {
        // Protocols read records only (§8.4); missing routes and invalid records score 0.
        let asked = &settings.protocols;
        for (i, r) in routes.iter_mut().enumerate() {
            r.protocols = Some(match outcomes.get(i).and_then(|o| o.record()) {
                Some(rec) => {
                    let (p, w) = score_record(rec, asked);
                    r.warnings.extend(w);
                    p
                }
                None => RouteProtocols::without_record(asked),
            });
        }
    }
    let mut warnings = facts.warnings;
    for r in &routes {
        let route = r.route_id.clone().unwrap_or_else(|| {
            r.source
                .as_ref()
                .map_or_else(|| "<no route_id>".into(), ToString::to_string)
        });
        warnings.extend(r.warnings.iter().map(|w| Warning::Route {
            route: route.clone(),
            warning: Box::new(w.clone()),
        }));
    }
    let counted: Vec<&RouteReport> = counted_routes(&routes).collect();
    let scores = Scores::over(&counted, facts.n);
    let mut summary = summarize(outcomes, scores, facts.n, missing.len());
    let all = Aggregates::over(&counted, summary.routes.max(counted.len()));
    let ability_missing = missing.iter().map(|m| m.route_id.clone()).collect();
    summary.protocols = all.protocols.clone();
    let mut b2d = Bench2Drive::new(&all, &routes, ability_missing);
    b2d.ability_rule = settings.ability_rule.name();
    summary.bench2drive = Some(b2d);
    Report {
        schema: SCHEMA,
        profile: settings.core.profile.name(),
        config: settings.clone(),
        inputs: facts.inputs,
        dropped: facts.dropped,
        routes,
        summary,
        groups: None,
        warnings,
        files_read: outcomes
            .iter()
            .flat_map(|o| o.files_read.iter().cloned())
            .collect(),
        route_set: facts.route_set,
    }
}

impl Report {
    /// Adds the breakdown by `by` (§8.3) to the report (`groups`), and its warnings. Label
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
