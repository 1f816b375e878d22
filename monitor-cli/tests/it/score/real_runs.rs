//! Real runs as people keep them (docs/SCORE.md §2.2, docs/SCORE.md §14.1, docs/SCORE.md §13), end to end on the real
//! Bench2Drive files in `../shared/fixtures/b2d`: several inputs and duplicates, the route set
//! with missing and foreign routes, N, the stored-figure check, the telemetry messages, and
//! label files. Skips, with a printed reason, when the fixtures are absent.

use std::collections::BTreeSet;
use std::fs;
use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

/// `../shared/fixtures/b2d`, or `None` (the skip said).
fn fixtures() -> Option<PathBuf> {
    crate::common::b2d_fixtures(&[])
}

/// `sds score ARGS -o report.json`: (exit code, report, stderr).
fn score(args: &[&dyn AsRef<std::ffi::OsStr>]) -> (i32, Option<Value>, String) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report.json");
    let o = Command::new(env!("CARGO_BIN_EXE_sds"))
        .arg("score")
        .args(args)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let report = fs::read(&out)
        .ok()
        .map(|b| serde_json::from_slice(&b).unwrap());
    (
        o.status.code().unwrap_or(-1),
        report,
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn ids(report: &Value, state: &str) -> Vec<String> {
    report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] == state)
        .map(|r| r["route_id"].as_str().unwrap().to_string())
        .collect()
}

const TFPP: &str = "carla_garage_tfpp_b2d_traj_merged.json";
const SHARDS: &str = "tfpp_raw_shards";
const XML: &str = "routes/bench2drive220.xml";

