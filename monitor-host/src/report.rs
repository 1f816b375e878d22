//! The report (spec section 10): per-route results, benchmark aggregates, and their JSON,
//! table and CSV forms. Aggregates are f64, summed in input order.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use crate::replay::{CollisionEvent, Options, RouteOutcome, TelemetryState};

/// The report's schema name.
pub const SCHEMA: &str = "sds-report/1";

/// The configuration block: every threshold and default, by name.
#[derive(Clone, Debug, Serialize)]
pub struct ReportConfig {
    /// The core's configuration (bounds, windows, slack, factors).
    #[serde(flatten)]
    pub core: monitor_core::Config,
    /// Junction-gap length, m.
    pub gap_max: f64,
    /// Lateral forward-search window, m.
    pub lookahead: f64,
    /// Alignment distance, m.
    pub align_max_dist: f64,
    /// Alignment tie tolerance, m.
    pub align_tie: f64,
    /// Penalty re-check flavour.
    pub penalty_flavour: &'static str,
    /// `--expected-routes`, if given.
    pub expected_routes: Option<usize>,
    /// Routes without telemetry scored without telemetry terms.
    pub allow_missing_telemetry: bool,
}

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

/// One collision event of a route.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct EventReport {
    /// `collisions_pedestrian`, `collisions_vehicle` or `collisions_layout`.
    pub list: &'static str,
    /// The object's type id.
    pub type_id: Option<String>,
    /// A work-zone contact.
    pub workzone: bool,
    /// Aligned frame (0-based).
    pub frame: Option<usize>,
    /// Its step number.
    pub step: Option<u64>,
    /// `nearest`, `infractions.json` or null.
    pub aligned_by: Option<&'static str>,
    /// Speed at the frame, m/s.
    pub impact_speed: Option<f32>,
    /// Decelerated before.
    pub decelerated: Option<bool>,
    /// Exempt.
    pub exempt: Option<bool>,
    /// Why the collision string did not parse.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parse_error: Option<String>,
}

impl From<&CollisionEvent> for EventReport {
    fn from(e: &CollisionEvent) -> Self {
        EventReport {
            list: e.list.name(),
            type_id: e.type_id.clone(),
            workzone: e.workzone,
            frame: e.frame,
            step: e.step,
            aligned_by: e.aligned_by.map(|a| a.name()),
            impact_speed: e.impact_speed,
            decelerated: e.decelerated,
            exempt: e.exempt,
            parse_error: e.parse_error.clone(),
        }
    }
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
    pub telemetry: String,
    /// `ok`, `missing` or `invalid: <reason>` for the route as a whole (record or telemetry).
    pub state: String,
    /// The results file and record index.
    pub source: String,
    /// Collision events.
    pub collision_events: Vec<EventReport>,
    /// Penalty re-check; null for an invalid record.
    pub penalty_check: Option<PenaltyReport>,
    /// The batch reference agreed with the streaming monitor; null when not replayed.
    pub batch_agrees: Option<bool>,
    /// Problems that did not stop the route from being scored.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Benchmark aggregates (spec section 8).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Summary {
    /// N: routes found, or `--expected-routes`.
    pub routes: usize,
    /// Routes found in the input.
    pub routes_found: usize,
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
}

/// The whole report.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Report {
    /// `sds-report/1`.
    pub schema: &'static str,
    /// `physical` or `b2d-legacy`.
    pub profile: &'static str,
    /// Every threshold and default.
    pub config: serde_json::Value,
    /// Per route, in input order.
    pub routes: Vec<RouteReport>,
    /// Aggregates.
    pub summary: Summary,
    /// Warnings met while reading (duplicates, skipped files, crashed runs...).
    pub warnings: Vec<String>,
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
        telemetry: o.telemetry.to_string(),
        state: o.state(),
        source: format!("{}#{}", o.loaded.source.display(), o.loaded.index),
        collision_events: o.events.iter().map(EventReport::from).collect(),
        penalty_check: o.penalty.map(|p| PenaltyReport {
            recomputed: p.recomputed,
            agrees: p.agrees,
        }),
        batch_agrees: o.batch_agrees,
        warnings: o.warnings.clone(),
    }
}

/// Computes the aggregates over the outcomes, in input order.
pub fn summarize(outcomes: &[RouteOutcome], expected: Option<usize>) -> Summary {
    let found = outcomes.len();
    let n = expected.unwrap_or(found);
    let per = |total: f64| (n > 0).then(|| total / n as f64);
    let mut composed = 0.0f64;
    let mut successes = 0usize;
    let mut ds_safe = 0.0f64;
    let mut all_scored = true;
    let mut comfort_sum = 0.0f64;
    let mut comfort_routes = 0usize;
    let mut collided = 0usize;
    for o in outcomes {
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
    }
}

