//! `sds score`: protocols, the lateral reference, route sets and what the report says per route.

// ---- Issue 33, items 7, 4 and 8 (lateral re-acquisition, the page's route status, inputs) ----

mod i33_lateral {
    use std::path::{Path, PathBuf};

    use crate::common::sds;

    /// The shared fixtures, or `None` (with the reason printed) when they are absent.
    pub fn fixtures() -> Option<PathBuf> {
        let p = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/fixtures/b2d"
        ));
        if p.is_dir() {
            Some(p)
        } else {
            eprintln!("skipped: shared fixtures absent at {}", p.display());
            None
        }
    }

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
        let infractions: serde_json::Map<String, serde_json::Value> = lists
            .iter()
            .map(|l| (l.to_string(), serde_json::json!([])))
            .collect();
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

/// Issue 33 item 7 (spec v1.4 §2 re-acquisition), on a synthetic route: telemetry that starts at
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
    let Some(fx) = fixtures() else { return };
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
    let Some(fx) = i33_lateral::fixtures() else {
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
