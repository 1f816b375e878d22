//! `sds link` and `sds checker` (issue 49): the demo run played to the host checker over a
//! child's stdin/stdout, with and without faults.

use std::path::Path;

use crate::common::{demo, sds};

fn checker() -> String {
    format!("exec:{} checker", env!("CARGO_BIN_EXE_sds"))
}

/// `sds link` on the demo in `dir` with `extra` arguments; the report and the exit code.
fn link(dir: &Path, extra: &[&str]) -> (serde_json::Value, i32, String) {
    let out_file = dir.join(format!("link-{}.json", extra.len()));
    let d = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let (results, telemetry, out) = (
        d("results.json"),
        d("telemetry"),
        out_file.to_str().unwrap().to_string(),
    );
    let to = checker();
    let mut args = vec![
        "link",
        "--results",
        &results,
        "--telemetry",
        &telemetry,
        "-o",
        &out,
    ];
    let to_args: Vec<&str> = if extra.contains(&"--to") {
        vec![]
    } else {
        vec!["--to", &to]
    };
    args.extend_from_slice(&to_args);
    args.extend_from_slice(extra);
    let o = sds(&args);
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    let report = std::fs::read_to_string(&out_file)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or(serde_json::Value::Null);
    let _ = std::fs::remove_file(&out_file);
    (report, o.status.code().unwrap_or(-1), stderr)
}

#[test]
fn i49_2_link_to_host_checker_equals_replay_on_every_demo_route() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let (rep, code, stderr) = link(dir.path(), &[]);
    assert_eq!(code, 0, "{stderr}");
    let routes = rep["routes"].as_array().unwrap();
    assert!(routes.len() >= 5);
    assert_eq!(rep["summary"]["equal_routes"], routes.len());
    for r in routes {
        let l = &r["link"];
        assert_eq!(l["equal"], true, "{r}");
        // No fault: every frame accepted, one segment, every status OK.
        assert_eq!(l["accepted"], r["frames"], "{r}");
        assert_eq!(l["statuses"]["OK"], r["frames"]);
        assert_eq!(l["statuses"]["ERROR"], 0);
        assert_eq!(l["link_faults"].as_array().unwrap().len(), 0);
        assert_eq!(l["events"], l["replay_events"]);
    }
    // The demo has events to compare (comfort chunks at least).
    assert!(routes
        .iter()
        .any(|r| r["link"]["events"].as_u64().unwrap() > 0));
}

#[test]
fn i49_2_link_faults_are_deterministic_for_a_seed_and_never_wrong_verdicts() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let faults = "drop=0.05,corrupt=0.05,duplicate=0.05,reorder=0.05,seed=11";
    let (tap1, tap2) = (dir.path().join("tap1"), dir.path().join("tap2"));
    let mut runs = Vec::new();
    for tap in [&tap1, &tap2] {
        let (rep, code, stderr) = link(
            dir.path(),
            &["--inject", faults, "--tap", tap.to_str().unwrap()],
        );
        assert_eq!(code, 0, "{stderr}");
        runs.push(rep);
    }
    let sent1 = std::fs::read(tap1.join("sent.bin")).unwrap();
    assert_eq!(sent1, std::fs::read(tap2.join("sent.bin")).unwrap());
    assert!(!std::fs::read(tap1.join("received.bin")).unwrap().is_empty());
    // What the checker accepted and judged is the same in both runs (NONEWDATA aside: it is
    // the checker's clock, and only ever cuts a segment).
    let key = |rep: &serde_json::Value| -> Vec<String> {
        rep["routes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                let l = &r["link"];
                let s = &l["statuses"];
                format!(
                    "{} {} {} {} {} {} {} {}",
                    l["equal"],
                    l["accepted"],
                    l["events"],
                    s["OK"],
                    s["OKSOMELOST"],
                    s["WRONGSEQUENCE"],
                    s["REPEATED"],
                    s["ERROR"]
                )
            })
            .collect()
    };
    assert_eq!(key(&runs[0]), key(&runs[1]));
    let routes = runs[0]["routes"].as_array().unwrap();
    let total = |k: &str| -> u64 {
        routes
            .iter()
            .map(|r| r["link"]["statuses"][k].as_u64().unwrap())
            .sum()
    };
    // Each fault kind happened, and the checker still agreed with the replay everywhere.
    assert!(total("ERROR") > 0 && total("REPEATED") > 0 && total("WRONGSEQUENCE") > 0);
    assert!(total("OKSOMELOST") > 0);
    assert!(routes.iter().all(|r| r["link"]["equal"] == true));
    let frames: u64 = routes.iter().map(|r| r["frames"].as_u64().unwrap()).sum();
    let accepted: u64 = routes
        .iter()
        .map(|r| r["link"]["accepted"].as_u64().unwrap())
        .sum();
    assert!(accepted < frames);
}

