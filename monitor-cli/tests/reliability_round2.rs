//! Reliability, round 2 (issue 29): what an adversarial trial of the HTML page, the traces, the
//! maps, the label files, `sds compare` and the Python package found, one test per finding
//! (`docs/RELIABILITY.md`). Each test builds the demo run in a temporary folder, breaks it the
//! way the finding did, and checks the fixed behaviour.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{json, Value};

use common::sds;

/// The demo run in a temporary folder, and its records (raw evaluator values).
struct Run {
    tmp: tempfile::TempDir,
    records: Vec<Value>,
}

impl Run {
    fn new() -> Run {
        let tmp = tempfile::tempdir().unwrap();
        common::demo(tmp.path());
        let doc: Value =
            serde_json::from_slice(&fs::read(tmp.path().join("results.json")).unwrap()).unwrap();
        let records = doc["_checkpoint"]["records"].as_array().unwrap().clone();
        Run { tmp, records }
    }

    fn path(&self, p: &str) -> PathBuf {
        self.tmp.path().join(p)
    }

    fn s(&self, p: &str) -> String {
        self.path(p).to_str().unwrap().to_string()
    }

    /// Writes `records` as a raw evaluator file `name` in the run's folder.
    fn write(&self, name: &str, records: &[Value]) -> String {
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
    fn score(&self, results: &str, extra: &[&str]) -> Output {
        let telemetry = self.s("telemetry");
        let mut args = vec!["score", "--results", results, "--telemetry", &telemetry];
        args.extend_from_slice(extra);
        sds(&args)
    }
}

fn code(o: &Output) -> i32 {
    o.status.code().expect("sds was killed by a signal")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn stderr(o: &Output) -> String {
    text(&o.stderr)
}

/// Every cell of a CSV text.
fn csv_cells(b: &[u8]) -> Vec<Vec<String>> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(b)
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect()
}

/// A CSV cell a spreadsheet would run as a formula: it starts with `=`, `+`, `-`, `@`, TAB or CR
/// and is not a number.
fn is_formula(cell: &str) -> bool {
    cell.starts_with(['=', '+', '-', '@', '\t', '\r']) && cell.parse::<f64>().is_err()
}

/// Finding 1: `--group-by ... --format csv` wrote group labels raw.
#[test]
fn grouped_csv_neutralises_formulas_in_every_cell() {
    let run = Run::new();
    let mut recs = run.records.clone();
    let evil = [
        "=HYPERLINK(\"http://x\")",
        "+cmd|' /C calc'!A0",
        "@SUM(A1)",
        "\tTAB",
        "-2+3+cmd|' /C calc'!A0",
    ];
    for (r, e) in recs.iter_mut().zip(evil) {
        r["scenario_name"] = json!(format!("{e}_1"));
        r["town_name"] = json!(e);
        r["weather_id"] = json!(e);
    }
    let results = run.write("evil.json", &recs);
    let labels = run.path("labels.csv");
    fs::write(
        &labels,
        "id,label\nRouteScenario_900001_rep0,\"-2+3+cmd|' /C calc'!A0\"\nRouteScenario_900002_rep0,=1+1\n",
    )
    .unwrap();
    let labels = labels.to_str().unwrap();
    for by in [
        &["--group-by", "scenario"][..],
        &["--group-by", "town"],
        &["--group-by", "weather"],
        &["--group-by", "route", "--labels", labels],
    ] {
        let mut args = vec!["--format", "csv"];
        args.extend_from_slice(by);
        let o = run.score(&results, &args);
        assert_eq!(code(&o), 0, "{by:?}: {}", stderr(&o));
        let cells = csv_cells(&o.stdout);
        assert!(cells.len() > 2, "{by:?}");
        for row in &cells {
            for c in row {
                assert!(!is_formula(c), "{by:?}: formula cell {c:?} in {row:?}");
            }
        }
        // The labels are kept, as text.
        let out = text(&o.stdout);
        assert!(
            out.contains("'=HYPERLINK") || out.contains("'-2+3+cmd"),
            "{by:?}: {out}"
        );
    }
    // The per-route CSV too.
    let o = run.score(&results, &["--format", "csv"]);
    for row in csv_cells(&o.stdout) {
        for c in &row {
            assert!(!is_formula(c), "per-route: formula cell {c:?}");
        }
    }
}

/// The characters that make text read as other text: bidi embeddings, overrides and isolates,
/// zero-width characters and marks, the BOM, and control characters.
const HIDDEN: [char; 9] = [
    '\u{202e}', '\u{202a}', '\u{2066}', '\u{2069}', '\u{200b}', '\u{200f}', '\u{feff}', '\u{1b}',
    '\u{7}',
];

fn assert_no_hidden(what: &str, s: &str) {
    for c in HIDDEN {
        assert!(!s.contains(c), "{what}: raw {:?} in the output", c);
    }
}

/// Finding 2: bidi and invisible format characters reached the page, tables, Markdown, LaTeX,
/// CSV and stderr raw, so a route id could be made to read as another; the per-route CSV kept
/// ESC raw.
#[test]
fn bidi_and_invisible_characters_are_escaped_in_every_rendering() {
    let run = Run::new();
    let mut recs = run.records.clone();
    recs[0]["route_id"] = json!("RouteScenario_1\u{202e}01_rep0\u{1b}[2K");
    recs[0]["town_name"] = json!("Town\u{2066}05\u{2069}");
    recs[0]["scenario_name"] = json!("Acc\u{200b}ident\u{feff}_1");
    recs[0]["weather_id"] = json!("1\u{202a}\u{7}");
    recs[0]["status"] = json!("Completed\u{200f}");
    // A route without telemetry: its id is printed on stderr.
    recs[1]["route_id"] = json!("RouteScenario_2\u{202e}02_rep0\u{1b}]0;x\u{7}");
    recs[1]["save_name"] = json!("nowhere\u{202e}");
    let results = run.write("bidi.json", &recs);
    let labels = run.path("labels.json");
    fs::write(
        &labels,
        serde_json::to_vec(&json!({"RouteScenario_900003_rep0": "hard\u{202e}easy"})).unwrap(),
    )
    .unwrap();
    let labels = labels.to_str().unwrap();
    for format in ["csv", "table", "markdown", "latex", "html"] {
        for by in [
            &[][..],
            &["--group-by", "town"],
            &["--group-by", "weather"],
            &["--group-by", "scenario"],
            &["--group-by", "route", "--labels", labels],
        ] {
            let mut args = vec!["--format", format];
            args.extend_from_slice(by);
            let o = run.score(&results, &args);
            assert_eq!(code(&o), 3, "{format} {by:?}: {}", stderr(&o));
            let what = format!("{format} {by:?}");
            assert_no_hidden(&format!("{what} stdout"), &text(&o.stdout));
            assert_no_hidden(&format!("{what} stderr"), &stderr(&o));
        }
    }
    let o = run.score(&results, &["--format", "csv"]);
    let out = text(&o.stdout);
    assert!(
        out.contains("RouteScenario_1\\u{202e}01_rep0\\u{1b}[2K"),
        "{out}"
    );
    assert!(
        stderr(&o).contains("RouteScenario_2\\u{202e}02_rep0"),
        "{}",
        stderr(&o)
    );
}

/// Finding 3: a table cell of 65,536+ characters aborted `--format table` (a u16 format width).
#[test]
fn a_table_cell_of_any_length_renders() {
    let run = Run::new();
    let mut recs = run.records.clone();
    let long = "x".repeat(70_000);
    recs[0]["scenario_name"] = json!(format!("{long}_1"));
    recs[1]["town_name"] = json!(long);
    recs[2]["weather_id"] = json!(format!("w{long}"));
    let results = run.write("long.json", &recs);
    let labels = run.path("labels.csv");
    fs::write(&labels, format!("RouteScenario_900004_rep0,L{long}\n")).unwrap();
    let labels = labels.to_str().unwrap();
    for format in ["table", "markdown", "latex", "html"] {
        for by in [
            &["--group-by", "scenario"][..],
            &["--group-by", "town"],
            &["--group-by", "weather"],
            &["--group-by", "route", "--labels", labels],
        ] {
            let mut args = vec!["--format", format];
            args.extend_from_slice(by);
            let o = run.score(&results, &args);
            assert_eq!(code(&o), 0, "{format} {by:?}: {}", stderr(&o));
            assert!(text(&o.stdout).contains(&long), "{format} {by:?}");
        }
    }
    // A run name as long, in `sds compare`.
    let name = format!("{}=", "r".repeat(70_000));
    let a = format!("{name}{}", run.s("results.json"));
    let o = sds(&[
        "compare",
        &a,
        &run.s("results.json"),
        "--allow-missing-telemetry",
        "--format",
        "table",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(text(&o.stdout).contains(&"r".repeat(70_000)));
}

/// Finding 14: a control character in a route id made the standalone trace SVG malformed XML.
#[test]
fn a_control_character_in_a_route_id_leaves_the_trace_svg_well_formed() {
    let run = Run::new();
    let mut recs = run.records.clone();
    for (i, r) in recs.iter_mut().enumerate() {
        let id = r["route_id"].as_str().unwrap().to_string();
        r["route_id"] = json!(format!("{id}\u{1}\u{8}<&\u{202e}"));
        // The telemetry under a save_name that names no route.
        let from = run.path("telemetry").join(r["save_name"].as_str().unwrap());
        let to = run.path("telemetry").join(format!("t{i}"));
        fs::create_dir_all(&to).unwrap();
        fs::copy(from.join("metric_info.json"), to.join("metric_info.json")).unwrap();
        r["save_name"] = json!(format!("t{i}"));
    }
    let results = run.write("ctl.json", &recs);
    let traces = run.s("traces");
    let o = run.score(&results, &["--traces", &traces, "-o", &run.s("r.json")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let mut svgs = 0;
    for e in fs::read_dir(&traces).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "svg") {
            let s = fs::read_to_string(&p).unwrap();
            roxmltree::Document::parse(&s)
                .unwrap_or_else(|e| panic!("{}: not well-formed XML: {e}", p.display()));
            assert_no_hidden(&p.display().to_string(), &s);
            svgs += 1;
        }
    }
    assert!(svgs > 0, "no trace written");
}

/// The JSON report of `sds score`, which must exit with `expect`.
fn report(o: &Output, expect: i32) -> Value {
    assert_eq!(code(o), expect, "{}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("not JSON: {e}"))
}

/// Moves every geometry of an OpenDRIVE text by `dy` metres across (its `y="..."`).
fn move_map(xodr: &str, dy: f64) -> String {
    let mut out = String::new();
    let mut rest = xodr;
    while let Some(i) = rest.find(" y=\"") {
        out.push_str(&rest[..i + 4]);
        rest = &rest[i + 4..];
        let j = rest.find('"').unwrap();
        let x: f64 = rest[..j].parse().unwrap();
        out.push_str(&(x + dy).to_string());
        rest = &rest[j..];
    }
    out + rest
}

/// Finding 4: a map that serves no route (no roads, no driving lane, or the right map moved
/// 40 m: a wrong town) was used silently: every route `map-route` / `map-lane`, the lateral
/// penalty gone under `lane`, or every chunk critical. Now it is reported per route, with the
/// distance, and not used: the routes score as without a map.
#[test]
fn a_map_that_serves_no_route_is_reported_per_route_and_not_used() {
    let run = Run::new();
    let results = run.s("results.json");
    let routes = run.s("routes.xml");
    let good = fs::read_to_string(run.path("maps/DemoTown.xodr")).unwrap();
    let variants = [
        ("moved", move_map(&good, 40.0), "does not serve"),
        (
            "no-roads",
            "<OpenDRIVE><header revMajor=\"1\" revMinor=\"4\"/></OpenDRIVE>".to_string(),
            "has no driving lane",
        ),
        (
            "no-driving-lane",
            good.replace("type=\"driving\"", "type=\"sidewalk\""),
            "has no driving lane",
        ),
    ];
    for lateral in ["route", "lane"] {
        let set = format!("lateral_reference={lateral}");
        let base = report(
            &run.score(&results, &["--routes", &routes, "--set", &set]),
            0,
        );
        let with_good = report(
            &run.score(
                &results,
                &["--routes", &routes, "--set", &set, "--maps", &run.s("maps")],
            ),
            0,
        );
        assert!(
            with_good["routes"]
                .as_array()
                .unwrap()
                .iter()
                .all(|r| r["lateral"]["reference"] != "xml"),
            "the demo's own map serves its routes"
        );
        for (name, xodr, says) in &variants {
            let dir = run.path(&format!("maps-{name}"));
            fs::create_dir_all(&dir).unwrap();
            fs::write(dir.join("DemoTown.xodr"), xodr).unwrap();
            let o = run.score(
                &results,
                &[
                    "--routes",
                    &routes,
                    "--set",
                    &set,
                    "--maps",
                    dir.to_str().unwrap(),
                ],
            );
            let r = report(&o, 0);
            let warnings: Vec<String> = r["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .map(|w| w.as_str().unwrap().to_string())
                .collect();
            for route in r["routes"].as_array().unwrap() {
                let id = route["route_id"].as_str().unwrap();
                assert_eq!(
                    route["lateral"]["reference"], "xml",
                    "{name} {lateral}: {id}"
                );
                assert!(
                    warnings
                        .iter()
                        .any(|w| w.contains(id) && w.contains(says) && w.contains("DemoTown.xodr")),
                    "{name} {lateral}: no warning for {id}: {warnings:#?}"
                );
            }
            if *name == "moved" {
                assert!(
                    warnings
                        .iter()
                        .any(|w| w.contains(" m (median) from the nearest")),
                    "{warnings:#?}"
                );
            }
            // Scored as without a map.
            assert_eq!(
                r["summary"]["sds"], base["summary"]["sds"],
                "{name} {lateral}"
            );
            for (a, b) in r["routes"]
                .as_array()
                .unwrap()
                .iter()
                .zip(base["routes"].as_array().unwrap())
            {
                assert_eq!(a["lateral"]["critical"], b["lateral"]["critical"], "{name}");
                assert_eq!(a["ds_safe"], b["ds_safe"], "{name} {lateral}");
            }
        }
    }
}

/// One road `length` m long with `shape` as its only geometry, `lanes` right lanes of width
/// record `width`, and the road's `junction` attribute.
fn one_road(length: f64, shape: &str, lanes: usize, width: &str, junction: &str) -> String {
    let right: String = (1..=lanes)
        .map(|i| {
            format!("<lane id=\"-{i}\" type=\"driving\"><width sOffset=\"0\" {width}/></lane>")
        })
        .collect();
    format!(
        "<OpenDRIVE><road id=\"1\" length=\"{length}\" junction=\"{junction}\">\
         <planView><geometry s=\"0\" x=\"0\" y=\"0\" hdg=\"0\" length=\"{length}\">{shape}</geometry></planView>\
         <lanes><laneSection s=\"0\"><center><lane id=\"0\" type=\"none\"/></center>\
         <right>{right}</right></laneSection></lanes></road></OpenDRIVE>"
    )
}

fn map_error(xodr: &str) -> String {
    use monitor_host::geometry::map::Map;
    match Map::parse(xodr, "hostile.xodr") {
        Ok(_) => panic!("accepted: {}", &xodr[..xodr.len().min(300)]),
        Err(e) => e.to_string(),
    }
}

const W: &str = "a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"";

/// Finding 5: small maps, huge cost (an arc of curvature 1e300: 7-14 s per run; coiled over
/// 99,999 m: past 60 s; a 10 KB road with 100 lanes: 2.9 GB). The work per map is bounded by
/// its real extent: what no CARLA town has is refused, naming the road and geometry or lane
/// section; CARLA's own towns still load.
#[test]
fn map_work_is_bounded_by_the_real_extent() {
    use monitor_host::geometry::map::Map;
    let e = map_error(&one_road(50.0, "<arc curvature=\"1e300\"/>", 1, W, "-1"));
    assert!(
        e.contains("hostile.xodr: road 1, geometry 0: curvature"),
        "{e}"
    );
    let e = map_error(&one_road(99_999.0, "<arc curvature=\"0.1\"/>", 1, W, "-1"));
    assert!(
        e.contains("road 1, geometry 0") && e.contains("full circle"),
        "{e}"
    );
    let e = map_error(&one_road(
        99_999.0,
        "<spiral curvStart=\"0\" curvEnd=\"0.01\"/>",
        1,
        W,
        "-1",
    ));
    assert!(e.contains("full circle"), "{e}");
    let e = map_error(&one_road(1000.0, "<line/>", 100, W, "-1"));
    assert!(
        e.contains("road 1, lane section 0") && e.contains("100 lanes"),
        "{e}"
    );
    // 30 lanes of 100 km: 3,000 km of driving lanes.
    let e = map_error(&one_road(99_999.0, "<line/>", 30, W, "-1"));
    assert!(e.contains("km long, more than 2000 km"), "{e}");
    // Within the bounds: a tight but real curve, a wide road.
    let ok = one_road(5.0, "<arc curvature=\"0.8\"/>", 10, W, "-1");
    assert_eq!(Map::parse(&ok, "ok.xodr").unwrap().lane_count(), 10);
    // CARLA's towns (when the fixtures are present).
    let maps = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/fixtures/maps"
    ));
    let towns: Vec<PathBuf> = fs::read_dir(&maps)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "xodr"))
                .collect()
        })
        .unwrap_or_default();
    if towns.is_empty() {
        eprintln!("SKIP (CARLA towns): {} not found", maps.display());
    }
    for t in towns {
        Map::load(&t).unwrap_or_else(|e| panic!("a CARLA town is refused: {e}"));
    }
}

