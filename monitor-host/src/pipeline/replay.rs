//! Replay: one loaded record → its telemetry read and prepared → streamed through a fresh
//! [`Monitor`] → scored, and checked against the batch reference (docs/SCORE.md §11, docs/SCORE.md §13).

use std::path::{Path, PathBuf};

use monitor_core::{
    score, CollisionVerdict, ComfortSummary, Config, ConfigError, Event, Monitor, MonitorError,
    Profile, RecordScores, RouteSummary,
};

use crate::geometry::corridor::ReferenceKind;
use crate::geometry::map::Map;
use crate::geometry::map_fit::{self, MapFit};
use crate::geometry::town_maps::town_of;
use crate::input::discovery;
use crate::input::lead_infractions;
use crate::input::record::{LoadedRecord, Record};
use crate::input::route_xml::RouteSet;
use crate::input::telemetry::format::read_telemetry as read_telemetry_file;
use crate::input::warning::Warning;
use crate::pipeline::motion::MovingComfort;
use crate::pipeline::outcome::{CollisionEvent, RouteOutcome, TelemetryState};
use crate::pipeline::placement;
use crate::pipeline::prepare::{collision_events, prepare_with, PreparedRoute};
use crate::pipeline::step_period::{self, StepPeriod};
use crate::pipeline::timeline::{ChunkLog, RouteTimeline};
use crate::reference::batch;
use crate::settings::Settings;

/// Why the monitor refused a route.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Refused {
    /// The configuration (checked before any frame).
    #[error("{0}")]
    Config(ConfigError),
    /// A frame (its index), or `finish` (index = the number of frames).
    #[error("{error}")]
    Frame {
        /// Index of the frame.
        index: usize,
        /// What the monitor said.
        error: MonitorError,
    },
}

impl Refused {
    /// The index of the refused frame (0 for the configuration).
    pub fn index(&self) -> usize {
        match self {
            Refused::Config(_) => 0,
            Refused::Frame { index, .. } => *index,
        }
    }
}

/// Streams prepared frames through a fresh monitor; fills the events' verdicts.
/// Returns the summary, or why the monitor refused the route.
///
/// # Errors
/// The first frame (or the configuration) the monitor refused.
pub fn stream(prepared: &mut PreparedRoute, config: &Config) -> Result<RouteSummary, Refused> {
    stream_logged(prepared, config, &mut ChunkLog::default()).map(|s| s.summary)
}

/// What streaming a route gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Streamed {
    /// The route's counts under the run's profile.
    pub summary: RouteSummary,
    /// Its comfort under `b2d-legacy`, Bench2Drive's smoothness (docs/SCORE.md §10.1), whatever the run's
    /// profile: counted by the same monitor ([`Monitor::with_second_profile`]) unless the run's
    /// profile is `b2d-legacy` already.
    pub legacy_comfort: ComfortSummary,
}

/// The profile to count beside the run's own so that Bench2Drive's smoothness (docs/SCORE.md §10.1) is
/// reported under every profile: `b2d-legacy`, unless the run uses it already.
///
/// ```
/// use monitor_core::{Config, Profile};
/// use monitor_host::pipeline::replay::smoothness_profile;
/// assert_eq!(smoothness_profile(&Config::DEFAULT), Some(Profile::B2dLegacy));
/// let legacy = Config { profile: Profile::B2dLegacy, ..Config::DEFAULT };
/// assert_eq!(smoothness_profile(&legacy), None);
/// ```
pub fn smoothness_profile(config: &Config) -> Option<Profile> {
    (config.profile != Profile::B2dLegacy).then_some(Profile::B2dLegacy)
}

