//! Replay: one evaluator record plus its telemetry -> frames (f32) -> `Monitor` -> outcome.
//!
//! Geometry (speed, lateral error, collision alignment) is computed in f64 on the raw
//! coordinates and rounded to f32 once, when the [`Frame`] is built (spec section 2).

use std::path::PathBuf;

use monitor_core::{
    score, Collisions, Config, Event, Frame, Monitor, RecordScores, RouteSummary, SafeScore,
};

use crate::align::{self, AlignedBy, EventRef};
use crate::batch;
use crate::infraction::{self, CollisionList, PenaltyCheck, PenaltyFlavour};
use crate::results::{LoadedRecord, Record};
use crate::route::{LateralTracker, RouteSet};
use crate::telemetry::{self, Telemetry};

/// Host-side settings next to the core's [`Config`] (spec sections 1.3, 2, 5).
#[derive(Clone, Debug)]
pub struct Options {
    /// The monitor's configuration.
    pub config: Config,
    /// A reference segment strictly longer than this is a junction gap, m (8.0) **\[decision\]**.
    pub gap_max: f64,
    /// Forward-search window of the lateral error, m of route length (10.0) **\[decision\]**.
    pub lookahead: f64,
    /// Farthest a collision may be from its frame to be aligned, m, inclusive (1.0) **\[decision\]**.
    pub align_max_dist: f64,
    /// Frames within this of the smallest distance tie; ties go to the earliest, m (1e-3).
    pub align_tie: f64,
    /// Where `<save_name>/metric_info.json` folders are.
    pub telemetry_root: Option<PathBuf>,
    /// Score routes without telemetry terms instead of failing them.
    pub allow_missing_telemetry: bool,
    /// Factors of the penalty re-check.
    pub penalty_flavour: PenaltyFlavour,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            config: Config::DEFAULT,
            gap_max: 8.0,
            lookahead: 10.0,
            align_max_dist: 1.0,
            align_tie: 1e-3,
            telemetry_root: None,
            allow_missing_telemetry: false,
            penalty_flavour: PenaltyFlavour::Bench2Drive,
        }
    }
}

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

impl std::fmt::Display for TelemetryState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TelemetryState::Ok => f.write_str("ok"),
            TelemetryState::Missing => f.write_str("missing"),
            TelemetryState::Invalid(r) => write!(f, "invalid: {r}"),
        }
    }
}

/// One entry of a collision list and what the replay made of it.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionEvent {
    /// The list it came from.
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
    pub parse_error: Option<String>,
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
    /// Telemetry terms; `None` when the route could not be scored.
    pub summary: Option<RouteSummary>,
    /// DS_safe; `None` when the route could not be scored.
    pub safe: Option<SafeScore>,
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
    pub warnings: Vec<String>,
}

impl RouteOutcome {
    /// The record, when it is valid.
    pub fn record(&self) -> Option<&Record> {
        self.loaded.entry.as_ref().ok()
    }

    /// `ok`, `missing` or `invalid: <reason>`: the route's state in the report.
    pub fn state(&self) -> String {
        match &self.loaded.entry {
            Err(e) => format!("invalid: {}", e.reason),
            Ok(_) => self.telemetry.to_string(),
        }
    }
}

/// The lists whose entries are collisions, in the order they are reported.
pub const COLLISION_LISTS: [CollisionList; 3] = [
    CollisionList::Pedestrian,
    CollisionList::Vehicle,
    CollisionList::Layout,
];

/// Parses a record's collision lists into events (not yet aligned).
pub fn collision_events(record: &Record) -> Vec<(CollisionEvent, String, Option<[f64; 2]>)> {
    let mut out = Vec::new();
    for list in COLLISION_LISTS {
        for s in record.infractions.list(list.name()) {
            let (type_id, workzone, loc, parse_error) = match infraction::parse_collision(s) {
                Ok(c) => {
                    let wz = list == CollisionList::Layout && infraction::is_workzone(&c.type_id);
                    (Some(c.type_id), wz, c.location.map(|l| [l[0], l[1]]), None)
                }
                Err(e) => (None, false, None, Some(e.to_string())),
            };
            out.push((
                CollisionEvent {
                    list,
                    type_id,
                    workzone,
                    frame: None,
                    step: None,
                    aligned_by: None,
                    impact_speed: None,
                    decelerated: None,
                    exempt: None,
                    parse_error,
                },
                s.clone(),
                loc,
            ));
        }
    }
    out
}

