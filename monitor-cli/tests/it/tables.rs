//! `sds score --tables DIR` (issue 37, docs/TABLES-SCHEMA.md): the long tables `routes.csv`,
//! `events.csv` and `frames.csv` hold the JSON report's routes and events and `sds frames`'
//! output, row for row and value for value; docs/TABLES-SCHEMA.md names every column.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use monitor_host::report::escape::csv_cell;
use serde_json::Value;

use crate::common::{demo, sds};

/// A CSV file as its header and rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// The leaves of a JSON object, names joined with `.`, lists as one leaf.
fn leaves(prefix: &str, v: &Value, out: &mut BTreeMap<String, Value>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                leaves(&name, x, out);
            }
        }
        x => {
            out.insert(prefix.to_string(), x.clone());
        }
    }
}

/// Asserts that `cell` holds the JSON value `v` as the tables write it.
fn assert_cell(cell: &str, v: &Value, what: &str) {
    match v {
        Value::Null => assert_eq!(cell, "", "{what}"),
        Value::Bool(b) => assert_eq!(cell, b.to_string(), "{what}"),
        Value::Number(n) => {
            // The same text as the JSON prints, and the same number read back.
            assert_eq!(cell, n.to_string(), "{what}");
            assert_eq!(cell.parse::<f64>().ok(), n.as_f64(), "{what}");
        }
        Value::String(s) => assert_eq!(cell, csv_cell(s), "{what}"),
        Value::Array(_) | Value::Object(_) => {
            let back: Value = serde_json::from_str(cell).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(&back, v, "{what}");
        }
    }
}

/// Asserts that a table row holds exactly the leaves of `object` after its `keys` columns
/// (a column the object lacks is empty; every leaf has its column).
fn assert_row(header: &[String], row: &[String], keys: usize, object: &Value, what: &str) {
    let mut l = BTreeMap::new();
    leaves("", object, &mut l);
    assert_eq!(row.len(), header.len(), "{what}: row length");
    for (c, cell) in header.iter().zip(row).skip(keys) {
        match l.remove(c) {
            Some(v) => assert_cell(cell, &v, &format!("{what}: column {c}")),
            // Another row's field, or an always-null parent of an object (flattened away).
            None => assert_eq!(cell, "", "{what}: column {c} is not in the JSON"),
        }
    }
    // A null under a name whose object other rows have is written as its object's empty cells.
    l.retain(|k, v| !(v.is_null() && header.iter().any(|c| c.starts_with(&format!("{k}.")))));
    assert!(l.is_empty(), "{what}: leaves without a column: {l:?}");
}

