//! Scoring vehicle logs (docs/SCORE.md §2.4): each MCAP log (or rosbag2 folder) is one route, named
//! by its file stem, whose telemetry is made from its ROS 2 messages
//! ([`crate::input::mcap`]) and fed to the same pipeline as a Bench2Drive route: comfort,
//! lateral excess against the log's path, braking before its events, distance, stationary
//! share, events and pictures. A log has no Leaderboard record, so the report holds no DS, SR,
//! DS_safe, SDS or protocols, and says so.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::Error;
use crate::geometry::corridor::ReferenceKind;
use crate::geometry::town_maps::TownMaps;
use crate::input::lead_infractions::StepInfraction;
use crate::input::mcap::{read_log, scan_log, LogEvent, McapError, Topics, VehicleLog};
use crate::input::record::{Infractions, LoadedRecord, Meta, Record};
use crate::input::route_xml::RouteRef;
use crate::input::warning::Warning;
use crate::model::frames::RouteFrames;
use crate::model::report::{assemble, Report, RunFacts};
use crate::model::vehicle_log::{without_leaderboard, NO_LEADERBOARD};
use crate::pipeline::drive::{held_log_telemetry, replay_drive};
use crate::pipeline::outcome::{RouteOutcome, TelemetryState};
use crate::pipeline::replay::{unreplayed, RouteTelemetry};
use crate::provenance::Provenance;
use crate::route::row::route_rows;
use crate::settings::{decimal, Settings};

/// The collision list a log's events go to **\[decision\]**: the event topic says "something
/// happened here" (a collision or an emergency), and §5's check only needs its time.
pub const EVENT_LIST: &str = "collisions_vehicle";

/// One log as a route: its record (named by the log, its events in [`EVENT_LIST`]), the
/// events' steps, and the path as the route's reference.
struct LogRoute {
    loaded: LoadedRecord,
    steps: Vec<StepInfraction>,
    reference: Option<RouteRef>,
}

fn log_route(log: &VehicleLog) -> LogRoute {
    let messages: Vec<String> = log
        .events
        .iter()
        .enumerate()
        .map(|(i, e)| {
            // The collision form §1.1 gives, so that the events go through §5 unchanged; the
            // message's type stands for the object's.
            let kind = if e.kind.is_empty() { "event" } else { &e.kind };
            format!("Agent collided against object with type={kind} and id={i}")
        })
        .collect();
    let steps = log
        .events
        .iter()
        .zip(&messages)
        .filter_map(|(e, m)| {
            Some(StepInfraction {
                step: log.telemetry.frames.get(e.frame?)?.step,
                message: m.clone(),
            })
        })
        .collect();
    let record = Record {
        route_id: log.name.clone(),
        scenario_name: String::new(),
        weather_id: None,
        save_name: None,
        town_name: None,
        status: String::new(),
        infractions: Infractions::from_lists([(EVENT_LIST, messages)]),
        // Placeholders: no Leaderboard record. The report drops every figure made from them.
        score_route: 100.0,
        score_penalty: 1.0,
        score_composed: 100.0,
        meta: Meta::default(),
    };
    let reference = log.path_points.as_ref().map(|p| RouteRef {
        id: log.name.clone(),
        town: String::new(),
        waypoints: p.iter().map(|q| [q[0], q[1]]).collect(),
        heights: p.iter().map(|q| q[2]).collect(),
        scenario_type: None,
    });
    LogRoute {
        loaded: LoadedRecord {
            source: log.path.clone(),
            index: 0,
            records_in_file: 1,
            entry: Ok(record),
        },
        steps,
        reference,
    }
}

/// The log's telemetry prepared as the replay takes it.
fn prepared(
    log: &VehicleLog,
    route: &LogRoute,
    settings: &Settings,
    keep_lateral: bool,
) -> RouteTelemetry {
    let Ok(record) = &route.loaded.entry else {
        unreachable!("a log's record is made valid")
    };
    held_log_telemetry(
        record,
        log,
        route.reference.as_ref(),
        &route.steps,
        settings,
        keep_lateral,
    )
}

fn notes(log: &VehicleLog) -> Vec<Warning> {
    log.notes
        .iter()
        .map(|n| Warning::VehicleLog {
            file: log.path.clone(),
            text: n.clone(),
        })
        .collect()
}

/// One log replayed as it streams ([`replay_drive`]: memory flat in the log's length): its
/// outcome (a log that cannot be read is an invalid route whose reason names the file, topic and
/// fix).
fn replay_log(path: &Path, topics: &Topics, settings: &Settings) -> RouteOutcome {
    let dt = decimal(settings.core.dt);
    let invalid = |e: McapError| {
        let mut record = log_route(&empty_log(path)).loaded;
        record.source = path.to_path_buf();
        let mut out = unreplayed(&record);
        out.telemetry = TelemetryState::Invalid(e.to_string());
        out
    };
    let mut scan = match scan_log(path, topics, dt, settings.mcap.max_hold) {
        Ok(scan) => scan,
        Err(e) => return invalid(e),
    };
    // The log's record and path; its events' frames come as the frames stream.
    let route = log_route(&VehicleLog {
        events: scan
            .events
            .iter()
            .map(|(t, kind)| LogEvent {
                t: *t,
                frame: None,
                kind: kind.clone(),
            })
            .collect(),
        path_points: scan.reference_path().map(<[_]>::to_vec),
        ..empty_log(&scan.path)
    });
    let Ok(record) = &route.loaded.entry else {
        unreachable!("a log's record is made valid")
    };
    let replayed = replay_drive(
        &mut scan,
        unreplayed(&route.loaded),
        record,
        route.reference.as_ref(),
        settings,
        |notes| {
            notes
                .iter()
                .map(|n| Warning::VehicleLog {
                    file: path.to_path_buf(),
                    text: n.clone(),
                })
                .collect()
        },
    );
    match replayed {
        Ok(mut out) => {
            // The path stands where a route XML would.
            if route.reference.is_none() {
                out.reference = Some(ReferenceKind::None);
            }
            out
        }
        Err(e) => invalid(e),
    }
}

