//! `sds merge`, the rerun list and the provenance (issue 36, docs/SCORE.md §13.2): parts scored where
//! the files are, merged into the report `sds score` over all their inputs writes.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{demo, read, run, s, split_demo};

/// `sds score` of `results` into `out` (JSON) with `extra` arguments; asserts exit 0 or 3.
fn score_to(out: &Path, results: &[&Path], extra: &[&str]) -> Value {
    let mut args = vec!["score".to_string()];
    for r in results {
        args.extend(["--results".into(), s(r)]);
    }
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(["-o".into(), s(out)]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = run(&argv);
    assert!(code == 0 || code == 3, "sds {argv:?}: exit {code}\n{err}");
    read(out)
}

/// `sds merge parts -o out`; asserts exit 0.
fn merge_to(out: &Path, parts: &[&Path], extra: &[&str]) -> Value {
    let mut args = vec!["merge".to_string()];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(["-o".into(), s(out)]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = run(&argv);
    assert_eq!(code, 0, "sds {argv:?}:\n{err}");
    read(out)
}

/// Every field but `inputs` and `warnings` equal (the spec's merge contract), with the first
/// difference named.
fn assert_same_report(merged: &Value, scored: &Value, what: &str) {
    let (m, s) = (merged.as_object().unwrap(), scored.as_object().unwrap());
    let keys = |o: &serde_json::Map<String, Value>| -> Vec<String> {
        o.keys()
            .filter(|k| *k != "inputs" && *k != "warnings")
            .cloned()
            .collect()
    };
    assert_eq!(keys(m), keys(s), "{what}: top-level keys");
    for k in keys(s) {
        if k == "routes" {
            let (a, b) = (m[&k].as_array().unwrap(), s[&k].as_array().unwrap());
            assert_eq!(a.len(), b.len(), "{what}: routes");
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                for f in y.as_object().unwrap().keys() {
                    assert_eq!(x.get(f), y.get(f), "{what}: routes[{i}].{f}");
                }
                assert_eq!(x, y, "{what}: routes[{i}]");
            }
        }
        assert_eq!(m[&k], s[&k], "{what}: {k}");
    }
    // The same text too (key order included), but for inputs and warnings.
    let strip = |v: &Value| {
        let mut v = v.clone();
        let o = v.as_object_mut().unwrap();
        o.remove("inputs");
        o.remove("warnings");
        serde_json::to_string(&v).unwrap()
    };
    assert_eq!(strip(merged), strip(scored), "{what}: the report's text");
}

fn demo_args(dir: &Path) -> Vec<String> {
    vec![
        "--telemetry".into(),
        s(&dir.join("telemetry")),
        "--routes".into(),
        s(&dir.join("routes.xml")),
        "--maps".into(),
        s(&dir.join("maps")),
    ]
}

#[test]
fn i36_provenance_names_version_settings_files_and_host() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let results = dir.join("results.json");
    let r = score_to(&dir.join("r.json"), &[&results], &extra);
    let p = &r["inputs"]["provenance"];
    assert_eq!(p["sds_version"], env!("CARGO_PKG_VERSION"));
    let config = serde_json::to_vec(&r["config"]).unwrap();
    assert_eq!(
        p["settings_sha256"],
        monitor_host::provenance::sha256_hex(&config)
    );
    let files = p["files"].as_array().unwrap();
    let roles: Vec<&str> = files.iter().map(|f| f["role"].as_str().unwrap()).collect();
    assert_eq!(roles, ["results", "routes", "map"]);
    let bytes = std::fs::read(&results).unwrap();
    assert_eq!(files[0]["file"], s(&results));
    assert_eq!(files[0]["size"], bytes.len());
    assert_eq!(
        files[0]["sha256"],
        monitor_host::provenance::sha256_hex(&bytes)
    );
    assert!(p["host"].is_string(), "{p}");
    // A changed setting changes the hash; the host is left out on request.
    let mut more = extra.clone();
    more.extend(["--set", "slack=0.5", "--set", "provenance.host=false"]);
    let r2 = score_to(&dir.join("r2.json"), &[&results], &more);
    let p2 = &r2["inputs"]["provenance"];
    assert!(p2["host"].is_null(), "{p2}");
    assert_ne!(p2["settings_sha256"], p["settings_sha256"]);
    assert_eq!(
        r2["config"].get("provenance"),
        None,
        "not a scoring setting"
    );
}

