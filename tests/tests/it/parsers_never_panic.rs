//! Reliability properties: no input makes the core or a parser panic, hang or lose data, and every
//! refusal says what is wrong (`docs/RELIABILITY.md` lists what is covered here).
//!
//! Core: every f32 bit pattern in every frame field, frames after the route ended, configurations
//! that make no sense. Parsers: arbitrary bytes and structured corruptions of `metric_info.json`,
//! results files, collision strings and route XML.

use std::path::Path;

use monitor_core::{
    json, Collisions, Config, ConfigError, Field, Frame, FrameError, Monitor, MonitorError,
    Profile, RouteSummary,
};
use monitor_host::geometry::kinematics;
use monitor_host::input::metric_info::{self as telemetry, FieldProblem, TelemetryError};
use monitor_host::input::{collision as infraction, results_file as results, route_xml as route};
use monitor_host::reference::batch;
use proptest::prelude::*;
use proptest::test_runner::Config as PropConfig;

// ---------------------------------------------------------------------------------------------
// Core: arbitrary floats in every field.

/// Special f32 values, as bit patterns where the bits matter (quiet/signalling NaN, -0).
const SPECIAL_BITS: [u32; 16] = [
    0x7fc0_0000, // quiet NaN
    0xffc0_0000, // negative quiet NaN
    0x7f80_0001, // signalling NaN
    0x7fff_ffff, // NaN with every payload bit
    0x7f80_0000, // +inf
    0xff80_0000, // -inf
    0x0000_0001, // smallest subnormal
    0x8000_0001, // negative smallest subnormal
    0x007f_ffff, // largest subnormal
    0x0080_0000, // f32::MIN_POSITIVE
    0x7f7f_ffff, // f32::MAX
    0xff7f_ffff, // f32::MIN
    0x8000_0000, // -0.0
    0x0000_0000, // 0.0
    0x4b80_0000, // 2^24 (f32 integers stop being exact)
    0xc2c8_0000, // -100.0
];

fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => any::<u32>().prop_map(f32::from_bits),
        2 => proptest::sample::select(SPECIAL_BITS.to_vec()).prop_map(f32::from_bits),
        5 => -60.0f32..60.0,
    ]
}

fn any_collisions() -> impl Strategy<Value = Collisions> {
    prop_oneof![
        4 => Just(Collisions::NONE),
        1 => (any::<u16>(), any::<u16>(), any::<u16>(), any::<u16>()).prop_map(
            |(pedestrian, vehicle, layout, workzone)| Collisions {
                pedestrian,
                vehicle,
                layout,
                workzone,
            }
        ),
        1 => (0u16..3, 0u16..3).prop_map(|(vehicle, workzone)| Collisions {
            vehicle,
            workzone,
            ..Collisions::NONE
        }),
    ]
}

fn any_frame() -> impl Strategy<Value = Frame> {
    (
        (any_f32(), any_f32(), any_f32(), any_f32(), any_f32()),
        proptest::option::of(any_f32()),
        any_collisions(),
    )
        .prop_map(
            |((a_lon, a_lat, a_mag, yaw_rate, speed), lat_err, collisions)| Frame {
                a_lon,
                a_lat,
                a_mag,
                yaw_rate,
                speed,
                lat_err,
                collisions,
            },
        )
}

/// A plausible frame (what a healthy route looks like), to surround the garbage.
fn plausible_frame() -> impl Strategy<Value = Frame> {
    (
        -8.0f32..4.0,
        -5.0f32..5.0,
        0.0f32..9.0,
        -40.0f32..40.0,
        0.0f32..30.0,
        proptest::option::of(0.0f32..3.0),
    )
        .prop_map(|(a_lon, a_lat, a_mag, yaw_rate, speed, lat_err)| Frame {
            a_lon,
            a_lat,
            a_mag,
            yaw_rate,
            speed,
            lat_err,
            collisions: Collisions::NONE,
        })
}

/// The invariants every summary must satisfy, whatever the input.
fn check_summary(s: &RouteSummary, pushed: u32) {
    assert_eq!(s.frames, pushed);
    assert!(s.comfort.comfortable <= s.comfort.chunks, "{s:?}");
    assert!(s.lateral.scored_chunks <= s.lateral.chunks, "{s:?}");
    assert!(
        s.lateral.anomalous + s.lateral.critical <= s.lateral.scored_chunks,
        "{s:?}"
    );
    // Counters saturate at u32::MAX; below that, exempt + nodecel never exceed aligned.
    if s.collisions.aligned < u32::MAX {
        assert!(
            u64::from(s.collisions.exempt) + u64::from(s.collisions.nodecel)
                <= u64::from(s.collisions.aligned),
            "{s:?}"
        );
    }
    if let Some(c) = s.comfort_score() {
        assert!((0.0..=1.0).contains(&c), "comfort {c}");
    }
}

/// Pushes `frames` into a fresh monitor, checking each verdict against `Frame::validate`, then
/// finishes; returns the frames that were accepted and the summary.
fn run_monitor(config: Config, frames: &[Frame]) -> (Vec<Frame>, RouteSummary) {
    let mut m: Monitor = Monitor::new(config).expect("valid config");
    let mut accepted = Vec::new();
    for f in frames {
        let before = *m.summary();
        match m.push(f) {
            Ok(_) => {
                assert_eq!(f.validate(), Ok(()), "accepted an invalid frame {f:?}");
                accepted.push(*f);
            }
            Err(MonitorError::Frame(e)) => {
                assert_eq!(f.validate(), Err(e), "refused {f:?} for the wrong reason");
                assert_eq!(*m.summary(), before, "a refused frame changed the state");
            }
            Err(e) => panic!("unexpected {e:?} for {f:?}"),
        }
    }
    let done = m.finish().expect("first finish");
    check_summary(&done.summary, accepted.len() as u32);
    // The route has ended: more frames and a second finish are refused, nothing changes.
    if let Some(f) = frames.first() {
        assert_eq!(m.push(f).err(), Some(MonitorError::Finished));
    }
    assert_eq!(
        m.push(&Frame::default()).err(),
        Some(MonitorError::Finished)
    );
    assert_eq!(m.finish().err(), Some(MonitorError::Finished));
    assert_eq!(*m.summary(), done.summary);
    (accepted, done.summary)
}

