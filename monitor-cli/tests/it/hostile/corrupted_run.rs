//! End-to-end reliability of `sds score` on a corrupted copy of a run (`docs/RELIABILITY.md`).
//!
//! The run is built at test time in a temporary folder: the demo's 9 routes split into one raw
//! evaluator file per route (as a Bench2Drive farm leaves them), more copies of demo routes under
//! new ids that are then broken in every way the issue lists, and the real single-route fixtures
//! (a finished route without telemetry and a crashed run with no records) when
//! `../../shared/fixtures/b2d` is present. The assertions: exit code 3, every route in the report
//! with its exact state and a reason naming the file, step and field, healthy routes scored to
//! the bit as in the clean run, and no partial report after a failed or killed write.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{json, Value};

use crate::common::{code, stderr};

const SDS: &str = env!("CARGO_BIN_EXE_sds");
const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/fixtures/b2d");

fn sds(args: &[&dyn AsRef<std::ffi::OsStr>]) -> Output {
    let mut c = Command::new(SDS);
    for a in args {
        c.arg(a);
    }
    c.output().expect("run sds")
}

/// The demo run in `dir`: its records (raw evaluator values) and paths.
struct Demo {
    records: Vec<Value>,
    telemetry: PathBuf,
    routes: PathBuf,
}

fn demo(dir: &Path) -> Demo {
    let o = sds(&[&"demo", &dir]);
    assert_eq!(code(&o), 0, "sds demo failed: {}", stderr(&o));
    let doc: Value = serde_json::from_slice(&fs::read(dir.join("results.json")).unwrap()).unwrap();
    let records = doc["_checkpoint"]["records"].as_array().unwrap().clone();
    assert_eq!(records.len(), 9);
    Demo {
        records,
        telemetry: dir.join("telemetry"),
        routes: dir.join("routes.xml"),
    }
}

/// Writes one raw evaluator file holding `records`.
fn write_raw(path: &Path, records: &[Value]) {
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    let doc = json!({
        "_checkpoint": {"global_record": {}, "progress": [records.len(), records.len()],
                        "records": records},
        "entry_status": "Finished", "eligible": true, "sensors": [], "values": [], "labels": []
    });
    fs::write(path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
}

fn score(results: &Path, telemetry: &Path, routes: &Path, out: &Path) -> (Output, Option<Value>) {
    let o = sds(&[
        &"score",
        &"--results",
        &results,
        &"--telemetry",
        &telemetry,
        &"--routes",
        &routes,
        &"--jobs",
        &"2",
        &"--duplicates",
        &"all",
        &"-o",
        &out,
    ]);
    let report = fs::read(out)
        .ok()
        .map(|b| serde_json::from_slice(&b).expect("the report is complete JSON"));
    (o, report)
}

fn routes_by_source(report: &Value) -> BTreeMap<String, Value> {
    report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let src = &r["source"];
            let key = format!("{}#{}", src["file"].as_str().unwrap(), src["index"]);
            (key, r.clone())
        })
        .collect()
}

/// A route's state with its reason, as `invalid: <reason>` (the report gives them apart).
fn full_state(r: &Value) -> String {
    match (r["state"].as_str().unwrap(), r["reason"].as_str()) {
        ("invalid", Some(reason)) => format!("invalid: {reason}"),
        (state, _) => state.to_string(),
    }
}

/// A copy of demo record `base` under a new xml id (and a new telemetry folder holding a copy of
/// its telemetry, transformed by `tel`). Returns the record and its telemetry path.
fn clone_route(
    demo: &Demo,
    base: usize,
    new_id: u32,
    tel_root: &Path,
    tel: impl FnOnce(String) -> String,
) -> (Value, PathBuf) {
    let mut r = demo.records[base].clone();
    let old_id = r["route_id"].as_str().unwrap().to_string();
    let old_save = r["save_name"].as_str().unwrap().to_string();
    let new_route = format!("RouteScenario_{new_id}_rep0");
    let new_save = old_save.replace(&old_id, &new_route);
    r["route_id"] = new_route.into();
    r["save_name"] = new_save.clone().into();
    let text = fs::read_to_string(demo.telemetry.join(&old_save).join("metric_info.json")).unwrap();
    let folder = tel_root.join(&new_save);
    fs::create_dir_all(&folder).unwrap();
    let path = folder.join("metric_info.json");
    fs::write(&path, tel(text)).unwrap();
    (r, path)
}

