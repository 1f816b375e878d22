//! A campaign a lab can trust (issue 46 items 1, 2, 3 and 6; issue 47 findings 2, 7 and 8):
//! the rerun list and route XML of Bench2Drive's resume rule, merges refused when their parts
//! were scored differently or edited, and the rerun files inside the output unit.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::{b2d_fixtures, demo, read, run, s, split_demo};

/// `sds score` of `results` into `out` (JSON) with `extra`; asserts exit 0 or 3; returns the
/// report and standard error.
fn score_to(out: &Path, results: &[&Path], extra: &[&str]) -> (Value, String) {
    let mut args = vec!["score".to_string()];
    for r in results {
        args.extend(["--results".into(), s(r)]);
    }
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(["-o".into(), s(out)]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = run(&argv);
    assert!(code == 0 || code == 3, "sds {argv:?}: exit {code}\n{err}");
    (read(out), err)
}

/// `sds merge parts -o out extra`: (exit code, stderr).
fn merge(out: &Path, parts: &[&Path], extra: &[&str]) -> (i32, String) {
    let mut args = vec!["merge".to_string()];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(["-o".into(), s(out)]);
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    run(&argv)
}

/// The lines of a rerun list: (id, reason).
fn lines(p: &Path) -> Vec<(String, String)> {
    std::fs::read_to_string(p)
        .unwrap()
        .lines()
        .map(|l| {
            let (id, why) = l.split_once('\t').expect("id<TAB>reason");
            (id.to_string(), why.to_string())
        })
        .collect()
}

/// The XML ids of the records of `results` (files or per-route folders) whose status is
/// `status`.
fn ids_with_status(results: &Path, status: &str) -> Vec<String> {
    let files: Vec<PathBuf> = if results.is_dir() {
        std::fs::read_dir(results)
            .unwrap()
            .map(|e| e.unwrap().path().join("checkpoint_endpoint.json"))
            .collect()
    } else {
        vec![results.to_path_buf()]
    };
    let mut out = Vec::new();
    for f in files {
        for r in read(&f)["_checkpoint"]["records"].as_array().unwrap() {
            if r["status"] == status {
                let id = r["route_id"].as_str().unwrap();
                out.push(
                    id.trim_start_matches("RouteScenario_")
                        .split("_rep")
                        .next()
                        .unwrap()
                        .to_string(),
                );
            }
        }
    }
    out.sort();
    out
}

/// Scores `results` against the 220-route XML with `--rerun-list` (and `extra`); returns the
/// list's lines.
fn rerun_list_of(
    dir: &Path,
    name: &str,
    results: &[&Path],
    extra: &[&str],
) -> Vec<(String, String)> {
    let b2d = b2d_fixtures(&[]).unwrap();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    let list = dir.join(format!("{name}.tsv"));
    let l = s(&list);
    let mut args = vec![
        "--routes",
        &xml,
        "--allow-missing-telemetry",
        "--rerun-list",
        &l,
    ];
    args.extend_from_slice(extra);
    score_to(&dir.join(format!("{name}.json")), results, &args);
    lines(&list)
}

fn count(got: &[(String, String)], why: &str) -> usize {
    got.iter().filter(|(_, w)| w == why).count()
}

#[test]
fn i46_1_rerun_lists_of_the_real_runs_name_no_tickruntime_route_unless_asked() {
    let Some(b2d) = b2d_fixtures(&[
        "routes/bench2drive220.xml",
        "tfpp_raw_shards",
        "b2dzoo_UniAD-Base_merged.json",
        "b2dzoo_VAD_merged.json",
        "b2dzoo_TCP-only-traj_merged.json",
        "lead_tfv6_per_route",
    ]) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // (file, missing routes, other reasons expected by default)
    type Expected<'a> = (&'a str, usize, &'a [(&'a str, usize)]);
    let zoo: [Expected; 3] = [
        ("b2dzoo_UniAD-Base_merged.json", 2, &[]),
        ("b2dzoo_VAD_merged.json", 7, &[]),
        (
            "b2dzoo_TCP-only-traj_merged.json",
            10,
            &[("agent-setup", 2)],
        ),
    ];
    for (name, missing, others) in zoo {
        let file = b2d.join(name);
        let timeouts = ids_with_status(&file, "Failed - TickRuntime");
        assert!(
            timeouts.len() > 40,
            "{name}: {} TickRuntime records",
            timeouts.len()
        );
        let got = rerun_list_of(dir, name, &[&file], &[]);
        assert!(
            got.iter().all(|(id, _)| !timeouts.contains(id)),
            "{name}: a TickRuntime route is listed: {got:?}"
        );
        assert_eq!(count(&got, "missing"), missing, "{name}: {got:?}");
        for (why, n) in others {
            assert_eq!(count(&got, why), *n, "{name}: {got:?}");
        }
        assert_eq!(
            got.len(),
            missing + others.iter().map(|(_, n)| n).sum::<usize>()
        );
        // On request, every TickRuntime route is listed, as a timeout.
        let with = rerun_list_of(dir, &format!("{name}_t"), &[&file], &["--rerun-timeouts"]);
        let mut listed: Vec<String> = with
            .iter()
            .filter(|(_, w)| w == "timeout")
            .map(|(id, _)| id.clone())
            .collect();
        listed.sort();
        assert_eq!(listed, timeouts, "{name}");
        assert_eq!(with.len(), got.len() + timeouts.len());
    }
    // The 8 TransFuser++ shards, together and each scored with the route XML.
    let shards: Vec<PathBuf> = (0..8)
        .map(|i| b2d.join(format!("tfpp_raw_shards/eval_bench2drive220_{i}.json")))
        .collect();
    let timeouts: Vec<String> = shards
        .iter()
        .flat_map(|f| ids_with_status(f, "Failed - TickRuntime"))
        .collect();
    assert_eq!(timeouts.len(), 7);
    let all: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    assert!(rerun_list_of(dir, "tfpp", &all, &[]).is_empty());
    assert_eq!(
        count(
            &rerun_list_of(dir, "tfpp_t", &all, &["--rerun-timeouts"]),
            "timeout"
        ),
        7
    );
    // Each shard scored with the route XML (the documented sharded path): its own TickRuntime
    // routes are not listed; the routes of the other shards are missing from it.
    for (i, shard) in shards.iter().enumerate() {
        let own = ids_with_status(shard, "Failed - TickRuntime");
        let got = rerun_list_of(dir, &format!("shard{i}"), &[shard], &[]);
        assert!(
            got.iter()
                .all(|(id, w)| w == "missing" && !own.contains(id)),
            "shard {i}"
        );
        let records = read(shard)["_checkpoint"]["records"]
            .as_array()
            .unwrap()
            .len();
        assert_eq!(got.len(), 220 - records, "shard {i}");
    }
    // LEAD's per-route files: 9 crashed before writing a record, 9 records say the simulation
    // crashed (Bench2Drive's resume rule runs both again), 4 ran out of ticks (it does not).
    let lead = b2d.join("lead_tfv6_per_route");
    let got = rerun_list_of(dir, "lead", &[&lead], &[]);
    assert_eq!(count(&got, "missing"), 9);
    let crashed = ids_with_status(&lead, "Failed - Simulation crashed");
    assert_eq!(crashed.len(), 9);
    let mut listed: Vec<String> = got
        .iter()
        .filter(|(_, w)| w == "simulation-crashed")
        .map(|(id, _)| id.clone())
        .collect();
    listed.sort();
    assert_eq!(listed, crashed);
    assert_eq!(got.len(), 18);
    // Every id is a route XML id (what --routes-subset reads).
    assert!(got
        .iter()
        .all(|(id, _)| id.bytes().all(|b| b.is_ascii_digit())));
}

