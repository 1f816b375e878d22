//! `sds score`: protocols, the lateral reference, route sets and what the report says per route.

// ---- issue 33 items 1, 5, 6 and issue 34 finding 8: scoring protocols ----

mod protocols {
    use std::path::{Path, PathBuf};

    use serde_json::{json, Value};

    use crate::common::sds;

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
    /// at the harmonic mean (docs/PROTOCOLS.md "The min-speed grid"), worked by hand.
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
        let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml"]) else {
            return;
        };
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

        let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml"]) else {
            return;
        };
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
        let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml"]) else {
            return;
        };
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
        let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml"]) else {
            return;
        };
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

// ---- Issue 33, items 7, 4 and 8 (lateral re-acquisition, the page's route status, inputs) ----

mod i33_lateral {
    use std::path::{Path, PathBuf};

    use crate::common::sds;

    /// The point `s` m along the polyline `w`, moved `offset` m to its right (CARLA's y points
    /// right of x), and the direction of travel there.
    fn along(w: &[[f64; 2]], s: f64, offset: f64) -> ([f64; 2], [f64; 2]) {
        let mut left = s;
        for p in w.windows(2) {
            let (dx, dy) = (p[1][0] - p[0][0], p[1][1] - p[0][1]);
            let len = dx.hypot(dy);
            if len == 0.0 {
                continue;
            }
            let (ux, uy) = (dx / len, dy / len);
            if left <= len {
                let (x, y) = (p[0][0] + ux * left, p[0][1] + uy * left);
                return ([x - uy * offset, y + ux * offset], [ux, uy]);
            }
            left -= len;
        }
        let p = w[w.len() - 1];
        (p, [1.0, 0.0])
    }

    /// The steps of the excerpt of issue 33: telemetry that starts at step 480 and jumps from
    /// 501 to 789 (as a Bench2Drive-VL excerpt does), then runs to 899.
    pub fn excerpt_steps() -> Vec<u64> {
        (480..=501).chain(789..=899).collect()
    }

    /// Writes a one-route run into `dir`: a route XML of `waypoints` (`[x, y, z]`) under id `id`,
    /// a raw evaluator file with one completed record and, for each of `steps`, a
    /// `metric_info.json` frame `step / 1000` of the way along the route, 0.3 m right of it.
    /// Returns (results, telemetry root, routes).
    pub fn write_run(
        dir: &Path,
        id: &str,
        town: &str,
        waypoints: &[[f64; 3]],
        steps: &[u64],
    ) -> (String, String, String) {
        let w2: Vec<[f64; 2]> = waypoints.iter().map(|p| [p[0], p[1]]).collect();
        let length: f64 = w2
            .windows(2)
            .map(|p| (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]))
            .sum();
        let mut xml = format!("<routes><route id=\"{id}\" town=\"{town}\"><waypoints>\n");
        for p in waypoints {
            xml += &format!("<position x=\"{}\" y=\"{}\" z=\"{}\"/>\n", p[0], p[1], p[2]);
        }
        xml += "</waypoints></route></routes>\n";
        let routes = dir.join("routes.xml");
        std::fs::write(&routes, xml).unwrap();

        let route_id = format!("RouteScenario_{id}_rep0");
        let save_name = format!("{route_id}_{town}_Excerpt_1_1_11_27_10_00_00");
        let frames: serde_json::Map<String, serde_json::Value> = steps
            .iter()
            .map(|&step| {
                let (loc, fwd) = along(&w2, length * step as f64 / 1000.0, 0.3);
                let frame = serde_json::json!({
                    "acceleration": [0.0, 0.0, 0.0],
                    "angular_velocity": [0.0, 0.0, 0.0],
                    "forward_vector": [fwd[0], fwd[1], 0.0],
                    "right_vector": [-fwd[1], fwd[0], 0.0],
                    "location": [loc[0], loc[1], 0.0],
                    "rotation": [0.0, 0.0, 0.0],
                });
                (step.to_string(), frame)
            })
            .collect();
        let tel = dir.join("telemetry");
        std::fs::create_dir_all(tel.join(&save_name)).unwrap();
        std::fs::write(
            tel.join(&save_name).join("metric_info.json"),
            serde_json::to_string(&frames).unwrap(),
        )
        .unwrap();