/// Copies a route's XML element under a new id (so that lateral error is scored for clones).
fn xml_with_clones(xml: &str, clones: &[(u32, u32)]) -> String {
    let mut extra = String::new();
    for &(from, to) in clones {
        let start = xml.find(&format!("<route id=\"{from}\"")).unwrap();
        let end = start + xml[start..].find("</route>").unwrap() + "</route>".len();
        extra
            .push_str(&xml[start..end].replace(&format!("id=\"{from}\""), &format!("id=\"{to}\"")));
        extra.push('\n');
    }
    xml.replace("</routes>", &format!("{extra}</routes>"))
}

/// Replaces the `n`-th occurrence (0-based) of `pat`.
fn replace_nth(s: &str, pat: &str, n: usize, with: &str) -> String {
    let (i, _) = s
        .match_indices(pat)
        .nth(n)
        .unwrap_or_else(|| panic!("no {pat:?} #{n}"));
    format!("{}{with}{}", &s[..i], &s[i + pat.len()..])
}

/// Writes `token` (e.g. `NaN`) as element 0 of `field` in the frame at position `frame`.
fn poison(text: &str, field: &str, frame: usize, token: &str) -> String {
    let key = format!("\"{field}\": [");
    let (i, _) = text.match_indices(&key).nth(frame).unwrap();
    let start = i + key.len();
    let end = start + text[start..].find(',').unwrap();
    format!("{}\n{token}{}", &text[..start], &text[end..])
}

/// What a broken route must look like in the report.
struct Expect {
    source: String,
    /// Exact state, or a prefix followed by substrings the reason must contain.
    state_prefix: &'static str,
    reason_has: Vec<String>,
    route_id: Option<String>,
}

