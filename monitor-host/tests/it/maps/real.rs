//! `--maps` on the real CARLA towns (`../shared/fixtures/maps`) and real routes of
//! `bench2drive220.xml`. The real results carry no telemetry, so a drive is synthesized along a
//! Town01 route that crosses junctions: on its lanes (the route with its junction gaps filled by
//! the map, as a car drives it) with a gentle sideways wobble. A Town12 route (no map in the
//! fixtures) rides along to check the fallback. Skips with a printed reason when the fixtures
//! are absent.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use monitor_host::geometry::corridor::reference_polyline;
use monitor_host::geometry::map::Map;
use monitor_host::input::route_xml::{read_route_xml, RouteRef};
use monitor_host::{score_run, Inputs, Settings};

fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures")
}

/// A drive along `path` (CARLA x, y) at 0.5 m per 20 Hz step (10 m/s), `frames` long, offset
/// sideways by `0.4 sin(t)` m: `metric_info.json` in Bench2Drive's layout.
fn drive(path: &[[f64; 2]], frames: usize) -> String {
    let mut cum = vec![0.0];
    for w in path.windows(2) {
        cum.push(cum.last().unwrap() + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]));
    }
    let mut out = String::from("{");
    let mut seg = 0;
    for i in 0..frames {
        let at = (0.5 * i as f64).min(*cum.last().unwrap());
        while seg + 2 < path.len() && cum[seg + 1] < at {
            seg += 1;
        }
        let (a, b) = (path[seg], path[seg + 1]);
        let len = (cum[seg + 1] - cum[seg]).max(1e-9);
        let f = ((at - cum[seg]) / len).clamp(0.0, 1.0);
        let (dx, dy) = ((b[0] - a[0]) / len, (b[1] - a[1]) / len);
        // CARLA's right vector of heading (dx, dy) is (-dy, dx).
        let off = 0.4 * (0.05 * i as f64).sin();
        let (x, y) = (
            a[0] + f * (b[0] - a[0]) - dy * off,
            a[1] + f * (b[1] - a[1]) + dx * off,
        );
        let sep = if i == 0 { "" } else { "," };
        let _ = write!(
            out,
            "{sep}\"{}\": {{\"acceleration\": [0.0, 0.0, 0.0], \"angular_velocity\": [0.0, 0.0, 0.0], \
             \"forward_vector\": [{dx}, {dy}, 0.0], \"right_vector\": [{}, {dx}, 0.0], \
             \"location\": [{x}, {y}, 0.0]}}",
            i + 1,
            -dy
        );
    }
    out.push('}');
    out
}

fn record(index: usize, route: &RouteRef, save: &str, frames: usize) -> serde_json::Value {
    serde_json::json!({
        "index": index,
        "route_id": format!("RouteScenario_{}_rep0", route.id),
        "status": "Completed",
        "num_infractions": 0,
        "infractions": {},
        "scores": {"score_route": 100.0, "score_penalty": 1.0, "score_composed": 100.0},
        "meta": {"route_length": 100.0, "duration_game": frames as f64 * 0.05,
                 "duration_system": 1.0},
        "save_name": save,
        "town_name": route.town,
    })
}