#[test]
fn i46_1_the_watch_crash_figure_counts_the_rerun_classes() {
    let Some(b2d) = b2d_fixtures(&[
        "routes/bench2drive220.xml",
        "lead_tfv6_per_route",
        "b2dzoo_UniAD-Base_merged.json",
    ]) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    // (results, crashes): UniAD-Base's 71 TickRuntime routes are no crash; LEAD's 9 records
    // whose simulation crashed are.
    for (results, want) in [
        (b2d.join("b2dzoo_UniAD-Base_merged.json"), 0),
        (b2d.join("lead_tfv6_per_route"), 9),
    ] {
        let out = tmp.path().join("live.json");
        let (code, err) = run(&[
            "watch",
            "--once",
            "--status-json",
            "--results",
            &s(&results),
            "--routes",
            &xml,
            "--allow-missing-telemetry",
            "-o",
            &s(&out),
        ]);
        assert!(code == 0 || code == 3, "{err}");
        let last: Value = err
            .lines()
            .rfind(|l| l.starts_with('{'))
            .map(|l| serde_json::from_str(l).unwrap())
            .expect("a status line");
        assert_eq!(last["crashes"], want, "{}: {last}", results.display());
    }
}

/// A route parser written from Bench2Drive's route file format (not its code): `<routes>` of
/// `<route id town>`, each with `<waypoints>` of `<position x y z>`, `<scenarios>` of
/// `<scenario name type>` with a `<trigger_point x y z yaw>`, and `<weathers>` of `<weather
/// route_percentage ...>` keyframes. Like the evaluator, it refuses a subset id not in the file.
fn parse_b2d_routes(text: &str, subset: &[String]) -> Result<Vec<(String, String, usize)>, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| e.to_string())?;
    let root = doc.root_element();
    if root.tag_name().name() != "routes" {
        return Err(format!("root <{}>", root.tag_name().name()));
    }
    let mut out = Vec::new();
    for route in root.children().filter(|n| n.has_tag_name("route")) {
        let id = route
            .attribute("id")
            .ok_or("a route without id")?
            .to_string();
        let town = route
            .attribute("town")
            .ok_or("a route without town")?
            .to_string();
        let child = |name: &str| {
            route
                .children()
                .find(|n| n.has_tag_name(name))
                .ok_or(format!("route {id}: no <{name}>"))
        };
        let mut points = 0;
        for p in child("waypoints")?.children().filter(|n| n.is_element()) {
            for a in ["x", "y", "z"] {
                p.attribute(a)
                    .ok_or(format!("route {id}: a position without {a}"))?
                    .parse::<f64>()
                    .map_err(|e| format!("route {id}: {e}"))?;
            }
            points += 1;
        }
        for sc in child("scenarios")?.children().filter(|n| n.is_element()) {
            sc.attribute("name").ok_or("a scenario without name")?;
            sc.attribute("type").ok_or("a scenario without type")?;
            let t = sc
                .children()
                .find(|n| n.has_tag_name("trigger_point"))
                .ok_or(format!("route {id}: a scenario without trigger_point"))?;
            for a in ["x", "y", "z", "yaw"] {
                t.attribute(a)
                    .ok_or(format!("route {id}: trigger_point {a}"))?;
            }
        }
        for w in child("weathers")?.children().filter(|n| n.is_element()) {
            w.attribute("route_percentage")
                .ok_or(format!("route {id}: a weather without route_percentage"))?;
        }
        out.push((id, town, points));
    }
    if let Some(id) = subset
        .iter()
        .find(|id| !out.iter().any(|(r, _, _)| r == *id))
    {
        return Err(format!("route id {id} is not in the route file"));
    }
    Ok(out)
}

