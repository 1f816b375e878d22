//! Spec §9: the streaming monitor and the batch reference agree bit for bit.
//!
//! Random routes (0..200 frames, smooth driving-like signals, wild and extreme values, unknown
//! lateral errors, collisions anywhere, both profiles, varied chunking and deceleration windows)
//! go through `Monitor::push`/`finish` and through `monitor_host::reference::batch::compute`; every count,
//! every event and every score must be identical (floats compared with `to_bits`).
//!
//! Cases: `PROPTEST_CASES` if set, else 10,000 for the main property (2,000 for the others).
//! Run: `cargo test -p sds-tests --release --test it streaming_vs_batch::`.

use monitor_core::{
    score, Band, Bounds, Collisions, Config, Factors, Frame, Monitor, MonitorError, Profile,
    RecordScores,
};
use monitor_host::reference::batch::{self, BatchRoute};
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::select;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config as ProptestConfig, TestCaseError, TestRunner};
use sds_tests::{stream, Streamed, SPECIAL_VALUES};

/// Frames per generated route: 0..MAX_FRAMES.
const MAX_FRAMES: usize = 200;

fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn proptest_config(default_cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases: cases(default_cases),
        ..ProptestConfig::default()
    }
}

// ---------------------------------------------------------------------------------------------
// Strategies

/// Any finite f32 (normal, subnormal, zero, either sign).
fn finite() -> impl Strategy<Value = f32> {
    use proptest::num::f32::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
}

/// A single value of a wild signal: ordinary, special, or any finite value.
fn wild_value() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => -8.0f32..8.0,
        3 => select(SPECIAL_VALUES),
        1 => finite(),
    ]
}

/// A driving-like signal: `base + slope * i + noise_i`, with slopes that put the filtered
/// derivatives on both sides of the jerk and yaw-acceleration bounds.
fn smooth(n: usize, base: (f32, f32), slope: f32, noise: f32) -> impl Strategy<Value = Vec<f32>> {
    (
        base.0..base.1,
        -slope..slope,
        vec(-noise..noise, n),
        select(vec![0.0f32, 0.0, noise]),
    )
        .prop_map(|(b, s, noise, keep)| {
            noise
                .iter()
                .enumerate()
                .map(|(i, e)| b + s * i as f32 + if keep > 0.0 { *e } else { 0.0 })
                .collect()
        })
}

/// One signal of `n` frames: smooth, or wild, or a constant special value.
fn signal(n: usize, base: (f32, f32), slope: f32, noise: f32) -> impl Strategy<Value = Vec<f32>> {
    prop_oneof![
        5 => smooth(n, base, slope, noise),
        2 => vec(wild_value(), n),
        1 => select(SPECIAL_VALUES).prop_map(move |v| vec![v; n]),
    ]
}

/// Yaw rate in deg/s: physical-scale, legacy-scale (near the deg/s-as-rad/s bounds), or with
/// jumps of about a turn that the legacy unwrap folds back.
fn yaw(n: usize) -> impl Strategy<Value = Vec<f32>> {
    prop_oneof![
        3 => signal(n, (-70.0, 70.0), 8.0, 2.0),
        2 => signal(n, (-1.5, 1.5), 0.15, 0.05),
        1 => (vec(select(vec![0.0f32, 6.283_185_5, -6.283_185_5, 6.5, 12.566_371]), n),
              -0.5f32..0.5)
            .prop_map(|(jumps, b)| jumps.into_iter().map(|j| b + j).collect()),
    ]
}

fn speed() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => 0.0f32..20.0,
        2 => 0.45f32..0.55,
        2 => select(vec![0.0f32, -0.0, 1e-45, 0.5, 0.5f32.next_down(), 0.5f32.next_up(), f32::MAX]),
    ]
}

/// A known lateral error: ordinary, on the band edges (as f32 sums and exact), or extreme.
fn known_lat_err() -> impl Strategy<Value = f32> {
    // slack + band edge as f32 sums and their neighbours, for the slacks of
    // `lateral_thresholds` (0.82, 0 and 1).
    let mut edges = vec![0.82f32, 0.0, -0.0, 1e-45, f32::MAX, -f32::MAX];
    for slack in [0.82f32, 0.0, 1.0] {
        for band in [0.25f32, 0.65] {
            let x = slack + band;
            edges.extend([x, -x, x.next_up(), x.next_down()]);
        }
    }
    prop_oneof![
        5 => -2.0f32..2.0,
        2 => select(edges),
        1 => finite(),
    ]
}