#[test]
fn merged_file_beside_its_shards_is_refused_then_deduplicated() {
    let Some(d) = fixtures() else { return };
    let (merged, shards) = (d.join(TFPP), d.join(SHARDS));
    let (code, report, err) = score(&[&"--results", &merged, &"--results", &shards]);
    assert_eq!(code, 2, "{err}");
    assert!(report.is_none(), "nothing is scored");
    assert!(
        err.contains("220 route id(s) appear more than once"),
        "{err}"
    );
    // Every duplicated id on its own line, with both sources (file and record index).
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.trim_start().starts_with("RouteScenario_"))
        .collect();
    let named: BTreeSet<&str> = lines
        .iter()
        .map(|l| l.trim_start().split(':').next().unwrap())
        .collect();
    assert_eq!((lines.len(), named.len()), (220, 220), "{err}");
    let m = merged.display().to_string();
    assert!(lines
        .iter()
        .all(|l| l.contains(&format!("{m} record ")) && l.contains("eval_bench2drive220_")));
    assert!(err.contains(&format!(
        "RouteScenario_4937_rep0: {m} record 0, {} record 24",
        shards.join("eval_bench2drive220_3.json").display()
    )));
    assert!(err.contains("duplicates = newest|first|last"), "{err}");
    assert!(err.trim_end().ends_with("(--duplicates)"), "{err}");

    // `last`: the shards' copies are kept; Bench2Drive's figures over 220 routes.
    for how in [["--duplicates", "last"], ["--set", "duplicates=last"]] {
        let (code, report, err) = score(&[
            &"--results",
            &merged,
            &"--results",
            &shards,
            &how[0],
            &how[1],
            &"--allow-missing-telemetry",
        ]);
        assert_eq!(code, 0, "{err}");
        let r = report.unwrap();
        let s = &r["summary"];
        assert_eq!(s["routes"], 220);
        assert!((f(&s["driving_score"]) - 84.20590742727273).abs() < 1e-9);
        assert!((f(&s["success_rate"]) - 67.27272727272727).abs() < 1e-9);
        let dropped = r["dropped"].as_array().unwrap();
        assert_eq!(dropped.len(), 220);
        assert!(dropped.iter().all(|x| x["source"]["file"] == m.as_str()
            && x["kept"]["file"]
                .as_str()
                .unwrap()
                .contains("eval_bench2drive220_")));
        assert!(r["routes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|x| x["source"]["file"] != m.as_str()));
    }
    // `first` keeps the merged file's copies; `all` scores both with a warning (N = 440).
    let (_, report, _) = score(&[
        &"--results",
        &merged,
        &"--results",
        &shards,
        &"--duplicates",
        &"first",
        &"--allow-missing-telemetry",
    ]);
    let r = report.unwrap();
    assert!(r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .all(|x| x["source"]["file"] == m.as_str()));
    let (_, report, err) = score(&[
        &"--results",
        &merged,
        &"--results",
        &merged,
        &"--duplicates",
        &"all",
        &"--allow-missing-telemetry",
    ]);
    let r = report.unwrap();
    assert_eq!(r["summary"]["routes"], 440);
    assert!((f(&r["summary"]["driving_score"]) - 84.20590742727273).abs() < 1e-9);
    assert!(
        err.contains("220 route id(s) scored more than once"),
        "{err}"
    );
}

#[test]
fn lead_per_route_folder_with_the_route_set() {
    let Some(d) = fixtures() else { return };
    let (lead, xml) = (d.join("lead_tfv6_per_route"), d.join(XML));
    let (code, report, err) = score(&[
        &"--results",
        &lead,
        &"--routes",
        &xml,
        &"--allow-missing-telemetry",
    ]);
    assert_eq!(code, 0, "{err}");
    let r = report.unwrap();
    let s = &r["summary"];
    assert_eq!(
        (s["routes"].clone(), s["routes_found"].clone()),
        (220.into(), 211.into())
    );
    assert_eq!(
        (s["missing"].clone(), s["foreign"].clone()),
        (9.into(), 0.into())
    );
    // Bench2Drive's rule (/220); a mean over the 211 finished routes would read 89.38.
    assert!(
        (f(&s["driving_score"]) - 85.7246475090909).abs() < 1e-9,
        "{s}"
    );
    let crashed: Vec<String> = [
        24759, 25378, 25381, 25857, 25955, 26393, 26956, 26966, 28048,
    ]
    .iter()
    .map(|id| format!("RouteScenario_{id}_rep0"))
    .collect();
    assert_eq!(ids(&r, "missing"), crashed);
    let m = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == crashed[0].as_str())
        .unwrap();
    assert_eq!(
        (
            m["success"].clone(),
            m["score_composed"].clone(),
            m["ds_safe"].clone()
        ),
        (false.into(), 0.0.into(), 0.0.into())
    );
    assert!(m["comfort"]["score"].is_null() && m["source"].is_null());
    assert!(
        m["town"].is_string() && m["scenario_type"].is_string(),
        "from the XML: {m}"
    );
    // Every crashed file is still named in the warnings.
    assert_eq!(
        r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w
                .as_str()
                .unwrap()
                .contains("crashed before any route finished"))
            .count(),
        9
    );
    // Per-route sources: the argument joined with the path inside the folder.
    let first = &r["routes"][0]["source"];
    assert_eq!(
        first["file"],
        lead.join("10857/checkpoint_endpoint.json")
            .display()
            .to_string()
    );
    assert_eq!(first["index"], 0);

    // N below the routes counted is refused.
    let (code, _, err) = score(&[
        &"--results",
        &lead,
        &"--routes",
        &xml,
        &"--expected-routes",
        &"200",
        &"--allow-missing-telemetry",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("N = 200 is smaller than the 220 routes counted"),
        "{err}"
    );
}

#[test]
fn no_telemetry_is_said_once_and_a_mistyped_root_is_an_error() {
    let Some(d) = fixtures() else { return };
    let lead = d.join("lead_tfv6_per_route");
    let (code, report, err) = score(&[&"--results", &lead]);
    assert_eq!(code, 3, "{err}");
    assert_eq!(err.matches("no route has telemetry").count(), 1, "{err}");
    assert!(
        err.contains("(telemetry)") && err.contains("allow_missing_telemetry"),
        "{err}"
    );
    assert!(!err.contains("RouteScenario_"), "no line per route:\n{err}");
    let r = report.unwrap();
    assert_eq!(ids(&r, "invalid").len(), 211);
    assert!(r["routes"][0]["reason"]
        .as_str()
        .unwrap()
        .starts_with("telemetry missing: no telemetry root given"));

    let typo = d.join("telemetyr");
    let (code, report, err) = score(&[&"--results", &lead, &"--telemetry", &typo]);
    assert_eq!(code, 2, "{err}");
    assert!(report.is_none());
    assert!(
        err.contains(&format!("telemetry {}: no such folder", typo.display()))
            && err.trim_end().ends_with("(--telemetry)"),
        "{err}"
    );
}

