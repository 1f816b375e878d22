//! The batch reference: the SDS counts of a whole route, computed over whole arrays
//! (docs/SCORE.md §4-7, docs/SCORE.md §9, docs/SCORE.md §11).
//!
//! Why it exists: docs/SCORE.md §11 requires the streaming monitor ([`monitor_core::Monitor`], one frame at a
//! time in fixed memory) and a batch computation over whole arrays to agree bit for bit. This
//! module is that second path, written in the plain style of the spec's formulas so that it can
//! be read against the spec line by line; the property test `tests/tests/it/streaming_vs_batch.rs`
//! checks that the two paths agree on random routes, and the replay tool can run both.
//!
//! What it shares with `monitor-core`: only the low-level f32 kernels, which the spec requires
//! to be the same — the Savitzky–Golay filter and its tables ([`sg::filter`], [`sg::VALUE`],
//! [`sg::DERIVATIVE`]), the per-frame kernels ([`signal::excess`], [`signal::unwrap`],
//! [`monitor_core::Profile::comfort_yaw_rate`]) and the score formula
//! [`monitor_core::score::ds_safe`]. Chunking, the bound comparisons, the deceleration window,
//! the lateral bands and the counting are written here again, independently of the monitor's
//! state machine (no `Monitor`, `ChunkBuffer`, `DecelWindow`, `LateralChunk`, `Band::of`).
//!
//! ```
//! use monitor_core::{Collisions, Config, Frame, RecordScores};
//! use monitor_core::score;
//! use monitor_host::reference::batch;
//!
//! let mut frames = vec![Frame { speed: 8.0, lat_err: Some(0.3), ..Frame::default() }; 45];
//! frames[30].collisions = Collisions { vehicle: 1, ..Collisions::NONE };
//! frames[44].lat_err = Some(1.2); // excess 0.38 m: an anomalous trailing chunk
//! let route = batch::compute(&frames, &Config::DEFAULT);
//! assert_eq!(route.summary.comfort.chunks, 2); // frames 40..45 are dropped for comfort
//! assert_eq!(route.summary.lateral.chunks, 3); // ... but not for lateral excess
//! assert_eq!(route.summary.lateral.anomalous, 1);
//! assert_eq!(route.summary.collisions.nodecel, 1);
//! assert_eq!(route.collisions[0].frame, 30);
//!
//! let record = RecordScores { score_route: 100.0, score_penalty: 1.0, workzone: 0 };
//! let safe = score::ds_safe(&route.summary, &record, &Config::DEFAULT.factors);
//! assert!((safe.ds_safe - 100.0 * 0.8 * 0.95).abs() < 1e-9);
//! ```

use std::ops::Range;

use monitor_core::{
    sg, signal, CollisionSummary, ComfortSummary, Config, FailureCounts, Failures, Frame,
    LateralSummary, Profile, RouteSummary,
};

/// Everything the batch reference computes for one route.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchRoute {
    /// The route's counts; equal to the streaming monitor's [`RouteSummary`].
    pub summary: RouteSummary,
    /// One verdict per frame that has collisions, in frame order.
    pub collisions: Vec<BatchCollision>,
    /// One entry per comfort chunk, in chunk order.
    pub comfort: Vec<BatchComfort>,
    /// The comfort counts under the second profile of [`compute_with`], if one was asked for
    /// (the streaming side: [`monitor_core::Monitor::second_comfort`]).
    pub second_comfort: Option<ComfortSummary>,
    /// Per lateral chunk (the trailing partial chunk included), the maximum excess over its
    /// frames of known excess; `None` for an unscored chunk.
    pub lateral: Vec<Option<f32>>,
}

/// The deceleration verdict of one frame with collisions (docs/SCORE.md §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchCollision {
    /// Index of the frame in the route (0-based; in the part, for [`compute_part`]).
    pub frame: usize,
    /// Some frame of the window before it had `a_lon <= decel_threshold`.
    pub decelerated: bool,
    /// The frame is the route's first, or its speed is below `stationary_speed`.
    pub exempt: bool,
}

/// The comfort verdict of one chunk (docs/SCORE.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchComfort {
    /// Frames in the chunk (`chunk_len`, or fewer for a short route).
    pub frames: usize,
    /// The bounds the chunk failed.
    pub failed: Failures,
}