/// Lateral errors of a route: all known, all unknown, or mixed (runs of unknown included).
fn lat_errs(n: usize) -> impl Strategy<Value = Vec<Option<f32>>> {
    prop_oneof![
        2 => vec(known_lat_err().prop_map(Some), n),
        1 => Just(vec![None; n]),
        3 => vec(prop::option::weighted(0.6, known_lat_err()), n),
        1 => (vec(known_lat_err(), n), 0..=n, 0..=n).prop_map(|(v, a, b)| {
            let (a, b) = (a.min(b), a.max(b));
            v.into_iter()
                .enumerate()
                .map(|(i, x)| if (a..b).contains(&i) { None } else { Some(x) })
                .collect()
        }),
    ]
}

fn collisions() -> impl Strategy<Value = Collisions> {
    let kinds = |max: u16| {
        (0..=max, 0..=max, 0..=max, 0..=max).prop_map(|(p, v, l, w)| Collisions {
            pedestrian: p,
            vehicle: v,
            layout: l,
            workzone: w,
        })
    };
    prop_oneof![
        14 => Just(Collisions::NONE),
        4 => kinds(3),
        1 => kinds(u16::MAX),
    ]
}

/// Values substituted at a few random places of a route: (frame, field, value).
fn overrides() -> impl Strategy<Value = Vec<(usize, u8, f32)>> {
    vec((0..MAX_FRAMES, 0u8..5, wild_value()), 0..4)
}

/// A valid route of `0..MAX_FRAMES` frames.
fn route() -> impl Strategy<Value = Vec<Frame>> {
    (0..MAX_FRAMES)
        .prop_flat_map(|n| {
            (
                signal(n, (-4.5, 3.0), 0.3, 0.05),
                signal(n, (-5.5, 5.5), 0.3, 0.05),
                signal(n, (0.0, 6.0), 0.5, 0.05),
                yaw(n),
                vec(speed(), n),
                lat_errs(n),
                vec(collisions(), n),
                overrides(),
            )
        })
        .prop_map(|(a_lon, a_lat, a_mag, yaw, speed, lat, hits, over)| {
            let mut frames: Vec<Frame> = (0..a_lon.len())
                .map(|i| Frame {
                    a_lon: a_lon[i],
                    a_lat: a_lat[i],
                    a_mag: a_mag[i],
                    yaw_rate: yaw[i],
                    speed: speed[i],
                    lat_err: lat[i],
                    collisions: hits[i],
                })
                .collect();
            for (i, field, v) in over {
                if let Some(f) = frames.get_mut(i) {
                    match field {
                        0 => f.a_lon = v,
                        1 => f.a_lat = v,
                        2 => f.a_mag = v,
                        3 => f.yaw_rate = v,
                        _ => f.speed = v,
                    }
                }
            }
            // The monitor takes only valid frames: a_mag and speed are not negative.
            // (-0.0 stays: it is not below 0.)
            for f in &mut frames {
                f.a_mag = make_non_negative(f.a_mag);
                f.speed = make_non_negative(f.speed);
                // Smooth signals of extreme bases can overflow: keep frames finite.
                for v in [&mut f.a_lon, &mut f.a_lat, &mut f.a_mag, &mut f.yaw_rate] {
                    if !v.is_finite() {
                        *v = f32::MAX.copysign(*v);
                    }
                }
            }
            frames
        })
}

fn make_non_negative(v: f32) -> f32 {
    if v < 0.0 {
        -v
    } else {
        v
    }
}

/// Lateral thresholds (slack, anomalous, critical): mostly the defaults; slack 0 and 1 make the
/// band edges reachable exactly (with 0.82 no f32 lateral error has an excess of exactly 0.25 or
/// 0.65); equal thresholds leave no anomalous band.
fn lateral_thresholds() -> impl Strategy<Value = (f32, f32, f32)> {
    prop_oneof![
        4 => Just((0.82f32, 0.25f32, 0.65f32)),
        2 => Just((0.0, 0.25, 0.65)),
        1 => Just((1.0, 0.25, 0.65)),
        1 => Just((0.0, 0.25, 0.25)),
        1 => Just((0.0, 0.0, 0.65)),
    ]
}

