//! A vehicle log scored as it streams (issue 51, goal 2: memory flat in a drive's length): the
//! log's frames come from the MCAP reader one tick at a time ([`LogScan::frames`]) and each goes
//! at once through the frame builder, the monitor, the batch check, the motion figures and the
//! timeline; none of them holds the drive.
//!
//! - The batch reference (docs/SCORE.md §9) is checked part by part: every
//!   [`PART_CHUNKS`] chunks of a segment, [`batch::compute_part`] over the part's frames (with the
//!   deceleration window's frames before it) gives each chunk's comfort verdict, compared with
//!   the monitor's verdict of that chunk, and counts that add up to the route's, compared with
//!   the monitor's at the end. The batch side stays the independent reference it is for a
//!   results run: whole arrays over the part, no monitor state.
//! - The timeline keeps the chunk verdicts it draws and the frames around collisions
//!   ([`TimelineKeeper`]); the motion figures are running sums ([`MotionMeter`]).
//!
//! The outcome is the one [`crate::pipeline::replay::replay_read`] gives on the frames held
//! whole (the test `drive_streams_what_the_held_frames_give`; `bench/drive-memory.sh` compares
//! the reports with another binary's).

use monitor_core::{Collisions, ComfortSummary, Frame, RouteSummary};

use crate::geometry::corridor::{Corridor, ReferenceKind};
use crate::input::lead_infractions::StepInfraction;
use crate::input::mcap::{LogScan, LogTick, McapError, VehicleLog};
use crate::input::record::Record;
use crate::input::route_xml::RouteRef;
use crate::input::warning::Warning;
use crate::pipeline::align::AlignedBy;
use crate::pipeline::live::LiveFrames;
use crate::pipeline::motion::{MotionMeter, MovingComfort};
use crate::pipeline::outcome::{RouteOutcome, TelemetryState};
use crate::pipeline::placement;
use crate::pipeline::prepare::{collision_events, prepare_on};
use crate::pipeline::replay::{
    conclude, refusal_in_file_terms, smoothness_profile, Refused, RouteTelemetry, SegmentMonitor,
};
use crate::pipeline::step_period::{DtSource, StepPeriod};
use crate::pipeline::timeline::{ChunkLog, TimelineKeeper};
use crate::reference::batch;
use crate::settings::{decimal, Settings};

/// Chunks of a segment checked against the batch reference at a time.
pub const PART_CHUNKS: usize = 64;

/// The batch check of one segment, part by part.
struct BatchCheck {
    /// The segment's last `decel_window` frames before the part.
    before: Vec<Frame>,
    part: Vec<Frame>,
    /// Whether a part of the segment was checked already (the next part does not start it).
    started: bool,
}

/// A drive's state as its frames pass.
struct Drive<'a> {
    config: monitor_core::Config,
    dt: f64,
    chunk_len: usize,
    events: Vec<crate::pipeline::outcome::CollisionEvent>,
    live: LiveFrames<'a>,
    /// Why the monitor refused the route, and the step of the refused frame once known.
    refused: Option<(Refused, Option<u64>)>,
    monitor: SegmentMonitor,
    log: ChunkLog,
    check: BatchCheck,
    batch_total: RouteSummary,
    batch_legacy: ComfortSummary,
    /// Comfort verdicts of the monitor compared with the batch's so far.
    compared: usize,
    agrees: bool,
    seg_start: usize,
    meter: MotionMeter,
    keeper: TimelineKeeper,
    chunk_steps: Vec<u64>,
    chunk_frames: Vec<usize>,
    first_step: Option<u64>,
    last_step: u64,
    n: usize,
}

