//! Hostile and careless input: markup in names, planted links, huge counts, interrupted writes.

use std::fs;
use std::path::Path;

use serde_json::{json, Value};

use crate::common::{code, sds, stderr, Run};

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
    keep_for_the_browser(what, &html);
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

/// With `SDS_MARKDOWN_HTML_OUT=DIR` (scripts/markdown-browser-test.sh), writes the rendered
/// HTML of `what` into DIR for headless Chromium, and once a control page: the same names
/// rendered unescaped, on which the browser check must find live markup (or it checks nothing).
fn keep_for_the_browser(what: &str, html: &str) {
    let Some(dir) = std::env::var_os("SDS_MARKDOWN_HTML_OUT") else {
        return;
    };
    let dir = Path::new(&dir);
    fs::create_dir_all(dir).unwrap();
    let page = |body: &str| format!("<!DOCTYPE html><html><body>\n{body}</body></html>\n");
    let name: String = what
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    fs::write(dir.join(format!("{name}.html")), page(html)).unwrap();
    let mut control = String::new();
    // Live, but without `alert` (a dialog would hold headless Chromium until its timeout).
    let raw = MARKUP.join("\n\n").replace("alert(1)", "void 0");
    pulldown_cmark::html::push_html(&mut control, pulldown_cmark::Parser::new(&raw));
    fs::write(dir.join("control.html"), page(&control)).unwrap();
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

/// Every file in `dir` with its contents, sorted (none: the folder is absent).
fn listing(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let Ok(rd) = fs::read_dir(dir) else {
        return vec![];
    };
    let mut v: Vec<(String, Vec<u8>)> = rd
        .map(|e| {
            let e = e.unwrap();
            let bytes = fs::read(e.path()).unwrap_or_default();
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect();
    v.sort();
    v
}

const TRACE: &str = "RouteScenario_900005_rep0_collision0";

/// Finding 2: `--figures` / `--traces` wrote through a symbolic link planted at a name the
/// tool chose (`routes.svg`, `<route>_collision<i>.csv`), overwriting a private file outside.
#[test]
fn r3_02_a_planted_link_at_a_chosen_name_is_never_followed() {
    let run = Run::new();
    let private = run.path("private.txt");
    fs::write(&private, "secret").unwrap();
    let (figs, traces) = (run.path("figs"), run.path("traces"));
    fs::create_dir(&figs).unwrap();
    fs::create_dir(&traces).unwrap();
    for (dir, name, flag) in [
        (&figs, "routes.svg".to_string(), "--figures"),
        (&traces, format!("{TRACE}.csv"), "--traces"),
    ] {
        let link = dir.join(&name);
        std::os::unix::fs::symlink(&private, &link).unwrap();
        let out = run.path("report.json");
        let o = run.score(
            &run.s("results.json"),
            &[flag, dir.to_str().unwrap(), "-o", out.to_str().unwrap()],
        );
        assert_eq!(code(&o), 1, "{flag}: {}", stderr(&o));
        assert_eq!(fs::read_to_string(&private).unwrap(), "secret", "{flag}");
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert!(
            stderr(&o).contains(&name) && stderr(&o).contains("symbolic link"),
            "{flag}: {}",
            stderr(&o)
        );
        assert!(!out.exists(), "{flag}: a report was written");
        // Nothing else is left in the folder: only the planted link.
        assert_eq!(listing(dir).len(), 1, "{flag}: {:?}", listing(dir));
        fs::remove_file(&link).unwrap();
    }
}

/// Finding 3: when a later figure or trace failed, "all or nothing" removed the user's own
/// `decomposition.svg` and a previous run's traces. Only what the call created is removed; what
/// it replaced is put back.
#[test]
fn r3_03_a_failed_write_puts_back_what_it_replaced() {
    let run = Run::new();
    let (figs, traces) = (run.path("figs"), run.path("traces"));
    fs::create_dir(&figs).unwrap();
    fs::create_dir(&traces).unwrap();
    fs::write(figs.join("decomposition.svg"), "my own drawing").unwrap();
    fs::write(figs.join("notes.txt"), "mine").unwrap();
    fs::write(traces.join(format!("{TRACE}.csv")), "previous run").unwrap();
    let (figs_before, traces_before) = (listing(&figs), listing(&traces));
    // routes.svg cannot be written (a folder has its name): the figures fail after the traces
    // and decomposition.svg were written.
    fs::create_dir(figs.join("routes.svg")).unwrap();
    let out = run.path("report.json");
    let args = [
        "--traces",
        traces.to_str().unwrap(),
        "--figures",
        figs.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    let o = run.score(&run.s("results.json"), &args);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("routes.svg"), "{}", stderr(&o));
    assert_eq!(listing(&traces), traces_before);
    let mut figs_after = listing(&figs);
    figs_after.retain(|(n, _)| n != "routes.svg");
    assert_eq!(figs_after, figs_before);
    assert!(!out.exists());
    // The report itself failing (its folder is missing) undoes the traces and figures too.
    fs::remove_dir(figs.join("routes.svg")).unwrap();
    let bad_out = run.path("missing/report.json");
    let args = [
        "--traces",
        traces.to_str().unwrap(),
        "--figures",
        figs.to_str().unwrap(),
        "-o",
        bad_out.to_str().unwrap(),
    ];
    let o = run.score(&run.s("results.json"), &args);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert_eq!(listing(&traces), traces_before);
    assert_eq!(listing(&figs), figs_before);
    // A folder the run created is removed again.
    let fresh = run.path("fresh/traces");
    let args = [
        "--traces",
        fresh.to_str().unwrap(),
        "-o",
        bad_out.to_str().unwrap(),
    ];
    let o = run.score(&run.s("results.json"), &args);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(!run.path("fresh").exists());
}

/// Finding 9: Ctrl-C while the traces were written left them on disk.
#[test]
fn r3_09_ctrl_c_while_writing_traces_undoes_them() {
    let run = Run::new();
    let traces = run.path("traces");
    fs::create_dir(&traces).unwrap();
    fs::write(traces.join(format!("{TRACE}.csv")), "previous run").unwrap();
    let before = listing(&traces);
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_sds"))
        .args([
            "score",
            "--results",
            &run.s("results.json"),
            "--telemetry",
            &run.s("telemetry"),
            "--traces",
            traces.to_str().unwrap(),
            "-o",
            &run.s("report.json"),
        ])
        .env("SDS_TEST_PLACE_HOLD", "4")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once 4 of the 10 traces are on disk: the run waits there for the signal (test
    // seam), so it is interrupted half-way whatever the machine's load.
    let start = std::time::Instant::now();
    while listing(&traces).len() < before.len() + 4 {
        assert!(start.elapsed().as_secs() < 60, "no trace appeared");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    // SAFETY: signalling our own child.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let o = child.wait_with_output().unwrap();
    assert!(!o.status.success());
    assert_eq!(listing(&traces), before, "{}", stderr(&o));
    assert!(!run.path("report.json").exists());
}

/// Finding 9: `-o` naming a figure or a trace wrote the report over it.
#[test]
fn r3_09_an_output_among_the_figures_or_traces_is_refused() {
    let run = Run::new();
    let (figs, traces) = (run.path("figs"), run.path("traces"));
    for (flag, dir, out) in [
        ("--figures", &figs, figs.join("routes.svg")),
        ("--figures", &figs, figs.join("./decomposition.svg")),
        ("--traces", &traces, traces.join(format!("{TRACE}.svg"))),
    ] {
        let o = run.score(
            &run.s("results.json"),
            &[flag, dir.to_str().unwrap(), "-o", out.to_str().unwrap()],
        );
        assert_eq!(code(&o), 2, "{out:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("choose another output path"),
            "{}",
            stderr(&o)
        );
        assert!(listing(dir).is_empty(), "{out:?}: {:?}", listing(dir));
    }
}

/// Finding 9: a UTF-8 byte order mark made results and telemetry "invalid JSON at line 1,
/// column 1"; it is skipped, as in label files.
#[test]
fn r3_09_a_byte_order_mark_is_skipped() {
    let run = Run::new();
    let with_bom = |p: &Path| {
        let mut b = b"\xEF\xBB\xBF".to_vec();
        b.extend(fs::read(p).unwrap());
        fs::write(p, b).unwrap();
    };
    let plain = run.score(&run.s("results.json"), &["--routes", &run.s("routes.xml")]);
    assert_eq!(code(&plain), 0, "{}", stderr(&plain));
    with_bom(&run.path("results.json"));
    for e in fs::read_dir(run.path("telemetry")).unwrap() {
        with_bom(&e.unwrap().path().join("metric_info.json"));
    }
    with_bom(&run.path("routes.xml"));
    let o = run.score(&run.s("results.json"), &["--routes", &run.s("routes.xml")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let (a, b): (Value, Value) = (
        serde_json::from_slice(&plain.stdout).unwrap(),
        serde_json::from_slice(&o.stdout).unwrap(),
    );
    assert_eq!(a["summary"], b["summary"]);
}

/// Finding 9 (round 2 residues): the closing line said "0 invalid record(s)" when there were
/// none; `sds compare` blamed a missing telemetry folder on `--telemetry`, an option it does
/// not have.
#[test]
fn r3_09_messages_say_what_is_wrong() {
    let run = Run::new();
    let mut recs = run.records.clone();
    recs[0]["save_name"] = json!("nowhere");
    let results = run.write("missing.json", &recs);
    let o = run.score(&results, &["--routes", &run.s("routes.xml")]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("1 route(s) with telemetry problems"), "{e}");
    assert!(!e.contains(" 0 "), "{e}");
    let o = sds(&[
        "compare",
        &format!("a={}:{}", run.s("results.json"), run.s("no-such-telemetry")),
        &format!("b={}:{}", run.s("results.json"), run.s("telemetry")),
    ]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(!e.contains("--telemetry "), "{e}");
    assert!(
        e.contains("run a: telemetry folder") && e.contains("no-such-telemetry: no such folder"),
        "{e}"
    );
}

/// Runs `sds args` to its end and returns its exit code and its peak resident memory in bytes
/// (`wait4`'s `ru_maxrss`, this child's own).
// The child is waited for by `wait4`, which alone gives its own resource usage.
#[allow(clippy::zombie_processes)]
fn peak_rss(args: &[&str]) -> (i32, u64) {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: waiting for our own child, with valid out-pointers; `child` is not waited for
    // again (its `Drop` does not wait).
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32);
    (libc::WEXITSTATUS(status), usage.ru_maxrss as u64 * 1024)
}

/// Finding 7: parallel workers read whole telemetry files at once: sparse files of 1000 MiB
/// (40 KB on disk) cost 7 GB with `--jobs 8`. The bytes in flight are now bounded by
/// `BYTES_IN_FLIGHT` (512 MiB) whatever `--jobs`: four sparse 300 MiB files read one at a time.
#[test]
fn r3_07_telemetry_bytes_in_flight_are_bounded() {
    let run = Run::new();
    let mut sparse = 0;
    for e in fs::read_dir(run.path("telemetry")).unwrap() {
        let p = e.unwrap().path().join("metric_info.json");
        if sparse < 4 {
            let f = fs::File::create(&p).unwrap();
            std::io::Write::write_all(&mut &f, b"{\"1\": ").unwrap();
            f.set_len(300 << 20).unwrap();
            sparse += 1;
        }
    }
    let (results, telemetry) = (run.s("results.json"), run.s("telemetry"));
    let args = [
        "score",
        "--results",
        &results,
        "--telemetry",
        &telemetry,
        "--jobs",
        "4",
    ];
    let (code, peak) = peak_rss(&args);
    assert_eq!(code, 3, "four routes have invalid telemetry");
    let mib = peak >> 20;
    eprintln!("r3_07: peak resident memory {mib} MiB");
    // One 300 MiB file at a time (two do not fit in 512 MiB); four at once would be 1200 MiB.
    assert!(mib < 700, "peak resident memory {mib} MiB");
}

/// Finding 7: no cap on the page's collision figures and timeline markers, nor on `--traces`
/// (100,000 collisions: a 1.09 GB page, 2.5 GB of memory, `--traces` still writing after
/// 120 s). Per route: at most 10 figures and 500 markers in the page and 100 traces, each with
/// "and N more"; every collision stays in the JSON report.
#[test]
fn r3_07_figures_markers_and_traces_are_capped_per_route() {
    let run = Run::new();
    let mut recs = run.records.clone();
    let r = recs
        .iter_mut()
        .find(|r| r["route_id"] == "RouteScenario_900005_rep0")
        .unwrap();
    let hit = r["infractions"]["collisions_vehicle"][0].clone();
    r["infractions"]["collisions_vehicle"] = json!(vec![hit; 2000]);
    let results = run.write("many.json", &recs);
    let (page, traces, json_out) = (
        run.path("page.html"),
        run.path("traces"),
        run.path("r.json"),
    );
    let o = run.score(
        &results,
        &["--format", "html", "-o", page.to_str().unwrap()],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let html = fs::read_to_string(&page).unwrap();
    let figs = html.matches("<div class=\"fig\" id=\"route-").count();
    let markers = html.matches("class=\"ev ev-collision").count();
    assert!(figs <= 5 * 10, "{figs} figures");
    assert!(markers <= 500 + 10, "{markers} markers");
    assert!(
        html.contains("and 1990 more aligned collision(s)"),
        "no count of the figures left out"
    );
    assert!(html.contains("more placed event(s) without a marker"));
    assert!(html.len() < 8 << 20, "page of {} bytes", html.len());
    let o = run.score(
        &results,
        &[
            "--traces",
            traces.to_str().unwrap(),
            "-o",
            json_out.to_str().unwrap(),
        ],
    );
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let files = fs::read_dir(&traces).unwrap().count();
    assert!(files <= 2 * (100 + 4), "{files} trace files");
    assert!(
        stderr(&o).contains("1900 more collision(s) without a trace"),
        "{}",
        stderr(&o)
    );
    let r: Value = serde_json::from_slice(&fs::read(&json_out).unwrap()).unwrap();
    let route = r["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["route_id"] == "RouteScenario_900005_rep0")
        .unwrap();
    assert_eq!(route["collision_events"].as_array().unwrap().len(), 2000);
}

/// A corrupted copy of a run: the full report, precise reasons, exit codes, atomic writes.
mod corrupted_run;
/// Special files, FIFOs, symbolic links, signals and hostile numbers (issue 12).
mod files;