/// The frames the monitor sees for a route, and the events aligned to them.
#[derive(Clone, Debug)]
pub struct PreparedRoute {
    /// One frame per telemetry step, in step order.
    pub frames: Vec<Frame>,
    /// Step number of each frame.
    pub steps: Vec<u64>,
    /// Collision events, aligned where possible.
    pub events: Vec<CollisionEvent>,
}

/// Builds the monitor's frames: signals from the raw vectors (f32 kernels), speed, lateral error
/// and alignment in f64, then rounded to f32 once.
pub fn prepare(
    record: &Record,
    tel: &Telemetry,
    routes: Option<&RouteSet>,
    infractions: Option<&[telemetry::StepInfraction]>,
    opts: &Options,
) -> PreparedRoute {
    let n = tel.frames.len();
    let steps = tel.steps();
    let locations = tel.locations();
    let speeds = telemetry::speeds(&tel.frames, f64::from(opts.config.dt));

    let reference = routes.and_then(|r| record.xml_id().and_then(|id| r.get(id)));
    let mut tracker = reference.map(|r| LateralTracker::new(r, opts.gap_max, opts.lookahead));

    let parsed = collision_events(record);
    let refs: Vec<EventRef> = parsed
        .iter()
        .map(|(_, msg, loc)| EventRef {
            message: msg,
            location: *loc,
        })
        .collect();
    let aligned = align::align_events(
        &refs,
        &steps,
        &locations,
        infractions,
        opts.align_max_dist,
        opts.align_tie,
    );
    let mut collisions = vec![Collisions::NONE; n];
    let mut events = Vec::with_capacity(parsed.len());
    for ((mut ev, _, _), a) in parsed.into_iter().zip(aligned) {
        if let Some(k) = a.frame.filter(|&k| k < n) {
            let c = &mut collisions[k];
            let slot = match (ev.list, ev.workzone) {
                (CollisionList::Pedestrian, _) => &mut c.pedestrian,
                (CollisionList::Vehicle, _) => &mut c.vehicle,
                (CollisionList::Layout, true) => &mut c.workzone,
                (CollisionList::Layout, false) => &mut c.layout,
            };
            *slot = slot.saturating_add(1);
            ev.frame = Some(k);
            ev.step = Some(steps[k]);
            ev.aligned_by = a.by;
            ev.impact_speed = Some(speeds[k] as f32);
        }
        events.push(ev);
    }

    let frames = tel
        .frames
        .iter()
        .zip(&speeds)
        .zip(collisions)
        .map(|((f, &speed), c)| {
            let lat_err = tracker.as_mut().and_then(|t| t.next(f.location));
            Frame::from_vectors(
                f.acc,
                f.fwd,
                f.right,
                f.yaw_rate_deg,
                speed as f32,
                lat_err.map(|e| e as f32),
                c,
            )
        })
        .collect();
    PreparedRoute {
        frames,
        steps,
        events,
    }
}

/// Streams prepared frames through a fresh monitor; fills the events' verdicts.
/// Returns the summary, or the first frame the monitor refused (index, reason).
pub fn stream(
    prepared: &mut PreparedRoute,
    config: &Config,
) -> Result<RouteSummary, (usize, String)> {
    let mut monitor: Monitor = Monitor::new(*config).map_err(|e| (0, e.to_string()))?;
    let mut verdicts = Vec::new();
    for (i, f) in prepared.frames.iter().enumerate() {
        let events = monitor.push(f).map_err(|e| (i, e.to_string()))?;
        for e in &events {
            if let Event::Collision(v) = e {
                verdicts.push(*v);
            }
        }
    }
    let done = monitor
        .finish()
        .map_err(|e| (prepared.frames.len(), e.to_string()))?;
    for ev in &mut prepared.events {
        if let Some(k) = ev.frame {
            if let Some(v) = verdicts.iter().find(|v| v.frame as usize == k) {
                ev.decelerated = Some(v.decelerated);
                ev.exempt = Some(v.exempt);
            }
        }
    }
    Ok(done.summary)
}

/// A route's telemetry, read and turned into frames.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The frames and aligned events.
    pub prepared: PreparedRoute,
    /// Missing step numbers.
    pub gaps: u64,
    /// The `metric_info.json` read.
    pub path: PathBuf,
}

