//! `sds compare` (docs/SCORE.md §10.3) end to end on hand-made runs whose per-route scores are
//! chosen here: known deltas and verdicts, the bootstrap's draws re-done independently (one
//! SplitMix64 per model and metric, each seeded with the seed), a one-route case,
//! n = 0, ties, repetitions averaged, seeds grouped only by `--seeds`, the same-route-set rule
//! and `--common-routes`, the gate's exit code 5 and its message, and `inputs.route_set`. Then
//! on the real fixtures (`../shared/fixtures/b2d`, skipped with a printed reason when absent).

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::common::sds;

/// One record: route id, score_composed, success.
type Rec<'a> = (&'a str, f64, bool);

/// Writes a merged results file of these records (no telemetry: compared with
/// `--allow-missing-telemetry`).
fn write_run(dir: &Path, name: &str, recs: &[Rec<'_>]) -> PathBuf {
    let lists = [
        "collisions_layout",
        "collisions_pedestrian",
        "collisions_vehicle",
        "min_speed_infractions",
        "outside_route_lanes",
        "red_light",
        "route_dev",
        "route_timeout",
        "scenario_timeouts",
        "stop_infraction",
        "vehicle_blocked",
        "yield_emergency_vehicle_infractions",
    ];
    let records: Vec<Value> = recs
        .iter()
        .enumerate()
        .map(|(i, (id, ds, ok))| {
            let mut inf = serde_json::Map::new();
            for l in lists {
                inf.insert(l.into(), json!([]));
            }
            json!({
                "index": i, "route_id": id, "infractions": inf,
                "meta": {"duration_game": 10.0, "duration_system": 30.0, "route_length": 100.0},
                "num_infractions": 0, "save_name": format!("{id}_T_S"), "scenario_name": "S_1",
                "scores": {"score_composed": ds, "score_penalty": 1.0, "score_route": ds},
                "status": if *ok { "Completed" } else { "Failed - Agent got blocked" },
                "town_name": "Town01", "weather_id": "1"
            })
        })
        .collect();
    let run = json!({"_checkpoint": {"records": records}, "entry_status": "Finished"});
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_vec(&run).unwrap()).unwrap();
    path
}

fn compare_json(extra: &[&str], runs: &[(&str, &Path)]) -> (Option<i32>, Value, String) {
    let mut args = vec!["compare", "--allow-missing-telemetry", "--format", "json"];
    args.extend_from_slice(extra);
    let named: Vec<String> = runs
        .iter()
        .map(|(n, p)| format!("{n}={}", p.display()))
        .collect();
    args.extend(named.iter().map(String::as_str));
    let out = sds(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let v = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
    (out.status.code(), v, stderr)
}

fn ids(n: usize) -> Vec<String> {
    (1..=n).map(|i| format!("RouteScenario_{i}_rep0")).collect()
}

fn paired<'a>(c: &'a Value, model: &str, metric: &str) -> &'a Value {
    c["paired"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["model"] == model && p["metric"] == metric)
        .unwrap_or_else(|| panic!("no paired row {model} {metric} in {c}"))
}

