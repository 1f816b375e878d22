//! `sds compare --sweep` (issue 50, docs/SCORE.md §10.4): every model's figures at every point of a
//! grid of settings, equal to `sds compare` at that point's settings; the refusals; the tables,
//! page and long table.

use std::path::Path;

use serde_json::Value;

use crate::common::sds;

/// The demo in `dir`, and two more results files over its telemetry: `results_b.json` (route
/// 900003 at 60 % of its route instead of 100 %, route 900009's penalty 0.85 instead of 0.7)
/// and `results_c.json` (route 900001 at 90 %), so the models' order depends on the critical
/// factor (900003 has 7 critical chunks).
fn runs(dir: &Path) -> [String; 3] {
    crate::common::demo(dir);
    let text = std::fs::read_to_string(dir.join("results.json")).unwrap();
    let edit = |name: &str, changes: &[(&str, f64, f64, f64)]| {
        let mut v: Value = serde_json::from_str(&text).unwrap();
        for r in v["_checkpoint"]["records"].as_array_mut().unwrap() {
            let id = r["route_id"].as_str().unwrap().to_string();
            for (route, score_route, penalty, composed) in changes {
                if id.contains(route) {
                    r["scores"] = serde_json::json!({
                        "score_route": score_route, "score_penalty": penalty,
                        "score_composed": composed
                    });
                }
            }
        }
        std::fs::write(dir.join(name), v.to_string()).unwrap();
    };
    edit(
        "results_b.json",
        &[("900003", 60.0, 1.0, 60.0), ("900009", 100.0, 0.85, 85.0)],
    );
    edit("results_c.json", &[("900001", 90.0, 1.0, 90.0)]);
    runs_named(dir)
}

/// `sds compare` of the three runs (`results_b` and `results_c` as seeds of one model), JSON.
fn compare(dir: &Path, extra: &[&str]) -> (Value, std::process::Output) {
    let [a, b, c] = runs_named(dir);
    let routes = dir.join("routes.xml");
    let mut args = vec![
        "compare",
        &a,
        &b,
        &c,
        "--seeds",
        "bc=results_b,results_c",
        "--routes",
        routes.to_str().unwrap(),
        "--bootstrap-samples",
        "1000",
        "--format",
        "json",
    ];
    args.extend_from_slice(extra);
    let out = sds(&args);
    let v = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
    (v, out)
}

/// The run arguments, when [`runs`] has written them.
fn runs_named(dir: &Path) -> [String; 3] {
    let tel = dir.join("telemetry");
    ["results", "results_b", "results_c"].map(|n| {
        format!(
            "{n}={}:{}",
            dir.join(format!("{n}.json")).display(),
            tel.display()
        )
    })
}