#[test]
fn i36_merge_of_demo_parts_equals_score_over_both() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let pa = score_to(&dir.join("ra.json"), &[&a], &extra);
    let pb = score_to(&dir.join("rb.json"), &[&b], &extra);
    // Each part misses the other's routes: the merge takes the records.
    assert!(pa["summary"]["missing"].as_u64().unwrap() > 0);
    assert!(pb["summary"]["missing"].as_u64().unwrap() > 0);
    let whole = score_to(&dir.join("whole.json"), &[&a, &b], &extra);
    let merged = merge_to(
        &dir.join("m.json"),
        &[&dir.join("ra.json"), &dir.join("rb.json")],
        &[],
    );
    assert_eq!(merged["summary"]["missing"], 0);
    assert_same_report(&merged, &whole, "demo, 2 parts");
    // The merged inputs list each part; each part's warnings are kept, naming it.
    let parts = merged["inputs"]["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 2);
    assert_eq!(parts[0]["file"], s(&dir.join("ra.json")));
    assert_eq!(parts[0]["sds_version"], env!("CARGO_PKG_VERSION"));
    let roles: Vec<&str> = merged["inputs"]["provenance"]["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["role"].as_str().unwrap())
        .collect();
    assert_eq!(roles, ["part", "part"]);
    let pw = pa["warnings"].as_array().unwrap().len() + pb["warnings"].as_array().unwrap().len();
    assert_eq!(merged["warnings"].as_array().unwrap().len(), pw);
    // A part's own warning comes through under its name (the demo's parts may have none).
    let mut warned = pa.clone();
    warned["warnings"] = serde_json::json!(["a warning of part a"]);
    let wa = dir.join("ra-warned.json");
    std::fs::write(&wa, serde_json::to_vec(&warned).unwrap()).unwrap();
    let mw = merge_to(&dir.join("mw.json"), &[&wa, &dir.join("rb.json")], &[]);
    let want = format!("part {}: a warning of part a", s(&wa));
    assert!(
        mw["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w == &want),
        "{}",
        mw["warnings"]
    );
    // A part merged alone is the part itself.
    let alone = merge_to(&dir.join("alone.json"), &[&dir.join("ra.json")], &[]);
    assert_same_report(&alone, &pa, "one part");
}

#[test]
fn i36_merge_of_tfpp_shards_equals_score_and_merge_of_merges() {
    let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml", "tfpp_raw_shards"])
    else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    let extra = [
        "--routes",
        &xml,
        "--allow-missing-telemetry",
        "--protocol",
        "all",
    ];
    let shards: Vec<PathBuf> = (0..8)
        .map(|i| b2d.join(format!("tfpp_raw_shards/eval_bench2drive220_{i}.json")))
        .collect();
    let parts: Vec<PathBuf> = (0..8).map(|i| dir.join(format!("part{i}.json"))).collect();
    for (shard, part) in shards.iter().zip(&parts) {
        let r = score_to(part, &[shard], &extra);
        assert_eq!(r["summary"]["routes"], 220);
    }
    let all: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let whole = score_to(&dir.join("whole.json"), &all, &extra);
    assert_eq!(whole["summary"]["routes_found"], 220);
    let p: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    let merged = merge_to(&dir.join("m8.json"), &p, &[]);
    assert_same_report(&merged, &whole, "8 shards");
    // TransFuser++'s published DS over 220 routes.
    let ds = merged["summary"]["driving_score"].as_f64().unwrap();
    assert!((ds - 84.206).abs() < 1e-3, "DS {ds}");
    let a = merge_to(&dir.join("ma.json"), &p[..4], &[]);
    assert!(a["summary"]["missing"].as_u64().unwrap() > 100);
    merge_to(&dir.join("mb.json"), &p[4..], &[]);
    let ab = merge_to(
        &dir.join("mab.json"),
        &[&dir.join("ma.json"), &dir.join("mb.json")],
        &[],
    );
    assert_same_report(&ab, &whole, "merge of two 4-shard merges");
}

#[test]
fn i36_merge_refuses_parts_with_different_settings_or_route_sets() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let ra = dir.join("ra.json");
    score_to(&ra, &[&a], &extra);
    let mut slack = extra.clone();
    slack.extend(["--set", "slack=0.5"]);
    let rb = dir.join("rb_slack.json");
    score_to(&rb, &[&b], &slack);
    let (code, err) = run(&["merge", &s(&ra), &s(&rb)]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("different settings: slack is") && err.contains("rb_slack.json"),
        "{err}"
    );
    // Without --routes: another route set.
    let rc = dir.join("rb_noxml.json");
    score_to(
        &rc,
        &[&b],
        &[
            "--telemetry",
            &s(&dir.join("telemetry")),
            "--maps",
            &s(&dir.join("maps")),
        ],
    );
    let (code, err) = run(&["merge", &s(&ra), &s(&rc)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("different route sets"), "{err}");
    // --route-subset found keeps each part's own routes: other route sets.
    let mut found = extra.clone();
    found.extend(["--route-subset", "found"]);
    let fa = dir.join("fa.json");
    let fb = dir.join("fb.json");
    score_to(&fa, &[&a], &found);
    score_to(&fb, &[&b], &found);
    let (code, err) = run(&["merge", &s(&fa), &s(&fb)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("different route sets"), "{err}");
}

#[test]
fn i36_merge_duplicates_across_parts_follow_the_policy() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let ra = dir.join("ra.json");
    let rb = dir.join("rb.json");
    let whole = dir.join("whole_part.json");
    score_to(&ra, &[&a], &extra);
    score_to(&rb, &[&b], &extra);
    // A part holding every route beside one holding the first four: four duplicated ids.
    let w = score_to(&whole, &[&a, &b], &extra);
    let (code, err) = run(&["merge", &s(&ra), &s(&whole)]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("has a record in")
            && err.contains("ra.json")
            && err.contains("whole_part.json"),
        "{err}"
    );
    assert!(err.contains("4 duplicated route id(s)"), "{err}");
    let first = merge_to(
        &dir.join("first.json"),
        &[&ra, &whole],
        &["--duplicates", "first"],
    );
    assert_eq!(first["summary"], w["summary"]);
    let dropped = first["dropped"].as_array().unwrap();
    assert_eq!(dropped.len(), 4);
    assert_eq!(dropped[0]["kept"]["file"], s(&a));
    let last = merge_to(
        &dir.join("last.json"),
        &[&ra, &whole],
        &["--duplicates", "last"],
    );
    assert_eq!(last["summary"], w["summary"]);
    let all = merge_to(
        &dir.join("all.json"),
        &[&ra, &whole],
        &["--duplicates", "all"],
    );
    assert_eq!(
        all["routes"].as_array().unwrap().len(),
        w["routes"].as_array().unwrap().len() + 4
    );
}

#[test]
fn i36_merge_refuses_a_part_that_is_not_a_report() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let ra = dir.join("ra.json");
    score_to(&ra, &[&dir.join("results.json")], &extra);
    // A results file is not a report.
    let (code, err) = run(&["merge", &s(&ra), &s(&dir.join("results.json"))]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("results.json: not an sds report"), "{err}");
    // Another schema, and a report whose row is not what a report writes.
    let mut v = read(&ra);
    v["schema"] = "sds-compare/1".into();
    let other = dir.join("other.json");
    std::fs::write(&other, v.to_string()).unwrap();
    let (code, err) = run(&["merge", &s(&other)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("schema sds-compare/1"), "{err}");
    let mut v = read(&ra);
    v["routes"][2]["comfort"]["score"] = "high".into();
    let broken = dir.join("broken.json");
    std::fs::write(&broken, v.to_string()).unwrap();
    let (code, err) = run(&["merge", &s(&broken)]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("routes[2].comfort.score: expected a number"),
        "{err}"
    );
    let (code, err) = run(&["merge", &s(&dir.join("nope.json"))]);
    assert_eq!(code, 1, "{err}");
}

#[test]
fn i36_rerun_list_names_crashed_and_missing_routes_of_the_fixtures() {
    let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml", "tfpp_raw_shards"])
    else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    let lines = |p: &Path| -> Vec<(String, String)> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .map(|l| {
                let (id, why) = l.split_once('\t').expect("id<TAB>reason");
                (id.to_string(), why.to_string())
            })
            .collect()
    };
    // UniAD-Base lacks two routes; its 71 TickRuntime records are the agent's outcome, not
    // crashes (v1.5: Bench2Drive's resume rule; campaign.rs checks them in full).
    let list = dir.join("uniad.tsv");
    let l = s(&list);
    score_to(
        &dir.join("uniad.json"),
        &[&b2d.join("b2dzoo_UniAD-Base_merged.json")],
        &[
            "--routes",
            &xml,
            "--allow-missing-telemetry",
            "--rerun-list",
            &l,
        ],
    );
    let got = lines(&list);
    let missing: Vec<&str> = got
        .iter()
        .filter(|(_, w)| w == "missing")
        .map(|(id, _)| id.as_str())
        .collect();
    assert_eq!(missing, ["3800", "23670"]);
    assert_eq!(got.len(), 2);
    // LEAD's per-route files: 9 crashed before writing a record (no record: missing), and
    // records whose status says the simulation crashed.
    let list = dir.join("lead.tsv");
    let l = s(&list);
    let r = score_to(
        &dir.join("lead.json"),
        &[&b2d.join("lead_tfv6_per_route")],
        &[
            "--routes",
            &xml,
            "--allow-missing-telemetry",
            "--rerun-list",
            &l,
        ],
    );
    let got = lines(&list);
    assert_eq!(got.iter().filter(|(_, w)| w == "missing").count(), 9);
    let crashed_statuses = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| {
            r["status"]
                .as_str()
                .is_some_and(|s| s == "Failed - Simulation crashed")
        })
        .count();
    assert!(crashed_statuses > 0);
    assert_eq!(
        got.iter()
            .filter(|(_, w)| w == "simulation-crashed")
            .count(),
        crashed_statuses
    );
    // Every id is a route XML id (what --routes-subset reads).
    assert!(got
        .iter()
        .all(|(id, _)| !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit())));
}