proptest! {
    #![proptest_config(PropConfig { cases: 400, ..PropConfig::default() })]

    /// Any frames (every bit pattern, huge collision counts): no panic, a frame is refused iff
    /// it is invalid, a refused frame changes nothing, and the summary stays consistent.
    #[test]
    fn monitor_survives_any_frames(frames in proptest::collection::vec(any_frame(), 0..90)) {
        for profile in [Profile::Physical, Profile::B2dLegacy] {
            run_monitor(Config { profile, ..Config::DEFAULT }, &frames);
        }
    }

    /// Garbage interleaved with healthy frames: the healthy frames are scored exactly as if the
    /// garbage had never been sent (refused frames leave no trace), and streaming equals batch.
    #[test]
    fn refused_frames_leave_no_trace(
        good in proptest::collection::vec(plausible_frame(), 0..70),
        bad in proptest::collection::vec((any_frame(), 0usize..70), 0..20),
    ) {
        let mut mixed = good.clone();
        for (f, at) in &bad {
            if f.validate().is_err() {
                let at = (*at).min(mixed.len());
                mixed.insert(at, *f);
            }
        }
        let (accepted, with_garbage) = run_monitor(Config::DEFAULT, &mixed);
        prop_assert_eq!(&accepted, &good);
        let (_, clean) = run_monitor(Config::DEFAULT, &good);
        prop_assert_eq!(with_garbage, clean);
        prop_assert_eq!(batch::compute(&good, &Config::DEFAULT).summary, clean);
    }

    /// Valid but extreme frames (huge, subnormal, signed zeros): streaming and the batch
    /// reference still agree bit for bit (docs/SCORE.md §11).
    #[test]
    fn extreme_valid_frames_stream_equals_batch(
        frames in proptest::collection::vec(any_frame(), 0..80),
    ) {
        let valid: Vec<Frame> = frames.into_iter().filter(|f| f.validate().is_ok()).collect();
        for profile in [Profile::Physical, Profile::B2dLegacy] {
            let config = Config { profile, ..Config::DEFAULT };
            let (_, streamed) = run_monitor(config, &valid);
            prop_assert_eq!(batch::compute(&valid, &config).summary, streamed);
        }
    }

    /// Any configuration, built from arbitrary bit patterns: `Monitor::new` returns a result
    /// (never panics), and a monitor it accepts survives any frames.
    #[test]
    fn any_config_is_accepted_or_refused(
        floats in proptest::collection::vec(any_f32(), 20),
        lens in (0u16..40, 0u16..40, 0u16..40),
        factors in proptest::collection::vec(
            prop_oneof![any::<u64>().prop_map(f64::from_bits), -0.5f64..1.5], 5),
        legacy in any::<bool>(),
        frames in proptest::collection::vec(any_frame(), 0..45),
    ) {
        let f = &floats;
        let config = Config {
            profile: if legacy { Profile::B2dLegacy } else { Profile::Physical },
            dt: f[0],
            legacy_jerk_spacing: f[1],
            chunk_len: lens.0,
            min_chunk: lens.1,
            bounds: monitor_core::Bounds {
                lon_acc_min: f[2],
                lon_acc_max: f[3],
                lat_acc: f[4],
                mag_jerk: f[5],
                lon_jerk: f[6],
                yaw_acc: f[7],
                yaw_rate: f[8],
            },
            slack: f[9],
            anomalous_excess: f[10],
            critical_excess: f[11],
            decel_threshold: f[12],
            decel_window: lens.2,
            stationary_speed: f[13],
            factors: monitor_core::Factors {
                workzone: factors[0],
                layout: factors[1],
                nodecel: factors[2],
                anomalous: factors[3],
                critical: factors[4],
            },
        };
        match Monitor::<20>::new(config) {
            Ok(_) => {
                prop_assert_eq!(config.validate(20), Ok(()));
                run_monitor(config, &frames);
            }
            Err(e) => prop_assert_eq!(config.validate(20), Err(e)),
        }
    }

    /// `decode_frame` on arbitrary bytes never panics; what it returns is a valid frame.
    #[test]
    fn decode_frame_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        if let Ok(f) = json::decode_frame(&bytes) {
            prop_assert_eq!(f.validate(), Ok(()));
        }
    }

    /// A valid frame survives encode + decode bit for bit. (An invalid one may not: the encoder
    /// writes a non-finite float as `null`, which is refused, or for `lat_err` read as unknown.)
    #[test]
    fn decode_frame_round_trip(f in any_frame()) {
        if f.validate().is_err() {
            return Ok(());
        }
        let mut buf = [0u8; 512];
        match json::encode(&f, &mut buf) {
            Ok(n) => match json::decode_frame(&buf[..n]) {
                Ok(g) => {
                    prop_assert_eq!(f.validate(), Ok(()));
                    let bits = |f: &Frame| {
                        [f.a_lon, f.a_lat, f.a_mag, f.yaw_rate, f.speed].map(f32::to_bits)
                    };
                    prop_assert_eq!(bits(&g), bits(&f));
                    prop_assert_eq!(g.lat_err.map(f32::to_bits), f.lat_err.map(f32::to_bits));
                    prop_assert_eq!(g.collisions, f.collisions);
                }
                // Only an invalid frame may fail to come back.
                Err(_) => prop_assert!(f.validate().is_err(), "valid frame lost: {:?}", f),
            },
            Err(e) => prop_assert!(false, "encode failed: {e:?}"),
        }
    }
}

#[test]
fn every_special_value_in_every_field() {
    let base = Frame {
        a_lon: 0.2,
        a_lat: 0.1,
        a_mag: 0.3,
        yaw_rate: 2.0,
        speed: 8.0,
        lat_err: Some(0.4),
        collisions: Collisions::NONE,
    };
    let fields = [
        Field::ALon,
        Field::ALat,
        Field::AMag,
        Field::YawRate,
        Field::Speed,
        Field::LatErr,
    ];
    for bits in SPECIAL_BITS {
        let v = f32::from_bits(bits);
        for field in fields {
            let mut f = base;
            match field {
                Field::ALon => f.a_lon = v,
                Field::ALat => f.a_lat = v,
                Field::AMag => f.a_mag = v,
                Field::YawRate => f.yaw_rate = v,
                Field::Speed => f.speed = v,
                Field::LatErr => f.lat_err = Some(v),
            }
            let expected = if !v.is_finite() {
                Err(FrameError::NonFinite(field))
            } else if v < 0.0 && matches!(field, Field::Speed | Field::AMag) {
                Err(FrameError::Negative(field))
            } else {
                Ok(())
            };
            assert_eq!(f.validate(), expected, "{} = {v:?}", field.name());
            // In the middle of a chunk of healthy frames, and as the chunk's last frame.
            for at in [0usize, 7, 19, 25] {
                let mut frames = vec![base; 30];
                frames.insert(at, f);
                let (accepted, _) = run_monitor(Config::DEFAULT, &frames);
                assert_eq!(accepted.len(), 30 + usize::from(expected.is_ok()));
            }
            // The error names the field.
            if expected.is_err() {
                let mut m: Monitor = Monitor::default();
                let msg = m.push(&f).unwrap_err().to_string();
                assert!(msg.contains(field.name()), "{msg}");
            }
        }
    }
}

