//! Pre-collision deceleration (docs/SCORE.md §6): the raw a_lon of the 20 frames before the
//! collision frame (k-20 .. k-1), `a_lon <= -0.5` decelerates, `speed < 0.5` exempts, frame 0 is
//! exempt, every collision of a frame counts.

use crate::common::{collision_verdicts, cruise, run};
use monitor_core::{Collisions, Config, Frame};

const K: usize = 30;

fn hit(n: u16) -> Collisions {
    Collisions {
        vehicle: n,
        ..Collisions::NONE
    }
}

/// 40 cruising frames (5 m/s) with one vehicle collision at frame K; `edit` changes the route.
fn route(edit: impl FnOnce(&mut Vec<Frame>)) -> Vec<Frame> {
    let mut r = vec![cruise(); 40];
    r[K].collisions = hit(1);
    edit(&mut r);
    r
}

/// (aligned, exempt, nodecel) and the verdicts of the route.
fn outcome(r: &[Frame]) -> ((u32, u32, u32), Vec<monitor_core::CollisionVerdict>) {
    outcome_with(Config::DEFAULT, r)
}

fn outcome_with(c: Config, r: &[Frame]) -> ((u32, u32, u32), Vec<monitor_core::CollisionVerdict>) {
    let (events, done) = run(c, r);
    let s = done.summary.collisions;
    (
        (s.aligned, s.exempt, s.nodecel),
        collision_verdicts(&events),
    )
}

#[test]
fn threshold_is_inclusive() {
    // a_lon = -0.5 exactly at k-1: -0.5 <= -0.5: decelerated, not penalised.
    let (c, v) = outcome(&route(|r| r[K - 1].a_lon = -0.5));
    assert_eq!(c, (1, 0, 0));
    assert!(v[0].decelerated && !v[0].exempt && !v[0].nodecel());
    // -0.49999997 (the float just above -0.5) does not count: nodecel.
    assert_eq!((-0.5f32).next_up(), -0.499_999_97);
    let (c, v) = outcome(&route(|r| r[K - 1].a_lon = -0.499_999_97));
    assert_eq!(c, (1, 0, 1));
    assert!(!v[0].decelerated && v[0].nodecel());
}

#[test]
fn the_window_is_the_twenty_frames_before() {
    // k-20 is the oldest frame of the window: counts.
    assert_eq!(outcome(&route(|r| r[K - 20].a_lon = -3.0)).0, (1, 0, 0));
    // k-21 is outside it.
    assert_eq!(outcome(&route(|r| r[K - 21].a_lon = -3.0)).0, (1, 0, 1));
    // The collision frame itself is not in the window.
    let (c, v) = outcome(&route(|r| r[K].a_lon = -3.0));
    assert_eq!(c, (1, 0, 1));
    assert!(!v[0].decelerated);
    // Nor is any frame after it.
    assert_eq!(outcome(&route(|r| r[K + 1].a_lon = -3.0)).0, (1, 0, 1));
}

#[test]
fn a_configured_window_is_respected() {
    // decel_window 5: k-5 counts, k-6 does not.
    let c = Config {
        decel_window: 5,
        ..Config::DEFAULT
    };
    assert_eq!(
        outcome_with(c, &route(|r| r[K - 5].a_lon = -1.0)).0,
        (1, 0, 0)
    );
    assert_eq!(
        outcome_with(c, &route(|r| r[K - 6].a_lon = -1.0)).0,
        (1, 0, 1)
    );
    // decel_window 0: nothing can count.
    let c0 = Config {
        decel_window: 0,
        ..Config::DEFAULT
    };
    assert_eq!(
        outcome_with(c0, &route(|r| r[K - 1].a_lon = -9.0)).0,
        (1, 0, 1)
    );
}

#[test]
fn the_window_crosses_chunk_boundaries() {
    // Brake at frame 19 (chunk 0), collision at frame 25 (chunk 1): 25 - 19 = 6 <= 20.
    let mut r = vec![cruise(); 30];
    r[19].a_lon = -1.0;
    r[25].collisions = hit(1);
    assert_eq!(outcome(&r).0, (1, 0, 0));
}