        let infractions = crate::common::no_infractions();
        let results = serde_json::json!({
            "_checkpoint": {"global_record": {}, "progress": [1, 1], "records": [{
                "index": 0,
                "route_id": route_id,
                "scenario_name": "Excerpt_1",
                "weather_id": "1",
                "save_name": save_name,
                "town_name": town,
                "status": "Completed",
                "infractions": infractions,
                "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0},
                "meta": {"route_length": length, "duration_game": 50.0, "duration_system": 80.0},
            }]},
            "entry_status": "Finished", "eligible": true, "sensors": [], "values": [], "labels": [],
        });
        let res = dir.join("results.json");
        std::fs::write(&res, serde_json::to_string_pretty(&results).unwrap()).unwrap();
        let s = |p: PathBuf| p.to_str().unwrap().to_string();
        (s(res), s(tel), s(routes))
    }

    /// `sds score` of the run (plus `extra`), its one route, and `sds frames`' host-side
    /// lateral error per frame (`None` where unknown), each with its step.
    pub fn score(
        run: &(String, String, String),
        id: &str,
        extra: &[&str],
    ) -> (serde_json::Value, Vec<(u64, Option<f64>)>) {
        let (res, tel, routes) = run;
        let mut args = vec![
            "score",
            "--results",
            res,
            "--telemetry",
            tel,
            "--routes",
            routes,
        ];
        args.extend_from_slice(extra);
        let out = sds(&args);
        assert!(
            out.status.success(),
            "sds score: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let route = report["routes"][0].clone();
        let rid = format!("RouteScenario_{id}_rep0");
        let mut args = vec![
            "frames",
            "--results",
            res,
            "--telemetry",
            tel,
            "--routes",
            routes,
            "--route-id",
            &rid,
        ];
        args.extend_from_slice(extra);
        let out = sds(&args);
        assert!(
            out.status.success(),
            "sds frames: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let lat = String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(|l| {
                let v: serde_json::Value = serde_json::from_str(l).unwrap();
                (
                    v["host"]["step"].as_u64().unwrap(),
                    v["host"]["lat_err"].as_f64(),
                )
            })
            .collect();
        (route, lat)
    }

    /// The largest known lateral error, m.
    pub fn worst(lat: &[(u64, Option<f64>)]) -> f64 {
        lat.iter().filter_map(|l| l.1).fold(0.0, f64::max)
    }

    /// A synthetic route that always runs: 300 m of 2 m pieces, bending left halfway.
    pub fn synthetic_route() -> Vec<[f64; 3]> {
        let mut w: Vec<[f64; 3]> = (0..=75).map(|i| [2.0 * f64::from(i), 0.0, 0.0]).collect();
        w.extend((1..=75).map(|i| [150.0, -2.0 * f64::from(i), 0.0]));
        w
    }
}

/// Issue 33 item 7 (docs/SCORE.md §3 re-acquisition), on a synthetic route: telemetry that starts at
/// step 480 and jumps 501 → 789 stays within 0.3 m of its route (the drive's own offset) and
/// no chunk is anomalous or critical. Before, the 10 m window needed frames to catch up: the
/// first frames read 130 m and the frames after the jump 80 m, as critical chunks.
#[test]
fn i33_7_late_start_and_gap_reacquire_the_route_synthetic() {
    use i33_lateral::*;
    let dir = tempfile::tempdir().unwrap();
    let run = write_run(
        dir.path(),
        "900100",
        "Town01",
        &synthetic_route(),
        &excerpt_steps(),
    );
    let (route, lat) = score(&run, "900100", &[]);
    assert_eq!(lat.len(), excerpt_steps().len());
    assert!(
        worst(&lat) <= 0.3 + 1e-9,
        "lat_err up to {} m: {lat:?}",
        worst(&lat)
    );
    assert!(
        lat.iter().all(|l| l.1.is_some()),
        "every frame has a lateral error"
    );
    assert_eq!(route["lateral"]["critical"], 0, "{}", route["lateral"]);
    assert_eq!(route["lateral"]["anomalous"], 0, "{}", route["lateral"]);
    assert_eq!(route["ds_safe"], route["score_composed"], "{route}");
    assert_eq!(route["batch_agrees"], true, "streaming == batch: {route}");
}