fn config() -> impl Strategy<Value = Config> {
    (
        prop_oneof![Just(Profile::Physical), Just(Profile::B2dLegacy)],
        7u16..=20,
        0u16..=20,
        any::<bool>(),
        lateral_thresholds(),
        prop_oneof![4 => Just(0.5f32), 1 => Just(0.0), 1 => Just(5.0)],
        prop_oneof![4 => Just(-0.5f32), 1 => Just(0.0), 1 => Just(-4.05)],
        // Both step periods met in real telemetry (docs/SCORE.md §2.2): 20 Hz and 10 Hz.
        prop_oneof![Just(0.05f32), Just(0.1f32)],
    )
        .prop_flat_map(
            |(profile, chunk_len, decel_window, default, lateral, standing, decel, dt)| {
                (7u16..=chunk_len).prop_map(move |min_chunk| {
                    let base = Config {
                        profile,
                        dt,
                        ..Config::DEFAULT
                    };
                    if default {
                        return base;
                    }
                    let (slack, anomalous_excess, critical_excess) = lateral;
                    Config {
                        chunk_len,
                        min_chunk,
                        decel_window,
                        slack,
                        anomalous_excess,
                        critical_excess,
                        stationary_speed: standing,
                        decel_threshold: decel,
                        ..base
                    }
                })
            },
        )
}

fn record() -> impl Strategy<Value = RecordScores> {
    let score_route = prop_oneof![
        4 => 0.0f64..=100.0,
        1 => select(vec![0.0f64, 100.0, 1e-300, 5e-324, 33.333_333_333_333_336]),
    ];
    (
        score_route,
        0.0f64..=1.0,
        prop_oneof![3 => 0u32..4, 1 => 0u32..2000],
    )
        .prop_map(|(score_route, score_penalty, workzone)| RecordScores {
            score_route,
            score_penalty,
            workzone,
        })
}

fn factors() -> impl Strategy<Value = Factors> {
    let factor = || prop_oneof![2 => 0.0f64..=1.0, 1 => select(vec![0.0f64, 1.0, 0.5, 0.95])];
    prop_oneof![
        Just(Factors::DEFAULT),
        (factor(), 1e-6f64..=1.0, factor(), factor(), factor()).prop_map(
            |(workzone, layout, nodecel, anomalous, critical)| Factors {
                workzone,
                layout,
                nodecel,
                anomalous,
                critical,
            }
        ),
    ]
}

// ---------------------------------------------------------------------------------------------
// Comparison

/// The lateral events the spec predicts from batch's chunk maxima (docs/SCORE.md §7, exclusive bands).
fn expected_lateral(b: &BatchRoute, config: &Config) -> Vec<(u32, u32, Band)> {
    b.lateral
        .iter()
        .enumerate()
        .filter_map(|(i, m)| {
            let m = (*m)?;
            let band = if m > config.critical_excess {
                Band::Critical
            } else if config.anomalous_excess < m {
                Band::Anomalous
            } else {
                return None;
            };
            Some((i as u32, m.to_bits(), band))
        })
        .collect()
}

