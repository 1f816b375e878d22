//! Lateral excess (docs/SCORE.md §3, 3, 6): `excess = max(0, |lat_err| - slack)`, the chunk's
//! maximum, exclusive bands `0.25 < m <= 0.65` (anomalous) and `m > 0.65` (critical).

use crate::common::{lateral_verdicts, run};
use monitor_core::signal::excess;
use monitor_core::{Band, Config, Frame};

fn lat(e: Option<f32>) -> Frame {
    Frame {
        lat_err: e,
        ..Frame::default()
    }
}

/// The lateral summary (chunks, scored, anomalous, critical) of a route.
fn counts(config: Config, route: &[Frame]) -> (u32, u32, u32, u32) {
    let l = run(config, route).1.summary.lateral;
    (l.chunks, l.scored_chunks, l.anomalous, l.critical)
}

/// One 20-frame chunk whose only known excess comes from `lat_err` at frame 7.
fn one_chunk(lat_err: f32) -> Vec<Frame> {
    let mut r = vec![lat(None); 20];
    r[7] = lat(Some(lat_err));
    r
}

#[test]
fn with_the_default_slack_no_lat_err_gives_exactly_0_25_or_0_65() {
    // 0.82f32 = 0x3F51EB85: an odd multiple of 2^-24. lat_err near 1.07 or 1.47 lies in [1, 2),
    // a multiple of 2^-23, so lat_err - 0.82f32 is an odd multiple of 2^-24, computed exactly
    // (Sterbenz: 0.41 <= lat_err <= 1.64), and 0.25, 0.65f32 (= 0x3F266666, even) are not.
    assert_eq!(0.82f32.to_bits(), 0x3F51_EB85);
    for target in [0.25f32, 0.65] {
        let mut x = target + 0.82;
        for _ in 0..10_000 {
            x = x.next_down();
        }
        let (mut below, mut above) = (0, 0);
        for _ in 0..20_000 {
            let e = excess(x, 0.82);
            assert_ne!(e.to_bits(), target.to_bits(), "lat_err {x:e}");
            if e < target {
                below += 1;
            } else {
                above += 1;
            }
            x = x.next_up();
        }
        assert!(below > 0 && above > 0);
    }
}

#[test]
fn bands_at_the_default_slack_switch_between_neighbouring_floats() {
    // The last lat_err whose excess is <= 0.25 and the float after it straddle the band edge.
    let c = Config::DEFAULT;
    for (edge, lower, upper) in [
        (0.25f32, Band::Normal, Band::Anomalous),
        (0.65, Band::Anomalous, Band::Critical),
    ] {
        let mut x = edge + 0.82;
        while excess(x, 0.82) > edge {
            x = x.next_down();
        }
        while excess(x.next_up(), 0.82) <= edge {
            x = x.next_up();
        }
        assert!(excess(x, 0.82) <= edge && excess(x.next_up(), 0.82) > edge);
        assert_eq!(Band::of(excess(x, 0.82), &c), lower);
        assert_eq!(Band::of(excess(x.next_up(), 0.82), &c), upper);
        let anom = |b: Band| (b == Band::Anomalous) as u32;
        let crit = |b: Band| (b == Band::Critical) as u32;
        assert_eq!(counts(c, &one_chunk(x)), (1, 1, anom(lower), crit(lower)));
        assert_eq!(
            counts(c, &one_chunk(x.next_up())),
            (1, 1, anom(upper), crit(upper))
        );
    }
}

#[test]
fn excess_exactly_on_the_band_edges() {
    // slack 0: excess = |lat_err| - 0 = lat_err exactly, so the monitor sees 0.25f32, 0.65f32.
    let c = Config {
        slack: 0.0,
        ..Config::DEFAULT
    };
    assert_eq!(excess(0.25, 0.0).to_bits(), 0.25f32.to_bits());
    assert_eq!(excess(0.65, 0.0).to_bits(), 0.65f32.to_bits());
    // 0.25 -> normal (0.25 < m fails); next float -> anomalous; 0.65 -> anomalous (m <= 0.65);
    // next float -> critical.
    assert_eq!(counts(c, &one_chunk(0.25)), (1, 1, 0, 0));
    assert_eq!(counts(c, &one_chunk(0.25f32.next_up())), (1, 1, 1, 0));
    assert_eq!(counts(c, &one_chunk(0.65)), (1, 1, 1, 0));
    assert_eq!(counts(c, &one_chunk(0.65f32.next_up())), (1, 1, 0, 1));
    // slack 0.75 (exact): lat_err 1.0 -> 1.0 - 0.75 = 0.25 exactly; 0.65f32 + 0.75 is exact
    // (0.65f32 is an even multiple of 2^-24), so that lat_err gives 0.65f32 back exactly.
    let c75 = Config {
        slack: 0.75,
        ..Config::DEFAULT
    };
    let l65 = 0.65f32 + 0.75;
    assert_eq!(excess(1.0, 0.75).to_bits(), 0.25f32.to_bits());
    assert_eq!(excess(l65, 0.75).to_bits(), 0.65f32.to_bits());
    assert_eq!(excess(-l65, 0.75).to_bits(), 0.65f32.to_bits());
    assert_eq!(counts(c75, &one_chunk(1.0)), (1, 1, 0, 0));
    assert_eq!(counts(c75, &one_chunk(l65)), (1, 1, 1, 0));
    assert_eq!(counts(c75, &one_chunk(-l65)), (1, 1, 1, 0));
    assert_eq!(counts(c75, &one_chunk(l65.next_up())), (1, 1, 0, 1));
}

