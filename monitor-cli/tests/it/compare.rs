//! `sds compare`: paired intervals, verdicts, the gate and what the tables and page show.

// ---- issue 33 item 5: the ability rule named in compare's tables ----

/// `sds compare --ability-rule b2d-0.0.3` names the rule in its Bench2Drive table heading, as
/// `sds score`'s does, in text, Markdown and LaTeX.
#[test]
fn i33_5_compare_tables_name_the_ability_rule() {
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    let results = dir.path().join("results.json");
    let telemetry = dir.path().join("telemetry");
    let run = |name: &str| format!("{name}={}:{}", results.display(), telemetry.display());
    let (a, b) = (run("a"), run("b"));
    let routes = dir.path().join("routes.xml");
    for (rule, extra) in [
        ("b2d-0.0.3", vec!["--ability-rule", "b2d-0.0.3"]),
        ("b2d-0.0.4", vec![]),
    ] {
        for format in ["table", "markdown", "latex"] {
            let mut args = vec![
                "compare",
                &a,
                &b,
                "--routes",
                routes.to_str().unwrap(),
                "--bootstrap-samples",
                "1000",
                "--format",
                format,
            ];
            args.extend(extra.iter().copied());
            let out = crate::common::sds(&args);
            let text = String::from_utf8_lossy(&out.stdout);
            let heading = text
                .lines()
                .find(|l| l.contains("Bench2Drive: closed-loop metrics"))
                .unwrap_or_else(|| {
                    panic!(
                        "{format}: no Bench2Drive table: {}",
                        String::from_utf8_lossy(&out.stderr)
                    )
                });
            assert!(
                heading.contains(&format!("ability rule {rule}")),
                "{format}: {heading}"
            );
        }
    }
}

/// Issue 33 item 3 and parts of items 8, issue 34 findings 4 and 6: one generator per model and
/// metric, `no data` and the gate, the bounds on B, the forest plot's names and empty panels,
/// the page's status line, the missing-maps warning said once.
mod bootstrap_and_gate {
    use std::path::{Path, PathBuf};

    use serde_json::{json, Value};

    use crate::common::sds;

    /// One record: route id, score_composed, success, town.
    type Rec = (String, f64, bool, &'static str);

    /// A merged results file of these records (no telemetry: compared with
    /// `--allow-missing-telemetry`, so comfort is undefined on every route).
    fn write_run(dir: &Path, name: &str, recs: &[Rec]) -> PathBuf {
        let records: Vec<Value> = recs
            .iter()
            .enumerate()
            .map(|(i, (id, ds, ok, town))| {
                let inf = crate::common::no_infractions();
                json!({
                    "index": i, "route_id": id, "infractions": inf,
                    "meta": {"duration_game": 10.0, "duration_system": 30.0, "route_length": 100.0},
                    "num_infractions": 0, "save_name": format!("{id}_T_S"), "scenario_name": "S_1",
                    "scores": {"score_composed": ds, "score_penalty": 1.0, "score_route": ds},
                    "status": if *ok { "Completed" } else { "Failed - Agent got blocked" },
                    "town_name": town, "weather_id": "1"
                })
            })
            .collect();
        let run = json!({"_checkpoint": {"records": records}, "entry_status": "Finished"});
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, serde_json::to_vec(&run).unwrap()).unwrap();
        path
    }

    /// A run of `n` routes whose DS and success follow `f(i)`.
    fn run_of(dir: &Path, name: &str, n: usize, f: impl Fn(usize) -> (f64, bool)) -> PathBuf {
        let recs: Vec<Rec> = (0..n)
            .map(|i| {
                let (ds, ok) = f(i);
                (format!("RouteScenario_{}_rep0", i + 1), ds, ok, "Town01")
            })
            .collect();
        write_run(dir, name, &recs)
    }

    /// `sds compare --format json` of named runs: exit code, report, stderr.
    fn compare(extra: &[&str], runs: &[(&str, &Path)]) -> (Option<i32>, Value, String) {
        let mut args: Vec<String> = ["compare", "--allow-missing-telemetry", "--format", "json"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        args.extend(extra.iter().map(|s| s.to_string()));
        args.extend(runs.iter().map(|(n, p)| format!("{n}={}", p.display())));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = sds(&args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        let v = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
        (out.status.code(), v, stderr)
    }

    fn row<'a>(c: &'a Value, model: &str, metric: &str) -> &'a Value {
        c["paired"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["model"] == model && p["metric"] == metric)
            .unwrap_or_else(|| panic!("no paired row {model} {metric} in {c}"))
    }

