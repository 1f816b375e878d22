//! What a researcher's day on real result files found (issue 23), one test per finding: the
//! newest re-run, several runs in one folder, weather names, the step period of partial
//! telemetry, warning noise, route subsets and output nits. The real fixtures
//! (`../../shared/fixtures/b2d`) are used where they show the problem; a test that needs them
//! prints SKIP and passes when they are absent. Re-run folders are built by hand in a temporary
//! folder, with the time stamps of SimLingo's real re-runs.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{json, Value};

use common::sds;

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/fixtures/b2d");

/// The real fixtures folder, or `None` after printing why the test is skipped.
fn fixtures(test: &str) -> Option<PathBuf> {
    let p = PathBuf::from(FIXTURES);
    if p.join("routes/bench2drive220.xml").is_file() {
        Some(p)
    } else {
        eprintln!("SKIP {test}: {FIXTURES} is absent (the real Bench2Drive fixtures)");
        None
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `sds score` with `args`, the JSON report written to `dir/report.json` and read back.
fn score_json(dir: &Path, args: &[&str]) -> (Output, Value) {
    let out = dir.join("report.json");
    let mut a = vec!["score"];
    a.extend_from_slice(args);
    a.extend_from_slice(&["-o", s(&out)]);
    let o = sds(&a);
    let report = fs::read(&out)
        .ok()
        .and_then(|b| serde_json::from_slice(&b).ok())
        .unwrap_or(Value::Null);
    (o, report)
}

fn warnings(report: &Value) -> Vec<String> {
    report["warnings"]
        .as_array()
        .map(|w| w.iter().map(|x| x.as_str().unwrap().to_string()).collect())
        .unwrap_or_default()
}

fn route<'a>(report: &'a Value, id: &str) -> &'a Value {
    report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == id)
        .unwrap_or_else(|| panic!("{id} not in the report"))
}

