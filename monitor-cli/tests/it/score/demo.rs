//! End to end: `sds demo DIR`, then `sds score` on it, checked against figures worked out by hand
//! from the demo's scripts (monitor-host/src/demo/mod.rs).

use std::path::Path;

use serde_json::Value;

use crate::common::{self, demo, sds};

/// `sds score` on the demo in `dir` (results, telemetry, routes), with `extra` arguments.
fn run_score(dir: &Path, extra: &[&str]) -> std::process::Output {
    common::score_demo(dir, None, extra)
}

/// `sds score ... -o report.json`: the exit code and the report.
fn score_json(dir: &Path, extra: &[&str]) -> (i32, Value) {
    let report = dir.join("report.json");
    let mut args = vec!["-o", report.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = run_score(dir, &args);
    let text = std::fs::read_to_string(&report).expect("report written");
    (
        out.status.code().unwrap_or(-1),
        serde_json::from_str(&text).expect("report is JSON"),
    )
}

fn route<'a>(report: &'a Value, id: &str) -> &'a Value {
    report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == id)
        .unwrap_or_else(|| panic!("{id} missing from the report"))
}

fn close(a: &Value, b: f64) -> bool {
    a.as_f64()
        .is_some_and(|a| (a - b).abs() < 1e-9 * b.abs().max(1.0))
}

