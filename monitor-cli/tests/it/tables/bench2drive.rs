//! Everything a Bench2Drive paper reports, on real result files (`../shared/fixtures/b2d`):
//! Bench2Drive's own ability and efficiency outputs reproduced exactly, the per-weather table
//! against counts worked out here from the raw JSON, and `sds compare` of three seeds against
//! mean ± std worked out by hand. Skips, with a printed reason, when the fixtures are absent.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

use crate::common::{path_str as s, sds};

/// `../shared/fixtures` with the Bench2Drive route file, or `None` (the skip said).
fn fixtures() -> Option<PathBuf> {
    crate::common::shared_fixtures("b2d/routes/bench2drive220.xml")
}

fn json_of(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "not JSON ({e}); stderr:\n{}",
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

fn read(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// Route id -> (town, scenario type) from the route XML, read here with plain string search
/// (independently of the tool's XML reader).
fn xml_routes(xml: &Path) -> BTreeMap<String, (String, String)> {
    let text = std::fs::read_to_string(xml).unwrap();
    let attr = |chunk: &str, name: &str| -> String {
        let key = format!("{name}=\"");
        let i = chunk.find(&key).unwrap() + key.len();
        chunk[i..i + chunk[i..].find('"').unwrap()].to_string()
    };
    text.split("<route ")
        .skip(1)
        .map(|chunk| {
            let head = &chunk[..chunk.find('>').unwrap()];
            let scen = &chunk[chunk.find("<scenario ").unwrap()..];
            let scen = &scen[..scen.find('>').unwrap()];
            (attr(head, "id"), (attr(head, "town"), attr(scen, "type")))
        })
        .collect()
}

const TRAFFIC_SIGNS: [&str; 19] = [
    "BlockedIntersection",
    "OppositeVehicleTakingPriority",
    "OppositeVehicleRunningRedLight",
    "PedestrianCrossing",
    "VehicleTurningRoute",
    "VehicleTurningRoutePedestrian",
    "EnterActorFlow",
    "CrossingBicycleFlow",
    "NonSignalizedJunctionLeftTurn",
    "NonSignalizedJunctionRightTurn",
    "NonSignalizedJunctionLeftTurnEnterFlow",
    "SignalizedJunctionLeftTurn",
    "SignalizedJunctionRightTurn",
    "SignalizedJunctionLeftTurnEnterFlow",
    "T_Junction",
    "VanillaNonSignalizedTurn",
    "VanillaSignalizedTurnEncounterGreenLight",
    "VanillaSignalizedTurnEncounterRedLight",
    "VanillaNonSignalizedTurnEncounterStopsign",
];

fn success(r: &Value) -> bool {
    let status = r["status"].as_str().unwrap();
    (status == "Completed" || status == "Perfect")
        && r["infractions"]
            .as_object()
            .unwrap()
            .iter()
            .all(|(k, v)| k == "min_speed_infractions" || v.as_array().unwrap().is_empty())
}

fn xml_id(route_id: &str) -> &str {
    let rest = route_id.strip_prefix("RouteScenario_").unwrap();
    &rest[..rest.rfind("_rep").unwrap()]
}

fn score_json(extra: &[&str]) -> Value {
    let mut args = vec!["score", "--allow-missing-telemetry", "--format", "json"];
    args.extend_from_slice(extra);
    let out = sds(&args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    json_of(&out)
}

#[test]
fn abilities_reproduce_bench2drive_for_tfpp() {
    let Some(fx) = fixtures() else { return };
    let b2d = fx.join("b2d");
    let results = b2d.join("carla_garage_tfpp_b2d_traj_merged.json");
    let xml = b2d.join("routes/bench2drive220.xml");
    let maps = fx.join("maps");
    let theirs = read(&b2d.join("tfpp_raw_shards/merged_ability.json"));

    let r = score_json(&[
        "--results",
        s(&results),
        "--routes",
        s(&xml),
        "--maps",
        s(&maps),
    ]);
    let b = &r["summary"]["bench2drive"];
    // The four abilities without a junction credit: identical to Bench2Drive's output.
    for (name, k, n) in [
        ("Overtaking", 26, 45),
        ("Merging", 47, 80),
        ("Emergency_Brake", 50, 60),
        ("Give_Way", 4, 10),
    ] {
        assert_eq!(b["ability_counts"][name]["successes"], k, "{name}");
        assert_eq!(b["ability_counts"][name]["routes"], n, "{name}");
        assert_eq!(b["ability"][name].as_f64(), theirs[name].as_f64(), "{name}");
    }
    assert_eq!(b["ability_missing"].as_array().unwrap().len(), 0);

    // Traffic_Signs, worked out here from the records and the XML: 95 routes, 67 plain
    // successes, 28 failures of which 27 lie in towns without a map in the fixtures.
    let towns_with_maps: Vec<String> = std::fs::read_dir(&maps)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().into_string().unwrap();
            let stem = name.strip_suffix(".xodr")?;
            Some(stem.trim_end_matches("_Opt").to_string())
        })
        .collect();
    let routes = xml_routes(&xml);
    let records = read(&results)["_checkpoint"]["records"].clone();
    let ts: Vec<&Value> = records
        .as_array()
        .unwrap()
        .iter()
        .filter(|rec| {
            TRAFFIC_SIGNS.contains(&routes[xml_id(rec["route_id"].as_str().unwrap())].1.as_str())
        })
        .collect();
    assert_eq!(ts.len(), 95);
    let failed: Vec<&&Value> = ts.iter().filter(|rec| !success(rec)).collect();
    assert_eq!(ts.len() - failed.len(), 67);
    let unmapped: Vec<&&&Value> = failed
        .iter()
        .filter(|rec| !towns_with_maps.contains(&rec["town_name"].as_str().unwrap().to_string()))
        .collect();
    assert_eq!(unmapped.len(), 27);
    let decidable: Vec<&str> = failed
        .iter()
        .filter(|rec| towns_with_maps.contains(&rec["town_name"].as_str().unwrap().to_string()))
        .map(|rec| rec["route_id"].as_str().unwrap())
        .collect();
    assert_eq!(decidable, ["RouteScenario_28093_rep0"]);
    // Undecided: the failures in towns without a map whose credit is not already ruled out by
    // a red light or a stop sign; every one is named with its town.
    let eligible = |rec: &Value| {
        rec["infractions"]["red_light"]
            .as_array()
            .unwrap()
            .is_empty()
            && rec["infractions"]["stop_infraction"]
                .as_array()
                .unwrap()
                .is_empty()
    };
    let mut expected: Vec<&str> = unmapped
        .iter()
        .filter(|rec| eligible(rec))
        .map(|rec| rec["route_id"].as_str().unwrap())
        .collect();
    expected.sort_unstable();
    let mut undecided: Vec<&str> = b["ability_undecided"]
        .as_array()
        .unwrap()
        .iter()
        .map(|u| u["route_id"].as_str().unwrap())
        .collect();
    undecided.sort_unstable();
    assert_eq!(undecided, expected);
    assert!(!undecided.is_empty());
    let text = sds(&[
        "score",
        "--allow-missing-telemetry",
        "--results",
        s(&results),
        "--routes",
        s(&xml),
        "--maps",
        s(&maps),
        "--format",
        "table",
    ]);
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(
        text.contains(&format!(
            "Traffic_Signs under b2d-0.0.4: {} failed route(s) whose junction credit is undecided",
            expected.len()
        )),
        "{text}"
    );
    assert!(text.contains("Overtaking 26/45, Merging 47/80, Emergency_Brake 50/60, Give_Way 4/10"));

    // Route 28093 (Town04) is decided with the map (credited or not); without maps it is not.
    let route = |report: &Value| -> Value {
        report["routes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["route_id"] == "RouteScenario_28093_rep0")
            .unwrap()
            .clone()
    };
    // With the maps, 28093 is decided: it completed its route (score_route 100), far beyond
    // the point where its dense route enters its first junction, so it is credited.
    let j = &route(&r)["ability"]["junction"];
    assert_eq!(j["credited"], true, "{j}");
    assert_eq!(j["score"], 1.0);
    let completion = j["junction_completion"].as_f64().unwrap();
    assert!(completion > 0.0 && completion < 0.85, "{completion}");
    assert_eq!(j["marginal"], false);
    assert_eq!(b["ability_counts"]["Traffic_Signs"]["successes"], 68);
    assert_eq!(b["ability_counts"]["Traffic_Signs"]["routes"], 95);
    // Without maps it is undecided too, and the reason names its town.
    let without = score_json(&["--results", s(&results), "--routes", s(&xml)]);
    assert!(route(&without)["ability"]["junction"]["undecided"]
        .as_str()
        .unwrap()
        .contains("Town04"));
    let wb = &without["summary"]["bench2drive"];
    assert_eq!(
        wb["ability_undecided"].as_array().unwrap().len(),
        expected.len() + 1
    );
    assert_eq!(wb["ability_counts"]["Traffic_Signs"]["successes"], 67);
}

#[test]
fn a_broken_map_is_an_error_naming_it() {
    let Some(fx) = fixtures() else { return };
    let b2d = fx.join("b2d");
    let maps = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(fx.join("maps/Town04.xodr")).unwrap();
    std::fs::write(maps.path().join("Town04.xodr"), &good[..good.len() / 2]).unwrap();
    let out = sds(&[
        "score",
        "--allow-missing-telemetry",
        "--results",
        s(&b2d.join("carla_garage_tfpp_b2d_traj_merged.json")),
        "--routes",
        s(&b2d.join("routes/bench2drive220.xml")),
        "--maps",
        s(maps.path()),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("Town04.xodr"), "{err}");
}

#[test]
fn efficiency_reproduces_bench2drive_for_pdm_lite() {
    let Some(fx) = fixtures() else { return };
    let b2d = fx.join("b2d");
    let theirs = read(&b2d.join("carla_garage_pdm_lite_b2d_traj_merged_ability.json"));
    let r = score_json(&[
        "--results",
        s(&b2d.join("carla_garage_pdm_lite_b2d_traj_merged.json")),
        "--routes",
        s(&b2d.join("routes/bench2drive220.xml")),
    ]);
    let b = &r["summary"]["bench2drive"];
    assert_eq!(b["efficiency"].as_f64(), Some(250.03924965239113));
    assert_eq!(
        theirs["Driving Efficiency"].as_f64(),
        Some(250.03924965239113)
    );
    // Abilities without a junction credit are Bench2Drive's too.
    for name in ["Overtaking", "Merging", "Emergency_Brake", "Give_Way"] {
        assert_eq!(b["ability"][name].as_f64(), theirs[name].as_f64(), "{name}");
    }
    // Per route: the mean of its percentages up to 1000, worked out here for route 4937,
    // which has an outlier above 1000.
    let rec = read(&b2d.join("carla_garage_pdm_lite_b2d_traj_merged.json"))["_checkpoint"]
        ["records"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == "RouteScenario_4937_rep0")
        .unwrap()
        .clone();
    let pcts: Vec<f64> = rec["infractions"]["min_speed_infractions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let m = m.as_str().unwrap();
            let rest = m.strip_prefix("Average speed is ").unwrap();
            rest[..rest.find('%').unwrap()].parse().unwrap()
        })
        .collect();
    let kept: Vec<f64> = pcts.iter().copied().filter(|x| *x <= 1000.0).collect();
    assert!(kept.len() < pcts.len(), "route 4937 has an outlier");
    let want = kept.iter().sum::<f64>() / kept.len() as f64;
    let got = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == "RouteScenario_4937_rep0")
        .unwrap()["efficiency"]
        .as_f64()
        .unwrap();
    assert!((got - want).abs() < 1e-9, "{got} vs {want}");
}

/// `k/n (r%)`, as the Table 3-style breakdown prints it.
fn cell(k: usize, n: usize) -> String {
    format!("{k}/{n} ({:.1}%)", 100.0 * k as f64 / n as f64)
}

#[test]
fn weather_table_of_a_real_run_matches_counts_from_the_json() {
    let Some(fx) = fixtures() else { return };
    let results = fx.join("b2d/carla_garage_tfpp_b2d_traj_merged.json");
    // Counted here from the raw JSON: per weather id, routes and routes with each list.
    let lists = [
        "red_light",
        "collisions_layout",
        "outside_route_lanes",
        "vehicle_blocked",
        "collisions_vehicle",
    ];
    let mut expected: BTreeMap<String, (usize, [usize; 5])> = BTreeMap::new();
    for rec in read(&results)["_checkpoint"]["records"].as_array().unwrap() {
        let w = rec["weather_id"]
            .as_str()
            .map(str::to_string)
            .unwrap_or_else(|| rec["weather_id"].to_string());
        let e = expected.entry(w).or_default();
        e.0 += 1;
        for (i, l) in lists.iter().enumerate() {
            e.1[i] += usize::from(!rec["infractions"][l].as_array().unwrap().is_empty());
        }
    }
    assert!(expected.len() > 3, "several weathers");
    let out = sds(&[
        "score",
        "--allow-missing-telemetry",
        "--results",
        s(&results),
        "--group-by",
        "weather",
        "--infraction",
        "collisions_vehicle",
        "--format",
        "table",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    let table3 = &text[text.find("Table 3-style").expect("a Table 3")..];
    let mut total = (0, [0usize; 5]);
    for (w, (n, ks)) in &expected {
        let line = table3
            .lines()
            .find(|l| l.split_whitespace().next() == Some(w.as_str()))
            .unwrap_or_else(|| panic!("no row for weather {w} in\n{table3}"));
        let want: Vec<String> = ks.iter().map(|k| cell(*k, *n)).collect();
        let got: Vec<&str> = line
            .split("  ")
            .map(str::trim)
            .filter(|c| !c.is_empty())
            .collect();
        assert_eq!(got[1], n.to_string(), "{line}");
        assert_eq!(got[2..], want[..], "weather {w}");
        total.0 += n;
        for (t, k) in total.1.iter_mut().zip(ks) {
            *t += k;
        }
    }
    let combined = table3.lines().find(|l| l.starts_with("Combined")).unwrap();
    for k in total.1 {
        assert!(combined.contains(&cell(k, total.0)), "{combined}");
    }
    // The JSON report holds the same counts; Markdown and LaTeX the same cells.
    let r = score_json(&["--results", s(&results), "--group-by", "weather"]);
    let g = &r["groups"];
    assert_eq!(g["by"], "weather");
    for row in g["rows"].as_array().unwrap() {
        let (n, ks) = expected[row["label"].as_str().unwrap()];
        assert_eq!(row["routes"], n);
        for (i, l) in lists.iter().enumerate() {
            assert_eq!(row["infraction_routes"][l], ks[i]);
        }
    }
    assert_eq!(g["combined"]["routes"], 220);
    assert_eq!(
        g["combined"]["driving_score"],
        r["summary"]["driving_score"]
    );
    for (format, needle) in [("markdown", "| "), ("latex", " & ")] {
        let out = sds(&[
            "score",
            "--allow-missing-telemetry",
            "--results",
            s(&results),
            "--group-by",
            "weather",
            "--format",
            format,
        ]);
        let text = String::from_utf8(out.stdout).unwrap();
        let (w, (n, ks)) = expected.iter().next().unwrap();
        let c = cell(ks[0], *n).replace('%', if format == "latex" { "\\%" } else { "%" });
        assert!(
            text.lines()
                .any(|l| l.contains(&c) && l.contains(needle) && l.contains(w.as_str())),
            "{format}: no {c} for weather {w} in\n{text}"
        );
        if format == "latex" {
            assert!(text.contains("\\toprule") && text.contains("\\bottomrule"));
        }
    }
}

/// Σ score_composed / records of a merged file, worked out from the raw JSON.
fn ds_of(file: &Path, keep: impl Fn(&str) -> bool) -> (f64, usize) {
    let v = read(file);
    let recs: Vec<&Value> = v["_checkpoint"]["records"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| keep(r["route_id"].as_str().unwrap()))
        .collect();
    let sum = recs.iter().fold(0.0, |a, r| {
        a + r["scores"]["score_composed"].as_f64().unwrap()
    });
    (sum / recs.len() as f64, recs.len())
}

#[test]
fn compare_three_runs_as_seeds_with_mean_and_std() {
    let Some(fx) = fixtures() else { return };
    let b2d = fx.join("b2d");
    let a = b2d.join("carla_garage_tfpp_b2d_traj_merged.json");
    let b = b2d.join("carla_garage_pdm_lite_b2d_traj_merged.json");
    let c = b2d.join("b2dzoo_UniAD-Base_merged.json"); // 218 routes: 23670 and 3800 absent
    let arg = |n: &str, p: &Path| format!("{n}={}", p.display());
    let runs = [arg("m_1", &a), arg("m_2", &b), arg("m_3", &c), arg("t", &a)];
    let run = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            "--allow-missing-telemetry",
            "--seeds",
            "m=m_1,m_2,m_3",
        ];
        args.extend_from_slice(extra);
        args.extend(runs.iter().map(String::as_str));
        sds(&args)
    };
    // UniAD lacks two routes: refused by default, naming them.
    let out = run(&["--format", "json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("2 route key(s) are not in every run (first: 23670, 3800)"),
        "{err}"
    );
    let out = run(&["--format", "json", "--common-routes"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cmp = json_of(&out);
    // Only the routes present in every run, and the report says which were left out.
    assert_eq!(cmp["scope"]["routes"], 218);
    let gone = ["RouteScenario_23670_rep0", "RouteScenario_3800_rep0"];
    let left: Vec<String> = cmp["scope"]["left_out"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e[0].as_str().unwrap().to_string())
        .collect();
    assert_eq!(left, ["m_1", "m_2", "t"]);
    // By hand: each run's DS over the 218 common routes, then mean and sample std.
    let keep = |id: &str| !gone.contains(&id);
    let ds: Vec<f64> = [&a, &b, &c]
        .iter()
        .map(|f| ds_of(f, keep))
        .map(|(d, n)| {
            assert_eq!(n, 218);
            d
        })
        .collect();
    let mean = (ds[0] + ds[1] + ds[2]) / 3.0;
    let std =
        (((ds[0] - mean).powi(2) + (ds[1] - mean).powi(2) + (ds[2] - mean).powi(2)) / 2.0).sqrt();
    let m = &cmp["models"][0];
    assert_eq!(m["name"], "m");
    assert_eq!(m["runs"], serde_json::json!(["m_1", "m_2", "m_3"]));
    assert!((m["driving_score"]["mean"].as_f64().unwrap() - mean).abs() < 1e-9);
    assert!((m["driving_score"]["std"].as_f64().unwrap() - std).abs() < 1e-9);
    assert!(std > 1.0, "three different models: a real spread ({std})");
    // The single run t = the first seed: its DS over the same routes.
    assert!((cmp["models"][1]["driving_score"]["mean"].as_f64().unwrap() - ds[0]).abs() < 1e-9);

    // The table: the model row as mean ± std, and which runs it groups.
    let out = run(&["--common-routes"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains(&format!("{mean:.2} ± {std:.2}")), "{text}");
    assert!(text.contains("m: seeds m_1, m_2, m_3"), "{text}");
    assert!(text.contains("compared on the 218 route key(s) every run holds (common_routes)"));
}