/// Streaming result `s` of `frames` against the batch reference.
fn compare(s: &Streamed, frames: &[Frame], config: &Config) -> Result<(), TestCaseError> {
    let b = batch::compute(frames, config);
    prop_assert_eq!(
        s.summary,
        b.summary,
        "RouteSummary: streaming (left) vs batch (right)"
    );

    prop_assert_eq!(s.collisions.len(), b.collisions.len(), "collision verdicts");
    for (v, c) in s.collisions.iter().zip(&b.collisions) {
        prop_assert_eq!(v.frame as usize, c.frame, "collision frame");
        prop_assert_eq!(
            v.decelerated,
            c.decelerated,
            "decelerated at frame {}",
            c.frame
        );
        prop_assert_eq!(v.exempt, c.exempt, "exempt at frame {}", c.frame);
        let f = &frames[c.frame];
        prop_assert_eq!(
            v.collisions,
            f.collisions,
            "collisions at frame {}",
            c.frame
        );
        prop_assert_eq!(
            v.speed.to_bits(),
            f.speed.to_bits(),
            "speed at frame {}",
            c.frame
        );
    }

    prop_assert_eq!(s.comfort.len(), b.comfort.len(), "comfort verdicts");
    for (i, (v, c)) in s.comfort.iter().zip(&b.comfort).enumerate() {
        prop_assert_eq!(v.chunk as usize, i, "comfort chunk index");
        prop_assert_eq!(
            usize::from(v.frames),
            c.frames,
            "frames of comfort chunk {}",
            i
        );
        prop_assert_eq!(v.failed, c.failed, "failures of comfort chunk {}", i);
    }

    let got: Vec<(u32, u32, Band)> = s
        .lateral
        .iter()
        .map(|v| (v.chunk, v.max_excess.to_bits(), v.band))
        .collect();
    prop_assert_eq!(
        got,
        expected_lateral(&b, config),
        "lateral events (chunk, max bits, band)"
    );
    Ok(())
}