#[test]
fn huge_finite_signals_are_uncomfortable_not_a_crash() {
    // f32::MAX accelerations overflow inside the filter (inf - inf = NaN): such a chunk must be
    // judged uncomfortable, never comfortable, and nothing may panic.
    for v in [f32::MAX, f32::MIN, 1e30, -1e30] {
        let frames: Vec<Frame> = (0..40)
            .map(|i| Frame {
                a_lon: if i % 2 == 0 { v } else { -v },
                a_lat: v,
                a_mag: v.abs(),
                yaw_rate: v,
                speed: 10.0,
                lat_err: Some(v.abs()),
                collisions: Collisions::NONE,
            })
            .collect();
        for profile in [Profile::Physical, Profile::B2dLegacy] {
            let config = Config {
                profile,
                ..Config::DEFAULT
            };
            let (_, s) = run_monitor(config, &frames);
            assert_eq!(s.comfort.chunks, 2);
            assert_eq!(s.comfort.comfortable, 0, "{v} judged comfortable");
            assert_eq!(s.lateral.critical, 2, "{v}: huge lateral error is critical");
            assert_eq!(batch::compute(&frames, &config).summary, s);
        }
    }
}

#[test]
fn collision_counts_saturate() {
    // 4 x u16::MAX collisions on every frame for many frames: counters saturate, no overflow.
    let hit = Frame {
        speed: 5.0,
        collisions: Collisions {
            pedestrian: u16::MAX,
            vehicle: u16::MAX,
            layout: u16::MAX,
            workzone: u16::MAX,
        },
        ..Frame::default()
    };
    let frames = vec![hit; 20_000];
    let (_, s) = run_monitor(Config::DEFAULT, &frames);
    assert_eq!(s.collisions.aligned, u32::MAX);
    // Frame 0 is exempt (the route's first frame); every later hit is without deceleration.
    assert_eq!(s.collisions.exempt, 4 * u32::from(u16::MAX));
    assert_eq!(s.collisions.nodecel, u32::MAX);
}

#[test]
fn nonsense_configs_are_refused_with_a_reason() {
    let d = Config::DEFAULT;
    let cases: Vec<(Config, ConfigError)> = vec![
        // Windows larger than the capacity / a chunk shorter than the filter window.
        (
            Config {
                decel_window: 21,
                ..d
            },
            ConfigError::DecelWindow,
        ),
        (Config { chunk_len: 21, ..d }, ConfigError::ChunkLen),
        (Config { chunk_len: 5, ..d }, ConfigError::ChunkLen),
        (
            Config {
                min_chunk: 3,
                chunk_len: 5,
                ..d
            },
            ConfigError::MinChunk,
        ),
        (Config { min_chunk: 21, ..d }, ConfigError::ChunkLen),
        // Negative or non-finite thresholds.
        (Config { slack: -0.82, ..d }, ConfigError::Slack),
        (
            Config {
                anomalous_excess: -0.25,
                ..d
            },
            ConfigError::ExcessBands,
        ),
        (
            Config {
                critical_excess: 0.1,
                ..d
            },
            ConfigError::ExcessBands,
        ),
        (
            Config {
                critical_excess: f32::INFINITY,
                ..d
            },
            ConfigError::ExcessBands,
        ),
        (
            Config {
                stationary_speed: -0.5,
                ..d
            },
            ConfigError::StationarySpeed,
        ),
        (
            Config {
                decel_threshold: f32::NAN,
                ..d
            },
            ConfigError::DecelThreshold,
        ),
        (Config { dt: 0.0, ..d }, ConfigError::Dt),
        (Config { dt: -0.05, ..d }, ConfigError::Dt),
        (
            Config {
                legacy_jerk_spacing: f32::NAN,
                ..d
            },
            ConfigError::LegacySpacing,
        ),
        (
            Config {
                bounds: monitor_core::Bounds {
                    lat_acc: -4.89,
                    ..d.bounds
                },
                ..d
            },
            ConfigError::Bounds,
        ),
        (
            Config {
                bounds: monitor_core::Bounds {
                    lon_acc_min: 3.0,
                    lon_acc_max: 2.4,
                    ..d.bounds
                },
                ..d
            },
            ConfigError::Bounds,
        ),
        (
            Config {
                factors: monitor_core::Factors {
                    nodecel: 1.5,
                    ..d.factors
                },
                ..d
            },
            ConfigError::Factor,
        ),
        (
            Config {
                factors: monitor_core::Factors {
                    layout: 0.0,
                    ..d.factors
                },
                ..d
            },
            ConfigError::Factor,
        ),
        (
            Config {
                factors: monitor_core::Factors {
                    critical: f64::NAN,
                    ..d.factors
                },
                ..d
            },
            ConfigError::Factor,
        ),
    ];
    for (config, expected) in cases {
        assert_eq!(
            Monitor::<20>::new(config).err(),
            Some(expected),
            "{config:?}"
        );
        assert!(!expected.to_string().is_empty());
    }
    // The default configuration does not fit a smaller monitor: refused, not a panic.
    assert_eq!(Monitor::<10>::new(d).err(), Some(ConfigError::ChunkLen));
    assert_eq!(
        Monitor::<10>::new(Config { chunk_len: 10, ..d }).err(),
        Some(ConfigError::DecelWindow)
    );
}

#[test]
fn a_frame_after_the_route_ended_is_refused_until_reset() {
    let mut m: Monitor = Monitor::default();
    for _ in 0..25 {
        m.push(&Frame {
            speed: 3.0,
            ..Frame::default()
        })
        .unwrap();
    }
    let done = m.finish().unwrap();
    assert_eq!(
        m.push(&Frame::default()).err(),
        Some(MonitorError::Finished)
    );
    assert_eq!(m.finish().err(), Some(MonitorError::Finished));
    assert_eq!(*m.summary(), done.summary);
    m.reset();
    assert_eq!(m.frames(), 0);
    m.push(&Frame::default()).unwrap();
    assert_eq!(m.finish().unwrap().summary.frames, 1);
}

