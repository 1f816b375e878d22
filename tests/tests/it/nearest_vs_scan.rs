//! The fast nearest-frame index (`monitor_host::geometry::nearest`) gives exactly the answer of the
//! old quadratic scan, kept here as the oracle: same frame, same `None`s, for every tie band,
//! distance bound, duplicate location and non-finite value.

use monitor_host::geometry::nearest::NearestIndex;
use monitor_host::input::lead_infractions::StepInfraction;
use monitor_host::pipeline::align::{align_events, nearest_frame, AlignedBy, Alignment, EventRef};
use proptest::prelude::*;

/// The scan `nearest_frame` was before the index (the spec's rule, written plainly).
fn scan(locations: &[[f64; 2]], x: f64, y: f64, max_dist: f64, tie: f64) -> Option<usize> {
    let dist = |p: &[f64; 2]| {
        let (dx, dy) = (p[0] - x, p[1] - y);
        (dx * dx + dy * dy).sqrt()
    };
    let mut min = f64::INFINITY;
    for p in locations {
        let d = dist(p);
        if d < min {
            min = d;
        }
    }
    if min
        .partial_cmp(&max_dist)
        .is_none_or(|o| o == std::cmp::Ordering::Greater)
    {
        return None;
    }
    locations.iter().position(|p| dist(p) - min <= tie)
}

/// The old alignment: first unused entry by a linear search, then the scan.
fn scan_align(
    events: &[EventRef<'_>],
    steps: &[u64],
    locations: &[[f64; 2]],
    infractions: Option<&[StepInfraction]>,
    max_dist: f64,
    tie: f64,
) -> Vec<Alignment> {
    let mut used = vec![false; infractions.map_or(0, <[StepInfraction]>::len)];
    events
        .iter()
        .map(|ev| {
            if let Some(entries) = infractions {
                let hit = entries
                    .iter()
                    .enumerate()
                    .find(|(i, e)| !used[*i] && e.message == ev.message);
                if let Some((i, entry)) = hit {
                    used[i] = true;
                    if let Ok(frame) = steps.binary_search(&entry.step) {
                        return Alignment {
                            frame: Some(frame),
                            by: Some(AlignedBy::InfractionsJson),
                        };
                    }
                }
            }
            let frame = ev
                .location
                .and_then(|[x, y]| scan(locations, x, y, max_dist, tie));
            Alignment {
                frame,
                by: frame.map(|_| AlignedBy::Nearest),
            }
        })
        .collect()
}

/// Coordinates that collide a lot: a coarse grid, millimetre offsets around it (the tie band),
/// far values, and now and then a non-finite one.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => (-4i32..4).prop_map(|i| f64::from(i) * 0.5),
        6 => ((-4i32..4), (-3i32..3)).prop_map(|(i, k)| f64::from(i) * 0.5 + f64::from(k) * 4e-4),
        3 => -5.0f64..5.0,
        1 => proptest::sample::select(vec![1e300, -1e300, 1e6 + 0.1]),
        1 => proptest::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
    ]
}

fn point() -> impl Strategy<Value = [f64; 2]> {
    (coord(), coord()).prop_map(|(x, y)| [x, y])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn nearest_index_matches_the_scan(
        locations in proptest::collection::vec(point(), 0..80),
        queries in proptest::collection::vec(point(), 1..20),
        max_dist in prop_oneof![Just(0.0), Just(1.0), 0.0f64..3.0, Just(1e308)],
        tie in prop_oneof![Just(0.0), Just(1e-3), 0.0f64..0.01, Just(0.6)],
    ) {
        let index = NearestIndex::new(&locations);
        for [x, y] in queries {
            let want = scan(&locations, x, y, max_dist, tie);
            prop_assert_eq!(index.nearest(x, y, max_dist, tie), want);
            prop_assert_eq!(nearest_frame(&locations, x, y, max_dist, tie), want);
        }
    }

    #[test]
    fn alignment_matches_the_old_quadratic_one(
        locations in proptest::collection::vec(point(), 1..60),
        events in proptest::collection::vec((0u8..4, proptest::option::of(point())), 0..30),
        entries in proptest::collection::vec((0u8..4, 0u64..80), 0..20),
    ) {
        let steps: Vec<u64> = (0..locations.len() as u64).map(|s| s + 10).collect();
        let messages = ["a", "b", "c", "d"];
        let refs: Vec<EventRef> = events
            .iter()
            .map(|(m, loc)| EventRef { message: messages[*m as usize], location: *loc })
            .collect();
        let entries: Vec<StepInfraction> = entries
            .iter()
            .map(|(m, s)| StepInfraction { step: *s, message: messages[*m as usize].into() })
            .collect();
        for inf in [None, Some(entries.as_slice())] {
            prop_assert_eq!(
                align_events(&refs, &steps, &locations, inf, 1.0, 1e-3),
                scan_align(&refs, &steps, &locations, inf, 1.0, 1e-3)
            );
        }
    }
}

/// The case, shrunk: many events on a long route align in well under a second (the scan
/// took 51 s for 40,000 events x 100,000 frames; timings are in docs/PERFORMANCE.md, this only
/// checks the answer on a size the scan could not finish quickly).
#[test]
fn many_events_on_a_long_route() {
    let frames = 100_000;
    let locations: Vec<[f64; 2]> = (0..frames).map(|i| [i as f64 * 0.3, 0.0]).collect();
    let steps: Vec<u64> = (0..frames as u64).collect();
    let events: Vec<EventRef> = (0..40_000)
        .map(|i| EventRef {
            message: "m",
            location: Some([i as f64 * 0.75 + 0.01, 0.2]),
        })
        .collect();
    let a = align_events(&events, &steps, &locations, None, 1.0, 1e-3);
    for (i, al) in a.iter().enumerate() {
        if i % 997 == 0 {
            let want = scan(&locations, events[i].location.unwrap()[0], 0.2, 1.0, 1e-3);
            assert_eq!(al.frame, want, "event {i}");
        }
        assert!(al.frame.is_some());
    }
}