/// [`stream`], keeping the monitor's per-chunk verdicts in `log`, and counting Bench2Drive's
/// smoothness beside the run's comfort ([`Streamed`]). A vehicle log's segments
/// ([`PreparedRoute::segments`], docs/SCORE.md §2.4) each stream through a fresh monitor, and their
/// counts are added up; the verdicts keep the route's frame indices, and chunks are numbered
/// on across segments (each segment's after the `ceil(n / chunk_len)` chunks of those before).
///
/// # Errors
/// As [`stream`].
pub fn stream_logged(
    prepared: &mut PreparedRoute,
    config: &Config,
    log: &mut ChunkLog,
) -> Result<Streamed, Refused> {
    let mut monitor = SegmentMonitor::new(*config);
    monitor.check()?;
    let ranges =
        crate::input::telemetry::Telemetry::ranges(&prepared.segments, prepared.frames.len());
    for range in ranges {
        monitor.start(range.start)?;
        for (index, f) in prepared.frames[range.clone()].iter().enumerate() {
            monitor.push(range.start + index, f, log)?;
        }
        monitor.end(range.end, log)?;
    }
    monitor.verdicts_onto(&mut prepared.events);
    Ok(Streamed {
        summary: monitor.total,
        legacy_comfort: monitor.legacy,
    })
}

/// The monitor over a route's segments (docs/SCORE.md §2.4), for a route streamed whole
/// ([`stream_logged`]) and a drive streamed as its log is read ([`crate::pipeline::drive`]):
/// a fresh monitor per segment, the collision verdicts at the route's frame indices, the
/// chunks numbered on across segments (each segment's after the `ceil(n / chunk_len)` chunks
/// of those before), the counts added up.
pub(crate) struct SegmentMonitor {
    config: Config,
    monitor: Option<Monitor>,
    /// The route's index of the open segment's first frame.
    start: usize,
    chunks_before: u32,
    verdicts: Vec<CollisionVerdict>,
    /// The counts of the segments ended, added up.
    pub(crate) total: RouteSummary,
    /// Bench2Drive's smoothness of the segments ended, added up.
    pub(crate) legacy: ComfortSummary,
}

impl SegmentMonitor {
    pub(crate) fn new(config: Config) -> SegmentMonitor {
        SegmentMonitor {
            config,
            monitor: None,
            start: 0,
            chunks_before: 0,
            verdicts: Vec::new(),
            total: RouteSummary::ZERO,
            legacy: ComfortSummary::ZERO,
        }
    }

    /// The configuration, checked once before any frame, as a route without frames would be.
    pub(crate) fn check(&self) -> Result<(), Refused> {
        Monitor::<{ monitor_core::DEFAULT_CAPACITY }>::new(self.config)
            .map(drop)
            .map_err(Refused::Config)
    }

    /// Whether a segment is open.
    pub(crate) fn is_open(&self) -> bool {
        self.monitor.is_some()
    }

    /// Opens a segment at the route's frame `start` (the one before ended).
    pub(crate) fn start(&mut self, start: usize) -> Result<(), Refused> {
        let mut m: Monitor = Monitor::new(self.config).map_err(Refused::Config)?;
        if let Some(profile) = smoothness_profile(&self.config) {
            m = m.with_second_profile(profile);
        }
        self.monitor = Some(m);
        self.start = start;
        Ok(())
    }

    /// The route's frame `index` through the open segment's monitor (none open: nothing), its
    /// chunk verdicts into `log`.
    pub(crate) fn push(
        &mut self,
        index: usize,
        frame: &monitor_core::Frame,
        log: &mut ChunkLog,
    ) -> Result<(), Refused> {
        let Some(m) = self.monitor.as_mut() else {
            return Ok(());
        };
        let events = m
            .push(frame)
            .map_err(|error| Refused::Frame { index, error })?;
        // Most frames have no event.
        if !events.is_empty() {
            keep(
                &events,
                self.start,
                self.chunks_before,
                log,
                &mut self.verdicts,
            );
        }
        Ok(())
    }

    /// Ends the open segment before the route's frame `end`: its last verdicts and its counts.
    /// False when none was open.
    pub(crate) fn end(&mut self, end: usize, log: &mut ChunkLog) -> Result<bool, Refused> {
        let Some(mut m) = self.monitor.take() else {
            return Ok(false);
        };
        let done = m
            .finish()
            .map_err(|error| Refused::Frame { index: end, error })?;
        keep(
            &done.events,
            self.start,
            self.chunks_before,
            log,
            &mut self.verdicts,
        );
        self.total.merge(&done.summary);
        self.legacy
            .merge(m.second_comfort().unwrap_or(&done.summary.comfort));
        let chunk_len = u32::from(self.config.chunk_len.max(1));
        self.chunks_before += ((end - self.start) as u32).div_ceil(chunk_len);
        Ok(true)
    }

