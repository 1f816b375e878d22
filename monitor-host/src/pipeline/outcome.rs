//! What became of one route: its state, its collision events and its scores (docs/SCORE.md
//! §13). Typed here; the report turns them into text.

use monitor_core::{ComfortSummary, RouteSummary, SafeScore};
use serde::Deserialize as _;

use crate::geometry::corridor::ReferenceKind;
use crate::input::collision::CollisionList;
use crate::input::record::{LoadedRecord, Record};
use crate::input::warning::Warning;
use crate::pipeline::align::AlignedBy;
use crate::pipeline::motion::{Motion, MovingComfort};
use crate::pipeline::step_period::StepPeriod;
use crate::pipeline::timeline::RouteTimeline;

/// What became of a route's telemetry.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TelemetryState {
    /// Read and replayed.
    Ok,
    /// No `metric_info.json` was found; the reason says where it was looked for (the report's
    /// `telemetry` field prints `missing`, the route's `reason` the detail).
    Missing(String),
    /// Found but unusable; the reason names the file, step and field.
    Invalid(String),
}

impl serde::Serialize for TelemetryState {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for TelemetryState {
    /// `ok`, `missing` (its reason is the row's `reason`, which the reader of the row puts
    /// back) or `invalid: <reason>`.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        match s.as_str() {
            "ok" => Ok(TelemetryState::Ok),
            "missing" => Ok(TelemetryState::Missing(String::new())),
            t => match t.strip_prefix("invalid: ") {
                Some(r) => Ok(TelemetryState::Invalid(r.to_string())),
                None => Err(serde::de::Error::custom(format!(
                    "unknown telemetry state {t:?}; expected ok, missing or invalid: <reason>"
                ))),
            },
        }
    }
}

/// The state of a route as a whole (docs/SCORE.md §13). The report's `state` field
/// prints [`RouteState::name`]; [`std::fmt::Display`] adds an invalid route's reason.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum RouteState {
    /// Scored: telemetry replayed, or scored without telemetry terms under
    /// `allow_missing_telemetry` (`scored`).
    Scored,
    /// A member of the route set (`--routes`) without any record (`missing`): scores 0, not a
    /// success, comfort undefined; counted in N.
    Missing,
    /// A record whose route is not in the route set (`foreign`): reported, left out of every
    /// aggregate.
    Foreign,
    /// The record, or its telemetry without `allow_missing_telemetry`, cannot be used
    /// (`invalid`); the reason names the file, step or field.
    Invalid(String),
}

impl RouteState {
    /// `scored`, `missing`, `foreign` or `invalid`.
    pub fn name(&self) -> &'static str {
        match self {
            RouteState::Scored => "scored",
            RouteState::Missing => "missing",
            RouteState::Foreign => "foreign",
            RouteState::Invalid(_) => "invalid",
        }
    }

    /// Why the route is invalid.
    pub fn reason(&self) -> Option<&str> {
        match self {
            RouteState::Invalid(r) => Some(r),
            _ => None,
        }
    }
}

impl std::fmt::Display for RouteState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RouteState::Invalid(r) => write!(f, "invalid: {r}"),
            s => f.write_str(s.name()),
        }
    }
}

impl serde::Serialize for RouteState {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for RouteState {
    /// By [`RouteState::name`]; an invalid route's reason is the row's `reason`, which the
    /// reader of the row puts back.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let names = ["scored", "missing", "foreign", "invalid"];
        Ok(match crate::named::one_of(d, &names)? {
            "scored" => RouteState::Scored,
            "missing" => RouteState::Missing,
            "foreign" => RouteState::Foreign,
            _ => RouteState::Invalid(String::new()),
        })
    }
}

impl TelemetryState {
    /// Why the telemetry is missing or invalid.
    pub fn reason(&self) -> Option<&str> {
        match self {
            TelemetryState::Ok => None,
            TelemetryState::Missing(r) | TelemetryState::Invalid(r) => Some(r),
        }
    }
}

impl std::fmt::Display for TelemetryState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TelemetryState::Ok => f.write_str("ok"),
            TelemetryState::Missing(_) => f.write_str("missing"),
            TelemetryState::Invalid(r) => write!(f, "invalid: {r}"),
        }
    }
}

/// One entry of a collision list and what the replay made of it: the one host type of a
/// collision event, from parsing to the report (its JSON form is the report's
/// `collision_events` entry; the string and location it came from are not printed).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollisionEvent {
    /// The list it came from.
    #[serde(serialize_with = "list_name", deserialize_with = "list_of_name")]
    pub list: CollisionList,
    /// `type=` of the collision string (`None` when the string does not parse).
    pub type_id: Option<String>,
    /// A work-zone contact (docs/SCORE.md §8).
    pub workzone: bool,
    /// The frame it was aligned to.
    pub frame: Option<usize>,
    /// That frame's step number.
    pub step: Option<u64>,
    /// How it was aligned; `None` when unaligned.
    pub aligned_by: Option<AlignedBy>,
    /// Seconds from the route's first frame: `(step - first_step) * dt`.
    pub time_s: Option<f64>,
    /// Speed at the frame, m/s.
    pub impact_speed: Option<f32>,
    /// Decelerated before (docs/SCORE.md §6); `None` when unaligned.
    pub decelerated: Option<bool>,
    /// Exempt (standing ego); `None` when unaligned.
    pub exempt: Option<bool>,
    /// Why the collision string did not parse.
    #[serde(default, skip_serializing_if = "Option::is_none")]
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