#[test]
fn demo_scores_as_worked_out_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let (code, r) = score_json(dir.path(), &[]);
    assert_eq!(code, 0, "a clean demo exits 0");
    assert_eq!(r["schema"], "sds-report/1");
    assert_eq!(r["profile"], "physical");
    assert_eq!(r["routes"].as_array().unwrap().len(), 9);

    // Cruising: 200 frames on the reference line at 10 m/s: 10 comfortable chunks, no excess.
    let cruise = route(&r, "RouteScenario_900001_rep0");
    assert_eq!(cruise["frames"], 200);
    assert_eq!(cruise["comfort"]["chunks"], 10);
    assert_eq!(cruise["comfort"]["comfortable"], 10);
    assert_eq!(cruise["lateral"]["chunks"], 10);
    assert_eq!(cruise["lateral"]["scored_chunks"], 10);
    assert!(close(&cruise["ds_safe"], 100.0));

    // Hard braking: -6 m/s² over frames 60..100 = exactly chunks 3 and 4 (chunks are filtered
    // independently, so the neighbours see no step): lon_acc fails twice, nothing else.
    let brake = route(&r, "RouteScenario_900002_rep0");
    assert_eq!(brake["comfort"]["comfortable"], 8);
    assert_eq!(brake["comfort"]["failed"]["lon_acc"], 2);
    assert_eq!(brake["comfort"]["failed"]["lon_jerk"], 0);
    assert!(close(&brake["comfort"]["score"], 0.8));
    assert!(close(&brake["ds_safe"], 100.0));

    // Lane change: y = 3.5 (10s³ - 15s⁴ + 6s⁵), s = (t - 2) / 4. Chunk 2 (t <= 2.95) peaks at
    // y(0.2375) = 0.318 m -> excess 0 (normal); chunk 3 (t <= 3.95) reaches y(0.4875) = 1.668
    // -> excess 0.848 (critical), and chunks 4..9 lie beyond: N_crit = 7, DS_safe = 100 * 0.9^7.
    let lane = route(&r, "RouteScenario_900003_rep0");
    assert_eq!(lane["lateral"]["critical"], 7);
    assert_eq!(lane["lateral"]["anomalous"], 0);
    assert_eq!(
        lane["comfort"]["comfortable"], 10,
        "|a_lat| <= 1.26 m/s², jerk <= 3.28 m/s³: comfortable"
    );
    assert!(close(&lane["ds_safe"], 100.0 * 0.9f64.powi(7)));

    // Cone contact at 3 m/s without braking: a work-zone contact (p_safe = 0.65 * 0.5/0.65)
    // and a collision without deceleration (x 0.8): 100 * 0.5 * 0.8 = 40.
    let cone = route(&r, "RouteScenario_900004_rep0");
    assert_eq!(cone["collisions"]["workzone"], 1);
    assert_eq!(cone["collisions"]["nodecel"], 1);
    assert!(close(&cone["p_safe"], 0.5));
    assert!(close(&cone["ds_safe"], 40.0));
    let ev = &cone["collision_events"][0];
    assert_eq!(ev["frame"], 90);
    assert_eq!(ev["step"], 91, "steps start at 1");
    assert_eq!(ev["aligned_by"], "nearest");
    assert_eq!(ev["decelerated"], false);

    // Crash without braking at 8 m/s (frame 120; the impact's -20 m/s² is in frame 120 itself,
    // which the window excludes): 62.5 * 0.6 * 0.8 = 30. Comfort: chunk 6 holds the impact.
    let crash = route(&r, "RouteScenario_900005_rep0");
    assert_eq!(crash["collisions"]["nodecel"], 1);
    assert!(close(&crash["ds_safe"], 30.0));
    let speed = crash["collision_events"][0]["impact_speed"]
        .as_f64()
        .unwrap();
    assert!((speed - 8.0).abs() < 1e-3);
    assert!(close(&crash["comfort"]["score"], 7.0 / 8.0));

    // Crash after braking: -3 m/s² from frame 100, pedestrian at frame 110: decelerated, so only
    // the evaluator's 0.5: DS_safe = 50. Speed at impact 8 - 10 * 0.15 = 6.5 m/s.
    let braked = route(&r, "RouteScenario_900006_rep0");
    assert_eq!(braked["collisions"]["nodecel"], 0);
    assert_eq!(braked["collision_events"][0]["decelerated"], true);
    let speed = braked["collision_events"][0]["impact_speed"]
        .as_f64()
        .unwrap();
    assert!((speed - 6.5).abs() < 1e-3);
    assert!(close(&braked["ds_safe"], 50.0));

    // Standing hit: stopped at frame 44 (v 0.125 m/s from frame 43 to 44, then 0); the hit's
    // position ties with every frame from 44 on and goes to the earliest: frame 44, exempt.
    let standing = route(&r, "RouteScenario_900007_rep0");
    let ev = &standing["collision_events"][0];
    assert_eq!(ev["frame"], 44);
    assert_eq!(ev["exempt"], true);
    assert_eq!(standing["collisions"]["exempt"], 1);
    assert!(close(&standing["ds_safe"], 60.0));

    // The 10 Hz route: 100 steps for duration_game 10.0 s, so dt = 0.1 (inferred). Braking at
    // -4 m/s² from t = 4.0 s, it touches a car at frame 55 (step 56, t = 5.5 s) at 10 - 4 * 1.5
    // = 4 m/s: physical units (at an assumed 0.05 s it would read 8 m/s). Decelerated, so only
    // the evaluator's 0.6: DS_safe = 60. Comfort: 5 chunks of 2 s; only the one holding the
    // braking (frames 40..59) fails: 0.8.
    let hz10 = route(&r, "RouteScenario_900008_rep0");
    assert_eq!(hz10["dt"], 0.1);
    assert_eq!(hz10["dt_source"], "inferred");
    assert_eq!(hz10["frames"], 100);
    let ev = &hz10["collision_events"][0];
    assert_eq!(
        (ev["frame"].clone(), ev["step"].clone()),
        (55.into(), 56.into())
    );
    assert!(close(&ev["time_s"], 5.5));
    assert!((ev["impact_speed"].as_f64().unwrap() - 4.0).abs() < 1e-3);
    assert_eq!(ev["decelerated"], true);
    assert!(close(&hz10["ds_safe"], 60.0));
    assert_eq!(hz10["comfort"]["chunks"], 5);
    assert!(close(&hz10["comfort"]["score"], 0.8));
    // Every 20 Hz route's period is inferred too.
    assert!(r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|x| x["route_id"] != "RouteScenario_900008_rep0")
        .all(|x| x["dt"] == 0.05 && x["dt_source"] == "inferred"));

    // The junction route (900009) without a map: its XML leaves out the junction, where it
    // drifts, so its lateral terms look clean; it ran the junction's red light (Bench2Drive's
    // 0.7): DS 70, comfort 1, DS_safe 70 (see the maps test below).
    let junction = route(&r, "RouteScenario_900009_rep0");
    assert_eq!(junction["lateral"]["reference"], "xml");
    assert_eq!(junction["lateral"]["scored_chunks"], 8);
    assert_eq!(junction["lateral"]["anomalous"], 0);
    assert_eq!(junction["infractions"]["red_light"], 1);
    assert_eq!(junction["success"], false);
    assert!(close(&junction["score_composed"], 70.0));
    assert!(close(&junction["ds_safe"], 70.0));

    // Aggregates over N = 9: DS = (100+100+100+65+37.5+50+60+60+70)/9, SR = 3/9 (routes 1-3),
    // mean comfort = (1 + 0.8 + 1 + 1 + 7/8 + 7/8 + 3/4 + 0.8 + 1) / 9 = 0.9, collision rate 5/9.
    let s = &r["summary"];
    assert_eq!(s["routes"], 9);
    assert!(close(&s["driving_score"], 642.5 / 9.0));
    assert!(close(&s["success_rate"], 300.0 / 9.0));
    assert!(close(&s["mean_comfort"], 0.9));
    assert!(close(&s["collision_rate"], 500.0 / 9.0));
    let mean_safe =
        (100.0 + 100.0 + 100.0 * 0.9f64.powi(7) + 40.0 + 30.0 + 50.0 + 60.0 + 60.0 + 70.0) / 9.0;
    assert!(close(&s["mean_ds_safe"], mean_safe));
    assert!(close(&s["sds"], mean_safe * 0.9));
    assert_eq!(s["penalty_mismatches"].as_array().unwrap().len(), 0);
    assert!(s["batch_disagreements"].as_array().unwrap().is_empty());
}

