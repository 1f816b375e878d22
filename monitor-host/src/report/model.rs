//! The report model (`SDS-SPEC.md` v1.2 §10): per-route results and benchmark aggregates, typed
//! until a rendering ([`crate::report::json`], [`crate::report::csv`], [`crate::report::table`])
//! turns it into text. Field order is the JSON report's key order.
//!
//! New per-route fields go into [`RouteReport`] (and [`route_report`]); new aggregates into
//! [`crate::aggregate::summary::Summary`].

use serde::Serialize;

use crate::aggregate::summary::{summarize, Summary};
use crate::pipeline::outcome::{CollisionEvent, RouteOutcome, RouteState, TelemetryState};
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
    /// Warnings met while reading (duplicates, skipped files, crashed runs...).
    pub warnings: Vec<Warning>,
    /// Every input file of the run (results files, route XML, located telemetry files), for
    /// front ends that must never write over an input. Not part of the JSON report.
    #[serde(skip)]
    pub files_read: Vec<std::path::PathBuf>,
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
    }
}

/// Builds the report from the outcomes (in input order), the settings and the run's warnings.
pub fn build(outcomes: &[RouteOutcome], settings: &Settings, warnings: Vec<Warning>) -> Report {
    Report {
        schema: SCHEMA,
        profile: settings.core.profile.name(),
        config: settings.clone(),
        routes: outcomes.iter().map(route_report).collect(),
        summary: summarize(outcomes, settings.expected_routes),
        warnings,
        files_read: outcomes
            .iter()
            .flat_map(|o| o.files_read.iter().cloned())
            .collect(),
    }
}

impl Report {
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