fn list_of_name<'de, D: serde::Deserializer<'de>>(d: D) -> Result<CollisionList, D::Error> {
    let name = String::deserialize(d)?;
    CollisionList::from_name(&name)
        .ok_or_else(|| serde::de::Error::custom(format!("unknown collision list {name:?}")))
}

/// Everything known about one route after the replay.
#[derive(Clone, Debug)]
pub struct RouteOutcome {
    /// The record (or why it is invalid) and where it came from.
    pub loaded: LoadedRecord,
    /// Telemetry state.
    pub telemetry: TelemetryState,
    /// The route's step period and where it came from; `None` without telemetry.
    pub period: Option<StepPeriod>,
    /// Not a member of the route set (docs/SCORE.md §14.1): left out of every aggregate.
    pub foreign: bool,
    /// Telemetry frames and missing steps (0 without telemetry).
    pub frames: u32,
    /// Missing step numbers.
    pub gaps: u64,
    /// A vehicle log's segments (docs/SCORE.md §2.4); `None` for telemetry.
    pub segments: Option<u64>,
    /// The frames and the monitor's per-chunk verdicts; `None` when not replayed.
    pub timeline: Option<RouteTimeline>,
    /// Telemetry terms; `None` when the route could not be scored.
    pub summary: Option<RouteSummary>,
    /// DS_safe; `None` when the route could not be scored.
    pub safe: Option<SafeScore>,
    /// Comfort under the `b2d-legacy` profile, whatever the run's profile: Bench2Drive's
    /// smoothness (docs/SCORE.md §10.1); `None` when the telemetry was not replayed.
    pub legacy_comfort: Option<ComfortSummary>,
    /// Collision events in list order (pedestrian, vehicle, layout).
    pub events: Vec<CollisionEvent>,
    /// The other infractions (placed where the telemetry allows) and the long stationary
    /// stretches ([`crate::pipeline::placement`]).
    pub placed: Vec<crate::pipeline::placement::PlacedEvent>,
    /// `N_wz`.
    pub workzone: u32,
    /// The batch reference gave the same summary (docs/SCORE.md §11); `None` when not replayed.
    pub batch_agrees: Option<bool>,
    /// Distance, stationary share and moving chunks (docs/SCORE.md §10.0); `None` when not replayed.
    pub motion: Option<Motion>,
    /// Comfort over the moving chunks; `None` when not replayed.
    pub moving: Option<MovingComfort>,
    /// What the lateral error is measured against (docs/SCORE.md §3); `None` for an invalid record.
    pub reference: Option<ReferenceKind>,
    /// Problems that did not stop the route from being scored (unreadable `infractions.json`,
    /// no reference route in the XML, unparseable collision strings).
    pub warnings: Vec<Warning>,
    /// The telemetry files located for this route (`metric_info.json`, `infractions.json`),
    /// read or not: a front end never writes over one of them.
    pub files_read: Vec<std::path::PathBuf>,
    /// When the telemetry is missing: the folders whose listing decided it
    /// ([`crate::input::discovery::looked_in`]); `sds watch` replays the route again only when
    /// one of them changed.
    pub looked_in: Vec<std::path::PathBuf>,
}

impl RouteOutcome {
    /// The record, when it is valid.
    pub fn record(&self) -> Option<&Record> {
        self.loaded.entry.as_ref().ok()
    }

    /// The route's state: an invalid record first (whatever the route XML holds: a broken
    /// record is never hidden as foreign), then foreign, then what became of its telemetry (a
    /// route scored without telemetry terms, as `allow_missing_telemetry` lets it, is
    /// `scored`).
    pub fn state(&self) -> RouteState {
        if let Err(e) = &self.loaded.entry {
            return RouteState::Invalid(e.reason.clone());
        }
        if self.foreign {
            return RouteState::Foreign;
        }
        match (&self.loaded.entry, &self.telemetry) {
            (Err(e), _) => RouteState::Invalid(e.reason.clone()),
            (Ok(_), TelemetryState::Ok) => RouteState::Scored,
            (Ok(_), _) if self.safe.is_some() => RouteState::Scored,
            (Ok(_), TelemetryState::Missing(r)) => {
                RouteState::Invalid(format!("telemetry missing: {r}"))
            }
            (Ok(_), TelemetryState::Invalid(r)) => RouteState::Invalid(r.clone()),
        }
    }

    /// Counted in the aggregates: not foreign.
    pub fn counted(&self) -> bool {
        !self.foreign
    }
}
