//! The OpenDRIVE map reader never panics (`docs/RELIABILITY.md`): on arbitrary text, on every
//! truncation of the hand-made maps, and on maps whose numbers are replaced by hostile values;
//! every refusal names the file; every map that loads answers projections, gap fills and dense
//! routes without panicking.

use std::path::Path;

use monitor_host::geometry::map::{dense_route, Map};
use proptest::prelude::*;
use proptest::test_runner::Config as PropConfig;

const FILE: &str = "prop.xodr";

fn maps() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../monitor-host/tests/data/maps");
    let mut out: Vec<String> = std::fs::read_dir(&dir)
        .expect("hand-made maps")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "xodr"))
        .map(|e| std::fs::read_to_string(e.path()).expect("map text"))
        .collect();
    out.sort();
    assert!(out.len() >= 10, "the hand-made maps are missing");
    out
}

/// Parses, and exercises whatever loads.
fn check(text: &str) {
    match Map::parse(text, FILE) {
        Ok(map) => {
            let pts = [
                [0.0, 0.0, 0.0],
                [10.0, 1.75, 0.0],
                [30.0, -2.0, 5.0],
                [f64::NAN, 0.0, 0.0],
            ];
            for p in pts {
                if let Some(pr) = map.project(p[0], p[1], p[2]) {
                    assert!(pr.distance_3d >= 0.0, "{pr:?}");
                    assert!(pr.tied >= 1);
                }
            }
            let _ = map.fill_gap(pts[0], pts[2]);
            let _ = dense_route(&pts[..3], 8.0, Some(&map));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.starts_with("prop.xodr: "),
                "error does not name the file: {msg}"
            );
        }
    }
}

const HOSTILE: [&str; 14] = [
    "NaN", "inf", "-inf", "-1", "-0", "0", "1e308", "-1e308", "1e-320", "", "abc", "2e5", "1e5",
    "3.4e38",
];

proptest! {
    #![proptest_config(PropConfig { cases: 1024, ..PropConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,400}") {
        check(&text);
    }

    #[test]
    fn every_truncation_never_panics(which in 0usize..64, cut in 0.0f64..1.0) {
        let maps = maps();
        let text = &maps[which % maps.len()];
        let mut at = (cut * text.len() as f64) as usize;
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        check(&text[..at]);
    }

    #[test]
    fn hostile_numbers_never_panic(which in 0usize..64, picks in proptest::collection::vec((0usize..4096, 0usize..HOSTILE.len()), 1..6)) {
        let maps = maps();
        let mut text = maps[which % maps.len()].clone();
        for (k, h) in picks {
            // Replace the value of the k-th attribute (modulo their count).
            let starts: Vec<usize> = text.match_indices("=\"").map(|(i, _)| i + 2).collect();
            if starts.is_empty() {
                break;
            }
            let s = starts[k % starts.len()];
            let e = s + text[s..].find('"').unwrap_or(0);
            text.replace_range(s..e, HOSTILE[h]);
        }
        check(&text);
    }
}

#[test]
fn truncated_maps_are_refused_with_the_file_name() {
    for text in maps() {
        for frac in [0.1, 0.5, 0.9] {
            let mut at = (frac * text.len() as f64) as usize;
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let err = Map::parse(&text[..at], FILE).expect_err("a truncated map is not a map");
            assert!(err.to_string().starts_with("prop.xodr: "), "{err}");
        }
    }
}