/// The counts of one route, computed over whole arrays (docs/SCORE.md §4-7).
///
/// `frames` are assumed valid ([`Frame::validate`]) and `config` valid ([`Config::validate`]);
/// on other input the counts are unspecified, but nothing panics.
///
/// ```
/// use monitor_core::{Config, Frame};
/// let route = monitor_host::reference::batch::compute(&[Frame::default(); 19], &Config::DEFAULT);
/// assert_eq!(route.summary.comfort.chunks, 1); // a short route: one chunk of 19 frames
/// assert_eq!(route.comfort[0].frames, 19);
/// ```
pub fn compute(frames: &[Frame], config: &Config) -> BatchRoute {
    compute_with(frames, config, None)
}

/// [`compute`], and the comfort counts under a `second` profile too (same chunks, same
/// bounds): for example Bench2Drive's smoothness (`b2d-legacy`, docs/SCORE.md §10.1) beside a `physical` run.
/// The three smoothed accelerations are computed once for both profiles.
///
/// ```
/// use monitor_core::{Config, Frame, Profile};
/// use monitor_host::reference::batch;
///
/// let turning = vec![Frame { speed: 5.0, yaw_rate: 40.0, ..Frame::default() }; 40];
/// let route = batch::compute_with(&turning, &Config::DEFAULT, Some(Profile::B2dLegacy));
/// let legacy = Config { profile: Profile::B2dLegacy, ..Config::DEFAULT };
/// assert_eq!(route.second_comfort, Some(batch::compute(&turning, &legacy).summary.comfort));
/// assert_eq!(route.summary.comfort.comfortable, 2); // 0.70 rad/s
/// assert_eq!(route.second_comfort.unwrap().comfortable, 0); // 40 "rad/s"
/// ```
pub fn compute_with(frames: &[Frame], config: &Config, second: Option<Profile>) -> BatchRoute {
    compute_part(&[], frames, true, config, second)
}

