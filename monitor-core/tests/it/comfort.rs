//! Comfort (docs/SCORE.md §5): the six strict bounds, exactly at and just inside each bound, and
//! the physical profile's degree-to-radian conversion.
//!
//! A filtered value that equals a bound to the bit is hard to write by hand, so each test crafts
//! it: a one-parameter family of routes (a constant or a ramp), the spec's pipeline recomputed
//! here with the public kernels (`SG`, `SG'`), and a scan over consecutive f32 parameters for one
//! whose filtered extreme has exactly the bound's bits (asserted before the monitor sees it).

use crate::common::{comfort_verdicts, run};
use monitor_core::sg::{self, DERIVATIVE, VALUE};
use monitor_core::signal::DEG_TO_RAD;
use monitor_core::{Config, Failures, Frame};

/// The six filtered series of one chunk, physical profile (docs/SCORE.md §5):
/// lon, lat, mag_jerk, lon_jerk, yaw_acc, yaw_rate.
struct Series {
    lon: Vec<f32>,
    lat: Vec<f32>,
    mag_jerk: Vec<f32>,
    lon_jerk: Vec<f32>,
    yaw_acc: Vec<f32>,
    yaw_rate: Vec<f32>,
}

fn sgf(x: &[f32], rows: &sg::Rows, h: Option<f32>) -> Vec<f32> {
    let mut out = vec![0.0; x.len()];
    assert!(sg::filter(x, rows, h, &mut out));
    out
}

fn series(frames: &[Frame], dt: f32) -> Series {
    let col = |f: fn(&Frame) -> f32| frames.iter().map(f).collect::<Vec<f32>>();
    let lon = sgf(&col(|f| f.a_lon), &VALUE, None);
    let lat = sgf(&col(|f| f.a_lat), &VALUE, None);
    let mag = sgf(&col(|f| f.a_mag), &VALUE, None);
    let yaw_rate = sgf(&col(|f| f.yaw_rate * DEG_TO_RAD), &VALUE, None);
    Series {
        lon_jerk: sgf(&lon, &DERIVATIVE, Some(dt)),
        mag_jerk: sgf(&mag, &DERIVATIVE, Some(dt)),
        yaw_acc: sgf(&yaw_rate, &DERIVATIVE, Some(dt)),
        lon,
        lat,
        yaw_rate,
    }
}

fn max(v: &[f32]) -> f32 {
    v.iter().copied().fold(f32::NEG_INFINITY, f32::max)
}
fn min(v: &[f32]) -> f32 {
    v.iter().copied().fold(f32::INFINITY, f32::min)
}

/// One bound under test.
struct Case {
    name: &'static str,
    /// Builds the route from the parameter and a variant (a shift or a length), 0..VARIANTS.
    route: fn(f32, usize) -> Vec<Frame>,
    /// The extreme of the relevant series that should hit the bound.
    extreme: fn(&Series) -> f32,
    /// The bound's value (upper bounds positive, lower bounds negative).
    bound: f32,
    /// Approximate parameter that reaches the bound.
    guess: f32,
    /// The step period (`Config::dt`).
    dt: f32,
    /// The one failure expected at the bound.
    failed: Failures,
}

fn step(x: f32, up: bool) -> f32 {
    if up {
        x.next_up()
    } else {
        x.next_down()
    }
}

/// Variants of each family tried in turn: a family's filtered outputs lie on a grid that may
/// skip the bound's float, and a shifted or shorter route has another grid.
const VARIANTS: usize = 32;

/// Scans consecutive f32 parameters around `guess`, variant by variant, for a route whose
/// extreme has `target`'s bits.
fn find(case: &Case, target: f32) -> (f32, usize) {
    for v in 0..VARIANTS {
        let eval = |p: f32| (case.extreme)(&series(&(case.route)(p, v), case.dt));
        let (mut up, mut down) = (case.guess, case.guess);
        for _ in 0..20_000 {
            for p in [up, down] {
                if eval(p).to_bits() == target.to_bits() {
                    return (p, v);
                }
            }
            up = step(up, true);
            down = step(down, false);
        }
    }
    panic!(
        "{}: no parameter near {} reaches {target:e}",
        case.name, case.guess
    );
}

