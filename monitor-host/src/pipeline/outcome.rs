//! What became of one route: its state, its collision events and its scores (`SDS-SPEC.md`
//! v1.2 §10). Typed here; the report turns them into text.

use monitor_core::{ComfortSummary, RouteSummary, SafeScore};

use crate::aggregate::penalty::PenaltyCheck;
use crate::input::collision::CollisionList;
use crate::input::record::{LoadedRecord, Record};
use crate::pipeline::align::AlignedBy;
use crate::pipeline::timeline::RouteTimeline;
use crate::warning::Warning;

/// What became of a route's telemetry.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TelemetryState {
    /// Read and replayed.
    Ok,
    /// No `metric_info.json` was found.
    Missing,
    /// Found but unusable; the reason names the file, step and field.
    Invalid(String),
}

impl serde::Serialize for TelemetryState {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The state of a route as a whole (its record and its telemetry), as the report names it.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum RouteState {
    /// Record valid, telemetry replayed: scored with every term (`ok`).
    Scored,
    /// Record valid, no telemetry found (`missing`); scored without telemetry terms only with
    /// `allow_missing_telemetry`.
    Missing,
    /// A route that is not part of the evaluated route set (`foreign`). Not produced yet: the
    /// route-set check of spec v1.2 fills it in.
    Foreign,
    /// The record or its telemetry cannot be used (`invalid: <reason>`); the reason names the
    /// file, step or field.
    Invalid(String),
}

impl std::fmt::Display for RouteState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RouteState::Scored => f.write_str("ok"),
            RouteState::Missing => f.write_str("missing"),
            RouteState::Foreign => f.write_str("foreign"),
            RouteState::Invalid(r) => write!(f, "invalid: {r}"),
        }
    }
}

impl serde::Serialize for RouteState {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl std::fmt::Display for TelemetryState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TelemetryState::Ok => f.write_str("ok"),
            TelemetryState::Missing => f.write_str("missing"),
            TelemetryState::Invalid(r) => write!(f, "invalid: {r}"),
        }
    }
}

/// One entry of a collision list and what the replay made of it: the one host type of a
/// collision event, from parsing to the report (its JSON form is the report's
/// `collision_events` entry; the string and location it came from are not printed).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CollisionEvent {
    /// The list it came from.
    #[serde(serialize_with = "list_name")]
    pub list: CollisionList,
    /// `type=` of the collision string (`None` when the string does not parse).
    pub type_id: Option<String>,
    /// A work-zone contact (spec section 7).
    pub workzone: bool,
    /// The frame it was aligned to.
    pub frame: Option<usize>,
    /// That frame's step number.
    pub step: Option<u64>,
    /// How it was aligned; `None` when unaligned.
    pub aligned_by: Option<AlignedBy>,
    /// Speed at the frame, m/s.
    pub impact_speed: Option<f32>,
    /// Decelerated before (spec section 5); `None` when unaligned.
    pub decelerated: Option<bool>,
    /// Exempt (standing ego); `None` when unaligned.
    pub exempt: Option<bool>,
    /// Why the collision string did not parse.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parse_error: Option<String>,
    /// The evaluator's string (matched against LEAD's `infractions.json` messages).
    #[serde(skip)]
    pub message: String,
    /// The (x, y) parsed from the string, if any.
    #[serde(skip)]
    pub location: Option<[f64; 2]>,
}

fn list_name<S: serde::Serializer>(list: &CollisionList, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(list.name())
}

/// Everything known about one route after the replay.
#[derive(Clone, Debug)]
pub struct RouteOutcome {
    /// The record (or why it is invalid) and where it came from.
    pub loaded: LoadedRecord,
    /// Telemetry state.
    pub telemetry: TelemetryState,
    /// Telemetry frames and missing steps (0 without telemetry).
    pub frames: u32,
    /// Missing step numbers.
    pub gaps: u64,
    /// The frames and the monitor's per-chunk verdicts; `None` when not replayed.
    pub timeline: Option<RouteTimeline>,
    /// Telemetry terms; `None` when the route could not be scored.
    pub summary: Option<RouteSummary>,
    /// DS_safe; `None` when the route could not be scored.
    pub safe: Option<SafeScore>,
    /// Comfort under the `b2d-legacy` profile, whatever the run's profile: Bench2Drive's
    /// smoothness (§8.2); `None` when the telemetry was not replayed.
    pub legacy_comfort: Option<ComfortSummary>,
    /// Collision events in list order (pedestrian, vehicle, layout).
    pub events: Vec<CollisionEvent>,
    /// `N_wz`.
    pub workzone: u32,
    /// Penalty re-check (spec section 8); `None` for an invalid record.
    pub penalty: Option<PenaltyCheck>,
    /// The batch reference gave the same summary (spec section 9); `None` when not replayed.
    pub batch_agrees: Option<bool>,
    /// Problems that did not stop the route from being scored (unreadable `infractions.json`,
    /// no reference route in the XML, unparseable collision strings).
    pub warnings: Vec<Warning>,
}

impl RouteOutcome {
    /// The record, when it is valid.
    pub fn record(&self) -> Option<&Record> {
        self.loaded.entry.as_ref().ok()
    }

    /// The route's state: an invalid record first, then what became of its telemetry.
    pub fn state(&self) -> RouteState {
        match (&self.loaded.entry, &self.telemetry) {
            (Err(e), _) => RouteState::Invalid(e.reason.clone()),
            (Ok(_), TelemetryState::Ok) => RouteState::Scored,
            (Ok(_), TelemetryState::Missing) => RouteState::Missing,
            (Ok(_), TelemetryState::Invalid(r)) => RouteState::Invalid(r.clone()),
        }
    }
}
