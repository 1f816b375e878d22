//! Golden report: the demo run's JSON report, byte for byte, against the copy committed in
//! `tests/golden/demo-report.json`. Any change to the report shows up in review as a diff of that
//! file.
//!
//! The demo is written to a temporary folder; its path in the report (`source`) is replaced by
//! `<demo>`, and the host name in its provenance by `<host>`. After an intended change to the report, regenerate the file with
//! `SDS_BLESS=1 cargo test -p monitor-host --release --test it golden` and commit it with the change.

use std::path::Path;

use monitor_host::{demo, report, score_run, Inputs, Settings};

const GOLDEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/demo-report.json");

fn demo_report(settings: &Settings) -> String {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry),
        route_xml: Some(run.routes),
        maps: Some(run.maps),
        ..Inputs::new([run.results])
    };
    let report = score_run(&inputs, settings).unwrap();
    let json = String::from_utf8(report::json::json(&report).unwrap()).unwrap();
    let root = dir.path().display().to_string();
    assert!(json.contains(&root), "the report names the results file");
    let json = json.replace(&root, "<demo>");
    // The provenance names the machine: the golden file names none.
    match monitor_host::provenance::host_name() {
        Some(host) => json.replace(
            &format!("\"host\": {}", serde_json::to_string(&host).unwrap()),
            "\"host\": \"<host>\"",
        ),
        None => json.replace("\"host\": null", "\"host\": \"<host>\""),
    }
}

#[test]
fn demo_report_matches_the_golden_file() {
    let got = demo_report(&Settings::default());
    if std::env::var_os("SDS_BLESS").is_some_and(|v| v == "1") {
        std::fs::write(GOLDEN, &got).unwrap();
        eprintln!("blessed {GOLDEN}");
        return;
    }
    let want = std::fs::read_to_string(Path::new(GOLDEN)).unwrap_or_else(|e| {
        panic!(
            "{GOLDEN}: {e} (create it with SDS_BLESS=1 cargo test -p monitor-host --release --test it golden)"
        )
    });
    if got != want {
        let line = got
            .lines()
            .zip(want.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| got.lines().count().min(want.lines().count()));
        panic!(
            "the demo report differs from {GOLDEN} at line {}:\n  got:  {}\n  want: {}\n\
             If the change is intended, regenerate with SDS_BLESS=1 and commit the file.",
            line + 1,
            got.lines().nth(line).unwrap_or("<end>"),
            want.lines().nth(line).unwrap_or("<end>")
        );
    }
}

#[test]
fn a_changed_setting_changes_the_report() {
    // The golden comparison can fail: a different slack gives a different report.
    let mut settings = Settings::default();
    settings.set("slack", "0.5").unwrap();
    let other = demo_report(&settings);
    let want = std::fs::read_to_string(GOLDEN).unwrap_or_default();
    assert_ne!(other, want);
}

/// A report written and read back by the types that write it: the same bytes again, and the
/// typed states (whose reasons the row states once) the same.
fn reads_back(report: &monitor_host::Report, what: &str) {
    let bytes = report::json::json(report).unwrap();
    let back = monitor_host::Report::from_json(&bytes).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(
        String::from_utf8(report::json::json(&back).unwrap()).unwrap(),
        String::from_utf8(bytes).unwrap(),
        "{what}: written again differently"
    );
    assert_eq!(back.summary, report.summary, "{what}");
    assert_eq!(back.groups, report.groups, "{what}");
    assert_eq!(back.config, report.config, "{what}");
    for (a, b) in back.routes.iter().zip(&report.routes) {
        assert_eq!((&a.state, &a.telemetry), (&b.state, &b.telemetry), "{what}");
        assert_eq!(a.kept, b.kept, "{what}");
        assert_eq!(a.events, b.events, "{what}");
    }
}

#[test]
fn i48_2_every_golden_report_reads_back_byte_for_byte() {
    let dir = Path::new(GOLDEN).parent().unwrap();
    let mut read = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "json") {
            continue;
        }
        let bytes = std::fs::read(&path).unwrap();
        let back = monitor_host::Report::read(&path).unwrap_or_else(|e| panic!("{e}"));
        let again = report::json::json(&back).unwrap();
        assert!(
            again == bytes,
            "{}: read back and written again, it differs",
            path.display()
        );
        reads_back(&back, &path.display().to_string());
        read += 1;
    }
    assert!(read >= 1, "no golden report in {}", dir.display());
}

#[test]
fn i48_2_reports_of_every_shape_read_back() {
    use monitor_host::aggregate::groups::GroupBy;
    use monitor_host::input::duplicates::DuplicatePolicy;
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let inputs = Inputs {
        telemetry: Some(run.telemetry.clone()),
        route_xml: Some(run.routes.clone()),
        maps: Some(run.maps.clone()),
        ..Inputs::new([run.results.clone()])
    };
    // Every protocol (per-route and summary `protocols`, `min_speed_grid`), a breakdown by
    // group, and the legacy profile with a route count N beyond the routes found.
    let mut all = Settings::default();
    all.apply_pairs([
        ("protocols", "all"),
        ("profile", "b2d-legacy"),
        ("expected_routes", "40"),
    ])
    .unwrap();
    let mut grouped = score_run(&inputs, &all).unwrap();
    grouped.group(GroupBy::Scenario, None).unwrap();
    reads_back(&grouped, "protocols, groups, b2d-legacy");
    // Without telemetry: missing telemetry, its reasons.
    let bare = Settings {
        allow_missing_telemetry: true,
        ..Settings::default()
    };
    let no_telemetry = score_run(&Inputs::new([run.results.clone()]), &bare).unwrap();
    assert!(no_telemetry
        .routes
        .iter()
        .any(|r| r.telemetry.reason().is_some_and(|r| !r.is_empty())));
    reads_back(&no_telemetry, "no telemetry");
    // A merged report (its parts' inputs) of two copies of the run: `kept`, `dropped`.
    let part = dir.path().join("part.json");
    std::fs::write(
        &part,
        report::json::json(&score_run(&inputs, &Settings::default()).unwrap()).unwrap(),
    )
    .unwrap();
    let merged =
        monitor_host::merge::merge(&[part.clone(), part], DuplicatePolicy::Last, false).unwrap();
    assert!(!merged.dropped.is_empty());
    assert!(merged.routes.iter().any(|r| r.kept.is_some()));
    reads_back(&merged, "a merge with duplicates = last");
}