#[test]
fn i36_rerun_list_of_a_merge_names_the_routes_no_part_ran() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, _) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let ra = dir.join("ra.json");
    let pa = score_to(&ra, &[&a], &extra);
    let list = dir.join("rerun.tsv");
    merge_to(&dir.join("m.json"), &[&ra], &["--rerun-list", &s(&list)]);
    let text = std::fs::read_to_string(&list).unwrap();
    let want: Vec<String> = pa["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] == "missing")
        .map(|r| {
            let id = r["route_id"].as_str().unwrap();
            let xml = id
                .trim_start_matches("RouteScenario_")
                .split("_rep")
                .next()
                .unwrap();
            format!("{xml}\tmissing\n")
        })
        .collect();
    assert!(!want.is_empty());
    assert_eq!(text, want.concat());
}

#[test]
fn i36_watch_writes_the_rerun_list_when_it_stops() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, _) = split_demo(dir, 4);
    let list = dir.join("rerun.tsv");
    let out = dir.join("live.json");
    let mut args = vec![
        "watch".to_string(),
        "--once".into(),
        "--results".into(),
        s(&a),
        "-o".into(),
        s(&out),
        "--rerun-list".into(),
        s(&list),
    ];
    args.extend(demo_args(dir));
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = run(&argv);
    assert!(code == 0 || code == 3, "{err}");
    let report = read(&out);
    let missing = report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] == "missing")
        .count();
    let text = std::fs::read_to_string(&list).unwrap();
    assert_eq!(text.lines().count(), missing, "{text}");
    assert!(missing > 0 && text.lines().all(|l| l.ends_with("\tmissing")));
}