#[test]
fn missing_telemetry_exits_3_and_keeps_the_route() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let tel = dir.path().join("telemetry");
    let gone = std::fs::read_dir(&tel)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().contains("900004"))
        .unwrap();
    std::fs::remove_dir_all(&gone).unwrap();
    let (code, r) = score_json(dir.path(), &[]);
    assert_eq!(code, 3);
    let cone = route(&r, "RouteScenario_900004_rep0");
    assert_eq!(cone["telemetry"], "missing");
    assert!(cone["ds_safe"].is_null());
    assert!(r["summary"]["mean_ds_safe"].is_null());

    // Allowed: scored without telemetry terms: the work-zone factor still applies, the event is
    // unaligned and not penalised: 100 * 0.5 = 50.
    let (code, r) = score_json(dir.path(), &["--allow-missing-telemetry"]);
    assert_eq!(code, 0);
    let cone = route(&r, "RouteScenario_900004_rep0");
    assert!(close(&cone["ds_safe"], 50.0));
    assert_eq!(cone["collisions"]["unaligned"], 1);
    assert!(cone["comfort"]["score"].is_null());
}

#[test]
fn a_fixed_dt_turns_inference_off() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Forcing 20 Hz on the 10 Hz route doubles its speeds: what the inference prevents.
    let (code, r) = score_json(dir.path(), &["--set", "dt=0.05"]);
    assert_eq!(code, 0);
    assert_eq!(r["config"]["dt"], 0.05);
    assert_eq!(r["config"]["dt_inference"], false);
    let hz10 = route(&r, "RouteScenario_900008_rep0");
    assert_eq!(
        (hz10["dt"].clone(), hz10["dt_source"].clone()),
        (0.05.into(), "config".into())
    );
    let ev = &hz10["collision_events"][0];
    assert!((ev["impact_speed"].as_f64().unwrap() - 8.0).abs() < 1e-3);
    assert!(close(&ev["time_s"], 2.75));
}