/// A model's `[ds_safe, comfort, sds]` in a compare report.
fn figures(report: &Value, model: &str) -> [Value; 3] {
    let m = report["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == model)
        .unwrap();
    ["mean_ds_safe", "mean_comfort", "sds"].map(|k| m[k]["mean"].clone())
}

/// Issue 50: at every point of a grid that moves a penalty factor (DS_safe computed again), a
/// comfort bound (the frames streamed again) and the chunk length (the telemetry prepared again),
/// every model's DS_safe, comfort, SDS and rank equal `sds compare --set` at that point; at the
/// given settings the report is `sds compare`'s without `--sweep`, figure for figure.
#[test]
fn i50_1_every_point_equals_compare_at_its_settings() {
    let dir = tempfile::tempdir().unwrap();
    runs(dir.path());
    let axes = [
        ("factors.critical", ["0.7", "0.9"]),
        ("bounds.lat_acc", ["0.5", "4.89"]),
        ("chunk_len", ["10", "20"]),
    ];
    let sweep: Vec<String> = axes
        .iter()
        .map(|(n, v)| format!("--sweep={n}={}", v.join(",")))
        .collect();
    let extra: Vec<&str> = sweep.iter().map(String::as_str).collect();
    let (swept, out) = compare(dir.path(), &extra);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = &swept["sweep"];
    assert_eq!(
        s["settings"],
        serde_json::json!(["factors.critical", "bounds.lat_acc", "chunk_len"])
    );
    let points = s["points"].as_array().unwrap();
    assert_eq!(points.len(), 8);
    let mut distinct = std::collections::BTreeSet::new();
    for (i, p) in points.iter().enumerate() {
        // The last setting varies fastest.
        let at = [i / 4, (i / 2) % 2, i % 2];
        let sets: Vec<String> = axes
            .iter()
            .zip(at)
            .map(|((n, v), k)| format!("--set={n}={}", v[k]))
            .collect();
        for ((n, v), k) in axes.iter().zip(at) {
            assert_eq!(p["values"][n].as_f64(), v[k].parse().ok(), "point {i}: {n}");
        }
        let extra: Vec<&str> = sets.iter().map(String::as_str).collect();
        let (plain, out) = compare(dir.path(), &extra);
        assert!(out.status.success());
        let sds: Vec<f64> = ["results", "bc"]
            .iter()
            .map(|m| figures(&plain, m)[2].as_f64().unwrap())
            .collect();
        for (k, model) in ["results", "bc"].iter().enumerate() {
            let f = &p["models"][k];
            assert_eq!(f["model"], *model);
            let want = figures(&plain, model);
            assert_eq!(
                [f["ds_safe"].clone(), f["comfort"].clone(), f["sds"].clone()],
                want,
                "point {i} ({sets:?}), model {model}"
            );
            let rank = 1 + sds.iter().filter(|x| **x > sds[k]).count();
            assert_eq!(f["rank"], rank, "point {i}, model {model}");
            distinct.insert(want[2].to_string());
        }
    }
    // The grid moves the figures (else the test would check little).
    assert!(distinct.len() >= 6, "{distinct:?}");
    // The given settings: the report without `sweep` is `sds compare`'s, to the byte.
    let (plain, _) = compare(dir.path(), &[]);
    let mut without = swept.clone();
    without.as_object_mut().unwrap().remove("sweep");
    assert_eq!(without, plain);
    let given = &points[7]; // 0.9, 4.89, 20: the defaults
    for (k, model) in ["results", "bc"].iter().enumerate() {
        let f = &given["models"][k];
        assert_eq!(
            [f["ds_safe"].clone(), f["comfort"].clone(), f["sds"].clone()],
            figures(&plain, model)
        );
    }
}

/// Issue 50: the order of two models flips between two values of the critical factor; the pair
/// says where, and each model's SDS range spans its points.
#[test]
fn i50_2_order_flips_where_the_factor_moves() {
    let dir = tempfile::tempdir().unwrap();
    runs(dir.path());
    let [a, b, _] = runs_named(dir.path());
    let routes = dir.path().join("routes.xml");
    let routes = routes.to_str().unwrap();
    let out = sds(&[
        "compare",
        &a,
        &b,
        "--routes",
        routes,
        "--bootstrap-samples",
        "1000",
        "--sweep",
        "factors.critical=0.7,0.8,0.9",
        "--format",
        "json",
    ]);
    assert!(out.status.success());
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let s = &v["sweep"];
    let rank = |p: usize, m: usize| s["points"][p]["models"][m]["rank"].as_u64().unwrap();
    // b loses 40 points of route 900003 times 0.x^7 and gains 15 on 900009.
    assert_eq!([rank(0, 0), rank(1, 0), rank(2, 0)], [2, 2, 1]);
    assert_eq!([rank(0, 1), rank(1, 1), rank(2, 1)], [1, 1, 2]);
    let pair = &s["pairs"][0];
    assert_eq!(
        (pair["a"].as_str(), pair["b"].as_str()),
        (Some("results"), Some("results_b"))
    );
    assert_eq!(pair["order_stable"], false);
    assert_eq!(pair["flips"], serde_json::json!([2]));
    for (m, r) in s["ranges"].as_array().unwrap().iter().enumerate() {
        let all: Vec<f64> = (0..3)
            .map(|p| s["points"][p]["models"][m]["sds"].as_f64().unwrap())
            .collect();
        let lo = all.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = all.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(
            (r["sds_min"].as_f64(), r["sds_max"].as_f64()),
            (Some(lo), Some(hi))
        );
        assert!(lo < hi);
    }
    // A comfort bound that moves nothing here keeps the order.
    let out = sds(&[
        "compare",
        &a,
        &b,
        "--routes",
        routes,
        "--bootstrap-samples",
        "1000",
        "--sweep",
        "bounds.yaw_rate=0.9,0.95",
        "--format",
        "json",
    ]);
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["sweep"]["pairs"][0]["order_stable"], true);
    assert_eq!(v["sweep"]["pairs"][0]["flips"], serde_json::json!([]));
}