/// Checks `dir`'s `routes.csv` and `events.csv` against the JSON report `report`, and returns
/// the `frames.csv` rows per route index.
fn check_routes_and_events(dir: &Path, report: &Value) -> BTreeMap<usize, Vec<Vec<String>>> {
    let routes = report["routes"].as_array().unwrap();
    let (header, rows) = read_csv(&dir.join("routes.csv"));
    assert_eq!(header[..2], ["route_index", "route_id"]);
    assert_eq!(rows.len(), routes.len(), "one row per route");
    for (i, (row, r)) in rows.iter().zip(routes).enumerate() {
        assert_eq!(row[0], i.to_string());
        assert_row(&header, row, 1, r, &format!("routes.csv row {i}"));
    }

    let (eh, erows) = read_csv(&dir.join("events.csv"));
    assert_eq!(eh[..3], ["route_index", "route_id", "event_index"]);
    let events: Vec<(usize, usize, &Value)> = routes
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            let es = r["events"].as_array().unwrap();
            es.iter().enumerate().map(move |(j, e)| (i, j, e))
        })
        .collect();
    assert_eq!(erows.len(), events.len(), "one row per event");
    for (row, (i, j, e)) in erows.iter().zip(&events) {
        assert_eq!(row[0], i.to_string());
        assert_cell(&row[1], &routes[*i]["route_id"], "events.csv route_id");
        assert_eq!(row[2], j.to_string());
        assert_row(&eh, row, 3, e, &format!("events.csv route {i} event {j}"));
    }

    let (fh, frows) = read_csv(&dir.join("frames.csv"));
    assert_eq!(fh[..4], ["route_index", "route_id", "frame", "time"]);
    let mut by_route: BTreeMap<usize, Vec<Vec<String>>> = BTreeMap::new();
    for r in frows {
        by_route.entry(r[0].parse().unwrap()).or_default().push(r);
    }
    // Every row of a route with telemetry has its frames, and only those.
    for (i, r) in routes.iter().enumerate() {
        let n = by_route.get(&i).map_or(0, Vec::len);
        let expected = if r["telemetry"] == "ok" {
            r["frames"].as_u64().unwrap() as usize
        } else {
            0
        };
        assert_eq!(n, expected, "frames.csv rows of route {i}");
    }
    let mut framed = by_route;
    framed.insert(usize::MAX, vec![fh]);
    framed
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sds-it-tables-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `sds score --tables` on the demo (every option that adds columns: maps, protocols).
fn demo_tables(dir: &Path) -> Value {
    demo(dir);
    let s = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let out = sds(&[
        "score",
        "--results",
        &s("results.json"),
        "--telemetry",
        &s("telemetry"),
        "--routes",
        &s("routes.xml"),
        "--maps",
        &s("maps"),
        "--protocol",
        "all",
        "--format",
        "json",
        "-o",
        &s("report.json"),
        "--tables",
        &s("tables"),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap()
}

#[test]
fn tables_equal_the_json_report_and_sds_frames_on_the_demo() {
    let dir = tmp("demo");
    let report = demo_tables(&dir);
    let mut frames = check_routes_and_events(&dir.join("tables"), &report);
    let header = frames.remove(&usize::MAX).unwrap().remove(0);
    assert!(!frames.is_empty(), "the demo's routes have telemetry");
    let s = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let mut compared = 0;
    for (i, rows) in &frames {
        let id = report["routes"][*i]["route_id"].as_str().unwrap();
        let out = sds(&[
            "frames",
            "--results",
            &s("results.json"),
            "--telemetry",
            &s("telemetry"),
            "--routes",
            &s("routes.xml"),
            "--maps",
            &s("maps"),
            "--route-id",
            id,
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let lines: Vec<Value> = String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(rows.len(), lines.len(), "{id}: frames");
        for (k, (row, line)) in rows.iter().zip(&lines).enumerate() {
            assert_eq!(
                (row[1].as_str(), row[2].as_str()),
                (id, k.to_string().as_str())
            );
            assert_row(&header, row, 4, line, &format!("frames.csv {id} frame {k}"));
            compared += 1;
        }
    }
    assert!(compared > 1000, "{compared} frames compared");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 46 item 5d (docs/TABLES-SCHEMA.md: "step, time, the core frame, the host values"): `frames.csv`
/// has a `time` column after `frame`, the seconds from the route's first frame, computed as the
/// events' `time_s` is, so that an event and its frame show the same time.
#[test]
fn i46_5d_frames_table_has_the_time_of_each_frame() {
    let dir = tmp("time");
    demo_tables(&dir);
    let (fh, frows) = read_csv(&dir.join("tables/frames.csv"));
    assert_eq!(fh[..4], ["route_index", "route_id", "frame", "time"]);
    let col = |h: &[String], n: &str| h.iter().position(|c| c == n).unwrap();
    let (step, dt) = (col(&fh, "host.step"), col(&fh, "host.dt"));
    let mut first: BTreeMap<String, u64> = BTreeMap::new();
    let mut at: BTreeMap<(String, String), String> = BTreeMap::new();
    let mut nonzero = 0;
    for r in &frows {
        let s: u64 = r[step].parse().unwrap();
        let s0 = *first.entry(r[0].clone()).or_insert(s);
        let want = (s - s0) as f64 * r[dt].parse::<f64>().unwrap();
        assert_eq!(
            r[3].parse::<f64>().unwrap(),
            want,
            "route {} frame {}",
            r[0],
            r[2]
        );
        assert_eq!(
            r[3],
            serde_json::Number::from_f64(want).unwrap().to_string()
        );
        nonzero += usize::from(want > 0.0);
        at.insert((r[0].clone(), r[2].clone()), r[3].clone());
    }
    assert!(nonzero > 1000, "{nonzero} frames after the first");
    // An event placed at a frame shows that frame's time.
    let (eh, erows) = read_csv(&dir.join("tables/events.csv"));
    let (frame, time_s) = (col(&eh, "frame"), col(&eh, "time_s"));
    let mut placed = 0;
    for e in erows.iter().filter(|e| !e[frame].is_empty()) {
        let t = &at[&(e[0].clone(), e[frame].clone())];
        assert_eq!(e[time_s].parse::<f64>().unwrap(), t.parse::<f64>().unwrap());
        placed += 1;
    }
    assert!(placed > 0, "the demo has placed events");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tables_equal_the_json_report_on_a_real_run() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures/b2d");
    let results = fixtures.join("carla_garage_tfpp_b2d_traj_merged.json");
    let routes = fixtures.join("routes/bench2drive220.xml");
    if !results.is_file() || !routes.is_file() {
        crate::common::skipped(&format!("{} is absent", results.display()));
        return;
    }
    let dir = tmp("tfpp");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let out = sds(&[
        "score",
        "--results",
        &s(&results),
        "--routes",
        &s(&routes),
        "--allow-missing-telemetry",
        "--format",
        "json",
        "-o",
        &s(&dir.join("report.json")),
        "--tables",
        &s(&dir.join("tables")),
    ]);
    assert!(
        out.status.code().is_some_and(|c| c == 0 || c == 3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    let mut frames = check_routes_and_events(&dir.join("tables"), &report);
    let header = frames.remove(&usize::MAX).unwrap().remove(0);
    assert!(frames.is_empty(), "no telemetry, no frames");
    // Issue 46 item 5a: no frame, but the columns every frame has (a query naming them reads
    // an empty table instead of failing to bind).
    let always: BTreeSet<String> = documented()["frames.csv"]
        .iter()
        .filter(|(_, always)| *always)
        .map(|(n, _)| n.clone())
        .collect();
    assert_eq!(header.iter().cloned().collect::<BTreeSet<_>>(), always);
    assert!(header.contains(&"a_lat".to_string()) && header.len() > 10);
    assert_eq!(report["routes"].as_array().unwrap().len(), 220);
    let (_, events) = read_csv(&dir.join("tables/events.csv"));
    assert!(events.len() > 100, "{} events", events.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The columns docs/TABLES-SCHEMA.md names per table, with whether each is always present.
fn documented() -> BTreeMap<String, Vec<(String, bool)>> {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/TABLES-SCHEMA.md"),
    )
    .unwrap();
    let mut out: BTreeMap<String, Vec<(String, bool)>> = BTreeMap::new();
    let mut table = None;
    for line in text.lines() {
        if let Some(t) = line.strip_prefix("## ") {
            table = Some(t.trim().to_string());
            continue;
        }
        let (Some(t), Some(rest)) = (&table, line.strip_prefix("| `")) else {
            continue;
        };
        let name = rest.split('`').next().unwrap().to_string();
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        out.entry(t.clone())
            .or_default()
            .push((name, cells.get(4) == Some(&"always")));
    }
    out
}

/// A documented name matches a column: equal, or a family with `<...>` parts.
fn matches(doc: &str, column: &str) -> bool {
    if !doc.contains('<') {
        return doc == column;
    }
    let (head, tail) = doc.split_once('<').unwrap();
    let tail = tail.split_once('>').unwrap().1;
    column.len() > head.len() + tail.len() && column.starts_with(head) && column.ends_with(tail)
}

#[test]
fn tables_schema_names_every_column() {
    let dir = tmp("schema");
    demo_tables(&dir);
    let docs = documented();
    assert_eq!(
        docs.keys().collect::<BTreeSet<_>>(),
        ["events.csv", "frames.csv", "routes.csv", "sweep.csv"]
            .iter()
            .map(|s| s.to_string())
            .collect::<BTreeSet<_>>()
            .iter()
            .collect()
    );
    // sweep.csv comes from `sds compare --sweep` (issue 50), in a folder of its own.
    let run = format!(
        "a={}:{}",
        dir.join("results.json").display(),
        dir.join("telemetry").display()
    );
    let b = run.replacen("a=", "b=", 1);
    let swept = dir.join("swept");
    let out = sds(&[
        "compare",
        &run,
        &b,
        "--bootstrap-samples",
        "1000",
        "--sweep",
        "factors.critical=0.8,0.9",
        "--tables",
        swept.to_str().unwrap(),
        "-o",
        dir.join("compare.json").to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (file, names) in &docs {
        let folder = if file == "sweep.csv" {
            swept.clone()
        } else {
            dir.join("tables")
        };
        let (header, _) = read_csv(&folder.join(file));
        for c in &header {
            assert!(
                names.iter().any(|(n, _)| matches(n, c)),
                "{file}: column {c} is not in docs/TABLES-SCHEMA.md"
            );
        }
        for (n, always) in names {
            assert!(
                !always || header.contains(n),
                "{file}: docs/TABLES-SCHEMA.md names {n} (always present), the table has no such column"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tables_refuse_a_planted_link_and_write_nothing() {
    let dir = tmp("link");
    demo(&dir);
    let tables = dir.join("tables");
    std::fs::create_dir_all(&tables).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep").unwrap();
    std::os::unix::fs::symlink(&victim, tables.join("frames.csv")).unwrap();
    let s = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let out = sds(&[
        "score",
        "--results",
        &s("results.json"),
        "--telemetry",
        &s("telemetry"),
        "--format",
        "json",
        "-o",
        &s("report.json"),
        "--tables",
        &s("tables"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--tables") && err.contains("symbolic link"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
    assert!(!tables.join("routes.csv").exists() && !dir.join("report.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compare_tables_hold_each_runs_score_report_under_its_run_and_model() {
    let dir = tmp("compare");
    demo(&dir);
    let s = |p: &str| dir.join(p).to_str().unwrap().to_string();
    let (results, telemetry, routes) = (s("results.json"), s("telemetry"), s("routes.xml"));
    let out = sds(&[
        "compare",
        &format!("a={results}:{telemetry}"),
        &format!("b={results}:{telemetry}"),
        &format!("c={results}:{telemetry}"),
        "--seeds",
        "m=a,b",
        "--routes",
        &routes,
        "--format",
        "json",
        "-o",
        &s("compare.json"),
        "--tables",
        &s("tables"),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        !dir.join("tables/frames.csv").exists(),
        "frames: sds score only"
    );
    let out = sds(&[
        "score",
        "--results",
        &results,
        "--telemetry",
        &telemetry,
        "--routes",
        &routes,
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let routes = report["routes"].as_array().unwrap();

    let (header, rows) = read_csv(&dir.join("tables/routes.csv"));
    assert_eq!(header[..4], ["run", "model", "route_index", "route_id"]);
    assert_eq!(rows.len(), 3 * routes.len());
    for (k, row) in rows.iter().enumerate() {
        let (run, i) = (["a", "b", "c"][k / routes.len()], k % routes.len());
        let model = if run == "c" { "c" } else { "m" };
        assert_eq!((row[0].as_str(), row[1].as_str()), (run, model));
        assert_eq!(row[2], i.to_string());
        assert_row(&header, row, 3, &routes[i], &format!("{run} route {i}"));
    }
    let (eh, erows) = read_csv(&dir.join("tables/events.csv"));
    let events: usize = routes
        .iter()
        .map(|r| r["events"].as_array().unwrap().len())
        .sum();
    assert_eq!(erows.len(), 3 * events);
    for row in &erows {
        let i: usize = row[2].parse().unwrap();
        let j: usize = row[4].parse().unwrap();
        assert_row(&eh, row, 5, &routes[i]["events"][j], "compare events.csv");
    }
    let docs = documented();
    for (file, header) in [("routes.csv", &header), ("events.csv", &eh)] {
        for c in header {
            assert!(
                docs[file].iter().any(|(n, _)| matches(n, c)),
                "{file}: {c} undocumented"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Bench2Drive tables (abilities, efficiency, weathers, seeds) of real runs reproduce
/// Bench2Drive's own figures.
mod bench2drive;