#[test]
fn table_and_csv_formats() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = run_score(dir.path(), &["--format", "table", "--group-by", "town"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("DS_safe") && text.contains("SDS"));
    assert!(text.contains("DemoTown"), "{text}");
    let out = run_score(dir.path(), &["--format", "csv"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().count(), 10, "header + 9 routes");
    assert!(text
        .lines()
        .nth(1)
        .unwrap()
        .starts_with("RouteScenario_900001_rep0,DemoCruising,"));
}

#[test]
fn bad_setting_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let out = sds(&[
        "score",
        "--results",
        &d("results.json"),
        "--set",
        "chunk_len=99",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("chunk_len"));
}

#[test]
fn breakdown_by_family_uses_the_families_file() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Three collision scenarios in one family; the others are left unmapped.
    std::fs::write(
        dir.path().join("families.csv"),
        "# type,label\nDemoCrashNoBrake,collisions\nDemoCrashBraking,collisions\n\
         DemoStandingHit,collisions\n",
    )
    .unwrap();
    let families = dir.path().join("families.csv");
    let out = run_score(
        dir.path(),
        &[
            "--format",
            "table",
            "--group-by",
            "family",
            "--families",
            families.to_str().unwrap(),
        ],
    );
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let row = text
        .lines()
        .find(|l| l.starts_with("collisions "))
        .unwrap_or_else(|| panic!("no family row in\n{text}"));
    // 3 routes, DS = (37.5 + 50 + 60) / 3 = 49.1667, SR 0, collision rate 100.
    let cols: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(cols[..5], ["collisions", "3", "49.17", "0.00", "100.00"]);
    // The other six types have no label: one "(unmapped)" group, and a warning naming them.
    let unmapped = text
        .lines()
        .find(|l| l.starts_with("(unmapped) "))
        .unwrap_or_else(|| panic!("no (unmapped) row in\n{text}"));
    assert_eq!(unmapped.split_whitespace().nth(1), Some("6"));
    assert!(!text.lines().any(|l| l.starts_with("DemoCruising ")));
    let combined = text.lines().find(|l| l.starts_with("Combined ")).unwrap();
    assert_eq!(combined.split_whitespace().nth(1), Some("9"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("group_by = family: 6 route(s)") && stderr.contains("DemoCruising"),
        "{stderr}"
    );
    // Without its label map, grouping by family is a usage error.
    let out = run_score(dir.path(), &["--format", "table", "--group-by", "family"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--families"));
}

#[test]
fn infractions_json_gives_the_step_exactly() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let results: Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("results.json")).unwrap()).unwrap();
    let cone = results["_checkpoint"]["records"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == "RouteScenario_900004_rep0")
        .unwrap();
    let message = cone["infractions"]["collisions_layout"][0]
        .as_str()
        .unwrap();
    let save = cone["save_name"].as_str().unwrap();
    // LEAD's step-exact log says the contact happened at step 96 (frame 95), not at the frame
    // nearest to the logged position (frame 90, step 91).
    let log = serde_json::json!({ "infractions": [
        { "step": 96, "infraction": "collisions_layout", "frame": 0, "message": message,
          "event_type": "COLLISION_STATIC", "meters_travelled": 14.0 }
    ]});
    std::fs::write(
        dir.path()
            .join("telemetry")
            .join(save)
            .join("infractions.json"),
        log.to_string(),
    )
    .unwrap();
    let (code, r) = score_json(dir.path(), &[]);
    assert_eq!(code, 0);
    let ev = &route(&r, "RouteScenario_900004_rep0")["collision_events"][0];
    assert_eq!(ev["aligned_by"], "infractions.json");
    assert_eq!(ev["step"], 96);
    assert_eq!(ev["frame"], 95);
}

/// The report's warnings without the demo's one note, its 10 Hz route's inferred period (in the
/// report since issue 48 item 2).
fn not_notes(r: &Value) -> Vec<&str> {
    r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .filter(|w| !w.starts_with("step period inferred as 0.1 s"))
        .collect()
}