    /// SplitMix64 and the percentile bootstrap written out from (docs/SCORE.md §10.3), independently of
    /// the library: a fresh generator seeded with `seed`, B resamples of n indices
    /// `floor(((next() >> 11) * 2^-53) * n)`, each resample's mean summed in draw order; the
    /// interval `[stat[floor(0.025 B)], stat[ceil(0.975 B) - 1]]` and `p_better`.
    fn bootstrap_by_hand(d: &[f64], b: usize, seed: u64) -> ([f64; 2], f64) {
        let mut s = seed;
        let mut next = || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        let n = d.len();
        let mut stats: Vec<f64> = (0..b)
            .map(|_| {
                let mut sum = 0.0;
                for _ in 0..n {
                    let u = (next() >> 11) as f64 * 2f64.powi(-53);
                    sum += d[(u * n as f64).floor() as usize];
                }
                sum / n as f64
            })
            .collect();
        let better = stats.iter().filter(|x| **x > 0.0).count() as f64 / b as f64;
        stats.sort_by(f64::total_cmp);
        let lo = stats[(0.025 * b as f64).floor() as usize];
        let hi = stats[(0.975 * b as f64).ceil() as usize - 1];
        ([lo, hi], better)
    }

    /// The paired differences of model `m` (index in the report's models) on metric `k`.
    fn differences(c: &Value, m: usize, k: usize) -> Vec<f64> {
        c["routes"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|r| Some(r["values"][m][k].as_f64()? - r["values"][0][k].as_f64()?))
            .collect()
    }

    /// Every paired row of `model` on the four base metrics.
    fn rows_of(c: &Value, model: &str) -> Vec<Value> {
        ["ds", "success", "ds_safe", "comfort"]
            .iter()
            .map(|m| row(c, model, m).clone())
            .collect()
    }

    /// docs/SCORE.md §10.3: each (model, metric) has its own generator seeded with `bootstrap_seed`, so a
    /// protocol, a model added or a model left out changes no other model's figures; one
    /// interval re-derived by hand.
    #[test]
    fn i33_3_each_model_and_metric_draws_its_own_generator() {
        let dir = tempfile::tempdir().unwrap();
        let n = 13;
        let base = run_of(dir.path(), "base", n, |i| {
            ((i * 7 % 11) as f64 * 9.0, i % 3 == 0)
        });
        let m1 = run_of(dir.path(), "m1", n, |i| {
            ((i * 5 % 13) as f64 * 8.0, i % 2 == 0)
        });
        let m2 = run_of(dir.path(), "m2", n, |i| {
            ((i * 3 % 7) as f64 * 14.0, i % 4 == 1)
        });
        let m3 = run_of(dir.path(), "m3", n, |i| (i as f64 * 7.0, i > 6));
        let opts = ["--bootstrap-samples", "1000", "--bootstrap-seed", "7"];
        let with = |extra: &[&str], runs: &[(&str, &Path)]| {
            let (code, c, err) = compare(&[&opts[..], extra].concat(), runs);
            assert_eq!(code, Some(0), "{err}");
            c
        };
        let plain = with(&[], &[("base", &base), ("m1", &m1), ("m2", &m2)]);
        let proto = with(
            &["--protocol", "lb2.1,lb2.0"],
            &[("base", &base), ("m1", &m1), ("m2", &m2)],
        );
        let fewer = with(&[], &[("base", &base), ("m2", &m2)]);
        let more = with(
            &[],
            &[("base", &base), ("m3", &m3), ("m1", &m1), ("m2", &m2)],
        );
        for model in ["m1", "m2"] {
            assert_eq!(rows_of(&plain, model), rows_of(&proto, model), "{model}");
            assert_eq!(rows_of(&plain, model), rows_of(&more, model), "{model}");
        }
        assert_eq!(rows_of(&plain, "m2"), rows_of(&fewer, "m2"));
        // A protocol's own figures do not depend on the models either.
        let proto_fewer = with(&["--protocol", "lb2.1"], &[("base", &base), ("m2", &m2)]);
        assert_eq!(
            row(&proto, "m2", "ds@lb2.1"),
            row(&proto_fewer, "m2", "ds@lb2.1")
        );
        // Common random numbers: m1 and m2 compare the same n routes, so their resamples are of
        // the same route positions; re-derived by hand for m2 (second model), ds and success.
        for (k, metric) in [(0, "ds"), (1, "success")] {
            let d = differences(&plain, 2, k);
            assert_eq!(d.len(), n);
            let (ci, p) = bootstrap_by_hand(&d, 1000, 7);
            let got = row(&plain, "m2", metric);
            assert_eq!(got["ci95"], json!(ci), "m2 {metric}");
            assert_eq!(got["p_better"], json!(p), "m2 {metric}");
        }
    }