#[test]
fn corrupted_run_yields_full_report_and_precise_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let demo = demo(&tmp.path().join("demo"));
    let run = tmp.path().join("run");
    let res = run.join("results");
    let tel = run.join("telemetry");
    fs::create_dir_all(&tel).unwrap();

    // --- the clean run: the demo's 9 routes, one raw file per route, as a farm writes them.
    let healthy_ids: Vec<String> = demo
        .records
        .iter()
        .map(|r| r["route_id"].as_str().unwrap().to_string())
        .collect();
    for (r, id) in demo.records.iter().zip(&healthy_ids) {
        write_raw(&res.join(id).join("endpoint.json"), std::slice::from_ref(r));
        let save = r["save_name"].as_str().unwrap();
        let dst = tel.join(save);
        fs::create_dir_all(&dst).unwrap();
        fs::copy(
            demo.telemetry.join(save).join("metric_info.json"),
            dst.join("metric_info.json"),
        )
        .unwrap();
    }
    let clean_out = tmp.path().join("clean.json");
    let (o, clean) = score(&res, &tel, &demo.routes, &clean_out);
    assert_eq!(code(&o), 0, "clean run: {}", stderr(&o));
    let clean = clean.expect("clean report");
    let clean_routes = routes_by_source(&clean);
    assert_eq!(clean_routes.len(), 9);

    // --- break copies of demo routes, each in one way.
    let mut expect: Vec<Expect> = Vec::new();
    let mut clones = Vec::new();
    let src = |id: &str| format!("{}#0", res.join(id).join("endpoint.json").display());
    let mut add = |demo: &Demo,
                   base: usize,
                   id: u32,
                   tel_fn: &dyn Fn(String) -> String,
                   rec_fn: &dyn Fn(&mut Value),
                   state_prefix: &'static str,
                   reason_has: &[&str]| {
        let (mut r, tel_path) = clone_route(demo, base, id, &tel, tel_fn);
        rec_fn(&mut r);
        let route_id = format!("RouteScenario_{id}_rep0");
        write_raw(&res.join(&route_id).join("endpoint.json"), &[r]);
        clones.push((900_001 + base as u32, id));
        let mut reason: Vec<String> = reason_has.iter().map(|s| s.to_string()).collect();
        // A telemetry problem names the telemetry file; a record problem names the field (its
        // file is the route's `source`).
        if state_prefix == "invalid: " && !reason_has.iter().any(|r| r.starts_with("field ")) {
            reason.push(tel_path.display().to_string());
        }
        expect.push(Expect {
            source: src(&route_id),
            state_prefix,
            reason_has: reason,
            route_id: Some(route_id),
        });
    };
    let same = |t: String| t;
    let keep = |_: &mut Value| {};
    // Telemetry: NaN / Infinity tokens (Python's json writes them).
    add(
        &demo,
        0,
        910_001,
        &|t| poison(&t, "forward_vector", 4, "NaN"),
        &keep,
        "invalid: ",
        &["step 5: field forward_vector: NaN or infinite value"],
    );
    add(
        &demo,
        1,
        910_002,
        &|t| poison(&t, "acceleration", 1, "-Infinity"),
        &keep,
        "invalid: ",
        &["step 2: field acceleration: NaN or infinite value"],
    );
    // In a key the monitor does not read (`velocity`): still not JSON, the step is named.
    add(
        &demo,
        3,
        910_020,
        &|t| poison(&t, "velocity", 6, "Infinity"),
        &keep,
        "invalid: ",
        &["step 7: NaN or infinite value at line "],
    );
    // Truncated telemetry (a crashed writer).
    add(
        &demo,
        2,
        910_003,
        &|t| t[..t.len() / 2].to_string(),
        &keep,
        "invalid: ",
        &["not valid JSON", "line "],
    );
    // An empty object.
    add(
        &demo,
        3,
        910_004,
        &|_| "{}".to_string(),
        &keep,
        "invalid: ",
        &["no frames"],
    );
    // A duplicate step ("5" and "0005").
    add(
        &demo,
        4,
        910_005,
        &|t| t.replacen("\"6\":", "\"0005\":", 1),
        &keep,
        "invalid: ",
        &["step 5 appears twice"],
    );
    // A vector of the wrong length.
    add(
        &demo,
        5,
        910_006,
        &|t| {
            let i = t.find("\"right_vector\"").unwrap();
            let j = i + t[i..].find(']').unwrap();
            format!("{}\"right_vector\": [0.0, 1.0{}", &t[..i], &t[j..])
        },
        &keep,
        "invalid: ",
        &["step 1", "right_vector", "fewer than 3 numbers"],
    );
    // A missing key.
    add(
        &demo,
        6,
        910_007,
        &|t| replace_nth(&t, "\"location\"", 9, "\"locatio\""),
        &keep,
        "invalid: ",
        &["step 10", "location", "missing"],
    );
    // A non-numeric step.
    add(
        &demo,
        0,
        910_008,
        &|t| t.replacen("\"3\":", "\"3a\":", 1),
        &keep,
        "invalid: ",
        &["step key \"3a\""],
    );
    // Results: wrong types in a record.
    add(
        &demo,
        1,
        910_009,
        &same,
        &|r| r["scores"]["score_route"] = "100".into(),
        "invalid: ",
        &["field scores.score_route", "expected a number, got string"],
    );
    // Results: a record without save_name -> its telemetry cannot be found.
    add(
        &demo,
        2,
        910_010,
        &same,
        &|r| {
            r.as_object_mut().unwrap().remove("save_name");
        },
        "invalid: telemetry missing",
        &["the record has no save_name"],
    );

    // Healthy variants that must still score (flagged where it matters):
    // decreasing steps: the same frames in reverse order score exactly like the original.
    let (r, _) = clone_route(&demo, 1, 910_011, &tel, |t| {
        let v: serde_json::Map<String, Value> = serde_json::from_str(&t).unwrap();
        let mut items: Vec<_> = v.into_iter().collect();
        items.sort_by_key(|(k, _)| std::cmp::Reverse(k.parse::<u64>().unwrap()));
        let mut out = String::from("{");
        for (i, (k, v)) in items.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str(&format!("\"{k}\": {v}"));
        }
        out.push('}');
        out
    });
    write_raw(
        &res.join("RouteScenario_910011_rep0").join("endpoint.json"),
        &[r],
    );
    clones.push((900_002, 910_011));
    // Large step gaps: every other step dropped after step 50 -> gaps counted, still scored.
    let (r, _) = clone_route(&demo, 0, 910_012, &tel, |t| {
        let v: serde_json::Map<String, Value> = serde_json::from_str(&t).unwrap();
        let kept: serde_json::Map<String, Value> = v
            .into_iter()
            .filter(|(k, _)| {
                let s: u64 = k.parse().unwrap();
                s <= 50 || s.is_multiple_of(2)
            })
            .map(|(k, v)| {
                let s: u64 = k.parse().unwrap();
                ((if s > 50 { s * 1000 } else { s }).to_string(), v)
            })
            .collect();
        serde_json::to_string(&kept).unwrap()
    });
    write_raw(
        &res.join("RouteScenario_910012_rep0").join("endpoint.json"),
        &[r],
    );
    clones.push((900_001, 910_012));
    // Unknown status, an unparseable collision string, a collision far from any frame.
    let (mut r, _) = clone_route(&demo, 3, 910_013, &tel, |t| t);
    r["status"] = "Exploded".into();
    r["infractions"]["collisions_vehicle"] =
        json!(["Agent collided against object with type=vehicle.audi.tt and id=x1"]);
    let far = r["infractions"]["collisions_layout"][0]
        .as_str()
        .unwrap()
        .replace("(x=", "(x=9");
    r["infractions"]["collisions_layout"] = json!([far]);
    write_raw(
        &res.join("RouteScenario_910013_rep0").join("endpoint.json"),
        &[r],
    );
    clones.push((900_004, 910_013));
    // A route id missing from the XML (not cloned into it): scored, without lateral terms.
    let (r, _) = clone_route(&demo, 0, 910_014, &tel, |t| t);
    write_raw(
        &res.join("RouteScenario_910014_rep0").join("endpoint.json"),
        &[r],
    );
    // The same route id in two files: both kept.
    let dup_a = res.join("dup_a").join("endpoint.json");
    let dup_b = res.join("dup_b").join("endpoint.json");
    let (r, _) = clone_route(&demo, 0, 910_015, &tel, |t| t);
    write_raw(&dup_a, std::slice::from_ref(&r));
    write_raw(&dup_b, &[r]);
    clones.push((900_001, 910_015));
    // Telemetry whose frames are far from the route (another run's folder): 5 km away.
    let (r, _) = clone_route(&demo, 0, 910_016, &tel, |t| {
        let mut v: serde_json::Map<String, Value> = serde_json::from_str(&t).unwrap();
        for f in v.values_mut() {
            let x = f["location"][0].as_f64().unwrap();
            f["location"][0] = (x + 5000.0).into();
        }
        serde_json::to_string(&v).unwrap()
    });
    write_raw(
        &res.join("RouteScenario_910016_rep0").join("endpoint.json"),
        &[r],
    );
    clones.push((900_001, 910_016));
    // An empty record and a record that is not an object, in one file with a healthy clone.
    let (r, _) = clone_route(&demo, 6, 910_017, &tel, |t| t);
    let mixed = res.join("mixed").join("endpoint.json");
    write_raw(&mixed, &[json!({}), r, json!("oops")]);
    clones.push((900_007, 910_017));
    expect.push(Expect {
        source: format!("{}#0", mixed.display()),
        state_prefix: "invalid: ",
        reason_has: vec!["field route_id: missing".into()],
        route_id: None,
    });
    expect.push(Expect {
        source: format!("{}#2", mixed.display()),
        state_prefix: "invalid: ",
        reason_has: vec!["record: expected an object, got string".into()],
        route_id: None,
    });
    // A truncated results file: its record cannot be read; the file is named in a warning.
    let trunc = res.join("RouteScenario_910018_rep0").join("endpoint.json");
    write_raw(&trunc, &[demo.records[0].clone()]);
    let text = fs::read(&trunc).unwrap();
    fs::write(&trunc, &text[..text.len() * 2 / 3]).unwrap();
    // A directory named metric_info.json where the telemetry should be.
    let (r, p) = clone_route(&demo, 0, 910_019, &tel, |t| t);
    fs::remove_file(&p).unwrap();
    fs::create_dir_all(p.join("junk")).unwrap();
    write_raw(
        &res.join("RouteScenario_910019_rep0").join("endpoint.json"),
        &[r],
    );

    // Real evaluator files, when the fixtures are there.
    let fixtures = Path::new(FIXTURES);
    let have_fixtures = fixtures.is_dir();
    let real = res.join("3564").join("endpoint.json");
    let crashed = res.join("24206").join("endpoint.json");
    if have_fixtures {
        fs::create_dir_all(real.parent().unwrap()).unwrap();
        fs::create_dir_all(crashed.parent().unwrap()).unwrap();
        fs::copy(
            fixtures.join("pdmlite_route3564_endpoint_tickruntime_mesh_collisions.json"),
            &real,
        )
        .unwrap();
        fs::copy(
            fixtures.join("pdmlite_route24206_endpoint_crashed_empty.json"),
            &crashed,
        )
        .unwrap();
        // Not in the run's route XML: a foreign route (checked below), reported, not counted.
    } else {
        crate::common::skipped(&format!(
            "real fixtures absent ({FIXTURES}); the run uses demo routes only"
        ));
    }

    let xml = xml_with_clones(&fs::read_to_string(&demo.routes).unwrap(), &clones);
    let routes_xml = run.join("routes.xml");
    fs::write(&routes_xml, xml).unwrap();

    // --- score the corrupted run.
    let out = tmp.path().join("report.json");
    let (o, report) = score(&res, &tel, &routes_xml, &out);
    let err = stderr(&o);
    assert_eq!(code(&o), 3, "exit code; stderr:\n{err}");
    let report = report.expect("a report is written even with broken routes");
    let by_source = routes_by_source(&report);
    let warnings: Vec<String> = report["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect();
    let all_warnings = warnings.join("\n");

    // Every record of every readable file is in the report: 9 healthy + 11 broken + 11 variants
    // (910011-910017 with a duplicate and 2 invalid records in `mixed`, and 910019), + 1 real,
    // + 1 entry for the truncated results file, whose routes cannot be known.
    let expected_routes = 9 + 11 + 11 + usize::from(have_fixtures) + 1;
    assert_eq!(
        by_source.len(),
        expected_routes,
        "routes: {:#?}",
        by_source.keys()
    );
    // Routes whose id is not in the route XML are foreign: reported, not counted.
    let foreign: Vec<&str> = report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] == "foreign")
        .map(|r| r["route_id"].as_str().unwrap())
        .collect();
    let mut want = vec!["RouteScenario_910014_rep0", "RouteScenario_910019_rep0"];
    if have_fixtures {
        want.insert(0, "RouteScenario_3564_rep0");
    }
    assert_eq!(foreign, want);
    assert_eq!(
        report["summary"]["routes_found"].as_u64().unwrap() as usize + foreign.len(),
        expected_routes
    );
    assert_eq!(report["summary"]["foreign"], foreign.len());

    // Healthy routes: scored exactly as in the clean run (compare bits).
    for (id, clean_route) in healthy_ids.iter().zip(clean_routes.values()) {
        let r = &by_source[&src(id)];
        assert_eq!(r["state"], "scored", "{id}");
        for key in ["ds_safe", "p_safe"] {
            let a = r[key].as_f64().unwrap().to_bits();
            let b = clean_route[key].as_f64().unwrap().to_bits();
            assert_eq!(a, b, "{id} {key} differs from the clean run");
        }
        for key in ["comfort", "lateral", "collisions", "frames", "gaps"] {
            assert_eq!(r[key], clean_route[key], "{id} {key}");
        }
    }

    // Broken routes: exact state, a reason naming file / step / field, and a stderr line.
    for e in &expect {
        let r = by_source
            .get(&e.source)
            .unwrap_or_else(|| panic!("route {} lost", e.source));
        let state = full_state(r);
        assert!(
            state.starts_with(e.state_prefix),
            "{}: state {state:?}",
            e.source
        );
        for part in &e.reason_has {
            assert!(
                state.contains(part.as_str()),
                "{}: {state:?} lacks {part:?}",
                e.source
            );
        }
        assert_eq!(
            r["route_id"].as_str().map(String::from),
            e.route_id,
            "{}",
            e.source
        );
        assert!(
            r["ds_safe"].is_null(),
            "{}: a broken route was scored",
            e.source
        );
        let shown = e.route_id.as_deref().unwrap_or("<no route_id>");
        assert!(
            err.lines()
                .any(|l| l.contains(shown) && l.contains(&e.source) && l.contains(&state)),
            "no stderr line for {} {state}:\n{err}",
            e.source
        );
    }

    // Healthy variants.
    let get = |id: &str| &by_source[&src(id)];
    let reversed = get("RouteScenario_910011_rep0");
    let original = &clean_routes[&src("RouteScenario_900002_rep0")];
    assert_eq!(reversed["state"], "scored");
    assert_eq!(
        reversed["ds_safe"].as_f64().unwrap().to_bits(),
        original["ds_safe"].as_f64().unwrap().to_bits()
    );
    assert_eq!(reversed["comfort"], original["comfort"]);
    let gappy = get("RouteScenario_910012_rep0");
    assert_eq!(gappy["state"], "scored");
    assert_eq!(gappy["frames"], 125);
    assert_eq!(gappy["gaps"], 200_000 - 125); // steps 1..=50, then 52_000..=200_000 by 2_000
    let odd = get("RouteScenario_910013_rep0");
    assert_eq!(odd["state"], "scored");
    assert_eq!(odd["success"], false);
    assert!(
        all_warnings.contains("unknown status \"Exploded\""),
        "{all_warnings}"
    );
    let events = odd["collision_events"].as_array().unwrap();
    assert_eq!(events.len(), 2);
    let unparsed = events
        .iter()
        .find(|e| e["list"] == "collisions_vehicle")
        .unwrap();
    assert!(
        unparsed["parse_error"]
            .as_str()
            .unwrap()
            .contains("id is not"),
        "{unparsed}"
    );
    assert!(unparsed["frame"].is_null());
    let far_event = events
        .iter()
        .find(|e| e["list"] == "collisions_layout")
        .unwrap();
    assert!(
        far_event["frame"].is_null() && far_event["aligned_by"].is_null(),
        "{far_event}"
    );
    assert_eq!(odd["collisions"]["unaligned"], 2);
    assert!(odd["ds_safe"].is_number());
    let no_xml = get("RouteScenario_910014_rep0");
    // Not in the route XML: foreign (left out of the aggregates), but still replayed.
    assert_eq!(no_xml["state"], "foreign");
    assert!(no_xml["ds_safe"].is_number());
    assert_eq!(
        no_xml["lateral"]["scored_chunks"], 0,
        "no reference: no lateral error"
    );
    let w = no_xml["warnings"].to_string();
    assert!(
        w.contains("route 910014: not found") && w.contains(&routes_xml.display().to_string()),
        "{w}"
    );
    let dups: Vec<_> = [&dup_a, &dup_b]
        .iter()
        .map(|p| &by_source[&format!("{}#0", p.display())])
        .collect();
    assert!(dups
        .iter()
        .all(|r| r["route_id"] == "RouteScenario_910015_rep0" && r["state"] == "scored"));
    assert!(
        warnings.iter().any(|w| w.contains("scored more than once")
            && w.contains("RouteScenario_910015_rep0")
            && w.contains(&dup_a.display().to_string())
            && w.contains(&dup_b.display().to_string())),
        "{all_warnings}"
    );
    let far_frames = get("RouteScenario_910016_rep0");
    assert_eq!(far_frames["state"], "scored");
    assert_eq!(
        far_frames["lateral"]["scored_chunks"],
        far_frames["lateral"]["chunks"]
    );
    assert_eq!(
        far_frames["lateral"]["critical"],
        far_frames["lateral"]["chunks"]
    );
    assert_eq!(
        by_source[&format!("{}#1", mixed.display())]["state"],
        "scored"
    );
    // The truncated results file: named, with the reason, in the warnings and on stderr.
    let trunc_s = trunc.display().to_string();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains(&trunc_s) && w.contains("truncated JSON")),
        "{all_warnings}"
    );
    assert!(err.contains(&trunc_s), "{err}");
    let trunc_entry = &by_source[&format!("{trunc_s}#0")];
    assert!(trunc_entry["route_id"].is_null());
    let state = full_state(trunc_entry);
    assert!(
        state.starts_with("invalid: ") && state.contains("truncated JSON"),
        "{state}"
    );
    // A directory where metric_info.json should be: not scored, never `ok`.
    let dir_tel = get("RouteScenario_910019_rep0");
    assert_ne!(dir_tel["state"], "scored");
    assert!(dir_tel["ds_safe"].is_null());
    if have_fixtures {
        assert!(
            warnings
                .iter()
                .any(|w| w.contains(&crashed.display().to_string())
                    && w.contains("crashed before any route finished")),
            "{all_warnings}"
        );
    }
    // Summary counts: the 3 invalid records and the unreadable results file.
    assert_eq!(report["summary"]["invalid_records"], 4);
    assert!(
        report["summary"]["mean_ds_safe"].is_null(),
        "not every route was scored"
    );

    // The CSV lists every route too (a header line, then one line per route, broken or not).
    let o = sds(&[
        &"score",
        &"--results",
        &res,
        &"--telemetry",
        &tel,
        &"--routes",
        &routes_xml,
        &"--duplicates",
        &"all",
        &"--format",
        &"csv",
    ]);
    assert_eq!(code(&o), 3);
    let text = String::from_utf8(o.stdout).unwrap();
    assert_eq!(text.lines().count(), expected_routes + 1, "{text}");
}