/// Item 4: the step period is not inferred from telemetry that holds only part of the run, and
/// an inferred period other than 0.05 s is always said.
#[test]
fn step_period_is_not_inferred_from_partial_telemetry() {
    let dir = tempfile::tempdir().unwrap();
    common::demo(dir.path());
    let d = |p: &str| dir.path().join(p);
    let demo_args = |extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = [
            "--results",
            s(&d("results.json")),
            "--telemetry",
            s(&d("telemetry")),
            "--routes",
            s(&d("routes.xml")),
        ]
        .iter()
        .map(|x| x.to_string())
        .collect();
        a.extend(extra.iter().map(|x| x.to_string()));
        a
    };
    // The whole 10 Hz route: inferred as 0.1 s, and said once.
    let args = demo_args(&[]);
    let (o, r) = score_json(
        dir.path(),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let hz10 = "RouteScenario_900008_rep0";
    assert_eq!(route(&r, hz10)["dt"], 0.1);
    let err = stderr(&o);
    let said: Vec<&str> = err
        .lines()
        .filter(|w| w.contains("step period inferred as 0.1 s"))
        .collect();
    assert_eq!(said.len(), 1, "{err}");
    assert!(
        said[0].starts_with("sds: note:") && said[0].contains(hz10),
        "{}",
        said[0]
    );
    assert!(said[0].contains("1 route(s)"), "{}", said[0]);

    // Keep steps 1..=30 and 61..=100 of its 100: 30 missing (over 10 %). Its 10 s of game time
    // over a span of 100 would still fit 0.1 s, but a partial file cannot tell: the setting,
    // with a warning naming the route and --set dt=.
    let folder = fs::read_dir(d("telemetry"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().contains("900008"))
        .unwrap();
    let file = folder.join("metric_info.json");
    let mut frames: serde_json::Map<String, Value> =
        serde_json::from_slice(&fs::read(&file).unwrap()).unwrap();
    frames.retain(|k, _| {
        let step: u64 = k.parse().unwrap();
        !(31..=60).contains(&step)
    });
    fs::write(&file, serde_json::to_vec(&frames).unwrap()).unwrap();
    let (o, r) = score_json(
        dir.path(),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let route10 = route(&r, hz10);
    assert_eq!(
        (route10["dt"].clone(), route10["dt_source"].clone()),
        (json!(0.05), json!("config"))
    );
    let w: Vec<String> = warnings(&r)
        .into_iter()
        .filter(|w| w.starts_with(hz10))
        .collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("step period not inferred")
            && w[0].contains("30 of 100")
            && w[0].contains("setting dt="),
        "{}",
        w[0]
    );
    assert!(!stderr(&o).contains("inferred as 0.1"), "{}", stderr(&o));
}

/// The first `n` records of a real file written as a merge-format file without stored figures
/// (a short debug run).
fn first_records(src: &Path, n: usize, dst: &Path) -> Vec<Value> {
    let doc: Value = serde_json::from_slice(&fs::read(src).unwrap()).unwrap();
    let records: Vec<Value> = doc["_checkpoint"]["records"].as_array().unwrap()[..n].to_vec();
    let out = json!({"_checkpoint": {"records": records}});
    fs::write(dst, serde_json::to_vec(&out).unwrap()).unwrap();
    records
}

/// Item 5: shards of one run, a stored figure rounded for printing, several towns without a
/// map and a long list of missing routes give no noise.
#[test]
fn warnings_are_not_noise() {
    let Some(f) = fixtures("warnings_are_not_noise") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let xml = f.join("routes/bench2drive220.xml");
    // TransFuser++'s 8 per-GPU raw files: each stores the mean over its own 27 or 28 records.
    let (o, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&f.join("tfpp_raw_shards")),
            "--routes",
            s(&xml),
            "--allow-missing-telemetry",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(warnings(&r).is_empty(), "{:?}", warnings(&r));
    let inputs = r["inputs"]["files"].as_array().unwrap();
    assert_eq!(inputs.len(), 8);
    assert!(inputs.iter().all(|i| i["stored"]["denominator"]
        .as_str()
        .unwrap()
        .ends_with(" records")));
    // One shard alone with N = 220 is still a shard (its `progress` planned 28 routes: issue
    // 46 item 3), silent; a whole run's file whose stored figure uses another N still warns.
    let (_, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&f.join("tfpp_raw_shards/eval_bench2drive220_0.json")),
            "--allow-missing-telemetry",
            "--expected-routes",
            "220",
        ],
    );
    assert!(warnings(&r).is_empty(), "{:?}", warnings(&r));
    let (_, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&f.join("carla_garage_tfpp_b2d_traj_merged.json")),
            "--allow-missing-telemetry",
            "--expected-routes",
            "230",
        ],
    );
    assert_eq!(
        warnings(&r)
            .iter()
            .filter(|w| w.contains("stored driving score"))
            .count(),
        1,
        "a single file whose stored figure uses another N still warns"
    );

    // SimLingo stores 88.452; the records give 88.451894818...: equal at the stored precision.
    let (o, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&f.join("simlingo_bench2drive220_targetpoint_checkpoint.json")),
            "--routes",
            s(&xml),
            "--allow-missing-telemetry",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(warnings(&r).is_empty(), "{:?}", warnings(&r));
    let computed = r["inputs"]["files"][0]["computed"]["driving_score"]
        .as_f64()
        .unwrap();
    assert!((computed - 88.452).abs() > 1e-6 && (computed - 88.452).abs() < 5e-4);

    // --maps with 5 of the 12 towns: one line naming the 7 others.
    let maps = f.join("../maps");
    if maps.join("Town01.xodr").is_file() {
        let (o, r) = score_json(
            dir.path(),
            &[
                "--results",
                s(&f.join("carla_garage_tfpp_b2d_traj_merged.json")),
                "--routes",
                s(&xml),
                "--maps",
                s(&maps),
                "--allow-missing-telemetry",
            ],
        );
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let w: Vec<String> = warnings(&r)
            .into_iter()
            .filter(|w| w.contains("no map"))
            .collect();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with("no map for 7 towns: Town03 (11 routes), Town05 (9 routes)"),
            "{}",
            w[0]
        );
        assert!(w[0].contains("their 190 routes fall back"), "{}", w[0]);
        assert_eq!(
            stderr(&o).matches("no map for").count(),
            2,
            "the line and its example"
        );
    } else {
        eprintln!(
            "SKIP (part of warnings_are_not_noise): no CARLA maps in {}",
            maps.display()
        );
    }

    // A 20-route debug run against the 220-route XML: the table note names the first 10 of the
    // 200 routes without a record and a count.
    let debug = dir.path().join("debug20.json");
    first_records(
        &f.join("carla_garage_tfpp_b2d_traj_merged.json"),
        20,
        &debug,
    );
    let o = sds(&[
        "score",
        "--results",
        s(&debug),
        "--routes",
        s(&xml),
        "--allow-missing-telemetry",
        "--format",
        "table",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let table = String::from_utf8(o.stdout).unwrap();
    let note = table
        .lines()
        .find(|l| l.contains("have no record"))
        .expect("the missing-routes note");
    assert!(
        note.contains("200 route(s)") && note.ends_with(" and 190 more"),
        "{note}"
    );
    assert_eq!(note.matches("RouteScenario_").count(), 10, "{note}");
}

/// A raw evaluator file holding `records`.
fn write_raw(path: &Path, records: &[Value]) {
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    let doc = json!({
        "_checkpoint": {"global_record": {}, "progress": [records.len(), records.len()],
                        "records": records},
        "entry_status": "Finished", "eligible": true,
    });
    fs::write(path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
}

/// `record` re-run at `stamp` (`mm_dd_HH_MM_SS`) with `score_route`.
fn rerun(record: &Value, stamp: &str, score_route: f64) -> Value {
    let mut r = record.clone();
    let save = r["save_name"].as_str().unwrap();
    let base = save.rsplitn(6, '_').last().unwrap();
    r["save_name"] = json!(format!("{base}_{stamp}"));
    r["scores"]["score_route"] = json!(score_route);
    r["scores"]["score_penalty"] = json!(1.0);
    r["scores"]["score_composed"] = json!(score_route);
    r
}

fn find_record<'a>(records: &'a [Value], id: &str) -> &'a Value {
    records.iter().find(|r| r["route_id"] == id).unwrap()
}

