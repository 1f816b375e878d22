//! How far a route drove and how long it stood (docs/SCORE.md §10.0): distance, the share
//! of stationary frames, and which comfort chunks were driven rather than stood through.
//!
//! Bench2Drive's comfort counts a chunk in which the car stands still as comfortable, so a car
//! that barely moves looks smooth. These figures let a report show comfort over the chunks the
//! car actually drove (`comfort.moving_score`).
//!
//! Host geometry, as the lateral error: double precision on the raw coordinates, in step order.
//! The core does not compute them: its frames carry no position (only the f32 speed), and
//! adding one would change the frame of every front end (C, firmware, Python) for a figure that
//! is about the run, not about safety; the comfort verdicts it emits per chunk are matched with
//! the moving flags here ([`MovingComfort::count`]).
//!
//! ```
//! use monitor_host::pipeline::motion::{measure, MotionSettings};
//! // 30 frames at 20 Hz: 10 standing, then 20 at 2 m/s.
//! let steps: Vec<u64> = (0..30).collect();
//! let locations: Vec<[f64; 2]> =
//!     (0..30).map(|i| [if i < 10 { 0.0 } else { 0.1 * (i - 9) as f64 }, 0.0]).collect();
//! let m = measure(&locations, &steps, 0.05, &MotionSettings::default(), 20, 7);
//! assert!((m.distance_m - 2.0).abs() < 1e-9);
//! assert_eq!(m.stationary_share, Some(10.0 / 30.0));
//! assert_eq!(m.moving, vec![true]); // chunk 0 (frames 0..20): 1.0 m in 0.95 s
//! ```

use monitor_core::ComfortVerdict;

pub use crate::settings::MotionSettings;

/// A route's motion figures.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    /// The sum of the 2-D distances between consecutive frames, m.
    pub distance_m: f64,
    /// Frames slower than `stationary_speed` / frames (`None` without frames); frame 0 takes
    /// frame 1's speed, a one-frame route counts as stationary.
    pub stationary_share: Option<f64>,
    /// Per comfort chunk (docs/SCORE.md §4: full chunks of `chunk_len`, or one chunk for a short route of at
    /// least `min_chunk` frames), whether it is moving.
    pub moving: Vec<bool>,
    /// The stationary stretches, as frame ranges `[start, end)` (the HTML page's timeline).
    pub stationary: Vec<(u32, u32)>,
}