// ---------------------------------------------------------------------------------------------
// metric_info.json

const FIELDS: [&str; 5] = [
    "acceleration",
    "angular_velocity",
    "forward_vector",
    "right_vector",
    "location",
];

/// One frame's JSON, Bench2Drive layout. `values[f]` overrides field f's text.
fn frame_json(step: &str, i: usize, values: &[Option<String>; 5], skip: Option<usize>) -> String {
    let defaults = [
        format!("[{}, 0.1, 0.0]", 0.01 * i as f64),
        "[0.0, 0.0, 1.5]".to_string(),
        "[1.0, 0.0, 0.0]".to_string(),
        "[0.0, 1.0, 0.0]".to_string(),
        format!("[{}, -3310.0, 0.2]", 1520.0 + 0.5 * i as f64),
    ];
    let mut parts = Vec::new();
    for (k, name) in FIELDS.iter().enumerate() {
        if skip == Some(k) {
            continue;
        }
        let v = values[k].clone().unwrap_or_else(|| defaults[k].clone());
        parts.push(format!("\"{name}\": {v}"));
    }
    parts.push("\"rotation\": [0.0, 0.0, 0.0]".to_string());
    format!("\"{step}\": {{{}}}", parts.join(", "))
}

fn doc(frames: &[String]) -> String {
    format!("{{\n{}\n}}\n", frames.join(",\n"))
}

fn healthy_doc(steps: &[u64]) -> String {
    let none: [Option<String>; 5] = Default::default();
    doc(&steps
        .iter()
        .enumerate()
        .map(|(i, s)| frame_json(&s.to_string(), i, &none, None))
        .collect::<Vec<_>>())
}