/// [`compute_with`] over part of a route: `frames` start at a chunk boundary of the route,
/// `before` holds the route's frames before them (the last `decel_window` at least), and
/// `starts` says whether `frames` start the route (said, not read from an empty `before`: with
/// `decel_window` 0 every part's `before` is empty). The counts of consecutive parts add up to the whole route's
/// ([`RouteSummary::merge`]): the chunks are the same, a collision's deceleration window reaches
/// into `before`, only the route's first frame is exempt as the first, and a short route's
/// single chunk (docs/SCORE.md §4) is one only when the part starts the route. So a long drive is checked part
/// by part as its frames pass, without holding it.
///
/// ```
/// use monitor_core::{Collisions, Config, Frame, RouteSummary};
/// use monitor_host::reference::batch;
/// let mut frames = vec![Frame { speed: 5.0, ..Frame::default() }; 95];
/// frames[30].a_lon = -5.0; // braking 15 frames before the collision, in the part before it
/// frames[45].collisions = Collisions { vehicle: 1, ..Collisions::NONE };
/// let config = Config::DEFAULT;
/// let whole = batch::compute(&frames, &config).summary;
/// assert_eq!((whole.collisions.aligned, whole.collisions.nodecel), (1, 0));
/// let window = usize::from(config.decel_window);
/// let mut parts = RouteSummary::ZERO;
/// for (a, b) in [(0usize, 40), (40, 80), (80, 95)] {
///     let before = &frames[a.saturating_sub(window)..a];
///     parts.merge(&batch::compute_part(before, &frames[a..b], a == 0, &config, None).summary);
/// }
/// assert_eq!(parts, whole);
/// ```
pub fn compute_part(
    before: &[Frame],
    frames: &[Frame],
    starts: bool,
    config: &Config,
    second: Option<Profile>,
) -> BatchRoute {
    let n = frames.len();
    // A valid config has chunk_len >= 7; never let 0 reach `chunks`.
    let chunk_len = usize::from(config.chunk_len).max(1);
    let min_chunk = usize::from(config.min_chunk);

    // docs/SCORE.md §3: per-frame arrays.
    let a_lon: Vec<f32> = frames.iter().map(|f| f.a_lon).collect();
    let a_lat: Vec<f32> = frames.iter().map(|f| f.a_lat).collect();
    let a_mag: Vec<f32> = frames.iter().map(|f| f.a_mag).collect();
    let omega_deg: Vec<f32> = frames.iter().map(|f| f.yaw_rate).collect();
    let excess: Vec<Option<f32>> = frames
        .iter()
        .map(|f| f.lat_err.map(|e| signal::excess(e, config.slack)))
        .collect();

    // docs/SCORE.md §4-5: comfort over full chunks; a short route (min_chunk <= n < chunk_len) is one chunk;
    // a chunk shorter than the filter window has no verdict.
    let mut spans: Vec<Range<usize>> = if n >= chunk_len || !starts {
        (0..n / chunk_len)
            .map(|k| k * chunk_len..(k + 1) * chunk_len)
            .collect()
    } else if n >= min_chunk {
        std::iter::once(0..n).collect()
    } else {
        Vec::new()
    };
    spans.retain(|r| r.len() >= sg::WINDOW);
    let smoothed = Smoothed {
        lon: per_chunk(&a_lon, &spans, smooth),
        lat: per_chunk(&a_lat, &spans, smooth),
        mag: per_chunk(&a_mag, &spans, smooth),
    };
    let comfort = comfort_chunks(&smoothed, &omega_deg, &spans, config.profile, config);
    let second_comfort = second.map(|profile| {
        comfort_summary(&comfort_chunks(
            &smoothed, &omega_deg, &spans, profile, config,
        ))
    });

    // docs/SCORE.md §7: lateral excess over every chunk, the trailing partial one included.
    let lateral: Vec<Option<f32>> = excess
        .chunks(chunk_len)
        .map(|c| c.iter().flatten().copied().reduce(f32::max))
        .collect();

    // docs/SCORE.md §6: pre-collision deceleration.
    let window = usize::from(config.decel_window);
    let mut collisions = Vec::new();
    let mut counts = CollisionSummary::default();
    for (k, f) in frames.iter().enumerate() {
        let hits = f.collisions.total();
        if hits == 0 {
            continue;
        }
        // The window's frames before this part are the last of `before`.
        let earlier = &before[before.len() - window.saturating_sub(k).min(before.len())..];
        let decelerated = earlier
            .iter()
            .chain(&frames[k.saturating_sub(window)..k])
            .any(|p| p.a_lon <= config.decel_threshold);
        let exempt = (k == 0 && starts) || f.speed < config.stationary_speed;
        counts.aligned = counts.aligned.saturating_add(hits);
        if exempt {
            counts.exempt = counts.exempt.saturating_add(hits);
        } else if !decelerated {
            counts.nodecel = counts.nodecel.saturating_add(hits);
        }
        collisions.push(BatchCollision {
            frame: k,
            decelerated,
            exempt,
        });
    }

    let summary = RouteSummary {
        frames: count(n),
        comfort: comfort_summary(&comfort),
        lateral: lateral_summary(&lateral, config),
        collisions: counts,
    };
    BatchRoute {
        summary,
        collisions,
        comfort,
        second_comfort,
        lateral,
    }
}

fn count(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// `op` applied to each span of `x` on its own (the chunks of §3), into one array of `x`'s
/// length; zero outside the spans.
fn per_chunk(x: &[f32], spans: &[Range<usize>], op: impl Fn(&[f32], &mut [f32])) -> Vec<f32> {
    let mut out = vec![0.0f32; x.len()];
    for r in spans {
        if let (Some(x), Some(o)) = (x.get(r.clone()), out.get_mut(r.clone())) {
            op(x, o);
        }
    }
    out
}

/// `SG(x)`: the smoothed values (`x` holds at least the filter window).
fn smooth(x: &[f32], out: &mut [f32]) {
    sg::filter(x, &sg::VALUE, None, out);
}

/// `SG'(x, h)`: the first derivative over sample spacing `h`.
fn derivative(h: f32) -> impl Fn(&[f32], &mut [f32]) {
    move |x, out| {
        sg::filter(x, &sg::DERIVATIVE, Some(h), out);
    }
}

/// The values of `x` in the span `r`.
fn at<'a>(x: &'a [f32], r: &Range<usize>) -> &'a [f32] {
    x.get(r.clone()).unwrap_or_default()
}

/// Every value strictly inside `(lo, hi)`; NaN is never inside.
fn within(values: &[f32], lo: f32, hi: f32) -> bool {
    values.iter().all(|&v| lo < v && v < hi)
}

/// `lon = SG(a_lon)`, `lat = SG(a_lat)`, `mag = SG(a_mag)`, chunk by chunk: the same under
/// every profile (docs/SCORE.md §5).
struct Smoothed {
    lon: Vec<f32>,
    lat: Vec<f32>,
    mag: Vec<f32>,
}

