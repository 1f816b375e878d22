//! `sds watch`: rounds, the cache, the stop rule, retries and the final report.

use std::fs;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use monitor_host::report::json::json;
use monitor_host::{demo, Inputs, LabelFiles, NoProgress, RoundOutcome, Settings};
use monitor_host::{Report, RoundStatus, ScoreRequest, WatchRequest, Watcher};
use serde_json::Value;

use crate::common::{s, sds};

/// Spawns `sds` with `args`, standard error piped.
fn spawn(args: &[String], env: &[(&str, &str)]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(args)
        .envs(env.iter().copied())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits for `child` (killed after `limit`), returning its exit status and standard error.
fn wait(child: &mut Child, limit: Duration) -> Output {
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = Vec::new();
        let _ = err.read_to_end(&mut text);
        text
    });
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "sds watch did not stop within {limit:?}: {}",
                String::from_utf8_lossy(&reader.join().unwrap())
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = child.wait().unwrap();
    Output {
        status,
        stdout: Vec::new(),
        stderr: reader.join().unwrap(),
    }
}

/// A watch whose standard error is read line by line while it runs: a test waits for what the
/// watch said (a status line, a warning) before it acts, instead of sleeping and hoping a round
/// came in between (issue 47 item 13: such sleeps raced the rounds on a busy machine).
struct Live {
    child: Child,
    lines: std::sync::mpsc::Receiver<String>,
    seen: Vec<String>,
}