fn check_scores(
    s: &Streamed,
    frames: &[Frame],
    config: &Config,
    record: &RecordScores,
    factors: &Factors,
) -> Result<(), TestCaseError> {
    let b = batch::compute(frames, config);
    for f in [factors, &config.factors] {
        let a = score::ds_safe(&s.summary, record, f);
        // The reference scores its own summary with the one score formula (docs/SCORE.md §11).
        let c = score::ds_safe(&b.summary, record, f);
        prop_assert_eq!(
            a.p_safe.to_bits(),
            c.p_safe.to_bits(),
            "p_safe {} vs {}",
            a.p_safe,
            c.p_safe
        );
        prop_assert_eq!(
            a.ds_safe.to_bits(),
            c.ds_safe.to_bits(),
            "ds_safe {} vs {}",
            a.ds_safe,
            c.ds_safe
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Properties

proptest! {
    #![proptest_config(proptest_config(10_000))]

    /// docs/SCORE.md §11: every count, event and score of the streaming monitor equals the batch reference's.
    #[test]
    fn streaming_equals_batch(
        frames in route(),
        config in config(),
        record in record(),
        factors in factors(),
    ) {
        for f in &frames {
            prop_assert!(f.validate().is_ok(), "generator made an invalid frame {:?}", f);
        }
        let s = stream(&frames, &config)
            .map_err(|e| TestCaseError::fail(format!("monitor refused a valid route: {e:?}")))?;
        compare(&s, &frames, &config)?;
        check_scores(&s, &frames, &config, &record, &factors)?;
    }
}

proptest! {
    #![proptest_config(proptest_config(2_000))]

    /// A second comfort profile (how the replay counts Bench2Drive's smoothness beside the run's
    /// comfort) shares the smoothing with the first, and counts exactly what a monitor of that
    /// profile alone counts; the first profile's counts and events do not change. The batch
    /// reference's second profile agrees too.
    #[test]
    fn a_second_profile_counts_what_its_own_monitor_counts(
        frames in route(),
        config in config(),
        second in select(Profile::ALL.to_vec()),
    ) {
        // Autoware's profile with the physical default bounds is refused (Config::validate):
        // then both monitors judge against Autoware's own bounds.
        let config = if second == Profile::Autoware && config.bounds == Bounds::DEFAULT {
            Config { bounds: Bounds::of(second), ..config }
        } else {
            config
        };
        let alone_config = Config { profile: second, ..config };
        let alone = stream(&frames, &alone_config)
            .map_err(|e| TestCaseError::fail(format!("monitor refused a valid route: {e:?}")))?;
        let first = stream(&frames, &config)
            .map_err(|e| TestCaseError::fail(format!("monitor refused a valid route: {e:?}")))?;

        let mut both: Monitor = Monitor::new(config)
            .map_err(|e| TestCaseError::fail(format!("{e:?}")))?
            .with_second_profile(second);
        let mut events = sds_tests::Streamed::default();
        for f in &frames {
            let e = both.push(f).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
            e.iter().for_each(|e| events.record(e));
        }
        let done = both.finish().map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        done.events.iter().for_each(|e| events.record(e));
        events.summary = done.summary;
        prop_assert_eq!(&events, &first, "the second profile changed the first's output");
        prop_assert_eq!(both.second_comfort(), Some(&alone.summary.comfort));

        let b = batch::compute_with(&frames, &config, Some(second));
        prop_assert_eq!(b.summary, batch::compute(&frames, &config).summary);
        prop_assert_eq!(b.second_comfort, Some(alone.summary.comfort));
        prop_assert_eq!(batch::compute(&frames, &alone_config).summary, alone.summary);
    }
}

/// An invalid frame: a valid one with one field made NaN, infinite, or negative where it must
/// not be.
fn invalid_frame() -> impl Strategy<Value = Frame> {
    let bad = select(vec![f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY]);
    let negative = select(vec![-1e-45f32, -1.0e-40, -1.0, -0.5, -f32::MAX]);
    (
        (
            wild_value(),
            wild_value(),
            wild_value(),
            wild_value(),
            speed(),
        ),
        prop::option::of(known_lat_err()),
        0u8..8,
        bad,
        negative,
        collisions(),
    )
        .prop_map(
            |((a_lon, a_lat, a_mag, yaw_rate, speed), lat_err, field, nan, neg, hit)| {
                let mut f = Frame {
                    a_lon,
                    a_lat,
                    a_mag: make_non_negative(a_mag),
                    yaw_rate,
                    speed: make_non_negative(speed),
                    lat_err,
                    collisions: hit,
                };
                match field {
                    0 => f.a_lon = nan,
                    1 => f.a_lat = nan,
                    2 => f.a_mag = nan,
                    3 => f.yaw_rate = nan,
                    4 => f.speed = nan,
                    5 => f.lat_err = Some(nan),
                    6 => f.speed = neg,
                    _ => f.a_mag = neg,
                }
                f
            },
        )
}

proptest! {
    #![proptest_config(proptest_config(2_000))]

    /// An invalid frame anywhere is refused, changes nothing, and the rest of the route still
    /// matches the batch reference of the valid frames.
    #[test]
    fn invalid_frames_change_nothing(
        frames in route(),
        config in config(),
        bad in vec((0..=MAX_FRAMES, invalid_frame()), 1..4),
    ) {
        let mut monitor: Monitor = Monitor::new(config)
            .map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        let mut s = Streamed::default();
        for i in 0..=frames.len() {
            for (_, f) in bad.iter().filter(|(at, _)| (*at).min(frames.len()) == i) {
                prop_assert!(f.validate().is_err());
                let before = (*monitor.summary(), monitor.frames());
                let r = monitor.push(f);
                prop_assert!(matches!(r, Err(MonitorError::Frame(_))), "{:?} gave {:?}", f, r);
                prop_assert_eq!((*monitor.summary(), monitor.frames()), before);
            }
            if let Some(f) = frames.get(i) {
                let events = monitor
                    .push(f)
                    .map_err(|e| TestCaseError::fail(format!("valid frame {i} refused: {e:?}")))?;
                events.iter().for_each(|e| s.record(e));
            }
        }
        let done = monitor.finish().map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        done.events.iter().for_each(|e| s.record(e));
        s.summary = done.summary;
        compare(&s, &frames, &config)?;
    }
}

/// The generators reach every outcome the property is about; without this a generator bug
/// (say, every chunk failing) would make the main property vacuous.
#[test]
fn generators_cover_every_outcome() {
    let mut runner = TestRunner::deterministic();
    let strategy = (route(), config());
    let mut seen = [0u32; 14];
    let names = [
        "comfortable chunk",
        "uncomfortable chunk",
        "short-route comfort chunk",
        "route without comfort chunk",
        "nodecel collision",
        "decelerated collision",
        "exempt collision",
        "anomalous chunk",
        "critical chunk",
        "unscored lateral chunk",
        "legacy profile with a comfortable chunk",
        "non-default chunk length",
        "20 Hz route with comfort chunks",
        "10 Hz route with comfort chunks",
    ];
    for _ in 0..3000 {
        let (frames, config) = strategy.new_tree(&mut runner).expect("strategy").current();
        let b = batch::compute(&frames, &config).summary;
        let n = frames.len();
        let outcomes = [
            b.comfort.comfortable > 0,
            b.comfort.comfortable < b.comfort.chunks,
            n < usize::from(config.chunk_len) && b.comfort.chunks == 1,
            n > 0 && b.comfort.chunks == 0,
            b.collisions.nodecel > 0,
            b.collisions.aligned > b.collisions.exempt + b.collisions.nodecel,
            b.collisions.exempt > 0,
            b.lateral.anomalous > 0,
            b.lateral.critical > 0,
            b.lateral.scored_chunks < b.lateral.chunks,
            config.profile == Profile::B2dLegacy && b.comfort.comfortable > 0,
            config.chunk_len != 20 && b.comfort.chunks > 0,
            config.dt == 0.05 && b.comfort.chunks > 0,
            config.dt == 0.1 && b.comfort.chunks > 0,
        ];
        for (s, o) in seen.iter_mut().zip(outcomes) {
            *s += u32::from(o);
        }
    }
    for (name, count) in names.iter().zip(seen) {
        assert!(
            count >= 10,
            "only {count} of 3000 generated routes had a {name}"
        );
    }
}

/// The demo's 10 Hz route (dt inferred as 0.1 s from its record): the frames `sds` streams
/// give the batch reference's summary with the route's own period.
#[test]
fn demo_10hz_route_streams_as_batch() {
    use monitor_host::{demo, route_frames, score_run, Inputs, Settings};
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry),
        route_xml: Some(run.routes),
        ..Inputs::new([run.results])
    };
    let id = "RouteScenario_900008_rep0";
    let report = score_run(&inputs, &Settings::default()).unwrap();
    let route = report
        .routes
        .iter()
        .find(|r| r.route_id.as_deref() == Some(id))
        .unwrap();
    assert_eq!(route.dt, Some(0.1));
    assert_eq!(route.batch_agrees, Some(true));
    let frames = route_frames(&inputs, id, &Settings::default())
        .unwrap()
        .frames;
    assert_eq!(frames.len(), 100);
    for dt in [0.1f32, 0.05] {
        let config = Config {
            dt,
            ..Config::DEFAULT
        };
        let s = stream(&frames, &config).unwrap();
        compare(&s, &frames, &config).unwrap();
    }
    let config = Config {
        dt: 0.1,
        ..Config::DEFAULT
    };
    let b = batch::compute(&frames, &config).summary;
    assert_eq!(
        (b.comfort.chunks, b.comfort.comfortable),
        (route.comfort.chunks, route.comfort.comfortable),
        "the report used the 0.1 s period"
    );
}

/// The demo town's map and route XML, written once.
fn demo_town() -> &'static (
    monitor_host::geometry::map::Map,
    monitor_host::input::route_xml::RouteSet,
) {
    use std::sync::OnceLock;
    static TOWN: OnceLock<(
        monitor_host::geometry::map::Map,
        monitor_host::input::route_xml::RouteSet,
    )> = OnceLock::new();
    TOWN.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let run = monitor_host::demo::write(dir.path()).unwrap();
        let map = monitor_host::geometry::map::Map::load(
            &run.maps.join(format!("{}.xodr", monitor_host::demo::TOWN)),
        )
        .unwrap();
        let set = monitor_host::input::route_xml::read_route_xml(&run.routes).unwrap();
        (map, set)
    })
}