fn verdict(route: &[Frame]) -> Failures {
    verdict_dt(route, Config::DEFAULT.dt)
}

fn verdict_dt(route: &[Frame], dt: f32) -> Failures {
    let (events, done) = run(
        Config {
            dt,
            ..Config::DEFAULT
        },
        route,
    );
    let v = comfort_verdicts(&events);
    assert_eq!(v.len(), 1, "one comfort chunk");
    assert_eq!(done.summary.comfort.chunks, 1);
    v[0].failed
}

/// `20 - v % 13` (8..=20) frames of `f(c)`.
fn constant(c: f32, v: usize, f: impl Fn(f32) -> Frame) -> Vec<Frame> {
    (0..20 - v % 13).map(|_| f(c)).collect()
}

fn cases() -> Vec<Case> {
    let only = |f: fn(&mut Failures)| {
        let mut x = Failures::default();
        f(&mut x);
        x
    };
    vec![
        Case {
            // a_lon = c on 20 frames: SG(c) ≈ c at every position (rows sum to 1), jerk ≈ 0.
            name: "lon_acc upper 2.40",
            route: |c, v| {
                constant(c, v, |c| Frame {
                    a_lon: c,
                    ..Frame::default()
                })
            },
            extreme: |s| max(&s.lon),
            bound: 2.40,
            guess: 2.40,
            failed: only(|f| f.lon_acc = true),
            dt: 0.05,
        },
        Case {
            name: "lon_acc lower -4.05",
            route: |c, v| {
                constant(c, v, |c| Frame {
                    a_lon: c,
                    ..Frame::default()
                })
            },
            extreme: |s| min(&s.lon),
            bound: -4.05,
            guess: -4.05,
            failed: only(|f| f.lon_acc = true),
            dt: 0.05,
        },
        Case {
            name: "lat_acc +4.89",
            route: |c, v| {
                constant(c, v, |c| Frame {
                    a_lat: c,
                    ..Frame::default()
                })
            },
            extreme: |s| max(&s.lat),
            bound: 4.89,
            guess: 4.89,
            failed: only(|f| f.lat_acc = true),
            dt: 0.05,
        },
        Case {
            name: "lat_acc -4.89",
            route: |c, v| {
                constant(c, v, |c| Frame {
                    a_lat: c,
                    ..Frame::default()
                })
            },
            extreme: |s| min(&s.lat),
            bound: -4.89,
            guess: -4.89,
            failed: only(|f| f.lat_acc = true),
            dt: 0.05,
        },
        Case {
            // a_mag_i = c·(i + v) (v < 32, a_mag >= 0): mag_jerk = c / 0.05; 8.37 · 0.05 = 0.4185.
            name: "mag_jerk 8.37",
            route: |c, v| {
                (0..20)
                    .map(|i| Frame {
                        a_mag: c * (i + v) as f32,
                        ..Frame::default()
                    })
                    .collect()
            },
            extreme: |s| max(&s.mag_jerk),
            bound: 8.37,
            guess: 0.4185,
            failed: only(|f| f.mag_jerk = true),
            dt: 0.05,
        },
        Case {
            // a_lon_i = c·(i - v) on a 12-frame route (one short chunk): lon within
            // [-1.04, 2.27] (inside its bounds), lon_jerk = c / 0.05; 4.13 · 0.05 = 0.2065.
            name: "lon_jerk 4.13",
            route: |c, v| {
                let v = (v % 6) as f32;
                (0..12)
                    .map(|i| Frame {
                        a_lon: c * (i as f32 - v),
                        ..Frame::default()
                    })
                    .collect()
            },
            extreme: |s| max(&s.lon_jerk),
            bound: 4.13,
            guess: 0.2065,
            failed: only(|f| f.lon_jerk = true),
            dt: 0.05,
        },
        Case {
            // 10-frame route (one short chunk), dt = 1/16 (see
            // `yaw_acc_of_exactly_1_93_is_unreachable_with_dt_0_05`): yaw_i = c·(i - 5) deg/s; in
            // rad/s the slope is c·π/180 per frame and yaw_acc = that · 16 = 1.93 at
            // c = 1.93 / 16 · 180/π ≈ 6.9113.
            name: "yaw_acc 1.93",
            route: |c, v| {
                // Plus an offset of 0.37·v deg/s (at most 11.5 deg/s = 0.2 rad/s), which shifts
                // the rounding pattern but not the slope: |yaw rate| <= 0.48 + 0.2 rad/s.
                let o = 0.37 * v as f32;
                (0..10)
                    .map(|i| Frame {
                        yaw_rate: c * (i as f32 - 5.0) + o,
                        ..Frame::default()
                    })
                    .collect()
            },
            extreme: |s| max(&s.yaw_acc),
            bound: 1.93,
            guess: 6.9113,
            dt: 0.0625,
            failed: only(|f| f.yaw_acc = true),
        },
        Case {
            // yaw = c deg/s: c·π/180 = 0.95 rad/s at c ≈ 54.431. Consecutive c differ by
            // 3.8e-6 deg/s = 6.7e-8 rad/s, more than an ulp of 0.95 (6e-8): a constant skips
            // floats of the yaw rate, so the variants add a ripple of at most 2e-4·31·4 = 0.025
            // deg/s ((7i mod 5) · 2e-4 · v) that changes the rounding, not the verdict.
            name: "yaw_rate 0.95",
            route: |c, v| {
                (0..20)
                    .map(|i| Frame {
                        yaw_rate: c + 2e-4 * (v * ((7 * i) % 5)) as f32,
                        ..Frame::default()
                    })
                    .collect()
            },
            extreme: |s| max(&s.yaw_rate),
            bound: 0.95,
            guess: 54.431,
            failed: only(|f| f.yaw_rate = true),
            dt: 0.05,
        },
    ]
}

