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