#[test]
fn known_deltas_give_their_verdicts() {
    let dir = tempfile::tempdir().unwrap();
    let ids = ids(20);
    let base: Vec<Rec> = ids.iter().map(|i| (i.as_str(), 50.0, false)).collect();
    let up: Vec<Rec> = ids.iter().map(|i| (i.as_str(), 60.0, true)).collect();
    let same: Vec<Rec> = ids.iter().map(|i| (i.as_str(), 50.0, false)).collect();
    let b = write_run(dir.path(), "base", &base);
    let u = write_run(dir.path(), "up", &up);
    let s = write_run(dir.path(), "same", &same);
    let (code, c, err) = compare_json(&[], &[("base", &b), ("up", &u), ("same", &s)]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(c["schema"], "sds-compare/1");
    assert_eq!(c["baseline"], "base");
    let ds = paired(&c, "up", "ds");
    assert_eq!(ds["n"], 20);
    assert_eq!(ds["delta"], 10.0);
    assert_eq!(ds["ci95"], json!([10.0, 10.0]));
    assert_eq!(ds["p_better"], 1.0);
    assert_eq!(ds["verdict"], "better");
    assert_eq!(paired(&c, "up", "success")["delta"], 1.0);
    // Ties: no difference on any route is not better.
    let t = paired(&c, "same", "ds");
    assert_eq!(
        (&t["delta"], &t["ci95"], &t["p_better"], &t["verdict"]),
        (
            &json!(0.0),
            &json!([0.0, 0.0]),
            &json!(0.0),
            &json!("within noise")
        )
    );
    // n = 0: no telemetry, so comfort is undefined everywhere.
    let cf = paired(&c, "up", "comfort");
    assert_eq!(cf["n"], 0);
    for k in ["delta", "ci95", "p_better"] {
        assert!(cf[k].is_null(), "{k}: {cf}");
    }
    assert_eq!(cf["verdict"], "no data", "v1.4: {cf}");
    // Flips: every route went from failed to success.
    let f = &c["flips"][0];
    assert_eq!(f["model"], "up");
    assert_eq!(f["fixed"].as_array().unwrap().len(), 20);
    assert_eq!(f["regressed"], json!([]));
    assert_eq!(f["largest"].as_array().unwrap().len(), 10);
    assert_eq!(f["largest"][0]["key"], "1"); // all ties on |d|: by key, byte-wise
    assert_eq!(f["largest"][1]["key"], "10");
    // One seed each: the report says that seeds would tighten the intervals.
    assert!(c["notes"].to_string().contains("seeds"));
}

#[test]
fn one_route() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_run(dir.path(), "a", &[("RouteScenario_7_rep0", 40.0, false)]);
    let b = write_run(dir.path(), "b", &[("RouteScenario_7_rep0", 30.0, false)]);
    let (code, c, err) = compare_json(&[], &[("a", &a), ("b", &b)]);
    assert_eq!(code, Some(0), "{err}");
    let ds = paired(&c, "b", "ds");
    assert_eq!((&ds["n"], &ds["delta"]), (&json!(1), &json!(-10.0)));
    assert_eq!(ds["ci95"], json!([-10.0, -10.0]));
    assert_eq!(ds["verdict"], "worse");
}

/// The bootstrap's draws re-done here, one generator per model and metric (v1.4), each seeded
/// with `--bootstrap-seed`.
#[test]
fn draw_order_across_models_and_metrics() {
    let dir = tempfile::tempdir().unwrap();
    let ids = ids(13);
    let make = |name: &str, f: &dyn Fn(usize) -> (f64, bool)| {
        let recs: Vec<Rec> = ids
            .iter()
            .enumerate()
            .map(|(i, id)| {
                let (d, s) = f(i);
                (id.as_str(), d, s)
            })
            .collect();
        write_run(dir.path(), name, &recs)
    };
    let base = make("base", &|i| ((i * 7 % 11) as f64 * 9.0, i % 3 == 0));
    let m1 = make("m1", &|i| ((i * 5 % 13) as f64 * 8.0, i % 2 == 0));
    let m2 = make("m2", &|i| ((i * 3 % 7) as f64 * 14.0, i % 4 == 1));
    let (code, c, err) = compare_json(
        &["--bootstrap-samples", "1001", "--bootstrap-seed", "12345"],
        &[("base", &base), ("m1", &m1), ("m2", &m2)],
    );
    assert_eq!(code, Some(0), "{err}");
    let b = 1001usize;
    let metrics = ["ds", "success", "ds_safe", "comfort"];
    let mut checked = 0;
    for (mi, model) in ["m1", "m2"].iter().enumerate() {
        for (k, metric) in metrics.iter().enumerate() {
            let d: Vec<f64> = c["routes"]
                .as_array()
                .unwrap()
                .iter()
                .filter_map(|r| {
                    Some(r["values"][mi + 1][k].as_f64()? - r["values"][0][k].as_f64()?)
                })
                .collect();
            let p = paired(&c, model, metric);
            if d.is_empty() {
                assert!(p["delta"].is_null());
                assert_eq!(p["verdict"], "no data");
                continue;
            }
            let n = d.len();
            let mut s: u64 = 12345;
            let mut next = || {
                s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = s;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^ (z >> 31)
            };
            let mut stats: Vec<f64> = (0..b)
                .map(|_| {
                    let mut sum = 0.0;
                    for _ in 0..n {
                        let u = (next() >> 11) as f64 / 9_007_199_254_740_992.0;
                        sum += d[(u * n as f64).floor() as usize];
                    }
                    sum / n as f64
                })
                .collect();
            let better = stats.iter().filter(|x| **x > 0.0).count() as f64 / b as f64;
            stats.sort_by(f64::total_cmp);
            let lo = stats[(0.025 * b as f64).floor() as usize];
            let hi = stats[(0.975 * b as f64).ceil() as usize - 1];
            assert_eq!(p["ci95"], json!([lo, hi]), "{model} {metric}");
            assert_eq!(p["p_better"], json!(better), "{model} {metric}");
            checked += 1;
        }
    }
    assert_eq!(
        checked, 6,
        "ds, success, ds_safe for two models (comfort has n = 0)"
    );
    // Another seed draws other numbers.
    let (_, c2, _) = compare_json(
        &["--bootstrap-samples", "1001", "--bootstrap-seed", "1"],
        &[("base", &base), ("m1", &m1), ("m2", &m2)],
    );
    assert_ne!(
        paired(&c2, "m1", "ds")["ci95"],
        paired(&c, "m1", "ds")["ci95"]
    );
}