    /// The collision verdicts onto the route's events, by frame index.
    pub(crate) fn verdicts_onto(&self, events: &mut [CollisionEvent]) {
        for ev in events {
            if let Some(k) = ev.frame {
                if let Some(v) = self.verdicts.iter().find(|v| v.frame as usize == k) {
                    ev.decelerated = Some(v.decelerated);
                    ev.exempt = Some(v.exempt);
                }
            }
        }
    }
}

/// Keeps a `push` or `finish`'s events: collision verdicts at the route's frame index
/// (`offset`: the segment's first), chunk verdicts numbered on across segments.
fn keep(
    events: &monitor_core::Events,
    offset: usize,
    chunks_before: u32,
    log: &mut ChunkLog,
    verdicts: &mut Vec<CollisionVerdict>,
) {
    for e in events {
        match *e {
            Event::Collision(mut v) => {
                v.frame += offset as u32;
                verdicts.push(v);
            }
            Event::Comfort(mut c) => {
                c.chunk += chunks_before;
                log.comfort.push(c);
            }
            Event::Lateral(mut l) => {
                l.chunk += chunks_before;
                log.lateral.push(l);
            }
        }
    }
}

/// The batch reference of a route's frames (docs/SCORE.md §11), segment by segment as the monitor streams
/// them ([`stream_logged`]): the counts added up, and Bench2Drive's smoothness beside them.
pub fn batch_reference(prepared: &PreparedRoute, core: &Config) -> (RouteSummary, ComfortSummary) {
    let ranges =
        crate::input::telemetry::Telemetry::ranges(&prepared.segments, prepared.frames.len());
    let mut total = RouteSummary::ZERO;
    let mut legacy = ComfortSummary::ZERO;
    for r in ranges {
        let b = batch::compute_with(&prepared.frames[r], core, smoothness_profile(core));
        total.merge(&b.summary);
        legacy.merge(&b.second_comfort.unwrap_or(b.summary.comfort));
    }
    (total, legacy)
}

/// Why the monitor refused a frame, said in the file's own fields: the frame's numbers are
/// derived (a_mag from `acceleration`, speed from `location` and `dt`), and a reader looking for
/// `a_mag` in `metric_info.json` would not find it.
///
/// ```
/// use monitor_core::{Field, FrameError, MonitorError};
/// use monitor_host::pipeline::replay::{refusal_in_file_terms, Refused};
/// let r = Refused::Frame { index: 3, error: MonitorError::Frame(FrameError::NonFinite(Field::AMag)) };
/// assert_eq!(
///     refusal_in_file_terms(&r, 12, 0.05),
///     "acceleration at step 12 is too large: |a| overflows f32 (a_mag is not finite)"
/// );
/// ```
pub fn refusal_in_file_terms(refused: &Refused, step: u64, dt: f32) -> String {
    use monitor_core::{Field, FrameError};
    let Refused::Frame {
        error: MonitorError::Frame(FrameError::NonFinite(field)),
        ..
    } = refused
    else {
        return format!("step {step}: {refused}");
    };
    let (what, why) = match field {
        Field::AMag => ("acceleration", "is too large: |a| overflows f32"),
        Field::ALon => (
            "acceleration",
            "is too large: its component along forward_vector overflows f32",
        ),
        Field::ALat => (
            "acceleration",
            "is too large: its component along right_vector overflows f32",
        ),
        Field::YawRate => (
            "angular_velocity",
            "is too large: the yaw rate overflows f32",
        ),
        Field::Speed => {
            return format!(
                "location at step {step} jumps too far from the previous step: the distance / \
                 dt ({dt} s) overflows f32 ({})",
                FrameError::NonFinite(*field)
            )
        }
        Field::LatErr => (
            "location",
            "is too far from the route XML's reference: the lateral error overflows f32",
        ),
    };
    format!(
        "{what} at step {step} {why} ({})",
        FrameError::NonFinite(*field)
    )
}