/// Locates and reads a record's telemetry (and `infractions.json` beside it) and prepares its
/// frames. Problems that do not stop the route are pushed to `warnings`.
pub fn load(
    loaded: &LoadedRecord,
    record: &Record,
    routes: Option<&RouteSet>,
    opts: &Options,
    warnings: &mut Vec<String>,
) -> Result<Loaded, TelemetryState> {
    let path = record
        .save_name
        .as_deref()
        .and_then(|save| {
            telemetry::locate(
                opts.telemetry_root.as_deref(),
                save,
                &loaded.source,
                loaded.records_in_file == 1,
            )
        })
        .ok_or(TelemetryState::Missing)?;
    let tel = telemetry::read_metric_info(&path)
        .map_err(|e| TelemetryState::Invalid(format!("{}: {e}", path.display())))?;
    let infractions = match telemetry::infractions_beside(&path) {
        None => None,
        Some(p) => match telemetry::read_infractions(&p) {
            Ok(list) => Some(list),
            Err(e) => {
                warnings.push(format!(
                    "{}: {e}; collisions aligned by position instead",
                    p.display()
                ));
                None
            }
        },
    };
    if let (Some(set), Some(id)) = (routes, record.xml_id()) {
        if let Err(e) = set.get_checked(id) {
            warnings.push(format!("{e}: lateral excess unknown for this route"));
        }
    }
    let prepared = prepare(record, &tel, routes, infractions.as_deref(), opts);
    Ok(Loaded {
        prepared,
        gaps: tel.gaps,
        path,
    })
}

/// Replays one loaded record: locate and read telemetry, prepare frames, stream, score, and
/// check the batch reference.
pub fn replay(loaded: &LoadedRecord, routes: Option<&RouteSet>, opts: &Options) -> RouteOutcome {
    let mut out = RouteOutcome {
        loaded: loaded.clone(),
        telemetry: TelemetryState::Missing,
        frames: 0,
        gaps: 0,
        summary: None,
        safe: None,
        events: Vec::new(),
        workzone: 0,
        penalty: None,
        batch_agrees: None,
        warnings: Vec::new(),
    };
    let Ok(record) = &loaded.entry else {
        return out;
    };
    out.penalty = Some(infraction::check_penalty(record, opts.penalty_flavour));
    let summary = match load(loaded, record, routes, opts, &mut out.warnings) {
        Ok(Loaded {
            mut prepared,
            gaps,
            path,
        }) => {
            out.frames = prepared.frames.len() as u32;
            out.gaps = gaps;
            match stream(&mut prepared, &opts.config) {
                Ok(summary) => {
                    let reference = batch::summarize(&prepared.frames, &opts.config);
                    out.batch_agrees = Some(reference.summary == summary);
                    out.telemetry = TelemetryState::Ok;
                    out.events = prepared.events;
                    Some(summary)
                }
                Err((i, reason)) => {
                    out.telemetry = TelemetryState::Invalid(format!(
                        "{}: step {}: {reason}",
                        path.display(),
                        prepared.steps.get(i).copied().unwrap_or_default()
                    ));
                    None
                }
            }
        }
        Err(state) => {
            out.telemetry = state;
            None
        }
    };
    // A route not replayed keeps its collisions, unaligned (spec section 10).
    if out.telemetry != TelemetryState::Ok {
        out.events = collision_events(record)
            .into_iter()
            .map(|(e, _, _)| e)
            .collect();
    }
    for e in &out.events {
        if let Some(reason) = &e.parse_error {
            out.warnings.push(format!(
                "{}: unparseable collision string ({reason}): counted, not aligned",
                e.list.name()
            ));
        }
    }
    out.workzone = out.events.iter().filter(|e| e.workzone).count() as u32;
    // Without telemetry the route is scored without telemetry terms only when allowed.
    let summary = summary.or_else(|| opts.allow_missing_telemetry.then_some(RouteSummary::ZERO));
    if let Some(s) = summary {
        let scores = RecordScores {
            score_route: record.score_route,
            score_penalty: record.score_penalty,
            workzone: out.workzone,
        };
        out.safe = Some(score::ds_safe(&s, &scores, &opts.config.factors));
        out.summary = Some(s);
    }
    out
}