    /// On Bench2DriveZoo's UniAD-Base (baseline), VAD and TCP-traj over the 220 routes: every
    /// interval is the same with and without `--protocol` and with a model added in the middle;
    /// the first model's ds keeps its v1.3 interval; TCP's ds interval re-derived by hand.
    #[test]
    fn i33_3_fixture_intervals_do_not_move_with_protocol_or_model() {
        let Some(fx) = crate::common::b2d_fixtures(&[
            "routes/bench2drive220.xml",
            "b2dzoo_TCP-only-traj_merged.json",
        ]) else {
            return;
        };
        let xml = fx.join("routes/bench2drive220.xml");
        let uniad = fx.join("b2dzoo_UniAD-Base_merged.json");
        let vad = fx.join("b2dzoo_VAD_merged.json");
        let tcp = fx.join("b2dzoo_TCP-only-traj_merged.json");
        let tfpp = fx.join("carla_garage_tfpp_b2d_traj_merged.json");
        let xml_s = xml.to_str().unwrap();
        let with = |extra: &[&str], runs: &[(&str, &Path)]| {
            let (code, c, err) = compare(&[&["--routes", xml_s][..], extra].concat(), runs);
            assert_eq!(code, Some(0), "{err}");
            c
        };
        let three = [("uniad", uniad.as_path()), ("vad", &vad), ("tcp", &tcp)];
        let plain = with(&[], &three);
        let proto = with(&["--protocol", "lb2.1"], &three);
        let more = with(
            &[],
            &[
                ("uniad", &uniad),
                ("tfpp", &tfpp),
                ("vad", &vad),
                ("tcp", &tcp),
            ],
        );
        for model in ["vad", "tcp"] {
            assert_eq!(rows_of(&plain, model), rows_of(&proto, model), "{model}");
            assert_eq!(rows_of(&plain, model), rows_of(&more, model), "{model}");
        }
        // The first model's ds draws what v1.3's single generator drew first (the figures of
        // `sds compare` before v1.4 on these files, B = 10000, seed 0).
        let vad_ds = row(&plain, "vad", "ds");
        assert_eq!(vad_ds["n"], 220);
        assert_eq!(
            vad_ds["ci95"],
            json!([-8.128834554545454, 1.2528106772727277])
        );
        // TCP (second model): before v1.4, [8.4581, 19.6296] without --protocol and
        // [8.3932, 19.7084] with it; now the spec's own generator, re-derived here.
        let d = differences(&plain, 2, 0);
        let (ci, p) = bootstrap_by_hand(&d, 10_000, 0);
        let tcp_ds = row(&plain, "tcp", "ds");
        assert_eq!(tcp_ds["ci95"], json!(ci));
        assert_eq!(tcp_ds["p_better"], json!(p));
        assert_eq!(tcp_ds["verdict"], "better");
    }

    /// docs/SCORE.md §10.3: comfort undefined on every route (no telemetry) is `no data`, not `within
    /// noise`; gated, it fails with exit 5 and says the metric could not be compared; the
    /// tables and the page say `no data`.
    #[test]
    fn i33_3_comfort_without_data_fails_the_gate() {
        let dir = tempfile::tempdir().unwrap();
        let a = run_of(dir.path(), "a", 8, |i| (50.0 + i as f64, true));
        let b = run_of(dir.path(), "b", 8, |i| (52.0 + i as f64, true));
        let runs = [("a", a.as_path()), ("b", b.as_path())];
        let (code, c, err) = compare(&["--fail-if-worse", "comfort"], &runs);
        assert_eq!(
            code,
            Some(5),
            "a gate on a metric without data must fail: {err}"
        );
        assert!(
            err.contains("b could not be compared with the baseline on comfort")
                && err.contains("n = 0"),
            "{err}"
        );
        let cf = row(&c, "b", "comfort");
        assert_eq!((&cf["n"], &cf["verdict"]), (&json!(0), &json!("no data")));
        assert!(cf["ci95"].is_null() && cf["delta"].is_null());
        // The same runs gated on a metric with data: ds is better, the gate passes.
        let (code, _, err) = compare(&["--fail-if-worse", "ds"], &runs);
        assert_eq!(code, Some(0), "{err}");
        // The tables and the page say it.
        for format in ["table", "markdown", "latex"] {
            let out = sds(&[
                "compare",
                "--allow-missing-telemetry",
                "--format",
                format,
                &format!("a={}", a.display()),
                &format!("b={}", b.display()),
            ]);
            let text = String::from_utf8_lossy(&out.stdout);
            let line = text
                .lines()
                .find(|l| l.contains("comfort") && l.contains(" 0 "));
            assert!(
                line.is_some_and(|l| l.contains("no data")),
                "{format}: {text}"
            );
        }
    }