/// Issue 33 item 7: `reacquire_steps` is a setting: at 1000 the 288-step jump is not a gap, the
/// window must catch up again and the frames after it are critical (the first frame still
/// re-acquires: its step is not 0).
#[test]
fn i33_7_reacquire_steps_is_a_setting() {
    use i33_lateral::*;
    let dir = tempfile::tempdir().unwrap();
    let run = write_run(
        dir.path(),
        "900100",
        "Town01",
        &synthetic_route(),
        &excerpt_steps(),
    );
    let (route, lat) = score(&run, "900100", &["--set", "reacquire_steps=1000"]);
    let before_jump = lat.iter().filter(|l| l.0 <= 501);
    assert!(
        before_jump.filter_map(|l| l.1).all(|e| e <= 0.3 + 1e-9),
        "{lat:?}"
    );
    let after = lat.iter().find(|l| l.0 == 789).and_then(|l| l.1).unwrap();
    assert!(
        after > 10.0,
        "the window alone lags behind after the jump: {after} m"
    );
    assert!(
        route["lateral"]["critical"].as_u64().unwrap() >= 1,
        "{}",
        route["lateral"]
    );
    let (_, lat) = score(&run, "900100", &["--set", "reacquire_steps=287"]);
    assert!(
        worst(&lat) <= 0.3 + 1e-9,
        "a jump of 288 steps > 287 re-acquires"
    );
}

/// Issue 33 item 7 on a real route of `bench2drive220.xml` (route 25300, Town04, 155 m, no
/// junction gap): the late-start excerpt stays within its 0.3 m offset, no chunk is critical.
#[test]
fn i33_7_late_start_and_gap_reacquire_a_real_route() {
    use i33_lateral::*;
    let Some(fx) = crate::common::b2d_fixtures(&[]) else {
        return;
    };
    let set = monitor_host::input::route_xml::read_route_xml(&fx.join("routes/bench2drive220.xml"))
        .unwrap();
    let r = set.get("25300").expect("route 25300 in bench2drive220.xml");
    let dir = tempfile::tempdir().unwrap();
    let run = write_run(
        dir.path(),
        "25300",
        &r.town,
        &r.waypoints_3d(),
        &excerpt_steps(),
    );
    let (route, lat) = score(&run, "25300", &[]);
    assert!(
        worst(&lat) <= 0.3 + 1e-6,
        "lat_err up to {} m: {lat:?}",
        worst(&lat)
    );
    assert_eq!(route["lateral"]["critical"], 0, "{}", route["lateral"]);
    assert_eq!(route["lateral"]["anomalous"], 0, "{}", route["lateral"]);
    assert_eq!(route["ds_safe"], route["score_composed"], "{route}");
}

/// Rewrites the one record of the results file at `path` with `f`.
fn i33_edit_record(path: &str, f: impl FnOnce(&mut serde_json::Value)) {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    f(&mut v["_checkpoint"]["records"][0]);
    std::fs::write(path, serde_json::to_string(&v).unwrap()).unwrap();
}

