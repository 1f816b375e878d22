//! Chunks (docs/SCORE.md §4): frames [20k, 20k+20) form chunk k; comfort uses full chunks (or one
//! short chunk for 7 <= n < 20) and drops the trailing partial one; lateral uses ceil(n / 20).

use crate::common::{comfort_verdicts, lateral_verdicts, run};
use monitor_core::{Config, Frame};

#[test]
fn chunk_counts_by_route_length() {
    // n:            0  6  7  19 20 21 40 41
    // comfort:      0  0  1  1  1  1  2  2   (floor(n/20), or 1 for 7 <= n < 20)
    // lateral:      0  1  1  1  1  2  2  3   (ceil(n/20))
    let table = [
        (0, 0, 0),
        (6, 0, 1),
        (7, 1, 1),
        (19, 1, 1),
        (20, 1, 1),
        (21, 1, 2),
        (40, 2, 2),
        (41, 2, 3),
    ];
    for (n, comfort, lateral) in table {
        let route = vec![Frame::default(); n];
        let (events, done) = run(Config::DEFAULT, &route);
        let s = done.summary;
        assert_eq!(s.frames, n as u32);
        assert_eq!(s.comfort.chunks, comfort, "comfort chunks, n={n}");
        assert_eq!(s.lateral.chunks, lateral, "lateral chunks, n={n}");
        assert_eq!(
            comfort_verdicts(&events).len(),
            comfort as usize,
            "comfort events, n={n}"
        );
        // Comfort undefined below 7 frames; all-zero signals are comfortable otherwise.
        let want = if n < 7 { None } else { Some(1.0) };
        assert_eq!(s.comfort_score(), want, "n={n}");
        // No lat_err: no chunk scored, no lateral event.
        assert_eq!(s.lateral.scored_chunks, 0);
        assert!(lateral_verdicts(&events).is_empty());
    }
}

#[test]
fn short_route_chunk_holds_all_frames() {
    // n = 19: one chunk of 19 frames, emitted by finish; indices start at 0.
    let mut m: monitor_core::Monitor = monitor_core::Monitor::new(Config::DEFAULT).unwrap();
    for _ in 0..19 {
        assert!(m.push(&Frame::default()).unwrap().is_empty());
    }
    let done = m.finish().unwrap();
    let v = comfort_verdicts(done.events.as_slice());
    assert_eq!(v.len(), 1);
    assert_eq!((v[0].chunk, v[0].frames), (0, 19));
}

#[test]
fn full_chunks_close_on_their_last_frame() {
    // The comfort event of chunk k comes with frame 20k + 19; the trailing partial chunk's
    // comfort is dropped (n = 45: events at frames 19 and 39, none at finish).
    let mut m: monitor_core::Monitor = monitor_core::Monitor::new(Config::DEFAULT).unwrap();
    let mut at = Vec::new();
    for i in 0..45 {
        for v in comfort_verdicts(m.push(&Frame::default()).unwrap().as_slice()) {
            at.push((i, v.chunk, v.frames));
        }
    }
    assert_eq!(at, [(19, 0, 20), (39, 1, 20)]);
    let done = m.finish().unwrap();
    assert!(comfort_verdicts(done.events.as_slice()).is_empty());
    assert_eq!(done.summary.comfort.chunks, 2);
}

#[test]
fn a_trailing_partial_chunk_is_dropped_even_if_it_is_bad() {
    // 30 frames; a 30 m/s² lateral spike at frame 25 (in the dropped partial chunk): comfort 1/1.
    let mut route = vec![Frame::default(); 30];
    route[25].a_lat = 30.0;
    let (_, done) = run(Config::DEFAULT, &route);
    assert_eq!(done.summary.comfort_score(), Some(1.0));
}

#[test]
fn configured_chunk_length_and_minimum() {
    // chunk_len 10, min_chunk 8: n = 7 -> no comfort chunk; n = 8 -> one short chunk;
    // n = 25 -> comfort 2, lateral 3.
    let c = Config {
        chunk_len: 10,
        min_chunk: 8,
        ..Config::DEFAULT
    };
    for (n, comfort, lateral) in [(7, 0, 1), (8, 1, 1), (25, 2, 3)] {
        let s = run(c, &vec![Frame::default(); n]).1.summary;
        assert_eq!(
            (s.comfort.chunks, s.lateral.chunks),
            (comfort, lateral),
            "n={n}"
        );
    }
}
