//! Hostile and careless input: markup in names, planted links, huge counts, interrupted writes.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{json, Value};

use crate::common::{self, sds};

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

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Markup a name may carry: HTML, a link, an image, bare URLs, emphasis, code, an entity.
const MARKUP: [&str; 6] = [
    "<script>alert(1)</script>",
    "[see the log](https://evil.example)",
    "![](https://evil.example/pixel.png)",
    "https://evil.example www.evil.example",
    "*em* _em_ **b** ~~del~~ `code` $x$",
    "&lt;b&gt; &#106; <img src=x onerror=alert(1)> \\| a|b",
];

/// What a CommonMark renderer (with GitHub's tables and strikethrough) makes of `md`: its HTML
/// and its text. Panics on any markup beyond the tables' own and `**` (the title, the total).
fn render_markdown(md: &str) -> (String, String) {
    use pulldown_cmark::{Event, Options, Parser, Tag};
    let opts = Options::ENABLE_TABLES | Options::ENABLE_STRIKETHROUGH | Options::ENABLE_MATH;
    let mut text = String::new();
    let events: Vec<Event> = Parser::new_ext(md, opts).collect();
    for e in &events {
        match e {
            Event::Text(t) => text.push_str(t),
            Event::SoftBreak | Event::HardBreak => text.push('\n'),
            Event::Start(Tag::Table(_) | Tag::TableHead | Tag::TableRow | Tag::Paragraph)
            | Event::Start(Tag::TableCell | Tag::Strong)
            | Event::End(_) => {}
            Event::Start(t) => panic!("live markup {t:?} in\n{md}"),
            other => panic!("live markup {other:?} in\n{md}"),
        }
        if matches!(e, Event::End(pulldown_cmark::TagEnd::TableCell)) {
            text.push('\t');
        }
    }
    let mut html = String::new();
    pulldown_cmark::html::push_html(&mut html, events.into_iter());
    (html, text)
}

/// Checks a Markdown rendering: no HTML, link or image, no bare URL a GitHub renderer links,
/// and each name in `names` read back as its text.
fn assert_inert(what: &str, md: &str, names: &[&str]) {
    let (html, text) = render_markdown(md);
    for tag in ["<script", "<a ", "<img", "<em>", "<code>", "<del>"] {
        assert!(!html.contains(tag), "{what}: {tag} in\n{html}");
    }
    // GitHub links `https://...` and `www....` in text by itself (pulldown-cmark does not).
    assert!(
        !md.replace("\\://", "").contains("://") && !md.contains("www."),
        "{what}: a bare URL in\n{md}"
    );
    for n in names {
        assert!(
            text.contains(n),
            "{what}: {n:?} does not read as itself in\n{text}"
        );
    }
}

/// Finding 1: `--format markdown` of `score` and `compare` wrote scenario names and run names
/// raw: rendered, `<script>` ran, a link and a tracking image went live.
#[test]
fn r3_01_markdown_cells_render_as_their_text() {
    let run = Run::new();
    let mut recs = run.records.clone();
    for (r, m) in recs.iter_mut().zip(MARKUP) {
        r["scenario_name"] = json!(format!("{m}_1"));
    }
    let results = run.write("evil.json", &recs);
    for by in ["scenario", "town"] {
        let o = run.score(&results, &["--format", "markdown", "--group-by", by]);
        assert_eq!(code(&o), 0, "{}", stderr(&o));
        let md = String::from_utf8(o.stdout).unwrap();
        let names: &[&str] = if by == "scenario" { &MARKUP } else { &[] };
        assert_inert(&format!("score --group-by {by}"), &md, names);
    }
    // Run names (no `/` in a name): a folder's name, and `NAME=`.
    let folder = run.path("<script>alert(1)<script> [x](javascript:alert(1)) www.evil.example");
    fs::create_dir(&folder).unwrap();
    fs::copy(run.path("results.json"), folder.join("results.json")).unwrap();
    let tel = run.s("telemetry");
    let a = format!("{}:{tel}", folder.display());
    let b = format!("![](x.png) *b* `c` &amp;={}:{tel}", run.s("results.json"));
    let o = sds(&["compare", &a, &b, "--format", "markdown"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let md = String::from_utf8(o.stdout).unwrap();
    let folder_name = folder.file_name().unwrap().to_str().unwrap();
    assert_inert("compare", &md, &[folder_name, "![](x.png) *b* `c` &amp;"]);
}