#[test]
fn the_window_is_short_early_in_the_route() {
    // Collision at frame 3: the window is frames 0..3; a brake at frame 0 counts.
    let mut r = vec![cruise(); 10];
    r[3].collisions = hit(1);
    r[0].a_lon = -0.6;
    assert_eq!(outcome(&r).0, (1, 0, 0));
    r[0].a_lon = 0.0;
    assert_eq!(outcome(&r).0, (1, 0, 1));
}

#[test]
fn stationary_exemption_is_strict() {
    // speed exactly 0.5 is not below 0.5: not exempt, no brake: nodecel.
    let (c, v) = outcome(&route(|r| r[K].speed = 0.5));
    assert_eq!(c, (1, 0, 1));
    assert!(!v[0].exempt);
    assert_eq!(v[0].speed, 0.5);
    // 0.49999997 < 0.5: exempt.
    assert_eq!(0.5f32.next_down(), 0.499_999_97);
    let (c, v) = outcome(&route(|r| r[K].speed = 0.499_999_97));
    assert_eq!(c, (1, 1, 0));
    assert!(v[0].exempt && !v[0].nodecel());
    // Exempt whether or not it decelerated: counted exempt once, never nodecel.
    let (c, v) = outcome(&route(|r| {
        r[K].speed = 0.1;
        r[K - 1].a_lon = -2.0;
    }));
    assert_eq!(c, (1, 1, 0));
    assert!(v[0].exempt && v[0].decelerated);
}

#[test]
fn a_collision_at_frame_zero_is_exempt() {
    // Frame 0: empty window, exempt even at 10 m/s.
    let mut r = vec![cruise(); 5];
    r[0].collisions = hit(2);
    r[0].speed = 10.0;
    let (c, v) = outcome(&r);
    assert_eq!(c, (2, 2, 0));
    assert_eq!(v[0].frame, 0);
    assert!(v[0].exempt && !v[0].decelerated);
}

#[test]
fn every_collision_of_a_frame_counts() {
    // 1 pedestrian + 2 vehicle + 1 layout + 1 work zone = 5 collisions in frame K, no brake:
    // aligned 5, nodecel 5 (0.8^5 later), one event carrying all of them.
    let (c, v) = outcome(&route(|r| {
        r[K].collisions = Collisions {
            pedestrian: 1,
            vehicle: 2,
            layout: 1,
            workzone: 1,
        }
    }));
    assert_eq!(c, (5, 0, 5));
    assert_eq!(v.len(), 1);
    assert_eq!(v[0].collisions.total(), 5);
    assert_eq!(v[0].frame, K as u32);
    // Exempt: all 5 exempt.
    let (c, _) = outcome(&route(|r| {
        r[K].collisions.pedestrian = 4;
        r[K].speed = 0.0;
    }));
    assert_eq!(c, (5, 5, 0));
}

#[test]
fn an_earlier_impact_counts_as_deceleration_for_a_later_collision() {
    // Frame 30: collision with impact a_lon = -6 (no brake before: nodecel). Frame 35: another
    // collision; frame 30's a_lon is in its window: decelerated.
    let mut r = vec![cruise(); 40];
    r[30].collisions = hit(1);
    r[30].a_lon = -6.0;
    r[35].collisions = hit(1);
    let (c, v) = outcome(&r);
    assert_eq!(c, (2, 0, 1));
    assert_eq!(v.len(), 2);
    assert!(!v[0].decelerated && v[1].decelerated);
    assert_eq!((v[0].frame, v[1].frame), (30, 35));
}

#[test]
fn reset_forgets_the_window() {
    let mut m: monitor_core::Monitor = monitor_core::Monitor::new(Config::DEFAULT).unwrap();
    let mut brake = cruise();
    brake.a_lon = -3.0;
    for _ in 0..5 {
        m.push(&brake).unwrap();
    }
    m.reset();
    assert_eq!(m.frames(), 0);
    m.push(&cruise()).unwrap();
    let mut crash = cruise();
    crash.collisions = hit(1);
    m.push(&crash).unwrap();
    assert_eq!(m.finish().unwrap().summary.collisions.nodecel, 1);
}