/// The comfort verdict of every chunk under `profile` (docs/SCORE.md §5).
fn comfort_chunks(
    s: &Smoothed,
    omega_deg: &[f32],
    spans: &[Range<usize>],
    profile: Profile,
    config: &Config,
) -> Vec<BatchComfort> {
    let b = &config.bounds;
    let (lon_jerk, mag_jerk, yaw_rate, yaw_acc) = match profile {
        Profile::Physical | Profile::Autoware => {
            let omega: Vec<f32> = omega_deg
                .iter()
                .map(|&w| profile.comfort_yaw_rate(w))
                .collect();
            let yaw_rate = per_chunk(&omega, spans, smooth);
            let yaw_acc = per_chunk(&yaw_rate, spans, derivative(config.dt));
            (
                per_chunk(&s.lon, spans, derivative(config.dt)),
                per_chunk(&s.mag, spans, derivative(config.dt)),
                yaw_rate,
                yaw_acc,
            )
        }
        Profile::B2dLegacy => {
            let u = per_chunk(omega_deg, spans, signal::unwrap);
            let yaw_rate = per_chunk(&u, spans, smooth);
            let yaw_acc = yaw_rate.clone(); // Bench2Drive's bug: no derivative
            let h = config.legacy_jerk_spacing;
            (
                per_chunk(&s.lon, spans, derivative(h)),
                per_chunk(&s.mag, spans, derivative(h)),
                yaw_rate,
                yaw_acc,
            )
        }
    };
    spans
        .iter()
        .map(|r| BatchComfort {
            frames: r.len(),
            failed: Failures {
                lon_acc: !within(at(&s.lon, r), b.lon_acc_min, b.lon_acc_max),
                lat_acc: !within(at(&s.lat, r), -b.lat_acc, b.lat_acc),
                mag_jerk: !within(at(&mag_jerk, r), -b.mag_jerk, b.mag_jerk),
                lon_jerk: !within(at(&lon_jerk, r), -b.lon_jerk, b.lon_jerk),
                yaw_acc: !within(at(&yaw_acc, r), -b.yaw_acc, b.yaw_acc),
                yaw_rate: !within(at(&yaw_rate, r), -b.yaw_rate, b.yaw_rate),
            },
        })
        .collect()
}

fn comfort_summary(chunks: &[BatchComfort]) -> ComfortSummary {
    let tally =
        |pick: fn(&Failures) -> bool| count(chunks.iter().filter(|c| pick(&c.failed)).count());
    ComfortSummary {
        chunks: count(chunks.len()),
        comfortable: count(
            chunks
                .iter()
                .filter(|c| {
                    let f = &c.failed;
                    !(f.lon_acc || f.lat_acc || f.mag_jerk || f.lon_jerk || f.yaw_acc || f.yaw_rate)
                })
                .count(),
        ),
        failed: FailureCounts {
            lon_acc: tally(|f| f.lon_acc),
            lat_acc: tally(|f| f.lat_acc),
            mag_jerk: tally(|f| f.mag_jerk),
            lon_jerk: tally(|f| f.lon_jerk),
            yaw_acc: tally(|f| f.yaw_acc),
            yaw_rate: tally(|f| f.yaw_rate),
        },
    }
}

