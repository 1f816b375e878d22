//! `sds compare` on seeds, repetitions and rankings (docs/SCORE.md §10.3, issue 38): the per-route
//! spread over samples, flaky routes, the seeds a claim needs, and the bootstrap ranking.

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use crate::common::sds;

/// The Bench2Drive files these tests read.
const FIXTURES: [&str; 5] = [
    "b2dzoo_UniAD-Base_merged.json",
    "b2dzoo_VAD_merged.json",
    "b2dzoo_TCP-only-traj_merged.json",
    "carla_garage_tfpp_b2d_traj_merged.json",
    "routes/bench2drive220.xml",
];

/// `sds compare --format json` with `args` (runs and options): exit code, report, stderr.
fn compare(args: &[String]) -> (Option<i32>, Value, String) {
    let mut all: Vec<&str> = vec!["compare", "--allow-missing-telemetry", "--format", "json"];
    all.extend(args.iter().map(String::as_str));
    let out = sds(&all);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let v = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
    (out.status.code(), v, err)
}

/// A merged results file of records `(route_id, score_composed, success)`.
fn write_run(dir: &Path, name: &str, recs: &[(&str, f64, bool)]) -> PathBuf {
    let records: Vec<Value> = recs
        .iter()
        .enumerate()
        .map(|(i, (id, ds, ok))| {
            let inf = crate::common::no_infractions();
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

fn model<'a>(c: &'a Value, name: &str) -> &'a Value {
    c["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == name)
        .unwrap_or_else(|| panic!("no model {name} in {c}"))
}

fn place(c: &Value, name: &str) -> (u64, Value, f64) {
    let r = c["ranking"]
        .as_array()
        .unwrap_or_else(|| panic!("no ranking in {c}"))
        .iter()
        .find(|r| r["model"] == name)
        .unwrap();
    (
        r["rank"].as_u64().unwrap(),
        r["rank_ci95"].clone(),
        r["p_best"].as_f64().unwrap(),
    )
}

/// The three Bench2DriveZoo models and CARLA Garage's TF++ over Bench2Drive's 220 routes:
/// TCP ranks first of the Zoo with [1, 1], TF++ first of all four; UniAD-Base and VAD share
/// [3, 4]. The ranking is listed by rank, and absent without `--rank`.
#[test]
fn i38_bench2drivezoo_models_ranked() {
    let Some(fx) = crate::common::b2d_fixtures(&FIXTURES) else {
        return;
    };
    let f = |n: &str| fx.join(n).display().to_string();
    let routes = ["--routes".to_string(), f("routes/bench2drive220.xml")];
    let zoo = [
        format!("uniad={}", f("b2dzoo_UniAD-Base_merged.json")),
        format!("vad={}", f("b2dzoo_VAD_merged.json")),
        format!("tcp={}", f("b2dzoo_TCP-only-traj_merged.json")),
    ];
    let mut args: Vec<String> = zoo.to_vec();
    args.extend(routes.iter().cloned());
    let (code, plain, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    assert!(plain.get("ranking").is_none(), "ranking without --rank");
    args.push("--rank".into());
    let (code, c, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(place(&c, "tcp"), (1, json!([1, 1]), 1.0));
    assert_eq!(c["ranking"][0]["model"], "tcp");
    let mut four = args.clone();
    four.push(format!(
        "tfpp={}",
        f("carla_garage_tfpp_b2d_traj_merged.json")
    ));
    let (code, c, err) = compare(&four);
    assert_eq!(code, Some(0), "{err}");
    let order: Vec<&str> = c["ranking"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["model"].as_str().unwrap())
        .collect();
    assert_eq!(order, ["tfpp", "tcp", "uniad", "vad"]);
    assert_eq!(place(&c, "tfpp"), (1, json!([1, 1]), 1.0));
    assert_eq!(place(&c, "tcp").1, json!([2, 2]));
    assert_eq!(place(&c, "uniad").1, json!([3, 4]));
    assert_eq!(place(&c, "vad").1, json!([3, 4]));
    // mean_ds is the model's mean ds over the compared routes: its DS over the 220.
    let ds = model(&c, "tcp")["driving_score"]["mean"].as_f64().unwrap();
    let mean = c["ranking"][1]["mean_ds"].as_f64().unwrap();
    assert!((ds - mean).abs() < 1e-9, "{ds} vs {mean}");
    // The table a paper pastes.
    let mut text = vec!["compare".to_string(), "--allow-missing-telemetry".into()];
    text.extend(four.iter().cloned());
    let out = sds(&text.iter().map(String::as_str).collect::<Vec<_>>());
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("uniad") && l.contains('['))
        .unwrap_or_else(|| panic!("no ranking line for uniad: {text}"));
    assert!(line.contains("3 [3, 4]"), "{line}");
}

/// The spec's ranking worked by a second implementation: one SplitMix64 seeded with
/// `bootstrap_seed`, n draws per resample, each model's mean over the drawn positions, rank =
/// 1 + the models with a strictly greater mean; the interval over B sorted ranks, p_best with a
/// shared first place split.
#[test]
fn i38_ranking_matches_a_second_implementation() {
    let dir = tempfile::tempdir().unwrap();
    let ds: [[f64; 6]; 3] = [
        [80.0, 10.0, 55.0, 100.0, 0.0, 40.0],
        [70.0, 30.0, 60.0, 90.0, 20.0, 35.0],
        [85.0, 0.0, 40.0, 100.0, 10.0, 50.0],
    ];
    let names = ["a", "b", "c"];
    let ids: Vec<String> = (1..=6).map(|i| format!("RouteScenario_{i}_rep0")).collect();
    let mut args = Vec::new();
    for (name, row) in names.iter().zip(&ds) {
        let recs: Vec<(&str, f64, bool)> = ids
            .iter()
            .zip(row)
            .map(|(id, d)| (id.as_str(), *d, *d == 100.0))
            .collect();
        args.push(format!(
            "{name}={}",
            write_run(dir.path(), name, &recs).display()
        ));
    }
    let (b, seed) = (1000usize, 7u64);
    args.extend(
        [
            "--rank",
            "--bootstrap-samples",
            "1000",
            "--bootstrap-seed",
            "7",
        ]
        .map(String::from),
    );
    let (code, c, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    // The second implementation.
    let mut s = seed;
    let mut next = || {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let n = 6;
    let rank = |means: &[f64], i: usize| 1 + means.iter().filter(|m| **m > means[i]).count();
    let mut ranks = vec![Vec::new(); 3];
    // A first place shared by k models counts 1/k to each (issue 47 item 12).
    let mut best = [0.0f64; 3];
    for _ in 0..b {
        let idx: Vec<usize> = (0..n)
            .map(|_| (((next() >> 11) as f64 * 2f64.powi(-53)) * n as f64).floor() as usize)
            .collect();
        let means: Vec<f64> = ds
            .iter()
            .map(|row| idx.iter().map(|i| row[*i]).sum::<f64>() / n as f64)
            .collect();
        for (m, r) in ranks.iter_mut().enumerate() {
            r.push(rank(&means, m));
        }
        let k = (0..3).filter(|m| rank(&means, *m) == 1).count();
        for (m, share) in best.iter_mut().enumerate() {
            if rank(&means, m) == 1 {
                *share += 1.0 / k as f64;
            }
        }
    }
    let full: Vec<f64> = ds
        .iter()
        .map(|r| r.iter().sum::<f64>() / n as f64)
        .collect();
    for (m, name) in names.iter().enumerate() {
        let best = best[m] / b as f64;
        ranks[m].sort();
        let ci = [
            ranks[m][(0.025 * b as f64).floor() as usize],
            ranks[m][(0.975 * b as f64).ceil() as usize - 1],
        ];
        assert_eq!(
            place(&c, name),
            (rank(&full, m) as u64, json!(ci), best),
            "{name}"
        );
    }
    // Listed by rank, ties by name: the full-set means are 47.5, 50.83, 47.5.
    let order: Vec<&str> = c["ranking"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["model"].as_str().unwrap())
        .collect();
    assert_eq!(order, ["b", "a", "c"]);
}

/// Seeds from real files (`--seeds`): two result files as the seeds of one model. Each route's
/// spread, the flaky routes and each seed's DS agree with `sds score` of each file alone; the
/// seeds needed follow `--repro-halfwidth`.
#[test]
fn i38_seeds_from_real_files() {
    let Some(fx) = crate::common::b2d_fixtures(&FIXTURES) else {
        return;
    };
    let f = |n: &str| fx.join(n).display().to_string();
    let xml = f("routes/bench2drive220.xml");
    let (tcp, vad) = (
        f("b2dzoo_TCP-only-traj_merged.json"),
        f("b2dzoo_VAD_merged.json"),
    );
    let args: Vec<String> = vec![
        format!("uniad={}", f("b2dzoo_UniAD-Base_merged.json")),
        format!("s1={tcp}"),
        format!("s2={vad}"),
        "--seeds".into(),
        "pair=s1,s2".into(),
        "--routes".into(),
        xml.clone(),
        "--repro-halfwidth".into(),
        "2".into(),
    ];
    let (code, c, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    // Each file scored alone.
    let score = |file: &str| -> Value {
        let out = sds(&[
            "score",
            "--results",
            file,
            "--routes",
            &xml,
            "--allow-missing-telemetry",
            "--format",
            "json",
        ]);
        serde_json::from_slice(&out.stdout).expect("sds score json")
    };
    let (a, b) = (score(&tcp), score(&vad));
    let by_key = |r: &Value| -> std::collections::HashMap<String, (f64, bool)> {
        r["routes"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|x| x["state"] != "foreign")
            .map(|x| {
                let id = x["route_id"].as_str().unwrap();
                let key = id
                    .trim_start_matches("RouteScenario_")
                    .split("_rep")
                    .next()
                    .unwrap();
                (
                    key.to_string(),
                    (
                        x["score_composed"].as_f64().unwrap_or(0.0),
                        x["success"] == true,
                    ),
                )
            })
            .collect()
    };
    let (ka, kb) = (by_key(&a), by_key(&b));
    let pair = model(&c, "pair");
    let rows = pair["routes"].as_array().unwrap();
    assert_eq!(rows.len(), 220);
    let mut flaky = Vec::new();
    for r in rows {
        let k = r["route"].as_str().unwrap();
        let ((x, sx), (y, sy)) = (ka[k], kb[k]);
        assert!(
            (r["ds_mean"].as_f64().unwrap() - (x + y) / 2.0).abs() < 1e-9,
            "{r}"
        );
        let sd = (x - y).abs() / 2f64.sqrt();
        assert!((r["ds_std"].as_f64().unwrap() - sd).abs() < 1e-9, "{r}");
        assert_eq!(r["ds_min"].as_f64(), Some(x.min(y)));
        assert_eq!(r["ds_max"].as_f64(), Some(x.max(y)));
        let share = (u8::from(sx) + u8::from(sy)) as f64 / 2.0;
        assert_eq!(r["success_share"].as_f64(), Some(share));
        if sx != sy {
            flaky.push(k.to_string());
        }
    }
    assert!(flaky.len() > 10, "{}", flaky.len());
    assert_eq!(pair["flaky_routes"], json!(flaky));
    let ds = |r: &Value| r["summary"]["driving_score"].as_f64().unwrap();
    let (da, db) = (ds(&a), ds(&b));
    let got: Vec<f64> = pair["seed_ds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        (got[0] - da).abs() < 1e-9 && (got[1] - db).abs() < 1e-9,
        "{got:?} vs {da} {db}"
    );
    let sd = (da - db).abs() / 2f64.sqrt();
    assert!((pair["seed_std"].as_f64().unwrap() - sd).abs() < 1e-9);
    let needed = (1.96 * sd / 2.0).powi(2).ceil() as u64;
    assert_eq!(pair["seeds_needed"].as_u64(), Some(needed));
    assert_eq!(c["config"]["repro.halfwidth"], 2.0);
    // The baseline has one seed: no spread, no seed count.
    let uniad = model(&c, "uniad");
    assert_eq!(uniad["seed_std"], Value::Null);
    assert_eq!(uniad["seeds_needed"], Value::Null);
    // A half-width that sizes nothing is refused before scoring.
    let mut bad = args.clone();
    *bad.last_mut().unwrap() = "0".into();
    let (code, _, err) = compare(&bad);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("repro.halfwidth"), "{err}");
}

/// Leaderboard repetitions of one key (`_rep0`, `_rep1`) are samples of one route: a model
/// with one run gets the route's spread and a flaky route from them, but (one seed) no
/// `seed_std` and no `seeds_needed`; the tables list the flaky route with each sample.
#[test]
fn i38_repetitions_of_one_key_and_one_seed() {
    let dir = tempfile::tempdir().unwrap();
    let base = write_run(
        dir.path(),
        "base",
        &[
            ("RouteScenario_1_rep0", 50.0, false),
            ("RouteScenario_2_rep0", 100.0, true),
        ],
    );
    let reps = write_run(
        dir.path(),
        "reps",
        &[
            ("RouteScenario_1_rep0", 100.0, true),
            ("RouteScenario_2_rep0", 100.0, true),
            ("RouteScenario_1_rep1", 40.0, false),
            ("RouteScenario_2_rep1", 100.0, true),
        ],
    );
    let args = vec![
        format!("base={}", base.display()),
        format!("reps={}", reps.display()),
        "--bootstrap-samples".to_string(),
        "1000".into(),
    ];
    let (code, c, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    let m = model(&c, "reps");
    assert_eq!(m["routes"][0]["route"], "1");
    assert_eq!(m["routes"][0]["ds_mean"], 70.0);
    let sd = m["routes"][0]["ds_std"].as_f64().unwrap();
    assert!((sd - 1800f64.sqrt()).abs() < 1e-9, "{sd}");
    assert_eq!(
        (
            m["routes"][0]["ds_min"].as_f64(),
            m["routes"][0]["ds_max"].as_f64()
        ),
        (Some(40.0), Some(100.0))
    );
    assert_eq!(m["routes"][0]["success_share"], 0.5);
    assert_eq!(m["routes"][1]["success_share"], 1.0);
    assert_eq!(m["flaky_routes"], json!(["1"]));
    assert_eq!(m["seed_ds"].as_array().map(Vec::len), Some(1));
    assert_eq!(m["seed_std"], Value::Null);
    assert_eq!(m["seeds_needed"], Value::Null);
    // One sample per route: no route std.
    assert_eq!(model(&c, "base")["routes"][0]["ds_std"], Value::Null);
    // The tables: the seeds line and the flaky route with both samples.
    let mut text: Vec<&str> = vec![
        "compare",
        "--allow-missing-telemetry",
        "--format",
        "markdown",
    ];
    text.extend(args.iter().map(String::as_str));
    let out = sds(&text);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Flaky routes"), "{text}");
    let line = text
        .lines()
        .find(|l| l.starts_with("| reps") && l.contains("fail"))
        .unwrap_or_else(|| panic!("no flaky row: {text}"));
    assert!(line.contains("reps: 100.0 pass; reps: 40.0 fail"), "{line}");
}

/// The HTML page of a ranked comparison of three checkpoints (ep30 the best, given last):
/// the ranking figure draws the models in the order given with each one's mean DS and its rank
/// interval, and the flaky route gets a strip of its outcomes across the seeds (one square per
/// sample, in the order of the model's runs).
#[test]
fn i38_page_draws_the_ranking_in_order_and_the_flaky_strips() {
    let dir = tempfile::tempdir().unwrap();
    let ids = ["RouteScenario_1", "RouteScenario_2", "RouteScenario_3"];
    let run = |name: &str, ds: [f64; 3], ok: [bool; 3]| {
        let recs: Vec<(&str, f64, bool)> = (0..3).map(|i| (ids[i], ds[i], ok[i])).collect();
        write_run(dir.path(), name, &recs)
    };
    let ep10 = run("ep10", [10.0, 20.0, 30.0], [false, false, false]);
    let ep20a = run("ep20a", [60.0, 100.0, 40.0], [false, true, false]);
    let ep20b = run("ep20b", [50.0, 30.0, 40.0], [false, false, false]);
    let ep30 = run("ep30", [90.0, 100.0, 95.0], [false, true, false]);
    let page = dir.path().join("c.html");
    let arg = |n: &str, p: &Path| format!("{n}={}", p.display());
    let args = [
        "compare".to_string(),
        "--allow-missing-telemetry".into(),
        arg("ep10", &ep10),
        arg("ep20a", &ep20a),
        arg("ep20b", &ep20b),
        arg("ep30", &ep30),
        "--seeds".into(),
        "ep20=ep20a,ep20b".into(),
        "--rank".into(),
        "--bootstrap-samples".into(),
        "1000".into(),
        "--format".into(),
        "html".into(),
        "-o".into(),
        page.display().to_string(),
    ];
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = sds(&argv);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(&page).unwrap();
    let at = |needle: &str| {
        html.find(needle)
            .unwrap_or_else(|| panic!("no {needle:?} in the page"))
    };
    // The ranking figure: the models in the order given (not by rank), each with its mean DS.
    let fig = at("id=\"ranking\"");
    let (a, b, c) = (at(">ep10</text>"), at(">ep20</text>"), at(">ep30</text>"));
    assert!(fig < a && a < b && b < c, "{fig} {a} {b} {c}");
    assert!(html.contains("ep10: mean DS 20.00"), "ep10's mean DS");
    assert!(html.contains("ep30: mean DS 95.00"), "ep30's mean DS");
    assert!(
        html.contains("ep30: rank 1 [1, 1]"),
        "ep30's rank and interval"
    );
    assert!(
        html.contains("ep10: rank 3 [3, 3]"),
        "ep10's rank and interval"
    );
    // The flaky strip: route 2 passed in ep20a and failed in ep20b.
    let flaky = at("id=\"flaky\"");
    let row = &html[flaky..];
    let row = &row[row
        .find("<td>RouteScenario_2</td>")
        .unwrap_or_else(|| panic!("route 2 in the strips: {}", &html[flaky..]))..];
    let row = &row[..row.find("</tr>").unwrap()];
    let pass = row
        .find("ep20a: DS 100.0, success")
        .expect("ep20a's square");
    let fail = row.find("ep20b: DS 30.0, failure").expect("ep20b's square");
    assert!(pass < fail, "{row}");
    assert_eq!(row.matches("<rect").count(), 2, "{row}");
    // Without --rank and without flaky routes: neither section.
    let plain = dir.path().join("p.html");
    let out = sds(&[
        "compare",
        "--allow-missing-telemetry",
        &arg("ep10", &ep10),
        &arg("ep30", &ep30),
        "--bootstrap-samples",
        "1000",
        "--format",
        "html",
        "-o",
        plain.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let plain = std::fs::read_to_string(&plain).unwrap();
    assert!(!plain.contains("id=\"ranking\"") && !plain.contains("id=\"flaky\""));
}

/// Issue 47 item 12: `--rank` over runs with no common route (`--common-routes`) ranked every
/// model 1; there is nothing to rank on: every rank, interval and `p_best` is null, the table
/// says `-`. Three identical runs split the first place: `p_best` 1/3 each, summing to 1 (was
/// 3.0).
#[test]
fn r4_12_rank_without_common_routes_is_null_and_ties_split() {
    let dir = tempfile::tempdir().unwrap();
    let a = write_run(dir.path(), "a", &[("RouteScenario_1_rep0", 50.0, false)]);
    let b = write_run(dir.path(), "b", &[("RouteScenario_2_rep0", 80.0, false)]);
    let args: Vec<String> = vec![
        format!("a={}", a.display()),
        format!("b={}", b.display()),
        "--rank".into(),
        "--common-routes".into(),
        "--bootstrap-samples".into(),
        "1000".into(),
    ];
    let (_, c, err) = compare(&args);
    let ranking = c["ranking"].as_array().unwrap_or_else(|| panic!("{err}"));
    assert_eq!(ranking.len(), 2, "{err}");
    for r in ranking {
        assert!(
            r["rank"].is_null() && r["rank_ci95"].is_null() && r["p_best"].is_null(),
            "{r}"
        );
    }
    let recs = [
        ("RouteScenario_1_rep0", 50.0, false),
        ("RouteScenario_2_rep0", 100.0, true),
        ("RouteScenario_3_rep0", 20.0, false),
    ];
    let mut args = Vec::new();
    for name in ["x", "y", "z"] {
        args.push(format!(
            "{name}={}",
            write_run(dir.path(), name, &recs).display()
        ));
    }
    args.extend(["--rank", "--bootstrap-samples", "1000"].map(String::from));
    let (code, c, err) = compare(&args);
    assert_eq!(code, Some(0), "{err}");
    let p: Vec<f64> = c["ranking"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["p_best"].as_f64().unwrap())
        .collect();
    assert_eq!(p.len(), 3);
    assert!(p.iter().all(|x| (x - 1.0 / 3.0).abs() < 1e-12), "{p:?}");
    assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{p:?}");
}