#[test]
fn i46_1_rerun_xml_is_a_bench2drive_route_file_of_the_listed_routes() {
    let Some(b2d) = b2d_fixtures(&["routes/bench2drive220.xml", "b2dzoo_UniAD-Base_merged.json"])
    else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let xml_path = b2d.join("routes/bench2drive220.xml");
    let input = std::fs::read_to_string(&xml_path).unwrap();
    let (list, xml) = (dir.join("rerun.tsv"), dir.join("rerun.xml"));
    let (_, err) = score_to(
        &dir.join("r.json"),
        &[&b2d.join("b2dzoo_UniAD-Base_merged.json")],
        &[
            "--routes",
            &s(&xml_path),
            "--allow-missing-telemetry",
            "--rerun-timeouts",
            "--rerun-list",
            &s(&list),
            "--rerun-xml",
            &s(&xml),
        ],
    );
    assert!(err.contains("wrote 73 route(s) to run again"), "{err}");
    let ids: Vec<String> = lines(&list).into_iter().map(|(id, _)| id).collect();
    assert_eq!(ids.len(), 73);
    let text = std::fs::read_to_string(&xml).unwrap();
    let routes = parse_b2d_routes(&text, &ids).unwrap();
    let mut got: Vec<&str> = routes.iter().map(|(id, _, _)| id.as_str()).collect();
    let mut want: Vec<&str> = ids.iter().map(String::as_str).collect();
    got.sort();
    want.sort();
    assert_eq!(got, want);
    // Each <route> element byte for byte as in the input, in the input's order.
    let whole = parse_b2d_routes(&input, &[]).unwrap();
    assert_eq!(whole.len(), 220);
    let element = |t: &str, id: &str| -> String {
        let start = t.find(&format!("<route id=\"{id}\"")).unwrap();
        let end = start + t[start..].find("</route>").unwrap() + "</route>".len();
        t[start..end].to_string()
    };
    let mut last = 0;
    for (id, _, _) in &routes {
        assert_eq!(element(&text, id), element(&input, id), "route {id}");
        let at = input.find(&format!("<route id=\"{id}\"")).unwrap();
        assert!(at > last, "route {id} out of the input's order");
        last = at;
    }
    // The parser refuses an id that is not in the file, as Bench2Drive's evaluator does.
    assert!(parse_b2d_routes(&text, &["1711".into()]).is_err() || ids.contains(&"1711".into()));
    // Without --routes there is no route XML to restrict.
    let (code, err) = run(&[
        "score",
        "--results",
        &s(&b2d.join("b2dzoo_UniAD-Base_merged.json")),
        "--rerun-xml",
        &s(&dir.join("x.xml")),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--routes"), "{err}");
}

fn demo_args(dir: &Path) -> Vec<String> {
    vec![
        "--telemetry".into(),
        s(&dir.join("telemetry")),
        "--routes".into(),
        s(&dir.join("routes.xml")),
    ]
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[test]
fn i46_2_merge_refuses_parts_scored_with_other_maps_route_xml_or_labels() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let base = demo_args(dir);
    let maps = [base.clone(), vec!["--maps".into(), s(&dir.join("maps"))]].concat();
    let (pa, pb, pc) = (
        dir.join("pa.json"),
        dir.join("pb.json"),
        dir.join("pc.json"),
    );
    score_to(&pa, &[&a], &strs(&maps));
    score_to(&pb, &[&b], &strs(&maps));
    score_to(&pc, &[&b], &strs(&base));
    let out = dir.join("m.json");
    assert_eq!(merge(&out, &[&pa, &pb], &[]).0, 0);
    let sha = |p: &Path| monitor_host::provenance::sha256_hex(&std::fs::read(p).unwrap());
    let map_sha = sha(&dir.join("maps/DemoTown.xodr"));
    // With a map and without one, for a town both parts drove in.
    let (code, err) = merge(&out, &[&pa, &pc], &[]);
    assert_eq!(code, 2, "{err}");
    for want in ["pa.json", "pc.json", "map of DemoTown", &map_sha, "no map"] {
        assert!(err.contains(want), "{want}: {err}");
    }
    // Another map's bytes.
    let maps2 = dir.join("maps2");
    std::fs::create_dir(&maps2).unwrap();
    let mut map = std::fs::read_to_string(dir.join("maps/DemoTown.xodr")).unwrap();
    map.push_str("\n<!-- edited -->\n");
    std::fs::write(maps2.join("DemoTown.xodr"), map).unwrap();
    let pd = dir.join("pd.json");
    score_to(
        &pd,
        &[&b],
        &strs(&[base.clone(), vec!["--maps".into(), s(&maps2)]].concat()),
    );
    let (code, err) = merge(&out, &[&pa, &pd], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("map of DemoTown")
            && err.contains(&map_sha)
            && err.contains(&sha(&maps2.join("DemoTown.xodr"))),
        "{err}"
    );
    // A route XML with one waypoint edited: the same route set, other bytes.
    let xml = std::fs::read_to_string(dir.join("routes.xml")).unwrap();
    let at = xml.find("<position x=\"").unwrap() + "<position x=\"".len();
    let edited = format!("{}1{}", &xml[..at], &xml[at..]);
    let xml2 = dir.join("routes2.xml");
    std::fs::write(&xml2, edited).unwrap();
    let pe = dir.join("pe.json");
    score_to(
        &pe,
        &[&b],
        &[
            "--telemetry",
            &s(&dir.join("telemetry")),
            "--routes",
            &s(&xml2),
            "--maps",
            &s(&dir.join("maps")),
        ],
    );
    let (code, err) = merge(&out, &[&pa, &pe], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("route XML")
            && err.contains(&sha(&dir.join("routes.xml")))
            && err.contains(&sha(&xml2)),
        "{err}"
    );
    // A label file in one part only.
    let fam = dir.join("families.json");
    std::fs::write(&fam, r#"{"DemoCrashBraking": "crash"}"#).unwrap();
    let pf = dir.join("pf.json");
    score_to(
        &pf,
        &[&b],
        &strs(&[maps.clone(), vec!["--families".into(), s(&fam)]].concat()),
    );
    let (code, err) = merge(&out, &[&pa, &pf], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("label files") && err.contains(&sha(&fam)),
        "{err}"
    );
}

/// The demo's results with the record at `index` re-run: its `save_name` stamp set to `stamp`.
fn rerun_copy(dir: &Path, name: &str, index: usize, stamp: &str) -> PathBuf {
    let mut d = read(&dir.join("results.json"));
    let rec = d["_checkpoint"]["records"][index].clone();
    let save = rec["save_name"].as_str().unwrap();
    let cut: Vec<&str> = save.rsplitn(6, '_').collect();
    let new = format!("{}_{stamp}", cut[5]);
    let mut rec = rec.clone();
    rec["save_name"] = new.clone().into();
    // Its telemetry under the re-run's own folder name.
    let (from, to) = (
        dir.join("telemetry").join(save),
        dir.join("telemetry").join(&new),
    );
    std::fs::create_dir(&to).unwrap();
    for e in std::fs::read_dir(&from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
    d["_checkpoint"]["records"] = Value::Array(vec![rec]);
    d["_checkpoint"]["progress"] = serde_json::json!([1, 1]);
    let p = dir.join(name);
    std::fs::write(&p, d.to_string()).unwrap();
    p
}

#[test]
fn i46_2_merge_duplicates_newest_works_across_parts_and_states_its_rule() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let args = demo_args(dir);
    let results = dir.join("results.json");
    // A re-run of record 2 with a stamp later than any of the run's, given FIRST.
    let rerun = rerun_copy(dir, "rerun.json", 2, "12_30_23_59_00");
    let d = read(&results);
    let old_save = d["_checkpoint"]["records"][2]["save_name"]
        .as_str()
        .unwrap()
        .to_string();
    let id = d["_checkpoint"]["records"][2]["route_id"]
        .as_str()
        .unwrap()
        .to_string();
    let (pr, pw) = (dir.join("pr.json"), dir.join("pw.json"));
    let (r, _) = score_to(&pr, &[&rerun], &strs(&args));
    // Each row keeps its record's stamp.
    let row = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == id.as_str())
        .unwrap();
    assert_eq!(row["stamp"], "12_30_23_59_00");
    score_to(&pw, &[&results], &strs(&args));
    let (want, _) = score_to(
        &dir.join("want.json"),
        &[&rerun, &results],
        &strs(&[args.clone(), vec!["--duplicates".into(), "newest".into()]].concat()),
    );
    for (policy, kept_file) in [("newest", &rerun), ("last", &results), ("first", &rerun)] {
        let out = dir.join(format!("{policy}.json"));
        let (code, err) = merge(&out, &[&pr, &pw], &["--duplicates", policy]);
        assert_eq!(code, 0, "{policy}: {err}");
        let m = read(&out);
        assert_eq!(m["config"]["duplicates"], policy, "the rule applied");
        let row = m["routes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["route_id"] == id.as_str())
            .unwrap();
        assert_eq!(row["source"]["file"], s(kept_file), "{policy}");
        assert_eq!(row["kept"]["policy"], policy);
        assert!(
            row["kept"]["stamp"].is_string(),
            "{policy}: kept.stamp {}",
            row["kept"]
        );
        if policy == "newest" {
            assert_eq!(row["kept"]["stamp"], "12_30_23_59_00");
            assert!(!old_save.ends_with("12_30_23_59_00"));
            assert_eq!(
                m["summary"], want["summary"],
                "newest across parts = newest over the files"
            );
        }
    }
    // A merge's inputs.files lists every part's results files.
    let m = read(&dir.join("newest.json"));
    let files: Vec<&str> = m["inputs"]["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap())
        .collect();
    assert_eq!(files, [s(&rerun), s(&results)]);
}

#[test]
fn i46_3_a_shard_scored_with_its_route_xml_gives_no_stored_figure_warning() {
    let Some(b2d) = b2d_fixtures(&["routes/bench2drive220.xml", "tfpp_raw_shards"]) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let xml = s(&b2d.join("routes/bench2drive220.xml"));
    let mut parts = Vec::new();
    for i in 0..8 {
        let shard = b2d.join(format!("tfpp_raw_shards/eval_bench2drive220_{i}.json"));
        let part = dir.join(format!("p{i}.json"));
        let (r, err) = score_to(
            &part,
            &[&shard],
            &["--routes", &xml, "--allow-missing-telemetry"],
        );
        assert!(!err.contains("stored driving score"), "shard {i}: {err}");
        let w = r["warnings"].as_array().unwrap();
        assert!(
            w.iter()
                .all(|w| !w.as_str().unwrap().contains("stored driving score")),
            "{w:?}"
        );
        // Both figures are still in the report's inputs.
        let f = &r["inputs"]["files"][0];
        assert!(
            f["stored"]["driving_score"].is_number() && f["computed"]["driving_score"].is_number()
        );
        parts.push(part);
    }
    let p: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    let out = dir.join("m.json");
    let (code, err) = merge(&out, &p, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("stored driving score"), "{err}");
}

/// A hand-edit of the part `src` written to `name`.
fn edited(dir: &Path, src: &Path, name: &str, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let mut v = read(src);
    edit(&mut v);
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

#[test]
fn i46_6_r4_07_merge_and_compare_refuse_hand_edited_part_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, b) = split_demo(dir, 4);
    let args = demo_args(dir);
    let (pa, pb) = (dir.join("pa.json"), dir.join("pb.json"));
    let (ra, _) = score_to(&pa, &[&a], &strs(&args));
    score_to(&pb, &[&b], &strs(&args));
    let out = dir.join("m.json");
    assert_eq!(merge(&out, &[&pa, &pb], &[]).0, 0);
    let routes = ra["routes"].as_array().unwrap();
    let i = routes.iter().position(|r| r["state"] == "scored").unwrap();
    let set = |field: &'static str, x: Value| {
        move |v: &mut Value| {
            let mut at = &mut v["routes"][i];
            for k in field.split('.') {
                at = &mut at[k];
            }
            *at = x;
        }
    };
    type Edit<'a> = Box<dyn FnOnce(&mut Value) + 'a>;
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "composed",
            Box::new(set("score_composed", 40.0.into())),
            "score_composed 40 is not score_route",
        ),
        (
            "route1",
            Box::new(|v: &mut Value| {
                v["routes"][i]["score_route"] = 1.0.into();
                v["routes"][i]["score_composed"] = 40.0.into();
            }),
            "is not score_route × score_penalty",
        ),
        (
            "huge",
            Box::new(set("score_composed", 1e308.into())),
            "score_composed 1e308 is outside 0..100",
        ),
        (
            "ds250",
            Box::new(set("ds_safe", 250.0.into())),
            "ds_safe 250 is outside 0..100",
        ),
        (
            "dsneg",
            Box::new(set("ds_safe", (-50.0).into())),
            "ds_safe -50 is outside 0..100",
        ),
        (
            "dsoff",
            Box::new(set("ds_safe", 1.0.into())),
            "ds_safe 1 is not what its scores and counts give",
        ),
        (
            "comfort",
            Box::new(set("comfort.score", 5.0.into())),
            "comfort.score 5 is outside 0..1",
        ),
        (
            "foreign",
            Box::new(|v: &mut Value| {
                let mut extra = v["routes"][i].clone();
                extra["route_id"] = "RouteScenario_424242_rep0".into();
                v["routes"].as_array_mut().unwrap().push(extra);
            }),
            "are not its inputs.route_set",
        ),
        (
            "dropped",
            Box::new(|v: &mut Value| {
                v["routes"].as_array_mut().unwrap().remove(i);
            }),
            "are not its inputs.route_set",
        ),
    ];
    for (name, edit, want) in cases {
        let part = edited(dir, &pa, &format!("{name}.json"), edit);
        let (code, err) = merge(&out, &[&part, &pb], &[]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(
            err.contains(&format!("{name}.json")) && err.contains(want),
            "{name}: {err}"
        );
        assert!(err.contains("edited"), "{name}: {err}");
        // `sds compare` reads a report back the same way: refused too, never ranked.
        let (code, err) = run(&[
            "compare",
            &format!("a={}", s(&pb)),
            &format!("b={}", s(&part)),
        ]);
        assert_ne!(code, 0, "{name}: compare accepted the edited part\n{err}");
        assert!(err.contains(want), "{name}: {err}");
    }
}

#[test]
fn r4_02_route_ids_that_would_inject_into_the_rerun_list_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    // Routes of the XML without a record (so listed as missing) whose ids would add a line, split
    // into several ids, add an argument, or read otherwise than they run.
    let xml = std::fs::read_to_string(dir.join("routes.xml")).unwrap();
    let hostile = [
        "1&#10;2204&#9;crashed",
        "4,5,6",
        "3 --agent=/tmp/evil.py",
        "--agent=x",
        "77&#x202E;1",
    ];
    let extra: String = hostile
        .iter()
        .map(|id| {
            format!(
                "<route id=\"{id}\" town=\"DemoTown\"><waypoints><position x=\"0\" y=\"0\" z=\"0\"/>\
                 <position x=\"5\" y=\"0\" z=\"0\"/></waypoints></route>\n"
            )
        })
        .collect();
    let end = xml.rfind("</routes>").unwrap();
    let routes = dir.join("hostile.xml");
    std::fs::write(&routes, format!("{}{extra}{}", &xml[..end], &xml[end..])).unwrap();
    let (list, rxml) = (dir.join("rerun.tsv"), dir.join("rerun.xml"));
    let (r, err) = score_to(
        &dir.join("r.json"),
        &[&dir.join("results.json")],
        &[
            "--telemetry",
            &s(&dir.join("telemetry")),
            "--routes",
            &s(&routes),
            "--rerun-list",
            &s(&list),
            "--rerun-xml",
            &s(&rxml),
        ],
    );
    let missing = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["state"] == "missing")
        .count();
    assert_eq!(missing, 5);
    let text = std::fs::read_to_string(&list).unwrap();
    assert_eq!(text, "", "no hostile id goes into the list");
    assert!(
        err.contains("5 route id(s) left out of the rerun list"),
        "{err}"
    );
    // Named escaped: the warning cannot rewrite the terminal either.
    assert!(!err.contains('\u{202e}') && err.contains("202e"), "{err}");
    // The route XML keeps them, as the input's own bytes.
    let rx = std::fs::read_to_string(&rxml).unwrap();
    assert_eq!(rx.matches("<route ").count(), 5, "{rx}");
    assert!(rx.contains("1&#10;2204&#9;crashed"));
}