/// A corruption of one frame of a healthy file, and the error it must produce.
#[derive(Clone, Debug)]
enum Corruption {
    /// A bare token (`NaN`, `Infinity`, `-Infinity`) as element `elem` of field `field`.
    Token(usize, usize, &'static str),
    /// Field `field` has `len` numbers (< 3).
    Short(usize, usize),
    /// Field `field` is absent.
    Missing(usize),
    /// Field `field` holds a string element.
    NonNumeric(usize),
    /// Field `field` is not an array.
    NotArray(usize),
    /// The frame's key is not decimal.
    BadKey(String),
    /// The frame is not an object.
    FrameNotObject,
    /// The frame's step repeats another frame's step (written with leading zeros).
    DuplicateStep,
    /// An overflowing literal (`1e999`).
    Overflow(usize),
}

fn corruption() -> impl Strategy<Value = Corruption> {
    prop_oneof![
        (
            0usize..5,
            0usize..3,
            proptest::sample::select(vec!["NaN", "Infinity", "-Infinity"])
        )
            .prop_map(|(f, e, t)| Corruption::Token(f, e, t)),
        (0usize..5, 0usize..3).prop_map(|(f, n)| Corruption::Short(f, n)),
        (0usize..5).prop_map(Corruption::Missing),
        (0usize..5).prop_map(Corruption::NonNumeric),
        (0usize..5).prop_map(Corruption::NotArray),
        "[a-z ._-]{1,8}|-[0-9]{1,3}|[0-9]{1,3}\\.[0-9]|\\+[0-9]".prop_map(Corruption::BadKey),
        Just(Corruption::FrameNotObject),
        Just(Corruption::DuplicateStep),
        (0usize..5).prop_map(Corruption::Overflow),
    ]
}

/// Builds a file with `n` frames (steps `first..`, in a shuffled order when `reverse`) whose
/// frame `at` is corrupted; returns the text and the corrupted step.
fn corrupted_doc(n: usize, first: u64, reverse: bool, at: usize, c: &Corruption) -> (String, u64) {
    let mut frames = Vec::new();
    let mut bad_step = 0;
    for i in 0..n {
        let step = first + i as u64;
        let mut values: [Option<String>; 5] = Default::default();
        let mut skip = None;
        let mut key = step.to_string();
        let mut text = None;
        if i == at {
            bad_step = step;
            match c {
                Corruption::Token(f, e, t) => {
                    let mut v = vec!["1.0".to_string(); 3];
                    v[*e] = t.to_string();
                    values[*f] = Some(format!("[{}]", v.join(", ")));
                }
                Corruption::Short(f, len) => {
                    values[*f] = Some(format!("[{}]", vec!["1.0"; *len].join(", ")));
                }
                Corruption::Missing(f) => skip = Some(*f),
                Corruption::NonNumeric(f) => values[*f] = Some("[1.0, \"x\", 0.0]".into()),
                Corruption::NotArray(f) => values[*f] = Some("{\"x\": 1.0}".into()),
                Corruption::BadKey(k) => key = k.clone(),
                Corruption::FrameNotObject => text = Some(format!("\"{step}\": [1, 2, 3]")),
                Corruption::DuplicateStep => {
                    // Same integer value as frame 0's step, written differently.
                    key = format!("000{first}");
                    bad_step = first;
                }
                Corruption::Overflow(f) => values[*f] = Some("[1e999, 0.0, 0.0]".into()),
            }
        }
        frames.push(text.unwrap_or_else(|| frame_json(&key, i, &values, skip)));
    }
    if reverse {
        frames.reverse();
    }
    (doc(&frames), bad_step)
}

fn check_corruption(err: &TelemetryError, c: &Corruption, step: u64) {
    let msg = err.to_string();
    let field_err = |f: usize, problem: FieldProblem| {
        assert!(
            matches!(err, TelemetryError::Field { step: s, field, problem: p }
                if *s == step && *field == FIELDS[f] && *p == problem),
            "{c:?}: expected step {step} field {} {problem:?}, got {err:?}",
            FIELDS[f]
        );
        assert!(
            msg.contains(&format!("step {step}")) && msg.contains(FIELDS[f]),
            "{msg}"
        );
    };
    match c {
        Corruption::Token(f, _, _) | Corruption::Overflow(f) => {
            field_err(*f, FieldProblem::NonFinite)
        }
        Corruption::Short(f, _) => field_err(*f, FieldProblem::TooShort),
        Corruption::Missing(f) => field_err(*f, FieldProblem::Missing),
        Corruption::NonNumeric(f) => field_err(*f, FieldProblem::NonNumeric),
        Corruption::NotArray(f) => field_err(*f, FieldProblem::NotAnArray),
        Corruption::BadKey(k) => {
            assert!(
                matches!(err, TelemetryError::BadStepKey { key } if key == k),
                "{c:?}: {err:?}"
            );
            assert!(msg.contains(k.as_str()), "{msg}");
        }
        Corruption::FrameNotObject => assert!(
            matches!(err, TelemetryError::FrameNotObject { step: s } if *s == step),
            "{err:?}"
        ),
        Corruption::DuplicateStep => assert!(
            matches!(err, TelemetryError::DuplicateStep { step: s } if *s == step),
            "{err:?}"
        ),
    }
}

proptest! {
    #![proptest_config(PropConfig { cases: 300, ..PropConfig::default() })]

    /// Arbitrary bytes: no panic; an error always has a message.
    #[test]
    fn metric_info_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        match telemetry::parse_metric_info(&bytes) {
            Ok(t) => prop_assert!(!t.frames.is_empty()),
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    /// A healthy file with one frame corrupted in any of the spec's ways: the error names the
    /// step and the field, whatever the frame order.
    #[test]
    fn metric_info_corruption_is_named(
        n in 1usize..12,
        first in prop_oneof![0u64..5, 1_000u64..2_000],
        at in 0usize..12,
        reverse in any::<bool>(),
        c in corruption(),
    ) {
        let at = at % n;
        if matches!(c, Corruption::DuplicateStep) && at == 0 {
            return Ok(()); // needs another frame to duplicate
        }
        let (text, step) = corrupted_doc(n.max(2), first, reverse, at, &c);
        let err = telemetry::parse_metric_info(text.as_bytes()).expect_err("corrupted file accepted");
        check_corruption(&err, &c, step);
    }

    /// Steps in any order, with any gaps: accepted, sorted, and the gap count is exact.
    #[test]
    fn metric_info_steps_any_order_and_gaps(
        steps in proptest::collection::btree_set(0u64..1_000_000_000_000, 1..30),
        shuffle in any::<u64>(),
    ) {
        let mut order: Vec<u64> = steps.iter().copied().collect();
        // A deterministic shuffle (decreasing runs, rotations) from the seed.
        let k = (shuffle as usize) % order.len();
        order.rotate_left(k);
        if shuffle & 1 == 1 {
            order.reverse();
        }
        let t = telemetry::parse_metric_info(healthy_doc(&order).as_bytes()).expect("healthy");
        let sorted: Vec<u64> = steps.iter().copied().collect();
        prop_assert_eq!(t.steps(), sorted.clone());
        let span = sorted[sorted.len() - 1] - sorted[0] + 1;
        prop_assert_eq!(t.gaps, span - sorted.len() as u64);
        let v = kinematics::speeds(&t.frames, 0.05);
        prop_assert!(v.iter().all(|s| s.is_finite() && *s >= 0.0));
    }
}

#[test]
fn metric_info_every_truncation_is_an_error() {
    let text = healthy_doc(&[1, 2, 3]);
    let full = text.trim_end();
    for cut in 0..full.len() {
        match telemetry::parse_metric_info(&full.as_bytes()[..cut]) {
            Ok(_) => panic!("truncated at {cut} accepted"),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
    assert_eq!(
        telemetry::parse_metric_info(full.as_bytes())
            .unwrap()
            .frames
            .len(),
        3
    );
}

#[test]
fn metric_info_whole_file_cases() {
    let cases: [(&[u8], &str); 8] = [
        (b"{}", "no frames"),
        (b"  {  }  ", "no frames"),
        (b"[]", "top level is not an object"),
        (b"null", "top level is not an object"),
        (b"", "not valid JSON"),
        (b"NaN", ""),
        (b"{\"1\": {\"acceleration\": [1, 2, 3]", ""),
        (b"\xff\xfe{}", "not valid JSON"),
    ];
    for (bytes, want) in cases {
        let e = telemetry::parse_metric_info(bytes).expect_err("invalid accepted");
        assert!(
            e.to_string().contains(want),
            "{:?}: {e}",
            String::from_utf8_lossy(bytes)
        );
    }
    // A bare NaN in an ignored key still makes the file invalid (it is not JSON), with the step.
    let none: [Option<String>; 5] = Default::default();
    let f = frame_json("4", 0, &none, None)
        .replace("\"rotation\": [0.0, 0.0, 0.0]", "\"rotation\": [NaN, 0, 0]");
    let e = telemetry::parse_metric_info(doc(&[f]).as_bytes()).unwrap_err();
    assert!(e.to_string().contains("step 4"), "{e}");
    // Vectors longer than 3 are fine (only the first 3 are read), values as integers too.
    let mut values: [Option<String>; 5] = Default::default();
    values[0] = Some("[1, 2, 3, 4, 5]".into());
    let t =
        telemetry::parse_metric_info(doc(&[frame_json("9", 0, &values, None)]).as_bytes()).unwrap();
    assert_eq!(t.frames[0].acc, [1.0, 2.0]);
    // A finite value too large for f32 is refused, naming step and field.
    let mut values: [Option<String>; 5] = Default::default();
    values[1] = Some("[0, 0, 1e300]".into());
    let e = telemetry::parse_metric_info(doc(&[frame_json("9", 0, &values, None)]).as_bytes())
        .unwrap_err();
    assert!(
        matches!(
            e,
            TelemetryError::Field {
                step: 9,
                field: "angular_velocity",
                problem: FieldProblem::OutOfF32Range
            }
        ),
        "{e:?}"
    );
    // Huge step numbers: the largest u64 is fine, one more is out of range.
    let t =
        telemetry::parse_metric_info(healthy_doc(&[u64::MAX - 1, u64::MAX]).as_bytes()).unwrap();
    assert_eq!(t.gaps, 0);
    let big = healthy_doc(&[1]).replace("\"1\"", "\"18446744073709551616\"");
    let e = telemetry::parse_metric_info(big.as_bytes()).unwrap_err();
    assert!(matches!(e, TelemetryError::StepOutOfRange { .. }), "{e:?}");
    // First and last steps far apart: the gap count does not overflow.
    let t = telemetry::parse_metric_info(healthy_doc(&[0, u64::MAX]).as_bytes()).unwrap();
    assert_eq!(t.gaps, u64::MAX - 1);
}

#[test]
fn metric_info_that_is_a_directory_or_absent_names_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let as_dir = dir.path().join("metric_info.json");
    std::fs::create_dir(&as_dir).unwrap();
    let e = telemetry::read_metric_info(&as_dir).unwrap_err();
    assert!(matches!(e, TelemetryError::Io { .. }), "{e:?}");
    assert!(e.to_string().contains(&as_dir.display().to_string()), "{e}");
    let absent = dir.path().join("nope").join("metric_info.json");
    let e = telemetry::read_metric_info(&absent).unwrap_err();
    assert!(e.to_string().contains(&absent.display().to_string()), "{e}");
}

// ---------------------------------------------------------------------------------------------
// Collision strings

proptest! {
    #![proptest_config(PropConfig { cases: 500, ..PropConfig::default() })]

    /// Arbitrary text, and text near the real form: no panic; an error quotes the input.
    #[test]
    fn collision_any_string(
        s in prop_oneof![
            any::<String>(),
            "Agent collided against object with type=[a-z.0-9 ]{0,20}( and id=[0-9a-z-]{0,25})?( at \\([xyz=0-9eE.+, -]{0,40}\\)?)?",
        ]
    ) {
        match infraction::parse_collision(&s) {
            Ok(c) => {
                prop_assert!(!c.type_id.is_empty());
                if let Some(l) = c.location {
                    prop_assert!(l.iter().all(|v| v.is_finite()));
                }
            }
            Err(e) => {
                prop_assert_eq!(&e.input, &s);
                prop_assert!(e.to_string().contains("cannot parse collision"));
            }
        }
    }

    /// Well-formed strings with any finite coordinates (Python repr) parse back exactly.
    #[test]
    fn collision_well_formed_round_trip(
        kind in "(static\\.prop|vehicle|walker\\.pedestrian)\\.[a-z0-9_]{1,12}",
        id in any::<u64>(),
        xyz in proptest::array::uniform3(prop_oneof![
            any::<f64>().prop_filter("finite", |v| v.is_finite()),
            -5000.0f64..5000.0,
        ]),
    ) {
        let s = format!(
            "Agent collided against object with type={kind} and id={id} at (x={:?}, y={:?}, z={:?})",
            xyz[0], xyz[1], xyz[2]
        );
        let c = infraction::parse_collision(&s).unwrap();
        prop_assert_eq!(c.type_id, kind);
        prop_assert_eq!(c.actor_id, Some(id));
        prop_assert_eq!(c.location, Some(xyz));
    }
}

#[test]
fn collision_strings_that_do_not_parse() {
    let p = "Agent collided against object with type=";
    let bad = [
        String::new(),
        "Agent collided against object".to_string(),
        p.to_string(),
        format!("{p}vehicle.audi.tt and id="),
        format!("{p}vehicle.audi.tt and id=-3"),
        format!("{p}vehicle.audi.tt and id=99999999999999999999999"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1.0, y=2.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1.0, y=2.0, z=3.0, w=4.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=nan, y=2.0, z=3.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=inf, y=2.0, z=3.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1e999, y=2.0, z=3.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1.0, y=2.0, z=3.0"),
        format!("{p}vehicle.audi.tt and id=1 at (y=1.0, x=2.0, z=3.0)"),
        format!("{p}vehicle.audi.tt trailing words"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1.0,y=2.0,z=3.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=, y=2.0, z=3.0)"),
        format!("{p}vehicle.audi.tt and id=1 at (x=1..0, y=2.0, z=3.0)"),
    ];
    for s in &bad {
        let e = infraction::parse_collision(s).expect_err(s);
        assert_eq!(&e.input, s);
        assert!(!e.reason.is_empty());
    }
}

// ---------------------------------------------------------------------------------------------
// Results files

fn json_value() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::Value;
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(Value::from),
        any::<f64>()
            .prop_filter("finite", |v| v.is_finite())
            .prop_map(Value::from),
        "[a-zA-Z_ 0-9.-]{0,12}".prop_map(Value::String),
    ];
    leaf.prop_recursive(3, 24, 6, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            proptest::collection::btree_map(
                prop_oneof![
                    proptest::sample::select(vec![
                        "route_id",
                        "status",
                        "scores",
                        "infractions",
                        "save_name",
                        "meta",
                        "score_route",
                        "score_penalty",
                        "score_composed",
                        "weather_id",
                        "town_name",
                        "scenario_name",
                        "collisions_layout",
                        "route_length",
                    ])
                    .prop_map(String::from),
                    "[a-z_]{1,8}",
                ],
                inner,
                0..6
            )
            .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

fn healthy_record(id: u32) -> serde_json::Value {
    serde_json::json!({
        "index": 0,
        "route_id": format!("RouteScenario_{id}_rep0"),
        "status": "Completed",
        "infractions": {"collisions_layout": [], "min_speed_infractions": []},
        "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0},
        "meta": {"route_length": 120.0, "duration_game": 10.0, "duration_system": 30.0},
        "save_name": format!("RouteScenario_{id}_rep0_Town01_X_1_1_11_22_06_00_00"),
        "town_name": "Town01",
        "scenario_name": "DemoCruising_1",
        "weather_id": "1"
    })
}

fn write_results(dir: &Path, name: &str, records: &[serde_json::Value]) -> std::path::PathBuf {
    let p = dir.join(name);
    let doc = serde_json::json!({
        "_checkpoint": {"global_record": {}, "progress": [records.len(), records.len()],
                        "records": records},
        "entry_status": "Finished"
    });
    std::fs::write(&p, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    p
}

proptest! {
    #![proptest_config(PropConfig { cases: 200, ..PropConfig::default() })]

    /// Arbitrary bytes as a results file: no panic; an error names the file.
    #[test]
    fn results_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("endpoint.json");
        std::fs::write(&p, &bytes).unwrap();
        match results::read_results(&p) {
            Ok(set) => prop_assert!(set.records.len() < 300),
            Err(e) => prop_assert!(e.to_string().contains("endpoint.json"), "{}", e),
        }
    }

    /// Arbitrary JSON values as records among healthy ones: every record is kept, in order,
    /// healthy ones valid, and an invalid one names the field.
    #[test]
    fn results_any_records_none_lost(
        junk in proptest::collection::vec(json_value(), 0..6),
        healthy in 0usize..4,
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut records: Vec<serde_json::Value> =
            (0..healthy).map(|i| healthy_record(900_001 + i as u32)).collect();
        records.extend(junk.iter().cloned());
        let p = write_results(dir.path(), "run.json", &records);
        let set = results::read_results(&p).unwrap();
        prop_assert_eq!(set.records.len(), records.len());
        for (i, r) in set.records.iter().enumerate() {
            prop_assert_eq!(r.index, i);
            if i < healthy {
                prop_assert!(r.entry.is_ok());
            } else if let Err(e) = &r.entry {
                prop_assert!(e.reason.contains("field ") || e.reason.starts_with("record:"),
                    "{}", e.reason);
            }
        }
    }
}

#[test]
fn results_every_truncation_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = write_results(dir.path(), "endpoint.json", &[healthy_record(1)]);
    let full = std::fs::read(&p).unwrap();
    let trunc = dir.path().join("truncated.json");
    for cut in 0..full.len() {
        std::fs::write(&trunc, &full[..cut]).unwrap();
        let e = results::read_results(&trunc).expect_err("truncated file accepted");
        let msg = e.to_string();
        assert!(msg.contains("truncated.json"), "{msg}");
        if cut > 0 && !full[..cut].iter().all(u8::is_ascii_whitespace) {
            assert!(
                matches!(e, results::ResultsError::TruncatedJson { .. }),
                "cut {cut}: {msg}"
            );
        }
    }
}

#[test]
fn results_bad_records_name_the_field() {
    let mut cases: Vec<(serde_json::Value, &str)> = Vec::new();
    let with = |f: &dyn Fn(&mut serde_json::Map<String, serde_json::Value>)| {
        let mut r = healthy_record(7);
        f(r.as_object_mut().unwrap());
        r
    };
    cases.push((serde_json::json!({}), "route_id"));
    cases.push((serde_json::json!([]), "record"));
    cases.push((serde_json::json!(null), "record"));
    cases.push((
        with(&|r| {
            r.remove("status");
        }),
        "status",
    ));
    cases.push((
        with(&|r| {
            r.insert("status".into(), 3.into());
        }),
        "status",
    ));
    cases.push((
        with(&|r| {
            r.remove("scores");
        }),
        "scores",
    ));
    cases.push((
        with(&|r| {
            r.insert("scores".into(), "high".into());
        }),
        "scores",
    ));
    cases.push((
        with(&|r| {
            r["scores"]["score_route"] = "100".into();
        }),
        "scores.score_route",
    ));
    cases.push((
        with(&|r| {
            r["scores"].as_object_mut().unwrap().remove("score_penalty");
        }),
        "scores.score_penalty",
    ));
    cases.push((
        with(&|r| {
            r["scores"]["score_composed"] = serde_json::Value::Null;
        }),
        "scores.score_composed",
    ));
    cases.push((
        with(&|r| {
            r.remove("infractions");
        }),
        "infractions",
    ));
    cases.push((
        with(&|r| {
            r["infractions"]["collisions_layout"] = "none".into();
        }),
        "infractions.collisions_layout",
    ));
    cases.push((
        with(&|r| {
            r["infractions"]["collisions_layout"] = serde_json::json!([1]);
        }),
        "infractions.collisions_layout[0]",
    ));
    cases.push((
        with(&|r| {
            r.insert("route_id".into(), 5.into());
        }),
        "route_id",
    ));
    cases.push((
        with(&|r| {
            r.insert("save_name".into(), 5.into());
        }),
        "save_name",
    ));
    cases.push((
        with(&|r| {
            r.insert("meta".into(), "x".into());
        }),
        "meta",
    ));
    cases.push((
        with(&|r| {
            r["meta"]["route_length"] = "far".into();
        }),
        "meta.route_length",
    ));
    cases.push((
        with(&|r| {
            r.insert("weather_id".into(), serde_json::json!([1]));
        }),
        "weather_id",
    ));
    let dir = tempfile::tempdir().unwrap();
    let records: Vec<_> = cases.iter().map(|(r, _)| r.clone()).collect();
    let p = write_results(dir.path(), "run.json", &records);
    let set = results::read_results(&p).unwrap();
    assert_eq!(set.records.len(), cases.len());
    for (lr, (_, field)) in set.records.iter().zip(&cases) {
        let e = lr.entry.as_ref().expect_err(field);
        assert!(e.reason.contains(field), "{field}: {}", e.reason);
    }
}

#[test]
fn results_records_kept_with_warnings() {
    let dir = tempfile::tempdir().unwrap();
    // Without save_name: valid, no telemetry folder; unknown status: valid, warned, not a success.
    let mut no_save = healthy_record(1);
    no_save.as_object_mut().unwrap().remove("save_name");
    let mut odd = healthy_record(2);
    odd["status"] = "Exploded".into();
    let a = write_results(dir.path(), "a.json", &[no_save, odd]);
    // The same route id in a second file: read twice; the duplicates policy (the run's business)
    // names both files.
    let b = write_results(dir.path(), "b.json", &[healthy_record(1)]);
    let set = results::read_results(dir.path()).unwrap();
    assert_eq!(set.records.len(), 3);
    let r0 = set.records[0].entry.as_ref().unwrap();
    assert_eq!(r0.save_name, None);
    let r1 = set.records[1].entry.as_ref().unwrap();
    assert!(!r1.is_success());
    let texts: Vec<String> = set.warnings.iter().map(ToString::to_string).collect();
    let w = texts.join("\n");
    assert!(
        w.contains("Exploded") && w.contains("RouteScenario_2_rep0"),
        "{w}"
    );
    let e = monitor_host::input::duplicates::deduplicate(
        set.records.clone(),
        monitor_host::input::duplicates::DuplicatePolicy::Error,
    )
    .unwrap_err();
    let dup = e.to_string();
    assert!(
        dup.contains(&format!(
            "RouteScenario_1_rep0: {} record 0, {} record 0",
            a.display(),
            b.display()
        )),
        "{dup}"
    );
}

#[test]
fn results_broken_file_in_a_directory_is_reported_not_fatal() {
    let dir = tempfile::tempdir().unwrap();
    write_results(dir.path(), "good.json", &[healthy_record(1)]);
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, b"{\"_checkpoint\": {\"records\": [{\"route_id\": ").unwrap();
    let set = results::read_results(dir.path()).unwrap();
    assert_eq!(set.records.len(), 1);
    assert_eq!(set.broken_files.len(), 1);
    assert_eq!(set.broken_files[0].0, bad);
    assert!(
        set.broken_files[0].1.contains("truncated"),
        "{:?}",
        set.broken_files
    );
    // A single file that is a directory of nothing useful: an error naming it.
    let empty = tempfile::tempdir().unwrap();
    let e = results::read_results(empty.path()).unwrap_err();
    assert!(e.to_string().contains(&empty.path().display().to_string()));
}

// ---------------------------------------------------------------------------------------------
// Route XML

proptest! {
    #![proptest_config(PropConfig { cases: 300, ..PropConfig::default() })]

    /// Arbitrary text and XML-ish text: no panic; an error names the file and where.
    #[test]
    fn route_xml_any_text(
        s in prop_oneof![
            any::<String>(),
            "<routes>(<route( id=\"[0-9]{1,3}\")?( town=\"T\")?>(<waypoints>(<position( x=\"[-0-9.eEnaif]{0,5}\")?( y=\"[-0-9.]{0,5}\")?/>){0,4}</waypoints>)?</route>){0,3}(</routes>)?",
        ]
    ) {
        match route::parse_route_xml(&s) {
            Ok(set) => {
                for r in set.iter() {
                    if let Ok(ok) = set.get_checked(&r.id) {
                        prop_assert!(!ok.waypoints.is_empty());
                        prop_assert!(ok.waypoints.iter().flatten().all(|v| v.is_finite()));
                    }
                }
            }
            Err(e) => prop_assert!(e.to_string().contains("<memory>"), "{}", e),
        }
    }
}

#[test]
fn route_xml_bad_cases() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("routes.xml");
    std::fs::write(&p, "<routes><route id=\"1\"><waypoints><position x=\"1\" y=\"2\"/></waypoint></route></routes>").unwrap();
    let e = route::read_route_xml(&p).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("routes.xml") && msg.contains("line 1"),
        "{msg}"
    );