/// The demo written to `dir/demo`, scored with one change made by `change`.
fn demo_with(dir: &Path, change: impl FnOnce(&Demo)) -> (Output, Option<Value>) {
    let demo = demo(&dir.join("demo"));
    change(&demo);
    score(
        &dir.join("demo/results.json"),
        &demo.telemetry,
        &demo.routes,
        &dir.join("r.json"),
    )
}

#[test]

fn a_directory_named_metric_info_is_reported_as_such() {
    let tmp = tempfile::tempdir().unwrap();
    let mut path = PathBuf::new();
    let (o, report) = demo_with(tmp.path(), |d| {
        let save = d.records[0]["save_name"].as_str().unwrap();
        path = d.telemetry.join(save).join("metric_info.json");
        fs::remove_file(&path).unwrap();
        fs::create_dir(&path).unwrap();
    });
    assert_eq!(code(&o), 3);
    let state = full_state(&report.unwrap()["routes"][0]);
    assert!(
        state.starts_with("invalid: ") && state.contains(&path.display().to_string()),
        "a directory in place of metric_info.json is reported as {state:?}"
    );
}

#[test]

fn a_broken_results_file_is_a_route_problem() {
    let tmp = tempfile::tempdir().unwrap();
    let demo = demo(&tmp.path().join("demo"));
    let res = tmp.path().join("res");
    write_raw(&res.join("a/endpoint.json"), &demo.records[..1]);
    let broken = res.join("b/endpoint.json");
    write_raw(&broken, &demo.records[1..2]);
    let text = fs::read(&broken).unwrap();
    fs::write(&broken, &text[..text.len() / 2]).unwrap();
    let (o, report) = score(
        &res,
        &demo.telemetry,
        &demo.routes,
        &tmp.path().join("r.json"),
    );
    let report = report.expect("report");
    assert!(report["warnings"].to_string().contains("truncated JSON"));
    // Something was lost: the exit code must say so.
    assert_eq!(code(&o), 3, "{}", stderr(&o));
}

