//! The per-route `events` of the JSON report: every collision (placed or not), every anomalous
//! and critical lateral chunk and every uncomfortable chunk, on the frame axis, in frame order.

use serde_json::Value;

mod common;
use common::{demo, score_demo};

fn count(r: &Value, kind: &str) -> u64 {
    r["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == kind)
        .count() as u64
}

#[test]
fn demo_events_match_the_counts_and_the_collisions() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = score_demo(dir.path(), None, &["--format", "json"]);
    assert_eq!(out.status.code(), Some(0));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut total = 0;
    for r in report["routes"].as_array().unwrap() {
        let id = &r["route_id"];
        let events = r["events"].as_array().unwrap();
        total += events.len();
        let lat = &r["lateral"];
        let comfort = &r["comfort"];
        assert_eq!(
            count(r, "lateral_anomalous"),
            lat["anomalous"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            count(r, "lateral_critical"),
            lat["critical"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            count(r, "uncomfortable"),
            comfort["chunks"].as_u64().unwrap() - comfort["comfortable"].as_u64().unwrap(),
            "{id}"
        );
        // Collisions: the same frame, step and time as collision_events, in that list's order.
        let collisions: Vec<&Value> = events.iter().filter(|e| e["kind"] == "collision").collect();
        let listed = r["collision_events"].as_array().unwrap();
        assert_eq!(collisions.len(), listed.len(), "{id}");
        for (e, c) in collisions.iter().zip(listed) {
            for k in ["frame", "step", "time_s"] {
                assert_eq!(e[k], c[k], "{id} {k}");
            }
            assert!(e["message"]
                .as_str()
                .unwrap()
                .starts_with(c["list"].as_str().unwrap()));
        }
        // Frame order; a chunk starts at a multiple of the chunk length, and its time follows
        // from its step as a collision's does.
        let frames: Vec<u64> = events
            .iter()
            .map(|e| e["frame"].as_u64().unwrap())
            .collect();
        assert!(frames.windows(2).all(|w| w[0] <= w[1]), "{id}: {frames:?}");
        let dt = r["dt"].as_f64().unwrap();
        for e in events.iter().filter(|e| e["kind"] != "collision") {
            assert_eq!(e["frame"].as_u64().unwrap() % 20, 0, "{id}");
            let t = e["time_s"].as_f64().unwrap();
            let want = e["frame"].as_f64().unwrap() * dt; // the demo has no gaps
            assert!((t - want).abs() < 1e-9, "{id}: {t} vs {want}");
        }
    }
    assert!(total >= 15, "only {total} events on the demo");
    // The 10 Hz route: its chunk 2 starts 4 s in, not 2 s.
    let r = report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == "RouteScenario_900008_rep0")
        .unwrap();
    let e = r["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "uncomfortable" && e["frame"] == 40)
        .expect("chunk 2 uncomfortable");
    assert_eq!(e["time_s"], 4.0);
}

#[test]
fn unplaced_collisions_are_listed_last() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Without telemetry nothing can be placed: every collision is listed, unplaced.
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let out = common::sds(&[
        "score",
        "--results",
        &d("results.json"),
        "--allow-missing-telemetry",
        "--format",
        "json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut unplaced = 0;
    for r in report["routes"].as_array().unwrap() {
        let events = r["events"].as_array().unwrap();
        assert_eq!(
            events.len(),
            r["collision_events"].as_array().unwrap().len()
        );
        for e in events {
            assert!(e["frame"].is_null() && e["step"].is_null() && e["time_s"].is_null());
            assert!(e["message"].as_str().unwrap().contains("not placed"));
            unplaced += 1;
        }
    }
    assert!(unplaced >= 5, "{unplaced}");
}