fn empty_log(path: &Path) -> VehicleLog {
    VehicleLog {
        name: crate::input::mcap::log_name(path),
        path: path.to_path_buf(),
        files: Vec::new(),
        telemetry: Default::default(),
        times: Vec::new(),
        dt: 0.0,
        events: Vec::new(),
        path_points: None,
        messages: 0,
        bytes: 0,
        notes: Vec::new(),
    }
}

/// Scores vehicle logs: each log one route (docs/SCORE.md §2.4), the report as [`crate::score_run`]
/// makes it, without the figures that need a Leaderboard record (it says so in its warnings).
///
/// ```no_run
/// use monitor_core::Profile;
/// use monitor_host::{NoProgress, RunSettings, ScoreRequest};
/// let request = ScoreRequest {
///     logs: vec!["drive.mcap".into()],
///     settings: RunSettings { profile: Profile::Autoware, ..RunSettings::default() },
///     ..ScoreRequest::default()
/// };
/// let report = request.score(&NoProgress)?.report;
/// assert!(report.summary.scores.driving_score.is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`Error`] for invalid settings. A log that cannot be read is an invalid route of the report,
/// its reason naming the file, the topic and the fix.
pub(crate) fn score_logs(
    logs: &[PathBuf],
    topics: &Topics,
    settings: &Settings,
) -> Result<Report, Error> {
    settings.validate()?;
    if logs.is_empty() {
        return Err(Error::EmptyRun { inputs: Vec::new() });
    }
    // As for results files: a log that is not there stops the run (exit 1), and two logs of one
    // name would be two routes of one id (exit 2, as duplicate ids of --results are).
    let mut names: Vec<(String, &PathBuf)> = Vec::with_capacity(logs.len());
    for log in logs {
        std::fs::metadata(log).map_err(|source| McapError::Unreadable {
            file: log.clone(),
            source,
        })?;
        let name = crate::input::mcap::log_name(log);
        if let Some((_, first)) = names.iter().find(|(n, _)| *n == name) {
            return Err(McapError::Duplicate {
                name,
                first: (*first).clone(),
                second: log.clone(),
            }
            .into());
        }
        names.push((name, log));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.worker_threads(logs.len()))
        .build()?;
    let outcomes: Vec<RouteOutcome> = pool.install(|| {
        logs.par_iter()
            .map(|p| replay_log(p, topics, settings))
            .collect()
    });
    let maps = TownMaps::load(None, std::iter::empty())?;
    let rows = route_rows(&outcomes, &[], settings, None, &maps);
    let files: Vec<PathBuf> = outcomes
        .iter()
        .flat_map(|o| o.files_read.iter().cloned())
        .collect();
    let provenance = Provenance::new(settings, files.iter().map(|f| (f.as_path(), "mcap")));
    let facts = RunFacts {
        provenance,
        n: outcomes.len(),
        route_set: None,
        inputs: Vec::new(),
        dropped: Vec::new(),
        kept: Vec::new(),
        // About the run, not a file: no file named.
        warnings: vec![Warning::VehicleLog {
            file: PathBuf::new(),
            text: NO_LEADERBOARD.to_string(),
        }],
    };
    let mut report = assemble(rows, &outcomes, settings, facts);
    without_leaderboard(&mut report);
    let mut files = files;
    files.append(&mut report.files_read);
    files.sort();
    files.dedup();
    report.files_read = files;
    Ok(report)
}

/// The frames of one log as [`score_logs`] streams them (`sds frames --mcap`).
///
/// # Errors
/// [`Error::VehicleLog`] naming the file, topic and fix; invalid settings.
pub(crate) fn log_frames(
    path: &Path,
    topics: &Topics,
    settings: &Settings,
) -> Result<RouteFrames, Error> {
    settings.validate()?;
    let log = read_log(
        path,
        topics,
        decimal(settings.core.dt),
        settings.mcap.max_hold,
    )?;
    let route = log_route(&log);
    let tel = prepared(&log, &route, settings, true);
    Ok(RouteFrames {
        frames: tel.prepared.frames,
        steps: tel.prepared.steps,
        lateral: tel.prepared.lateral,
        reference: tel.prepared.reference,
        dt: settings.core.dt,
        warnings: notes(&log),
        files_read: log.files.clone(),
    })
}

impl From<McapError> for Error {
    fn from(e: McapError) -> Self {
        Error::VehicleLog(Box::new(e))
    }
}
