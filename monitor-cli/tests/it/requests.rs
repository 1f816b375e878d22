//! The options of a command as the library names them (issue 48 item 1): the command line's
//! choices are the library's enum names, and every command that scores reads `score`'s options
//! from one definition (`RunArgs`), so an option added there reaches each of them.

use monitor_host::demo::LargeLayout;
use monitor_host::settings::AbilityRule;

use crate::common::{code, s, sds, stderr};

/// A refused choice lists exactly the library's names: `--ability-rule` (AbilityRule, kept as
/// text in RunSettings) and `sds demo --layout` (LargeLayout, once a CLI mirror enum).
#[test]
fn i48_1_choices_are_the_librarys_names() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(Vec<String>, &[&str]); 2] = [
        (
            ["score", "--results", "r.json", "--ability-rule", "nope"]
                .map(String::from)
                .to_vec(),
            AbilityRule::NAMES,
        ),
        (
            vec![
                "demo".into(),
                s(&dir.path().join("d")),
                "--large".into(),
                "--layout".into(),
                "nope".into(),
            ],
            LargeLayout::NAMES,
        ),
    ];
    for (args, names) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = sds(&args);
        let err = stderr(&out);
        assert_eq!(code(&out), 2, "{args:?}: {err}");
        let listed = format!("[possible values: {}]", names.join(", "));
        assert!(
            err.contains(&listed),
            "{args:?}: expected {listed} in: {err}"
        );
    }
    // Each name is accepted as it is spelled in the library.
    for name in LargeLayout::NAMES {
        let d = dir.path().join(format!("large-{name}"));
        let out = sds(&[
            "demo",
            &s(&d),
            "--large",
            "--large-routes",
            "1",
            "--large-frames",
            "50",
            "--layout",
            name,
        ]);
        assert_eq!(code(&out), 0, "--layout {name}: {}", stderr(&out));
    }
}

/// `sds frames` takes every option of `score` (one `RunArgs`): the options that do not change a
/// frame are accepted and leave the frames as they are; one that does (`--set slack=...`, the
/// lateral slack behind each frame's value) is read.
#[test]
fn i48_1_frames_takes_every_score_option() {
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    let d = |p: &str| s(&dir.path().join(p));
    let (results, telemetry, routes) = (d("results.json"), d("telemetry"), d("routes.xml"));
    let base = [
        "frames",
        "--results",
        &results,
        "--telemetry",
        &telemetry,
        "--routes",
        &routes,
        "--route-id",
        "RouteScenario_900005_rep0",
    ];
    let plain = sds(&base);
    assert_eq!(code(&plain), 0, "{}", stderr(&plain));
    assert!(!plain.stdout.is_empty());
    let mut with = base.to_vec();
    with.extend([
        "--expected-routes",
        "9",
        "--jobs",
        "1",
        "--ability-rule",
        "b2d-0.0.3",
        "--protocol",
        "lb2.1",
        "--allow-missing-telemetry",
    ]);
    let out = sds(&with);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert_eq!(
        out.stdout, plain.stdout,
        "options that change no frame changed the frames"
    );
    let mut slack = base.to_vec();
    slack.extend(["--set", "slack=0.5"]);
    let out = sds(&slack);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert_ne!(out.stdout, plain.stdout, "--set slack was not read");
}

/// `--lateral-reference` (a named option added after the move to one request per command, in
/// the four places docs/DESIGN.md "Adding a named option to score" lists): the same report as
/// `--set lateral_reference=...`, given before the overrides (a later `--set` wins), and its
/// choices are the library's names.
#[test]
fn i48_1_lateral_reference_is_a_named_option() {
    use monitor_host::settings::LateralReference;
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    let maps = s(&dir.path().join("maps"));
    let json = |extra: &[&str]| {
        let mut args = vec!["--maps", maps.as_str(), "--format", "json"];
        args.extend_from_slice(extra);
        let out = crate::common::score_demo(dir.path(), None, &args);
        assert_eq!(code(&out), 0, "{extra:?}: {}", stderr(&out));
        out.stdout
    };
    let config = |bytes: &[u8]| -> String {
        let v: serde_json::Value = serde_json::from_slice(bytes).unwrap();
        v["config"]["lateral_reference"]
            .as_str()
            .unwrap()
            .to_string()
    };
    let route = json(&[]);
    let lane = json(&["--lateral-reference", "lane"]);
    assert_eq!(config(&route), "route");
    assert_eq!(config(&lane), "lane");
    assert_eq!(lane, json(&["--set", "lateral_reference=lane"]));
    assert_ne!(lane, route, "--lateral-reference lane changed nothing");
    // Named options come before the overrides: the later `--set` wins.
    assert_eq!(
        route,
        json(&[
            "--lateral-reference",
            "lane",
            "--set",
            "lateral_reference=route"
        ])
    );
    let out = crate::common::score_demo(dir.path(), None, &["--lateral-reference", "nope"]);
    assert_eq!(code(&out), 2);
    let listed = format!("[possible values: {}]", LateralReference::NAMES.join(", "));
    assert!(stderr(&out).contains(&listed), "{}", stderr(&out));
}
