//! The per-route row of the report (docs/SCORE.md §13): what one route's record, replay
//! and checks come to ([`route_report`], [`missing_report`]), and every row of a run with its
//! collision traces and abilities ([`route_rows`]). Field order is the JSON report's key order.
//!
//! New per-route fields go into [`RouteReport`] (and [`route_report`]); new aggregates into
//! [`crate::aggregate::aggregates::Scores`] (docs/SCORE.md §10: the summary, groups and comparisons get them)
//! or [`crate::aggregate::aggregates::Aggregates`] (docs/SCORE.md §10.1, per group and comparison).

use serde::{Deserialize, Serialize};

use crate::geometry::corridor::ReferenceKind;
use crate::geometry::junctions::junction_samples;
use crate::geometry::town_maps::TownMaps;
use crate::input::duplicates::{Kept, Source};
use crate::input::record::{Infractions, KNOWN_LISTS, MIN_SPEED_LIST};
use crate::input::route_set::MissingRoute;
use crate::input::route_xml::RouteSet;
use crate::input::warning::Warning;
use crate::pipeline::outcome::{CollisionEvent, RouteOutcome, RouteState, TelemetryState};
use crate::pipeline::step_period::DtSource;
use crate::pipeline::timeline::ChunkLog;
use crate::route::ability::{route_ability, RouteAbility};
use crate::route::decomposition::{split, Applied, Losses};
use crate::route::efficiency::route_efficiency;
use crate::route::events::{route_events, RouteEvent};
use crate::route::penalty::check_penalty;
use crate::route::protocol::ability_rule::apply_rule;
use crate::route::protocol::min_speed::{min_speed_grid, MinSpeedGrid};
use crate::route::protocol::route::{score_record, RouteProtocols};
use crate::route::trace::{collision_traces, CollisionTrace};
use crate::settings::Settings;

/// Collision counts of a route.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
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
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub struct LateralReport {
    /// Chunks, the trailing partial one included.
    pub chunks: u32,
    /// Chunks with a known excess.
    pub scored_chunks: u32,
    /// `N_anom`.
    pub anomalous: u32,
    /// `N_crit`.
    pub critical: u32,
    /// What the lateral error was measured against (docs/SCORE.md §3): `map-route`, `xml`, `map-lane` or
    /// `none`; null for a route without a valid record.
    pub reference: Option<ReferenceKind>,
}

/// Comfort of a route.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct ComfortReport {
    /// Comfort chunks.
    pub chunks: u32,
    /// Comfortable chunks.
    pub comfortable: u32,
    /// `C_route`; null when undefined.
    pub score: Option<f64>,
    /// Chunks failing each bound.
    pub failed: monitor_core::FailureCounts,
    /// Comfort chunks in which the car moved (docs/SCORE.md §10.0: mean speed at least `motion.moving_speed`).
    pub moving_chunks: u32,
    /// Of those, the comfortable ones.
    pub moving_comfortable: u32,
    /// Comfort over the moving chunks; null when none moved.
    pub moving_score: Option<f64>,
}

/// The penalty re-check of a route.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
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

impl<'de> Deserialize<'de> for InfractionCounts {
    /// In the file's key order: the report's order is part of the row.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::named::pairs(d).map(InfractionCounts)
    }
}