/// Issue 50: a setting that does not exist or changes no route's figures is refused with the
/// list of those that do (exit 2, before any run is scored); more than 64 points is refused with
/// the count; a value the setting refuses, and a run given as a report, too.
#[test]
fn i50_3_refusals() {
    let dir = tempfile::tempdir().unwrap();
    runs(dir.path());
    let [a, b, _] = runs_named(dir.path());
    let refused = |sweep: &[&str]| -> String {
        let mut args = vec!["compare", a.as_str(), b.as_str()];
        for s in sweep {
            args.extend(["--sweep", s]);
        }
        let out = sds(&args);
        assert_eq!(out.status.code(), Some(2), "{sweep:?}");
        assert!(out.stdout.is_empty());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    for (sweep, why) in [
        ("nope=1,2", "sweep nope: no such setting"),
        (
            "protocols=all,none",
            "sweep protocols: changes no route's figures (group protocols)",
        ),
        (
            "expected_routes=220,300",
            "changes no route's figures (group aggregates)",
        ),
        (
            "events.min_standing=1,2",
            "changes no route's figures (group events)",
        ),
        (
            "penalty_flavour=bench2drive,leaderboard20",
            "changes no route's figures (group penalty)",
        ),
    ] {
        let e = refused(&[sweep]);
        assert!(e.contains(why), "{sweep}: {e}");
        // The list of those that do, from the settings table; ends with the flag.
        let list = e.split("comfort: ").nth(1).unwrap_or_default();
        for name in [
            "critical_excess",
            "anomalous_excess",
            "bounds.yaw_rate",
            "factors.workzone",
            "gap_max",
            "decel_threshold",
            "dt",
        ] {
            assert!(
                list.split([',', ' ']).any(|n| n == name),
                "{name} missing: {e}"
            );
        }
        for name in [
            "protocols",
            "expected_routes",
            "events.min_standing",
            "penalty_flavour",
            "duplicates",
        ] {
            assert!(
                !list.split([',', ' ']).any(|n| n == name),
                "{name} listed: {e}"
            );
        }
        assert!(e.trim_end().ends_with("(--sweep)"), "{e}");
    }
    let e = refused(&[
        "factors.critical=0.5,0.6,0.7,0.8,0.9",
        "slack=0.3,0.4,0.5,0.6,0.7,0.8,0.9,1,1.1,1.2,1.3,1.4,1.5",
    ]);
    assert!(
        e.contains("the grid has 65 points (5 x 13); at most 64"),
        "{e}"
    );
    let e = refused(&["chunk_len=10,99"]);
    assert!(
        e.contains("sweep chunk_len=99") && e.contains("chunk_len"),
        "{e}"
    );
    let e = refused(&["slack=0.5", "slack=0.6"]);
    assert!(e.contains("sweep slack is given twice"), "{e}");
    let e = refused(&["slack"]);
    assert!(e.contains("expected NAME=V1,V2"), "{e}");
    // A run given as its report cannot be scored again.
    let report = dir.path().join("report.json");
    let out = crate::common::score_demo(
        dir.path(),
        None,
        &["--format", "json", "-o", report.to_str().unwrap()],
    );
    assert!(out.status.success());
    let as_report = format!("r={}", report.display());
    let out = sds(&["compare", &a, &as_report, "--sweep", "slack=0.5,0.8"]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("run r is a report") && e.contains("give the run's results"),
        "{e}"
    );
}

/// Issue 50: the tables print one row per point, the page draws each model's rank over the
/// grid, and `--tables` writes `sweep.csv` (one row per point and model, the JSON's cells).
#[test]
fn i50_4_tables_page_and_long_table() {
    let dir = tempfile::tempdir().unwrap();
    runs(dir.path());
    let [a, b, _] = runs_named(dir.path());
    let routes = dir.path().join("routes.xml");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            a.as_str(),
            b.as_str(),
            "--routes",
            routes.to_str().unwrap(),
            "--bootstrap-samples",
            "1000",
            "--sweep",
            "factors.critical=0.7,0.8,0.9",
        ];
        args.extend_from_slice(extra);
        let out = sds(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let text = run(&[]);
    let table: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("Sweep:"))
        .collect();
    assert!(
        table[0].contains("3 point(s) of factors.critical"),
        "{text}"
    );
    assert!(
        table[1].contains("results DS_safe  results SDS (rank)"),
        "{}",
        table[1]
    );
    assert!(table[1].contains("results_b SDS (rank)"));
    let rows: Vec<&str> = table[3..6].to_vec();
    assert!(
        rows[0].contains("0.7") && rows[0].ends_with("(1)"),
        "{rows:?}"
    );
    assert!(
        rows[2].contains("0.9") && rows[2].ends_with("(2)"),
        "{rows:?}"
    );
    assert!(text.contains("results vs results_b: the order changes at point(s) 2"));
    let html = run(&["--format", "html"]);
    assert!(html.contains("<h2 id=\"sweep\">"));
    assert!(html.contains("point 2: results: rank 1, SDS"), "page");
    assert!(html.contains("0: factors.critical=0.7; 1: factors.critical=0.8"));
    let tables = dir.path().join("tables");
    let json = run(&["--format", "json", "--tables", tables.to_str().unwrap()]);
    let v: Value = serde_json::from_str(&json).unwrap();
    let csv = std::fs::read_to_string(tables.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "point,factors.critical,model,ds_safe,comfort,sds,rank"
    );
    assert_eq!(lines.len(), 1 + 3 * 2);
    for (i, line) in lines[1..].iter().enumerate() {
        let (p, m) = (i / 2, i % 2);
        let f = &v["sweep"]["points"][p]["models"][m];
        let want = format!(
            "{p},{},{},{},{},{},{}",
            v["sweep"]["points"][p]["values"]["factors.critical"],
            f["model"].as_str().unwrap(),
            f["ds_safe"],
            f["comfort"],
            f["sds"],
            f["rank"]
        );
        assert_eq!(*line, want);
    }
}

