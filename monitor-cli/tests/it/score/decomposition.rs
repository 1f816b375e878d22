//! The decomposition from DS to SDS (`docs/SCORE.md` "Decomposition") sums back, step by step,
//! to DS, DS_safe and SDS: per route, in the summary, in every group and in `combined`; on the
//! demo and on every real Bench2Drive results file of the shared fixtures (no telemetry there:
//! `--allow-missing-telemetry`).

use std::path::PathBuf;

use serde_json::Value;

use crate::common::{demo, score_demo, sds};

const STEPS: [&str; 5] = ["rounding", "workzone", "nodecel", "anomalous", "critical"];

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

fn losses(d: &Value) -> f64 {
    STEPS.iter().map(|k| f(&d[k])).sum()
}

/// One aggregate row (the summary, a group, `combined`): its decomposition against its own
/// driving_score, mean_ds_safe and sds. Returns whether it had one.
fn check_row(what: &str, row: &Value) -> bool {
    let d = &row["decomposition"];
    if d.is_null() {
        assert!(row["mean_ds_safe"].is_null(), "{what}: decomposition null");
        return false;
    }
    let close = |a: f64, b: f64, name: &str| {
        assert!((a - b).abs() < 1e-9, "{what}: {name} {a} != {b}");
    };
    close(f(&d["ds"]), f(&row["driving_score"]), "ds");
    close(f(&d["ds_safe"]), f(&row["mean_ds_safe"]), "ds_safe");
    close(f(&d["ds"]) - losses(d), f(&d["ds_safe"]), "ds - losses");
    if row["sds"].is_null() {
        assert!(d["sds"].is_null() && d["comfort"].is_null(), "{what}");
    } else {
        close(f(&d["sds"]), f(&row["sds"]), "sds");
        close(
            f(&d["ds_safe"]) - f(&d["comfort"]),
            f(&row["sds"]),
            "ds_safe - comfort",
        );
    }
    true
}

/// Every route, the summary, every group and `combined` of a report.
fn check_report(what: &str, r: &Value) -> usize {
    let mut split = 0;
    for route in r["routes"].as_array().unwrap() {
        let d = &route["decomposition"];
        if route["ds_safe"].is_null() {
            continue;
        }
        let ds = f(&route["score_composed"]);
        let safe = f(&route["ds_safe"]);
        assert!(
            (ds - losses(d) - safe).abs() < 1e-9,
            "{what} {}: {ds} - {} != {safe}",
            route["route_id"],
            losses(d)
        );
        split += usize::from(d["rounding"] != 0.0 || losses(d) != 0.0);
    }
    assert!(check_row(what, &r["summary"]), "{what}: summary");
    let rows = r["groups"]["rows"].as_array().expect("groups asked");
    let checked = rows
        .iter()
        .filter(|row| check_row(&format!("{what} group {}", row["label"]), row))
        .count();
    let combined = check_row(&format!("{what} combined"), &r["groups"]["combined"]);
    assert!(checked > 0 && combined, "{what}: no group decomposed");
    split
}

#[test]
fn demo_decomposition_sums_back() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = score_demo(
        dir.path(),
        None,
        &["--format", "json", "--group-by", "scenario"],
    );
    assert_eq!(out.status.code(), Some(0));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(check_report("demo", &r) >= 3);
    // The worked route of docs/SCORE.md: 65 -> 40 through one work-zone contact and one
    // collision without deceleration, shared as -ln(0.5/0.65) : -ln(0.8).
    let route = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == "RouteScenario_900004_rep0")
        .unwrap();
    let d = &route["decomposition"];
    let (wz, nd) = (-(0.5f64 / 0.65).ln(), -(0.8f64).ln());
    assert!((f(&d["workzone"]) - 25.0 * wz / (wz + nd)).abs() < 1e-9);
    assert!((f(&d["nodecel"]) - 25.0 * nd / (wz + nd)).abs() < 1e-9);
    // The summary: the demo's lane change alone loses to critical excursions.
    let s = &r["summary"]["decomposition"];
    assert!(f(&s["critical"]) > 0.0 && f(&s["comfort"]) > 0.0);
}

