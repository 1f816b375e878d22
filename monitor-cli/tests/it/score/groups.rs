//! `--group-by route --labels FILE` (docs/SCORE.md §10.2 "any label map"): the demo run split by a label map of
//! its route ids, checked against sums worked out here from the per-route report.

use std::path::Path;
use std::process::Output;

use serde_json::Value;

use crate::common::{demo, score_demo as score};

fn json_of(out: &Output) -> Value {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the report is JSON")
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

fn row<'a>(report: &'a Value, label: &str) -> &'a Value {
    report["groups"]["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["label"] == label)
        .unwrap_or_else(|| panic!("no group {label}: {}", report["groups"]))
}

/// DS, SR, mean DS_safe and mean comfort of `ids`, summed here in report order from the
/// per-route entries of an ungrouped report.
fn by_hand(routes: &Value, ids: &[&str]) -> (usize, f64, f64, f64, f64) {
    let mine: Vec<&Value> = routes
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| ids.contains(&r["route_id"].as_str().unwrap()))
        .collect();
    assert_eq!(mine.len(), ids.len());
    let n = mine.len() as f64;
    let sum = |f: &dyn Fn(&Value) -> f64| mine.iter().fold(0.0, |a, r| a + f(r));
    (
        mine.len(),
        sum(&|r| r["score_composed"].as_f64().unwrap()) / n,
        sum(&|r| if r["success"] == true { 100.0 } else { 0.0 }) / n,
        sum(&|r| r["ds_safe"].as_f64().unwrap()) / n,
        sum(&|r| r["comfort"]["score"].as_f64().unwrap()) / n,
    )
}

fn assert_row(g: &Value, expected: (usize, f64, f64, f64, f64)) {
    let (n, ds, sr, ds_safe, comfort) = expected;
    assert_eq!(g["routes"], n, "{g}");
    assert_eq!(g["driving_score"].as_f64(), Some(ds), "{g}");
    assert_eq!(g["success_rate"].as_f64(), Some(sr), "{g}");
    assert_eq!(g["mean_ds_safe"].as_f64(), Some(ds_safe), "{g}");
    assert_eq!(g["mean_comfort"].as_f64(), Some(comfort), "{g}");
}

const EASY: [&str; 3] = [
    "RouteScenario_900001_rep0",
    "RouteScenario_900002_rep0",
    "RouteScenario_900003_rep0",
];
const HARD: [&str; 6] = [
    "RouteScenario_900004_rep0",
    "RouteScenario_900005_rep0",
    "RouteScenario_900006_rep0",
    "RouteScenario_900007_rep0",
    "RouteScenario_900008_rep0",
    "RouteScenario_900009_rep0",
];

#[test]
fn a_route_label_map_splits_the_demo_in_two() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let plain = json_of(&score(dir.path(), None, &[]));
    let routes = &plain["routes"];
    // Every accepted id form: the XML id, RouteScenario_<id>, the full route id.
    let labels = write(
        dir.path(),
        "split.json",
        r#"{"900001": "easy", "RouteScenario_900002": "easy", "RouteScenario_900003_rep0": "easy",
            "900004": "hard", "900005": "hard", "RouteScenario_900006": "hard",
            "900007": "hard", "RouteScenario_900008_rep0": "hard", "900009": "hard"}"#,
    );
    let out = score(
        dir.path(),
        None,
        &["--group-by", "route", "--labels", &labels],
    );
    // Nothing but the note on the demo's 10 Hz route.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.lines().all(|l| l.starts_with("sds: note:")), "{err}");
    let r = json_of(&out);
    assert_eq!(r["groups"]["by"], "route");
    assert_eq!(r["groups"]["rows"].as_array().unwrap().len(), 2);
    let easy = by_hand(routes, &EASY);
    let hard = by_hand(routes, &HARD);
    assert_row(row(&r, "easy"), easy);
    assert_row(row(&r, "hard"), hard);
    // The demo's scripts by hand: 900001-3 complete (100 each); 900004-9 score
    // 65, 37.5, 50, 60, 60, 70 (the last ran a red light: not a success).
    assert_eq!((easy.1, easy.2), (100.0, 100.0));
    assert!((hard.1 - 342.5 / 6.0).abs() < 1e-12, "{}", hard.1);
    assert_eq!(hard.2, 0.0);
    // The combined row is the run's summary; nothing else in the report changes.
    let c = &r["groups"]["combined"];
    for k in [
        "routes",
        "driving_score",
        "success_rate",
        "mean_ds_safe",
        "sds",
    ] {
        assert_eq!(c[k], plain["summary"][k], "{k}");
    }
    assert_eq!(r["summary"], plain["summary"]);
    assert_eq!(r["routes"], plain["routes"]);

    // The same split as TSV, with one route also in a second group (a list label).
    let tsv = write(
        dir.path(),
        "split.tsv",
        "# route\tsplit\n900001\teasy\n900002\teasy\n900003\teasy\n900004\thard\n900005\thard\n\
         900006\thard\n900007\thard\n900008\thard\n900009\thard\n900009\tcomplete\n",
    );
    let r = json_of(&score(
        dir.path(),
        None,
        &["--group-by", "route", "--labels", &tsv],
    ));
    assert_row(row(&r, "easy"), easy);
    assert_row(row(&r, "hard"), hard);
    assert_row(
        row(&r, "complete"),
        by_hand(routes, &["RouteScenario_900009_rep0"]),
    );

    // The Table 2-style breakdown prints the groups.
    let out = score(
        dir.path(),
        None,
        &[
            "--group-by",
            "route",
            "--labels",
            &labels,
            "--format",
            "table",
        ],
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("breakdown by route"), "{text}");
    let line = text.lines().find(|l| l.starts_with("hard")).unwrap();
    assert!(line.contains(&format!("{:.2}", hard.1)), "{line}");
}