#[test]
fn i36_merge_says_when_parts_were_scored_by_different_versions() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let ra = dir.join("ra.json");
    let rb = dir.join("rb.json");
    score_to(&ra, &[&a], &extra);
    let mut v = score_to(&rb, &[&b], &extra);
    v["inputs"]["provenance"]["sds_version"] = "0.0.9".into();
    std::fs::write(&rb, v.to_string()).unwrap();
    let m = merge_to(&dir.join("m.json"), &[&ra, &rb], &[]);
    let w: Vec<&str> = m["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .filter(|w| w.contains("different sds versions"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", m["warnings"]);
    assert!(
        w[0].contains(&format!("{}: {}", env!("CARGO_PKG_VERSION"), s(&ra)))
            && w[0].contains(&format!("0.0.9: {}", s(&rb))),
        "{}",
        w[0]
    );
    assert_eq!(m["inputs"]["parts"][1]["sds_version"], "0.0.9");
}

/// `sds merge --tables DIR` writes the routes and events long tables of the merged rows, equal
/// byte for byte to those of `sds score --tables` over the union of the parts' inputs; no
/// frames (a merge reads no telemetry), while `score` has them.
#[test]
fn i36_merge_tables_equal_score_tables_over_the_union() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    score_to(&dir.join("ra.json"), &[&a], &extra);
    score_to(&dir.join("rb.json"), &[&b], &extra);
    let (st, mt) = (dir.join("score_tables"), dir.join("merge_tables"));
    let mut with = extra.clone();
    let st_s = s(&st);
    with.extend(["--tables", &st_s]);
    score_to(&dir.join("whole.json"), &[&a, &b], &with);
    let mt_s = s(&mt);
    merge_to(
        &dir.join("m.json"),
        &[&dir.join("ra.json"), &dir.join("rb.json")],
        &["--tables", &mt_s],
    );
    for name in ["routes.csv", "events.csv"] {
        let (x, y) = (
            std::fs::read_to_string(st.join(name)).unwrap(),
            std::fs::read_to_string(mt.join(name)).unwrap(),
        );
        assert!(y.lines().count() > 1, "{name}: no rows\n{y}");
        assert_eq!(y, x, "{name}");
    }
    assert_eq!(
        std::fs::read_to_string(mt.join("routes.csv"))
            .unwrap()
            .lines()
            .count(),
        1 + read(&dir.join("m.json"))["routes"]
            .as_array()
            .unwrap()
            .len()
    );
    assert!(st.join("frames.csv").exists());
    assert!(!mt.join("frames.csv").exists());
    // -o among the tables is refused before any work.
    let clash = s(&mt.join("routes.csv"));
    let (code, err) = run(&[
        "merge",
        &s(&dir.join("ra.json")),
        "--tables",
        &mt_s,
        "-o",
        &clash,
    ]);
    assert_eq!(code, 2, "{err}");
}