#[test]
fn the_gate_exits_5_naming_model_metric_delta_and_interval() {
    let dir = tempfile::tempdir().unwrap();
    let ids = ids(10);
    let base: Vec<Rec> = ids.iter().map(|i| (i.as_str(), 80.0, true)).collect();
    let worse: Vec<Rec> = ids.iter().map(|i| (i.as_str(), 70.0, true)).collect();
    let b = write_run(dir.path(), "base", &base);
    let w = write_run(dir.path(), "cand", &worse);
    let out_file = dir.path().join("cmp.json");
    let out = sds(&[
        "compare",
        "--allow-missing-telemetry",
        "--fail-if-worse",
        "ds,success",
        "--format",
        "json",
        "-o",
        out_file.to_str().unwrap(),
        &format!("base={}", b.display()),
        &format!("cand={}", w.display()),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(
        err.contains("cand is worse than the baseline on ds: delta -10.0000, 95 % interval [-10.0000, -10.0000]"),
        "{err}"
    );
    assert!(!err.contains("on success"), "success did not change: {err}");
    // The report is written before the gate fails.
    let c: Value = serde_json::from_slice(&std::fs::read(&out_file).unwrap()).unwrap();
    assert_eq!(c["config"]["fail_if_worse"], json!(["ds", "success"]));
    // Not gated on ds: exit 0.
    let (code, _, err) = compare_json(
        &["--fail-if-worse", "success"],
        &[("base", &b), ("cand", &w)],
    );
    assert_eq!(code, Some(0), "{err}");
    // The other way round the candidate is better: exit 0.
    let (code, _, err) = compare_json(&["--fail-if-worse", "ds"], &[("cand", &w), ("base", &b)]);
    assert_eq!(code, Some(0), "{err}");
    // --baseline picks the baseline whatever the order.
    let (code, c, _) = compare_json(
        &["--fail-if-worse", "ds", "--baseline", "base"],
        &[("cand", &w), ("base", &b)],
    );
    assert_eq!((code, &c["baseline"]), (Some(5), &json!("base")));
    // An unknown metric is a usage error.
    let (code, _, err) = compare_json(&["--fail-if-worse", "dss"], &[("base", &b), ("cand", &w)]);
    assert_eq!(code, Some(2));
    assert!(err.contains("unknown metric dss"), "{err}");
}

#[test]
fn different_route_sets_are_refused_unless_common_routes() {
    let dir = tempfile::tempdir().unwrap();
    let all = ids(6);
    let a: Vec<Rec> = all.iter().map(|i| (i.as_str(), 50.0, true)).collect();
    let b: Vec<Rec> = all[..4].iter().map(|i| (i.as_str(), 40.0, true)).collect();
    let (pa, pb) = (
        write_run(dir.path(), "a", &a),
        write_run(dir.path(), "b", &b),
    );
    let (code, _, err) = compare_json(&[], &[("a", &pa), ("b", &pb)]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("2 route key(s) are not in every run (first: 5, 6)")
            && err.contains("b lacks 2"),
        "{err}"
    );
    assert!(err.contains("--common-routes"), "{err}");
    let (code, c, err) = compare_json(&["--common-routes"], &[("a", &pa), ("b", &pb)]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("compared over the 4 route key(s) every run holds"),
        "{err}"
    );
    assert_eq!(c["scope"]["routes"], 4);
    assert_eq!(c["scope"]["common_routes"], true);
    assert_eq!(c["scope"]["left_out"], json!([["a", ["5", "6"]]]));
    assert_eq!(paired(&c, "b", "ds")["n"], 4);
    // Each model's aggregates run over the shared routes too.
    assert_eq!(c["models"][0]["driving_score"]["mean"], 50.0);
    assert_eq!(c["models"][0]["route_counts"], json!([4]));
    // docs/SCORE.md §10.3: `routes` is the per-route spread over the compared keys.
    assert_eq!(c["models"][0]["routes"].as_array().map(Vec::len), Some(4));
}

#[test]
fn repetitions_are_averaged_per_key() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_run(
        dir.path(),
        "a",
        &[
            ("RouteScenario_1_rep0", 100.0, true),
            ("RouteScenario_2_rep0", 10.0, false),
            ("RouteScenario_1_rep1", 0.0, false),
        ],
    );
    let b = write_run(
        dir.path(),
        "b",
        &[
            ("RouteScenario_2_rep0", 30.0, false),
            ("RouteScenario_1_rep0", 20.0, false),
        ],
    );
    let (code, c, err) = compare_json(&[], &[("a", &a), ("b", &b)]);
    assert_eq!(code, Some(0), "{err}");
    // Keys in the baseline's order (its first record of each key).
    let keys: Vec<&str> = c["routes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["key"].as_str().unwrap())
        .collect();
    assert_eq!(keys, ["1", "2"]);
    assert_eq!(c["routes"][0]["values"][0][0], 50.0, "rep0 100 and rep1 0");
    assert_eq!(c["routes"][0]["values"][0][1], 0.5, "success fraction");
    assert_eq!(
        c["routes"][0]["route_ids"][0],
        json!(["RouteScenario_1_rep0", "RouteScenario_1_rep1"])
    );
    // d = (20 - 50, 30 - 10), summed in that order.
    assert_eq!(paired(&c, "b", "ds")["delta"], -5.0);
    // A success fraction of 0.5 is neither a regression nor a fix.
    assert_eq!(c["flips"][0]["regressed"], json!([]));
}

#[test]
fn seeds_are_grouped_only_by_the_seeds_option() {
    let dir = tempfile::tempdir().unwrap();
    let ids = ids(4);
    let run = |name: &str, ds: f64| {
        let recs: Vec<Rec> = ids.iter().map(|i| (i.as_str(), ds, ds > 50.0)).collect();
        write_run(dir.path(), name, &recs)
    };
    let (b, m1, m2) = (run("b", 40.0), run("m_1", 60.0), run("m_2", 80.0));
    // Names like m_1, m_2 are not grouped by themselves: three models.
    let (code, c, err) = compare_json(&[], &[("b", &b), ("m_1", &m1), ("m_2", &m2)]);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(c["models"].as_array().unwrap().len(), 3);
    // --seeds groups them: the per-route value is the mean over seeds.
    let (code, c, err) = compare_json(
        &["--seeds", "m=m_1,m_2"],
        &[("b", &b), ("m_1", &m1), ("m_2", &m2)],
    );
    assert_eq!(code, Some(0), "{err}");
    let m = &c["models"][1];
    assert_eq!(m["name"], "m");
    assert_eq!(m["runs"], json!(["m_1", "m_2"]));
    assert_eq!(m["driving_score"]["mean"], 70.0);
    assert_eq!(m["driving_score"]["std"], 200f64.sqrt());
    assert_eq!(paired(&c, "m", "ds")["delta"], 30.0);
    assert!(c["notes"]
        .to_string()
        .contains("m = the mean over the seeds m_1, m_2 (grouped by seeds)"));
    // The table says it too, with mean ± std.
    let out = sds(&[
        "compare",
        "--allow-missing-telemetry",
        "--seeds",
        "m=m_1,m_2",
        &format!("b={}", b.display()),
        &format!("m_1={}", m1.display()),
        &format!("m_2={}", m2.display()),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("70.00 ± 14.14") && text.contains("m: seeds m_1, m_2"),
        "{text}"
    );
    // A seed group named like another run is refused, never merged with it.
    let (code, _, err) = compare_json(
        &["--seeds", "b=m_1,m_2"],
        &[("b", &b), ("m_1", &m1), ("m_2", &m2)],
    );
    assert_eq!(code, Some(2));
    assert!(err.contains("two models are named b"), "{err}");
    // A seed that is not a run.
    let (code, _, err) = compare_json(&["--seeds", "m=m_1,m_9"], &[("b", &b), ("m_1", &m1)]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("seeds names m_9, which is not a run (--seeds)"),
        "{err}"
    );
}

#[test]
fn telemetry_per_run_and_formats() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo(dir.path());
    // The telemetry root given after the results file, and by --telemetry-of.
    let tel = run.join("telemetry");
    let res = run.join("results.json");
    let out = sds(&[
        "compare",
        "--format",
        "json",
        &format!("a={}:{}", res.display(), tel.display()),
        &format!("b={}", res.display()),
        "--telemetry-of",
        &format!("b={}", tel.display()),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let c: Value = serde_json::from_slice(&out.stdout).unwrap();
    // With telemetry, comfort is compared.
    assert!(paired(&c, "b", "comfort")["n"].as_u64().unwrap() > 0);
    for (format, needle) in [
        ("markdown", "| b | ds |"),
        ("latex", "\\toprule"),
        ("table", "Paired comparison against the baseline a"),
        ("html", "id=\"per-route\""),
    ] {
        let out = sds(&[
            "compare",
            "--format",
            format,
            &format!("a={}:{}", res.display(), tel.display()),
            &format!("b={}:{}", res.display(), tel.display()),
        ]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{format}");
        assert!(text.contains(needle), "{format}: {text}");
        assert!(
            text.contains("Emergency Brake") && text.contains("SDS"),
            "{format}"
        );
    }
}

fn demo(dir: &Path) -> PathBuf {
    let run = dir.join("demo");
    let out = sds(&["demo", run.to_str().unwrap()]);
    assert!(out.status.success());
    run
}

/// `inputs.route_set` in every score report: the counted route ids sorted byte-wise, joined
/// with `\n`, hashed with SHA-256.
#[test]
fn score_reports_carry_the_route_set() {
    use sha2::{Digest, Sha256};
    let dir = tempfile::tempdir().unwrap();
    let a = write_run(
        dir.path(),
        "a",
        &[
            ("RouteScenario_9_rep0", 1.0, false),
            ("RouteScenario_10_rep0", 1.0, false),
        ],
    );
    let out = sds(&[
        "score",
        "--allow-missing-telemetry",
        "--results",
        a.to_str().unwrap(),
        "--format",
        "json",
    ]);
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    let want: String = Sha256::digest(b"RouteScenario_10_rep0\nRouteScenario_9_rep0")
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    assert_eq!(
        r["inputs"]["route_set"],
        json!({"routes": 2, "sha256": want})
    );
    assert_eq!(r["inputs"]["files"][0]["records"], 2);
}

fn fixtures() -> Option<std::path::PathBuf> {
    crate::common::b2d_fixtures(&["routes/bench2drive220.xml", "lead_tfv6_per_route"])
}

/// TransFuser++ (merged file) against LEAD (per-route files) over the 220 routes: the paired
/// table is printed, and the gate exits 5 exactly when the verdict on DS is `worse`.
#[test]
fn fixtures_tfpp_against_lead_and_the_gate() {
    let Some(fx) = fixtures() else { return };
    let xml = fx.join("routes/bench2drive220.xml");
    let tfpp = fx.join("carla_garage_tfpp_b2d_traj_merged.json");
    let lead = fx.join("lead_tfv6_per_route");
    let pdm = fx.join("carla_garage_pdm_lite_b2d_traj_merged.json");
    let base = |extra: &[&str], runs: &[(&str, &Path)]| {
        let mut args = vec![
            "compare".to_string(),
            "--allow-missing-telemetry".into(),
            "--routes".into(),
            xml.display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        args.extend(runs.iter().map(|(n, p)| format!("{n}={}", p.display())));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        sds(&args)
    };
    let out = base(&[], &[("tfpp", &tfpp), ("lead", &lead)]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("Paired comparison against the baseline tfpp"),
        "{text}"
    );
    let row = text
        .lines()
        .find(|l| l.starts_with("lead") && l.contains(" ds "))
        .unwrap();
    assert!(row.contains("220"), "{row}");
    println!("{text}");
    for (runs, label) in [
        (
            vec![("tfpp", tfpp.as_path()), ("lead", lead.as_path())],
            "lead vs tfpp",
        ),
        (
            vec![("pdm", pdm.as_path()), ("tfpp", tfpp.as_path())],
            "tfpp vs pdm",
        ),
    ] {
        let out = base(&["--format", "json"], &runs);
        let c: Value = serde_json::from_slice(&out.stdout).unwrap();
        let verdict = paired(&c, runs[1].0, "ds")["verdict"]
            .as_str()
            .unwrap()
            .to_string();
        let gated = base(&["--fail-if-worse", "ds"], &runs);
        let want = if verdict == "worse" { 5 } else { 0 };
        assert_eq!(
            gated.status.code(),
            Some(want),
            "{label}: verdict {verdict}"
        );
        if want == 5 {
            let err = String::from_utf8_lossy(&gated.stderr);
            assert!(
                err.contains("tfpp is worse than the baseline on ds"),
                "{err}"
            );
        }
    }
}

/// The options `sds compare` shares with `sds score` (RunArgs) score each run as `sds score`
/// would: each model row carries the run's §8.1 and §8.5 figures of `sds score` with the same
/// flags, and `--protocol` puts each run's protocol table on the HTML page.
#[test]
fn shared_options_score_each_run_as_sds_score() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo(dir.path());
    let (res, tel, xml) = (
        run.join("results.json"),
        run.join("telemetry"),
        run.join("routes.xml"),
    );
    let shared = [
        "--routes",
        xml.to_str().unwrap(),
        "--set",
        "slack=0.9",
        "--protocol",
        "lb2.1",
        "--jobs",
        "1",
    ];
    let out = sds(&[
        &[
            "score",
            "--format",
            "json",
            "--results",
            res.to_str().unwrap(),
        ],
        &["--telemetry", tel.to_str().unwrap()][..],
        &shared[..],
    ]
    .concat());
    assert_eq!(out.status.code(), Some(0));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(r["summary"]["protocols"]["lb2.1"].is_object());
    let a = format!("a={}:{}", res.display(), tel.display());
    let b = format!("b={}:{}", res.display(), tel.display());
    let out = sds(&[&["compare", "--format", "json", &a, &b][..], &shared[..]].concat());
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let c: Value = serde_json::from_slice(&out.stdout).unwrap();
    let m = &c["models"][1];
    let s = &r["summary"];
    for (model_key, summary_key) in [
        ("driving_score", "driving_score"),
        ("mean_ds_safe", "mean_ds_safe"),
        ("mean_comfort", "mean_comfort"),
        ("mean_comfort_moving", "mean_comfort_moving"),
        ("mean_stationary_share", "mean_stationary_share"),
        ("distance_km", "distance_km"),
    ] {
        assert!(s[summary_key].is_f64(), "{summary_key}");
        assert_eq!(m[model_key]["mean"], s[summary_key], "{model_key}");
    }
    let out = sds(&[&["compare", "--format", "html", &a, &b][..], &shared[..]].concat());
    let page = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0));
    // The run sections (after the comparison's tables) each hold the protocol table.
    let runs = &page[page.find("<section id=\"run-a\">").unwrap()..];
    assert!(runs.matches("lb2.1").count() >= 2, "{runs}");
    let out = sds(&[&["compare", "--format", "table", &a, &b][..], &shared[..]].concat());
    assert!(String::from_utf8_lossy(&out.stdout).contains("Comfort (moving)"));
    // A bad shared option is the same usage error as for sds score.
    let out = sds(&["compare", &a, &b, "--protocol", "nope"]);
    assert_eq!(out.status.code(), Some(2));
}

/// docs/SCORE.md §10.3: each asked protocol's score is a compared metric (`ds@<id>`), drawn after the four
/// base metrics; its delta is the mean of the per-route differences of the runs' own protocol
/// scores; it can gate; gating on a protocol not asked is refused.
#[test]
fn protocol_scores_are_paired_metrics() {
    let tmp = tempfile::tempdir().unwrap();
    let ids = ids(6);
    let a: Vec<Rec> = ids.iter().map(|id| (id.as_str(), 100.0, true)).collect();
    let b: Vec<Rec> = ids
        .iter()
        .enumerate()
        .map(|(i, id)| (id.as_str(), 40.0 + 10.0 * i as f64, false))
        .collect();
    let (pa, pb) = (
        write_run(tmp.path(), "a", &a),
        write_run(tmp.path(), "b", &b),
    );
    let runs = [("a", pa.as_path()), ("b", pb.as_path())];
    let (code, c, err) = compare_json(&["--protocol", "lb2.1,lb2.0"], &runs);
    assert_eq!(code, Some(0), "{err}");
    let metrics: Vec<&str> = c["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap())
        .collect();
    assert_eq!(
        metrics,
        ["ds", "success", "ds_safe", "comfort", "ds@lb2.0", "ds@lb2.1"]
    );
    // The protocol scores from each run's own report (sds score --protocol).
    let scores = |path: &Path| -> Vec<f64> {
        let out = sds(&[
            "score",
            "--allow-missing-telemetry",
            "--protocol",
            "lb2.1",
            "--format",
            "json",
            "--results",
            path.to_str().unwrap(),
        ]);
        let r: Value = serde_json::from_slice(&out.stdout).unwrap();
        r["routes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x["protocols"]["lb2.1"]["score"].as_f64().unwrap())
            .collect()
    };
    let (sa, sb) = (scores(&pa), scores(&pb));
    let delta = sb.iter().zip(&sa).map(|(x, y)| x - y).sum::<f64>() / 6.0;
    let row = paired(&c, "b", "ds@lb2.1");
    assert_eq!(row["n"], 6);
    assert!(
        (row["delta"].as_f64().unwrap() - delta).abs() < 1e-12,
        "{row}"
    );
    assert!(delta < 0.0);
    assert_eq!(row["verdict"], "worse");
    // Per route, each model's values carry the protocol scores too.
    assert_eq!(c["routes"][0]["values"][1].as_array().unwrap().len(), 6);
    // The gate on a protocol metric.
    let (code, _, err) = compare_json(
        &["--protocol", "lb2.1", "--fail-if-worse", "ds@lb2.1"],
        &runs,
    );
    assert_eq!(code, Some(5), "{err}");
    assert!(
        err.contains("b is worse than the baseline on ds@lb2.1"),
        "{err}"
    );
    // A protocol metric without its protocol, and an unknown protocol id.
    let (code, _, err) = compare_json(&["--fail-if-worse", "ds@lb2.1"], &runs);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("protocols = lb2.1"), "{err}");
    let (code, _, err) = compare_json(&["--fail-if-worse", "ds@lb9"], &runs);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("unknown metric ds@lb9"), "{err}");
    // Each model and metric draws its own generator: the base metrics' figures do not change
    // when protocols are added.
    let (_, plain, _) = compare_json(&[], &runs);
    for m in ["ds", "success", "ds_safe", "comfort"] {
        assert_eq!(paired(&plain, "b", m), paired(&c, "b", m), "{m}");
    }
}