#[test]
fn missing_telemetry_names_the_folder_tried_and_the_closest_one() {
    let Some(d) = fixtures() else { return };
    let file = d.join("pdmlite_route3564_endpoint_tickruntime_mesh_collisions.json");
    let tmp = tempfile::tempdir().unwrap();
    let other = "RouteScenario_3564_rep0_Town13_InvadingTurn_1_23_07_01_10_00_00";
    fs::create_dir_all(tmp.path().join(other)).unwrap();
    fs::create_dir_all(tmp.path().join("RouteScenario_1711_rep0_Town12_X")).unwrap();
    let (code, report, err) = score(&[&"--results", &file, &"--telemetry", &tmp.path()]);
    assert_eq!(code, 3, "{err}");
    let reason = report.unwrap()["routes"][0]["reason"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        reason
            .contains("no folder RouteScenario_3564_rep0_Town13_InvadingTurn_1_23_06_17_06_49_04")
            && reason.contains(&tmp.path().display().to_string())
            && reason.contains(&format!(
                "the closest folder for RouteScenario_3564_rep0 is {other}"
            )),
        "{reason}"
    );
    assert!(err.contains(other), "{err}");
}

#[test]
fn stored_figures_beside_the_computed_ones() {
    let Some(d) = fixtures() else { return };
    let (tcp, xml) = (d.join("b2dzoo_TCP-only-traj_merged.json"), d.join(XML));
    // With the route set: N = 220, the 10 routes without a record are missing, and DS equals
    // the stored figure.
    let (code, report, err) = score(&[
        &"--results",
        &tcp,
        &"--routes",
        &xml,
        &"--allow-missing-telemetry",
    ]);
    assert_eq!(code, 0, "{err}");
    let r = report.unwrap();
    let s = &r["summary"];
    assert_eq!(
        (s["routes"].clone(), s["missing"].clone()),
        (220.into(), 10.into())
    );
    assert!((f(&s["driving_score"]) - 59.89672075000001).abs() < 1e-9);
    assert!((f(&s["success_rate"]) - 30.0).abs() < 1e-9);
    let input = &r["inputs"]["files"][0];
    assert_eq!(input["records"], 210);
    assert_eq!(input["stored"]["from"], "merged");
    assert_eq!(input["stored"]["driving_score"], 59.89672075000001);
    assert_eq!(input["stored"]["eval_num"], 210);
    assert_eq!(input["stored"]["denominator"], "N = 220");
    assert!((f(&input["computed"]["driving_score"]) - 59.89672075000001).abs() < 1e-9);
    assert_eq!(input["computed"]["n"], 220);
    assert!(!err.contains("stored driving score"), "{err}");

    // Without it: N = the 210 routes kept, and a warning says which denominator each used.
    let (_, report, err) = score(&[&"--results", &tcp, &"--allow-missing-telemetry"]);
    let r = report.unwrap();
    assert!((f(&r["summary"]["driving_score"]) - 62.74894554761902).abs() < 1e-9);
    assert!(
        err.contains("stored driving score 59.89672075000001 (a mean over 220 (Bench2Drive's benchmark size))")
            && err.contains("divided by N = 210"),
        "{err}"
    );
    assert!(r["warnings"].to_string().contains("stored driving score"));

    // VAD: 213 records while eval num says 214; DS over 220 as stored.
    let vad = d.join("b2dzoo_VAD_merged.json");
    let (_, report, err) = score(&[
        &"--results",
        &vad,
        &"--routes",
        &xml,
        &"--allow-missing-telemetry",
    ]);
    let r = report.unwrap();
    assert!(
        err.contains("eval num 214 but 213 records in the file"),
        "{err}"
    );
    assert_eq!(r["summary"]["missing"], 7);
    assert!((f(&r["summary"]["driving_score"]) - 42.35073638636364).abs() < 1e-9);
    assert_eq!(r["inputs"]["files"][0]["stored"]["eval_num"], 214);
}