/// The demo with its own town map (`maps/DemoTown.xodr`): the junction route's gap is filled by
/// the lane chain, so its drift inside the junction is scored; `lateral_reference=lane` measures
/// against the nearest lane; a town without a map falls back with one warning; a broken map
/// stops the run naming the file.
#[test]
fn demo_with_its_town_map() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let maps = dir.path().join("maps");
    let maps_arg = maps.to_str().unwrap().to_string();

    let (code, xml) = score_json(dir.path(), &[]);
    assert_eq!(code, 0);
    let (code, map) = score_json(dir.path(), &["--maps", &maps_arg]);
    assert_eq!(code, 0);
    assert!(not_notes(&map).is_empty(), "{}", map["warnings"]);
    for r in map["routes"].as_array().unwrap() {
        assert_eq!(r["lateral"]["reference"], "map-route", "{}", r["route_id"]);
        assert_eq!(r["batch_agrees"], true);
    }
    // The junction route: 8 of 10 chunks scored from the XML, all 10 with the map; the 1.4 m
    // drift (excess 1.4 - 0.82 = 0.58 m) makes 2 of them anomalous: DS_safe 70 * 0.95^2.
    let (j_xml, j_map) = (
        route(&xml, "RouteScenario_900009_rep0"),
        route(&map, "RouteScenario_900009_rep0"),
    );
    assert_eq!(j_xml["lateral"]["scored_chunks"], 8);
    assert_eq!(j_map["lateral"]["scored_chunks"], 10);
    assert_eq!(j_map["lateral"]["anomalous"], 2);
    assert!(close(&j_map["ds_safe"], 70.0 * 0.95 * 0.95));
    // On 3.5 m lanes the map's slack is the default one: every other route scores as before.
    for (a, b) in xml["routes"]
        .as_array()
        .unwrap()
        .iter()
        .zip(map["routes"].as_array().unwrap())
    {
        if a["route_id"] != "RouteScenario_900009_rep0" {
            assert_eq!(a["ds_safe"], b["ds_safe"], "{}", a["route_id"]);
            assert_eq!(a["lateral"]["critical"], b["lateral"]["critical"]);
        }
    }

    // lane: the lane change is only an excess while the car straddles the lane line.
    let (code, lane) = score_json(
        dir.path(),
        &["--maps", &maps_arg, "--set", "lateral_reference=lane"],
    );
    assert_eq!(code, 0);
    assert_eq!(lane["config"]["lateral_reference"], "lane");
    let change = route(&lane, "RouteScenario_900003_rep0");
    assert_eq!(change["lateral"]["reference"], "map-lane");
    let before = route(&map, "RouteScenario_900003_rep0")["lateral"]["critical"]
        .as_u64()
        .unwrap();
    let after = change["lateral"]["critical"].as_u64().unwrap();
    assert!(after > 0 && after < before, "{after} vs {before}");

    // A maps folder without the town: one warning naming the town and its 9 routes; lane falls
    // back to the route XML.
    let empty = dir.path().join("no-maps");
    std::fs::create_dir_all(&empty).unwrap();
    let (code, none) = score_json(
        dir.path(),
        &[
            "--maps",
            empty.to_str().unwrap(),
            "--set",
            "lateral_reference=lane",
        ],
    );
    assert_eq!(code, 0);
    let warnings = not_notes(&none);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0];
    assert!(
        w.contains("no map for DemoTown") && w.contains("9 routes") && w.contains("falls back"),
        "{w}"
    );
    for r in none["routes"].as_array().unwrap() {
        assert_eq!(r["lateral"]["reference"], "xml");
    }
    assert_eq!(none["summary"], xml["summary"]);

    // A broken map stops the run, naming the file and the road.
    let broken = dir.path().join("broken-maps");
    std::fs::create_dir_all(&broken).unwrap();
    let text = std::fs::read_to_string(maps.join("DemoTown.xodr")).unwrap();
    let text = text.replacen("hdg=\"0\" length=\"110\"", "hdg=\"0\" length=\"-110\"", 1);
    std::fs::write(broken.join("DemoTown.xodr"), text).unwrap();
    let out = run_score(dir.path(), &["--maps", broken.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("DemoTown.xodr") && err.contains("road 1"),
        "{err}"
    );
}