impl Drive<'_> {
    /// The current part's batch counts, and its chunks' comfort verdicts against the
    /// monitor's (given as the part's chunks end).
    fn check_part(&mut self) {
        let c = &mut self.check;
        if c.part.is_empty() {
            return;
        }
        let config = &self.config;
        let b = batch::compute_part(
            &c.before,
            &c.part,
            !c.started,
            config,
            smoothness_profile(config),
        );
        c.started = true;
        self.batch_total.merge(&b.summary);
        self.batch_legacy
            .merge(&b.second_comfort.unwrap_or(b.summary.comfort));
        for chunk in &b.comfort {
            let same =
                self.log.comfort.get(self.compared).is_some_and(|v| {
                    usize::from(v.frames) == chunk.frames && v.failed == chunk.failed
                });
            self.agrees &= same;
            self.compared += 1;
        }
        let window = usize::from(config.decel_window);
        let mut joined = std::mem::take(&mut c.before);
        joined.append(&mut c.part);
        let keep = window.min(joined.len());
        c.before = joined.split_off(joined.len() - keep);
    }

    /// Ends a segment: the monitor's last verdicts and counts, the batch check's last part.
    /// `end`: the index of the frame after it, `step`: that frame's step, if any.
    fn close(&mut self, end: usize, step: Option<u64>) {
        if self.refused.is_some() {
            return;
        }
        match self.monitor.end(end, &mut self.log) {
            Ok(true) => {
                self.check_part();
                self.check = BatchCheck {
                    before: Vec::new(),
                    part: Vec::new(),
                    started: false,
                };
            }
            Ok(false) => {}
            Err(refused) => self.refused = Some((refused, step)),
        }
    }

    /// One frame of the log.
    fn tick(&mut self, tick: &LogTick<'_>) {
        let index = tick.index;
        let step = tick.frame.step;
        self.n += 1;
        if let Some((r, s @ None)) = self.refused.as_mut() {
            // Refused at the end of the segment before, or the configuration: this frame's step
            // is the one said.
            if r.index() == index {
                *s = Some(step);
            }
        }
        if self.refused.is_some() {
            return;
        }
        let first = *self.first_step.get_or_insert(step);
        self.last_step = step;
        if tick.new_segment {
            self.close(index, Some(step));
            if self.refused.is_some() {
                return;
            }
            self.seg_start = index;
            self.live.start_segment();
            if let Err(refused) = self.monitor.start(index) {
                self.refused = Some((refused, Some(first)));
                return;
            }
        }
        let mut collisions = Collisions::NONE;
        for &e in tick.events {
            if let Some(ev) = self.events.get_mut(e) {
                ev.list.count_in(ev.workzone, &mut collisions);
                ev.frame = Some(index);
                ev.step = Some(step);
                ev.aligned_by = Some(AlignedBy::LogTime);
                ev.time_s = Some((step - first) as f64 * self.dt);
            }
        }
        let (frame, _) = self.live.build(tick.frame, collisions);
        for &e in tick.events {
            if let Some(ev) = self.events.get_mut(e) {
                ev.impact_speed = Some(frame.speed);
            }
        }
        if !self.monitor.is_open() {
            return;
        }
        if let Err(refused) = self.monitor.push(index, &frame, &mut self.log) {
            self.refused = Some((refused, Some(step)));
            return;
        }
        self.check.part.push(frame);
        if self.check.part.len() == PART_CHUNKS * self.chunk_len {
            self.check_part();
        }
        self.meter.push(tick.frame.location, step, tick.new_segment);
        self.keeper
            .push(index, step, frame, !tick.events.is_empty());
        if (index - self.seg_start).is_multiple_of(self.chunk_len) {
            self.chunk_steps.push(step);
            self.chunk_frames.push(index);
        }
    }
}