#[test]
fn a_value_exactly_on_each_bound_fails() {
    for case in cases() {
        let (p, v) = find(&case, case.bound);
        let route = (case.route)(p, v);
        // The crafted route really has a filtered value with the bound's bits ...
        let s = series(&route, case.dt);
        assert_eq!(
            (case.extreme)(&s).to_bits(),
            case.bound.to_bits(),
            "{}",
            case.name
        );
        // ... and the strict comparison fails exactly that bound.
        assert_eq!(
            verdict_dt(&route, case.dt),
            case.failed,
            "{} at the bound",
            case.name
        );
    }
}

#[test]
fn a_value_just_inside_each_bound_passes() {
    for case in cases() {
        // From the parameter that hits the bound, step the parameter towards the inside until the
        // extreme is strictly inside: the nearest value the family reaches below the bound (the
        // filtered outputs lie on a grid, so not every float is reachable), within 8 ulps of it.
        let (p0, var) = find(&case, case.bound);
        let eval = |p: f32| (case.extreme)(&series(&(case.route)(p, var), case.dt));
        let towards_inside = (eval(step(p0, true)) < eval(p0)) == (case.bound > 0.0);
        let mut p = p0;
        let mut v = eval(p);
        while v.to_bits() == case.bound.to_bits() {
            p = step(p, towards_inside);
            v = eval(p);
        }
        let ulps = (v.to_bits() as i64 - case.bound.to_bits() as i64).abs();
        assert!(
            v.abs() < case.bound.abs() && ulps <= 8,
            "{}: {v:e} ({ulps} ulps)",
            case.name
        );
        let route = (case.route)(p, var);
        assert_eq!(
            verdict_dt(&route, case.dt),
            Failures::default(),
            "{} just inside",
            case.name
        );
    }
}