#[test]
fn i49_2_link_stall_cuts_segments_and_stays_equal() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let (rep, code, stderr) = link(dir.path(), &["--inject", "stall=0.4,seed=3"]);
    assert_eq!(code, 0, "{stderr}");
    for r in rep["routes"].as_array().unwrap() {
        let l = &r["link"];
        assert_eq!(l["equal"], true, "{r}");
        // 0.4 s lost: 8 frames at 20 Hz (4 at 10 Hz), and the next one a counter jump past
        // max_delta (WRONGSEQUENCE, dropped) that starts a new segment; fewer at a route's end.
        let lost = r["frames"].as_u64().unwrap() - l["accepted"].as_u64().unwrap();
        let jumps = l["statuses"]["WRONGSEQUENCE"].as_u64().unwrap();
        assert!((1..=9).contains(&lost), "{r}");
        assert!(jumps <= 1, "{r}");
        if jumps == 1 {
            assert!(l["segments"].as_u64().unwrap() >= 2, "{r}");
        }
    }
}

#[test]
fn i49_2_link_detects_a_checker_that_judges_otherwise() {
    // The checker tolerates no lost frame (max_delta 1) while the doer judges with the default
    // 3: frames after a loss are accepted by one and not the other, and the report says so.
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let strict = format!(
        "exec:{} checker --set link.max_delta=1",
        env!("CARGO_BIN_EXE_sds")
    );
    let (rep, code, _) = link(
        dir.path(),
        &["--to", &strict, "--inject", "drop=0.1,seed=5"],
    );
    assert_eq!(code, 3);
    assert!(
        rep["summary"]["equal_routes"].as_u64().unwrap()
            < rep["summary"]["routes"].as_u64().unwrap()
    );
}