/// A route's telemetry, read and turned into frames.
#[derive(Clone, Debug)]
pub struct RouteTelemetry {
    /// The frames and aligned events.
    pub prepared: PreparedRoute,
    /// The route's step period (docs/SCORE.md §2.2).
    pub period: StepPeriod,
    /// The settings of this route: the run's, with the route's `dt`.
    pub settings: Settings,
    /// Missing step numbers.
    pub gaps: u64,
    /// The `metric_info.json` read.
    pub path: PathBuf,
    /// The town's map was used (given, and it serves the route: [`crate::geometry::map_fit`]).
    pub map_used: bool,
}

/// What reading one route's telemetry needs from the run besides the record: the route's
/// reference (the route XML, the town map), where the telemetry lies, and the settings.
#[derive(Clone, Copy)]
pub struct RouteContext<'a> {
    /// The run's route XML, when given.
    pub routes: Option<&'a RouteSet>,
    /// The route's town map, when given and found.
    pub map: Option<&'a Map>,
    /// The `--telemetry` folder, when given.
    pub telemetry_root: Option<&'a Path>,
    /// The run's settings.
    pub settings: &'a Settings,
    /// Keep each frame's host-side lateral values (`PreparedRoute::lateral`): `sds frames`.
    pub keep_lateral: bool,
}

/// Locates and reads a record's telemetry (and `infractions.json` beside it), infers its step
/// period, and prepares its frames. Problems that do not stop the route are pushed to
/// `warnings`.
///
/// Every file located (read or not) is pushed to `files`.
pub fn read_telemetry(
    loaded: &LoadedRecord,
    record: &Record,
    context: RouteContext<'_>,
    warnings: &mut Vec<Warning>,
    files: &mut Vec<PathBuf>,
) -> Result<RouteTelemetry, TelemetryState> {
    let RouteContext {
        routes,
        map,
        telemetry_root,
        settings,
        keep_lateral,
    } = context;
    // A save_name naming another route's folder would score this record with that telemetry.
    if let Some(other) = record
        .save_name
        .as_deref()
        .and_then(discovery::save_name_route)
    {
        if other != record.route_id {
            return Err(TelemetryState::Invalid(format!(
                "{}: record {}: save_name {:?} names the telemetry of route {other}, not of this \
                 record's {}",
                loaded.source.display(),
                loaded.index,
                record.save_name.as_deref().unwrap_or_default(),
                record.route_id
            )));
        }
    }
    let path = record
        .save_name
        .as_deref()
        .and_then(|save| {
            discovery::locate_metric_info(
                telemetry_root,
                save,
                &loaded.source,
                loaded.records_in_file == 1,
            )
        })
        .ok_or_else(|| {
            TelemetryState::Missing(discovery::missing_reason(
                telemetry_root,
                record.save_name.as_deref(),
                &record.route_id,
                &loaded.source,
                loaded.records_in_file == 1,
            ))
        })?;
    files.push(path.clone());
    let tel = read_telemetry_file(&path)
        .map_err(|e| TelemetryState::Invalid(format!("{}: {e}", path.display())))?;
    let infractions = match discovery::lead_infractions_beside(&path) {
        None => None,
        Some(p) => match lead_infractions::read_lead_infractions({
            files.push(p.clone());
            &p
        }) {
            Ok(list) => Some(list),
            Err(e) => {
                warnings.push(Warning::LeadInfractions {
                    file: p,
                    reason: e.to_string(),
                });
                None
            }
        },
    };
    if let (Some(set), Some(id)) = (routes, record.xml_id()) {
        match set.get_checked(id) {
            Err(e) => warnings.push(Warning::NoReference(e)),
            Ok(r) if r.all_gaps(settings.gap_max) => warnings.push(Warning::AllGaps {
                file: set.file().to_string(),
                route: id.to_string(),
                gap_max: settings.gap_max,
            }),
            Ok(_) => {}
        }
    }
    let (first, last) = match (tel.frames.first(), tel.frames.last()) {
        (Some(a), Some(b)) => (a.step, b.step),
        _ => (0, 0),
    };
    let (period, period_warnings) =
        step_period::infer(first, last, tel.gaps, record.meta.duration_game, settings);
    warnings.extend(period_warnings);
    // A map that serves no route (no driving lane, or far from every frame) is not used.
    let map = map.filter(|m| {
        let points: Vec<[f64; 3]> = tel
            .frames
            .iter()
            .map(|f| [f.location[0], f.location[1], f.z])
            .collect();
        let distance = match map_fit::fit(m, &points) {
            MapFit::Serves => return true,
            MapFit::NoLanes => None,
            MapFit::TooFar { median } => Some(median),
        };
        warnings.push(Warning::MapNotServing {
            file: m.file().to_string(),
            town: town_of(record, routes).unwrap_or_default().to_string(),
            distance,
            reach: map_fit::MAP_REACH,
            lane_fallback: settings.lateral_reference == crate::settings::LateralReference::Lane,
        });
        false
    });
    // The period is configuration, set once for the route: the per-frame work is unchanged.
    let mut route_settings = settings.clone();
    route_settings.core.dt = period.as_f32(settings);
    let prepared = prepare_with(
        record,
        &tel,
        routes,
        map,
        infractions.as_deref(),
        &route_settings,
        keep_lateral,
    );
    Ok(RouteTelemetry {
        prepared,
        period,
        settings: route_settings,
        gaps: tel.gaps,
        path,
        map_used: map.is_some(),
    })
}