#[test]
fn physical_profile_converts_degrees_to_radians() {
    // 50 deg/s · π/180 = 0.87266 rad/s < 0.95: comfortable (a constant has no yaw acceleration).
    assert!((50.0f32 * DEG_TO_RAD - 0.872_664_6).abs() < 1e-6);
    let f = Failures::default();
    let yaw = |d: f32| Frame {
        yaw_rate: d,
        ..Frame::default()
    };
    assert_eq!(verdict(&vec![yaw(50.0); 20]), f);
    assert_eq!(verdict(&vec![yaw(-50.0); 20]), f);
    // 60 deg/s = 1.0472 rad/s > 0.95: fails the yaw rate only.
    let yaw_rate = Failures {
        yaw_rate: true,
        ..f
    };
    assert_eq!(verdict(&vec![yaw(60.0); 20]), yaw_rate);
    assert_eq!(verdict(&vec![yaw(-60.0); 20]), yaw_rate);
}

#[test]
fn one_bad_frame_fails_its_chunk_and_only_its_chunk() {
    // 60 frames; a lateral spike of 20 m/s² at frame 25 (chunk 1). SG's centre weight 7/21
    // gives at least 20/3 ≈ 6.7 > 4.89 at frame 25 itself: chunk 1 fails lat_acc; 0 and 2 pass.
    let mut route = vec![Frame::default(); 60];
    route[25].a_lat = 20.0;
    let (events, done) = run(Config::DEFAULT, &route);
    let v = comfort_verdicts(&events);
    assert_eq!(v.len(), 3);
    assert_eq!(v.iter().map(|v| v.chunk).collect::<Vec<_>>(), [0, 1, 2]);
    assert!(v[0].failed.comfortable() && v[2].failed.comfortable());
    assert_eq!(
        v[1].failed,
        Failures {
            lat_acc: true,
            ..Failures::default()
        }
    );
    let c = done.summary.comfort;
    assert_eq!((c.chunks, c.comfortable, c.failed.lat_acc), (3, 2, 1));
    // C_route = 2 / 3.
    assert_eq!(done.summary.comfort_score(), Some(2.0 / 3.0));
}

#[test]
fn chunks_are_filtered_independently() {
    // A step from 0 to 2.3 m/s² exactly at the chunk boundary (frame 20): inside one chunk the
    // SG filter would smooth the step into a jerk of about (2.3 / 4 frames) / 0.05 s ≈ 11 m/s³;
    // filtered per chunk each chunk is constant, so both chunks are comfortable.
    let mut route = vec![Frame::default(); 40];
    for f in &mut route[20..] {
        f.a_lon = 2.3;
    }
    let (events, _) = run(Config::DEFAULT, &route);
    let v = comfort_verdicts(&events);
    assert_eq!(v.len(), 2);
    assert!(v.iter().all(|v| v.failed.comfortable()), "{v:?}");
    // The same step in the middle of a chunk (frame 10) fails lon_jerk.
    let mut route = vec![Frame::default(); 20];
    for f in &mut route[10..] {
        f.a_lon = 2.3;
    }
    let (events, _) = run(Config::DEFAULT, &route);
    assert!(comfort_verdicts(&events)[0].failed.lon_jerk);
}

#[test]
fn yaw_acc_of_exactly_1_93_is_unreachable_with_dt_0_05() {
    // yaw_acc = fl(x / 0.05) for the f32 x = SG' output. Near 1.93 the outputs are 2^-22 apart
    // (1.19e-7) while x / 0.05 moves by 20 · 2^-27 = 1.49e-7 per input float near 0.0965: the
    // image skips floats, and 1.93f32 is one of them. So with the default dt no route can put a
    // yaw acceleration exactly on its bound; the strictness test above uses dt = 1/16 (exact).
    let target = 1.93f32;
    let mut below = 0;
    let mut above = 0;
    let mut x = 0.0965f32;
    for _ in 0..2000 {
        x = x.next_down();
    }
    for _ in 0..4000 {
        let q = x / 0.05;
        assert_ne!(q.to_bits(), target.to_bits(), "x = {x:e}");
        if q < target {
            below += 1;
        } else {
            above += 1;
        }
        x = x.next_up();
    }
    // The scan straddles the target: it is skipped, not out of range.
    assert!(below > 0 && above > 0);
}