#[test]
fn i49_2_bad_target_and_faults_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    demo(dir.path());
    let (_, code, stderr) = link(dir.path(), &["--to", "udp:1.2.3.4"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--to") && stderr.contains("tcp:HOST:PORT"),
        "{stderr}"
    );
    let (_, code, stderr) = link(dir.path(), &["--inject", "drop=1.5"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--inject") && stderr.contains("at most 1"),
        "{stderr}"
    );
    let out = sds(&["checker", "--set", "link.window=99"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("link.window"));
    // A vehicle log's topic without a log: refused by the library's request, as `sds score` is.
    let (_, code, stderr) = link(dir.path(), &["--topic", "path=/path"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("no log is given"), "{stderr}");
    // `--set` without `=`: the settings' own syntax error.
    let out = sds(&["checker", "--set", "link.window"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("link.window"));
}

/// Issue 49 item 5: a real route through the link. The fixtures hold no telemetry of a whole
/// route, so the telemetry is generated along the real waypoints of route 25300 of
/// `bench2drive220.xml` (Town04) at 20 Hz, weaving across the lane (±0.8 m, a 12 s period) and
/// changing speed, and scored against the real Town04 OpenDRIVE map (`lateral_reference=lane`).
/// Played by `sds link` into the host checker, the checker's events equal the replay's, clean
/// and with every fault kind at a fixed seed.
#[test]
fn i49_5_real_route_and_map_through_the_link_equal_the_replay() {
    let Some(fx) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml"]) else {
        return;
    };
    let maps = fx.join("../maps");
    if !maps.join("Town04.xodr").is_file() {
        eprintln!(
            "skipped: the real Town04 map is absent ({} not found)",
            maps.join("Town04.xodr").display()
        );
        return;
    }
    let set = monitor_host::input::route_xml::read_route_xml(&fx.join("routes/bench2drive220.xml"))
        .unwrap();
    let route = set.get("25300").expect("route 25300").waypoints_3d();
    let length: f64 = route
        .windows(2)
        .map(|p| (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]))
        .sum();
    let dt = 0.05;
    let (mut s, mut frames) = (0.0f64, Vec::new());
    let mut step = 0u64;
    while s < length - 1.0 && step < 1200 {
        let t = step as f64 * dt;
        let v = 7.0 + 2.0 * (t / 9.0).sin();
        let a = 2.0 / 9.0 * (t / 9.0).cos();
        let offset = 0.8 * (2.0 * std::f64::consts::PI * t / 12.0).sin();
        let (loc, psi) = crate::mcap::along(&route, s, offset);
        frames.push(crate::mcap::CarlaFrame {
            step,
            loc,
            psi,
            acc: [a * psi.cos(), a * psi.sin()],
            omega_deg: 0.0,
        });
        s += v * dt;
        step += 1;
    }
    // The whole route (about 135 m of it, 368 frames).
    assert!(frames.len() >= 300, "{} frames", frames.len());
    let tmp = tempfile::tempdir().unwrap();
    let ([res, tel, routes], _) =
        crate::mcap::write_telemetry_run(tmp.path(), "25300", "Town04", &route, &frames);
    // firmware-example/link-checker/run-link.sh plays the same run into the Cortex-M4F checker.
    if let Some(dir) = std::env::var_os("SDS_LINK_REAL_ROUTE_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        crate::mcap::write_telemetry_run(Path::new(&dir), "25300", "Town04", &route, &frames);
    }
    let out = tmp.path().join("link.json");
    let maps = maps.to_str().unwrap().to_string();
    let to = checker();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "link",
            "--results",
            &res,
            "--telemetry",
            &tel,
            "--routes",
            &routes,
            "--maps",
            &maps,
            "--set",
            "dt=0.05",
            "--set",
            "lateral_reference=lane",
            "--to",
            &to,
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = sds(&args);
        let text = std::fs::read_to_string(&out).unwrap_or_default();
        let rep: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
        (o, rep)
    };
    let (o, rep) = run(&[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let l = &rep["routes"][0]["link"];
    assert_eq!(l["equal"], true, "{l}");
    assert_eq!(l["accepted"].as_u64(), Some(frames.len() as u64), "{l}");
    assert_eq!(l["segments"], 1, "{l}");
    // The lateral chunks against the real lane raise events: the comparison has something to compare.
    assert!(l["events"].as_u64().unwrap() > 0, "{l}");
    assert_eq!(l["events"], l["replay_events"], "{l}");
    let (o, rep) = run(&[
        "--inject",
        "drop=0.03,corrupt=0.03,duplicate=0.02,reorder=0.02,stall=0.5,seed=5",
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let l = &rep["routes"][0]["link"];
    assert_eq!(l["equal"], true, "{l}");
    let bad: u64 = ["WRONGSEQUENCE", "REPEATED", "ERROR"]
        .iter()
        .map(|k| l["statuses"][k].as_u64().unwrap())
        .sum();
    assert!(
        bad > 0 && l["accepted"].as_u64().unwrap() < frames.len() as u64,
        "{l}"
    );
}