impl Live {
    fn spawn(args: &[String]) -> Live {
        let mut child = spawn(args, &[]);
        let err = child.stderr.take().unwrap();
        let (tx, lines) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in std::io::BufRead::lines(std::io::BufReader::new(err)) {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Live {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Waits for a line for which `f` holds and returns it (a hang fails after two minutes: a
    /// guard, never what decides the outcome).
    fn until(&mut self, what: &str, f: impl Fn(&str) -> bool) -> String {
        loop {
            match self.lines.recv_timeout(Duration::from_secs(120)) {
                Ok(l) => {
                    self.seen.push(l.clone());
                    if f(&l) {
                        return l;
                    }
                }
                Err(e) => {
                    let _ = self.child.kill();
                    panic!("no {what} ({e}):\n{}", self.seen.join("\n"));
                }
            }
        }
    }

    /// Waits for a JSON status line for which `f` holds.
    fn status(&mut self, what: &str, f: impl Fn(&Value) -> bool) -> Value {
        let l = self.until(what, |l| {
            l.starts_with('{') && serde_json::from_str::<Value>(l).is_ok_and(|v| f(&v))
        });
        serde_json::from_str(&l).unwrap()
    }

    /// Asks the watch to stop (SIGINT: it writes its final report).
    fn interrupt(&self) {
        #[allow(unsafe_code)]
        // SAFETY: kill(2) on our own child's pid.
        unsafe {
            libc::kill(self.child.id() as i32, libc::SIGINT);
        }
    }

    /// Waits for the watch to end (killed after `limit`); its exit status and whole standard
    /// error.
    fn finish(mut self, limit: Duration) -> Output {
        let start = Instant::now();
        let status = loop {
            if let Some(st) = self.child.try_wait().unwrap() {
                break st;
            }
            if start.elapsed() > limit {
                let _ = self.child.kill();
                panic!(
                    "sds watch did not stop within {limit:?}:\n{}",
                    self.seen.join("\n")
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        // The reader ends at the end of the stream: every line is here.
        self.seen.extend(self.lines.iter());
        let mut stderr = self.seen.join("\n").into_bytes();
        stderr.push(b'\n');
        Output {
            status,
            stdout: Vec::new(),
            stderr,
        }
    }
}

/// Polls until `f` holds (a state of the files, never a time); two minutes are a guard.
fn poll_until(what: &str, f: impl Fn() -> bool) {
    let start = Instant::now();
    while !f() {
        assert!(start.elapsed() < Duration::from_secs(120), "no {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The JSON status lines of a watch's standard error.
fn json_lines(err: &[u8]) -> Vec<Value> {
    String::from_utf8_lossy(err)
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

/// The demo's checkpoint and its records.
fn checkpoint(run: &demo::DemoRun) -> (Value, Vec<Value>) {
    let c: Value = serde_json::from_slice(&fs::read(&run.results).unwrap()).unwrap();
    let records = c["_checkpoint"]["records"].as_array().unwrap().clone();
    (c, records)
}

/// The checkpoint holding `records` of `total`, as the leaderboard writes it.
fn checkpoint_bytes(c: &Value, records: &[Value], total: usize) -> Vec<u8> {
    let mut c = c.clone();
    c["_checkpoint"]["records"] = Value::Array(records.to_vec());
    c["_checkpoint"]["progress"] = serde_json::json!([records.len(), total]);
    serde_json::to_vec_pretty(&c).unwrap()
}

/// Rewrites `file` in place, as the evaluator does (truncate, then write).
fn rewrite(file: &Path, bytes: &[u8]) {
    use std::io::Write as _;
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(file)
        .unwrap();
    f.write_all(bytes).unwrap();
}

fn watcher(inputs: Inputs) -> Watcher {
    Watcher::new(
        inputs,
        Settings::default(),
        LabelFiles::default(),
        None,
        Duration::ZERO,
    )
}

/// The report's JSON text.
fn j(r: &Report) -> String {
    String::from_utf8(json(r).unwrap()).unwrap()
}

/// What `sds score` writes for these inputs, default settings.
fn fresh(inputs: &Inputs) -> Report {
    ScoreRequest::new(inputs.clone())
        .score(&NoProgress)
        .unwrap()
        .report
}

fn scored(w: &mut Watcher) -> (Report, RoundStatus) {
    match w.round().unwrap() {
        RoundOutcome::Scored { scored, status, .. } => (scored.report, status),
        RoundOutcome::Retry { reason, .. } => panic!("round retried: {reason}"),
    }
}

fn demo_inputs(run: &demo::DemoRun) -> Inputs {
    Inputs {
        telemetry: Some(run.telemetry.clone()),
        route_xml: Some(run.routes.clone()),
        maps: Some(run.maps.clone()),
        ..Inputs::new([run.results.clone()])
    }
}

/// Issue 33 item 2: a run without telemetry (every public Bench2Drive file) is played back,
/// a record at a time; the watch stops by itself within two rounds of the last record, and a
/// round that found nothing new replayed nothing.
#[test]
fn i33_2_no_telemetry_playback_stops_by_itself() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, records) = checkpoint(&run);
    let n = records.len();
    let results = dir.path().join("results.json");
    rewrite(&results, &checkpoint_bytes(&c, &records[..1], n));
    // The route XML and the results' folder just written are too recent to trust (1 s).
    std::thread::sleep(Duration::from_millis(1100));
    let out = dir.path().join("live.json");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&results),
        "--routes",
        &s(&run.routes),
        "-o",
        &s(&out),
        "--status-json",
        "--interval",
        "0.05",
        "--timeout",
        "60",
    ]
    .map(String::from)
    .to_vec();
    // Paced by the watch's own status lines, not by a clock: each record is written once the
    // round that read the previous one and a round that found nothing new were said.
    let mut live = Live::spawn(&args);
    live.status("first round", |l| l["done"] == 1);
    live.status("idle round", |l| l["done"] == 1);
    for k in 2..=n {
        rewrite(&results, &checkpoint_bytes(&c, &records[..k], n));
        live.status("round reading the record", |l| l["done"] == k);
        if k < n {
            live.status("idle round", |l| l["done"] == k);
        }
    }
    let o = live.finish(Duration::from_secs(90));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("the route set is complete"), "{err}");
    let lines: Vec<Value> = json_lines(&o.stderr)
        .into_iter()
        .filter(|l| l["stopped"].is_null())
        .collect();
    let first_complete = lines.iter().position(|l| l["done"] == n).unwrap();
    // The round that read the last record, then one that found nothing new.
    assert!(
        lines.len() - first_complete <= 2,
        "{} rounds after the last record: {err}",
        lines.len() - first_complete
    );
    // A round after one that read the same records found nothing new: it replays nothing
    // (from 2 records on; the first one's folder may be too recent to trust at first).
    let idle: Vec<&Value> = lines
        .windows(2)
        .filter(|w| w[0]["done"] == w[1]["done"] && w[1]["done"].as_u64() >= Some(2))
        .map(|w| &w[1])
        .collect();
    assert!(idle.len() >= 3, "{err}");
    for l in idle {
        assert_eq!(l["rescored"], 0, "{l}: {err}");
    }
    // The final report is `sds score`'s.
    let reference = dir.path().join("score.json");
    let sc = sds(&[
        "score",
        "--results",
        &s(&results),
        "--routes",
        &s(&run.routes),
        "-o",
        &s(&reference),
    ]);
    assert_eq!(o.status.code(), sc.status.code(), "{err}");
    assert_eq!(fs::read(&out).unwrap(), fs::read(&reference).unwrap());
}

/// Issue 33 item 2: a shard caught half-written for several rounds keeps its last good reading
/// (the routes done never drop), and the status of a retried round keeps those figures.
#[test]
fn i33_2_half_written_round_keeps_the_last_good_figures() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, records) = checkpoint(&run);
    let n = records.len();
    let shards = dir.path().join("shards");
    fs::create_dir_all(&shards).unwrap();
    let (a, b) = (shards.join("eval_0.json"), shards.join("eval_1.json"));
    rewrite(&a, &checkpoint_bytes(&c, &records[..4], 5));
    rewrite(&b, &checkpoint_bytes(&c, &records[5..8], 4));
    let inputs = Inputs {
        results: vec![shards.clone()],
        ..demo_inputs(&run)
    };
    let mut w = watcher(inputs.clone());
    let (_, good) = scored(&mut w);
    assert_eq!((good.done, good.n), (7, n));
    // Shard 0 caught half-written, 5 rounds in a row (a warning from the third).
    let full = checkpoint_bytes(&c, &records[..5], 5);
    rewrite(&a, &full[..full.len() / 2]);
    for round in 1..=5 {
        match w.round().unwrap() {
            RoundOutcome::Retry {
                failures, status, ..
            } => {
                assert_eq!(failures, round);
                assert_eq!((status.done, status.n), (good.done, good.n));
                assert_eq!((status.ds_done, status.ds_n), (good.ds_done, good.ds_n));
                assert!(status.retry.as_deref().unwrap().contains("eval_0.json"));
            }
            RoundOutcome::Scored { status, .. } => {
                panic!(
                    "round {round} scored a half-written shard: done {}",
                    status.done
                )
            }
        }
    }
    rewrite(&a, &full);
    let (report, now) = scored(&mut w);
    assert_eq!(now.done, 8);
    assert_eq!(j(&report), j(&fresh(&inputs)));
}

/// Issue 33 item 2: every status line has the same fields; a retried round adds `retry`.
#[test]
fn i33_2_status_schema_is_the_same_in_retry_rounds() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, records) = checkpoint(&run);
    let n = records.len();
    let results = dir.path().join("results.json");
    let bytes = checkpoint_bytes(&c, &records[..4], n);
    rewrite(&results, &bytes);
    let out = dir.path().join("live.json");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "-o",
        &s(&out),
        "--status-json",
        "--interval",
        "0.05",
    ]
    .map(String::from)
    .to_vec();
    // Each write waits for the round it is meant for (no timer races the rounds).
    let mut live = Live::spawn(&args);
    live.status("first round", |l| l["done"] == 4);
    let more = checkpoint_bytes(&c, &records[..5], n);
    rewrite(&results, &more[..more.len() / 2]);
    live.status("retried round", |l| l.get("retry").is_some());
    rewrite(&results, &more);
    live.status("round after the write", |l| l["done"] == 5);
    live.interrupt();
    let o = live.finish(Duration::from_secs(60));
    let lines = json_lines(&o.stderr);
    let keys = |v: &Value| -> Vec<String> {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    let normal: Vec<&Value> = lines.iter().filter(|l| l.get("retry").is_none()).collect();
    let retry: Vec<&Value> = lines.iter().filter(|l| l.get("retry").is_some()).collect();
    assert!(!normal.is_empty() && !retry.is_empty(), "{lines:?}");
    let schema = keys(normal[0]);
    for l in &normal {
        assert_eq!(keys(l), schema);
    }
    for l in &retry {
        let mut k = keys(l);
        k.retain(|k| k != "retry");
        assert_eq!(k, schema, "{l}");
        // The last good reading's figures.
        assert_eq!(l["done"], 4, "{l}");
        assert!(l["ds_done"].is_number(), "{l}");
    }
    for key in [
        "round",
        "done",
        "n",
        "ds_done",
        "ds_n",
        "seconds_left",
        "time",
    ] {
        assert!(schema.contains(&key.to_string()), "{key}");
    }
}

/// `sds score` and `sds watch --once` over the demo with `extra` arguments: their exit codes
/// and the watch's time.
fn score_and_watch(
    run: &demo::DemoRun,
    results: &Path,
    extra: &[&str],
) -> (i32, i32, Duration, String) {
    let dir = run.results.parent().unwrap();
    let base: Vec<String> = [
        "--results",
        &s(results),
        "--telemetry",
        &s(&run.telemetry),
        "--maps",
        &s(&run.maps),
    ]
    .map(String::from)
    .to_vec();
    let mut score_args = vec!["score".to_string()];
    score_args.extend(base.clone());
    score_args.extend(extra.iter().map(|a| a.to_string()));
    score_args.extend(["-o".into(), s(&dir.join("score.out"))]);
    let sc = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(&score_args)
        .output()
        .unwrap();
    let mut args = vec!["watch".to_string()];
    args.extend(base);
    args.extend(extra.iter().map(|a| a.to_string()));
    args.extend(
        [
            "-o",
            &s(&dir.join("watch.out")),
            "--interval",
            "0.05",
            "--timeout",
            "20",
        ]
        .map(String::from),
    );
    let start = Instant::now();
    let mut child = spawn(&args, &[]);
    let o = wait(&mut child, Duration::from_secs(60));
    (
        sc.status.code().unwrap(),
        o.status.code().unwrap(),
        start.elapsed(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Issue 34 finding 5: errors no later round can mend stop the watch at once, with `sds
/// score`'s exit code: a mistyped `--routes`, `--labels`, `--families`, a null label,
/// duplicate route ids, a results file with a byte order mark.
#[test]
fn r3_05_permanent_errors_stop_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let (c, records) = checkpoint(&run);
    let null_label = dir.path().join("null_labels.json");
    fs::write(&null_label, r#"{"900001": null}"#).unwrap();
    let dup = dir.path().join("dup.json");
    let mut twice = records.clone();
    twice.push(records[0].clone());
    fs::write(&dup, checkpoint_bytes(&c, &twice, twice.len())).unwrap();
    let bom = dir.path().join("bom.json");
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(fs::read(&run.results).unwrap());
    fs::write(&bom, bytes).unwrap();
    let missing = s(&dir.path().join("no_such_file"));
    let nl = s(&null_label);
    let cases: Vec<(&str, PathBuf, Vec<&str>)> = vec![
        ("--routes", run.results.clone(), vec!["--routes", &missing]),
        (
            "--labels",
            run.results.clone(),
            vec!["--group-by", "route", "--labels", &missing],
        ),
        (
            "--families",
            run.results.clone(),
            vec!["--group-by", "family", "--families", &missing],
        ),
        (
            "null label",
            run.results.clone(),
            vec!["--group-by", "route", "--labels", &nl],
        ),
        ("duplicates", dup, vec![]),
        ("BOM", bom, vec![]),
    ];
    for (what, results, extra) in cases {
        let (score_code, watch_code, took, err) = score_and_watch(&run, &results, &extra);
        assert!(took < Duration::from_secs(10), "{what}: {took:?}: {err}");
        assert_eq!(watch_code, score_code, "{what}: {err}");
    }
}

/// Issue 34 finding 5: the cache key holds every input that changes a route's result. A map
/// added, the route XML changed, a telemetry file mended without a change of size or
/// modification time (what `chmod` does to an unreadable file): the next round equals `sds
/// score` over the same files.
#[test]
fn r3_05_cache_key_holds_every_input() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("run")).unwrap();
    // A map added mid-watch (renamed into place, as a copy finishes).
    let maps = dir.path().join("maps");
    fs::create_dir_all(&maps).unwrap();
    let inputs = Inputs {
        maps: Some(maps.clone()),
        ..demo_inputs(&run)
    };
    let mut w = watcher(inputs.clone());
    let (without, _) = scored(&mut w);
    for f in fs::read_dir(&run.maps).unwrap() {
        let f = f.unwrap();
        let tmp = dir.path().join("copy.tmp");
        fs::copy(f.path(), &tmp).unwrap();
        fs::rename(&tmp, maps.join(f.file_name())).unwrap();
    }
    let (with, _) = scored(&mut w);
    let reference = j(&fresh(&inputs));
    assert_ne!(j(&without), reference, "the map changes nothing?");
    assert_eq!(j(&with), reference, "map added");

    // The route XML changed: the first route's waypoints moved 1.5 m sideways (no maps, so
    // that the route is the lateral reference).
    let xml = fs::read_to_string(&run.routes).unwrap();
    let end = xml.find("</route>").unwrap();
    let changed = format!(
        "{}{}",
        xml[..end].replace("y=\"-3310.0\"", "y=\"-3308.5\""),
        &xml[end..]
    );
    assert_ne!(changed, xml);
    let routes = dir.path().join("routes.xml");
    fs::write(&routes, &xml).unwrap();
    let inputs = Inputs {
        route_xml: Some(routes.clone()),
        maps: None,
        ..demo_inputs(&run)
    };
    let mut w = watcher(inputs.clone());
    let (before, _) = scored(&mut w);
    fs::write(&routes, changed).unwrap();
    let (after, _) = scored(&mut w);
    let reference = j(&fresh(&inputs));
    assert_ne!(j(&before), reference, "the XML changes nothing?");
    assert_eq!(j(&after), reference, "route XML changed");

    // A telemetry file unreadable for a round, mended with the same size and times.
    let inputs = demo_inputs(&run);
    let name = fs::read_dir(&run.telemetry)
        .unwrap()
        .map(|e| e.unwrap().path())
        .min()
        .unwrap();
    let file = name.join("metric_info.json");
    let good = fs::read(&file).unwrap();
    let mtime = fs::metadata(&file).unwrap().modified().unwrap();
    let keep_mtime = |f: &Path| {
        fs::File::options()
            .write(true)
            .open(f)
            .unwrap()
            .set_modified(mtime)
            .unwrap()
    };
    rewrite(&file, &vec![b'x'; good.len()]);
    keep_mtime(&file);
    let mut w = watcher(inputs.clone());
    let (broken, _) = scored(&mut w);
    rewrite(&file, &good);
    keep_mtime(&file);
    let (mended, _) = scored(&mut w);
    let reference = j(&fresh(&inputs));
    assert_ne!(j(&broken), reference);
    assert_eq!(j(&mended), reference, "telemetry mended");
}

/// Issue 34 finding 5: a results file half-written when the watch stops is said, with a
/// non-zero exit (not an older report with exit 0).
#[test]
fn r3_05_half_written_at_the_stop_exits_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, records) = checkpoint(&run);
    let n = records.len();
    let results = dir.path().join("results.json");
    rewrite(&results, &checkpoint_bytes(&c, &records[..4], n));
    let out = dir.path().join("live.json");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "-o",
        &s(&out),
        "--interval",
        "0.05",
        "--status-json",
    ]
    .map(String::from)
    .to_vec();
    // Half-written after the first round, and still so when the watch is stopped (by a signal:
    // a timeout raced the write on a busy machine).
    let mut live = Live::spawn(&args);
    live.status("first round", |l| l["done"] == 4);
    let more = checkpoint_bytes(&c, &records[..5], n);
    rewrite(&results, &more[..more.len() / 2]);
    live.interrupt();
    let o = live.finish(Duration::from_secs(60));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("still half-written when the watch stopped"),
        "{err}"
    );
}