#[test]
fn the_event_carries_the_chunk_maximum() {
    // Frames of chunk 0 with lat_err 1.0, 1.3, 1.1 (slack 0.82): excess 0.18, 0.48, 0.28; the
    // maximum 1.3 - 0.82 = 0.48 (anomalous). Chunk 1: 1.6 -> 0.78 (critical).
    let mut route = vec![lat(None); 40];
    route[2] = lat(Some(1.0));
    route[9] = lat(Some(-1.3));
    route[15] = lat(Some(1.1));
    route[30] = lat(Some(1.6));
    let (events, done) = run(Config::DEFAULT, &route);
    let v = lateral_verdicts(&events);
    assert_eq!(v.len(), 2);
    assert_eq!((v[0].chunk, v[0].band), (0, Band::Anomalous));
    assert_eq!(v[0].max_excess, 1.3f32 - 0.82f32);
    assert_eq!((v[1].chunk, v[1].band), (1, Band::Critical));
    assert_eq!(v[1].max_excess, 1.6f32 - 0.82f32);
    let l = done.summary.lateral;
    assert_eq!(
        (l.chunks, l.scored_chunks, l.anomalous, l.critical),
        (2, 2, 1, 1)
    );
}

#[test]
fn a_chunk_with_only_unknown_excess_is_unscored() {
    // 20 frames, no lat_err: 1 chunk, 0 scored, no event.
    let (events, done) = run(Config::DEFAULT, &vec![lat(None); 20]);
    assert!(lateral_verdicts(&events).is_empty());
    let l = done.summary.lateral;
    assert_eq!(
        (l.chunks, l.scored_chunks, l.anomalous, l.critical),
        (1, 0, 0, 0)
    );
    // A known excess of 0 (lat_err 0.5 < slack) scores the chunk as normal.
    assert_eq!(counts(Config::DEFAULT, &one_chunk(0.5)), (1, 1, 0, 0));
}

#[test]
fn the_trailing_partial_chunk_counts() {
    // 25 frames: chunks [0, 20) and the partial [20, 25). A critical excess at frame 22 is
    // reported by finish, as chunk 1.
    let mut route = vec![lat(Some(0.1)); 25];
    route[22] = lat(Some(2.0)); // 2.0 - 0.82 = 1.18 > 0.65
    let mut m: monitor_core::Monitor = monitor_core::Monitor::new(Config::DEFAULT).unwrap();
    for f in &route {
        let e = m.push(f).unwrap();
        assert!(lateral_verdicts(e.as_slice()).is_empty());
    }
    let done = m.finish().unwrap();
    let v = lateral_verdicts(done.events.as_slice());
    assert_eq!(v.len(), 1);
    assert_eq!((v[0].chunk, v[0].band), (1, Band::Critical));
    assert_eq!(v[0].max_excess, 2.0f32 - 0.82f32);
    let l = done.summary.lateral;
    assert_eq!(
        (l.chunks, l.scored_chunks, l.anomalous, l.critical),
        (2, 2, 0, 1)
    );
    // A one-frame route is one lateral chunk too.
    assert_eq!(counts(Config::DEFAULT, &[lat(Some(1.2))]), (1, 1, 1, 0));
}

#[test]
fn excess_by_hand() {
    // max(0, |x| - slack): |−1.0| − 0.75 = 0.25; 0.5 − 0.82 < 0 → 0; |−2| − 0 = 2.
    assert_eq!(excess(-1.0, 0.75), 0.25);
    assert_eq!(excess(0.5, 0.82), 0.0);
    assert_eq!(excess(0.82, 0.82), 0.0);
    assert_eq!(excess(-2.0, 0.0), 2.0);
    assert!(excess(f32::NAN, 0.82).is_nan());
}
