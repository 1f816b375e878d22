//! Helpers shared by the end-to-end tests that run the `sds` binary on the demo run.
// Each test file compiles this module on its own and uses a part of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `sds` binary built for these tests.
pub fn sds(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(args)
        .output()
        .expect("run sds")
}

/// Writes the demo run into `dir`.
pub fn demo(dir: &Path) {
    let out = sds(&["demo", dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "sds demo failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `sds score` on the demo in `dir` (its telemetry and routes) with `results` (default: the
/// demo's) and `extra` arguments.
pub fn score_demo(dir: &Path, results: Option<&Path>, extra: &[&str]) -> Output {
    let d = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let results = results.map_or_else(|| d("results.json"), |p| p.to_str().unwrap().into());
    let (telemetry, routes) = (d("telemetry"), d("routes.xml"));
    let mut args = vec![
        "score",
        "--results",
        &results,
        "--telemetry",
        &telemetry,
        "--routes",
        &routes,
    ];
    args.extend_from_slice(extra);
    sds(&args)
}

/// `../shared/fixtures/b2d` when it holds every file or folder of `needed` (paths inside it), or
/// `None` with the reason printed: the tests on real Bench2Drive files skip without `../shared`.
pub fn b2d_fixtures(needed: &[&str]) -> Option<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures/b2d");
    match needed.iter().find(|f| !dir.join(f).exists()) {
        None if dir.is_dir() => Some(dir),
        missing => {
            eprintln!(
                "skipped: the Bench2Drive fixtures are absent ({} not found)",
                dir.join(missing.unwrap_or(&"")).display()
            );
            None
        }
    }
}

/// The 12 infraction lists of a Bench2Drive record, in the evaluator's order.
pub const INFRACTION_LISTS: [&str; 12] = [
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

/// A record's `infractions` object with every list empty.
pub fn no_infractions() -> serde_json::Map<String, serde_json::Value> {
    INFRACTION_LISTS
        .iter()
        .map(|l| (l.to_string(), serde_json::json!([])))
        .collect()
}