/// Replays one loaded record: locate and read telemetry, prepare frames, stream, score, and
/// check the batch reference.
pub fn replay(
    loaded: &LoadedRecord,
    routes: Option<&RouteSet>,
    map: Option<&Map>,
    telemetry_root: Option<&Path>,
    settings: &Settings,
) -> RouteOutcome {
    let out = unreplayed(loaded);
    let Ok(record) = &loaded.entry else {
        return out;
    };
    let has_route = routes
        .zip(record.xml_id())
        .is_some_and(|(set, id)| set.get(id).is_some());
    let context = RouteContext {
        routes,
        map,
        telemetry_root,
        settings,
        keep_lateral: false,
    };
    let mut out = replay_read(
        out,
        record,
        has_route,
        map.is_some(),
        settings,
        |warnings, files| read_telemetry(loaded, record, context, warnings, files),
    );
    if matches!(out.telemetry, TelemetryState::Missing(_)) {
        out.looked_in = discovery::looked_in(
            telemetry_root,
            record.save_name.as_deref(),
            &loaded.source,
            loaded.records_in_file == 1,
        );
    }
    out
}

/// [`replay`] at several points of `sds compare --sweep` (one [`RouteOutcome`] per point, in
/// order), doing each stage once per distinct input to it ([`crate::settings::defs::Sweep`]): a
/// point that moves only penalty factors takes an earlier point's counts and computes DS_safe
/// again; one that moves only what the monitor reads streams an earlier point's prepared frames
/// again; any other point reads and prepares the telemetry again. Each outcome is the one
/// [`replay`] gives at that point.
pub fn replay_points(
    loaded: &LoadedRecord,
    routes: Option<&RouteSet>,
    map: Option<&Map>,
    telemetry_root: Option<&Path>,
    points: &[Settings],
) -> Vec<RouteOutcome> {
    use crate::settings::defs::Sweep;
    let Ok(record) = &loaded.entry else {
        return points.iter().map(|_| unreplayed(loaded)).collect();
    };
    let has_route = routes
        .zip(record.xml_id())
        .is_some_and(|(set, id)| set.get(id).is_some());
    // Telemetry read at a point (by index), with what reading it said.
    type Read = (
        usize,
        Result<RouteTelemetry, TelemetryState>,
        Vec<Warning>,
        Vec<PathBuf>,
    );
    let mut reads: Vec<Read> = Vec::new();
    let mut outs: Vec<RouteOutcome> = Vec::with_capacity(points.len());
    for (i, settings) in points.iter().enumerate() {
        if let Some(j) = (0..i).find(|&j| points[j].sweep_stage(settings) <= Sweep::Factors) {
            let mut out = outs[j].clone();
            rescore(&mut out, record, settings);
            outs.push(out);
            continue;
        }
        let earlier = reads
            .iter()
            .find(|(j, ..)| points[*j].sweep_stage(settings) <= Sweep::Monitor);
        let mut out = match earlier {
            Some((_, read, warnings, files)) => replay_read(
                unreplayed(loaded),
                record,
                has_route,
                map.is_some(),
                settings,
                |w, f| {
                    w.extend(warnings.iter().cloned());
                    f.extend(files.iter().cloned());
                    // The same frames under this point's monitor settings (the period stays).
                    read.clone().map(|mut t| {
                        let dt = t.settings.core.dt;
                        t.settings = settings.clone();
                        t.settings.core.dt = dt;
                        t
                    })
                },
            ),
            None => {
                let context = RouteContext {
                    routes,
                    map,
                    telemetry_root,
                    settings,
                    keep_lateral: false,
                };
                let mut kept = None;
                let out = replay_read(
                    unreplayed(loaded),
                    record,
                    has_route,
                    map.is_some(),
                    settings,
                    |w, f| {
                        let (mut warnings, mut files) = (Vec::new(), Vec::new());
                        let read =
                            read_telemetry(loaded, record, context, &mut warnings, &mut files);
                        w.extend(warnings.iter().cloned());
                        f.extend(files.iter().cloned());
                        kept = Some((read.clone(), warnings, files));
                        read
                    },
                );
                if let Some((read, warnings, files)) = kept {
                    reads.push((i, read, warnings, files));
                }
                out
            }
        };
        if matches!(out.telemetry, TelemetryState::Missing(_)) {
            out.looked_in = discovery::looked_in(
                telemetry_root,
                record.save_name.as_deref(),
                &loaded.source,
                loaded.records_in_file == 1,
            );
        }
        outs.push(out);
    }
    outs
}