#[test]
fn smoothness_is_the_legacy_comfort_whatever_the_profile() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // The cruising route turns at a steady 30 deg/s: 0.52 rad/s is within the physical yaw-rate
    // bound (0.95), but the legacy profile compares deg/s against it and fails every chunk.
    let tel = std::fs::read_dir(dir.path().join("telemetry"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("RouteScenario_900001_")
        })
        .unwrap()
        .join("metric_info.json");
    let mut steps: Value = serde_json::from_slice(&std::fs::read(&tel).unwrap()).unwrap();
    for (_, step) in steps.as_object_mut().unwrap() {
        step["angular_velocity"][2] = Value::from(30.0);
    }
    std::fs::write(&tel, serde_json::to_vec(&steps).unwrap()).unwrap();
    let (code, physical) = score_json(dir.path(), &[]);
    assert_eq!(code, 0);
    let cruise = route(&physical, "RouteScenario_900001_rep0");
    assert_eq!(cruise["comfort"]["score"], 1.0);
    assert_eq!(cruise["smoothness"], 0.0);
    let (code, legacy) = score_json(dir.path(), &["--profile", "b2d-legacy"]);
    assert_eq!(code, 0);
    // Bench2Drive's smoothness is the legacy profile's mean comfort, whichever profile the
    // report uses; per route it is the legacy C_route.
    let b = &physical["summary"]["bench2drive"];
    assert_eq!(b["smoothness"], legacy["summary"]["mean_comfort"]);
    assert_eq!(
        legacy["summary"]["bench2drive"]["smoothness"],
        legacy["summary"]["mean_comfort"]
    );
    assert_ne!(
        physical["summary"]["mean_comfort"], legacy["summary"]["mean_comfort"],
        "the demo's two profiles differ, so the test can tell them apart"
    );
    for (p, l) in physical["routes"]
        .as_array()
        .unwrap()
        .iter()
        .zip(legacy["routes"].as_array().unwrap())
    {
        assert_eq!(p["smoothness"], l["comfort"]["score"], "{}", p["route_id"]);
        assert_eq!(p["batch_agrees"], true);
    }
}

#[test]
fn groups_in_the_json_and_csv_with_list_labels() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Two collision types belong to two families each; DemoCruising, Demo10HzBraking and
    // DemoJunction to none listed.
    let families = dir.path().join("families.json");
    std::fs::write(
        &families,
        r#"{"DemoCrashNoBrake": ["collisions", "no-brake"], "DemoCrashBraking": ["collisions"],
            "DemoStandingHit": ["collisions", "standing"], "DemoHardBraking": "dynamics",
            "DemoLaneChange": "dynamics", "DemoConeContact": "workzone"}"#,
    )
    .unwrap();
    let f = families.to_str().unwrap();
    let (code, r) = score_json(dir.path(), &["--group-by", "family", "--families", f]);
    assert_eq!(code, 0);
    let g = &r["groups"];
    assert_eq!(g["by"], "family");
    let rows: Vec<(&str, u64)> = g["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| (x["label"].as_str().unwrap(), x["routes"].as_u64().unwrap()))
        .collect();
    assert_eq!(
        rows,
        [
            ("collisions", 3),
            ("dynamics", 2),
            ("no-brake", 1),
            ("standing", 1),
            ("workzone", 1),
            ("(unmapped)", 3)
        ]
    );
    // A group's aggregates are over its own routes: the crash with braking, the one without
    // and the standing hit (DS 37.5, 50, 60 by the demo's scripts).
    let coll = &g["rows"][0];
    assert!(close(&coll["driving_score"], (37.5 + 50.0 + 60.0) / 3.0));
    assert_eq!(coll["collision_rate"], 100.0);
    assert_eq!(
        coll["infraction_routes"]["collisions_vehicle"]
            .as_u64()
            .unwrap()
            + coll["infraction_routes"]["collisions_pedestrian"]
                .as_u64()
                .unwrap(),
        3
    );
    // combined: every route once, with the run's N, and the summary's numbers.
    assert_eq!(g["combined"]["routes"], 9);
    assert_eq!(
        g["combined"]["driving_score"],
        r["summary"]["driving_score"]
    );
    assert_eq!(g["combined"]["sds"], r["summary"]["sds"]);
    let warnings = r["warnings"].as_array().unwrap();
    assert!(warnings
        .iter()
        .any(|w| w.as_str().unwrap().contains("DemoCruising")));
    // CSV: a header, one line per group, and the combined line.
    let out = run_score(
        dir.path(),
        &["--format", "csv", "--group-by", "family", "--families", f],
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + 6 + 1, "{text}");
    assert!(lines[0].starts_with("by,label,routes,driving_score,"));
    assert!(lines[1].starts_with("family,collisions,3,"));
    assert!(lines[7].starts_with("family,combined,9,"));
}