/// Finding 11: map numbers unchecked: lanes 1e300 m wide made the slack infinite (SDS up, 0
/// critical; under `lane` the error blamed the telemetry), and `junction="777"` naming no
/// junction was accepted.
#[test]
fn map_numbers_are_checked() {
    let e = map_error(&one_road(
        100.0,
        "<line/>",
        2,
        "a=\"1e300\" b=\"0\" c=\"0\" d=\"0\"",
        "-1",
    ));
    assert!(
        e.contains("road 1, lane section 0, lane -1, width 0") && e.contains("m wide"),
        "{e}"
    );
    // 3.5 m at both ends, 28.5 m in the middle.
    let e = map_error(&one_road(
        100.0,
        "<line/>",
        1,
        "a=\"3.5\" b=\"1\" c=\"-0.01\" d=\"0\"",
        "-1",
    ));
    assert!(e.contains("m wide"), "{e}");
    let e = map_error(&one_road(100.0, "<line/>", 1, W, "777"));
    assert!(
        e.contains("road 1") && e.contains("junction=\"777\" names no <junction>"),
        "{e}"
    );
    // Through the CLI: the run stops, naming the map file (never scored with it).
    let run = Run::new();
    let maps = run.path("wide-maps");
    fs::create_dir_all(&maps).unwrap();
    let good = fs::read_to_string(run.path("maps/DemoTown.xodr")).unwrap();
    fs::write(
        maps.join("DemoTown.xodr"),
        good.replacen("a=\"3.5\"", "a=\"1e300\"", 1),
    )
    .unwrap();
    let o = run.score(
        &run.s("results.json"),
        &[
            "--routes",
            &run.s("routes.xml"),
            "--maps",
            maps.to_str().unwrap(),
        ],
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("DemoTown.xodr") && stderr(&o).contains("m wide"),
        "{}",
        stderr(&o)
    );
}