/// Issue 34 finding 5: a live round that cannot be written warns and is written again; only
/// the final write is fatal.
#[test]
fn r3_05_unwritable_live_round_warns_and_retries() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let out = dir.path().join("live.json");
    // A folder in the report's place: no round can be written while it is there.
    fs::create_dir_all(&out).unwrap();
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&run.results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "--expected-routes",
        "12",
        "-o",
        &s(&out),
        "--interval",
        "0.05",
    ]
    .map(String::from)
    .to_vec();
    // The folder goes once the first round said it could not write; stopped once a later
    // round wrote the report (no timer races the rounds).
    let mut live = Live::spawn(&args);
    let warning = live.until("warning", |l| l.starts_with("sds: warning: watch round"));
    assert!(
        warning.starts_with("sds: warning: watch round 1:"),
        "{warning}"
    );
    fs::remove_dir(&out).unwrap();
    poll_until("live report", || out.is_file());
    live.interrupt();
    let o = live.finish(Duration::from_secs(60));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("written again next round"), "{err}");
    assert!(err.contains("watch stopped (interrupted)"), "{err}");
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(out.is_file());
}

/// Issue 34 finding 5: `--interval` and `--timeout` are bounded (usage errors naming the
/// option and the bound), never a panic or a silent 0.
#[test]
fn r3_05_interval_and_timeout_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let out = s(&dir.path().join("out.json"));
    let results = s(&run.results);
    for (option, value, bound) in [
        ("--interval", "1e19", "86400"),
        ("--interval", "NaN", "86400"),
        ("--interval", "0", "86400"),
        ("--timeout", "inf", "31536000"),
        ("--timeout", "1e300", "31536000"),
        ("--timeout", "NaN", "31536000"),
        ("--timeout", "-5", "31536000"),
    ] {
        let o = sds(&[
            "watch",
            "--results",
            &results,
            "-o",
            &out,
            "--allow-missing-telemetry",
            &format!("{option}={value}"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{option} {value}: {err}");
        assert!(
            err.contains(option) && err.contains(bound),
            "{option} {value}: {err}"
        );
    }
}

/// Issue 34 finding 5: a closed standard error never panics the watch (`eprintln!` did on
/// EPIPE); the report is still written.
#[test]
fn r3_05_closed_stderr_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let out = dir.path().join("out.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args([
            "watch",
            "--results",
            &s(&run.results),
            "--telemetry",
            &s(&run.telemetry),
            "--routes",
            &s(&run.routes),
            "-o",
            &s(&out),
            "--interval",
            "0.05",
            "--status-json",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stderr.take()); // the reader goes away
    let start = Instant::now();
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no stop");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_ne!(status.code(), Some(101), "panicked");
    assert_eq!(status.code(), Some(0));
    assert!(out.is_file());
}

/// Issue 34 finding 5: the double SIGTERM of coreutils' `timeout` (to the child, then to its
/// process group) no longer loses the final report: the second signal, within 2 s of the
/// first, is the same request. The final write is slowed down (test seam) so that the second
/// signal arrives while it runs.
#[test]
fn r3_05_double_sigterm_keeps_the_final_report() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let reference = dir.path().join("score.html");
    let sc = sds(&[
        "score",
        "--results",
        &s(&run.results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "--expected-routes",
        "12",
        "--format",
        "html",
        "-o",
        &s(&reference),
    ]);
    for trial in 0..4 {
        let out = dir.path().join(format!("live{trial}.html"));
        let args: Vec<String> = [
            "watch",
            "--results",
            &s(&run.results),
            "--telemetry",
            &s(&run.telemetry),
            "--routes",
            &s(&run.routes),
            "--expected-routes",
            "12",
            "--format",
            "html",
            "-o",
            &s(&out),
            "--interval",
            "0.2",
        ]
        .map(String::from)
        .to_vec();
        let mut child = spawn(&args, &[("SDS_TEST_WRITE_DELAY_MS", "150")]);
        let start = Instant::now();
        while !out.exists() {
            assert!(start.elapsed() < Duration::from_secs(60), "no live round");
            std::thread::sleep(Duration::from_millis(10));
        }
        std::thread::sleep(Duration::from_millis(40 * trial as u64));
        for _ in 0..2 {
            #[allow(unsafe_code)]
            // SAFETY: kill(2) on our own child's pid.
            unsafe {
                libc::kill(child.id() as i32, libc::SIGTERM);
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let o = wait(&mut child, Duration::from_secs(60));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), sc.status.code(), "trial {trial}: {err}");
        assert!(err.contains("watch stopped (interrupted)"), "{err}");
        assert_eq!(
            fs::read(&out).unwrap(),
            fs::read(&reference).unwrap(),
            "trial {trial}"
        );
    }
}

/// Issue 34 finding 5: `--figures` (and `--tables`) write the final report's figures and
/// tables, as `sds score` does.
#[test]
fn r3_05_figures_are_written_for_the_final_report() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let common = [
        "--results".to_string(),
        s(&run.results),
        "--telemetry".into(),
        s(&run.telemetry),
        "--routes".into(),
        s(&run.routes),
    ];
    let (fs_score, fs_watch) = (dir.path().join("fs"), dir.path().join("fw"));
    let (ts_score, ts_watch) = (dir.path().join("ts"), dir.path().join("tw"));
    let mut a: Vec<String> = vec!["score".into()];
    a.extend(common.clone());
    a.extend([
        "--figures".into(),
        s(&fs_score),
        "--tables".into(),
        s(&ts_score),
        "-o".into(),
        s(&dir.path().join("s.json")),
    ]);
    let sc = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(&a)
        .output()
        .unwrap();
    assert!(sc.status.success());
    let mut a: Vec<String> = vec!["watch".into(), "--once".into()];
    a.extend(common);
    a.extend([
        "--figures".into(),
        s(&fs_watch),
        "--tables".into(),
        s(&ts_watch),
        "-o".into(),
        s(&dir.path().join("w.json")),
    ]);
    let o = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(&a)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let names = |d: &Path| {
        let mut v: Vec<_> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        v.sort();
        v
    };
    // The figures and (since the one write path of score and watch) the long tables.
    for (from_score, from_watch) in [(&fs_score, &fs_watch), (&ts_score, &ts_watch)] {
        assert!(!names(from_score).is_empty());
        assert_eq!(names(from_watch), names(from_score));
        for n in names(from_score) {
            assert_eq!(
                fs::read(from_watch.join(&n)).unwrap(),
                fs::read(from_score.join(&n)).unwrap()
            );
        }
    }
}