/// One route of the report. Read back by [`crate::model::report::Report::read`], which puts
/// what the row states once where the type holds it again (an invalid route's reason, a kept
/// copy's source); what the JSON report leaves out (traces, chunk verdicts, stretches) reads
/// back empty.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
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
    /// A success (docs/SCORE.md §9): completed and no infraction but minimum speed.
    pub success: bool,
    /// `scores.score_route`.
    pub score_route: Option<f64>,
    /// `scores.score_penalty`.
    pub score_penalty: Option<f64>,
    /// `scores.score_composed`.
    pub score_composed: Option<f64>,
    /// Seconds per telemetry step (docs/SCORE.md §2.2); null without telemetry.
    pub dt: Option<f64>,
    /// `inferred` or `config`; null without telemetry.
    pub dt_source: Option<DtSource>,
    /// Telemetry frames.
    pub frames: u32,
    /// Missing steps.
    pub gaps: u64,
    /// A vehicle log's segments (docs/SCORE.md §2.4): 1 + its gaps longer than `mcap.max_hold`, each
    /// monitored as a fresh start. Left out for telemetry, whose frames are one run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segments: Option<u64>,
    /// Entries per infraction list (all 12 lists and any unknown ones).
    pub infractions: InfractionCounts,
    /// Distance driven, m (docs/SCORE.md §10.0: the 2-D path through the frames); null without frames.
    pub distance_m: Option<f64>,
    /// Share of frames slower than `motion.stationary_speed` (docs/SCORE.md §10.0); null without frames.
    pub stationary_share: Option<f64>,
    /// Collision counts.
    pub collisions: CollisionCounts,
    /// Lateral counts.
    pub lateral: LateralReport,
    /// Comfort.
    pub comfort: ComfortReport,
    /// `C_route` under the `b2d-legacy` profile, whatever the run's profile (Bench2Drive's
    /// per-route smoothness, docs/SCORE.md §10.1); null when undefined.
    pub smoothness: Option<f64>,
    /// Bench2Drive's efficiency of the route (docs/SCORE.md §10.1); null when it has none.
    pub efficiency: Option<f64>,
    /// The abilities the route counts in (docs/SCORE.md §10.1); null when the route has no route XML entry.
    pub ability: Option<RouteAbility>,
    /// `p_safe`; null when not scored.
    pub p_safe: Option<f64>,
    /// `DS_safe`; null when not scored.
    pub ds_safe: Option<f64>,
    /// `score_composed − DS_safe` step by step: the evaluator's rounding and the loss to each
    /// SDS factor (`docs/SCORE.md` "Decomposition"); null when not scored.
    pub decomposition: Option<Losses>,
    /// The min-speed checkpoint grid its record was read on under the protocols (docs/PROTOCOLS.md v1.4):
    /// `b2d-20` or `lb-4`; absent when no protocol is asked or the route has no valid record.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_speed_grid: Option<MinSpeedGrid>,
    /// The route under each asked scoring protocol (docs/PROTOCOLS.md, docs/SCORE.md §13); absent when none is asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocols: Option<RouteProtocols>,
    /// `ok`, `missing` or `invalid: <reason>`.
    pub telemetry: TelemetryState,
    /// `scored`, `missing`, `foreign` or `invalid` (docs/SCORE.md §13).
    pub state: RouteState,
    /// Why the route is invalid, or its telemetry missing or invalid; null otherwise.
    pub reason: Option<String>,
    /// The results file (as found) and record index; null for a missing route.
    pub source: Option<Source>,
    /// The record's `save_name` time stamp (`mm_dd_HH_MM_SS`); absent when it has none. A
    /// merge keeps it, so that `duplicates = newest` chooses across parts too.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "stamp"
    )]
    pub stamp: Option<String>,
    /// For a route id with several copies: which copy was scored and why (docs/SCORE.md §14.1; `policy`,
    /// `copies`, `stamp`, `why`). Absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept: Option<Kept>,
    /// Collision events.
    pub collision_events: Vec<CollisionEvent>,
    /// Every event placed on the frame axis (collisions, lateral and uncomfortable chunks),
    /// by frame, unplaced ones last ([`crate::route::events`]).
    pub events: Vec<RouteEvent>,
    /// Penalty re-check; null for an invalid record.
    pub penalty_check: Option<PenaltyReport>,
    /// The batch reference agreed with the streaming monitor; null when not replayed.
    pub batch_agrees: Option<bool>,
    /// Problems that did not stop the route from being scored.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<Warning>,
    /// The traces of its aligned collisions (docs/SCORE.md §14.4): rendered as CSV and SVG files and in the
    /// HTML report, not in the JSON report.
    #[serde(skip)]
    pub traces: Vec<CollisionTrace>,
    /// The monitor's per-chunk verdicts (the HTML report's timelines); `None` when not
    /// replayed. Not in the JSON report.
    #[serde(skip)]
    pub chunks: Option<ChunkLog>,
    /// Stationary stretches as frame ranges (the HTML report's comfort timeline). Not in the
    /// JSON report.
    #[serde(skip)]
    pub stationary: Vec<(u32, u32)>,
    /// The Leaderboard's driven distance `RC/100 * meta.route_length / 1000`, km, for a route
    /// with a record (`infractions_per_km`, docs/SCORE.md §10.0); in the JSON report so that a merge of
    /// reports (docs/SCORE.md §13.2) recomputes `infractions_per_km`.
    pub driven_km: Option<f64>,
}

/// A `save_name` time stamp (`mm_dd_HH_MM_SS`) or null: a merge chooses the newest copy by it.
fn stamp<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    let s = Option::<String>::deserialize(d)?;
    match s {
        Some(t) if crate::input::duplicates::parse_stamp(&t).is_none() => {
            Err(serde::de::Error::custom(format!(
                "{t:?} is not a save_name time stamp mm_dd_HH_MM_SS"
            )))
        }
        s => Ok(s),
    }
}