/// Issue 33 item 4: the page says why a route's DS is low: its status, route completion and
/// penalty in the route table (status cell, RC and penalty columns) and its drill-down; a
/// collision of a route without telemetry is "not placed: no telemetry" (its message has
/// coordinates), one of a replayed route far from every frame "no frame near its position".
#[test]
fn i33_4_page_says_status_rc_penalty_and_why_not_placed() {
    use i33_lateral::*;
    let dir = tempfile::tempdir().unwrap();
    let run = write_run(
        dir.path(),
        "900100",
        "Town01",
        &synthetic_route(),
        &excerpt_steps(),
    );
    i33_edit_record(&run.0, |r| {
        r["status"] = "Failed - TickRuntime".into();
        r["scores"] = serde_json::json!({"score_route": 50.53, "score_penalty": 0.6,
                                         "score_composed": 30.318});
        r["infractions"]["collisions_vehicle"] = serde_json::json!([
            "Agent collided against object with type=vehicle.lincoln.mkz_2017 and id=18834 at (x=2201.654, y=4874.879, z=365.295)"
        ]);
    });
    let (res, tel, routes) = &run;
    let empty = dir.path().join("no-telemetry");
    std::fs::create_dir_all(&empty).unwrap();
    for (telemetry, why) in [
        (empty.to_str().unwrap(), "no telemetry"),
        (tel.as_str(), "no frame near its position"),
    ] {
        let base = [
            "score",
            "--results",
            res,
            "--telemetry",
            telemetry,
            "--routes",
            routes,
            "--allow-missing-telemetry",
        ];
        let out = crate::common::sds(&[&base[..], &["--format", "html"]].concat());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let page = String::from_utf8_lossy(&out.stdout);
        assert!(
            page.contains(
                "<p class=\"outcome\">Failed - TickRuntime, RC 50.53 × penalty 0.6 = 30.32</p>"
            ),
            "no outcome line in the drill-down"
        );
        assert!(page.contains(
            "<td class=\"status\" title=\"Failed - TickRuntime, RC 50.53 × penalty 0.6 = 30.32\">Failed - TickRuntime</td><td data-v=\"50.53\">50.53</td><td data-v=\"0.6\">0.600</td>"
        ));
        assert!(!page.contains("no usable position"));
        let out = crate::common::sds(&base);
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let events = report["routes"][0]["events"].as_array().unwrap();
        let hit = events.iter().find(|e| e["kind"] == "collision").unwrap();
        assert!(
            hit["message"]
                .as_str()
                .unwrap()
                .ends_with(&format!("(not placed: {why})")),
            "{hit}"
        );
        assert!(page.contains(&format!("(not placed: {why})")), "{why}");
    }
}

/// Issue 33 item 4 on the real TransFuser++ file: route 4683 reads "Failed - TickRuntime, RC
/// 50.53 × penalty 0.6 = 30.32" on the page, and its collisions "not placed: no telemetry".
#[test]
fn i33_4_real_tickruntime_route_explained_on_the_page() {
    let Some(fx) = crate::common::b2d_fixtures(&[]) else {
        return;
    };
    let file = fx.join("carla_garage_tfpp_b2d_traj_merged.json");
    let out = crate::common::sds(&[
        "score",
        "--results",
        file.to_str().unwrap(),
        "--format",
        "html",
    ]);
    let page = String::from_utf8_lossy(&out.stdout);
    assert!(page.contains("Failed - TickRuntime, RC 50.53 × penalty 0.6 = 30.32"));
    assert!(page.contains("(not placed: no telemetry)"));
    assert!(!page.contains("no usable position"));
}

/// A completed record of route `id` whose `save_name` ends with the time stamp `stamp`.
fn i33_record(id: u32, stamp: &str, score: f64) -> serde_json::Value {
    let infractions = crate::common::no_infractions();
    serde_json::json!({
        "route_id": format!("RouteScenario_{id}_rep0"),
        "scenario_name": "Excerpt_1",
        "weather_id": "1",
        "save_name": format!("RouteScenario_{id}_rep0_Town01_Excerpt_1_1_{stamp}"),
        "town_name": "Town01",
        "status": "Completed",
        "infractions": infractions,
        "scores": {"score_route": 100, "score_penalty": score / 100.0, "score_composed": score},
        "meta": {"route_length": 100.0, "duration_game": 50.0, "duration_system": 80.0},
    })
}

/// Writes a raw evaluator file of `records` with `progress` `[done, total]`, modified at
/// `modified` seconds after the epoch.
fn i33_results_file(
    path: &std::path::Path,
    records: Vec<serde_json::Value>,
    progress: [u64; 2],
    modified: u64,
) {
    let v = serde_json::json!({
        "_checkpoint": {"global_record": {}, "progress": progress, "records": records},
        "entry_status": if progress[0] < progress[1] { "Started" } else { "Finished" },
        "eligible": true, "sensors": [], "values": [], "labels": [],
    });
    std::fs::write(path, serde_json::to_string(&v).unwrap()).unwrap();
    let t = std::time::UNIX_EPOCH + std::time::Duration::from_secs(modified);
    std::fs::File::options()
        .write(true)
        .open(path)
        .unwrap()
        .set_modified(t)
        .unwrap();
}