/// `sds compare` over runs given as `sds` reports (scored elsewhere: a merged sharded
/// evaluation) reads them back, and says when runs were scored by different `sds` versions or
/// settings (from `inputs.provenance` and `config`), naming the runs and the first setting that
/// differs; runs scored alike say nothing, and a report run compares as its results file would.
#[test]
fn i36_compare_says_when_runs_were_scored_by_other_versions_or_settings() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let results = dir.join("results.json");
    let r1 = dir.join("r1.json");
    score_to(&r1, &[&results], &extra);
    let mut slack = extra.clone();
    slack.extend(["--set", "slack=0.5"]);
    let r2 = dir.join("r2.json");
    score_to(&r2, &[&results], &slack);
    let mut v = read(&r1);
    v["inputs"]["provenance"]["sds_version"] = "0.0.9".into();
    let r3 = dir.join("r3.json");
    std::fs::write(&r3, serde_json::to_vec_pretty(&v).unwrap()).unwrap();
    let compare = |runs: &[String]| -> Value {
        let out = dir.join("c.json");
        let mut args: Vec<&str> = vec!["compare", "--bootstrap-samples", "1000"];
        args.extend(runs.iter().map(String::as_str));
        // `sds compare` takes each run's telemetry with the run (RESULTS:TELEMETRY).
        args.extend(&extra[2..]);
        let o = s(&out);
        args.extend(["--format", "json", "-o", &o]);
        let (code, err) = run(&args);
        assert_eq!(code, 0, "{args:?}\n{err}");
        read(&out)
    };
    let about = |c: &Value| -> Vec<String> {
        c["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(Value::as_str)
            .filter(|w| w.contains("were scored"))
            .map(String::from)
            .collect()
    };
    let settings = compare(&[format!("base={}", s(&r1)), format!("other={}", s(&r2))]);
    let w = about(&settings);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("runs base and other were scored with different settings: slack is ")
            && w[0].contains(" in base and 0.5 in other"),
        "{}",
        w[0]
    );
    let version = compare(&[format!("base={}", s(&r1)), format!("old={}", s(&r3))]);
    let w = about(&version);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("runs base and old were scored by different sds versions")
            && w[0].contains(&format!("({} and 0.0.9)", env!("CARGO_PKG_VERSION"))),
        "{}",
        w[0]
    );
    // A report beside its own results file, scored alike: no warning, and the same figures.
    let alike = compare(&[
        format!("file={}:{}", s(&results), s(&dir.join("telemetry"))),
        format!("report={}", s(&r1)),
    ]);
    assert!(about(&alike).is_empty(), "{:?}", alike["warnings"]);
    let ds = alike["paired"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["metric"] == "ds")
        .unwrap();
    assert_eq!(ds["delta"], 0.0, "{ds}");
    assert_eq!(
        alike["models"][0]["driving_score"],
        alike["models"][1]["driving_score"]
    );
}

