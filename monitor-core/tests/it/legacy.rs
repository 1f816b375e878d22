//! The `b2d-legacy` comfort profile (docs/SCORE.md §5): yaw rate left in deg/s and phase-unwrapped
//! per chunk, yaw acceleration = the smoothed yaw rate itself, jerks over 0.1 s spacing.

use crate::common::{comfort_verdicts, run};
use monitor_core::sg::{self, DERIVATIVE, VALUE};
use monitor_core::signal::{self, unwrap};
use monitor_core::{Config, Failures, Frame, Profile};

const LEGACY: Config = Config {
    profile: Profile::B2dLegacy,
    ..Config::DEFAULT
};
/// τ = 2π in f32 = 6.2831854820251465 (exactly 2 · π_f32).
const TAU: f32 = core::f32::consts::TAU;

fn verdicts(config: Config, route: &[Frame]) -> Vec<Failures> {
    comfort_verdicts(&run(config, route).0)
        .into_iter()
        .map(|v| v.failed)
        .collect()
}

fn yaw(d: f32) -> Frame {
    Frame {
        yaw_rate: d,
        ..Frame::default()
    }
}

#[test]
fn legacy_keeps_degrees_per_second() {
    // 1 deg/s: legacy compares 1 > 0.95 (its "rad/s" bound): fails the yaw rate; 1 < 1.93 passes
    // the yaw "acceleration" (= SG(u) = 1). Physical: 1 deg/s = 0.01745 rad/s passes both.
    let f = Failures::default();
    assert_eq!(
        verdicts(LEGACY, &[yaw(1.0); 20]),
        [Failures {
            yaw_rate: true,
            ..f
        }]
    );
    assert_eq!(verdicts(Config::DEFAULT, &[yaw(1.0); 20]), [f]);
    // 0.94 deg/s passes in legacy (0.94 < 0.95).
    assert_eq!(verdicts(LEGACY, &[yaw(0.94); 20]), [f]);
}

#[test]
fn legacy_yaw_acc_is_the_smoothed_yaw_rate_not_its_derivative() {
    // A constant 1.95 deg/s has zero derivative, yet legacy compares SG(u) = 1.95 > 1.93 against
    // the yaw-acceleration bound: both yaw bounds fail.
    let both = Failures {
        yaw_rate: true,
        yaw_acc: true,
        ..Failures::default()
    };
    assert_eq!(verdicts(LEGACY, &[yaw(1.95); 20]), [both]);
    assert_eq!(verdicts(LEGACY, &[yaw(-1.95); 20]), [both]);
    // 1.9 deg/s: yaw rate only.
    let rate = Failures {
        yaw_rate: true,
        ..Failures::default()
    };
    assert_eq!(verdicts(LEGACY, &[yaw(1.9); 20]), [rate]);
}

#[test]
fn unwrap_by_hand() {
    // w = [0, 4, 8, 1] (deg/s, treated as radians by the 2π period):
    // j=1: (4-0)/τ = 0.637 -> 1;  j=2: (8-4)/τ = 0.637 -> 1;  j=3: (1-8)/τ = -1.114 -> -1.
    // Cumulative turns 1, 2, 1:
    // u0 = 0
    // u1 = 4 - τ   = 4 - 6.2831854820251465  = -2.2831854820251465 (exact in f32: ulp 2^-22)
    // u2 = 8 - 2τ  = 8 - 12.566370964050293  = -4.566370964050293  (exact: multiple of 2^-20)
    // u3 = 1 - τ   = 1 - 6.2831854820251465  = -5.2831854820251465 (exact: multiple of 2^-21)
    let mut u = [f32::NAN; 4];
    unwrap(&[0.0, 4.0, 8.0, 1.0], &mut u);
    let want = [
        0.0f64,
        -2.283_185_482_025_146_5,
        -4.566_370_964_050_293,
        -5.283_185_482_025_146_5,
    ];
    for (got, w) in u.iter().zip(want) {
        assert_eq!(*got as f64, w, "{u:?}");
    }
    // A jump of at most π is left alone: 3 / τ = 0.477 -> 0.
    unwrap(&[0.0, 3.0, 6.0, 9.0], &mut u);
    assert_eq!(u, [0.0, 3.0, 6.0, 9.0]);
    // Exactly π: π/τ = 0.5 exactly (τ = 2π in f32), ties to even -> 0: no unwrap; -π likewise.
    let pi = core::f32::consts::PI;
    let mut v = [f32::NAN; 3];
    unwrap(&[0.0, pi, 0.0], &mut v);
    assert_eq!(v, [0.0, pi, 0.0]);
    // Just above π: unwrapped to π_next - τ < 0.
    unwrap(&[0.0, pi.next_up(), 0.0], &mut v);
    assert_eq!(v, [0.0, pi.next_up() - TAU, 0.0]);
    // The output is shorter than the input: only that many values are written.
    let mut two = [f32::NAN; 2];
    unwrap(&[1.0, 8.0, 9.0], &mut two);
    assert_eq!(two, [1.0, 8.0 - TAU]);
}