/// `sds frames` takes the options of `score` that change a frame (`--maps`, `--set`, ...), and
/// what it prints is what `score` streamed: the demo with its town map and the lane reference,
/// every route's frames replayed through the core give the report's lateral and comfort figures,
/// and each frame's core value follows from its host-side distance and slack.
#[test]
fn frames_under_maps_and_the_lane_reference_are_what_score_used() {
    use monitor_core::{Config, Monitor};
    use std::process::Output;
    let stderr = |o: &Output| String::from_utf8_lossy(&o.stderr).into_owned();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let d = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let base = [
        "--results".to_string(),
        d("results.json"),
        "--telemetry".into(),
        d("telemetry"),
        "--routes".into(),
        d("routes.xml"),
        "--maps".into(),
        d("maps"),
    ];
    let with = |cmd: &str, extra: &[&str]| -> Output {
        let mut args: Vec<&str> = vec![cmd];
        args.extend(base.iter().map(String::as_str));
        args.extend(extra);
        sds(&args)
    };
    let lane = ["--set", "lateral_reference=lane"];
    let o = with("score", &lane);
    assert!(
        o.status.code().is_some_and(|c| c == 0 || c == 3),
        "{}",
        stderr(&o)
    );
    let report: Value = serde_json::from_slice(&o.stdout).unwrap();
    let mut lane_differs = false;
    for route in report["routes"].as_array().unwrap() {
        let id = route["route_id"].as_str().unwrap();
        assert_eq!(route["lateral"]["reference"], "map-lane", "{id}");
        let o = with("frames", &[&lane[..], &["--route-id", id]].concat());
        assert!(o.status.success(), "{id}: {}", stderr(&o));
        let text = String::from_utf8(o.stdout).unwrap();
        let mut config = Config::DEFAULT;
        config.dt = route["dt"].as_f64().unwrap() as f32;
        let mut m = Monitor::<20>::new(config).unwrap();
        for line in text.lines() {
            let f = monitor_core::json::decode_frame(line.as_bytes()).unwrap();
            let host: Value = serde_json::from_str::<Value>(line).unwrap()["host"].clone();
            assert_eq!(host["reference"], "map-lane", "{id}: {line}");
            if let Some(lat) = host["lat_err"].as_f64() {
                let slack = host["slack"].as_f64().unwrap();
                let width = host["lane_width"].as_f64().unwrap();
                assert_eq!(slack, width / 2.0 - 0.93, "{id}: {line}");
                let v = (lat.abs() - slack + f64::from(config.slack)).max(0.0) as f32;
                assert_eq!(f.lat_err, Some(v), "{id}: {line}");
            } else {
                assert_eq!(f.lat_err, None, "{id}: {line}");
            }
            m.push(&f).unwrap();
        }
        let s = m.finish().unwrap().summary;
        assert_eq!(
            u64::from(s.frames),
            route["frames"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            u64::from(s.lateral.anomalous),
            route["lateral"]["anomalous"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            u64::from(s.lateral.critical),
            route["lateral"]["critical"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            u64::from(s.comfort.comfortable),
            route["comfort"]["comfortable"].as_u64().unwrap(),
            "{id}"
        );
        // Without the setting the same route is measured against the route: other values.
        let core_lat = |text: &str| -> Vec<Option<f32>> {
            text.lines()
                .map(|l| {
                    monitor_core::json::decode_frame(l.as_bytes())
                        .unwrap()
                        .lat_err
                })
                .collect()
        };
        let route_ref = with("frames", &["--route-id", id]);
        lane_differs |= core_lat(&String::from_utf8(route_ref.stdout).unwrap()) != core_lat(&text);
    }
    assert!(
        lane_differs,
        "--set lateral_reference=lane changed no frame of the demo"
    );
}

/// docs/SCORE.md §10.0 on the demo: the route that stands through most of its frames (DemoStandingHit) is
/// stuck, and its comfort over the chunks it drove is below its comfort (its standing chunks
/// are all comfortable); a route that never stops has no stationary frame and the same comfort
/// both ways; the summary's figures follow from the routes'.
#[test]
fn a_standing_route_is_stuck_and_its_moving_comfort_is_lower() {
    let tmp = tempfile::tempdir().unwrap();
    demo(tmp.path());
    let d = |p: &str| tmp.path().join(p).to_str().unwrap().to_string();
    let o = sds(&[
        "score",
        "--results",
        &d("results.json"),
        "--telemetry",
        &d("telemetry"),
        "--routes",
        &d("routes.xml"),
    ]);
    let report: Value = serde_json::from_slice(&o.stdout).unwrap();
    let routes = report["routes"].as_array().unwrap();
    let by_type = |t: &str| routes.iter().find(|r| r["scenario_type"] == t).unwrap();
    let standing = by_type("DemoStandingHit");
    let share = standing["stationary_share"].as_f64().unwrap();
    assert!(share >= 0.5, "{share}");
    let (comfort, moving) = (
        standing["comfort"]["score"].as_f64().unwrap(),
        standing["comfort"]["moving_score"].as_f64().unwrap(),
    );
    assert!(moving < comfort, "moving {moving} vs comfort {comfort}");
    assert!(
        standing["comfort"]["moving_chunks"].as_u64().unwrap()
            < standing["comfort"]["chunks"].as_u64().unwrap()
    );
    let cruise = by_type("DemoCruising");
    assert_eq!(cruise["stationary_share"], 0.0);
    assert_eq!(
        cruise["comfort"]["moving_score"],
        cruise["comfort"]["score"]
    );
    // 200 frames at 10 m/s and 20 Hz: 199 gaps of 0.5 m.
    assert!((cruise["distance_m"].as_f64().unwrap() - 99.5).abs() < 1e-6);

    let s = &report["summary"];
    let stuck: Vec<&str> = s["stuck_routes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    let expected: Vec<&str> = routes
        .iter()
        .filter(|r| r["stationary_share"].as_f64().is_some_and(|x| x >= 0.5))
        .map(|r| r["route_id"].as_str().unwrap())
        .collect();
    assert_eq!(stuck, expected);
    assert!(stuck.contains(&standing["route_id"].as_str().unwrap()));
    let km: f64 = routes
        .iter()
        .filter_map(|r| r["distance_m"].as_f64())
        .sum::<f64>()
        / 1000.0;
    assert!((s["distance_km"].as_f64().unwrap() - km).abs() < 1e-12);
    assert!(s["mean_comfort_moving"].as_f64().unwrap() < s["mean_comfort"].as_f64().unwrap());
    // Leaderboard-style rate: entries over the sum of RC/100 * route_length / 1000.
    let results: Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("results.json")).unwrap()).unwrap();
    let (mut km, mut vehicle) = (0.0, 0.0);
    for rec in results["_checkpoint"]["records"].as_array().unwrap() {
        km += rec["scores"]["score_route"].as_f64().unwrap() / 100.0
            * rec["meta"]["route_length"].as_f64().unwrap()
            / 1000.0;
        vehicle += rec["infractions"]["collisions_vehicle"]
            .as_array()
            .unwrap()
            .len() as f64;
    }
    assert!(vehicle > 0.0);
    assert_eq!(
        s["infractions_per_km"]["collisions_vehicle"]
            .as_f64()
            .unwrap(),
        vehicle / km
    );
}