/// Builds the report.
pub fn build(
    outcomes: &[RouteOutcome],
    opts: &Options,
    expected: Option<usize>,
    warnings: Vec<String>,
) -> Report {
    let config = ReportConfig {
        core: opts.config,
        gap_max: opts.gap_max,
        lookahead: opts.lookahead,
        align_max_dist: opts.align_max_dist,
        align_tie: opts.align_tie,
        penalty_flavour: opts.penalty_flavour.name(),
        expected_routes: expected,
        allow_missing_telemetry: opts.allow_missing_telemetry,
    };
    Report {
        schema: SCHEMA,
        profile: opts.config.profile.name(),
        config: serde_json::to_value(config).unwrap_or(serde_json::Value::Null),
        routes: outcomes.iter().map(route_report).collect(),
        summary: summarize(outcomes, expected),
        warnings,
    }
}

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

fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

/// The paper's Table 1 row and a Table 2-style breakdown.
pub fn table(report: &Report, group_by: GroupBy, labels: &BTreeMap<String, String>) -> String {
    let s = &report.summary;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:>8} {:>8} {:>8} {:>8} {:>8}",
        "DS", "SR", "DS_safe", "Comfort", "SDS"
    );
    let _ = writeln!(
        out,
        "{:>8} {:>8} {:>8} {:>8} {:>8}",
        fmt_opt(s.driving_score, 2),
        fmt_opt(s.success_rate, 2),
        fmt_opt(s.mean_ds_safe, 2),
        fmt_opt(s.mean_comfort, 3),
        fmt_opt(s.sds, 2)
    );
    let _ = writeln!(
        out,
        "routes {} (found {}), comfort defined on {}, telemetry problems {}, invalid records {}",
        s.routes, s.routes_found, s.comfort_routes, s.telemetry_problems, s.invalid_records
    );
    // Breakdown: routes, DS, SR, collision rate per group (denominator: routes of the group).
    let mut groups: BTreeMap<String, (usize, f64, usize, usize)> = BTreeMap::new();
    for r in &report.routes {
        let key = match group_by {
            GroupBy::Scenario => r.scenario_type.clone(),
            GroupBy::Family => r
                .scenario_type
                .as_ref()
                .map(|t| labels.get(t).cloned().unwrap_or_else(|| t.clone())),
            GroupBy::Town => r.town.clone(),
            GroupBy::Weather => r
                .weather_id
                .as_ref()
                .map(|w| labels.get(w).cloned().unwrap_or_else(|| w.clone())),
        }
        .unwrap_or_else(|| "(unknown)".into());
        let g = groups.entry(key).or_default();
        g.0 += 1;
        g.1 += r.score_composed.unwrap_or(0.0);
        g.2 += usize::from(r.success);
        g.3 += usize::from(!r.collision_events.is_empty());
    }
    let name = match group_by {
        GroupBy::Scenario => "scenario",
        GroupBy::Family => "family",
        GroupBy::Town => "town",
        GroupBy::Weather => "weather",
    };
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "{name:<40} {:>6} {:>8} {:>8} {:>8}",
        "routes", "DS", "SR", "Coll."
    );
    for (k, (n, ds, sr, coll)) in groups {
        let d = n as f64;
        let _ = writeln!(
            out,
            "{k:<40} {n:>6} {:>8.2} {:>8.2} {:>8.2}",
            ds / d,
            100.0 * sr as f64 / d,
            100.0 * coll as f64 / d
        );
    }
    out
}

/// One CSV line per route.
pub fn csv(report: &Report) -> String {
    let mut out = String::from(
        "route_id,scenario_type,town,weather_id,status,state,score_route,score_penalty,score_composed,frames,gaps,pedestrian,vehicle,layout,workzone,unaligned,exempt,nodecel,lateral_chunks,anomalous,critical,comfort_chunks,comfortable,comfort,p_safe,ds_safe\n",
    );
    let q = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    let o = |x: Option<f64>| x.map_or_else(String::new, |v| v.to_string());
    for r in &report.routes {
        let c = &r.collisions;
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            q(r.route_id.as_deref().unwrap_or("")),
            q(r.scenario_type.as_deref().unwrap_or("")),
            q(r.town.as_deref().unwrap_or("")),
            q(r.weather_id.as_deref().unwrap_or("")),
            q(r.status.as_deref().unwrap_or("")),
            q(&r.state),
            o(r.score_route),
            o(r.score_penalty),
            o(r.score_composed),
            r.frames,
            r.gaps,
            c.pedestrian,
            c.vehicle,
            c.layout,
            c.workzone,
            c.unaligned,
            c.exempt,
            c.nodecel,
            r.lateral.chunks,
            r.lateral.anomalous,
            r.lateral.critical,
            r.comfort.chunks,
            r.comfort.comfortable,
            o(r.comfort.score),
            o(r.p_safe),
            o(r.ds_safe),
        );
    }
    out
}
