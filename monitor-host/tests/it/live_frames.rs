//! The live frame building (`pipeline::live`) fed the demo run's ticks one at a time gives the
//! frames `sds frames` prints (`route_frames`), bit for bit, with the town's map under both
//! lateral references, and without a map against the route alone.

use std::path::Path;
use std::sync::Arc;

use monitor_host::geometry::corridor::ReferenceKind;
use monitor_host::input::route_xml::read_route_xml;
use monitor_host::pipeline::live::{load_map, LiveFrames, Tick};
use monitor_host::{demo, route_frames, Inputs, Settings};

/// The (step, tick) pairs of a route's `metric_info.json`, in step order.
fn ticks(telemetry: &Path, route_id: &str) -> Vec<(u64, Tick)> {
    let dir = std::fs::read_dir(telemetry)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(&format!("{route_id}_"))
        })
        .unwrap();
    let text = std::fs::read_to_string(dir.join("metric_info.json")).unwrap();
    let json: serde_json::Map<String, serde_json::Value> = serde_json::from_str(&text).unwrap();
    let v3 = |e: &serde_json::Value, k: &str| -> [f64; 3] {
        let a = e[k].as_array().unwrap();
        [0, 1, 2].map(|i| a[i].as_f64().unwrap())
    };
    let mut out: Vec<(u64, Tick)> = json
        .iter()
        .map(|(k, e)| {
            let tick = Tick {
                acceleration: v3(e, "acceleration"),
                angular_velocity: v3(e, "angular_velocity"),
                forward_vector: v3(e, "forward_vector"),
                right_vector: v3(e, "right_vector"),
                location: v3(e, "location"),
            };
            (k.parse().unwrap(), tick)
        })
        .collect();
    out.sort_by_key(|(s, _)| *s);
    out
}

#[test]
fn live_frames_equal_sds_frames_with_and_without_the_map() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry.clone()),
        route_xml: Some(run.routes.clone()),
        maps: Some(run.maps.clone()),
        ..Inputs::new([run.results.clone()])
    };
    let xml = read_route_xml(&run.routes).unwrap();
    let mut compared = 0;
    let mut lateral_known = 0;
    for (reference, with_map, kind) in [
        ("route", true, ReferenceKind::MapRoute),
        ("lane", true, ReferenceKind::MapLane),
        ("route", false, ReferenceKind::Xml),
    ] {
        let inputs = Inputs {
            maps: with_map.then(|| run.maps.clone()),
            ..inputs.clone()
        };
        for id in &run.route_ids {
            let mut settings = Settings::default();
            settings.set("lateral_reference", reference).unwrap();
            let cli = route_frames(&inputs, id, &settings).unwrap();
            assert_eq!(cli.reference, kind, "{id}");
            let route = xml.get(id.split('_').nth(1).unwrap()).unwrap();
            let map = with_map.then(|| Arc::new(load_map(&run.maps, Some(&route.town)).unwrap()));
            // The route's step period as the replay found it.
            settings.core.dt = cli.dt;
            let mut live = LiveFrames::new(Some(&route.waypoints_3d()), map, &settings).unwrap();
            assert_eq!(live.reference(), kind, "{id}");
            let ticks = ticks(&run.telemetry, id);
            assert_eq!(ticks.len(), cli.frames.len(), "{id}");
            for ((step, tick), (want, want_step)) in
                ticks.iter().zip(cli.frames.iter().zip(&cli.steps))
            {
                assert_eq!(step, want_step);
                let got = live.push(Some(*step), tick, want.collisions, None).unwrap();
                assert_eq!(&got, want, "{id} ({reference}, map {with_map}) step {step}");
                compared += 1;
                lateral_known += usize::from(got.lat_err.is_some());
            }
        }
    }
    assert!(
        compared > 3000 && lateral_known > compared / 2,
        "{compared} {lateral_known}"
    );
}

#[test]
fn a_refused_frame_is_rewound() {
    let route = [
        [0.0, 0.0, 0.0],
        [5.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [15.0, 0.0, 0.0],
    ];
    let settings = Settings::default();
    let tick = |x: f64| Tick {
        forward_vector: [1.0, 0.0, 0.0],
        right_vector: [0.0, 1.0, 0.0],
        location: [x, 0.25, 0.0],
        ..Tick::default()
    };
    let mut a = LiveFrames::new(Some(&route), None, &settings).unwrap();
    let mut b = LiveFrames::new(Some(&route), None, &settings).unwrap();
    a.push(None, &tick(0.0), Default::default(), None).unwrap();
    b.push(None, &tick(0.0), Default::default(), None).unwrap();
    // `a` builds a frame far along the route, then goes back as if the monitor refused it.
    let c = a.checkpoint();
    a.push(None, &tick(14.0), Default::default(), None).unwrap();
    a.rewind(c);
    assert_eq!(a.last_step(), Some(0));
    for x in [0.4, 0.8, 1.2] {
        let fa = a.push(None, &tick(x), Default::default(), None).unwrap();
        let fb = b.push(None, &tick(x), Default::default(), None).unwrap();
        assert_eq!(fa, fb);
    }
    // Errors name the step and change nothing.
    let e = a
        .push(Some(1), &tick(2.0), Default::default(), None)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "step 1: not after the previous step 3 (steps must increase)"
    );
    let nan = Tick {
        acceleration: [f64::NAN, 0.0, 0.0],
        ..tick(2.0)
    };
    let e = a.push(None, &nan, Default::default(), None).unwrap_err();
    assert_eq!(
        e.to_string(),
        "step 4: field acceleration: NaN or infinite value"
    );
    assert_eq!(a.last_step(), Some(3));
}

#[test]
fn map_and_reference_errors() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let e = load_map(&run.maps, None).unwrap_err();
    assert!(e.to_string().contains("name the town"), "{e}");
    let e = load_map(&run.maps, Some("Town99")).unwrap_err();
    assert!(e.to_string().starts_with("no map for Town99 in "), "{e}");
    assert!(load_map(&run.maps.join("DemoTown.xodr"), None).is_ok());
    let mut lane = Settings::default();
    lane.set("lateral_reference", "lane").unwrap();
    let e = LiveFrames::new(None, None, &lane).unwrap_err();
    assert!(e.to_string().starts_with("lateral_reference lane "), "{e}");
}
