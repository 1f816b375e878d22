//! Robustness: every class of f32 in every field, misuse of the state machine, impossible
//! configurations, extreme but finite routes, and the fixed size of the monitor.

use crate::common::{comfort_verdicts, run};
use monitor_core::{
    Collisions, Config, ConfigError, Factors, Field, Frame, FrameError, Monitor, MonitorError,
    Profile, MONITOR_SIZE,
};

/// A route prefix that leaves state everywhere: brakes in the window, a half-full chunk, a
/// lateral maximum, counts.
fn warmed_up() -> Monitor {
    let mut m: Monitor = Monitor::new(Config::DEFAULT).unwrap();
    for i in 0..27 {
        let f = Frame {
            a_lon: if i % 5 == 0 { -1.0 } else { 0.3 },
            a_lat: 0.1 * i as f32,
            a_mag: 1.0,
            yaw_rate: 3.0,
            speed: 6.0,
            lat_err: if i % 3 == 0 { Some(1.2) } else { None },
            collisions: if i == 22 {
                Collisions {
                    vehicle: 1,
                    ..Collisions::NONE
                }
            } else {
                Collisions::NONE
            },
        };
        m.push(&f).unwrap();
    }
    m
}

fn set(f: &mut Frame, field: Field, v: f32) {
    match field {
        Field::ALon => f.a_lon = v,
        Field::ALat => f.a_lat = v,
        Field::AMag => f.a_mag = v,
        Field::YawRate => f.yaw_rate = v,
        Field::Speed => f.speed = v,
        Field::LatErr => f.lat_err = Some(v),
    }
}

const FIELDS: [Field; 6] = [
    Field::ALon,
    Field::ALat,
    Field::AMag,
    Field::YawRate,
    Field::Speed,
    Field::LatErr,
];

#[test]
fn every_bit_pattern_class_in_every_field() {
    let sub = f32::from_bits(1); // smallest subnormal
    let sub_max = f32::from_bits(0x007f_ffff); // largest subnormal
    let nan_payload = f32::from_bits(0x7fc0_1234);
    let neg_nan = f32::from_bits(0xffc0_0000);
    let classes: [(&str, f32); 12] = [
        ("NaN", f32::NAN),
        ("NaN payload", nan_payload),
        ("-NaN", neg_nan),
        ("+inf", f32::INFINITY),
        ("-inf", f32::NEG_INFINITY),
        ("+subnormal", sub),
        ("-subnormal", -sub),
        ("max subnormal", sub_max),
        ("+huge", f32::MAX),
        ("-huge", f32::MIN),
        ("-0", -0.0),
        ("min normal", f32::MIN_POSITIVE),
    ];
    for field in FIELDS {
        for (name, v) in classes {
            let mut m = warmed_up();
            let before = format!("{m:?}");
            let summary = *m.summary();
            let mut f = crate::common::cruise();
            set(&mut f, field, v);
            let r = m.push(&f);
            // The documented rule (Frame::validate): non-finite -> NonFinite(field); a negative
            // speed or a_mag -> Negative(field) (-0 is not negative); anything else is valid.
            let expected = if !v.is_finite() {
                Err(MonitorError::Frame(FrameError::NonFinite(field)))
            } else if v < 0.0 && matches!(field, Field::Speed | Field::AMag) {
                Err(MonitorError::Frame(FrameError::Negative(field)))
            } else {
                Ok(())
            };
            match (&r, expected) {
                (Err(e), Err(want)) => {
                    assert_eq!(*e, want, "{field:?} = {name}");
                    // Nothing changed: not the counts, not the buffers, not the window.
                    assert_eq!(format!("{m:?}"), before, "{field:?} = {name}");
                    assert_eq!(*m.summary(), summary);
                }
                (Ok(_), Ok(())) => assert_eq!(m.frames(), summary.frames + 1),
                _ => panic!("{field:?} = {name}: got {r:?}, want {expected:?}"),
            }
            // The route goes on (and ends) without panicking either way.
            for _ in 0..30 {
                m.push(&crate::common::cruise()).unwrap();
            }
            m.finish().unwrap();
        }
    }
}