    /// Issue 34 finding 6: `--common-routes` with no shared key compared nothing and the gate
    /// passed; now every verdict is `no data` and the gate fails (exit 5).
    #[test]
    fn r3_06_common_routes_without_shared_keys_fail_the_gate() {
        let dir = tempfile::tempdir().unwrap();
        let recs = |from: usize| -> Vec<Rec> {
            (from..from + 5)
                .map(|i| (format!("RouteScenario_{i}_rep0"), 60.0, true, "Town01"))
                .collect()
        };
        let a = write_run(dir.path(), "a", &recs(1));
        let b = write_run(dir.path(), "b", &recs(100));
        let runs = [("a", a.as_path()), ("b", b.as_path())];
        let (code, c, err) = compare(&["--common-routes", "--fail-if-worse", "ds"], &runs);
        assert_eq!(code, Some(5), "{err}");
        assert!(
            err.contains("b could not be compared with the baseline on ds")
                && err.contains("share no route key"),
            "{err}"
        );
        assert_eq!(c["scope"]["routes"], 0);
        for p in c["paired"].as_array().unwrap() {
            assert_eq!(
                (&p["n"], &p["verdict"]),
                (&json!(0), &json!("no data")),
                "{p}"
            );
        }
        // Not gated: the report is written, exit 0.
        let (code, _, err) = compare(&["--common-routes"], &runs);
        assert_eq!(code, Some(0), "{err}");
    }

    /// Issue 34 finding 6: `--bootstrap-samples` 1e12 aborted the process, 2^64 − 1 panicked
    /// and 1 gave a one-point interval: B is bounded (1,000 ≤ B ≤ 1,000,000) and n × B is at most
    /// 250 million per model and metric, each a usage error (exit 2) naming the option and
    /// the bound.
    #[test]
    fn r3_06_bootstrap_samples_are_bounded() {
        let dir = tempfile::tempdir().unwrap();
        let a = run_of(dir.path(), "a", 10, |i| (40.0 + i as f64, false));
        let b = run_of(dir.path(), "b", 10, |i| (45.0 + i as f64, true));
        let runs = [("a", a.as_path()), ("b", b.as_path())];
        for bad in [
            "0",
            "1",
            "999",
            "1000001",
            "1000000000000",
            "18446744073709551615",
        ] {
            let (code, c, err) = compare(&["--bootstrap-samples", bad], &runs);
            assert_eq!(code, Some(2), "B = {bad}: {err}");
            assert!(
                err.contains(&format!("bootstrap_samples = {bad}"))
                    && err.contains("(--bootstrap-samples)")
                    && err.contains("between 1000 and 1000000"),
                "B = {bad}: {err}"
            );
            assert!(c.is_null(), "no report for B = {bad}");
        }
        for good in ["1000", "1000000"] {
            let (code, c, err) = compare(&["--bootstrap-samples", good], &runs);
            assert_eq!(code, Some(0), "B = {good}: {err}");
            assert_eq!(
                c["config"]["bootstrap_samples"],
                good.parse::<u64>().unwrap()
            );
        }
        // n × B: 300 routes at B = 1,000,000 is 3e8 draws a metric, above the budget.
        let a = run_of(dir.path(), "big_a", 300, |i| {
            ((i % 10) as f64 * 10.0, false)
        });
        let b = run_of(dir.path(), "big_b", 300, |i| ((i % 7) as f64 * 10.0, false));
        let (code, _, err) = compare(&["--bootstrap-samples", "1000000"], &[("a", &a), ("b", &b)]);
        assert_eq!(code, Some(2), "{err}");
        assert!(
            err.contains("--bootstrap-samples")
                && err.contains("over the 300 routes")
                && err.contains("above the budget of 250000000")
                && err.contains("at most 833333 resamples"),
            "{err}"
        );
        // Refused before drawing: the message is the budget check's, made before any draw (a
        // wall-clock bound here raced a busy machine, issue 47 item 13).
        let (code, _, err) = compare(&["--bootstrap-samples", "833333"], &[("a", &a), ("b", &b)]);
        assert_eq!(code, Some(0), "{err}");
    }

