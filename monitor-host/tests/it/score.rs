//! `sds score`: protocols, the lateral reference, route sets and what the report says per route.

// ---- issue 33 items 1, 5, 6 and issue 34 finding 8: scoring protocols ----

mod protocols {
    use std::path::{Path, PathBuf};

    use serde_json::{json, Value};

    use crate::common::sds;

    /// `../shared/fixtures/b2d`, or `None` (with a printed reason) when it is absent.
    fn b2d_fixtures() -> Option<PathBuf> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures/b2d");
        if dir.join("routes/bench2drive220.xml").is_file() {
            Some(dir)
        } else {
            eprintln!("skipped: {} is absent", dir.display());
            None
        }
    }

    fn min_speed(ps: &[f64]) -> Vec<String> {
        ps.iter()
            .map(|p| format!("Average speed is {p}% of the surrounding traffic's one"))
            .collect()
    }

    /// A merged results file of `records` (route id, status, RC, infractions, penalty).
    fn write_results(dir: &Path, records: &[(&str, &str, f64, Value, f64)]) -> PathBuf {
        let records: Vec<Value> = records
            .iter()
            .map(|(id, status, rc, inf, pen)| {
                json!({
                    "route_id": id, "scenario_name": "Accident_1", "status": status,
                    "town_name": "Town12", "infractions": inf,
                    "scores": {"score_route": rc, "score_penalty": pen, "score_composed": rc * pen},
                    "meta": {"route_length": 1000.0, "duration_game": 60.0}
                })
            })
            .collect();
        let path = dir.join("results.json");
        std::fs::write(
            &path,
            json!({"_checkpoint": {"records": records}}).to_string(),
        )
        .unwrap();
        path
    }

    /// `sds score --format json` without telemetry; the report and stderr.
    fn score(args: &[&str]) -> (Value, String) {
        let mut all = vec!["score", "--allow-missing-telemetry", "--format", "json"];
        all.extend_from_slice(args);
        let out = sds(&all);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        let report = serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}); stderr:\n{stderr}"));
        (report, stderr)
    }

    fn close(a: f64, b: f64, what: &str) {
        assert!((a - b).abs() < 1e-9, "{what}: {a} vs {b}");
    }

    fn route<'a>(report: &'a Value, id: &str) -> &'a Value {
        report["routes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["route_id"] == id)
            .unwrap_or_else(|| panic!("no route {id}"))
    }

    /// TCP-traj's shape: 20 min-speed entries per route, above and below 100 %, regrouped by 5
    /// at the harmonic mean (spec v1.4 §8.4 "The min-speed grid"), worked by hand.
    #[test]
    fn i33_1_min_speed_grid_regroups_twenty_checkpoints() {
        let dir = tempfile::tempdir().unwrap();
        // Route 1: Bench2Drive's 20 checkpoints.
        //   [50, 200, 100, 100, 50] -> 5 / (1/50 + 1/200 + 1/100 + 1/100 + 1/50) = 5 / 0.065
        //                            = 1000/13 = 76.92 %: an event;
        //   [200; 5] -> 200 %: none;  [80; 5] -> 80 %: an event;  [1000; 5]: none.
        let mut twenty = vec![50.0, 200.0, 100.0, 100.0, 50.0];
        twenty.extend([200.0; 5]);
        twenty.extend([80.0; 5]);
        twenty.extend([1000.0; 5]);
        // Route 2: the Leaderboard's shape (4 entries, all below 100): every entry an event.
        // Route 3: 3 entries, one at or above 100: Bench2Drive's grid, one group
        //   3 / (1/50 + 1/150 + 1/90) = 79.41 %: one event.
        let results = write_results(
            dir.path(),
            &[
                (
                    "RouteScenario_1_rep0",
                    "Completed",
                    100.0,
                    json!({"min_speed_infractions": min_speed(&twenty)}),
                    1.0,
                ),
                (
                    "RouteScenario_2_rep0",
                    "Completed",
                    100.0,
                    json!({"min_speed_infractions": min_speed(&[60.0, 70.0, 80.0, 90.0])}),
                    1.0,
                ),
                (
                    "RouteScenario_3_rep0",
                    "Completed",
                    50.0,
                    json!({"min_speed_infractions": min_speed(&[50.0, 150.0, 90.0])}),
                    1.0,
                ),
            ],
        );
        let r = results.to_str().unwrap();
        // N = 4: one route without a record.
        let (rep, _) = score(&[
            "--results",
            r,
            "--protocol",
            "all",
            "--expected-routes",
            "4",
        ]);
        assert_eq!(rep["config"]["min_speed_grid"], "auto");
        let (r1, r2, r3) = (
            route(&rep, "RouteScenario_1_rep0"),
            route(&rep, "RouteScenario_2_rep0"),
            route(&rep, "RouteScenario_3_rep0"),
        );
        assert_eq!(r1["min_speed_grid"], "b2d-20");
        assert_eq!(r2["min_speed_grid"], "lb-4");
        assert_eq!(r3["min_speed_grid"], "b2d-20");
        let events = |r: &Value, p: &str| r["protocols"][p]["min_speed_events"].as_u64().unwrap();
        for p in ["lb2.0", "lb2.1", "lead-nds"] {
            assert_eq!(
                (events(r1, p), events(r2, p), events(r3, p)),
                (2, 4, 1),
                "{p}"
            );
        }
        for p in ["b2d", "f2d"] {
            assert_eq!(events(r1, p), 0, "{p} charges no min-speed event");
        }
        let pen = |r: &Value, p: &str| r["protocols"][p]["penalty"].as_f64().unwrap();
        let q1 = 1000.0 / 13.0;
        let q3 = 3.0 / (1.0 / 50.0 + 1.0 / 150.0 + 1.0 / 90.0);
        let lb21 = [
            1.0 / (1.0 + 0.4 * (1.0 - q1 / 100.0) + 0.4 * 0.2),
            1.0 / (1.0 + 0.4 * (0.4 + 0.3 + 0.2 + 0.1)),
            1.0 / (1.0 + 0.4 * (1.0 - q3 / 100.0)),
        ];
        let lb20 = [
            (1.0 - 0.3 * (1.0 - q1 / 100.0)) * (1.0 - 0.3 * 0.2),
            0.88 * 0.91 * 0.94 * 0.97,
            1.0 - 0.3 * (1.0 - q3 / 100.0),
        ];
        for (i, r) in [r1, r2, r3].into_iter().enumerate() {
            close(pen(r, "lb2.1"), lb21[i], "lb2.1 penalty");
            close(pen(r, "lb2.0"), lb20[i], "lb2.0 penalty");
            close(pen(r, "lead-nds"), lb20[i], "lead-nds penalty");
        }
        // Σ score / N and, under the Leaderboard, Σ penalty / N (v1.4); LEAD keeps the mean.
        let s = &rep["summary"]["protocols"];
        let rc = [100.0, 100.0, 50.0];
        let ds21: f64 = (0..3).map(|i| rc[i] * lb21[i]).sum::<f64>() / 4.0;
        close(
            s["lb2.1"]["driving_score"].as_f64().unwrap(),
            ds21,
            "lb2.1 DS",
        );
        close(
            s["lb2.1"]["infraction_score"].as_f64().unwrap(),
            lb21.iter().sum::<f64>() / 4.0,
            "lb2.1 IS",
        );
        close(
            s["lb2.0"]["infraction_score"].as_f64().unwrap(),
            lb20.iter().sum::<f64>() / 4.0,
            "lb2.0 IS",
        );
        close(
            s["lead-nds"]["infraction_score"].as_f64().unwrap(),
            lb20.iter().sum::<f64>() / 3.0,
            "lead IS",
        );
        close(
            s["b2d"]["infraction_score"].as_f64().unwrap(),
            1.0,
            "b2d IS",
        );
        let regrouped: Vec<&str> = rep["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(Value::as_str)
            .filter(|w| w.contains("regrouped"))
            .collect();
        assert_eq!(regrouped.len(), 1, "{regrouped:?}");
        assert!(
            regrouped[0].starts_with("protocols: 2 of 3 records"),
            "{}",
            regrouped[0]
        );

        // `lb-4` charges every entry below 100; `b2d-20` regroups route 2 as well.
        let (rep, _) = score(&[
            "--results",
            r,
            "--protocol",
            "lb2.1",
            "--set",
            "min_speed_grid=lb-4",
        ]);
        assert_eq!(rep["config"]["min_speed_grid"], "lb-4");
        let r1 = route(&rep, "RouteScenario_1_rep0");
        assert_eq!(
            (r1["min_speed_grid"].as_str(), events(r1, "lb2.1")),
            (Some("lb-4"), 7)
        );
        assert!(!rep["warnings"].to_string().contains("regrouped"));
        let (rep, _) = score(&[
            "--results",
            r,
            "--protocol",
            "lb2.1",
            "--set",
            "min_speed_grid=b2d-20",
        ]);
        let r2 = route(&rep, "RouteScenario_2_rep0");
        // One group: 4 / (1/60 + 1/70 + 1/80 + 1/90) = 73.85 %.
        let q2 = 4.0 / (1.0 / 60.0 + 1.0 / 70.0 + 1.0 / 80.0 + 1.0 / 90.0);
        assert_eq!(events(r2, "lb2.1"), 1);
        close(
            pen(r2, "lb2.1"),
            1.0 / (1.0 + 0.4 * (1.0 - q2 / 100.0)),
            "b2d-20 route 2",
        );
        let bad = sds(&[
            "score",
            "--allow-missing-telemetry",
            "--results",
            r,
            "--set",
            "min_speed_grid=20",
        ]);
        assert_eq!(bad.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&bad.stderr).contains("auto, b2d-20 or lb-4"));
    }

    /// TCP-traj, UniAD-Base and VAD: the Leaderboard scores of Bench2Drive files before v1.4
    /// (every entry an event: TCP lb2.1 19.10, lb2.0 7.26 against DS 59.90) and now.
    #[test]
    fn i33_1_real_bench2drive_files_on_the_twenty_checkpoint_grid() {
        let Some(b2d) = b2d_fixtures() else { return };
        let xml = b2d.join("routes/bench2drive220.xml");
        // (model, DS, lb2.0, lb2.1, records regrouped, records, lb2.0 and lb2.1 under lb-4)
        let cases = [
            (
                "TCP-only-traj",
                59.8967,
                32.9110,
                38.4526,
                193,
                210,
                7.2580,
                19.0997,
            ),
            (
                "UniAD-Base",
                45.8132,
                39.3507,
                40.8647,
                198,
                218,
                27.4324,
                31.7492,
            ),
            ("VAD", 42.3507, 37.6107, 39.2058, 195, 213, 28.0161, 31.4792),
        ];
        for (model, ds, lb20, lb21, regrouped, records, old20, old21) in cases {
            let results = b2d.join(format!("b2dzoo_{model}_merged.json"));
            let args = [
                "--results",
                results.to_str().unwrap(),
                "--routes",
                xml.to_str().unwrap(),
                "--protocol",
                "all",
            ];
            let (rep, _) = score(&args);
            let s = &rep["summary"]["protocols"];
            let got = |p: &str| s[p]["driving_score"].as_f64().unwrap();
            let near = |a: f64, b: f64, what: &str| {
                assert!((a - b).abs() < 1e-4, "{model} {what}: {a} vs {b}")
            };
            near(rep["summary"]["driving_score"].as_f64().unwrap(), ds, "DS");
            near(got("lb2.0"), lb20, "lb2.0");
            near(got("lb2.1"), lb21, "lb2.1");
            let want = format!("protocols: {regrouped} of {records} records hold");
            assert!(
                rep["warnings"].to_string().contains(&want),
                "{model}: {want}"
            );
            let mut lb4 = args.to_vec();
            lb4.extend(["--set", "min_speed_grid=lb-4"]);
            let (rep, _) = score(&lb4);
            let s = &rep["summary"]["protocols"];
            near(
                s["lb2.0"]["driving_score"].as_f64().unwrap(),
                old20,
                "lb2.0 on lb-4",
            );
            near(
                s["lb2.1"]["driving_score"].as_f64().unwrap(),
                old21,
                "lb2.1 on lb-4",
            );
        }
    }

    /// Fail2Drive's rule stays (infraction lists only), with a warning naming the successes that
    /// did not finish: UniAD-Base's 29 "Failed - TickRuntime" routes.
    #[test]
    fn i33_6_f2d_successes_that_did_not_finish_are_warned() {
        let dir = tempfile::tempdir().unwrap();
        let results = write_results(
            dir.path(),
            &[
                ("RouteScenario_1_rep0", "Completed", 100.0, json!({}), 1.0),
                (
                    "RouteScenario_2_rep0",
                    "Failed - TickRuntime",
                    40.0,
                    json!({}),
                    1.0,
                ),
                (
                    "RouteScenario_3_rep0",
                    "Completed",
                    80.0,
                    json!({"route_timeout": ["x"]}),
                    1.0,
                ),
            ],
        );
        let (rep, _) = score(&["--results", results.to_str().unwrap(), "--protocol", "f2d"]);
        let w = rep["warnings"].to_string();
        assert!(
            w.contains("f2d: 1 route(s) count as Fail2Drive successes though they did not finish")
                && w.contains("RouteScenario_2_rep0"),
            "{w}"
        );
        // Only with f2d asked.
        let (rep, _) = score(&[
            "--results",
            results.to_str().unwrap(),
            "--protocol",
            "lb2.1",
        ]);
        assert!(!rep["warnings"].to_string().contains("Fail2Drive"));

        let Some(b2d) = b2d_fixtures() else { return };
        let results = b2d.join("b2dzoo_UniAD-Base_merged.json");
        let xml = b2d.join("routes/bench2drive220.xml");
        let (rep, stderr) = score(&[
            "--results",
            results.to_str().unwrap(),
            "--routes",
            xml.to_str().unwrap(),
            "--protocol",
            "f2d",
        ]);
        let s = &rep["summary"]["protocols"]["f2d"];
        assert!((s["success_rate"].as_f64().unwrap() - 33.1818).abs() < 1e-3);
        let w: Vec<&str> = rep["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(Value::as_str)
            .filter(|w| w.contains("Fail2Drive successes"))
            .collect();
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("protocols: f2d: 29 route(s)")
                && w[0].contains("RouteScenario_4937_rep0, RouteScenario_4683_rep0")
                && w[0].ends_with("and 19 more"),
            "{}",
            w[0]
        );
        assert!(stderr.contains("f2d: 29 route(s)"), "{stderr}");
    }

    /// Impossible percentages (negative, not finite) are refused with a warning naming the route
    /// and the entry; factors beyond [0, 1] are clamped with a warning: every protocol score
    /// stays in [0, 100] and none is null.
    #[test]
    fn r3_08_protocol_scores_stay_within_0_and_100() {
        let dir = tempfile::tempdir().unwrap();
        let out = |q: &str| {
            format!("Agent went outside its route lanes for about 3.0 meters ({q}% of the completed route)")
        };
        let results = write_results(
            dir.path(),
            &[
                (
                    "RouteScenario_1_rep0",
                    "Completed",
                    100.0,
                    json!({"min_speed_infractions": ["Average speed is -300% of the surrounding traffic's one"]}),
                    1.0,
                ),
                (
                    "RouteScenario_2_rep0",
                    "Completed",
                    100.0,
                    json!({"min_speed_infractions": ["Average speed is -1e300% of the surrounding traffic's one", "Average speed is 1e999% of the surrounding traffic's one"]}),
                    1.0,
                ),
                (
                    "RouteScenario_3_rep0",
                    "Completed",
                    100.0,
                    json!({"outside_route_lanes": [out("150.0")]}),
                    0.0,
                ),
                (
                    "RouteScenario_4_rep0",
                    "Completed",
                    100.0,
                    json!({"outside_route_lanes": [out("-50.0")]}),
                    1.0,
                ),
            ],
        );
        let (rep, stderr) = score(&["--results", results.to_str().unwrap(), "--protocol", "all"]);
        for r in rep["routes"].as_array().unwrap() {
            for (p, s) in r["protocols"].as_object().unwrap() {
                let score = s["score"].as_f64().unwrap_or(f64::NAN);
                let pen = s["penalty"].as_f64().unwrap_or(f64::NAN);
                assert!(
                    (0.0..=100.0).contains(&score),
                    "{} {p}: score {score}",
                    r["route_id"]
                );
                assert!(
                    (0.0..=1.0).contains(&pen),
                    "{} {p}: penalty {pen}",
                    r["route_id"]
                );
            }
        }
        for (p, a) in rep["summary"]["protocols"].as_object().unwrap() {
            let ds = a["driving_score"].as_f64().unwrap_or(f64::NAN);
            assert!((0.0..=100.0).contains(&ds), "{p}: DS {ds}");
        }
        // The refused min-speed entries charge nothing: the routes are perfect.
        for id in ["RouteScenario_1_rep0", "RouteScenario_2_rep0"] {
            let r = route(&rep, id);
            assert_eq!(r["protocols"]["lb2.0"]["score"], 100.0, "{id}");
            assert_eq!(r["protocols"]["lb2.1"]["min_speed_events"], 0, "{id}");
        }
        let warned = |route: &str, what: &str| {
            stderr
                .lines()
                .any(|l| l.contains(route) && l.contains(what))
        };
        assert!(
            warned(
                "RouteScenario_1_rep0",
                "impossible percentage (negative or not finite), refused: \"Average speed is -300%"
            ),
            "{stderr}"
        );
        assert!(
            warned(
                "RouteScenario_2_rep0",
                "refused: \"Average speed is -1e300%"
            ),
            "{stderr}"
        );
        assert!(
            warned("RouteScenario_2_rep0", "refused: \"Average speed is 1e999%"),
            "{stderr}"
        );
        // LEAD's 1 - Q/100: Q = 150 clamped to 0, Q = -50 refused (factor 1).
        assert_eq!(
            route(&rep, "RouteScenario_3_rep0")["protocols"]["lead-nds"]["score"],
            0.0
        );
        assert_eq!(
            route(&rep, "RouteScenario_4_rep0")["protocols"]["lead-nds"]["score"],
            100.0
        );
        assert!(
            warned(
                "RouteScenario_3_rep0",
                "lead-nds: outside_route_lanes factor 1 - 150/100 = -0.5 clamped to [0, 1]"
            ),
            "{stderr}"
        );
        assert!(
            warned("RouteScenario_3_rep0", "clamped to [0, 1]")
                && warned("RouteScenario_3_rep0", "f_out"),
            "{stderr}"
        );
        assert!(
            warned(
                "RouteScenario_4_rep0",
                "lead-nds: outside_route_lanes entry with an impossible percentage"
            ),
            "{stderr}"
        );
    }

    /// `--ability-rule RULE` is `--set ability_rule=RULE` on `score` (and on `compare` and
    /// `watch`, which take the same options); an unknown rule is a usage error.
    #[test]
    fn i33_5_ability_rule_flag_is_the_setting() {
        let dir = tempfile::tempdir().unwrap();
        crate::common::demo(dir.path());
        let flag = crate::common::score_demo(dir.path(), None, &["--ability-rule", "b2d-0.0.3"]);
        let set = crate::common::score_demo(dir.path(), None, &["--set", "ability_rule=b2d-0.0.3"]);
        assert_eq!(flag.status.code(), set.status.code());
        assert_eq!(flag.stdout, set.stdout);
        let report: Value = serde_json::from_slice(&flag.stdout).unwrap();
        assert_eq!(report["config"]["ability_rule"], "b2d-0.0.3");
        assert_eq!(
            report["summary"]["bench2drive"]["ability_rule"],
            "b2d-0.0.3"
        );
        let bad = crate::common::score_demo(dir.path(), None, &["--ability-rule", "0.0.3"]);
        assert_eq!(bad.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&bad.stderr).contains("b2d-0.0.3"));
        for cmd in ["compare", "watch"] {
            let help = String::from_utf8(sds(&[cmd, "--help"]).stdout).unwrap();
            assert!(help.contains("--ability-rule <RULE>"), "{cmd}: {help}");
        }
    }

    /// Without every town's map, the Traffic Sign note gives the undecided routes and the
    /// bracket [decided, decided + undecided]; UniAD-Base's published 14.21 lies inside it.
    #[test]
    fn i33_5_undecided_traffic_sign_bracket_holds_the_published_rate() {
        let Some(b2d) = b2d_fixtures() else { return };
        let maps = b2d.join("../maps");
        let results = b2d.join("b2dzoo_UniAD-Base_merged.json");
        let xml = b2d.join("routes/bench2drive220.xml");
        let out = sds(&[
            "score",
            "--allow-missing-telemetry",
            "--format",
            "table",
            "--results",
            results.to_str().unwrap(),
            "--routes",
            xml.to_str().unwrap(),
            "--maps",
            maps.to_str().unwrap(),
            "--ability-rule",
            "b2d-0.0.3",
        ]);
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains("ability rule b2d-0.0.3"), "{text}");
        let note = text
            .lines()
            .find(|l| l.contains("Traffic Sign lies in"))
            .unwrap_or_else(|| panic!("no bracket note:\n{text}"));
        assert!(
            note.contains(
                "Traffic_Signs under b2d-0.0.3: 51 route(s) whose junction credit is undecided"
            ) && note.contains("[2.63, 29.47] (5/190 decided, up to 56/190"),
            "{note}"
        );
        let open = note.find("lies in [").unwrap() + "lies in [".len();
        let close = open + note[open..].find(']').unwrap();
        let (lo, hi) = note[open..close].split_once(", ").unwrap();
        let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
        let published = 14.21; // Bench2Drive's table, UniAD-Base Traffic Sign (27/190)
        assert!(lo <= published && published <= hi, "[{lo}, {hi}]");
    }

    /// The published table swaps Merging and Overtaking for TCP-traj: its Merging 8.89 is
    /// TCP-traj's Overtaking 4/45 and its Overtaking 24.29 the Merging 17/70 (docs/TABLES.md).
    #[test]
    fn i33_5_published_table_swaps_merging_and_overtaking_for_tcp() {
        let Some(b2d) = b2d_fixtures() else { return };
        let results = b2d.join("b2dzoo_TCP-only-traj_merged.json");
        let xml = b2d.join("routes/bench2drive220.xml");
        let (rep, _) = score(&[
            "--results",
            results.to_str().unwrap(),
            "--routes",
            xml.to_str().unwrap(),
        ]);
        let b = &rep["summary"]["bench2drive"];
        let count = |name: &str| {
            let c = &b["ability_counts"][name];
            (
                c["successes"].as_u64().unwrap(),
                c["routes"].as_u64().unwrap(),
            )
        };
        assert_eq!(count("Overtaking"), (4, 45));
        assert_eq!(count("Merging"), (17, 70));
        let (published_merging, published_overtaking) = (8.89, 24.29);
        let pct = |name: &str| format!("{:.2}", 100.0 * b["ability"][name].as_f64().unwrap());
        assert_eq!(pct("Overtaking"), format!("{published_merging:.2}"));
        assert_eq!(pct("Merging"), format!("{published_overtaking:.2}"));
    }
}
