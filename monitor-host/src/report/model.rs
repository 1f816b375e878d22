//! The report model (`SDS-SPEC.md` v1.2 §10): per-route results and benchmark aggregates, typed
//! until a rendering ([`crate::report::json`], [`crate::report::csv`], [`crate::report::table`])
//! turns it into text. Field order is the JSON report's key order.
//!
//! New per-route fields go into [`RouteReport`] (and [`route_report`]); new aggregates into
//! [`crate::aggregate::summary::Summary`].

use serde::Serialize;

use crate::aggregate::ability::{missing_routes, route_ability, RouteAbility};
use crate::aggregate::aggregates::{Aggregates, Counts};
use crate::aggregate::bench2drive::{route_efficiency, Bench2Drive};
use crate::aggregate::groups::{groups, GroupBy, Groups, Labels, NeedsLabels};
use crate::aggregate::summary::{summarize, Summary};
use crate::aggregate::trace::{collision_traces, CollisionTrace};
use crate::geometry::junctions::TownMaps;
use crate::input::record::MIN_SPEED_LIST;
use crate::input::route_xml::RouteSet;
use crate::pipeline::outcome::{CollisionEvent, RouteOutcome, RouteState, TelemetryState};
use crate::pipeline::timeline::ChunkLog;
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
    /// Telemetry frames.
    pub frames: u32,
    /// Missing steps.
    pub gaps: u64,
    /// Collision counts.
    pub collisions: CollisionCounts,
    /// Lateral counts.
    pub lateral: LateralReport,
    /// Comfort.
    pub comfort: ComfortReport,
    /// `C_route` under the `b2d-legacy` profile, whatever the run's profile (Bench2Drive's
    /// per-route smoothness, §8.2); null when undefined.
    pub smoothness: Option<f64>,
    /// Entries per infraction list: the 12 known lists, then any unknown one (§10.1).
    pub infractions: Counts<usize>,
    /// Bench2Drive's efficiency of the route (§8.2); null when it has none.
    pub efficiency: Option<f64>,
    /// The abilities the route counts in (§8.2); null when the route has no route XML entry.
    pub ability: Option<RouteAbility>,
    /// `p_safe`; null when not scored.
    pub p_safe: Option<f64>,
    /// `DS_safe`; null when not scored.
    pub ds_safe: Option<f64>,
    /// `ok`, `missing` or `invalid: <reason>`.
    pub telemetry: TelemetryState,
    /// `ok`, `missing` or `invalid: <reason>` for the route as a whole (record or telemetry).
    pub state: RouteState,
    /// The results file and record index.
    pub source: String,
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
    /// Per route, in input order.
    pub routes: Vec<RouteReport>,
    /// Aggregates.
    pub summary: Summary,
    /// The breakdown by group (§8.3), when asked for ([`Report::group`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub groups: Option<Groups>,
    /// Warnings met while reading (duplicates, skipped files, crashed runs...).
    pub warnings: Vec<Warning>,
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
        frames: o.frames,
        gaps: o.gaps,
        collisions: CollisionCounts {
            pedestrian: count("collisions_pedestrian"),
            vehicle: count("collisions_vehicle"),
            layout: count("collisions_layout"),
            workzone: o.workzone,
            unaligned: o.events.iter().filter(|e| e.frame.is_none()).count() as u32,
            exempt: s.map_or(0, |s| s.collisions.exempt),
            nodecel: s.map_or(0, |s| s.collisions.nodecel),
        },
        lateral: s.map_or_else(LateralReport::default, |s| LateralReport {
            chunks: s.lateral.chunks,
            scored_chunks: s.lateral.scored_chunks,
            anomalous: s.lateral.anomalous,
            critical: s.lateral.critical,
        }),
        comfort: s.map_or_else(ComfortReport::default, |s| ComfortReport {
            chunks: s.comfort.chunks,
            comfortable: s.comfort.comfortable,
            score: s.comfort_score(),
            failed: s.comfort.failed,
        }),
        smoothness: o
            .legacy_comfort
            .and_then(|c| (c.chunks > 0).then(|| f64::from(c.comfortable) / f64::from(c.chunks))),
        infractions: Counts(rec.map_or_else(Vec::new, |r| {
            r.infractions
                .all()
                .map(|(n, l)| (n.to_string(), l.len()))
                .collect()
        })),
        efficiency: rec.and_then(|r| route_efficiency(r.infractions.list(MIN_SPEED_LIST))),
        ability: None,
        p_safe: o.safe.map(|x| x.p_safe),
        ds_safe: o.safe.map(|x| x.ds_safe),
        telemetry: o.telemetry.clone(),
        state: o.state(),
        source: format!("{}#{}", o.loaded.source.display(), o.loaded.index),
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

/// Builds the report from the outcomes (in input order), the settings, the run's warnings, the
/// route XML (the abilities' scenario types and route set, §8.2) and the towns' maps (the
/// junction credit).
pub fn build(
    outcomes: &[RouteOutcome],
    settings: &Settings,
    warnings: Vec<Warning>,
    route_set: Option<&RouteSet>,
    maps: &TownMaps,
) -> Report {
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
    if let Some(set) = route_set {
        for (r, o) in routes.iter_mut().zip(outcomes) {
            let Some(rec) = o.record() else { continue };
            let Some(xml) = rec.xml_id().and_then(|id| set.get(id)) else {
                continue;
            };
            let scenario = xml.scenario_type.as_deref().unwrap_or(rec.scenario_type());
            let town = rec.town_name.as_deref().unwrap_or(&xml.town);
            r.ability = Some(route_ability(rec, scenario, || {
                maps.junction_samples(xml, town, settings.gap_max)
            }));
        }
    }
    let mut summary = summarize(outcomes, settings.expected_routes);
    let counted: Vec<&RouteReport> = routes.iter().collect();
    let all = Aggregates::over(&counted, summary.routes);
    let missing = route_set.map_or_else(Vec::new, |set| {
        missing_routes(set, routes.iter().filter_map(|r| r.route_id.as_deref()))
    });
    summary.bench2drive = Some(Bench2Drive::new(&all, &routes, missing));
    Report {
        schema: SCHEMA,
        profile: settings.core.profile.name(),
        config: settings.clone(),
        routes,
        summary,
        groups: None,
        warnings,
    }
}

impl Report {
    /// Adds the breakdown by `by` (§8.3) to the report (`groups`), and its warnings.
    ///
    /// # Errors
    /// [`NeedsLabels`] when `by` needs a label map that `labels` does not give.
    pub fn group(&mut self, by: GroupBy, labels: Option<&Labels>) -> Result<(), NeedsLabels> {
        let (g, warnings) = groups(&self.routes, self.summary.routes, by, labels)?;
        self.warnings.extend(warnings);
        self.groups = Some(g);
        Ok(())
    }

    /// The routes that make the run's exit status fail, with their state: every route not
    /// scored, except a valid record without usable telemetry when
    /// `allow_missing_telemetry` is set.
    pub fn problem_routes(&self) -> impl Iterator<Item = &RouteReport> {
        let allow = self.config.allow_missing_telemetry;
        self.routes
            .iter()
            .filter(move |r| r.state != RouteState::Scored && !(allow && r.penalty_check.is_some()))
    }

    /// True when the report has a problem a front end must signal (exit status 3 of `sds`):
    /// no route at all, a problem route, or a streaming/batch disagreement.
    pub fn has_problems(&self) -> bool {
        self.routes.is_empty()
            || self.problem_routes().next().is_some()
            || !self.summary.batch_disagreements.is_empty()
    }
}