fn fixtures() -> Option<std::path::PathBuf> {
    crate::common::b2d_fixtures(&[])
}

#[test]
fn fixtures_decomposition_sums_back() {
    let Some(b2d) = fixtures() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&b2d)
        .unwrap()
        .map(|e| e.unwrap().path())
        .flat_map(|p| {
            // lead_tfv6_per_route/<route>/checkpoint_endpoint.json: one results file per route.
            let inner = std::fs::read_dir(&p).into_iter().flatten();
            let inner: Vec<PathBuf> = inner.map(|e| e.unwrap().path()).collect();
            std::iter::once(p).chain(inner)
        })
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut scored = 0;
    for file in &files {
        let out = sds(&[
            "score",
            "--allow-missing-telemetry",
            "--format",
            "json",
            "--group-by",
            "scenario",
            "--results",
            file.to_str().unwrap(),
        ]);
        let Ok(r) = serde_json::from_slice::<Value>(&out.stdout) else {
            // Not a results file (an ability table) or a run the CLI refuses: said on stderr.
            eprintln!(
                "{}: no report ({})",
                file.display(),
                String::from_utf8_lossy(&out.stderr)
                    .lines()
                    .next()
                    .unwrap_or("")
            );
            continue;
        };
        if r["routes"].as_array().is_none_or(|a| a.is_empty()) {
            continue;
        }
        check_report(&file.display().to_string(), &r);
        scored += 1;
    }
    eprintln!("decomposition checked on {scored} real results files");
    assert!(scored >= 8, "only {scored} fixtures scored");
}

/// The texts of an SVG document, in order.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..t.find("</text>")?];
            Some(body.trim().to_string())
        })
        .collect()
}

#[test]
fn figures_writes_the_waterfall_and_the_route_chart() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let figs = dir.path().join("figs");
    let report = dir.path().join("report.json");
    let out = score_demo(
        dir.path(),
        None,
        &[
            "--figures",
            figs.to_str().unwrap(),
            "-o",
            report.to_str().unwrap(),
        ],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let d = &r["summary"]["decomposition"];

    // The waterfall: one bar per step (rounding is 0 on the demo: left out), each labelled, the
    // totals and the losses written as the JSON report has them.
    let svg = std::fs::read_to_string(figs.join("decomposition.svg")).unwrap();
    let t = texts(&svg);
    for label in [
        "DS",
        "work zone",
        "no decel.",
        "lat. anomalous",
        "lat. critical",
        "DS_safe",
        "comfort",
        "SDS",
    ] {
        assert!(t.iter().any(|x| x == label), "{label} missing: {t:?}");
    }
    for (key, sign) in [
        ("ds", ""),
        ("ds_safe", ""),
        ("sds", ""),
        ("critical", "−"),
        ("comfort", "−"),
    ] {
        let want = format!("{sign}{:.2}", f(&d[key]));
        assert!(t.contains(&want), "{key}: {want} missing from {t:?}");
    }
    // Background + 8 bars.
    assert_eq!(svg.matches("<rect").count(), 9);

    // The route chart: a DS bar per route, a DS_safe bar per route that has one, and the
    // legend's five swatches, on the background.
    let svg = std::fs::read_to_string(figs.join("routes.svg")).unwrap();
    let routes = r["routes"].as_array().unwrap();
    let safe = routes.iter().filter(|x| !x["ds_safe"].is_null()).count();
    assert_eq!(svg.matches("<rect").count(), 1 + routes.len() + safe + 5);
    assert!(texts(&svg).iter().any(|x| x.contains("9 routes, sorted")));
}

#[test]
fn figures_into_an_unwritable_place_stops_the_run() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let file = dir.path().join("a-file");
    std::fs::write(&file, "not a folder").unwrap();
    let report = dir.path().join("report.json");
    let out = score_demo(
        dir.path(),
        None,
        &[
            "--figures",
            file.to_str().unwrap(),
            "-o",
            report.to_str().unwrap(),
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("a-file"));
    assert!(!report.exists(), "no report after a failed --figures");
}