/// Finding 6: under `--routes` an invalid record whose id is not in the XML was hidden as
/// `foreign` (empty reason, exit 0); without `--routes` it is `invalid`, exit 3.
#[test]
fn an_invalid_record_stays_invalid_under_routes() {
    let run = Run::new();
    let mut recs = run.records.clone();
    recs[0]["route_id"] = json!("RouteScenario_424242_rep0");
    recs[0]["scores"]["score_route"] = json!("oops");
    let results = run.write("bad.json", &recs);
    for extra in [&[][..], &["--routes", &run.s("routes.xml")]] {
        let r = report(&run.score(&results, extra), 3);
        let route = r["routes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["route_id"] == "RouteScenario_424242_rep0")
            .unwrap_or_else(|| panic!("{extra:?}: the record is not in the report"));
        assert_eq!(route["state"], "invalid", "{extra:?}: {route}");
        assert!(
            route["reason"].as_str().unwrap().contains("score_route"),
            "{extra:?}: {route}"
        );
    }
}

/// Finding 7: a mistyped `--infraction` added a column of zeros.
#[test]
fn an_unknown_infraction_list_is_a_usage_error() {
    let run = Run::new();
    let o = run.score(
        &run.s("results.json"),
        &[
            "--group-by",
            "weather",
            "--infraction",
            "collisions_vehicel",
        ],
    );
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("collisions_vehicel") && e.contains("collisions_vehicle, collisions_layout"),
        "{e}"
    );
    assert!(o.stdout.is_empty());
    let o = run.score(
        &run.s("results.json"),
        &[
            "--group-by",
            "weather",
            "--infraction",
            "collisions_vehicle",
            "--format",
            "table",
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

/// Copies each record's telemetry to a save_name that names no route (`t<i>`), so that its
/// route id can be changed freely.
fn free_ids(run: &Run, recs: &mut [Value]) {
    for (i, r) in recs.iter_mut().enumerate() {
        let from = run.path("telemetry").join(r["save_name"].as_str().unwrap());
        let to = run.path("telemetry").join(format!("t{i}"));
        fs::create_dir_all(&to).unwrap();
        fs::copy(from.join("metric_info.json"), to.join("metric_info.json")).unwrap();
        r["save_name"] = json!(format!("t{i}"));
    }
}

/// The number `sds` says it wrote in "wrote N collision trace(s)".
fn traces_announced(o: &Output) -> usize {
    let e = stderr(o);
    let i = e.find("wrote ").unwrap_or_else(|| panic!("{e}")) + 6;
    e[i..].split(' ').next().unwrap().parse().unwrap()
}

/// Finding 8: trace file names collided when ids differ only in replaced characters or under
/// `--duplicates all` (6 traces announced, 5 pairs on disk).
#[test]
fn trace_file_names_are_unique_and_the_count_true() {
    let run = Run::new();
    let mut recs = run.records.clone();
    // Every record twice, and each colliding id once more with a `/` where the `_` was.
    let mut more: Vec<Value> = recs.clone();
    for r in &recs {
        let mut c = r.clone();
        c["route_id"] = json!(r["route_id"].as_str().unwrap().replace("_rep", "/rep"));
        more.push(c);
    }
    recs.extend(more);
    free_ids(&run, &mut recs);
    let results = run.write("dups.json", &recs);
    let traces = run.path("traces");
    let o = run.score(
        &results,
        &[
            "--duplicates",
            "all",
            "--traces",
            traces.to_str().unwrap(),
            "-o",
            &run.s("r.json"),
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let n = traces_announced(&o);
    let files: Vec<String> = fs::read_dir(&traces)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let svgs = files.iter().filter(|f| f.ends_with(".svg")).count();
    let csvs = files.iter().filter(|f| f.ends_with(".csv")).count();
    assert!(n >= 6, "{n}");
    assert_eq!((svgs, csvs), (n, n), "{files:#?}");
    // The plain name stays for a trace whose name is its own.
    let o = run.score(
        &run.s("results.json"),
        &["--traces", &run.s("plain"), "-o", &run.s("r2.json")],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(run
        .path("plain/RouteScenario_900005_rep0_collision0.svg")
        .is_file());
}

/// Finding 13: a `--traces` failure (a 254-character route id: name too long) exited 1, "no
/// report" by the README, after the report was written, leaving traces half-written. Now the
/// traces are written first: a long id is cut, and a trace that cannot be written stops the
/// run before the report, with the traces written so far removed.
#[test]
fn a_traces_failure_leaves_no_report_and_no_half_written_traces() {
    let run = Run::new();
    let mut recs = run.records.clone();
    free_ids(&run, &mut recs);
    let long = format!("RouteScenario_{}", "9".repeat(240));
    recs[4]["route_id"] = json!(long);
    let results = run.write("long.json", &recs);
    let out = run.path("report.json");
    let traces = run.path("traces");
    let o = run.score(
        &results,
        &[
            "--traces",
            traces.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(out.is_file());
    let n = traces_announced(&o);
    assert_eq!(fs::read_dir(&traces).unwrap().count(), 2 * n);
    // A trace that cannot be written: its name is taken by a folder.
    let (out2, traces2) = (run.path("report2.json"), run.path("traces2"));
    fs::create_dir_all(traces2.join("RouteScenario_900006_rep0_collision0.svg")).unwrap();
    let o = sds(&[
        "score",
        "--results",
        &run.s("results.json"),
        "--telemetry",
        &run.s("telemetry"),
        "--traces",
        traces2.to_str().unwrap(),
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(!out2.exists(), "a report was written");
    assert!(
        stderr(&o).contains("RouteScenario_900006_rep0_collision0.svg"),
        "{}",
        stderr(&o)
    );
    let left: Vec<_> = fs::read_dir(&traces2).unwrap().collect();
    assert_eq!(left.len(), 1, "traces left behind: {left:?}");
}

/// Finding 12: `sds demo DIR --score` overwrote an existing `report.html` and `traces/` without
/// `--force`.
#[test]
fn demo_score_never_overwrites_a_report_without_force() {
    for leftover in ["report.html", "traces", "figures"] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        if leftover != "report.html" {
            fs::create_dir_all(dir.join(leftover)).unwrap();
        } else {
            fs::write(dir.join(leftover), "mine").unwrap();
        }
        let o = sds(&["demo", dir.to_str().unwrap(), "--score"]);
        assert_ne!(code(&o), 0, "{leftover}: overwritten");
        assert!(
            stderr(&o).contains(leftover) && stderr(&o).contains("--force"),
            "{}",
            stderr(&o)
        );
        assert!(
            !dir.join("results.json").exists(),
            "{leftover}: demo written"
        );
        if leftover == "report.html" {
            assert_eq!(fs::read_to_string(dir.join(leftover)).unwrap(), "mine");
        }
        let o = sds(&["demo", dir.to_str().unwrap(), "--score", "--force"]);
        assert_eq!(code(&o), 0, "{}", stderr(&o));
        assert!(dir.join("report.html").is_file());
        // The pictures of the page, as SVG files for a paper (issue 28).
        for svg in ["decomposition.svg", "routes.svg"] {
            let text = fs::read_to_string(dir.join("figures").join(svg)).unwrap();
            assert!(text.starts_with("<svg") && text.contains("DS"), "{svg}");
        }
    }
}

/// Finding 10: `--maps` problems ended as "no map", exit 0: a mistyped folder, a file instead
/// of a folder (now usage errors, exit 2, as `--telemetry`), a town map that is a FIFO, a
/// dangling or looping link or a directory (now an error naming the file and the cause).
#[test]
fn maps_usage_errors_are_reported() {
    use std::os::unix::fs::symlink;
    let run = Run::new();
    let results = run.s("results.json");
    let routes = run.s("routes.xml");
    let score = |maps: &Path| {
        run.score(
            &results,
            &["--routes", &routes, "--maps", maps.to_str().unwrap()],
        )
    };
    for (what, path, says) in [
        ("missing", run.path("mpas"), "no such folder"),
        ("a file", run.path("results.json"), "not a folder"),
    ] {
        let o = score(&path);
        assert_eq!(code(&o), 2, "{what}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("--maps") && stderr(&o).contains(says),
            "{what}: {}",
            stderr(&o)
        );
    }
    /// A way to break a town map: its name, how, and what the error says.
    type Breakage<'a> = (&'a str, &'a dyn Fn(&Path), &'a str);
    let cases: [Breakage; 4] = [
        (
            "fifo",
            &|p: &Path| {
                let c = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
                assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
            },
            "FIFO",
        ),
        (
            "dangling",
            &|p: &Path| symlink(p.with_file_name("nowhere.xodr"), p).unwrap(),
            "No such file",
        ),
        ("loop", &|p: &Path| symlink(p, p).unwrap(), "symbolic links"),
        ("dir", &|p: &Path| fs::create_dir(p).unwrap(), "directory"),
    ];
    for (what, make, says) in cases {
        let dir = run.path(&format!("maps-{what}"));
        fs::create_dir_all(&dir).unwrap();
        make(&dir.join("DemoTown.xodr"));
        let o = score(&dir);
        assert_eq!(code(&o), 1, "{what}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&format!("maps-{what}/DemoTown.xodr")) && e.contains(says),
            "{what}: {e}"
        );
    }
}

/// Finding 16: label files parsed leniently: an unclosed CSV quote swallowed the rest of the
/// file (exit 0), an empty label became a group `""`, JSON `null` / objects / nested lists
/// became labels, a JSON file with a BOM was read as CSV.
#[test]
fn label_files_are_parsed_strictly() {
    use monitor_host::input::labels::parse_labels;
    let bad = [
        (
            "unclosed.csv",
            "RouteScenario_900001_rep0,\"easy\nRouteScenario_900002_rep0,hard\n",
            "unclosed",
        ),
        ("empty.csv", "RouteScenario_900001_rep0,\n", "empty label"),
        ("empty-key.csv", ",hard\n", "empty key"),
        (
            "null.json",
            r#"{"RouteScenario_900001_rep0": null}"#,
            "null is not a label",
        ),
        (
            "object.json",
            r#"{"RouteScenario_900001_rep0": {"a": 1}}"#,
            "is not a label",
        ),
        (
            "nested.json",
            r#"{"RouteScenario_900001_rep0": [["a"]]}"#,
            "is not a label",
        ),
        (
            "bool.json",
            r#"{"RouteScenario_900001_rep0": true}"#,
            "is not a label",
        ),
        (
            "empty.json",
            r#"{"RouteScenario_900001_rep0": ""}"#,
            "empty label",
        ),
        (
            "none.json",
            r#"{"RouteScenario_900001_rep0": []}"#,
            "empty list",
        ),
    ];
    let run = Run::new();
    for (name, text, says) in bad {
        let e = parse_labels(text, name).expect_err(name).to_string();
        assert!(e.contains(name) && e.contains(says), "{name}: {e}");
        let path = run.path(name);
        fs::write(&path, text).unwrap();
        let o = run.score(
            &run.s("results.json"),
            &["--group-by", "route", "--labels", path.to_str().unwrap()],
        );
        assert_ne!(code(&o), 0, "{name}: accepted");
        assert!(o.stdout.is_empty(), "{name}: a report was written");
        assert!(stderr(&o).contains(says), "{name}: {}", stderr(&o));
    }
    // A BOM before JSON: still JSON.
    let m = parse_labels("\u{feff}{\"RouteScenario_1_rep0\": [\"a\", 7]}", "bom.json").unwrap();
    assert_eq!(m["RouteScenario_1_rep0"], ["a", "7"]);
    let m = parse_labels("\u{feff}k,v\n", "bom.csv").unwrap();
    assert_eq!(m["k"], ["v"]);
    // What was accepted still is: quoted commas, several labels, comments.
    let m = parse_labels("# c\nA,\"x, y\"\nA,z\n", "ok.csv").unwrap();
    assert_eq!(m["A"], ["x, y", "z"]);
}

/// Finding 15: `sds compare`: the same file as three seeds gave `± 0.00` without a word; a run
/// in two `--seeds` models counted only in the first; a missing run folder was blamed on
/// `--telemetry` (an option compare does not have); a folder named `lr=0.1` was split into a
/// name and a path.
#[test]
fn compare_problems_are_named() {
    let run = Run::new();
    // Its own folder per run: the results beside their telemetry.
    let results = run.s("results.json");
    let compare = |args: &[&str]| {
        let mut a = vec!["compare", "--allow-missing-telemetry", "--format", "json"];
        a.extend_from_slice(args);
        sds(&a)
    };
    let (a, b, c) = (
        format!("m_1={results}"),
        format!("m_2={results}"),
        format!("m_3={results}"),
    );
    let o = compare(&[&a, &b, &c]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("runs m_1 and m_2 are the same results") && e.contains("m_3"),
        "{e}"
    );
    let o = compare(&[&a, &b, "--seeds", "x=m_1,m_2", "--seeds", "y=m_2"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("run m_2 is a seed of x and of y"),
        "{}",
        stderr(&o)
    );
    let missing = run.s("no-such-run");
    let o = compare(&[&a, &missing]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("run no-such-run") && e.contains("No such file or directory"),
        "{e}"
    );
    assert!(!e.contains("--telemetry"), "{e}");
    // A folder named `lr=0.1`: a path, named by its folder.
    let lr = run.path("lr=0.1");
    fs::create_dir_all(&lr).unwrap();
    fs::copy(run.path("results.json"), lr.join("results.json")).unwrap();
    // Given relative to the working folder, as typed.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_sds"))
        .current_dir(run.tmp.path())
        .args([
            "compare",
            "--allow-missing-telemetry",
            "--format",
            "json",
            "lr=0.1",
            &a,
        ])
        .output()
        .unwrap();
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v.to_string().contains("\"lr=0.1\""), "{v}");
}
