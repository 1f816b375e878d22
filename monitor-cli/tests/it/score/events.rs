//! The per-route `events` of the JSON report: every collision (placed or not), the evaluator's
//! other infractions (placed by their own rules or listed unplaced), every anomalous and critical
//! lateral chunk, every uncomfortable chunk and every long stationary stretch, on the frame axis,
//! in frame order.

use serde_json::Value;

use crate::common::{self, demo, score_demo};

fn count(r: &Value, kind: &str) -> u64 {
    r["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == kind)
        .count() as u64
}

#[test]
fn demo_events_match_the_counts_and_the_collisions() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = score_demo(dir.path(), None, &["--format", "json"]);
    assert_eq!(out.status.code(), Some(0));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut total = 0;
    for r in report["routes"].as_array().unwrap() {
        let id = &r["route_id"];
        let events = r["events"].as_array().unwrap();
        total += events.len();
        let lat = &r["lateral"];
        let comfort = &r["comfort"];
        assert_eq!(
            count(r, "lateral_anomalous"),
            lat["anomalous"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            count(r, "lateral_critical"),
            lat["critical"].as_u64().unwrap(),
            "{id}"
        );
        assert_eq!(
            count(r, "uncomfortable"),
            comfort["chunks"].as_u64().unwrap() - comfort["comfortable"].as_u64().unwrap(),
            "{id}"
        );
        // Collisions: the same frame, step and time as collision_events, in that list's order.
        let collisions: Vec<&Value> = events.iter().filter(|e| e["kind"] == "collision").collect();
        let listed = r["collision_events"].as_array().unwrap();
        assert_eq!(collisions.len(), listed.len(), "{id}");
        for (e, c) in collisions.iter().zip(listed) {
            for k in ["frame", "step", "time_s"] {
                assert_eq!(e[k], c[k], "{id} {k}");
            }
            assert!(e["message"]
                .as_str()
                .unwrap()
                .starts_with(c["list"].as_str().unwrap()));
        }
        // Frame order; a chunk starts at a multiple of the chunk length, and its time follows
        // from its step as a collision's does.
        let frames: Vec<u64> = events
            .iter()
            .map(|e| e["frame"].as_u64().unwrap())
            .collect();
        assert!(frames.windows(2).all(|w| w[0] <= w[1]), "{id}: {frames:?}");
        let dt = r["dt"].as_f64().unwrap();
        let chunk = |e: &&Value| e["placed_by"] == "chunk";
        for e in events.iter().filter(chunk) {
            assert_eq!(e["frame"].as_u64().unwrap() % 20, 0, "{id}");
            let t = e["time_s"].as_f64().unwrap();
            let want = e["frame"].as_f64().unwrap() * dt; // the demo has no gaps
            assert!((t - want).abs() < 1e-9, "{id}: {t} vs {want}");
        }
    }
    assert!(total >= 15, "only {total} events on the demo");
    // The 10 Hz route: its chunk 2 starts 4 s in, not 2 s.
    let r = report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == "RouteScenario_900008_rep0")
        .unwrap();
    let e = r["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "uncomfortable" && e["frame"] == 40)
        .expect("chunk 2 uncomfortable");
    assert_eq!(e["time_s"], 4.0);
}

#[test]
fn unplaced_collisions_are_listed_last() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    // Without telemetry nothing can be placed: every collision is listed, unplaced.
    let d = |p: &str| dir.path().join(p).to_str().unwrap().to_string();
    let out = common::sds(&[
        "score",
        "--results",
        &d("results.json"),
        "--allow-missing-telemetry",
        "--format",
        "json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut unplaced = 0;
    for r in report["routes"].as_array().unwrap() {
        let events = r["events"].as_array().unwrap();
        let collisions = events.iter().filter(|e| e["kind"] == "collision").count();
        assert_eq!(collisions, r["collision_events"].as_array().unwrap().len());
        // The other infractions too: a red light and a blocked agent in the demo.
        let others = events.iter().filter(|e| e["kind"] != "collision").count();
        let i = &r["infractions"];
        assert_eq!(
            others as u64,
            i["red_light"].as_u64().unwrap() + i["vehicle_blocked"].as_u64().unwrap(),
            "{}",
            r["route_id"]
        );
        for e in events {
            assert!(e["frame"].is_null() && e["step"].is_null() && e["time_s"].is_null());
            assert!(e["message"].as_str().unwrap().contains("not placed"));
            unplaced += 1;
        }
    }
    assert!(unplaced >= 7, "{unplaced}");
}

/// The demo's frames of one route, read back from its telemetry: (x, y) per frame.
fn locations(dir: &std::path::Path, save_name: &str) -> Vec<[f64; 2]> {
    let path = dir
        .join("telemetry")
        .join(save_name)
        .join("metric_info.json");
    let doc: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let mut steps: Vec<(u64, [f64; 2])> = doc
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| {
            let l = &v["location"];
            (
                k.parse().unwrap(),
                [l[0].as_f64().unwrap(), l[1].as_f64().unwrap()],
            )
        })
        .collect();
    steps.sort_by_key(|s| s.0);
    steps.into_iter().map(|s| s.1).collect()
}

#[test]
fn red_lights_sit_at_the_closest_approach_and_blocked_where_the_car_stopped() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let out = score_demo(dir.path(), None, &["--format", "json"]);
    assert_eq!(out.status.code(), Some(0));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let route = |id: &str| {
        report["routes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["route_id"] == id)
            .unwrap()
            .clone()
    };
    let save = |r: &Value| {
        let record: Value =
            serde_json::from_slice(&std::fs::read(dir.path().join("results.json")).unwrap())
                .unwrap();
        record["_checkpoint"]["records"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["route_id"] == r["route_id"])
            .unwrap()["save_name"]
            .as_str()
            .unwrap()
            .to_string()
    };
    // The junction route runs the light standing 6.5 m beside the lane at 58 m: the frame
    // nearest to the light, found here by brute force on the telemetry.
    let r = route("RouteScenario_900009_rep0");
    let light = [1520.0 + 58.0, -3310.0 + 6.5];
    let locs = locations(dir.path(), &save(&r));
    let dist = |l: &[f64; 2]| (l[0] - light[0]).hypot(l[1] - light[1]);
    let nearest = (0..locs.len())
        .min_by(|&a, &b| dist(&locs[a]).total_cmp(&dist(&locs[b])))
        .unwrap();
    let red: Vec<&Value> = r["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "red_light")
        .collect();
    assert_eq!(red.len(), 1);
    assert_eq!(red[0]["frame"], nearest as u64);
    assert_eq!(red[0]["list"], "red_light");
    assert_eq!(red[0]["placed_by"], "closest_approach");
    assert!((red[0]["distance_m"].as_f64().unwrap() - dist(&locs[nearest])).abs() < 1e-9);
    assert_eq!(r["infractions"]["red_light"], 1);
    // The crash route is blocked where it came to a stop: the first frame at its last position.
    let r = route("RouteScenario_900005_rep0");
    let locs = locations(dir.path(), &save(&r));
    let last = *locs.last().unwrap();
    let stop = locs
        .iter()
        .position(|l| (l[0] - last[0]).hypot(l[1] - last[1]) <= 1e-3)
        .unwrap();
    let blocked: Vec<&Value> = r["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "blocked")
        .collect();
    assert_eq!(blocked.len(), 1);
    assert_eq!(blocked[0]["frame"], stop as u64);
    assert_eq!(blocked[0]["placed_by"], "nearest");
    // The standing route: one stationary event from where it stopped to its last frame.
    let r = route("RouteScenario_900007_rep0");
    let st: Vec<&Value> = r["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "stationary")
        .collect();
    assert_eq!(st.len(), 1);
    assert_eq!(st[0]["end_frame"], r["frames"]);
    let span = st[0]["end_frame"].as_u64().unwrap() - st[0]["frame"].as_u64().unwrap();
    let share = r["stationary_share"].as_f64().unwrap();
    assert_eq!(span as f64 / r["frames"].as_f64().unwrap(), share);
}

fn fixtures() -> Option<std::path::PathBuf> {
    crate::common::b2d_fixtures(&[])
}

/// Every red light and stop sign of the real results files: listed in the report (unplaced:
/// no telemetry there), its position read from its message, within `events.signal_reach` of
/// its route's waypoints, and placed when the route's waypoints are driven (every 0.25 m).
#[test]
fn real_red_lights_and_stop_signs_are_listed_and_within_reach() {
    use monitor_host::input::message::message_position;
    use monitor_host::input::record::Infractions;
    use monitor_host::input::route_xml::read_route_xml;
    use monitor_host::pipeline::placement::{infraction_events, place, PlacedBy};
    use monitor_host::settings::Settings;

    let Some(b2d) = fixtures() else { return };
    let set = read_route_xml(&b2d.join("routes/bench2drive220.xml")).unwrap();
    let settings = Settings::default();
    let (mut listed, mut placed, mut farthest) = (0usize, 0usize, 0.0f64);
    for name in [
        "carla_garage_tfpp_b2d_traj_merged.json",
        "carla_garage_pdm_lite_b2d_traj_merged.json",
        "b2dzoo_UniAD-Base_merged.json",
        "b2dzoo_VAD_merged.json",
        "b2dzoo_TCP-only-traj_merged.json",
        "simlingo_bench2drive220_targetpoint_checkpoint.json",
        "lead_tfv6_per_route",
    ] {
        let file = b2d.join(name);
        let out = common::sds(&[
            "score",
            "--allow-missing-telemetry",
            "--format",
            "json",
            "--results",
            file.to_str().unwrap(),
        ]);
        let report: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|_| {
            panic!("{name}: {}", String::from_utf8_lossy(&out.stderr));
        });
        for r in report["routes"].as_array().unwrap() {
            let Some(events) = r["events"].as_array() else {
                continue;
            };
            for (kind, list) in [("red_light", "red_light"), ("stop_sign", "stop_infraction")] {
                let mine: Vec<&Value> = events.iter().filter(|e| e["kind"] == kind).collect();
                assert_eq!(
                    mine.len() as u64,
                    r["infractions"][list].as_u64().unwrap_or(0),
                    "{name} {}",
                    r["route_id"]
                );
                for e in &mine {
                    assert!(e["frame"].is_null(), "{name}: placed without telemetry");
                    assert!(e["message"]
                        .as_str()
                        .unwrap()
                        .ends_with("(not placed: no telemetry)"));
                }
                listed += mine.len();
            }
            // Drive the route's waypoints and place its signals on that drive.
            let id = r["route_id"].as_str().unwrap();
            let xml_id = id.split('_').nth(1).unwrap();
            let route = set.get(xml_id).unwrap();
            let mut locations = Vec::new();
            for w in route.waypoints.windows(2) {
                let n = ((w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]) / 0.25)
                    .ceil()
                    .max(1.0);
                for k in 0..n as usize {
                    let t = k as f64 / n;
                    locations.push([
                        w[0][0] + t * (w[1][0] - w[0][0]),
                        w[0][1] + t * (w[1][1] - w[0][1]),
                    ]);
                }
            }
            let steps: Vec<u64> = (0..locations.len() as u64).collect();
            let messages = |list: &str| -> Vec<String> {
                events
                    .iter()
                    .filter(|e| e["list"] == list)
                    .map(|e| {
                        let m = e["message"].as_str().unwrap();
                        m[list.len() + 2..m.len() - " (not placed: no telemetry)".len()].to_string()
                    })
                    .collect()
            };
            let inf = Infractions::from_lists([
                ("red_light", messages("red_light")),
                ("stop_infraction", messages("stop_infraction")),
            ]);
            let mut signals = infraction_events(&inf);
            for s in &signals {
                assert!(message_position(&s.message).is_some(), "{}", s.message);
            }
            place(&mut signals, &steps, &locations, None, &settings, 0.05);
            for s in &signals {
                assert_eq!(
                    s.placed_by,
                    Some(PlacedBy::ClosestApproach),
                    "{name} {id}: {}",
                    s.message
                );
                farthest = farthest.max(s.distance_m.unwrap());
                placed += 1;
            }
        }
    }
    eprintln!(
        "{listed} red lights and stop signs listed; {placed} placed on drives along their \
         routes' waypoints, the farthest {farthest:.1} m from its light or sign"
    );
    assert_eq!(placed, listed);
    assert!(listed >= 99, "{listed}");
}