#[test]
fn exit_codes() {
    let tmp = tempfile::tempdir().unwrap();
    // 0: a clean run.
    let (o, report) = demo_with(&tmp.path().join("ok"), |_| {});
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(report.unwrap()["routes"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["state"] == "scored"));
    // 3: a route with invalid telemetry; the report is written and the route named.
    let (o, report) = demo_with(&tmp.path().join("bad"), |d| {
        let save = d.records[2]["save_name"].as_str().unwrap();
        fs::write(d.telemetry.join(save).join("metric_info.json"), "{}").unwrap();
    });
    assert_eq!(code(&o), 3);
    let report = report.expect("report written");
    assert!(full_state(&report["routes"][2]).ends_with(": no frames"));
    assert!(stderr(&o).contains("RouteScenario_900003_rep0"));
    // 3 without telemetry; 0 with --allow-missing-telemetry (the route is scored without terms).
    let d = demo(&tmp.path().join("nt"));
    let results = tmp.path().join("nt/results.json");
    let out = tmp.path().join("nt/r.json");
    let o = sds(&[&"score", &"--results", &results, &"-o", &out]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let o = sds(&[
        &"score",
        &"--results",
        &results,
        &"--allow-missing-telemetry",
        &"-o",
        &out,
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let r: Value = serde_json::from_slice(&fs::read(&out).unwrap()).unwrap();
    assert!(r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["ds_safe"].is_number()));
    // 2: usage errors.
    for args in [
        vec!["score"],
        vec!["score", "--results"],
        vec!["score", "--results", "x.json", "--format", "yaml"],
        vec!["frobnicate"],
    ] {
        let o = Command::new(SDS).args(&args).output().unwrap();
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
    }
    // 1: unreadable inputs, each named on stderr, and no report.
    let missing = tmp.path().join("nope.json");
    let junk = tmp.path().join("junk.json");
    fs::write(&junk, "{\"_checkpoint\": {\"records\": [").unwrap();
    let bad_xml = tmp.path().join("bad.xml");
    fs::write(
        &bad_xml,
        "<routes>\n<route id=\"1\"><waypoints></route>\n</routes>",
    )
    .unwrap();
    let cases: Vec<(Vec<&dyn AsRef<std::ffi::OsStr>>, String)> = vec![
        (vec![&"--results", &missing], missing.display().to_string()),
        (vec![&"--results", &junk], junk.display().to_string()),
        (
            vec![
                &"--results",
                &results,
                &"--telemetry",
                &d.telemetry,
                &"--routes",
                &bad_xml,
            ],
            bad_xml.display().to_string(),
        ),
        (
            vec![&"--results", &results, &"--set", &"slack=-1"],
            "slack".into(),
        ),
        (
            vec![&"--results", &results, &"--set", &"decel_window=40"],
            "decel_window".into(),
        ),
        (
            vec![&"--results", &results, &"--set", &"chunk_len=5"],
            "chunk_len".into(),
        ),
    ];
    for (args, named) in cases {
        let out = tmp.path().join("never.json");
        let mut all: Vec<&dyn AsRef<std::ffi::OsStr>> = vec![&"score"];
        all.extend(args);
        all.push(&"-o");
        all.push(&out);
        let o = sds(&all);
        let err = stderr(&o);
        // A bad setting is a usage error (2); an unreadable input 1.
        let settings = ["slack", "decel_window", "chunk_len"].contains(&named.as_str());
        assert_eq!(code(&o), if settings { 2 } else { 1 }, "{named}: {err}");
        assert!(err.contains(&named), "stderr does not name {named}: {err}");
        assert!(
            !out.exists(),
            "a report was written for a failed run ({named})"
        );
    }
    // The malformed XML error gives the line.
    let o = sds(&[&"score", &"--results", &results, &"--routes", &bad_xml]);
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
}

/// Files in `dir` (names).
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_failed_write_leaves_no_partial_report() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("demo"));
    let results = tmp.path().join("demo/results.json");
    let run = |out: &Path| {
        sds(&[
            &"score",
            &"--results",
            &results,
            &"--telemetry",
            &d.telemetry,
            &"-o",
            &out,
        ])
    };
    // Into a folder that does not exist: exit 1, nothing created.
    let out = tmp.path().join("no/such/dir/report.json");
    let o = run(&out);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("no/such/dir"), "{}", stderr(&o));
    assert!(!tmp.path().join("no").exists());
    // Below a regular file: exit 1.
    let file = tmp.path().join("plain");
    fs::write(&file, "x").unwrap();
    let o = run(&file.join("report.json"));
    assert_eq!(code(&o), 1);
    assert_eq!(fs::read(&file).unwrap(), b"x");
    // Onto an existing directory: exit 1, the directory untouched, no temporary file left.
    let outdir = tmp.path().join("out");
    fs::create_dir_all(outdir.join("report.json")).unwrap();
    let before = listing(&outdir);
    let o = run(&outdir.join("report.json"));
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert_eq!(listing(&outdir), before, "a temporary file was left behind");
    assert!(outdir.join("report.json").is_dir());
    // A run that fails (unreadable input) leaves an existing report as it was.
    let old = tmp.path().join("old.json");
    fs::write(&old, "{\"previous\": true}").unwrap();
    let o = sds(&[
        &"score",
        &"--results",
        &tmp.path().join("nope.json"),
        &"-o",
        &old,
    ]);
    assert_eq!(code(&o), 1);
    assert_eq!(fs::read_to_string(&old).unwrap(), "{\"previous\": true}");
    // A successful run replaces it whole.
    let o = run(&old);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&fs::read(&old).unwrap()).unwrap();
    assert_eq!(v["routes"].as_array().unwrap().len(), 9);
}