/// Scores a scanned log as its frames stream (see the module): `out` the route's outcome before
/// replay, `record` and `reference` the log's record and path, `notes` the reader's notes as
/// warnings.
///
/// `sds score --mcap` calls it through [`crate::ScoreRequest`]:
///
/// ```no_run
/// use monitor_host::{NoProgress, ScoreRequest};
/// // An 8-hour drive: the frames are scored as they are made, none held.
/// let request = ScoreRequest { logs: vec!["drive_8h.mcap".into()], ..ScoreRequest::default() };
/// let report = request.score(&NoProgress)?.report;
/// assert_eq!(report.routes[0].batch_agrees, Some(true));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// What framing the log found ([`LogScan::frames`]): the route is then invalid with it.
pub fn replay_drive(
    scan: &mut LogScan,
    mut out: RouteOutcome,
    record: &Record,
    reference: Option<&RouteRef>,
    settings: &Settings,
    notes: impl Fn(&[String]) -> Vec<Warning>,
) -> Result<RouteOutcome, McapError> {
    let config = settings.core;
    let dt = decimal(config.dt);
    let chunk_len = usize::from(config.chunk_len.max(1));
    out.reference = Some(ReferenceKind::of(
        reference.is_some(),
        false,
        settings.lateral_reference,
    ));
    let monitor = SegmentMonitor::new(config);
    let mut d = Drive {
        config,
        dt,
        chunk_len,
        events: collision_events(record),
        live: LiveFrames::with_corridor(Corridor::new(reference, None, settings), config.dt),
        refused: monitor.check().err().map(|refused| (refused, None)),
        monitor,
        log: ChunkLog::default(),
        check: BatchCheck {
            before: Vec::new(),
            part: Vec::new(),
            started: false,
        },
        batch_total: RouteSummary::ZERO,
        batch_legacy: ComfortSummary::ZERO,
        compared: 0,
        agrees: true,
        seg_start: 0,
        meter: MotionMeter::new(
            dt,
            &settings.motion,
            chunk_len,
            usize::from(config.min_chunk),
        ),
        keeper: TimelineKeeper::new(dt, config.decel_window),
        chunk_steps: Vec::new(),
        chunk_frames: Vec::new(),
        first_step: None,
        last_step: 0,
        n: 0,
    };
    let framed = scan.frames(|tick| d.tick(tick))?;
    d.close(d.n, None);

    out.warnings.extend(notes(&framed.notes));
    out.files_read.extend(scan.files.iter().cloned());
    out.frames = d.n as u32;
    out.gaps = framed.gaps;
    out.period = Some(StepPeriod {
        dt,
        source: DtSource::Config,
    });
    out.segments = Some(framed.segments);
    let summary = match d.refused {
        Some((refused, step)) => {
            out.telemetry = TelemetryState::Invalid(format!(
                "{}: {}",
                scan.path.display(),
                refusal_in_file_terms(&refused, step.unwrap_or_default(), config.dt)
            ));
            None
        }
        None => {
            let mut events = d.events;
            d.monitor.verdicts_onto(&mut events);
            let (total, legacy) = (d.monitor.total, d.monitor.legacy);
            out.legacy_comfort = Some(legacy);
            out.batch_agrees = Some(d.agrees && d.batch_total == total && d.batch_legacy == legacy);
            out.telemetry = TelemetryState::Ok;
            let (motion, marks) = d.meter.finish();
            out.moving = Some(MovingComfort::count(&motion.moving, &d.log.comfort));
            // A log's record has only its events' collision list: nothing else to place.
            let mut placed = placement::infraction_events(&record.infractions);
            if let Some(first) = d.first_step {
                let step_at = |i: usize| {
                    marks
                        .binary_search_by_key(&(i as u32), |m| m.0)
                        .ok()
                        .map(|j| marks[j].1)
                };
                placed.extend(placement::standing_events_by(
                    &motion.stationary,
                    step_at,
                    first,
                    d.last_step,
                    settings,
                    dt,
                ));
            }
            out.motion = Some(motion);
            out.placed = placed;
            out.events = events;
            let mut timeline = d.keeper.finish(d.log);
            timeline.chunk_steps = d.chunk_steps;
            timeline.chunk_frames = d.chunk_frames;
            out.timeline = Some(timeline);
            Some(total)
        }
    };
    Ok(conclude(out, record, settings, summary))
}