/// Item 1: `--duplicates newest` keeps the newest re-run by its `save_name` time stamp, not the
/// last file in path order; each kept route says which copy won and why.
#[test]
fn duplicates_newest_keeps_the_latest_rerun() {
    let Some(f) = fixtures("duplicates_newest_keeps_the_latest_rerun") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("simlingo");
    // SimLingo's folder: the main run (route 11715 at 01_27_19_06_00) sorts after three re-runs
    // of 11715 (02_07, 02_10, 02_11), as in the real folder.
    let main = f.join("simlingo_bench2drive220_targetpoint_checkpoint.json");
    fs::create_dir_all(&run).unwrap();
    fs::copy(&main, run.join("simlingo_merged.json")).unwrap();
    let doc: Value = serde_json::from_slice(&fs::read(&main).unwrap()).unwrap();
    let records = doc["_checkpoint"]["records"].as_array().unwrap().clone();
    let r11715 = find_record(&records, "RouteScenario_11715_rep0");
    assert!(r11715["save_name"]
        .as_str()
        .unwrap()
        .ends_with("_01_27_19_06_00"));
    for (name, stamp, score) in [
        ("11715_rerun_a.json", "02_11_10_42_13", 77.0),
        ("11715_rerun_b.json", "02_07_22_15_40", 55.0),
        ("11715_rerun_c.json", "02_10_08_03_51", 66.0),
    ] {
        write_raw(&run.join(name), &[rerun(r11715, stamp, score)]);
    }
    // Route 3380 run twice at the same second: input order decides, with a warning.
    let r3380 = find_record(&records, "RouteScenario_3380_rep0");
    write_raw(
        &run.join("3380_x.json"),
        &[rerun(r3380, "02_12_09_00_00", 40.0)],
    );
    write_raw(
        &run.join("3380_y.json"),
        &[rerun(r3380, "02_12_09_00_00", 41.0)],
    );
    let xml = f.join("routes/bench2drive220.xml");
    let base = [
        "--results",
        s(&run),
        "--routes",
        s(&xml),
        "--allow-missing-telemetry",
    ];

    // `last` keeps the main run's 01_27 copy (it sorts last): the reported bug, still so.
    let mut args = base.to_vec();
    args.extend(["--duplicates", "last"]);
    let (o, r) = score_json(dir.path(), &args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let last = route(&r, "RouteScenario_11715_rep0");
    assert_eq!(
        last["score_route"].as_f64(),
        r11715["scores"]["score_route"].as_f64()
    );
    assert_eq!(last["kept"]["why"], "last of 4 copies in input order");

    // `newest` keeps the 02_11 re-run.
    let mut args = base.to_vec();
    args.extend(["--duplicates", "newest"]);
    let (o, r) = score_json(dir.path(), &args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let kept = route(&r, "RouteScenario_11715_rep0");
    assert_eq!(kept["score_route"], 77.0);
    assert!(kept["source"]["file"]
        .as_str()
        .unwrap()
        .ends_with("11715_rerun_a.json"));
    assert_eq!(kept["kept"]["policy"], "newest");
    assert_eq!(kept["kept"]["copies"], 4);
    assert_eq!(kept["kept"]["stamp"], "02_11_10_42_13");
    let why = kept["kept"]["why"].as_str().unwrap();
    assert!(
        why.starts_with("newest save_name time stamp 02_11_10_42_13 of 4 copies")
            && why.contains("01_27_19_06_00")
            && why.contains("02_07_22_15_40"),
        "{why}"
    );
    let dropped: Vec<&Value> = r["dropped"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["route_id"] == "RouteScenario_11715_rep0")
        .collect();
    assert_eq!(dropped.len(), 3);
    // The tie: the last in input order (3380_y), a warning naming the route.
    let tie = route(&r, "RouteScenario_3380_rep0");
    assert_eq!(tie["score_route"], 41.0);
    assert!(tie["kept"]["why"]
        .as_str()
        .unwrap()
        .contains("2 of 3 copies share"));
    let w: Vec<String> = warnings(&r)
        .into_iter()
        .filter(|w| w.starts_with("duplicates: newest: 1 route id(s) kept by input order"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", warnings(&r));
    assert!(w[0].contains("RouteScenario_3380_rep0"), "{}", w[0]);
    // A route with one copy has no `kept`; the run's 220 routes are all there once.
    assert!(route(&r, "RouteScenario_1711_rep0").get("kept").is_none());
    assert_eq!(r["routes"].as_array().unwrap().len(), 220);
    assert!(warnings(&r)
        .iter()
        .any(|w| w.starts_with("duplicates: newest: 5 copies of 2 route ids left out")));
}

/// Item 2: a folder holding several whole runs (three models' files of all 220 routes, and a
/// re-run) is refused in a few lines per file, pointing to scoring them apart or `sds compare`,
/// not to `--duplicates`.
#[test]
fn several_whole_runs_in_one_folder_are_said_per_file() {
    let Some(f) = fixtures("several_whole_runs_in_one_folder_are_said_per_file") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("pending_process");
    for (sub, file) in [
        (
            "targetpoint",
            "simlingo_bench2drive220_targetpoint_checkpoint.json",
        ),
        ("tfpp", "carla_garage_tfpp_b2d_traj_merged.json"),
        ("pdm_lite", "carla_garage_pdm_lite_b2d_traj_merged.json"),
    ] {
        fs::create_dir_all(run.join(sub)).unwrap();
        fs::copy(f.join(file), run.join(sub).join(file)).unwrap();
    }
    let doc: Value = serde_json::from_slice(
        &fs::read(f.join("simlingo_bench2drive220_targetpoint_checkpoint.json")).unwrap(),
    )
    .unwrap();
    let records = doc["_checkpoint"]["records"].as_array().unwrap();
    let r = find_record(records, "RouteScenario_11715_rep0");
    write_raw(
        &run.join("reruns/11715.json"),
        &[rerun(r, "02_07_22_15_40", 50.0)],
    );
    let o = sds(&["score", "--results", s(&run), "--allow-missing-telemetry"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.starts_with("sds: error: 3 files each hold all 220 routes: several runs?"),
        "{err}"
    );
    assert!(
        err.contains("compare them side by side") && !err.contains("duplicates = newest"),
        "{err}"
    );
    assert_eq!(err.matches(": 220 of 220 route ids").count(), 3, "{err}");
    assert!(
        err.contains("1 route id(s) also have copies in other files"),
        "{err}"
    );
    assert!(
        err.lines().count() <= 8,
        "a few lines, not one per route:\n{err}"
    );
    // The real case of a merged file beside its own shards keeps the per-id list (one whole
    // file): the advice there is --duplicates.
    let o = sds(&[
        "score",
        "--results",
        s(&f.join("carla_garage_tfpp_b2d_traj_merged.json")),
        "--results",
        s(&f.join("tfpp_raw_shards")),
        "--allow-missing-telemetry",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("duplicates = newest|first|last"));
}

/// Item 3: `--weathers weather.xml` names each of Bench2Drive's weathers after the CARLA preset
/// it is (every parameter the file gives), else by its id; group rows list their ids.
#[test]
fn weathers_are_named_after_carla_presets() {
    let Some(f) = fixtures("weathers_are_named_after_carla_presets") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let weather = f.join("routes/weather.xml");
    let results = f.join("carla_garage_tfpp_b2d_traj_merged.json");
    let (o, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&results),
            "--allow-missing-telemetry",
            "--group-by",
            "weather",
            "--weathers",
            s(&weather),
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let rows = r["groups"]["rows"].as_array().unwrap();
    let row = |label: &str| rows.iter().find(|g| g["label"] == label);
    // The 10 cases of weather.xml that are CARLA presets, with their ids.
    let presets = [
        ("ClearSunset", "1"),
        ("SoftRainNoon", "2"),
        ("MidRainyNoon", "3"),
        ("ClearNoon", "7"),
        ("HardRainNoon", "8"),
        ("ClearNight", "22"),
        ("MidRainyNight", "23"),
        ("HardRainNight", "25"),
    ];
    let ids_in_run: std::collections::BTreeSet<String> = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|x| x["weather_id"].as_str().map(String::from))
        .collect();
    let mut named = 0;
    for (name, id) in presets {
        if !ids_in_run.contains(id) {
            continue;
        }
        let g = row(name).unwrap_or_else(|| panic!("{name} (id {id}) is a group: {rows:?}"));
        assert_eq!(g["keys"], json!([id]), "{name}");
        named += 1;
    }
    assert!(named >= 5, "the run covers most preset ids");
    // Sun at 15° is a Sunset, never a Noon; altitude 0 (id 10) and 90 (id 0) are no preset.
    for id in ["0", "10", "26"] {
        if ids_in_run.contains(id) {
            let g = row(id).unwrap_or_else(|| panic!("id {id} keeps its id"));
            assert!(g.get("keys").is_none());
        }
    }
    let carla_names = [
        "ClearNoon",
        "ClearSunset",
        "ClearNight",
        "CloudyNoon",
        "CloudySunset",
        "CloudyNight",
        "WetNoon",
        "WetSunset",
        "WetNight",
        "WetCloudyNoon",
        "WetCloudySunset",
        "WetCloudyNight",
        "SoftRainNoon",
        "SoftRainSunset",
        "SoftRainNight",
        "MidRainyNoon",
        "MidRainSunset",
        "MidRainyNight",
        "HardRainNoon",
        "HardRainSunset",
        "HardRainNight",
        "DustStorm",
    ];
    for g in rows {
        let label = g["label"].as_str().unwrap();
        assert!(
            carla_names.contains(&label) || ids_in_run.contains(label),
            "{label} is a CARLA preset or an id"
        );
    }
    // Every route once.
    let total: u64 = rows.iter().map(|g| g["routes"].as_u64().unwrap()).sum();
    assert_eq!(total, 220);
    // The table's row lists the ids.
    let o = sds(&[
        "score",
        "--results",
        s(&results),
        "--allow-missing-telemetry",
        "--format",
        "table",
        "--group-by",
        "weather",
        "--weathers",
        s(&weather),
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.lines().any(|l| l.starts_with("ClearSunset (1) ")),
        "{text}"
    );
}

/// Item 6: `--route-subset found` scores a debug run over the route XML's routes that have a
/// record (abilities and groups included), and says so in the report and the tables.
#[test]
fn route_subset_found_scores_a_debug_run_over_its_routes() {
    let Some(f) = fixtures("route_subset_found_scores_a_debug_run_over_its_routes") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let debug = dir.path().join("debug20.json");
    let records = first_records(
        &f.join("carla_garage_tfpp_b2d_traj_merged.json"),
        20,
        &debug,
    );
    let xml = f.join("routes/bench2drive220.xml");
    let composed: f64 = records
        .iter()
        .map(|r| r["scores"]["score_composed"].as_f64().unwrap())
        .sum();
    let base = [
        "--results",
        s(&debug),
        "--routes",
        s(&xml),
        "--allow-missing-telemetry",
    ];

    // Over the whole XML: 200 missing routes, DS over 220.
    let (_, all) = score_json(dir.path(), &base);
    let ds_all = all["summary"]["driving_score"].as_f64().unwrap();
    assert!((ds_all - composed / 220.0).abs() < 1e-9);
    assert!(all.get("route_subset").is_none());

    let mut args = base.to_vec();
    args.extend(["--route-subset", "found", "--group-by", "scenario"]);
    let (o, r) = score_json(dir.path(), &args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        r["route_subset"],
        json!({"subset": "found", "routes": 20, "of": 220})
    );
    assert_eq!(r["config"]["route_subset"], "found");
    assert_eq!(
        r["routes"].as_array().unwrap().len(),
        20,
        "no missing route"
    );
    assert_eq!(r["summary"]["routes"], 20);
    let ds = r["summary"]["driving_score"].as_f64().unwrap();
    assert!((ds - composed / 20.0).abs() < 1e-9, "{ds}");
    // Abilities over the 20 routes only, none missing.
    let b = &r["summary"]["bench2drive"];
    assert!(b["ability_missing"].as_array().unwrap().is_empty(), "{b}");
    let counted: u64 = b["ability_counts"]
        .as_object()
        .unwrap()
        .values()
        .map(|c| c["routes"].as_u64().unwrap())
        .sum();
    assert!(counted > 0 && counted <= 20 * 2, "{b}");
    // Groups: the 20 routes, the combined row over N = 20.
    let rows = r["groups"]["rows"].as_array().unwrap();
    let grouped: u64 = rows.iter().map(|g| g["routes"].as_u64().unwrap()).sum();
    assert_eq!(grouped, 20);
    assert_eq!(r["groups"]["combined"]["routes"], 20);
    // The same through --set; and every table says which route set it is.
    let mut args = base.to_vec();
    args.extend(["--set", "route_subset=found", "--format", "table"]);
    let o = sds(&[&["score"], &args[..]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let note = "route set: the 20 of the route XML's 220 routes that have a record";
    assert_eq!(
        text.matches(note).count(),
        3,
        "Bench2Drive, Table 1 and 2:\n{text}"
    );
    assert!(
        !text.contains("have no record (not in the ability rates)"),
        "{text}"
    );
}

fn stdout_of(args: &[&str]) -> String {
    let o = sds(args);
    assert!(o.status.code().is_some_and(|c| c == 0), "{}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

/// Item 7: the HTML page and the other renderings of a real run: each warning once, file names
/// in the title, no status line, `--` for undefined LaTeX cells, CSV floats as short decimals,
/// no telemetry-problem count under --allow-missing-telemetry, grammar, and why Comfortness is
/// undefined. (The routes table's width is checked in a browser: scripts/html-report-test.sh.)
#[test]
fn output_nits_on_a_real_run() {
    let Some(f) = fixtures("output_nits_on_a_real_run") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // PDM-Lite: its hand-edited record gives route warnings.
    let results = f.join("carla_garage_pdm_lite_b2d_traj_merged.json");
    let xml = f.join("routes/bench2drive220.xml");
    let base = [
        "score",
        "--results",
        s(&results),
        "--routes",
        s(&xml),
        "--allow-missing-telemetry",
    ];
    let html = stdout_of(&[&base[..], &["--format", "html"]].concat());
    assert!(html.contains("<title>SDS report: carla_garage_pdm_lite_b2d_traj_merged.json</title>"));
    assert!(html.contains("<h1>SafeDriving Score: carla_garage_pdm_lite_b2d_traj_merged.json</h1>"));
    assert!(
        !html.contains(&format!("{}", f.display())),
        "no path of the inputs in the page"
    );
    assert!(
        html.contains("<p id=\"status\" hidden>"),
        "no debug line under the title"
    );

    // Each warning once: the demo with a route warning (part of its telemetry gone).
    let demo = tempfile::tempdir().unwrap();
    common::demo(demo.path());
    let folder = fs::read_dir(demo.path().join("telemetry"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy().contains("900008"))
        .unwrap();
    let file = folder.join("metric_info.json");
    let mut frames: serde_json::Map<String, Value> =
        serde_json::from_slice(&fs::read(&file).unwrap()).unwrap();
    frames.retain(|k, _| !(31..=60).contains(&k.parse::<u64>().unwrap()));
    fs::write(&file, serde_json::to_vec(&frames).unwrap()).unwrap();
    let d = |p: &str| demo.path().join(p).to_str().unwrap().to_string();
    let demo_args = [
        "--results".to_string(),
        d("results.json"),
        "--telemetry".into(),
        d("telemetry"),
    ];
    let demo_args: Vec<&str> = demo_args.iter().map(String::as_str).collect();
    let (_, r) = score_json(dir.path(), &demo_args);
    let json_warnings = warnings(&r);
    assert!(
        json_warnings
            .iter()
            .any(|w| w.starts_with("RouteScenario_900008_rep0: ")),
        "{json_warnings:?}"
    );
    let html = stdout_of(&[&["score"], &demo_args[..], &["--format", "html"]].concat());
    // The run's list holds each warning of the JSON once (a route's drill-down repeats its own).
    let list = &html[html.find("<ul id=\"warnings\">").unwrap()..];
    let list = &list[..list.find("</ul>").unwrap()];
    assert_eq!(
        list.matches("<li class=\"warn\">").count(),
        json_warnings.len(),
        "each once"
    );
    for w in &json_warnings {
        let escaped = monitor_host::report::html::escape(w);
        assert_eq!(list.matches(escaped.as_str()).count(), 1, "{w}");
    }
    assert!(html.contains(&format!("Warnings ({})", json_warnings.len())));

    // LaTeX: undefined cells are `--`, never a bare `-`.
    let tex = stdout_of(&[&base[..], &["--format", "latex"]].concat());
    let cells: Vec<&str> = tex
        .lines()
        .filter(|l| l.ends_with("\\\\"))
        .flat_map(|l| l.trim_end_matches("\\\\").split(" & "))
        .map(str::trim)
        .collect();
    assert!(cells.contains(&"--"), "{tex}");
    assert!(!cells.contains(&"-"), "{tex}");

    // Tables: no telemetry-problem count under --allow-missing-telemetry; why Comfortness is -.
    let table = stdout_of(&[&base[..], &["--format", "table"]].concat());
    assert!(!table.contains("telemetry problems"), "{table}");
    assert!(
        table.contains("Comfortness - : no route has telemetry"),
        "{table}"
    );
    assert!(table.contains("(telemetry: the folder holding"), "{table}");

    // CSV: UniAD-Base's route 4669 has DS_safe 50.15 x 0.6: 30.09, not 30.089999999999996.
    let uniad = f.join("b2dzoo_UniAD-Base_merged.json");
    let csv = stdout_of(&[
        "score",
        "--results",
        s(&uniad),
        "--allow-missing-telemetry",
        "--format",
        "csv",
    ]);
    let line = csv
        .lines()
        .find(|l| l.starts_with("RouteScenario_4669_rep0,"))
        .unwrap();
    assert!(line.contains(",30.09,"), "{line}");
    assert!(
        !csv.contains("30.089999999999996") && !csv.contains("99999999"),
        "{line}"
    );

    // "1 copy of 1 route id": the merged file and one record of it again.
    let doc: Value = serde_json::from_slice(&fs::read(&results).unwrap()).unwrap();
    let one = &doc["_checkpoint"]["records"][0];
    let again = dir.path().join("again.json");
    write_raw(&again, std::slice::from_ref(one));
    let (o, r) = score_json(
        dir.path(),
        &[
            "--results",
            s(&results),
            "--results",
            s(&again),
            "--duplicates",
            "last",
            "--allow-missing-telemetry",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        warnings(&r)
            .iter()
            .any(|w| w.starts_with("duplicates: last: 1 copy of 1 route id left out")),
        "{:?}",
        warnings(&r)
    );
}
