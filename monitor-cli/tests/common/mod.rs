//! Helpers shared by the end-to-end tests that run the `sds` binary: running it, the demo run,
//! the real fixtures (skipped with the reason said when absent), reading its outputs.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{json, Value};

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
/// `None` with the reason said ([`skipped`]): the tests on real Bench2Drive files skip without
/// `../shared`.
pub fn b2d_fixtures(needed: &[&str]) -> Option<PathBuf> {
    let dir = shared_fixtures("b2d")?.join("b2d");
    match needed.iter().find(|f| !dir.join(f).exists()) {
        None => Some(dir),
        Some(missing) => {
            skipped(&format!(
                "the Bench2Drive fixtures are absent ({} not found)",
                dir.join(missing).display()
            ));
            None
        }
    }
}

/// `../shared/fixtures` when it holds `needed` (a path inside it), or `None` with the reason
/// said ([`skipped`]).
pub fn shared_fixtures(needed: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures");
    if dir.join(needed).exists() {
        Some(dir)
    } else {
        skipped(&format!(
            "the shared fixtures are absent ({} not found)",
            dir.join(needed).display()
        ));
        None
    }
}

/// Says that the running test skips and why: on standard error (shown with `--nocapture`), and
/// as a line of `$SDS_SKIP_LOG` when set, which `scripts/test-all.sh` lists at its end (as
/// `scripts/skip.sh` does for the scripts), so that no skip is silent.
pub fn skipped(why: &str) {
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    eprintln!("SKIP {test}: {why}");
    if let Some(log) = std::env::var_os("SDS_SKIP_LOG") {
        use std::io::Write as _;
        if let Ok(mut f) = std::fs::OpenOptions::new().append(true).open(log) {
            let _ = writeln!(f, "sds-cli test {test}: {why}");
        }
    }
}

/// The exit code of a finished `sds` (a test fails if a signal killed it).
pub fn code(o: &Output) -> i32 {
    o.status.code().expect("sds was killed by a signal")
}

/// Standard error of a finished `sds`, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A path as an argument.
pub fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

/// A path as a borrowed argument.
pub fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `sds` and returns (exit code, stderr).
pub fn run(args: &[&str]) -> (i32, String) {
    let out = sds(args);
    (out.status.code().unwrap_or(-1), stderr(&out))
}

/// A JSON file `sds` wrote.
pub fn read(p: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(p).unwrap())
        .unwrap_or_else(|e| panic!("{}: not JSON: {e}", p.display()))
}

/// The demo's results in `dir` split into two results files: records `..cut` and `cut..`.
pub fn split_demo(dir: &Path, cut: usize) -> (PathBuf, PathBuf) {
    let d = read(&dir.join("results.json"));
    let records = d["_checkpoint"]["records"].as_array().unwrap().clone();
    let write = |name: &str, recs: &[Value]| {
        let mut e = d.clone();
        e["_checkpoint"]["records"] = Value::Array(recs.to_vec());
        e["_checkpoint"]["progress"] = serde_json::json!([recs.len(), recs.len()]);
        let p = dir.join(name);
        std::fs::write(&p, e.to_string()).unwrap();
        p
    };
    (
        write("part_a.json", &records[..cut]),
        write("part_b.json", &records[cut..]),
    )
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
pub fn no_infractions() -> serde_json::Map<String, Value> {
    INFRACTION_LISTS
        .iter()
        .map(|l| (l.to_string(), serde_json::json!([])))
        .collect()
}

/// The demo run in a temporary folder, and its records (raw evaluator values).
pub struct Run {
    pub tmp: tempfile::TempDir,
    pub records: Vec<Value>,
}

impl Run {
    pub fn new() -> Run {
        let tmp = tempfile::tempdir().unwrap();
        demo(tmp.path());
        let doc: Value =
            serde_json::from_slice(&fs::read(tmp.path().join("results.json")).unwrap()).unwrap();
        let records = doc["_checkpoint"]["records"].as_array().unwrap().clone();
        Run { tmp, records }
    }

    pub fn path(&self, p: &str) -> PathBuf {
        self.tmp.path().join(p)
    }

    pub fn s(&self, p: &str) -> String {
        self.path(p).to_str().unwrap().to_string()
    }

    /// Writes `records` as a raw evaluator file `name` in the run's folder.
    pub fn write(&self, name: &str, records: &[Value]) -> String {
        let doc = json!({
            "_checkpoint": {"global_record": {}, "progress": [records.len(), records.len()],
                            "records": records},
            "entry_status": "Finished", "eligible": true, "sensors": [], "values": [], "labels": []
        });
        let p = self.path(name);
        fs::write(&p, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
        p.to_str().unwrap().to_string()
    }

    /// `sds score --results results --telemetry <demo's>` and `extra`.
    pub fn score(&self, results: &str, extra: &[&str]) -> Output {
        let telemetry = self.s("telemetry");
        let mut args = vec!["score", "--results", results, "--telemetry", &telemetry];
        args.extend_from_slice(extra);
        sds(&args)
    }
}