#[test]
fn an_id_form_matching_nothing_is_unmapped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let plain = json_of(&score(dir.path(), None, &[]));
    // `Route_900009` and another repetition's id label nothing here.
    let labels = write(
        dir.path(),
        "split.csv",
        "900001,a\n900002,a\n900003,a\n900004,a\n900005,b\n900006,b\n900007,b\n\
         Route_900008,b\nRouteScenario_900009_rep1,b\n",
    );
    let out = score(
        dir.path(),
        None,
        &["--group-by", "route", "--labels", &labels],
    );
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    let r = json_of(&out);
    let unmapped = ["RouteScenario_900008_rep0", "RouteScenario_900009_rep0"];
    assert_row(row(&r, "(unmapped)"), by_hand(&plain["routes"], &unmapped));
    assert_eq!(row(&r, "b")["routes"], 3);
    assert!(
        stderr.contains("group_by = route: 2 route(s)")
            && unmapped.iter().all(|id| stderr.contains(id)),
        "{stderr}"
    );
    let warned = r["warnings"].as_array().unwrap();
    assert!(warned
        .iter()
        .any(|w| w.to_string().contains("RouteScenario_900009_rep0")));

    // A file none of whose ids is a route of the run: a usage error naming the option.
    let other = write(dir.path(), "other.csv", "Route_1,a\n12345,b\n");
    let out = score(
        dir.path(),
        None,
        &["--group-by", "route", "--labels", &other],
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--labels") && stderr.contains("other.csv"),
        "{stderr}"
    );
}

#[test]
fn missing_routes_are_labelled_by_their_xml_id() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Drop route 900005's record: it becomes a missing route of the route XML (0 / failed).
    let mut results: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("results.json")).unwrap())
            .unwrap();
    let records = results["_checkpoint"]["records"].as_array_mut().unwrap();
    let before = records.len();
    records.retain(|r| r["route_id"] != "RouteScenario_900005_rep0");
    assert_eq!(records.len(), before - 1);
    let trimmed = dir.path().join("trimmed.json");
    std::fs::write(&trimmed, results.to_string()).unwrap();
    let labels = write(
        dir.path(),
        "split.json",
        r#"{"900001": "kept", "900002": "kept", "900003": "kept", "900004": "kept",
            "900005": "dropped", "900006": "kept", "900007": "kept", "900008": "kept",
            "900009": "kept"}"#,
    );
    let r = json_of(&score(
        dir.path(),
        Some(&trimmed),
        &["--group-by", "route", "--labels", &labels],
    ));
    assert_eq!(r["summary"]["missing"], 1);
    let g = row(&r, "dropped");
    assert_eq!(g["routes"], 1);
    assert_eq!(g["driving_score"].as_f64(), Some(0.0));
    assert_eq!(g["success_rate"].as_f64(), Some(0.0));
    assert_eq!(row(&r, "kept")["routes"], 8);
    assert_eq!(r["groups"]["combined"]["routes"], 9);
}

#[test]
fn route_grouping_without_a_label_map_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = score(dir.path(), None, &["--group-by", "route"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("group_by = route needs its label map (labels) (--group-by, --labels)"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
    // And a route label map without route grouping is one too (it would be ignored).
    let labels = write(dir.path(), "l.csv", "900001,a\n");
    let out = score(
        dir.path(),
        None,
        &["--group-by", "town", "--labels", &labels],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("give group_by = route with it (--labels, --group-by)"));
}