proptest! {
    #![proptest_config(proptest_config(500))]

    /// docs/SCORE.md §11 with map-based lateral values (docs/SCORE.md §3): drives along the demo's junction route (its gap
    /// filled by the map) with random offsets, under both references and random settings.
    /// The monitor gets the host's per-frame values (`corridor::core_value`); the batch
    /// reference takes the same frames, and they agree bit for bit. Each frame's excess in the
    /// core is the frame's own `max(0, |lat_err| - slack_i)` to f32 rounding.
    #[test]
    fn streaming_equals_batch_with_map_lateral_values(
        offsets in vec(-4.0f64..4.0, 0..MAX_FRAMES),
        start in 0.0f64..120.0,
        step in 0.1f64..1.0,
        lane in any::<bool>(),
        config in config(),
    ) {
        use monitor_host::geometry::corridor::Corridor;
        use monitor_host::settings::LateralReference;
        let (map, set) = demo_town();
        let route = set.get("900009");
        let settings = monitor_host::Settings {
            core: config,
            lateral_reference: if lane { LateralReference::Lane } else { LateralReference::Route },
            ..Default::default()
        };
        let mut corridor = Corridor::new(route, Some(map), &settings);
        let (x0, y0) = (1520.0, -3310.0);
        let mut frames = Vec::with_capacity(offsets.len());
        for (i, dy) in offsets.iter().enumerate() {
            let loc = [x0 + start + step * i as f64, y0 + dy];
            // Rounded to f32 once, as the frame builder does.
            let lat_err = corridor.next(loc, 0.0).map(|v| v as f32);
            if lane {
                // The frame's own excess against the nearest lane, in f64.
                let p = map.project(loc[0], loc[1], 0.0).unwrap();
                let want = (p.distance_2d - (p.width / 2.0 - settings.ego_half_width)).max(0.0);
                let got = monitor_core::signal::excess(lat_err.unwrap(), config.slack);
                prop_assert!((f64::from(got) - want).abs() <= 2e-6, "{} vs {}", got, want);
            }
            frames.push(Frame { speed: 10.0, lat_err, ..Frame::default() });
        }
        if !lane && !offsets.is_empty() {
            // The junction is filled: every frame has a lateral value.
            prop_assert!(frames.iter().all(|f| f.lat_err.is_some()));
        }
        let s = stream(&frames, &config)
            .map_err(|e| TestCaseError::fail(format!("monitor refused a valid route: {e:?}")))?;
        compare(&s, &frames, &config)?;
    }
}