/// The runs of `true` in `flags` as ranges `[start, end)`.
fn stretches(flags: &[bool]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, f) in flags.iter().chain([&false]).enumerate() {
        match (start, *f) {
            (None, true) => start = Some(i as u32),
            (Some(s), false) => {
                out.push((s, i as u32));
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The 2-D distance between two locations.
fn step_length(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// Measures a route from its frames' 2-D `locations` and `steps` (step order) with step period
/// `dt` (s, the decimal the report prints) and the comfort chunking (`chunk_len`, `min_chunk`).
pub fn measure(
    locations: &[[f64; 2]],
    steps: &[u64],
    dt: f64,
    settings: &MotionSettings,
    chunk_len: usize,
    min_chunk: usize,
) -> Motion {
    let n = locations.len().min(steps.len());
    let gap = |i: usize| step_length(locations[i - 1], locations[i]);
    // `+ 0.0`: an empty f64 sum is -0.0, which a one-frame route would report.
    let distance_m = (1..n).map(gap).sum::<f64>() + 0.0;
    // speed_i (docs/SCORE.md §3) in double precision; frame 0 takes speed_1.
    let speed = |i: usize| {
        let span = steps[i].saturating_sub(steps[i - 1]) as f64 * dt;
        if span > 0.0 {
            gap(i) / span
        } else {
            0.0
        }
    };
    let stationary: Vec<bool> = (0..n)
        .map(|i| match (i, n) {
            (_, 1) => true,
            (0, _) => speed(1) < settings.stationary_speed,
            _ => speed(i) < settings.stationary_speed,
        })
        .collect();
    let stationary_share =
        (n > 0).then(|| stationary.iter().filter(|s| **s).count() as f64 / n as f64);
    let chunks: Vec<(usize, usize)> = if n >= chunk_len && chunk_len > 0 {
        (0..n / chunk_len)
            .map(|k| (k * chunk_len, (k + 1) * chunk_len))
            .collect()
    } else if n >= min_chunk.max(1) {
        vec![(0, n)]
    } else {
        Vec::new()
    };
    let moving = chunks
        .into_iter()
        .map(|(a, b)| {
            let path: f64 = (a + 1..b).map(gap).sum();
            let duration = steps[b - 1].saturating_sub(steps[a]) as f64 * dt;
            duration > 0.0 && path / duration >= settings.moving_speed
        })
        .collect();
    Motion {
        distance_m,
        stationary_share,
        moving,
        stationary: stretches(&stationary),
    }
}

/// [`measure`] over a vehicle log's segments (docs/SCORE.md §2.4; `segments`: the index of each
/// segment's first frame, empty for one run of frames): each segment is measured as a route of
/// its own (no distance across a gap, its first frame taking its second's speed), and the
/// figures added up. `moving` is indexed as the monitor numbers the chunks of a segmented route
/// (each segment's chunks after the `ceil(n / chunk_len)` of the segments before it); a chunk
/// with no comfort verdict (a segment's trailing partial chunk) is not moving.
///
/// ```
/// use monitor_host::pipeline::motion::{measure_segments, MotionSettings};
/// // Two segments of 25 frames at 2 m/s (20 Hz), 100 m apart: no distance across the gap.
/// let steps: Vec<u64> = (0..25).chain(1000..1025).collect();
/// let locations: Vec<[f64; 2]> = (0..50)
///     .map(|i| [if i < 25 { 0.1 * i as f64 } else { 100.0 + 0.1 * i as f64 }, 0.0])
///     .collect();
/// let m = measure_segments(&locations, &steps, &[0, 25], 0.05, &MotionSettings::default(), 20, 7);
/// assert!((m.distance_m - 4.8).abs() < 1e-9);
/// assert_eq!(m.stationary_share, Some(0.0));
/// assert_eq!(m.moving, vec![true, false, true]);
/// ```
pub fn measure_segments(
    locations: &[[f64; 2]],
    steps: &[u64],
    segments: &[usize],
    dt: f64,
    settings: &MotionSettings,
    chunk_len: usize,
    min_chunk: usize,
) -> Motion {
    let n = locations.len().min(steps.len());
    if segments.is_empty() {
        return measure(locations, steps, dt, settings, chunk_len, min_chunk);
    }
    let ranges = crate::input::telemetry::Telemetry::ranges(segments, n);
    let last = ranges.len().saturating_sub(1);
    let mut out = Motion::default();
    let mut standing = 0u64;
    for (i, r) in ranges.into_iter().enumerate() {
        let m = measure(
            &locations[r.clone()],
            &steps[r.clone()],
            dt,
            settings,
            chunk_len,
            min_chunk,
        );
        out.distance_m += m.distance_m;
        let offset = r.start as u32;
        for &(a, b) in &m.stationary {
            standing += u64::from(b - a);
            out.stationary.push((a + offset, b + offset));
        }
        out.moving.extend(&m.moving);
        if i < last && chunk_len > 0 {
            let chunks = r.len().div_ceil(chunk_len);
            out.moving
                .resize(out.moving.len() + chunks - m.moving.len(), false);
        }
    }
    out.stationary_share = (n > 0).then(|| standing as f64 / n as f64);
    out
}

/// [`measure_segments`] frame by frame, as a long drive streams (issue 51): the same figures,
/// to the bit, holding one segment's running sums and the stretches and chunk flags the
/// figures are made of, never the frames.
///
/// ```
/// use monitor_host::pipeline::motion::{measure_segments, MotionMeter, MotionSettings};
/// let steps: Vec<u64> = (0..25).chain(1000..1025).collect();
/// let locations: Vec<[f64; 2]> = (0..50)
///     .map(|i| [if i < 25 { 0.1 * i as f64 } else { 100.0 + 0.1 * i as f64 }, 0.0])
///     .collect();
/// let settings = MotionSettings::default();
/// let mut meter = MotionMeter::new(0.05, &settings, 20, 7);
/// for (i, (l, s)) in locations.iter().zip(&steps).enumerate() {
///     meter.push(*l, *s, i == 0 || i == 25);
/// }
/// let m = measure_segments(&locations, &steps, &[0, 25], 0.05, &settings, 20, 7);
/// assert_eq!(meter.finish().0, m);
/// ```
#[derive(Clone, Debug)]
pub struct MotionMeter {
    dt: f64,
    settings: MotionSettings,
    chunk_len: usize,
    min_chunk: usize,
    out: Motion,
    /// Stationary frames, all segments.
    standing: u64,
    /// Frames, all segments.
    n: u64,
    seg: Option<Segment>,
    /// The step of each stretch's first frame and of the frame after it (`standing_events`).
    marks: Vec<(u32, u64)>,
    /// A stretch that ended with its segment: its end's step is the next frame's.
    end_pending: Option<u32>,
    last_step: u64,
}

/// One segment's running sums.
#[derive(Clone, Debug)]
struct Segment {
    start: u32,
    n: usize,
    distance: f64,
    prev: ([f64; 2], u64),
    first_step: u64,
    /// The current stationary run's first frame (index in the route).
    run: Option<u32>,
    /// The current chunk's path and first step.
    path: f64,
    chunk_step: u64,
    /// Moving flags pushed for this segment.
    moving: usize,
}

impl MotionMeter {
    /// A meter with step period `dt` (s) and the comfort chunking.
    pub fn new(dt: f64, settings: &MotionSettings, chunk_len: usize, min_chunk: usize) -> Self {
        MotionMeter {
            dt,
            settings: *settings,
            chunk_len: chunk_len.max(1),
            min_chunk: min_chunk.max(1),
            out: Motion::default(),
            standing: 0,
            n: 0,
            seg: None,
            marks: Vec::new(),
            end_pending: None,
            last_step: 0,
        }
    }

    /// The next frame: its 2-D location and step; `new_segment` for a segment's first frame
    /// (the route's first included).
    pub fn push(&mut self, location: [f64; 2], step: u64, new_segment: bool) {
        let index = self.n as u32;
        if new_segment || self.seg.is_none() {
            self.close(false);
            self.seg = Some(Segment {
                start: index,
                n: 0,
                distance: -0.0,
                prev: (location, step),
                first_step: step,
                run: None,
                path: -0.0,
                chunk_step: step,
                moving: 0,
            });
        }
        if let Some(b) = self.end_pending.take() {
            self.marks.push((b, step));
        }
        let mut flags: [Option<(u32, bool)>; 2] = [None, None];
        let (dt, chunk_len) = (self.dt, self.chunk_len);
        let Some(seg) = self.seg.as_mut() else {
            return;
        };
        let j = seg.n;
        let mut moving = None;
        if j > 0 {
            let gap = step_length(seg.prev.0, location);
            seg.distance += gap;
            let span = step.saturating_sub(seg.prev.1) as f64 * dt;
            let speed = if span > 0.0 { gap / span } else { 0.0 };
            let still = speed < self.settings.stationary_speed;
            // Frame 0 takes frame 1's speed.
            if j == 1 {
                flags[0] = Some((seg.start, still));
            }
            flags[1] = Some((index, still));
            if j % chunk_len != 0 {
                seg.path += gap;
            }
        }
        if j % chunk_len == 0 {
            seg.path = -0.0;
            seg.chunk_step = step;
        }
        if j % chunk_len == chunk_len - 1 {
            let duration = step.saturating_sub(seg.chunk_step) as f64 * dt;
            moving = Some(duration > 0.0 && seg.path / duration >= self.settings.moving_speed);
            seg.moving += 1;
        }
        seg.prev = (location, step);
        seg.n += 1;
        self.n += 1;
        self.last_step = step;
        if let Some(m) = moving {
            self.out.moving.push(m);
        }
        for (i, still) in flags.into_iter().flatten() {
            self.flag(i, still, step);
        }
    }

    /// Frame `i`'s stationary flag (frames in order); `step`: the current frame's.
    fn flag(&mut self, i: u32, still: bool, step: u64) {
        let Some(seg) = self.seg.as_mut() else {
            return;
        };
        match (seg.run, still) {
            (None, true) => {
                seg.run = Some(i);
                // Frame 0's flag comes with frame 1: its step is the segment's first.
                let at = if i == seg.start { seg.first_step } else { step };
                self.marks.push((i, at));
            }
            (Some(a), false) => {
                self.out.stationary.push((a, i));
                self.standing += u64::from(i - a);
                self.marks.push((i, step));
                seg.run = None;
            }
            _ => {}
        }
    }

    /// Ends the current segment (`last`: the route's last).
    fn close(&mut self, last: bool) {
        let Some(seg) = self.seg.as_ref() else {
            return;
        };
        if seg.n == 1 {
            let (start, step) = (seg.start, seg.first_step);
            self.flag(start, true, step);
        }
        let Some(seg) = self.seg.take() else {
            return;
        };
        let end = seg.start + seg.n as u32;
        if let Some(a) = seg.run {
            self.out.stationary.push((a, end));
            self.standing += u64::from(end - a);
            self.end_pending = Some(end);
        }
        self.out.distance_m += seg.distance + 0.0;
        if seg.n < self.chunk_len && seg.n >= self.min_chunk {
            let duration = seg.prev.1.saturating_sub(seg.first_step) as f64 * self.dt;
            self.out
                .moving
                .push(duration > 0.0 && seg.path / duration >= self.settings.moving_speed);
        } else if !last {
            let chunks = seg.n.div_ceil(self.chunk_len);
            let len = self.out.moving.len() + chunks - seg.moving;
            self.out.moving.resize(len, false);
        }
    }

    /// The route's figures, and the steps at the stretches' ends (frame index → step) that
    /// [`crate::pipeline::placement::standing_events_by`] needs.
    pub fn finish(mut self) -> (Motion, Vec<(u32, u64)>) {
        self.close(true);
        if let Some(b) = self.end_pending.take() {
            self.marks.push((b, self.last_step));
        }
        self.out.stationary_share = (self.n > 0).then(|| self.standing as f64 / self.n as f64);
        self.marks.sort_by_key(|m| m.0);
        self.marks.dedup_by_key(|m| m.0);
        (self.out, self.marks)
    }
}

/// Comfort over the moving chunks of a route.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MovingComfort {
    /// Moving comfort chunks.
    pub chunks: u32,
    /// Of those, the comfortable ones.
    pub comfortable: u32,
}

impl MovingComfort {
    /// Matches the monitor's comfort verdicts (one per chunk, in chunk order) with the chunks'
    /// moving flags.
    ///
    /// ```
    /// use monitor_host::pipeline::motion::MovingComfort;
    /// let m = MovingComfort::count(&[true, false], &[]);
    /// assert_eq!((m.chunks, m.comfortable, m.score()), (0, 0, None));
    /// ```
    pub fn count(moving: &[bool], verdicts: &[ComfortVerdict]) -> Self {
        let mut out = MovingComfort::default();
        for v in verdicts {
            if moving.get(v.chunk as usize).copied().unwrap_or(false) {
                out.chunks += 1;
                out.comfortable += u32::from(v.failed.comfortable());
            }
        }
        out
    }

    /// Comfortable moving chunks / moving chunks; `None` when no chunk moved.
    pub fn score(self) -> Option<f64> {
        (self.chunks > 0).then(|| f64::from(self.comfortable) / f64::from(self.chunks))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn verdict(chunk: u32) -> ComfortVerdict {
        ComfortVerdict {
            chunk,
            frames: 20,
            failed: Default::default(),
        }
    }

    fn line(speeds: &[f64], dt: f64) -> Vec<[f64; 2]> {
        // Frame i is reached at speeds[i] from frame i-1 (speeds[0] unused).
        let mut x = 0.0;
        speeds
            .iter()
            .enumerate()
            .map(|(i, v)| {
                if i > 0 {
                    x += v * dt;
                }
                [x, 0.0]
            })
            .collect()
    }

    #[test]
    fn gaps_between_steps_divide_by_the_elapsed_time() {
        // Steps 0, 1, 5: the third frame is 0.4 m on, over 4 steps of 0.05 s = 2 m/s.
        let m = measure(
            &[[0.0, 0.0], [0.0, 0.0], [0.4, 0.0]],
            &[0, 1, 5],
            0.05,
            &MotionSettings::default(),
            20,
            7,
        );
        assert_eq!(m.distance_m, 0.4);
        // Frame 0 takes frame 1's speed (0): 2 of 3 stationary.
        assert_eq!(m.stationary, vec![(0, 2)]);
        assert_eq!(m.stationary_share, Some(2.0 / 3.0));
        assert!(m.moving.is_empty(), "3 frames: no comfort chunk");
    }

    #[test]
    fn a_one_frame_route_is_stationary_and_no_frame_means_no_share() {
        let one = measure(&[[5.0, 5.0]], &[7], 0.05, &MotionSettings::default(), 20, 7);
        assert_eq!((one.distance_m, one.stationary_share), (0.0, Some(1.0)));
        let none = measure(&[], &[], 0.05, &MotionSettings::default(), 20, 7);
        assert_eq!(none.stationary_share, None);
    }

    #[test]
    fn a_route_that_never_moves_has_no_moving_chunk() {
        let locs = vec![[1.0, 2.0]; 45];
        let steps: Vec<u64> = (0..45).collect();
        let m = measure(&locs, &steps, 0.05, &MotionSettings::default(), 20, 7);
        assert_eq!(m.moving, vec![false, false]);
        assert_eq!(m.stationary_share, Some(1.0));
        let verdicts = [verdict(0), verdict(1)];
        assert_eq!(MovingComfort::count(&m.moving, &verdicts).score(), None);
    }

    #[test]
    fn a_chunk_exactly_at_moving_speed_is_moving() {
        // 20 frames, 19 gaps of 0.05 s: 0.95 s; at exactly 1 m/s the path is 0.95 m.
        let dt = 0.05;
        let steps: Vec<u64> = (0..20).collect();
        let settings = MotionSettings::default();
        let at = |v: f64| measure(&line(&[v; 20], dt), &steps, dt, &settings, 20, 7).moving;
        // Sums of 0.05 m steps: compare with the threshold the way `measure` does.
        let exact: f64 = {
            let l = line(&[1.0; 20], dt);
            (1..20).map(|i| step_length(l[i - 1], l[i])).sum::<f64>() / (19.0 * dt)
        };
        assert_eq!(at(1.0), vec![exact >= 1.0]);
        assert_eq!(at(1.01), vec![true]);
        assert_eq!(at(0.99), vec![false]);
        // A threshold set exactly to the chunk's mean speed: moving (inclusive).
        let s = MotionSettings {
            moving_speed: exact,
            ..settings
        };
        assert_eq!(
            measure(&line(&[1.0; 20], dt), &steps, dt, &s, 20, 7).moving,
            vec![true]
        );
    }

    #[test]
    fn moving_comfort_counts_only_moving_chunks() {
        let mut failed = verdict(1);
        failed.failed.lon_jerk = true;
        let verdicts = [verdict(0), failed, verdict(2)];
        let m = MovingComfort::count(&[false, true, true], &verdicts);
        assert_eq!((m.chunks, m.comfortable), (2, 1));
        assert_eq!(m.score(), Some(0.5));
    }
}
