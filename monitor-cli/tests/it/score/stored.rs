//! `sds score` on real Bench2Drive result files (`../shared/fixtures/b2d`): the stored driving
//! score and success rate are reproduced, every record is reported, bad files are explained.
//! Skips, with a printed reason, when the fixtures are absent (a user's clone has none).

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

/// `../shared/fixtures/b2d`, or `None` (the skip said).
fn fixtures() -> Option<PathBuf> {
    crate::common::b2d_fixtures(&[])
}

/// Runs `sds score` and returns (exit code, report, stderr).
fn score(args: &[&str]) -> (i32, Option<Value>, String) {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("report.json");
    let out = Command::new(env!("CARGO_BIN_EXE_sds"))
        .arg("score")
        .args(args)
        .arg("-o")
        .arg(&out_path)
        .output()
        .unwrap();
    let report = std::fs::read_to_string(&out_path)
        .ok()
        .map(|t| serde_json::from_str(&t).unwrap());
    (
        out.status.code().unwrap_or(-1),
        report,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn stored(file: &Path) -> (f64, f64, usize) {
    let v: Value = serde_json::from_slice(&std::fs::read(file).unwrap()).unwrap();
    (
        v["driving score"].as_f64().unwrap(),
        v["success rate"].as_f64().unwrap(),
        v["_checkpoint"]["records"].as_array().unwrap().len(),
    )
}

#[test]
fn merged_files_reproduce_stored_driving_score_and_success_rate() {
    let Some(dir) = fixtures() else { return };
    for name in [
        "carla_garage_tfpp_b2d_traj_merged.json",
        "carla_garage_pdm_lite_b2d_traj_merged.json",
        "b2dzoo_UniAD-Base_merged.json",
    ] {
        let file = dir.join(name);
        let (ds, sr, records) = stored(&file);
        let (code, report, stderr) = score(&[
            "--results",
            file.to_str().unwrap(),
            "--expected-routes",
            "220",
        ]);
        // No telemetry ships with these runs: every route is reported `missing` -> exit 3.
        assert_eq!(code, 3, "{name}: {stderr}");
        let r = report.expect("report written");
        let s = &r["summary"];
        assert_eq!(s["routes"], 220);
        assert_eq!(s["routes_found"].as_u64().unwrap() as usize, records);
        assert_eq!(r["routes"].as_array().unwrap().len(), records, "{name}");
        assert!(r["routes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|x| x["telemetry"] == "missing"));
        let got_ds = s["driving_score"].as_f64().unwrap();
        let got_sr = s["success_rate"].as_f64().unwrap();
        assert!((got_ds - ds).abs() < 1e-9, "{name}: DS {got_ds} vs {ds}");
        assert!(
            (got_sr - 100.0 * sr).abs() < 1e-9,
            "{name}: SR {got_sr} vs {}",
            100.0 * sr
        );
        assert!(s["mean_ds_safe"].is_null(), "not scored without telemetry");

        // Allowed to score without telemetry terms: DS_safe = DS with work-zone factors only.
        let (code, report, _) = score(&[
            "--results",
            file.to_str().unwrap(),
            "--expected-routes",
            "220",
            "--allow-missing-telemetry",
        ]);
        assert_eq!(code, 0);
        let r = report.unwrap();
        for route in r["routes"].as_array().unwrap() {
            let wz = route["collisions"]["workzone"].as_i64().unwrap();
            let expect = route["score_route"].as_f64().unwrap()
                * route["score_penalty"].as_f64().unwrap()
                * (0.5f64 / 0.65).powi(wz as i32);
            let got = route["ds_safe"].as_f64().unwrap();
            assert!((got - expect).abs() < 1e-9, "{}", route["route_id"]);
        }
    }
}

#[test]
fn penalty_recheck_flags_the_hand_edited_record() {
    let Some(dir) = fixtures() else { return };
    let file = dir.join("carla_garage_pdm_lite_b2d_traj_merged.json");
    let (_, report, _) = score(&["--results", file.to_str().unwrap()]);
    let r = report.unwrap();
    assert_eq!(
        r["summary"]["penalty_mismatches"],
        serde_json::json!(["RouteScenario_11755_rep0"])
    );
}

#[test]
fn raw_files_and_the_crashed_run() {
    let Some(dir) = fixtures() else { return };
    let simlingo = dir.join("simlingo_bench2drive220_targetpoint_checkpoint.json");
    let (_, report, _) = score(&["--results", simlingo.to_str().unwrap()]);
    assert_eq!(report.unwrap()["routes"].as_array().unwrap().len(), 220);

    let route3564 = dir.join("pdmlite_route3564_endpoint_tickruntime_mesh_collisions.json");
    let (_, report, _) = score(&["--results", route3564.to_str().unwrap()]);
    let r = report.unwrap();
    let route = &r["routes"][0];
    assert_eq!(route["route_id"], "RouteScenario_3564_rep0");
    assert_eq!(route["collisions"]["layout"], 3);
    assert_eq!(
        route["collisions"]["workzone"], 0,
        "static.prop.mesh is a parked car"
    );
    assert_eq!(route["penalty_check"]["agrees"], true);

    // An empty run: one clear message, its own exit code, no report.
    let crashed = dir.join("pdmlite_route24206_endpoint_crashed_empty.json");
    let (code, report, stderr) = score(&["--results", crashed.to_str().unwrap()]);
    assert_eq!(code, 4, "an empty run has its own exit code: {stderr}");
    assert!(stderr.contains("no records in"), "{stderr}");
    assert!(stderr.contains(crashed.to_str().unwrap()), "{stderr}");
    assert!(stderr.contains("nothing was scored"), "{stderr}");
    assert_eq!(stderr.matches("sds: error").count(), 1, "{stderr}");
    assert!(report.is_none());

    // Beside another file, the crashed route counts as 0 / failed with the benchmark size.
    let (_, report, _) = score(&[
        "--results",
        crashed.to_str().unwrap(),
        "--results",
        route3564.to_str().unwrap(),
        "--expected-routes",
        "2",
        "--allow-missing-telemetry",
    ]);
    let r = report.unwrap();
    assert_eq!(r["summary"]["routes"], 2);
    assert_eq!(
        r["summary"]["driving_score"].as_f64().unwrap(),
        14.008621 / 2.0
    );
}