    let set = route::parse_route_xml(
        "<routes><route id=\"1\" town=\"T\"><waypoints></waypoints></route>\
         <route id=\"2\"><waypoints><position x=\"1\" y=\"nan\"/></waypoints></route>\
         <route id=\"3\"><waypoints><position x=\"1\" y=\"2\"/><position x=\"3\" y=\"2\"/></waypoints></route></routes>",
    )
    .unwrap();
    assert!(matches!(
        set.get_checked("1"),
        Err(route::RouteError::NoWaypoints { .. })
    ));
    let e = set.get_checked("2").unwrap_err().to_string();
    assert!(e.contains("route 2") && e.contains("waypoint 0"), "{e}");
    let e = set.get_checked("42").unwrap_err().to_string();
    assert!(e.contains("route 42") && e.contains("not found"), "{e}");
    assert_eq!(set.get("3").unwrap().waypoints.len(), 2);
    // A file that is a directory, or absent: an error naming it.
    let e = route::read_route_xml(dir.path()).unwrap_err().to_string();
    assert!(e.contains(&dir.path().display().to_string()), "{e}");
}

// ---------------------------------------------------------------------------------------------
// Entry points added by issue 12 (mirrored by the fuzz targets labels, settings, json_keys).

mod issue12 {
    use monitor_host::input::json_keys::first_duplicate_key;
    use monitor_host::input::labels::{parse_labels, LabelsError};
    use monitor_host::Settings;
    use proptest::prelude::*;