/// Issue 34 finding 4 (status part): a route id holding U+202E and a newline keeps every
/// `--status-json` line valid JSON (serde_json's escapes, not the text escape `\u{202e}`).
#[test]
fn r3_04_status_json_is_json_with_hostile_ids() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, mut records) = checkpoint(&run);
    // The last record: the status line's `last_route`.
    let last = records.len() - 1;
    records[last]["route_id"] = "RouteScenario_1\u{202e}01_rep0\n".into();
    let results = dir.path().join("results.json");
    let n = records.len();
    fs::write(&results, checkpoint_bytes(&c, &records, n)).unwrap();
    let o = sds(&[
        "watch",
        "--results",
        &s(&results),
        "--allow-missing-telemetry",
        "--once",
        "--status-json",
        "-o",
        &s(&dir.path().join("out.json")),
    ]);
    let lines = json_lines(&o.stderr);
    assert!(!lines.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(lines[0]["last_route"], "RouteScenario_1\u{202e}01_rep0\n");
    // No raw bidirectional character reaches the terminal either.
    assert!(!String::from_utf8_lossy(&o.stderr).contains('\u{202e}'));
}

/// Issue 33 item 2: the live page says it is live (done / N, DS over the routes done and of N,
/// the time left, the round's time); the final page is `sds score`'s.
#[test]
fn i33_2_live_page_says_it_is_live() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let out = dir.path().join("live.html");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&run.results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "--expected-routes",
        "12",
        "--format",
        "html",
        "-o",
        &s(&out),
        "--interval",
        "0.1",
    ]
    .map(String::from)
    .to_vec();
    // Read while the watch runs, then stopped (a 1 s timeout could end it before the live page
    // was read, on a busy machine).
    let live = Live::spawn(&args);
    poll_until("live round", || out.exists());
    let page = fs::read_to_string(&out).unwrap();
    assert!(page.contains("id=\"live\""), "no live banner");
    assert!(page.contains("9 / 12 routes done"));
    assert!(page.contains("over the routes done") && page.contains("of N"));
    assert!(page.contains("left"));
    let year =
        monitor_host::app::watch::watcher::utc(std::time::SystemTime::now())[..4].to_string();
    assert!(page.contains(&format!("at {year}-")));
    live.interrupt();
    let o = live.finish(Duration::from_secs(60));
    let reference = dir.path().join("score.html");
    let sc = sds(&[
        "score",
        "--results",
        &s(&run.results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "--expected-routes",
        "12",
        "--format",
        "html",
        "-o",
        &s(&reference),
    ]);
    assert_eq!(o.status.code(), sc.status.code());
    assert_eq!(fs::read(&out).unwrap(), fs::read(&reference).unwrap());
}