/// `sds score --allow-missing-telemetry` of `results` plus `extra`: the report and stderr.
fn i33_score_files(results: &[&std::path::Path], extra: &[&str]) -> (serde_json::Value, String) {
    let mut args: Vec<String> = vec!["score".into(), "--allow-missing-telemetry".into()];
    for r in results {
        args.extend(["--results".into(), r.to_str().unwrap().to_string()]);
    }
    args.extend(extra.iter().map(|s| s.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = crate::common::sds(&args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.code() == Some(0),
        "exit {:?}: {err}",
        out.status.code()
    );
    (serde_json::from_slice(&out.stdout).unwrap(), err)
}

/// Issue 33 item 8: `--duplicates newest` across New Year. A December run (stamp 12_20) and its
/// January re-run (01_05) carry no year: by stamp the December copy won. Stamps more than half
/// a year apart could wrap a year: the copy of the most recently modified file is kept, the
/// route's `kept` says so and a warning names the route; within one file, record order decides.
#[test]
fn i33_8_newest_across_new_year_uses_file_time() {
    let dir = tempfile::tempdir().unwrap();
    let (dec, jan) = (dir.path().join("dec.json"), dir.path().join("jan.json"));
    // December 2025 and January 2026 (modification times 1766224800, 1767603600).
    i33_results_file(
        &dec,
        vec![i33_record(1, "12_20_10_00_00", 40.0)],
        [1, 1],
        1_766_224_800,
    );
    i33_results_file(
        &jan,
        vec![i33_record(1, "01_05_09_00_00", 90.0)],
        [1, 1],
        1_767_603_600,
    );
    for order in [[&jan, &dec], [&dec, &jan]] {
        let (report, err) = i33_score_files(&[order[0], order[1]], &["--duplicates", "newest"]);
        let route = &report["routes"][0];
        assert_eq!(
            route["score_composed"], 90.0,
            "the January re-run is kept: {route}"
        );
        let why = route["kept"]["why"].as_str().unwrap();
        assert!(
            why.contains("could wrap") && why.contains("jan.json"),
            "{why}"
        );
        assert!(err.contains("could wrap a year"), "{err}");
    }
    // One checkpoint holding both copies: the checkpoint's own record order decides.
    let both = dir.path().join("both.json");
    let recs = vec![
        i33_record(1, "12_20_10_00_00", 40.0),
        i33_record(1, "01_05_09_00_00", 90.0),
    ];
    i33_results_file(&both, recs, [2, 2], 1_767_603_600);
    let (report, _) = i33_score_files(&[&both], &["--duplicates", "newest"]);
    assert_eq!(report["routes"][0]["score_composed"], 90.0);
    let why = report["routes"][0]["kept"]["why"].as_str().unwrap();
    assert!(why.contains("checkpoint's own order"), "{why}");
    // Stamps within half a year still decide by themselves (a later stamp, an older file).
    i33_results_file(
        &dec,
        vec![i33_record(1, "02_20_10_00_00", 40.0)],
        [1, 1],
        1_767_603_600,
    );
    i33_results_file(
        &jan,
        vec![i33_record(1, "01_05_09_00_00", 90.0)],
        [1, 1],
        1_766_224_800,
    );
    let (report, err) = i33_score_files(&[&jan, &dec], &["--duplicates", "newest"]);
    assert_eq!(report["routes"][0]["score_composed"], 40.0);
    assert!(!err.contains("could wrap"), "{err}");
}

/// Issue 33 item 8: a newer run file that re-ran a run but crashed before finishing (progress
/// 2 of 3) has no record of route 3: its kept record is from the earlier attempt, and the route's
/// `kept` and a warning say so.
#[test]
fn i33_8_newer_unfinished_run_says_the_record_is_from_the_earlier_attempt() {
    let dir = tempfile::tempdir().unwrap();
    let (first, rerun) = (dir.path().join("run1.json"), dir.path().join("run2.json"));
    let recs = (1..=3)
        .map(|i| i33_record(i, "03_01_10_00_00", 50.0))
        .collect();
    i33_results_file(&first, recs, [3, 3], 1_772_000_000);
    let recs = (1..=2)
        .map(|i| i33_record(i, "03_02_10_00_00", 80.0))
        .collect();
    i33_results_file(&rerun, recs, [2, 3], 1_772_100_000);
    for policy in ["newest", "last"] {
        let (report, err) = i33_score_files(&[&first, &rerun], &["--duplicates", policy]);
        let routes = report["routes"].as_array().unwrap();
        let r3 = routes
            .iter()
            .find(|r| r["route_id"] == "RouteScenario_3_rep0")
            .unwrap();
        let why = r3["kept"]["why"].as_str().unwrap_or_default();
        assert!(
            why.contains("earlier attempt") && why.contains("run2.json"),
            "{r3}"
        );
        assert!(
            err.contains("1 route(s) keep their record from the earlier attempt")
                && err.contains("progress 2 of 3")
                && err.contains("RouteScenario_3_rep0"),
            "{err}"
        );
    }
    // A finished re-run of two routes says nothing of the third.
    i33_results_file(
        &rerun,
        (1..=2)
            .map(|i| i33_record(i, "03_02_10_00_00", 80.0))
            .collect(),
        [2, 2],
        1_772_100_000,
    );
    let (_, err) = i33_score_files(&[&first, &rerun], &["--duplicates", "newest"]);
    assert!(!err.contains("earlier attempt"), "{err}");
}

/// Issue 33 item 8: a results file (or an XML without a `<route>`) given as `--routes` is
/// refused with exit 2 (it made every record a foreign route, with a warning each, exit 0).
#[test]
fn i33_8_routes_without_a_route_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let res = dir.path().join("results.json");
    i33_results_file(
        &res,
        vec![i33_record(1, "03_01_10_00_00", 50.0)],
        [1, 1],
        1_772_000_000,
    );
    let empty = dir.path().join("empty.xml");
    std::fs::write(&empty, "<routes>\n</routes>\n").unwrap();
    for routes in [&res, &empty] {
        let out = crate::common::sds(&[
            "score",
            "--allow-missing-telemetry",
            "--results",
            res.to_str().unwrap(),
            "--routes",
            routes.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("holds no route: not a route XML?"), "{err}");
        assert!(
            err.contains(routes.to_str().unwrap()),
            "names the file: {err}"
        );
    }
}

/// Issue 33 item 8: `--expected-routes 20` on a 20-route run scored against the whole route
/// XML is refused (N 20 < 220 counted); the message points at `--route-subset found`, which
/// then scores the 20 routes over N = 20.
#[test]
fn i33_8_expected_routes_suggests_route_subset_found() {
    let Some(fx) = crate::common::b2d_fixtures(&[]) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(fx.join("carla_garage_tfpp_b2d_traj_merged.json")).unwrap(),
    )
    .unwrap();
    let recs = v["_checkpoint"]["records"].as_array_mut().unwrap();
    recs.truncate(20);
    let twenty = dir.path().join("twenty.json");
    std::fs::write(&twenty, serde_json::to_string(&v).unwrap()).unwrap();
    let xml = fx.join("routes/bench2drive220.xml");
    let base = [
        "score",
        "--allow-missing-telemetry",
        "--results",
        twenty.to_str().unwrap(),
        "--routes",
        xml.to_str().unwrap(),
        "--expected-routes",
        "20",
    ];
    let out = crate::common::sds(&base);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("200 of them are routes of the route XML without a record")
            && err.contains("set route_subset = found")
            && err.ends_with("(--expected-routes, --route-subset)\n"),
        "{err}"
    );
    let out = crate::common::sds(&[&base[..], &["--route-subset", "found"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (
            report["summary"]["routes"].as_u64(),
            report["summary"]["missing"].as_u64()
        ),
        (Some(20), Some(0)),
        "{}",
        report["summary"]
    );
}

/// Issue 33 item 8: `--families safe2drive` (no such file) says what the name means (the paper's
/// three families, why there is no built-in map, how to write one) with exit 2 before scoring;
/// a file of that name is read as any label file.
#[test]
fn i33_8_families_safe2drive_says_what_the_name_means() {
    let dir = tempfile::tempdir().unwrap();
    let res = dir.path().join("results.json");
    i33_results_file(
        &res,
        vec![i33_record(1, "03_01_10_00_00", 50.0)],
        [1, 1],
        1_772_000_000,
    );
    let run = |families: &str| {
        crate::common::sds(&[
            "score",
            "--allow-missing-telemetry",
            "--results",
            res.to_str().unwrap(),
            "--group-by",
            "family",
            "--families",
            families,
        ])
    };
    let out = run("safe2drive");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    for said in [
        "work zones",
        "pedestrian jaywalking",
        "occluded vulnerable road users",
        "StaticWorkzoneRoute,work zone",
    ] {
        assert!(err.contains(said), "{said}: {err}");
    }
    let file = dir.path().join("safe2drive");
    std::fs::write(&file, "Excerpt,work zone\n").unwrap();
    let out = run(file.to_str().unwrap());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        report["groups"]["rows"][0]["label"], "work zone",
        "{}",
        report["groups"]
    );
}

/// Issue 47 item 12: `all` and `none` stand alone in `--protocol` (`all,none`, `all,all` and
/// `none,lb2.1` were accepted: a regression of round 3's held case); usage error 2 naming the
/// list. A list of ids still works.
#[test]
fn r4_12_protocol_all_or_none_stand_alone() {
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    for list in ["all,none", "all,all", "none,lb2.1", "lb2.1,all"] {
        let o = crate::common::score_demo(dir.path(), None, &["--protocol", list]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{list}: {err}");
        assert!(
            err.contains("protocols") && err.contains("alone") && err.contains(list),
            "{list}: {err}"
        );
    }
    let o = crate::common::score_demo(dir.path(), None, &["--protocol", "lb2.1,b2d"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Issue 46 item 6: warnings named the fix by the library's neutral names ("the setting
/// dt=SECONDS", "(telemetry)") where the user types `--set dt=SECONDS`, `--telemetry`: `sds`
/// spells its own flags after a warning as after an error. The report's JSON warnings keep the
/// neutral text (Python's users read them too).
#[test]
fn i46_6_warnings_spell_the_command_line_flags() {
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    // One route's telemetry with a third of its steps gone: its step period is not inferred.
    let results: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("results.json")).unwrap()).unwrap();
    let name = results["_checkpoint"]["records"][0]["save_name"]
        .as_str()
        .unwrap()
        .to_string();
    let file = dir
        .path()
        .join("telemetry")
        .join(&name)
        .join("metric_info.json");
    let mut frames: serde_json::Map<String, serde_json::Value> =
        serde_json::from_slice(&std::fs::read(&file).unwrap()).unwrap();
    let n = frames.len() as u64;
    frames.retain(|k, _| {
        let step: u64 = k.parse().unwrap();
        !(n / 4..n / 4 + n / 3).contains(&step)
    });
    std::fs::write(&file, serde_json::to_vec(&frames).unwrap()).unwrap();
    let out = dir.path().join("report.json");
    let o = crate::common::score_demo(dir.path(), None, &["-o", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    let line = err
        .lines()
        .find(|l| l.contains("step period not inferred"))
        .unwrap_or_else(|| panic!("no step-period warning: {err}"));
    assert!(line.starts_with("sds: warning: "), "{line}");
    assert!(line.ends_with(" (--set dt=SECONDS)"), "{line}");
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let neutral = report["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .find(|w| w.contains("step period not inferred"))
        .unwrap();
    assert!(neutral.contains("the setting dt=SECONDS") && !neutral.contains("--set"));
    // A run without telemetry: the fix names --telemetry and --allow-missing-telemetry.
    let o = crate::common::sds(&[
        "score",
        "--results",
        dir.path().join("results.json").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    let line = err
        .lines()
        .find(|l| l.contains("no route has telemetry"))
        .unwrap_or_else(|| panic!("no telemetry warning: {err}"));
    assert!(
        line.ends_with(" (--telemetry, --allow-missing-telemetry)"),
        "{line}"
    );
}

/// The deductions' decomposition sums back to the score; the figures drawn from it.
mod decomposition;
/// The demo scored as worked out by hand, formats, settings, families, maps and groups.
mod demo;
/// The report's events: counts, places and the real runs' red lights and stop signs.
mod events;
/// Route-label maps (`--route-labels`) and the group rows they make.
mod groups;
/// Each protocol's fixed terms on hand-made records, and every real fixture under all of them.
mod protocol_terms;
/// Real runs' layouts: shards beside merged files, per-route folders, missing telemetry, labels.
mod real_runs;
/// The real merged files reproduce their stored driving score and success rate.
mod stored;