#[test]
fn a_refused_frame_leaves_no_trace() {
    // Two monitors, one of which sees bad frames between the good ones: same final result.
    let mut a = warmed_up();
    let mut b = warmed_up();
    let good = |i: usize| Frame {
        a_lon: (i as f32 * 0.37).sin(),
        a_lat: (i as f32 * 0.11).cos(),
        a_mag: 1.0,
        yaw_rate: 20.0 * (i as f32 * 0.2).sin(),
        speed: 4.0,
        lat_err: Some(0.9 + 0.01 * i as f32),
        collisions: if i.is_multiple_of(17) {
            Collisions {
                layout: 1,
                ..Collisions::NONE
            }
        } else {
            Collisions::NONE
        },
    };
    for i in 0..60 {
        let mut bad = good(i);
        bad.lat_err = Some(f32::NAN);
        bad.collisions.vehicle = 3;
        assert!(b.push(&bad).is_err());
        assert_eq!(a.push(&good(i)).unwrap(), b.push(&good(i)).unwrap());
    }
    assert_eq!(a.finish().unwrap(), b.finish().unwrap());
}

#[test]
fn the_first_bad_field_is_named() {
    // Fields are checked in declaration order; non-finite before negative.
    let f = Frame {
        a_lat: f32::NAN,
        speed: f32::INFINITY,
        ..Frame::default()
    };
    assert_eq!(f.validate(), Err(FrameError::NonFinite(Field::ALat)));
    let g = Frame {
        speed: -1.0,
        lat_err: Some(f32::NAN),
        ..Frame::default()
    };
    assert_eq!(g.validate(), Err(FrameError::NonFinite(Field::LatErr)));
    let h = Frame {
        speed: -1.0,
        a_mag: -1.0,
        ..Frame::default()
    };
    assert_eq!(h.validate(), Err(FrameError::Negative(Field::Speed)));
}

#[test]
fn misuse_of_the_state_machine() {
    let mut m: Monitor = Monitor::new(Config::DEFAULT).unwrap();
    m.push(&Frame::default()).unwrap();
    let done = m.finish().unwrap();
    assert!(m.is_finished());
    // Push after finish: refused, nothing counted.
    assert_eq!(m.push(&Frame::default()), Err(MonitorError::Finished));
    assert_eq!(m.frames(), 1);
    // Finish twice: refused.
    assert_eq!(m.finish(), Err(MonitorError::Finished));
    assert_eq!(*m.summary(), done.summary);
    // A bad frame after finish: Finished first.
    let nan = Frame {
        a_lon: f32::NAN,
        ..Frame::default()
    };
    assert_eq!(m.push(&nan), Err(MonitorError::Finished));
    // reset starts a new route.
    m.reset();
    assert!(!m.is_finished());
    assert_eq!(m.frames(), 0);
    m.push(&Frame::default()).unwrap();
    assert_eq!(m.finish().unwrap().summary.frames, 1);
    // Finishing an empty route is fine: all zero.
    let mut e: Monitor = Monitor::new(Config::DEFAULT).unwrap();
    let d = e.finish().unwrap();
    assert!(d.events.is_empty());
    assert_eq!(d.summary, monitor_core::RouteSummary::default());
}