/// `sds score` and `sds watch` share one write path: the rerun list is written (and said)
/// once, and an `-o` among the figures is refused by both (exit 2), before any work.
#[test]
fn score_and_watch_share_the_write_path() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let common = [
        "--results".to_string(),
        s(&run.results),
        "--telemetry".into(),
        s(&run.telemetry),
        "--routes".into(),
        s(&run.routes),
    ];
    let sds = |cmd: &[&str], extra: &[String]| {
        let mut a: Vec<String> = cmd.iter().map(|c| c.to_string()).collect();
        a.extend(common.clone());
        a.extend(extra.iter().cloned());
        Command::new(env!("CARGO_BIN_EXE_sds"))
            .args(&a)
            .output()
            .unwrap()
    };
    let list = dir.path().join("rerun.tsv");
    let o = sds(
        &["score"],
        &[
            "--rerun-list".into(),
            s(&list),
            "-o".into(),
            s(&dir.path().join("r.json")),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("to run again to").count(), 1, "{err}");
    assert!(list.is_file());
    let figs = dir.path().join("figs");
    for cmd in [&["score"][..], &["watch", "--once"][..]] {
        let o = sds(
            cmd,
            &[
                "--figures".into(),
                s(&figs),
                "-o".into(),
                s(&figs.join("routes.svg")),
            ],
        );
        assert_eq!(
            o.status.code(),
            Some(2),
            "{cmd:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!figs.join("routes.svg").exists(), "{cmd:?}");
    }
}

/// Sets `file`'s modification time `ago` in the past (a shard whose last record is that old).
fn age(file: &Path, ago: Duration) {
    fs::File::options()
        .write(true)
        .open(file)
        .unwrap()
        .set_modified(std::time::SystemTime::now() - ago)
        .unwrap();
}

/// Issue 36: a watch over two shard checkpoints where one shard stops: its checkpoint has had
/// no new record for longer than K times its median route time, so the status names it (and
/// `sds watch` warns once); the shard that keeps writing never is, and the stalled one leaves
/// the list when it writes again.
#[test]
fn i36_watch_says_when_a_shard_stalls() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, records) = checkpoint(&run);
    let shards = dir.path().join("shards");
    fs::create_dir_all(&shards).unwrap();
    let (a, b) = (shards.join("eval_0.json"), shards.join("eval_1.json"));
    rewrite(&a, &checkpoint_bytes(&c, &records[..2], 5));
    rewrite(&b, &checkpoint_bytes(&c, &records[5..7], 4));
    // Shard 1's worker died an hour ago; its routes take seconds.
    let median = {
        let mut d: Vec<f64> = records[5..7]
            .iter()
            .map(|r| r["meta"]["duration_system"].as_f64().unwrap())
            .collect();
        d.sort_by(f64::total_cmp);
        (d[0] + d[1]) / 2.0
    };
    assert!(median > 0.0 && 5.0 * median < 3600.0, "{median}");
    age(&b, Duration::from_secs(3600));
    let inputs = Inputs {
        results: vec![shards.clone()],
        ..demo_inputs(&run)
    };
    let mut w = watcher(inputs.clone());
    let (_, first) = scored(&mut w);
    let files: Vec<&Path> = first.stalled.iter().map(|s| s.file.as_path()).collect();
    assert_eq!(files, [b.as_path()], "{:?}", first.stalled);
    let st = &first.stalled[0];
    assert!((st.median_s - median).abs() < 1e-9, "{st:?}");
    assert!(
        st.idle_s >= 3600.0 && (st.done, st.total) == (2, 4),
        "{st:?}"
    );
    let line: Value = serde_json::from_str(&first.json()).unwrap();
    assert!(line["stalled"][0]["file"]
        .as_str()
        .unwrap()
        .ends_with("eval_1.json"));
    // Shard 0 goes on writing; shard 1 is still silent.
    rewrite(&a, &checkpoint_bytes(&c, &records[..3], 5));
    let (_, second) = scored(&mut w);
    assert_eq!(second.stalled.len(), 1);
    // A K above the silence judges it live.
    w.set_stall_factor(3601.0 / median + 1.0);
    assert!(scored(&mut w).1.stalled.is_empty());
    w.set_stall_factor(5.0);
    // Shard 1 writes again: no stall.
    rewrite(&b, &checkpoint_bytes(&c, &records[5..8], 4));
    let (_, third) = scored(&mut w);
    assert!(third.stalled.is_empty(), "{:?}", third.stalled);
    assert_eq!(third.done, 6);
    // The command line warns, naming the shard; every status line has the field.
    age(&b, Duration::from_secs(3600));
    let out = dir.path().join("live.json");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&shards),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "-o",
        &s(&out),
        "--once",
    ]
    .map(String::from)
    .to_vec();
    let o = wait(&mut spawn(&args, &[]), Duration::from_secs(60));
    let err = String::from_utf8_lossy(&o.stderr);
    let warn: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("has written no record"))
        .collect();
    assert_eq!(warn.len(), 1, "{err}");
    assert!(
        warn[0].starts_with("sds: warning: shard ")
            && warn[0].contains("eval_1.json")
            && warn[0].contains("3/4 routes done"),
        "{}",
        warn[0]
    );
    let mut quiet = args.clone();
    quiet.extend(["--stall-factor".to_string(), "1e9".into()]);
    let o = wait(&mut spawn(&quiet, &[]), Duration::from_secs(60));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("has written no record"));
    let mut bad = args;
    bad.extend(["--stall-factor".to_string(), "0".into()]);
    let o = wait(&mut spawn(&bad, &[]), Duration::from_secs(60));
    assert_eq!(o.status.code(), Some(2));
}