    /// Issue 34 finding 4 (forest plot): model names with U+202E and a newline were drawn raw in
    /// the forest plot while every other output escapes them.
    #[test]
    fn r3_04_forest_plot_escapes_model_names() {
        let dir = tempfile::tempdir().unwrap();
        let a = run_of(dir.path(), "a", 6, |i| (40.0 + i as f64, false));
        let b = run_of(dir.path(), "b", 6, |i| (45.0 + i as f64, true));
        let evil = "new\u{202e}1\nrow";
        let out = sds(&[
            "compare",
            "--allow-missing-telemetry",
            "--format",
            "html",
            &format!("base={}", a.display()),
            &format!("{evil}={}", b.display()),
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let page = String::from_utf8(out.stdout).unwrap();
        let svg = &page[page.find("<svg").unwrap()..page.find("</svg>").unwrap()];
        assert!(!page.contains('\u{202e}'), "a raw U+202E on the page");
        assert!(
            svg.contains("new\\u{202e}1\\nrow"),
            "the forest plot's label is not the escaped name"
        );
    }

    /// Issue 33 item 8 (compare parts): the page showed a stray "ok" under its heading (the
    /// script's status line), and an empty "Δ comfort" panel said nothing.
    #[test]
    fn i33_8_compare_page_status_hidden_and_empty_panel_says_no_data() {
        let dir = tempfile::tempdir().unwrap();
        let a = run_of(dir.path(), "a", 6, |i| (40.0 + i as f64, false));
        let b = run_of(dir.path(), "b", 6, |i| (45.0 + i as f64, true));
        let out = sds(&[
            "compare",
            "--allow-missing-telemetry",
            "--format",
            "html",
            &format!("a={}", a.display()),
            &format!("b={}", b.display()),
        ]);
        let page = String::from_utf8(out.stdout).unwrap();
        assert!(
            page.contains("<p id=\"status\" hidden>"),
            "the status line is shown"
        );
        let svg = &page[page.find("<svg").unwrap()..page.find("</svg>").unwrap()];
        let comfort = &svg[svg.find("Δ comfort").expect("a comfort panel")..];
        assert!(
            comfort.contains("no data (n = 0)"),
            "the empty comfort panel says nothing"
        );
        // Panels with data have no such note.
        let before = &svg[..svg.find("Δ comfort").unwrap()];
        assert!(!before.contains("no data"), "{before}");
    }

    /// Issue 33 item 8 (compare part): the missing-maps warning (one line of 600+ characters)
    /// was repeated for every run; now one short line for the comparison, towns listed once,
    /// each run's count of routes.
    #[test]
    fn i33_8_missing_maps_warning_said_once() {
        let dir = tempfile::tempdir().unwrap();
        let maps = dir.path().join("maps");
        std::fs::create_dir(&maps).unwrap();
        let recs = |n: usize| -> Vec<Rec> {
            (0..n)
                .map(|i| {
                    let town = ["Town03", "Town12", "Town13"][i % 3];
                    (format!("RouteScenario_{}_rep0", i + 1), 50.0, true, town)
                })
                .collect()
        };
        let a = write_run(dir.path(), "a", &recs(9));
        let b = write_run(dir.path(), "b", &recs(9));
        let (code, _, err) = compare(&["--maps", maps.to_str().unwrap()], &[("a", &a), ("b", &b)]);
        assert_eq!(code, Some(0), "{err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.contains("no map")).collect();
        assert_eq!(lines.len(), 1, "{err}");
        let line = lines[0];
        assert!(
            line.contains("3 towns (Town03, Town12, Town13)") && line.contains("(a 9, b 9)"),
            "{line}"
        );
        assert!(
            line.chars().count() < 300,
            "{} characters: {line}",
            line.len()
        );
    }
}

/// Issue 46 item 6: `sds compare --route-subset`, as `sds score` has it. One TransFuser++ shard
/// (28 of the 220 routes) against Bench2Drive's route XML: `found` compares the 28 routes with
/// a record and each model's DS is `sds score --route-subset found`'s (89.47); `all` (the
/// default) compares 220, the 192 without a record counting 0.
#[test]
fn i46_6_compare_takes_route_subset() {
    let Some(fx) = crate::common::b2d_fixtures(&[
        "tfpp_raw_shards/eval_bench2drive220_0.json",
        "routes/bench2drive220.xml",
    ]) else {
        return;
    };
    let shard = fx.join("tfpp_raw_shards/eval_bench2drive220_0.json");
    let routes = fx.join("routes/bench2drive220.xml");
    let (a, b) = (
        format!("a={}", shard.display()),
        format!("b={}", shard.display()),
    );
    let run = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            &a,
            &b,
            "--routes",
            routes.to_str().unwrap(),
            "--allow-missing-telemetry",
            "--bootstrap-samples",
            "1000",
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        let out = crate::common::sds(&args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{extra:?}: {err}");
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let score = crate::common::sds(&[
        "score",
        "--results",
        shard.to_str().unwrap(),
        "--routes",
        routes.to_str().unwrap(),
        "--allow-missing-telemetry",
        "--route-subset",
        "found",
    ]);
    let score: serde_json::Value = serde_json::from_slice(&score.stdout).unwrap();
    let found = run(&["--route-subset", "found"]);
    assert_eq!(found["scope"]["routes"], 28);
    assert_eq!(
        found["models"][0]["driving_score"]["mean"],
        score["summary"]["driving_score"]
    );
    assert!((score["summary"]["driving_score"].as_f64().unwrap() - 89.4677).abs() < 1e-3);
    let all = run(&[]);
    assert_eq!(all["scope"]["routes"], 220);
    assert_eq!(run(&["--route-subset", "all"]), all);
    // `--set route_subset=found` is the same setting.
    assert_eq!(run(&["--set", "route_subset=found"]), found);
}

/// Issue 46 item 6: the Traffic Sign bracket and the undecided junction credits that `sds
/// score`'s table states were missing from `sds compare`'s tables. TransFuser++ and TCP over
/// the 220 routes without maps: each model's note in compare's tables is its `sds score` note
/// (TF++ [70.53, 93.68], 22 undecided), in text and Markdown.
#[test]
fn i46_6_compare_tables_say_the_traffic_sign_bracket() {
    let Some(fx) = crate::common::b2d_fixtures(&[
        "carla_garage_tfpp_b2d_traj_merged.json",
        "b2dzoo_TCP-only-traj_merged.json",
        "routes/bench2drive220.xml",
    ]) else {
        return;
    };
    let routes = fx.join("routes/bench2drive220.xml");
    let runs = [
        ("tfpp", fx.join("carla_garage_tfpp_b2d_traj_merged.json")),
        ("tcp", fx.join("b2dzoo_TCP-only-traj_merged.json")),
    ];
    let note_of = |text: &str| -> String {
        text.lines()
            .find(|l| l.contains("Traffic_Signs under"))
            .unwrap_or_else(|| panic!("no Traffic_Signs note: {text}"))
            .trim()
            .to_string()
    };
    let mut notes = Vec::new();
    for (name, file) in &runs {
        let out = crate::common::sds(&[
            "score",
            "--results",
            file.to_str().unwrap(),
            "--routes",
            routes.to_str().unwrap(),
            "--allow-missing-telemetry",
            "--format",
            "table",
        ]);
        notes.push((*name, note_of(&String::from_utf8_lossy(&out.stdout))));
    }
    assert!(
        notes[0].1.contains("Traffic Sign lies in [70.53, 93.68]"),
        "{}",
        notes[0].1
    );
    assert!(notes[0].1.contains("22 failed route(s)"), "{}", notes[0].1);
    let specs: Vec<String> = runs
        .iter()
        .map(|(n, f)| format!("{n}={}", f.display()))
        .collect();
    let out = crate::common::sds(&[
        "compare",
        &specs[0],
        &specs[1],
        "--routes",
        routes.to_str().unwrap(),
        "--allow-missing-telemetry",
        "--bootstrap-samples",
        "1000",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    for (name, note) in &notes {
        assert!(
            text.lines().any(|l| l.trim() == format!("{name}: {note}")),
            "{name}: no `{note}` in {text}"
        );
    }
    let md = crate::common::sds(&[
        "compare",
        &specs[0],
        &specs[1],
        "--routes",
        routes.to_str().unwrap(),
        "--allow-missing-telemetry",
        "--bootstrap-samples",
        "1000",
        "--format",
        "markdown",
    ]);
    assert!(String::from_utf8_lossy(&md.stdout).contains("Traffic Sign lies in \\[70.53, 93.68\\]"));
}

/// Paired differences and verdicts on small hand-made runs, the gate, seeds, telemetry per run,
/// and the real fixtures' runs against each other.
mod paired;