#[test]
fn a_killed_run_never_leaves_a_half_written_report() {
    // A run long enough to be killed at different moments (while reading, scoring, writing).
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("large");
    let o = sds(&[
        &"demo",
        &dir,
        &"--large",
        &"--large-routes",
        &"12",
        &"--large-frames",
        &"1500",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = tmp.path().join("out").join("report.json");
    fs::create_dir_all(out.parent().unwrap()).unwrap();
    let mut complete = 0;
    for delay_ms in [0u64, 5, 15, 30, 60, 100, 150, 250, 400, 700] {
        let _ = fs::remove_file(&out);
        let mut child = Command::new(SDS)
            .args(["score", "--jobs", "1", "--results"])
            .arg(dir.join("results.json"))
            .arg("--telemetry")
            .arg(dir.join("telemetry"))
            .arg("-o")
            .arg(&out)
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill(); // SIGKILL: no chance to clean up
        let _ = child.wait();
        if let Ok(bytes) = fs::read(&out) {
            let v: Value = serde_json::from_slice(&bytes)
                .unwrap_or_else(|e| panic!("killed after {delay_ms} ms: half-written report: {e}"));
            assert_eq!(v["routes"].as_array().unwrap().len(), 12);
            complete += 1;
        }
        // Only the report itself (no half-written file under its name) may be there; a
        // temporary file of a killed writer is hidden (`.tmp*`) and never named report.json.
        for name in listing(out.parent().unwrap()) {
            assert!(
                name == "report.json" || name.starts_with('.'),
                "stray file {name}"
            );
        }
    }
    eprintln!("{complete} of 10 killed runs had finished writing");
}