/// Issue 35: the one watch `Session` (the CLI and Python drive it with their own wait): a
/// complete run stops after a round that found nothing new, with `stopped` on the last status;
/// the wait is the front end's, asked for at most the interval.
#[test]
fn i35_session_stops_when_complete_and_nothing_new() {
    use monitor_host::{Step, Stop, Wake};
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    // Files older than the racy second: the second round can trust them unchanged.
    std::thread::sleep(Duration::from_millis(1100));
    let request = WatchRequest {
        score: ScoreRequest::new(demo_inputs(&run)),
        interval: 0.01,
        timeout: None,
        once: false,
        stall_factor: 5.0,
    };
    let mut session = request.session().unwrap();
    let mut waits = Vec::new();
    let mut wait = |d: Duration| {
        waits.push(d);
        std::thread::sleep(d);
        Wake::Elapsed
    };
    let Step::Round { outcome, stops } = session.next(&mut wait).unwrap() else {
        panic!("a round first")
    };
    assert!(matches!(
        outcome,
        RoundOutcome::Scored { changed: true, .. }
    ));
    assert_eq!(stops, None);
    let Step::Round { outcome, stops } = session.next(&mut wait).unwrap() else {
        panic!("a second round")
    };
    assert!(matches!(
        outcome,
        RoundOutcome::Scored { changed: false, .. }
    ));
    assert_eq!(stops, Some(Stop::Complete));
    let Step::Stopped(end) = session.next(&mut wait).unwrap() else {
        panic!("stopped")
    };
    assert_eq!(end.stop, Stop::Complete);
    assert!(end.reread.is_none() && end.stale.is_none());
    assert_eq!(end.status.stopped.as_deref(), Some("complete"));
    assert_eq!(end.status.round, 2);
    assert!(matches!(session.next(&mut wait).unwrap(), Step::Aborted));
    assert!(!waits.is_empty() && waits.iter().all(|d| *d <= Duration::from_millis(10)));
}