    /// Text near the label formats: keys, commas, tabs, quotes, braces, control characters.
    fn label_text() -> impl Strategy<Value = String> {
        proptest::collection::vec(
            prop_oneof![
                Just("Accident".to_string()),
                Just("7".to_string()),
                Just(",".to_string()),
                Just("\t".to_string()),
                Just("\n".to_string()),
                Just("\"".to_string()),
                Just("{".to_string()),
                Just("}".to_string()),
                Just(":".to_string()),
                Just("#".to_string()),
                Just("=cmd".to_string()),
                Just("\u{1b}[2K".to_string()),
                "[ -~]{0,6}",
            ],
            0..40,
        )
        .prop_map(|parts| parts.concat())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Never panics; errors name the file; a duplicate key is refused, never resolved.
        #[test]
        fn labels_any_text(text in label_text()) {
            match parse_labels(&text, "labels.csv") {
                Ok(map) => {
                    // Every CSV key appears once: no line was silently overridden.
                    if !text.trim_start().starts_with('{') {
                        let lines = text.lines().filter(|l| !l.trim().is_empty()).count();
                        prop_assert!(map.len() <= lines);
                    }
                }
                Err(e) => {
                    prop_assert!(e.to_string().contains("labels.csv"), "{}", e);
                    if let LabelsError::Duplicate { key, .. } = &e {
                        prop_assert!(text.contains(key.as_str()) || text.contains('\\'), "{:?}", key);
                    }
                }
            }
        }

        /// `Settings::set` with any name and value: never panics; accepted => the whole is
        /// valid; refused => unchanged.
        #[test]
        fn settings_any_name_and_value(
            name in prop_oneof![
                proptest::sample::select(Settings::NAMES.to_vec()).prop_map(String::from),
                "[a-z_.]{0,20}",
            ],
            value in prop_oneof![
                Just("NaN".to_string()), Just("inf".to_string()), Just("-1".to_string()),
                Just("1e-45".to_string()), Just("65535".to_string()), Just("0".to_string()),
                Just("b2d-legacy".to_string()), Just("".to_string()),
                any::<f64>().prop_map(|x| x.to_string()),
                "[ -~]{0,12}",
            ],
        ) {
            let mut s = Settings::default();
            let before = s.clone();
            match s.set(&name, &value) {
                Ok(()) => prop_assert!(s.validate().is_ok(), "{}={} accepted but invalid", name, value),
                Err(_) => prop_assert!(s == before, "{}={} refused but changed", name, value),
            }
        }

        /// Duplicate keys are found exactly: compare with the number of keys serde_json keeps.
        #[test]
        fn json_keys_exact(
            keys in proptest::collection::vec(proptest::sample::select(vec!["a", "b", "c", "route_id"]), 0..6),
            nest in 0usize..4,
        ) {
            let inner: Vec<String> = keys.iter().enumerate().map(|(i, k)| format!("\"{k}\": {i}")).collect();
            let mut doc = format!("{{{}}}", inner.join(", "));
            for _ in 0..nest {
                doc = format!("{{\"records\": [{doc}]}}");
            }
            let distinct: std::collections::HashSet<_> = keys.iter().collect();
            let dup = first_duplicate_key(doc.as_bytes()).unwrap();
            prop_assert_eq!(dup.is_some(), distinct.len() < keys.len(), "{}", doc);
            if let Some(path) = dup {
                prop_assert_eq!(path.matches("records[0]").count(), nest);
            }
        }

        /// Any bytes: never panics.
        #[test]
        fn json_keys_any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
            let _ = first_duplicate_key(&bytes);
        }
    }

    #[test]
    fn json_keys_deep_nesting_is_an_error_not_a_stack_overflow() {
        let deep = "[".repeat(100_000);
        assert!(first_duplicate_key(deep.as_bytes()).is_err());
    }
}