/// A vehicle log's telemetry held whole, prepared as the replay takes it (docs/SCORE.md,
/// "Vehicle logs"): its events placed by log time, the configured period (a log has no step
/// period to infer). `sds frames --mcap` reads it; the streamed drive checks itself against it
/// in its tests.
pub(crate) fn held_log_telemetry(
    record: &Record,
    log: &VehicleLog,
    reference: Option<&RouteRef>,
    steps: &[StepInfraction],
    settings: &Settings,
    keep_lateral: bool,
) -> RouteTelemetry {
    let mut prepared = prepare_on(
        record,
        &log.telemetry,
        reference,
        None,
        Some(steps),
        settings,
        keep_lateral,
    );
    for e in &mut prepared.events {
        if e.aligned_by.is_some() {
            e.aligned_by = Some(AlignedBy::LogTime);
        }
    }
    RouteTelemetry {
        prepared,
        period: StepPeriod {
            dt: decimal(settings.core.dt),
            source: DtSource::Config,
        },
        settings: settings.clone(),
        gaps: log.telemetry.gaps,
        path: log.path.clone(),
        map_used: false,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::input::mcap::{read_log, scan_log, Topics};
    use crate::input::record::{Infractions, LoadedRecord, Meta};
    use crate::pipeline::replay::{replay_read, unreplayed};

    use crate::demo::drive::{write_messages, Cdr, LogOptions, Message, IMU, ODOMETRY, PATH, T0};

    const MS: u64 = 1_000_000;

    /// A message's CDR, its header stamped `t`.
    fn stamped(t: u64) -> Cdr {
        let mut c = Cdr::new();
        c.header(t);
        c
    }

    type Msg = Message<'static>;

    /// A drive with what the streaming must get right: stops (standing events), hard braking
    /// and collisions (before the first pose, on frames, in a gap, after the last), recorder
    /// pauses (segments, one shorter than a chunk), messages out of order, a path.
    fn drive(imu: bool, path: bool) -> Vec<Msg> {
        let mut out: Vec<Msg> = Vec::new();
        let (mut x, mut yaw) = (0.0f64, 0.0f64);
        for i in 0..4_000u64 {
            // Pauses: 1.5 s at 1,000, then 6 frames and another pause (a 6-frame segment).
            if (1_000..1_030).contains(&i) || (1_036..1_060).contains(&i) {
                continue;
            }
            let t = T0 + i * 50 * MS;
            let s = i as f64 * 0.05;
            let v = match i {
                300..=500 => 0.0,
                1_500..=1_540 => 12.0 - (i - 1_500) as f64 * 0.3,
                _ => 8.0 + 3.0 * (s / 9.0).sin(),
            };
            let wz = 0.3 * (s / 5.0).sin();
            let ax = if (1_500..=1_540).contains(&i) {
                -6.0
            } else {
                0.8 * (s / 2.3).sin()
            };
            yaw += wz * 0.05;
            x += v * yaw.cos() * 0.05;
            let y = 0.4 * (s / 11.0).sin();
            let mut c = stamped(t);
            c.string("base_link");
            c.f64s(&[x, y, 0.0, 0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]);
            c.f64s(&[0.0; 36])
                .f64s(&[v, 0.0, 0.0, 0.0, 0.0, wz])
                .f64s(&[0.0; 36]);
            out.push(("/odom", "nav_msgs/msg/Odometry", ODOMETRY, t, c.0));
            if imu {
                let mut c = stamped(t + 3 * MS);
                c.f64s(&[
                    0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                ]);
                c.f64s(&[0.0, 0.0, wz]).f64s(&[0.0; 9]);
                c.f64s(&[ax, v * wz, 9.8]).f64s(&[0.0; 9]);
                out.push(("/imu", "sensor_msgs/msg/Imu", IMU, t + 3 * MS, c.0));
            }
        }
        // Out of order by less than a second: said and sorted.
        out.swap(40, 44);
        for t in [
            T0 - 20 * MS,
            T0 + 1_530 * 50 * MS,
            T0 + 1_012 * 50 * MS,
            T0 + 3_999 * 50 * MS + 30 * MS,
            T0 + 900 * 50 * MS + 7 * MS,
        ] {
            out.push(("/events", "std_msgs/msg/Empty", "", t, vec![0, 1, 0, 0]));
        }
        if path {
            let mut c = stamped(T0);
            c.u32(400);
            for k in 0..400 {
                c.header(T0)
                    .f64s(&[k as f64 * 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
            }
            out.push(("/path", "nav_msgs/msg/Path", PATH, T0, c.0));
        }
        out
    }

    fn write(path: &Path, messages: &[Msg]) {
        let options = LogOptions {
            chunk_size: 16_384,
            ..LogOptions::default()
        };
        write_messages(path, options, messages).unwrap();
    }

    /// The log's record and path, as `sds score --mcap` makes them.
    fn record(
        name: &str,
        source: &Path,
        kinds: &[String],
        path: Option<&[[f64; 3]]>,
    ) -> (LoadedRecord, Option<RouteRef>) {
        let messages: Vec<String> = kinds
            .iter()
            .enumerate()
            .map(|(i, k)| format!("Agent collided against object with type={k} and id={i}"))
            .collect();
        let record = Record {
            route_id: name.into(),
            scenario_name: String::new(),
            weather_id: None,
            save_name: None,
            town_name: None,
            status: String::new(),
            infractions: Infractions::from_lists([("collisions_vehicle", messages)]),
            score_route: 100.0,
            score_penalty: 1.0,
            score_composed: 100.0,
            meta: Meta::default(),
        };
        let reference = path.map(|p| RouteRef {
            id: name.into(),
            town: String::new(),
            waypoints: p.iter().map(|q| [q[0], q[1]]).collect(),
            heights: p.iter().map(|q| q[2]).collect(),
            scenario_type: None,
        });
        let loaded = LoadedRecord {
            source: source.to_path_buf(),
            index: 0,
            records_in_file: 1,
            entry: Ok(record),
        };
        (loaded, reference)
    }

    /// The outcome of the log's frames held whole (read_log, prepare, replay_read), as the
    /// replay was before it streamed.
    fn held(path: &Path, topics: &Topics, settings: &Settings) -> RouteOutcome {
        let log = read_log(
            path,
            topics,
            decimal(settings.core.dt),
            settings.mcap.max_hold,
        )
        .unwrap();
        let kinds: Vec<String> = log.events.iter().map(|e| e.kind.clone()).collect();
        let (loaded, reference) = record(&log.name, &log.path, &kinds, log.path_points.as_deref());
        let Ok(rec) = &loaded.entry else {
            unreachable!()
        };
        let steps: Vec<StepInfraction> = log
            .events
            .iter()
            .enumerate()
            .filter_map(|(i, e)| {
                Some(StepInfraction {
                    step: log.telemetry.frames.get(e.frame?)?.step,
                    message: format!(
                        "Agent collided against object with type={} and id={i}",
                        kinds[i]
                    ),
                })
            })
            .collect();
        let mut out = replay_read(
            unreplayed(&loaded),
            rec,
            reference.is_some(),
            false,
            settings,
            |w, f| {
                w.extend(log.notes.iter().map(|n| Warning::VehicleLog {
                    file: log.path.clone(),
                    text: n.clone(),
                }));
                f.extend(log.files.iter().cloned());
                Ok(held_log_telemetry(
                    rec,
                    &log,
                    reference.as_ref(),
                    &steps,
                    settings,
                    false,
                ))
            },
        );
        out.segments = Some(log.telemetry.segments.len().max(1) as u64);
        out
    }

    fn streamed(path: &Path, topics: &Topics, settings: &Settings) -> RouteOutcome {
        let mut scan = scan_log(
            path,
            topics,
            decimal(settings.core.dt),
            settings.mcap.max_hold,
        )
        .unwrap();
        let kinds: Vec<String> = scan.events.iter().map(|e| e.1.clone()).collect();
        let (loaded, reference) = record(
            &scan.name,
            &scan.path.clone(),
            &kinds,
            scan.reference_path(),
        );
        let Ok(rec) = &loaded.entry else {
            unreachable!()
        };
        let file = scan.path.clone();
        replay_drive(
            &mut scan,
            unreplayed(&loaded),
            rec,
            reference.as_ref(),
            settings,
            |notes| {
                notes
                    .iter()
                    .map(|n| Warning::VehicleLog {
                        file: file.clone(),
                        text: n.clone(),
                    })
                    .collect()
            },
        )
        .unwrap()
    }

    #[test]
    fn drive_streams_what_the_held_frames_give() {
        let dir = tempfile::tempdir().unwrap();
        for (imu, path, profile) in [
            (true, true, "physical"),
            (false, false, "physical"),
            (true, false, "b2d-legacy"),
            (true, true, "autoware"),
        ] {
            let log = dir
                .path()
                .join(format!("drive_{imu}_{path}_{profile}.mcap"));
            write(&log, &drive(imu, path));
            let mut topics = Topics {
                event: Some("/events".into()),
                ..Topics::default()
            };
            if path {
                topics.path = Some("/path".into());
            }
            let mut settings = Settings::default();
            settings.set("profile", profile).unwrap();
            let (a, b) = (
                held(&log, &topics, &settings),
                streamed(&log, &topics, &settings),
            );
            assert_eq!(b.telemetry, TelemetryState::Ok, "{imu} {path} {profile}");
            assert_eq!(b.batch_agrees, Some(true));
            // What must be there for the comparison to mean something.
            assert!(b.segments >= Some(3), "{:?}", b.segments);
            assert!(b.events.iter().filter(|e| e.frame.is_some()).count() >= 3);
            assert!(b.placed.iter().any(|p| p.kind == "stationary"));
            assert!(
                b.warnings
                    .iter()
                    .any(|w| w.to_string().contains("out of log-time order"))
                    || !imu
            );
            assert!(b.timeline.as_ref().is_some_and(|t| !t.kept.is_empty()));
            assert_eq!(format!("{a:?}"), format!("{b:?}"), "{imu} {path} {profile}");
        }
    }
}