/// Issue 35: after the timeout the session reads the inputs once more (no wait asked), and a
/// front end's `Wake::Abort` (Python's Ctrl-C) gives up at once, with no final reading.
#[test]
fn i35_session_timeout_reads_once_more_and_abort_gives_up() {
    use monitor_host::{Step, Stop, Wake};
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    std::thread::sleep(Duration::from_millis(1100)); // past the racy second
    let inputs = Inputs {
        telemetry: Some(run.telemetry.clone()),
        ..Inputs::new([run.results.clone()])
    };
    let request = |timeout| WatchRequest {
        score: ScoreRequest::new(inputs.clone()),
        interval: 60.0,
        timeout,
        once: false,
        stall_factor: 5.0,
    };
    let mut never = |_: Duration| -> Wake { panic!("no wait after the timeout") };
    let mut session = request(Some(0.0)).session().unwrap();
    assert!(matches!(
        session.next(&mut never).unwrap(),
        Step::Round { stops: None, .. }
    ));
    let Step::Stopped(end) = session.next(&mut never).unwrap() else {
        panic!("stopped")
    };
    assert_eq!(end.stop, Stop::Timeout);
    let (scored, status) = end.reread.expect("the final reading scored");
    assert!(!end.changed);
    assert_eq!(status.round, 2);
    assert_eq!(j(&scored.report), j(&fresh(&inputs)));
    assert_eq!(end.status.stopped.as_deref(), Some("timeout"));

    let mut session = request(None).session().unwrap();
    let mut abort = |_: Duration| Wake::Abort;
    assert!(matches!(
        session.next(&mut abort).unwrap(),
        Step::Round { .. }
    ));
    assert!(matches!(session.next(&mut abort).unwrap(), Step::Aborted));
}

/// Issue 35: the requests check what both front ends used to check apart: the watch's bounds
/// (each front end names its option), an unknown infraction list, and the options mapped to
/// settings in one order (named options first, overrides after them).
#[test]
fn i35_requests_validate_once_for_every_front_end() {
    use monitor_host::{RequestError, RunSettings};
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let watch = |interval| WatchRequest {
        score: ScoreRequest::new(demo_inputs(&run)),
        interval,
        timeout: None,
        once: false,
        stall_factor: 5.0,
    };
    assert!(matches!(
        watch(0.0).validate(),
        Err(RequestError::Interval { given, .. }) if given == 0.0
    ));
    let bad = ScoreRequest {
        infractions: vec!["collisions_vehicel".into()],
        ..ScoreRequest::new(demo_inputs(&run))
    };
    let e = bad.validate().unwrap_err();
    assert!(e
        .to_string()
        .starts_with("--infraction collisions_vehicel: no such infraction list"));
    let s = RunSettings {
        protocols: Some(vec!["lb2.1".into(), "b2d".into()]),
        overrides: vec![("protocols".into(), "f2d".into())],
        ..RunSettings::default()
    }
    .settings()
    .unwrap();
    assert_eq!(s.get("protocols").as_deref(), Some("f2d"));
}

/// The 8 TransFuser++ shard checkpoints copied into a fresh folder, with `merged.json` beside
/// them when `merged` (the folder Bench2Drive's merge leaves), and the route XML.
fn tfpp_shards(dir: &Path, merged: bool, shards: usize) -> Option<PathBuf> {
    let fx = crate::common::b2d_fixtures(&[
        "tfpp_raw_shards",
        "carla_garage_tfpp_b2d_traj_merged.json",
        "routes/bench2drive220.xml",
    ])?;
    let folder = dir.join("tfpp");
    fs::create_dir_all(&folder).unwrap();
    for k in 0..shards {
        let name = format!("eval_bench2drive220_{k}.json");
        fs::copy(fx.join("tfpp_raw_shards").join(&name), folder.join(&name)).unwrap();
    }
    if merged {
        fs::copy(
            fx.join("carla_garage_tfpp_b2d_traj_merged.json"),
            folder.join("merged.json"),
        )
        .unwrap();
    }
    Some(fx)
}