#[test]
fn impossible_configurations_are_refused() {
    let d = Config::DEFAULT;
    let cases: Vec<(Config, ConfigError)> = vec![
        (Config { chunk_len: 21, ..d }, ConfigError::ChunkLen),
        (Config { min_chunk: 6, ..d }, ConfigError::MinChunk),
        (Config { min_chunk: 0, ..d }, ConfigError::MinChunk),
        (
            Config {
                chunk_len: 8,
                min_chunk: 9,
                ..d
            },
            ConfigError::ChunkLen,
        ),
        (
            Config {
                decel_window: 21,
                ..d
            },
            ConfigError::DecelWindow,
        ),
        (Config { dt: 0.0, ..d }, ConfigError::Dt),
        (Config { dt: -0.05, ..d }, ConfigError::Dt),
        (Config { dt: f32::NAN, ..d }, ConfigError::Dt),
        (
            Config {
                dt: f32::INFINITY,
                ..d
            },
            ConfigError::Dt,
        ),
        (
            Config {
                legacy_jerk_spacing: 0.0,
                ..d
            },
            ConfigError::LegacySpacing,
        ),
        (
            Config {
                legacy_jerk_spacing: f32::NAN,
                ..d
            },
            ConfigError::LegacySpacing,
        ),
        (Config { slack: -0.1, ..d }, ConfigError::Slack),
        (
            Config {
                slack: f32::NAN,
                ..d
            },
            ConfigError::Slack,
        ),
        (
            Config {
                anomalous_excess: -0.25,
                ..d
            },
            ConfigError::ExcessBands,
        ),
        (
            Config {
                anomalous_excess: 0.7,
                ..d
            },
            ConfigError::ExcessBands,
        ),
        (
            Config {
                critical_excess: f32::NAN,
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
                decel_threshold: f32::NAN,
                ..d
            },
            ConfigError::DecelThreshold,
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
                stationary_speed: f32::NAN,
                ..d
            },
            ConfigError::StationarySpeed,
        ),
    ];
    let mut cases = cases;
    let bounds = [
        |c: &mut Config| c.bounds.lat_acc = -4.89,
        |c: &mut Config| c.bounds.mag_jerk = 0.0,
        |c: &mut Config| c.bounds.lon_jerk = f32::NAN,
        |c: &mut Config| c.bounds.yaw_acc = f32::INFINITY,
        |c: &mut Config| c.bounds.yaw_rate = -0.95,
        |c: &mut Config| c.bounds.lon_acc_min = 3.0, // above lon_acc_max
        |c: &mut Config| c.bounds.lon_acc_max = f32::NAN,
    ];
    for edit in bounds {
        let mut c = d;
        edit(&mut c);
        cases.push((c, ConfigError::Bounds));
    }
    let factors = [
        Factors {
            nodecel: 1.1,
            ..Factors::DEFAULT
        },
        Factors {
            anomalous: -0.1,
            ..Factors::DEFAULT
        },
        Factors {
            critical: f64::NAN,
            ..Factors::DEFAULT
        },
        Factors {
            workzone: 2.0,
            ..Factors::DEFAULT
        },
        Factors {
            layout: 0.0,
            ..Factors::DEFAULT
        },
        Factors {
            layout: f64::INFINITY,
            ..Factors::DEFAULT
        },
    ];
    for f in factors {
        cases.push((Config { factors: f, ..d }, ConfigError::Factor));
    }
    for (c, want) in cases {
        assert_eq!(c.validate(20), Err(want), "{c:?}");
        assert_eq!(Monitor::<20>::new(c).err(), Some(want), "{c:?}");
    }
    // The limits themselves are fine: chunk_len = capacity, min_chunk = 7, window = capacity,
    // factors 0 and 1, slack 0, equal bands.
    let edge = Config {
        chunk_len: 7,
        min_chunk: 7,
        decel_window: 7,
        slack: 0.0,
        anomalous_excess: 0.5,
        critical_excess: 0.5,
        factors: Factors {
            workzone: 0.0,
            nodecel: 1.0,
            ..Factors::DEFAULT
        },
        ..d
    };
    assert!(Monitor::<7>::new(edge).is_ok());
    // A capacity below the filter window can hold no valid configuration.
    assert_eq!(
        Monitor::<6>::new(Config {
            chunk_len: 6,
            min_chunk: 6,
            ..d
        })
        .err(),
        Some(ConfigError::MinChunk)
    );
    assert_eq!(Monitor::<6>::new(d).err(), Some(ConfigError::ChunkLen));
}

#[test]
fn an_extreme_but_finite_route_fails_every_bound_without_panicking() {
    for profile in [Profile::Physical, Profile::B2dLegacy] {
        for sign in [1.0f32, -1.0] {
            let c = Config {
                profile,
                ..Config::DEFAULT
            };
            let f = Frame {
                a_lon: sign * f32::MAX,
                a_lat: sign * f32::MAX,
                a_mag: f32::MAX,
                yaw_rate: sign * f32::MAX,
                speed: f32::MAX,
                lat_err: Some(sign * f32::MAX),
                collisions: Collisions {
                    pedestrian: u16::MAX,
                    vehicle: u16::MAX,
                    layout: u16::MAX,
                    workzone: u16::MAX,
                },
            };
            let (events, done) = run(c, &vec![f; 41]);
            let s = done.summary;
            // Every comfort chunk fails all six bounds (overflowing sums are inf or NaN, and a
            // NaN compares false, i.e. fails).
            let v = comfort_verdicts(&events);
            assert_eq!(v.len(), 2);
            for v in v {
                let x = v.failed;
                assert!(
                    x.lon_acc && x.lat_acc && x.mag_jerk && x.lon_jerk && x.yaw_acc && x.yaw_rate,
                    "{profile:?} {sign}: {x:?}"
                );
            }
            assert_eq!(s.comfort.comfortable, 0);
            assert_eq!(s.comfort.failed.yaw_rate, 2);
            // Every lateral chunk is critical. 4 · 65535 = 262140 collisions per frame, 41
            // frames; frame 0's are exempt; the others are nodecel at +MAX, while at -MAX every
            // earlier a_lon = -MAX <= -0.5 is a deceleration.
            assert_eq!((s.lateral.chunks, s.lateral.critical), (3, 3));
            assert_eq!(s.collisions.aligned, 41 * 262_140);
            assert_eq!(s.collisions.exempt, 262_140);
            let nodecel = if sign > 0.0 { 40 * 262_140 } else { 0 };
            assert_eq!(s.collisions.nodecel, nodecel);
        }
    }
    // Alternating ±MAX: also no panic, also all failed.
    let alt: Vec<Frame> = (0..20)
        .map(|i| {
            let s = if i % 2 == 0 { f32::MAX } else { f32::MIN };
            Frame {
                a_lon: s,
                a_lat: s,
                a_mag: f32::MAX * (i % 2) as f32,
                yaw_rate: s,
                speed: 1.0,
                lat_err: None,
                collisions: Collisions::NONE,
            }
        })
        .collect();
    for profile in [Profile::Physical, Profile::B2dLegacy] {
        let c = Config {
            profile,
            ..Config::DEFAULT
        };
        let (events, _) = run(c, &alt);
        assert!(!comfort_verdicts(&events)[0].failed.comfortable());
    }
}