#[test]
fn routes_outside_the_set_are_foreign() {
    let Some(d) = fixtures() else { return };
    let full = fs::read_to_string(d.join(XML)).unwrap();
    // A route XML of the first two routes of the tfpp run.
    let mut xml = String::from("<routes>\n");
    for id in ["4937", "4683"] {
        let start = full.find(&format!("<route id=\"{id}\"")).unwrap();
        let end = start + full[start..].find("</route>").unwrap() + "</route>".len();
        xml.push_str(&full[start..end]);
        xml.push('\n');
    }
    xml.push_str("</routes>\n");
    let tmp = tempfile::tempdir().unwrap();
    let small = tmp.path().join("two.xml");
    fs::write(&small, xml).unwrap();
    let (code, report, err) = score(&[
        &"--results",
        &d.join(TFPP),
        &"--routes",
        &small,
        &"--allow-missing-telemetry",
    ]);
    assert_eq!(code, 0, "{err}");
    let r = report.unwrap();
    let s = &r["summary"];
    assert_eq!(
        (s["routes"].clone(), s["foreign"].clone()),
        (2.into(), 218.into())
    );
    // (100.0 + 30.318) / 2; SR: the first is a success.
    assert!((f(&s["driving_score"]) - 65.159).abs() < 1e-9, "{s}");
    assert_eq!(ids(&r, "foreign").len(), 218);
    assert_eq!(
        err.matches("(a foreign route)").count(),
        218,
        "one warning per foreign route"
    );
}