/// Issue 46 item 6: a watch without `--routes` of the folder holding the 8 TransFuser++ shards
/// (all `progress [k, k]`) and `merged.json` never stopped (the merged file, skipped beside its
/// raw files, has no `progress` and counted as a shard not done); and the stopping round was
/// printed twice (once live, once with `stopped`). Now it stops by itself once the files are
/// settled, each round printed once, the last with `stopped: "complete"`.
#[test]
fn i46_6_done_shards_beside_merged_json_stop_and_print_each_round_once() {
    let dir = tempfile::tempdir().unwrap();
    if tfpp_shards(dir.path(), true, 8).is_none() {
        return;
    }
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&dir.path().join("tfpp")),
        "--allow-missing-telemetry",
        "--status-json",
        "--interval",
        "0.05",
        "--timeout",
        "120",
        "-o",
        &s(&dir.path().join("live.json")),
    ]
    .map(String::from)
    .to_vec();
    let o = wait(&mut spawn(&args, &[]), Duration::from_secs(180));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("watch stopped (the route set is complete)"),
        "{err}"
    );
    let lines = json_lines(&o.stderr);
    let rounds: Vec<u64> = lines.iter().map(|l| l["round"].as_u64().unwrap()).collect();
    let mut unique = rounds.clone();
    unique.dedup();
    assert_eq!(rounds, unique, "a round printed twice: {err}");
    let last = lines.last().unwrap();
    assert_eq!(last["stopped"], "complete", "{last}");
    assert_eq!(
        (last["done"].as_u64(), last["complete"].as_bool()),
        (Some(220), Some(true))
    );
}

/// Issue 46 item 6: 3 of the 8 shards, all done, against the 220-route XML: 136 routes no
/// shard runs. The time left was "about 0m left" (`seconds_left` 0); it is unknown (null), and
/// the live page says so.
#[test]
fn i46_6_time_left_is_unknown_when_no_shard_runs_the_routes_left() {
    let dir = tempfile::tempdir().unwrap();
    let Some(fx) = tfpp_shards(dir.path(), false, 3) else {
        return;
    };
    let page = dir.path().join("live.html");
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&dir.path().join("tfpp")),
        "--routes",
        &s(&fx.join("routes/bench2drive220.xml")),
        "--allow-missing-telemetry",
        "--status-json",
        "--interval",
        "0.05",
        "--format",
        "html",
        "-o",
        &s(&page),
    ]
    .map(String::from)
    .to_vec();
    let mut live = Live::spawn(&args);
    let first = live.status("first round", |_| true);
    assert_eq!(
        (first["done"].as_u64(), first["n"].as_u64()),
        (Some(84), Some(220))
    );
    assert!(first["seconds_left"].is_null(), "{first}");
    poll_until("live page", || page.exists());
    let html = fs::read_to_string(&page).unwrap();
    assert!(html.contains("time left unknown") && !html.contains("0m left"));
    live.interrupt();
    live.finish(Duration::from_secs(60));
}

/// Issue 47 item 12: `meta.duration_system` -100 gave `seconds_left` -300 in `--status-json`.
/// A negative (or non-finite) duration is no evaluator's: it is left out of the estimate (null
/// when no route has a usable one), never a negative time.
#[test]
fn r4_12_negative_durations_give_no_negative_time_left() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(&dir.path().join("src")).unwrap();
    let (c, mut records) = checkpoint(&run);
    let results = dir.path().join("results.json");
    for (half, expect_null) in [(false, true), (true, false)] {
        for (i, r) in records.iter_mut().enumerate() {
            let d = if half && i % 2 == 0 { 30.0 } else { -100.0 };
            r["meta"]["duration_system"] = serde_json::json!(d);
        }
        rewrite(&results, &checkpoint_bytes(&c, &records, records.len()));
        let o = sds(&[
            "watch",
            "--results",
            &s(&results),
            "--telemetry",
            &s(&run.telemetry),
            "--expected-routes",
            "12",
            "--once",
            "--status-json",
            "-o",
            &s(&dir.path().join("out.json")),
        ]);
        let lines = json_lines(&o.stderr);
        let left = &lines[0]["seconds_left"];
        if expect_null {
            assert!(left.is_null(), "{left}");
        } else {
            // 30 s a route (the usable durations) for the 12 - 9 routes left.
            assert_eq!(left.as_f64(), Some(90.0), "{left}");
        }
    }
}

/// Issue 47 item 12 (round 3's G05, last case): a telemetry file whose modification time is an
/// hour in the future was never "settled", so its route was replayed every round and the watch
/// of a complete run never stopped. A time that far ahead is no write under way: the watch
/// stops by itself.
#[test]
fn r4_12_a_file_from_the_future_does_not_keep_the_watch_running() {
    let dir = tempfile::tempdir().unwrap();
    let run = demo::write(dir.path()).unwrap();
    let (_, records) = checkpoint(&run);
    let name = records[0]["save_name"].as_str().unwrap();
    let file = run.telemetry.join(name).join("metric_info.json");
    let f = fs::OpenOptions::new().write(true).open(&file).unwrap();
    f.set_modified(std::time::SystemTime::now() + Duration::from_secs(3600))
        .unwrap();
    drop(f);
    let args: Vec<String> = [
        "watch",
        "--results",
        &s(&run.results),
        "--telemetry",
        &s(&run.telemetry),
        "--routes",
        &s(&run.routes),
        "--status-json",
        "--interval",
        "0.05",
        "--timeout",
        "60",
        "-o",
        &s(&dir.path().join("out.json")),
    ]
    .map(String::from)
    .to_vec();
    let o = wait(&mut spawn(&args, &[]), Duration::from_secs(120));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("watch stopped (the route set is complete)"),
        "{err}"
    );
}

/// Playback of a growing checkpoint in every layout, the live watch ending with the score
/// report, Ctrl-C and the time left.
mod playback;