#[test]
fn i48_2_real_reports_read_back_byte_for_byte() {
    // Every real results set scored as a report (every protocol, the route XML, a breakdown by
    // scenario), then read back by the types that wrote it: written again, the same bytes.
    let Some(b2d) = crate::common::b2d_fixtures(&["routes/bench2drive220.xml", "tfpp_raw_shards"])
    else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    let inputs = [
        "b2dzoo_UniAD-Base_merged.json",
        "b2dzoo_VAD_merged.json",
        "carla_garage_pdm_lite_b2d_traj_merged.json",
        "simlingo_bench2drive220_targetpoint_checkpoint.json",
        "lead_tfv6_per_route",
        "tfpp_raw_shards",
    ];
    for (i, name) in inputs.iter().enumerate() {
        let out = tmp.path().join(format!("r{i}.json"));
        let mut extra = vec![
            "--routes",
            &xml,
            "--allow-missing-telemetry",
            "--protocol",
            "all",
        ];
        // One with the duplicates policy's `kept` and `dropped` (LEAD's per-route files hold
        // no duplicates; the shards, read twice, do).
        let shards = s(&b2d.join("tfpp_raw_shards"));
        if *name == "tfpp_raw_shards" {
            extra.extend(["--results", &shards, "--duplicates", "last"]);
        } else {
            extra.extend(["--group-by", "scenario"]);
        }
        score_to(&out, &[&b2d.join(name)], &extra);
        let bytes = std::fs::read(&out).unwrap();
        let back = monitor_host::Report::read(&out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let again = monitor_host::report::json::json(&back).unwrap();
        assert!(
            again == bytes,
            "{name}: read back and written again, it differs"
        );
        if *name == "tfpp_raw_shards" {
            assert!(!back.dropped.is_empty() && back.routes.iter().any(|r| r.kept.is_some()));
        } else {
            assert!(back.groups.is_some(), "{name}");
        }
        assert!(back.summary.protocols.is_some(), "{name}");
    }
}

#[test]
fn i48_2_collisions_placed_by_log_time_merge() {
    // A vehicle log's collisions are aligned by `log time` (`sds score --mcap`); the hand reader
    // that merge had knew every other way an event is placed but not this one, and refused such
    // a part. The demo's collisions, placed as a log places them:
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let scored = dir.join("scored.json");
    let mut v = score_to(&scored, &[&dir.join("results.json")], &extra);
    let mut placed = 0;
    for r in v["routes"].as_array_mut().unwrap() {
        for e in r["collision_events"].as_array_mut().unwrap() {
            if !e["aligned_by"].is_null() {
                e["aligned_by"] = "log time".into();
            }
        }
        for e in r["events"].as_array_mut().unwrap() {
            if e["kind"] == "collision" && !e["placed_by"].is_null() {
                e["placed_by"] = "log time".into();
                placed += 1;
            }
        }
    }
    assert!(placed > 0, "the demo has aligned collisions");
    let part = dir.join("log-part.json");
    std::fs::write(&part, v.to_string()).unwrap();
    let merged = merge_to(&dir.join("m.json"), &[&part], &[]);
    let kept = merged["routes"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r["events"].as_array().unwrap())
        .filter(|e| e["placed_by"] == "log time")
        .count();
    assert_eq!(kept, placed);
}

/// Review of issue 48, item 4: a part's note (the demo's 10 Hz route, whose step period is
/// inferred) is read back as a note: the merged report keeps it under the part's name, and
/// `sds merge` prints it as `sds: note: `, not as a warning; a merge of that merge too.
#[test]
fn i48_r4_a_parts_note_is_merged_and_printed_as_a_note() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let extra = demo_args(dir);
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let part = dir.join("part.json");
    let scored = score_to(&part, &[&dir.join("results.json")], &extra);
    let note = "step period inferred as 0.1 s";
    assert!(
        scored["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().starts_with(note)),
        "{}",
        scored["warnings"]
    );
    let merged = dir.join("m.json");
    let again = dir.join("mm.json");
    for (parts, out, said) in [
        (&part, &merged, format!("part {}: {note}", s(&part))),
        (
            &merged,
            &again,
            format!("part {}: part {}: {note}", s(&merged), s(&part)),
        ),
    ] {
        let (code, err) = run(&["merge", &s(parts), "-o", &s(out)]);
        assert_eq!(code, 0, "{err}");
        let v = read(out);
        assert!(
            v["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .any(|w| w.as_str().unwrap().starts_with(&said)),
            "{}",
            v["warnings"]
        );
        assert!(err.contains(&format!("sds: note: {said}")), "{err}");
        assert!(!err.contains(&format!("sds: warning: {said}")), "{err}");
    }
}