#[test]
fn r4_08_the_rerun_files_are_inside_the_output_unit() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    demo(dir);
    let (a, _) = split_demo(dir, 4);
    let base = demo_args(dir);
    let report = dir.join("r.json");
    let run_with = |extra: &[&str]| {
        let mut args = vec!["score".to_string(), "--results".into(), s(&a)];
        args.extend(base.iter().cloned());
        args.extend(extra.iter().map(|x| x.to_string()));
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        run(&argv)
    };
    let (code, err) = run_with(&["-o", &s(&report)]);
    assert_eq!(code, 0, "{err}");
    let before = std::fs::read(&report).unwrap();
    // -o and the rerun list on one file: refused before any work, the report kept.
    let (code, err) = run_with(&["-o", &s(&report), "--rerun-list", &s(&report)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("the rerun list"), "{err}");
    assert_eq!(std::fs::read(&report).unwrap(), before);
    // The rerun list over a long table, or over the rerun route XML.
    let tb = dir.join("tb");
    let (code, err) = run_with(&[
        "--tables",
        &s(&tb),
        "--rerun-list",
        &s(&tb.join("routes.csv")),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a table"), "{err}");
    assert!(!tb.exists(), "nothing written");
    let same = s(&dir.join("x.txt"));
    let (code, err) = run_with(&["--rerun-list", &same, "--rerun-xml", &same]);
    assert_eq!(code, 2, "{err}");
    // A folder that does not exist: refused first, the report kept.
    let (code, err) = run_with(&[
        "-o",
        &s(&report),
        "--rerun-list",
        &s(&dir.join("no/such/r.tsv")),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--rerun-list") && err.contains("no/such"),
        "{err}"
    );
    assert_eq!(std::fs::read(&report).unwrap(), before);
    // A report that cannot be written (a dangling link at -o) rolls the rerun list back: the
    // previous list is put back.
    let list = dir.join("rerun.tsv");
    std::fs::write(&list, "old\tlist\n").unwrap();
    let dangling = dir.join("dangling.json");
    std::os::unix::fs::symlink(dir.join("nowhere/x.json"), &dangling).unwrap();
    let (code, err) = run_with(&["-o", &s(&dangling), "--rerun-list", &s(&list)]);
    assert_eq!(code, 1, "{err}");
    assert_eq!(
        std::fs::read_to_string(&list).unwrap(),
        "old\tlist\n",
        "{err}"
    );
    // And written with the report when everything can be.
    let (code, err) = run_with(&["-o", &s(&report), "--rerun-list", &s(&list)]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(&list)
        .unwrap()
        .ends_with("\tmissing\n"));
    // The same unit in a merge.
    let m = dir.join("m.json");
    let (code, err) = merge(&m, &[&report], &["--rerun-list", &s(&m)]);
    assert_eq!(code, 2, "{err}");
    assert!(!m.exists());
}

#[test]
fn i46_1_merge_writes_the_rerun_xml_of_the_parts_own_route_xml() {
    let Some(b2d) = b2d_fixtures(&["routes/bench2drive220.xml", "tfpp_raw_shards"]) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let xml = b2d.join("routes/bench2drive220.xml");
    // Shards 0..6 scored where they are; shards 6 and 7 "died": their routes are to run again.
    let mut parts = Vec::new();
    for i in 0..6 {
        let shard = b2d.join(format!("tfpp_raw_shards/eval_bench2drive220_{i}.json"));
        let part = dir.join(format!("p{i}.json"));
        score_to(
            &part,
            &[&shard],
            &["--routes", &s(&xml), "--allow-missing-telemetry"],
        );
        parts.push(part);
    }
    let p: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    let (list, rx) = (dir.join("rerun.tsv"), dir.join("rerun.xml"));
    let out = dir.join("m.json");
    let (code, err) = merge(
        &out,
        &p,
        &[
            "--rerun-list",
            &s(&list),
            "--routes",
            &s(&xml),
            "--rerun-xml",
            &s(&rx),
        ],
    );
    assert_eq!(code, 0, "{err}");
    let ids: Vec<String> = lines(&list).into_iter().map(|(id, _)| id).collect();
    let died: usize = [6, 7]
        .iter()
        .map(|i| {
            let f = b2d.join(format!("tfpp_raw_shards/eval_bench2drive220_{i}.json"));
            read(&f)["_checkpoint"]["records"].as_array().unwrap().len()
        })
        .sum();
    assert_eq!(ids.len(), died);
    let routes = parse_b2d_routes(&std::fs::read_to_string(&rx).unwrap(), &ids).unwrap();
    assert_eq!(routes.len(), died);
    // Another route XML than the parts' is refused, naming both hashes; nothing is written.
    let other = dir.join("other.xml");
    std::fs::write(
        &other,
        std::fs::read_to_string(&xml)
            .unwrap()
            .replacen("3672.9", "3672.8", 1),
    )
    .unwrap();
    let out2 = dir.join("m2.json");
    let (code, err) = merge(
        &out2,
        &p,
        &[
            "--routes",
            &s(&other),
            "--rerun-xml",
            &s(&dir.join("r2.xml")),
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("other.xml") && err.contains("bench2drive220.xml"),
        "{err}"
    );
    assert!(!out2.exists() && !dir.join("r2.xml").exists());
}