impl RouteReport {
    /// After reading a row back: what the JSON states once is put where the type holds it
    /// again: the `reason` of an invalid route or of missing telemetry, the `source` of a kept
    /// copy.
    pub(crate) fn restore(&mut self) {
        let reason = self.reason.clone().unwrap_or_default();
        if let TelemetryState::Missing(r) = &mut self.telemetry {
            r.clone_from(&reason);
        }
        if let RouteState::Invalid(r) = &mut self.state {
            *r = reason;
        }
        if let Some(k) = &mut self.kept {
            k.source = self.source.clone().unwrap_or_default();
        }
    }
}

/// What a row holds beyond its outcome, known before the row is built: its collision traces,
/// its abilities (with the route XML), its scores under the asked protocols and what they warned.
#[derive(Debug, Default)]
pub struct RowFacts {
    /// The collision traces (docs/SCORE.md §14.4).
    pub traces: Vec<CollisionTrace>,
    /// The abilities (docs/SCORE.md §10.1).
    pub ability: Option<RouteAbility>,
    /// The min-speed grid the protocols read the record on.
    pub min_speed_grid: Option<MinSpeedGrid>,
    /// The route under each asked protocol.
    pub protocols: Option<RouteProtocols>,
    /// The protocols' warnings (after the outcome's).
    pub warnings: Vec<Warning>,
}

/// The route id of an outcome's row: its record's, else the one an invalid record named.
fn row_id(o: &RouteOutcome) -> Option<String> {
    o.record().map(|r| r.route_id.clone()).or_else(|| {
        o.loaded
            .entry
            .as_ref()
            .err()
            .and_then(|e| e.route_id.clone())
    })
}

/// The [`RowFacts`] of one outcome: its traces, its abilities with the route XML (the towns'
/// maps give the junction credit), its protocols when some are asked.
fn row_facts(
    o: &RouteOutcome,
    settings: &Settings,
    xml: Option<&RouteSet>,
    maps: &TownMaps,
) -> RowFacts {
    let mut facts = RowFacts::default();
    if let (Some(t), Some(id)) = (&o.timeline, row_id(o)) {
        facts.traces = collision_traces(
            &id,
            t,
            &o.events,
            settings.core.decel_window,
            settings.core.decel_threshold,
        );
    }
    let counted = o.record().filter(|_| o.counted());
    if let (Some(set), Some(rec)) = (xml, counted) {
        if let Some(xml) = rec.xml_id().and_then(|id| set.get(id)) {
            let scenario = xml.scenario_type.as_deref().unwrap_or(rec.scenario_type());
            let town = rec.town_name.as_deref().unwrap_or(&xml.town);
            let samples = || junction_samples(maps, xml, town, settings.gap_max);
            let a = route_ability(rec, scenario, samples);
            facts.ability = Some(apply_rule(settings.ability_rule, a, rec, samples));
        }
    }
    if !settings.protocols.is_empty() {
        // Protocols read records only (docs/PROTOCOLS.md); invalid records score 0.
        let asked = &settings.protocols;
        facts.protocols = Some(match o.record() {
            Some(rec) => {
                let (p, w) = score_record(rec, asked, settings.min_speed_grid);
                facts.warnings = w;
                facts.min_speed_grid = Some(min_speed_grid(
                    rec.infractions.list(MIN_SPEED_LIST),
                    settings.min_speed_grid,
                ));
                p
            }
            None => RouteProtocols::without_record(asked),
        });
    }
    facts
}