/// Issue 50 on real files: Bench2DriveZoo's UniAD-Base, VAD and TCP (no telemetry, scored
/// without telemetry terms) under several lateral thresholds and work-zone factors. At the
/// given settings every figure is `sds compare`'s; without telemetry no lateral threshold moves
/// a figure, the work-zone factor does (UniAD-Base and VAD hit cones and warning signs).
#[test]
fn i50_5_zoo_models_under_lateral_thresholds() {
    let files = [
        "b2dzoo_UniAD-Base_merged.json",
        "b2dzoo_VAD_merged.json",
        "b2dzoo_TCP-only-traj_merged.json",
        "routes/bench2drive220.xml",
    ];
    let Some(fx) = crate::common::b2d_fixtures(&files) else {
        return;
    };
    let run = |name: &str, f: &str| format!("{name}={}", fx.join(f).display());
    let runs = [
        run("uniad", files[0]),
        run("vad", files[1]),
        run("tcp", files[2]),
    ];
    let routes = fx.join(files[3]);
    let compare = |extra: &[&str]| -> Value {
        let mut args: Vec<&str> = vec!["compare"];
        args.extend(runs.iter().map(String::as_str));
        args.extend([
            "--routes",
            routes.to_str().unwrap(),
            "--allow-missing-telemetry",
            "--bootstrap-samples",
            "1000",
            "--format",
            "json",
        ]);
        args.extend_from_slice(extra);
        let out = sds(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let swept = compare(&[
        "--sweep",
        "critical_excess=0.45,0.65,0.85",
        "--sweep",
        "factors.workzone=0.5,0.65",
    ]);
    let plain = compare(&[]);
    let mut without = swept.clone();
    without.as_object_mut().unwrap().remove("sweep");
    assert_eq!(without, plain);
    let points = swept["sweep"]["points"].as_array().unwrap();
    assert_eq!(points.len(), 6);
    let ds = |p: usize, m: usize| points[p]["models"][m]["ds_safe"].as_f64().unwrap();
    // The given point: critical_excess 0.65, factors.workzone 0.5 (index 2).
    for (m, name) in ["uniad", "vad", "tcp"].iter().enumerate() {
        assert_eq!(
            points[2]["models"][m]["ds_safe"],
            figures(&plain, name)[0],
            "{name}"
        );
        // No telemetry: no comfort, no SDS, no rank.
        assert_eq!(points[2]["models"][m]["sds"], Value::Null);
        assert_eq!(points[2]["models"][m]["rank"], Value::Null);
        // Lateral thresholds move nothing without a lateral error.
        for w in 0..2 {
            assert_eq!(ds(w, m), ds(2 + w, m));
            assert_eq!(ds(w, m), ds(4 + w, m));
        }
    }
    // A work-zone contact costs 0.5 / 0.65 at the default and nothing at 0.65.
    assert!(ds(1, 0) > ds(0, 0), "uniad: {} vs {}", ds(1, 0), ds(0, 0));
    assert!(ds(1, 1) > ds(0, 1), "vad");
}
