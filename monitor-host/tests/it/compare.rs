//! `sds compare`: paired intervals, verdicts, the gate and what the tables and page show.

// ---- issue 33 item 5: the ability rule named in compare's tables (engineer `protocols`) ----

/// `sds compare --ability-rule b2d-0.0.3` names the rule in its Bench2Drive table heading, as
/// `sds score`'s does, in text, Markdown and LaTeX.
#[test]
fn i33_5_compare_tables_name_the_ability_rule() {
    let dir = tempfile::tempdir().unwrap();
    crate::common::demo(dir.path());
    let results = dir.path().join("results.json");
    let telemetry = dir.path().join("telemetry");
    let run = |name: &str| format!("{name}={}:{}", results.display(), telemetry.display());
    let (a, b) = (run("a"), run("b"));
    let routes = dir.path().join("routes.xml");
    for (rule, extra) in [
        ("b2d-0.0.3", vec!["--ability-rule", "b2d-0.0.3"]),
        ("b2d-0.0.4", vec![]),
    ] {
        for format in ["table", "markdown", "latex"] {
            let mut args = vec![
                "compare",
                &a,
                &b,
                "--routes",
                routes.to_str().unwrap(),
                "--bootstrap-samples",
                "1000",
                "--format",
                format,
            ];
            args.extend(extra.iter().copied());
            let out = crate::common::sds(&args);
            let text = String::from_utf8_lossy(&out.stdout);
            let heading = text
                .lines()
                .find(|l| l.contains("Bench2Drive: closed-loop metrics"))
                .unwrap_or_else(|| {
                    panic!(
                        "{format}: no Bench2Drive table: {}",
                        String::from_utf8_lossy(&out.stderr)
                    )
                });
            assert!(
                heading.contains(&format!("ability rule {rule}")),
                "{format}: {heading}"
            );
        }
    }
}