/// Turns one outcome and what is known of it ([`RowFacts`]) into its report entry, with the
/// penalty re-check of its record (docs/SCORE.md §9) under `settings.penalty_flavour`.
pub fn route_report(o: &RouteOutcome, settings: &Settings, facts: RowFacts) -> RouteReport {
    let rec = o.record();
    let count = |name: &str| rec.map_or(0, |r| r.infractions.list(name).len() as u32);
    let s = o.summary;
    RouteReport {
        route_id: row_id(o),
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
        segments: o.segments,
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
        comfort: s.map_or_else(ComfortReport::default, |s| {
            let moving = o.moving.unwrap_or_default();
            ComfortReport {
                chunks: s.comfort.chunks,
                comfortable: s.comfort.comfortable,
                score: s.comfort_score(),
                failed: s.comfort.failed,
                moving_chunks: moving.chunks,
                moving_comfortable: moving.comfortable,
                moving_score: moving.score(),
            }
        }),
        distance_m: o.motion.as_ref().map(|m| m.distance_m),
        stationary_share: o.motion.as_ref().and_then(|m| m.stationary_share),
        smoothness: o
            .legacy_comfort
            .and_then(|c| (c.chunks > 0).then(|| f64::from(c.comfortable) / f64::from(c.chunks))),
        efficiency: rec.and_then(|r| route_efficiency(r.infractions.list(MIN_SPEED_LIST))),
        ability: facts.ability,
        p_safe: o.safe.map(|x| x.p_safe),
        ds_safe: o.safe.map(|x| x.ds_safe),
        decomposition: o.safe.zip(rec).zip(s).map(|((safe, r), s)| {
            let n = Applied {
                workzone: o.workzone,
                nodecel: s.collisions.nodecel,
                anomalous: s.lateral.anomalous,
                critical: s.lateral.critical,
            };
            split(
                r.score_composed,
                r.score_route,
                r.score_penalty,
                safe.ds_safe,
                n,
                &settings.core.factors,
            )
        }),
        min_speed_grid: facts.min_speed_grid,
        protocols: facts.protocols,
        telemetry: o.telemetry.clone(),
        reason: o
            .state()
            .reason()
            .or_else(|| o.telemetry.reason())
            .map(String::from),
        state: o.state(),
        source: Some(Source::of(&o.loaded)),
        stamp: o
            .loaded
            .entry
            .as_ref()
            .ok()
            .and_then(|r| r.save_name.as_deref())
            .and_then(crate::input::duplicates::save_name_stamp)
            .map(crate::input::duplicates::stamp_text),
        kept: None,
        collision_events: o.events.clone(),
        events: route_events(
            &o.events,
            &o.placed,
            o.timeline.as_ref(),
            settings.core.chunk_len,
            o.frames as usize,
        ),
        penalty_check: rec.map(|r| {
            let p = check_penalty(r, settings.penalty_flavour);
            PenaltyReport {
                recomputed: p.recomputed,
                agrees: p.agrees,
            }
        }),
        batch_agrees: o.batch_agrees,
        warnings: o.warnings.iter().cloned().chain(facts.warnings).collect(),
        traces: facts.traces,
        chunks: o.timeline.as_ref().map(|t| t.chunks.clone()),
        stationary: o
            .motion
            .as_ref()
            .map(|m| m.stationary.clone())
            .unwrap_or_default(),
        driven_km: rec.map(|r| r.score_route / 100.0 * r.meta.route_length.unwrap_or(0.0) / 1000.0),
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
        segments: None,
        infractions: InfractionCounts::of(None),
        distance_m: None,
        stationary_share: None,
        collisions: CollisionCounts::default(),
        lateral: LateralReport::default(),
        comfort: ComfortReport::default(),
        p_safe: None,
        ds_safe: Some(0.0),
        decomposition: Some(Losses::default()),
        min_speed_grid: None,
        protocols: None,
        smoothness: None,
        efficiency: None,
        ability: None,
        telemetry: TelemetryState::Missing(String::new()),
        state: RouteState::Missing,
        reason: None,
        source: None,
        stamp: None,
        kept: None,
        collision_events: Vec::new(),
        events: Vec::new(),
        penalty_check: None,
        batch_agrees: None,
        warnings: Vec::new(),
        traces: Vec::new(),
        chunks: None,
        stationary: Vec::new(),
        driven_km: None,
    }
}

/// The routes counted in the aggregates (docs/SCORE.md §14.1): every route but the foreign ones, in the
/// report's order.
pub fn counted_routes(routes: &[RouteReport]) -> impl Iterator<Item = &RouteReport> {
    routes.iter().filter(|r| r.state != RouteState::Foreign)
}

/// Every row of a run: the outcomes' rows (in input order), each built once with its
/// [`RowFacts`], then the missing routes' rows (in XML order; under protocols they score 0).
pub fn route_rows(
    outcomes: &[RouteOutcome],
    missing: &[MissingRoute],
    settings: &Settings,
    xml: Option<&RouteSet>,
    maps: &TownMaps,
) -> Vec<RouteReport> {
    let mut routes: Vec<RouteReport> = outcomes
        .iter()
        .map(|o| outcome_row(o, settings, xml, maps))
        .collect();
    let asked = &settings.protocols;
    routes.extend(missing.iter().map(|m| RouteReport {
        protocols: (!asked.is_empty()).then(|| RouteProtocols::without_record(asked)),
        ..missing_report(m)
    }));
    routes
}

/// The row of one outcome, built once with its [`RowFacts`]: what [`route_rows`] makes of each
/// outcome. A run builds it as soon as the route is replayed, so that the outcome (its timeline,
/// the frames kept for its traces, its record) is dropped when the route is done.
pub fn outcome_row(
    o: &RouteOutcome,
    settings: &Settings,
    xml: Option<&RouteSet>,
    maps: &TownMaps,
) -> RouteReport {
    route_report(o, settings, row_facts(o, settings, xml, maps))
}

/// The name of a row in the run's warnings: its route id, else its source.
pub fn row_name(r: &RouteReport) -> String {
    r.route_id.clone().unwrap_or_else(|| {
        r.source
            .as_ref()
            .map_or_else(|| "<no route_id>".into(), ToString::to_string)
    })
}