/// DS_safe again under `settings`' penalty factors, from the route's counts.
fn rescore(out: &mut RouteOutcome, record: &Record, settings: &Settings) {
    if let Some(s) = &out.summary {
        let scores = RecordScores {
            score_route: record.score_route,
            score_penalty: record.score_penalty,
            workzone: out.workzone,
        };
        out.safe = Some(score::ds_safe(s, &scores, &settings.core.factors));
    }
}

/// The part of [`replay`] after the telemetry is located: `read` gives the route's telemetry
/// (or why there is none), which is streamed, scored and checked. A vehicle log (docs/SCORE.md §2.4)
/// comes in here with telemetry made from its messages.
pub fn replay_read(
    mut out: RouteOutcome,
    record: &Record,
    has_route: bool,
    has_map: bool,
    settings: &Settings,
    read: impl FnOnce(&mut Vec<Warning>, &mut Vec<PathBuf>) -> Result<RouteTelemetry, TelemetryState>,
) -> RouteOutcome {
    out.reference = Some(ReferenceKind::of(
        has_route,
        has_map,
        settings.lateral_reference,
    ));
    let summary = match read(&mut out.warnings, &mut out.files_read) {
        Ok(RouteTelemetry {
            mut prepared,
            period,
            settings: route_settings,
            gaps,
            path,
            map_used,
        }) => {
            out.reference = Some(ReferenceKind::of(
                has_route,
                map_used,
                settings.lateral_reference,
            ));
            out.frames = prepared.frames.len() as u32;
            out.gaps = gaps;
            out.period = Some(period);
            let mut chunks = ChunkLog::default();
            match stream_logged(&mut prepared, &route_settings.core, &mut chunks) {
                Ok(Streamed {
                    summary,
                    legacy_comfort,
                }) => {
                    // docs/SCORE.md §11 for every count, Bench2Drive's smoothness included.
                    let (reference, legacy_reference) =
                        batch_reference(&prepared, &route_settings.core);
                    out.legacy_comfort = Some(legacy_comfort);
                    out.batch_agrees =
                        Some(reference == summary && legacy_reference == legacy_comfort);
                    out.telemetry = TelemetryState::Ok;
                    out.moving = Some(MovingComfort::count(
                        &prepared.motion.moving,
                        &chunks.comfort,
                    ));
                    out.motion = Some(prepared.motion);
                    out.events = prepared.events;
                    out.placed = prepared.placed;
                    let at: Vec<usize> = out.events.iter().filter_map(|e| e.frame).collect();
                    let mut timeline = RouteTimeline::around(
                        &prepared.frames,
                        &prepared.steps,
                        // The route's period as a decimal (0.05), as `time_s` uses it.
                        out.period
                            .map_or(crate::settings::decimal(route_settings.core.dt), |p| p.dt),
                        &at,
                        route_settings.core.decel_window,
                        chunks,
                    );
                    let chunk_len = usize::from(route_settings.core.chunk_len.max(1));
                    // Each segment's chunks start at its own first frame (docs/SCORE.md §2.4).
                    let n = prepared.steps.len();
                    let starts: Vec<usize> =
                        crate::input::telemetry::Telemetry::ranges(&prepared.segments, n)
                            .into_iter()
                            .flat_map(|r| r.step_by(chunk_len))
                            .collect();
                    timeline.chunk_steps = starts.iter().map(|&k| prepared.steps[k]).collect();
                    if !prepared.segments.is_empty() {
                        timeline.chunk_frames = starts;
                    }
                    out.timeline = Some(timeline);
                    Some(summary)
                }
                Err(refused) => {
                    let step = prepared
                        .steps
                        .get(refused.index())
                        .copied()
                        .unwrap_or_default();
                    out.telemetry = TelemetryState::Invalid(format!(
                        "{}: {}",
                        path.display(),
                        refusal_in_file_terms(&refused, step, settings.core.dt)
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
    conclude(out, record, settings, summary)
}

/// The end of a replay, whatever streamed the route's frames ([`replay_read`], or a drive
/// scored as it streams, [`crate::pipeline::drive`]): the collisions of a route not replayed,
/// the warnings of unparseable ones, and the route's DS_safe from its counts.
pub(crate) fn conclude(
    mut out: RouteOutcome,
    record: &Record,
    settings: &Settings,
    summary: Option<RouteSummary>,
) -> RouteOutcome {
    // A route not replayed keeps its collisions, unaligned (docs/SCORE.md §13).
    if out.telemetry != TelemetryState::Ok {
        out.events = collision_events(record);
        out.placed = placement::infraction_events(&record.infractions);
    }
    for e in &out.events {
        if let Some(reason) = &e.parse_error {
            out.warnings.push(Warning::UnparseableCollision {
                list: e.list,
                reason: reason.clone(),
            });
        }
    }
    out.workzone = out.events.iter().filter(|e| e.workzone).count() as u32;
    // Without telemetry the route is scored without telemetry terms only when allowed.
    let summary = summary.or_else(|| {
        settings
            .allow_missing_telemetry
            .then_some(RouteSummary::ZERO)
    });
    if let Some(s) = summary {
        let scores = RecordScores {
            score_route: record.score_route,
            score_penalty: record.score_penalty,
            workzone: out.workzone,
        };
        out.safe = Some(score::ds_safe(&s, &scores, &settings.core.factors));
        out.summary = Some(s);
    }
    out
}

/// A route's outcome before its replay: no telemetry yet, nothing scored.
pub fn unreplayed(loaded: &LoadedRecord) -> RouteOutcome {
    RouteOutcome {
        loaded: loaded.clone(),
        telemetry: TelemetryState::Missing(String::new()),
        period: None,
        foreign: false,
        frames: 0,
        gaps: 0,
        segments: None,
        summary: None,
        safe: None,
        legacy_comfort: None,
        timeline: None,
        events: Vec::new(),
        placed: Vec::new(),
        workzone: 0,
        batch_agrees: None,
        motion: None,
        moving: None,
        reference: None,
        warnings: Vec::new(),
        files_read: Vec::new(),
        looked_in: Vec::new(),
    }
}