#[test]
fn label_files_json_lists_csv_and_weather_xml() {
    let Some(d) = fixtures() else { return };
    let tfpp = d.join(TFPP);
    let tmp = tempfile::tempdir().unwrap();
    // weather.xml: every weather id of the run has a label.
    let (code, report, err) = score(&[
        &"--results",
        &tfpp,
        &"--allow-missing-telemetry",
        &"--weathers",
        &d.join("routes/weather.xml"),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("no label"), "{err}");
    assert!(report.is_some());
    let table = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(["score", "--allow-missing-telemetry", "--format", "table"])
        .args(["--group-by", "weather", "--results"])
        .arg(&tfpp)
        .arg("--weathers")
        .arg(d.join("routes/weather.xml"))
        .output()
        .unwrap();
    let text = String::from_utf8(table.stdout).unwrap();
    // CARLA's ClearNoon is Bench2Drive's weather id 7 (the row lists its ids).
    assert!(
        text.lines().any(|l| l.starts_with("ClearNoon (7) ")),
        "{text}"
    );
    // The Table 2-style breakdown: its title, header and rule, then one line per group up to
    // the rule above the Combined row.
    let rows: usize = text
        .lines()
        .skip_while(|l| !l.starts_with("Safe2Drive Table 2"))
        .skip(3)
        .take_while(|l| !l.starts_with('-'))
        .map(|l| {
            // The routes column: the first number after the label and its ids, `(1, 7)`.
            l.split_whitespace()
                .skip(1)
                .find_map(|t| t.parse::<usize>().ok())
                .unwrap()
        })
        .sum();
    assert_eq!(rows, 220, "each route once: {text}");

    // JSON with a list of labels: the route counts in both groups; keys missing: a warning.
    let fam = tmp.path().join("families.json");
    fs::write(
        &fam,
        r#"{"ParkingCutIn": ["cut-ins", "parking"], "StaticCutIn": "cut-ins"}"#,
    )
    .unwrap();
    let table = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(["score", "--allow-missing-telemetry", "--format", "table"])
        .args(["--group-by", "family", "--results"])
        .arg(&tfpp)
        .arg("--families")
        .arg(&fam)
        .output()
        .unwrap();
    let text = String::from_utf8(table.stdout).unwrap();
    let err = String::from_utf8(table.stderr).unwrap();
    let routes_of = |label: &str| {
        text.lines()
            .find(|l| l.split_whitespace().next() == Some(label))
            .map(|l| l.split_whitespace().nth(1).unwrap().to_string())
    };
    assert_eq!(routes_of("cut-ins").as_deref(), Some("10"), "{text}");
    assert_eq!(routes_of("parking").as_deref(), Some("5"), "{text}");
    assert!(
        err.contains("no label for 42 key(s)") && err.contains("Accident"),
        "{err}"
    );

    // CSV lines; a file that matches no route is an error naming it.
    let csv = tmp.path().join("families.csv");
    fs::write(&csv, "NoSuchScenario,x\nOther,y\n").unwrap();
    let (code, report, err) = score(&[
        &"--results",
        &tfpp,
        &"--allow-missing-telemetry",
        &"--families",
        &csv,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(report.is_none());
    assert!(
        err.contains(&csv.display().to_string()) && err.contains("none of its 2 key(s)"),
        "{err}"
    );
}

#[test]
fn csv_has_state_success_source_and_json_floats() {
    let Some(d) = fixtures() else { return };
    let lead = d.join("lead_tfv6_per_route");
    let o = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(["score", "--allow-missing-telemetry", "--format", "csv"])
        .arg("--results")
        .arg(&lead)
        .arg("--routes")
        .arg(d.join(XML))
        .output()
        .unwrap();
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 220);
    let first = &rows[0];
    assert_eq!(first[col("state")], "scored");
    assert_eq!(
        first[col("source")],
        format!(
            "{}#0",
            lead.join("10857/checkpoint_endpoint.json").display()
        )
    );
    assert!(["true", "false"].contains(&first[col("success")]));
    // Floats as JSON prints them: 100.0, not 100.
    assert!(rows.iter().any(|r| r[col("score_route")] == "100.0"));
    assert_eq!(
        rows.iter().filter(|r| r[col("state")] == "missing").count(),
        9
    );
}

#[test]
fn every_config_name_is_settable_and_penalty_flavour_reaches_leaderboard20() {
    let Some(d) = fixtures() else { return };
    let tfpp = d.join(TFPP);
    let (_, report, _) = score(&[&"--results", &tfpp, &"--allow-missing-telemetry"]);
    let r = report.unwrap();
    assert_eq!(
        r["summary"]["penalty_mismatches"].as_array().unwrap().len(),
        0
    );
    // Every name of the config block, set back to its own value, is accepted.
    let mut sets = Vec::new();
    for (k, v) in r["config"].as_object().unwrap() {
        match v.as_object() {
            Some(group) => sets.extend(group.iter().map(|(g, x)| format!("{k}.{g}={}", text(x)))),
            None => sets.push(format!("{k}={}", text(v))),
        }
    }
    // Every name but `provenance.host`, which changes no figure and is not in `config`.
    assert_eq!(sets.len(), monitor_host::Settings::NAMES.len() - 1);
    let mut args: Vec<&dyn AsRef<std::ffi::OsStr>> =
        vec![&"--results", &tfpp, &"--allow-missing-telemetry"];
    for s in &sets {
        args.push(&"--set");
        args.push(s);
    }
    let (code, report, err) = score(&args);
    assert_eq!(code, 0, "{err}");
    let mut config = report.unwrap()["config"].clone();
    config["dt_inference"] = true.into(); // `dt=` turns it off, by design
    assert_eq!(config, r["config"]);

    // The Leaderboard-2.0 flavour charges min-speed infractions in the re-check.
    let (code, report, err) = score(&[
        &"--results",
        &tfpp,
        &"--allow-missing-telemetry",
        &"--set",
        &"penalty_flavour=leaderboard20",
    ]);
    assert_eq!(code, 0, "{err}");
    let r = report.unwrap();
    assert_eq!(r["config"]["penalty_flavour"], "leaderboard20");
    assert!(r["summary"]["penalty_mismatches"].as_array().unwrap().len() > 100);

    // An unknown name lists the known ones.
    let (code, _, err) = score(&[&"--results", &tfpp, &"--set", &"penalty_flavor=x"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown setting penalty_flavor") && err.contains("penalty_flavour"));
}

fn text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => "null".into(),
        // A list setting (`protocols`) is written as ids joined by commas, or `none`.
        Value::Array(a) if a.is_empty() => "none".into(),
        Value::Array(a) => a.iter().map(text).collect::<Vec<_>>().join(","),
        v => v.to_string(),
    }
}