#[test]
fn real_towns_fill_junctions_and_fall_back_without_a_map() {
    let (maps, xml) = (
        shared().join("maps"),
        shared().join("b2d/routes/bench2drive220.xml"),
    );
    if !maps.join("Town01.xodr").is_file() || !xml.is_file() {
        eprintln!("SKIP: ../shared/fixtures (CARLA maps, bench2drive220.xml) not found");
        return;
    }
    let set = read_route_xml(&xml).unwrap();
    let town01 = Map::load(&maps.join("Town01.xodr")).unwrap();
    // The first Town01 route whose first junction gap the map fills.
    let (route, path) = set
        .iter()
        .filter(|r| r.town == "Town01")
        .find_map(|r| {
            let w = r.waypoints_3d();
            let gap = w
                .windows(2)
                .position(|p| (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]) > 8.0)?;
            if gap > 100 {
                return None;
            }
            let path = reference_polyline(&w, 8.0, Some(&town01));
            (path.len() > w.len()).then_some((r, path))
        })
        .expect("a Town01 route with a filled junction gap");
    let other = set
        .iter()
        .find(|r| r.town == "Town12")
        .expect("a Town12 route");

    let dir = tempfile::tempdir().unwrap();
    let tel = dir.path().join("telemetry");
    let mut records = Vec::new();
    for (i, (r, p)) in [(route, path.clone()), (other, other.waypoints.clone())]
        .into_iter()
        .enumerate()
    {
        let save = format!("RouteScenario_{}_rep0_{}_real", r.id, r.town);
        std::fs::create_dir_all(tel.join(&save)).unwrap();
        std::fs::write(tel.join(&save).join("metric_info.json"), drive(&p, 600)).unwrap();
        records.push(record(i, r, &save, 600));
    }
    let results = dir.path().join("results.json");
    let doc = serde_json::json!({"_checkpoint": {"progress": [2, 2], "records": records},
                                 "entry_status": "Finished"});
    std::fs::write(&results, doc.to_string()).unwrap();
    // The route XML of these two routes only (the run is not the whole benchmark).
    let mut routes_xml = String::from("<routes>");
    for r in [route, other] {
        let _ = write!(
            routes_xml,
            "<route id=\"{}\" town=\"{}\"><waypoints>",
            r.id, r.town
        );
        for w in &r.waypoints {
            let _ = write!(
                routes_xml,
                "<position x=\"{}\" y=\"{}\" z=\"0\"/>",
                w[0], w[1]
            );
        }
        routes_xml.push_str("</waypoints></route>");
    }
    routes_xml.push_str("</routes>");
    let routes = dir.path().join("routes.xml");
    std::fs::write(&routes, routes_xml).unwrap();

    let inputs = Inputs {
        telemetry: Some(tel),
        route_xml: Some(routes),
        ..Inputs::new([results])
    };
    let with_maps = Inputs {
        maps: Some(maps),
        ..inputs.clone()
    };
    let id = format!("RouteScenario_{}_rep0", route.id);
    let find = |rep: &monitor_host::Report, id: &str| {
        rep.routes
            .iter()
            .find(|r| r.route_id.as_deref() == Some(id))
            .cloned()
            .unwrap()
    };
    let plain = score_run(&inputs, &Settings::default()).unwrap();
    let mapped = score_run(&with_maps, &Settings::default()).unwrap();
    let (a, b) = (find(&plain, &id), find(&mapped, &id));
    assert_eq!(a.lateral.reference.map(|k| k.name()), Some("xml"));
    assert_eq!(b.lateral.reference.map(|k| k.name()), Some("map-route"));
    eprintln!(
        "{id} (Town01): scored chunks {} of {} from the route XML, {} with the map",
        a.lateral.scored_chunks, a.lateral.chunks, b.lateral.scored_chunks
    );
    assert_eq!(a.lateral.chunks, b.lateral.chunks);
    assert!(
        b.lateral.scored_chunks > a.lateral.scored_chunks,
        "junction frames scored: {} -> {}",
        a.lateral.scored_chunks,
        b.lateral.scored_chunks
    );
    // Driving on the lanes, 0.4 m at most off their centres: no excess anywhere.
    assert_eq!((b.lateral.anomalous, b.lateral.critical), (0, 0));
    assert_eq!(b.batch_agrees, Some(true));

    // Town12 has no map in the fixtures: one warning, the route XML as reference.
    let other_id = format!("RouteScenario_{}_rep0", other.id);
    let o = find(&mapped, &other_id);
    assert_eq!(o.lateral.reference.map(|k| k.name()), Some("xml"));
    let warnings: Vec<String> = mapped.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings
            .iter()
            .filter(|w| w.contains("no map for Town12"))
            .count(),
        1,
        "{warnings:?}"
    );
    assert!(
        warnings.iter().all(|w| !w.contains("Town01")),
        "{warnings:?}"
    );

    // lateral_reference=lane: the nearest lane, Town01 only.
    let mut lane = Settings::default();
    lane.set("lateral_reference", "lane").unwrap();
    let laned = score_run(&with_maps, &lane).unwrap();
    let l = find(&laned, &id);
    assert_eq!(l.lateral.reference.map(|k| k.name()), Some("map-lane"));
    assert_eq!(l.lateral.scored_chunks, l.lateral.chunks);
    assert_eq!(
        find(&laned, &other_id).lateral.reference.map(|k| k.name()),
        Some("xml")
    );
}