proptest! {
    #![proptest_config(proptest_config(500))]

    /// docs/SCORE.md §3 v1.4 re-acquisition, and §9: frames along the demo's straight junction route (x from
    /// 1510 to 1658 at y = -3310, a junction gap without a map; 0.05 m a step) whose telemetry
    /// starts at a random step (often not 0) and jumps ahead by hundreds of steps at random. Every frame beside
    /// a scored segment reads its own offset `|dy|` (the 10 m window alone lags tens of metres
    /// behind after a jump); the monitor and the batch reference agree bit for bit.
    #[test]
    fn reacquired_lateral_values_stream_as_batch(
        first in prop_oneof![Just(0u64), 1u64..1_000],
        moves in vec((select(vec![1u64, 1, 2, 11, 300, 600]), -1.5f64..1.5), 1..MAX_FRAMES),
        config in config(),
    ) {
        use monitor_host::geometry::corridor::Corridor;
        let (_, set) = demo_town();
        let route = set.get("900009");
        let settings = monitor_host::Settings { core: config, ..Default::default() };
        // 0.05 m a step (1 m/s at 20 Hz), within the route's 148 m: a jump of 300 steps is
        // 15 m, beyond the 10 m window; the frames past the route's end are left out.
        let mut steps = vec![first];
        for (d, _) in &moves[1..] {
            let next = steps[steps.len() - 1] + d;
            if next > 2_900 {
                break;
            }
            steps.push(next);
        }
        let mut corridor = Corridor::new(route, None, &settings);
        let mut frames = Vec::with_capacity(moves.len());
        let mut previous = None;
        for (step, (_, dy)) in steps.iter().zip(&moves) {
            let x = 1511.0 + 0.05 * *step as f64;
            let sample = corridor.sample_at([x, -3310.0 + dy], 0.0, *step, previous);
            if let Some(s) = sample {
                prop_assert!((s.lat_err - dy.abs()).abs() < 1e-9,
                    "step {} (previous {:?}): lat_err {} for an offset of {}", step, previous, s.lat_err, dy);
            }
            previous = Some(*step);
            let lat_err = sample.map(|s| s.value as f32);
            frames.push(Frame { speed: 10.0, lat_err, ..Frame::default() });
        }
        let s = stream(&frames, &config)
            .map_err(|e| TestCaseError::fail(format!("monitor refused a valid route: {e:?}")))?;
        compare(&s, &frames, &config)?;
    }
}