#[test]
fn the_monitor_has_a_fixed_small_size() {
    let size = core::mem::size_of::<Monitor>();
    eprintln!("size_of::<Monitor>() = {size} bytes (MONITOR_SIZE = {MONITOR_SIZE})");
    assert_eq!(MONITOR_SIZE, size);
    assert!(size <= 1024);
    // The layout of the parts (ChunkBuffer, LateralChunk, DecelWindow are internal) is checked
    // by the unit test `monitor::tests::state_layout`.
    assert_eq!(MONITOR_SIZE, 664);
    // A monitor is plain data: buildable in a static, no allocation.
    static M: Monitor = Monitor::new_static(Config::DEFAULT);
    assert_eq!(M.frames(), 0);
    let d = Monitor::default();
    assert_eq!(
        format!("{d:?}"),
        format!("{:?}", Monitor::<20>::new(Config::DEFAULT).unwrap())
    );
}

/// The capacity is bounded, so the chunk-end stack is too (`MAX_CAPACITY`, docs/RELIABILITY.md):
/// `Monitor<65535>` needed ~2.4 MB of stack at a chunk end and overflowed a default thread.
#[test]
fn capacity_is_bounded_and_the_largest_monitor_runs_on_a_small_stack() {
    assert_eq!(
        Config::DEFAULT.validate(monitor_core::MAX_CAPACITY + 1),
        Err(ConfigError::Capacity)
    );
    assert_eq!(
        Monitor::<{ monitor_core::MAX_CAPACITY + 1 }>::new(Config::DEFAULT).err(),
        Some(ConfigError::Capacity)
    );
    // The largest capacity a u16 chunk length could ask for: refused too. Its `Result` alone is
    // 1 MiB, which an unoptimised build keeps on the stack several times over: a thread big
    // enough for that (this checks the refusal, not a stack budget).
    let refused = std::thread::Builder::new()
        .stack_size(64 * 1024 * 1024)
        .spawn(|| Monitor::<65535>::new(Config::DEFAULT).err())
        .unwrap()
        .join()
        .unwrap();
    assert_eq!(refused, Some(ConfigError::Capacity));
    // The largest accepted monitor, with chunks as long as it allows, on a 128 KiB thread: the
    // budget holds in both profiles (measured: debug and release both pass at 128 KiB).
    const STACK: usize = 128 * 1024;
    eprintln!(
        "stack budget {} KiB ({} build)",
        STACK / 1024,
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        }
    );
    let h = std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(|| {
            let n = monitor_core::MAX_CAPACITY;
            let config = Config {
                chunk_len: n as u16,
                ..Config::DEFAULT
            };
            let mut m = Box::new(Monitor::<{ monitor_core::MAX_CAPACITY }>::new(config).unwrap());
            let f = Frame::from_vectors(
                [0.5, 0.1],
                [1.0, 0.0],
                [0.0, 1.0],
                3.0,
                5.0,
                Some(0.3),
                Collisions::NONE,
            );
            for _ in 0..(2 * n + 7) {
                m.push(&f).unwrap();
            }
            m.finish().unwrap().summary.comfort.chunks
        })
        .unwrap();
    // Two full chunks of 1024 frames were evaluated (and the route finished).
    assert!(h.join().unwrap() >= 2);
}