fn lateral_summary(maxima: &[Option<f32>], config: &Config) -> LateralSummary {
    let (anom, crit) = (config.anomalous_excess, config.critical_excess);
    let scored: Vec<f32> = maxima.iter().flatten().copied().collect();
    LateralSummary {
        chunks: count(maxima.len()),
        scored_chunks: count(scored.len()),
        anomalous: count(scored.iter().filter(|&&m| anom < m && m <= crit).count()),
        critical: count(scored.iter().filter(|&&m| m > crit).count()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use monitor_core::{score, Collisions, Factors, RecordScores};

    /// With `decel_window` 0 every part's `before` is empty; a later part must still not count
    /// as the route's start (its first frame exempt, a short remainder a route's one chunk).
    #[test]
    fn parts_add_up_with_no_decel_window() {
        let config = Config {
            decel_window: 0,
            ..Config::DEFAULT
        };
        let mut frames = vec![
            Frame {
                speed: 5.0,
                ..Frame::default()
            };
            95
        ];
        frames[40].a_lon = -9.0;
        let whole = compute(&frames, &config).summary;
        let mut parts = RouteSummary::ZERO;
        for (a, b) in [(0usize, 40), (40, 80), (80, 95)] {
            parts.merge(&compute_part(&[], &frames[a..b], a == 0, &config, None).summary);
        }
        assert_eq!(parts, whole);
    }

    fn cruise(n: usize) -> Vec<Frame> {
        vec![
            Frame {
                a_lon: 0.1,
                speed: 8.0,
                lat_err: Some(0.2),
                ..Frame::default()
            };
            n
        ]
    }

    fn hit(mut f: Frame, vehicle: u16, layout: u16) -> Frame {
        f.collisions = Collisions {
            vehicle,
            layout,
            ..Collisions::NONE
        };
        f
    }

    #[test]
    fn chunk_counts_by_route_length() {
        // (frames, comfort chunks, lateral chunks, frames of the first comfort chunk)
        let cases = [
            (0, 0, 0, None),
            (6, 0, 1, None),
            (7, 1, 1, Some(7)),
            (19, 1, 1, Some(19)),
            (20, 1, 1, Some(20)),
            (21, 1, 2, Some(20)),
            (39, 1, 2, Some(20)),
            (41, 2, 3, Some(20)),
        ];
        for (n, comfort, lateral, first) in cases {
            let r = compute(&cruise(n), &Config::DEFAULT);
            assert_eq!(r.summary.frames, n as u32, "n={n}");
            assert_eq!(r.summary.comfort.chunks, comfort, "n={n}");
            assert_eq!(r.summary.comfort.comfortable, comfort, "n={n}");
            assert_eq!(r.summary.lateral.chunks, lateral, "n={n}");
            assert_eq!(r.summary.lateral.scored_chunks, lateral, "n={n}");
            assert_eq!(r.comfort.first().map(|c| c.frames), first, "n={n}");
        }
    }

    #[test]
    fn min_chunk_decides_short_routes() {
        let config = Config {
            min_chunk: 10,
            ..Config::DEFAULT
        };
        assert_eq!(compute(&cruise(9), &config).summary.comfort.chunks, 0);
        assert_eq!(compute(&cruise(10), &config).summary.comfort.chunks, 1);
        let short = Config {
            chunk_len: 8,
            min_chunk: 8,
            ..Config::DEFAULT
        };
        // 17 frames of 8: two comfort chunks, three lateral chunks.
        let r = compute(&cruise(17), &short);
        assert_eq!(r.summary.comfort.chunks, 2);
        assert_eq!(r.summary.lateral.chunks, 3);
    }

    #[test]
    fn bound_violations_per_signal() {
        let with = |f: &dyn Fn(usize, &mut Frame)| {
            let mut frames = cruise(20);
            for (i, fr) in frames.iter_mut().enumerate() {
                f(i, fr);
            }
            compute(&frames, &Config::DEFAULT).summary.comfort
        };
        // A constant 2.5 m/s² is above 2.40; 2.3 is inside.
        let c = with(&|_, f| f.a_lon = 2.5);
        assert_eq!(
            (c.comfortable, c.failed.lon_acc, c.failed.lon_jerk),
            (0, 1, 0)
        );
        assert_eq!(with(&|_, f| f.a_lon = 2.3).comfortable, 1);
        // |lat| 4.9 > 4.89.
        let c = with(&|_, f| f.a_lat = -4.9);
        assert_eq!((c.comfortable, c.failed.lat_acc), (0, 1));
        // A ramp of 4.5 m/s³ (0.225 m/s² per 0.05 s) from -2.1 to 2.175: only the jerk fails.
        let c = with(&|i, f| f.a_lon = -2.1 + 0.225 * i as f32);
        assert_eq!(
            c.failed,
            FailureCounts {
                lon_jerk: 1,
                ..Default::default()
            }
        );
        // |a| rising 9 m/s³: only the jerk magnitude fails (a_mag itself is unbounded).
        let c = with(&|i, f| f.a_mag = 0.45 * i as f32);
        assert_eq!(
            c.failed,
            FailureCounts {
                mag_jerk: 1,
                ..Default::default()
            }
        );
        // 60 deg/s = 1.047 rad/s > 0.95; 50 deg/s = 0.873 rad/s is inside.
        let c = with(&|_, f| f.yaw_rate = 60.0);
        assert_eq!(
            c.failed,
            FailureCounts {
                yaw_rate: 1,
                ..Default::default()
            }
        );
        assert_eq!(with(&|_, f| f.yaw_rate = 50.0).comfortable, 1);
        // Yaw rate rising 2.5 rad/s² from -0.9 rad/s: 0.125 rad/s per frame, ends at 1.475.
        let c = with(&|i, f| f.yaw_rate = (-0.9 + 0.125 * i as f32) / signal::DEG_TO_RAD);
        assert_eq!((c.failed.yaw_acc, c.failed.yaw_rate), (1, 1));
        // A NaN from overflowing the filter fails the bound.
        let c = with(&|i, f| f.a_lat = if i % 2 == 0 { f32::MAX } else { -f32::MAX });
        assert_eq!(c.failed.lat_acc, 1);
    }

    #[test]
    fn legacy_profile_unwraps_yaw_per_chunk() {
        let legacy = Config {
            profile: Profile::B2dLegacy,
            ..Config::DEFAULT
        };
        // 0 and 6.5 deg/s alternating: every step jumps by about 2π, so the unwrapped signal is
        // 0, 6.5 - 2π = 0.217, 0, ... and stays within both yaw bounds.
        let mut frames = cruise(20);
        for (i, f) in frames.iter_mut().enumerate() {
            f.yaw_rate = if i % 2 == 0 { 0.0 } else { 6.5 };
        }
        let c = compute(&frames, &legacy).summary.comfort;
        assert_eq!(c.comfortable, 1);
        // The unwrap restarts in every chunk: 6.5 deg/s from frame 19 on unwraps to 0.217 in
        // chunk 0, but chunk 1 starts at 6.5 and stays there, failing both yaw bounds.
        let mut steps = cruise(40);
        for f in steps[19..].iter_mut() {
            f.yaw_rate = 6.5;
        }
        let r = compute(&steps, &legacy);
        assert_eq!(r.comfort[0].failed, Failures::default());
        assert!(r.comfort[1].failed.yaw_rate && r.comfort[1].failed.yaw_acc);
        // 0 and 3 deg/s alternating does not unwrap (3 / 2π rounds to 0): the smoothed values,
        // 1.14 and 1.86 in the centre, fail the 0.95 yaw-rate bound (deg/s compared as rad/s).
        for (i, f) in frames.iter_mut().enumerate() {
            f.yaw_rate = if i % 2 == 0 { 0.0 } else { 3.0 };
        }
        let c = compute(&frames, &legacy).summary.comfort;
        assert_eq!((c.comfortable, c.failed.yaw_rate), (0, 1));
        // A constant 1.0 deg/s: inside 1.93 (yaw_acc = SG(u)) but outside 0.95.
        for f in frames.iter_mut() {
            f.yaw_rate = 1.0;
        }
        let c = compute(&frames, &legacy).summary.comfort;
        assert_eq!(
            c.failed,
            FailureCounts {
                yaw_rate: 1,
                ..Default::default()
            }
        );
        // ... and 2.0 deg/s fails both.
        for f in frames.iter_mut() {
            f.yaw_rate = 2.0;
        }
        let c = compute(&frames, &legacy).summary.comfort;
        assert_eq!((c.failed.yaw_rate, c.failed.yaw_acc), (1, 1));
    }

    #[test]
    fn legacy_jerks_use_the_legacy_spacing() {
        // A 4.5 m/s³ ramp at 20 Hz is read as 2.25 m/s³ with 0.1 s spacing: comfortable.
        let mut frames = cruise(20);
        for (i, f) in frames.iter_mut().enumerate() {
            f.a_lon = -2.1 + 0.225 * i as f32;
        }
        let legacy = Config {
            profile: Profile::B2dLegacy,
            ..Config::DEFAULT
        };
        assert_eq!(compute(&frames, &legacy).summary.comfort.comfortable, 1);
    }

    #[test]
    fn collision_at_frame_zero_is_exempt() {
        let mut frames = cruise(5);
        frames[0] = hit(frames[0], 2, 1);
        let r = compute(&frames, &Config::DEFAULT);
        let c = r.summary.collisions;
        assert_eq!((c.aligned, c.exempt, c.nodecel), (3, 3, 0));
        assert_eq!(
            r.collisions,
            vec![BatchCollision {
                frame: 0,
                decelerated: false,
                exempt: true
            }]
        );
    }

    #[test]
    fn deceleration_window_is_the_frames_before() {
        let mut frames = cruise(60);
        frames[10].a_lon = -0.5; // exactly the threshold: counts
        frames[30] = hit(frames[30], 1, 0); // k-20 = 10: decelerated
        frames[31] = hit(frames[31], 1, 0); // window 11..31: not
        frames[32] = hit(frames[32], 0, 2); // window 12..32, frame 31 was no brake either
        frames[50].a_lon = -3.0; // the impact itself is not in its own window ...
        frames[50] = hit(frames[50], 1, 0);
        frames[51] = hit(frames[51], 1, 0); // ... but counts for the next one
        frames[51].speed = 0.49; // standing: exempt whatever the window
        let r = compute(&frames, &Config::DEFAULT);
        let v: Vec<(usize, bool, bool)> = r
            .collisions
            .iter()
            .map(|c| (c.frame, c.decelerated, c.exempt))
            .collect();
        assert_eq!(
            v,
            vec![
                (30, true, false),
                (31, false, false),
                (32, false, false),
                (50, false, false),
                (51, true, true)
            ]
        );
        let c = r.summary.collisions;
        assert_eq!((c.aligned, c.exempt, c.nodecel), (6, 1, 4));
        // A zero window never sees deceleration.
        let none = Config {
            decel_window: 0,
            ..Config::DEFAULT
        };
        assert_eq!(compute(&frames, &none).summary.collisions.nodecel, 5);
    }

    #[test]
    fn lateral_bands_are_exclusive() {
        // Excess 0.25 (normal), just above (anomalous), 0.65 (anomalous), above (critical),
        // unknown only (unscored), one chunk each.
        let slack = 0.82f32;
        let mut frames = cruise(100);
        for f in frames[80..].iter_mut() {
            f.lat_err = None;
        }
        let config = Config {
            slack,
            ..Config::DEFAULT
        };
        let mut set =
            |chunk: usize, excess: f32| frames[chunk * 20 + 7].lat_err = Some(slack + excess);
        set(0, 0.1);
        set(1, 0.5);
        set(2, 0.6);
        set(3, 2.0);
        let r = compute(&frames, &config);
        let l = r.summary.lateral;
        assert_eq!(
            (l.chunks, l.scored_chunks, l.anomalous, l.critical),
            (5, 4, 2, 1)
        );
        assert_eq!(r.lateral[3], Some(signal::excess(slack + 2.0, slack)));
        assert_eq!(r.lateral[4], None);
        // On the band edges. With slack 0 the excess is |lat_err| itself: 0.25 is normal, 0.65
        // anomalous, the next f32 above 0.65 critical.
        let mut edge = cruise(60);
        edge[0].lat_err = Some(-0.25);
        edge[20].lat_err = Some(0.65);
        edge[40].lat_err = Some(f32::from_bits(0.65f32.to_bits() + 1));
        let zero = Config {
            slack: 0.0,
            ..Config::DEFAULT
        };
        let l = compute(&edge, &zero).summary.lateral;
        assert_eq!((l.anomalous, l.critical), (1, 1));
        // With the default slack, the f32 sums 0.82 + 0.25 and 0.82 + 0.65 round to excesses
        // 0.24999994 (normal) and 0.65000004 (critical).
        let mut edge = cruise(40);
        edge[0].lat_err = Some(-(0.82f32 + 0.25));
        edge[20].lat_err = Some(0.82f32 + 0.65);
        let r = compute(&edge, &Config::DEFAULT);
        assert_eq!(r.lateral[0], Some(0.249_999_94));
        assert_eq!(r.lateral[1], Some(0.650_000_04));
        let l = r.summary.lateral;
        assert_eq!((l.anomalous, l.critical), (0, 1));
    }

    #[test]
    fn ds_safe_follows_the_formula() {
        let mut s = RouteSummary::default();
        s.collisions.nodecel = 2;
        s.lateral.anomalous = 1;
        s.lateral.critical = 1;
        let r = RecordScores {
            score_route: 80.0,
            score_penalty: 0.65,
            workzone: 1,
        };
        let safe = score::ds_safe(&s, &r, &Factors::DEFAULT);
        assert!((safe.p_safe - 0.5).abs() < 1e-12);
        assert!((safe.ds_safe - 80.0 * 0.5 * 0.64 * 0.95 * 0.9).abs() < 1e-9);
        let zero = score::ds_safe(&RouteSummary::default(), &r, &Factors::DEFAULT);
        assert_eq!(zero.ds_safe, 80.0 * zero.p_safe);
    }
}