#[test]
fn the_monitor_unwraps_the_legacy_yaw_rate() {
    // w alternates 0 and τ deg/s. Differences ±τ: turns +1, then 0, ...: u = all 0 exactly
    // (τ - τ·1 = 0, 0 - τ·0 = 0, ...). Without the unwrap SG(w) ≈ 3.14 would fail both bounds.
    let route: Vec<Frame> = (0..20)
        .map(|i| yaw(if i % 2 == 0 { 0.0 } else { TAU }))
        .collect();
    let mut u = [f32::NAN; 20];
    let w: Vec<f32> = route.iter().map(|f| f.yaw_rate).collect();
    unwrap(&w, &mut u);
    assert_eq!(u, [0.0; 20]);
    assert_eq!(verdicts(LEGACY, &route), [Failures::default()]);
}

#[test]
fn the_unwrap_restarts_in_every_chunk() {
    // Chunk 0: 20 frames of 0; chunk 1: 20 frames of τ. Restarted, chunk 1's u0 = w0 = τ: SG = τ
    // = 6.28 fails yaw rate and yaw acc. Unwrapped across the boundary it would be 0 and pass.
    let mut route = vec![yaw(0.0); 20];
    route.extend(vec![yaw(TAU); 20]);
    let both = Failures {
        yaw_rate: true,
        yaw_acc: true,
        ..Failures::default()
    };
    assert_eq!(verdicts(LEGACY, &route), [Failures::default(), both]);
}

#[test]
fn legacy_jerk_spacing_halves_the_jerk() {
    // a_lon_i = 0.25 (i - 10): lon in [-2.5, 2.25] (inside -4.05..2.40); slope 0.25 per frame.
    // physical: lon_jerk = 0.25 / 0.05 = 5 > 4.13 fails; legacy: 0.25 / 0.1 = 2.5 passes.
    // a_mag_i = 0.5 i: physical mag_jerk = 0.5 / 0.05 = 10 > 8.37; legacy 5 passes.
    let route: Vec<Frame> = (0..20)
        .map(|i| Frame {
            a_lon: 0.25 * (i as f32 - 10.0),
            a_mag: 0.5 * i as f32,
            ..Frame::default()
        })
        .collect();
    let jerks = Failures {
        lon_jerk: true,
        mag_jerk: true,
        ..Failures::default()
    };
    assert_eq!(verdicts(Config::DEFAULT, &route), [jerks]);
    assert_eq!(verdicts(LEGACY, &route), [Failures::default()]);
    // The two jerks differ by the spacing only: the same SG' output over 0.1 vs 0.05.
    let a: Vec<f32> = route.iter().map(|f| f.a_lon).collect();
    let mut lon = [0.0f32; 20];
    assert!(sg::filter(&a, &VALUE, None, &mut lon));
    let (mut p, mut l) = ([0.0f32; 20], [0.0f32; 20]);
    assert!(sg::filter(&lon, &DERIVATIVE, Some(0.05), &mut p));
    assert!(sg::filter(&lon, &DERIVATIVE, Some(0.1), &mut l));
    for (p, l) in p.iter().zip(&l) {
        assert!((p - 5.0).abs() < 1e-4 && (l - 2.5).abs() < 1e-4, "{p} {l}");
        assert!((p / l - 2.0).abs() < 1e-6);
    }
    // The spacing is the configured one: 0.025 s doubles the physical-looking jerk again.
    let fine = Config {
        legacy_jerk_spacing: 0.025,
        ..LEGACY
    };
    assert_eq!(verdicts(fine, &route), [jerks]);
}

#[test]
fn legacy_short_route_is_one_chunk() {
    // 7 <= n <= 20: one chunk of all n frames; n = 13 here, 1 deg/s fails the yaw rate.
    let (events, done) = run(LEGACY, &[yaw(1.0); 13]);
    let v = comfort_verdicts(&events);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0].frames, 13);
    assert!(v[0].failed.yaw_rate);
    assert_eq!(done.summary.comfort_score(), Some(0.0));
    // The legacy profile reports its name.
    assert_eq!(LEGACY.profile.name(), "b2d-legacy");
    assert_eq!(signal::round_half_even(-0.5), 0.0);
}
