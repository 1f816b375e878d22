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
