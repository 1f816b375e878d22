//! `sds watch` (spec §12) against a small evaluator simulator that plays the demo run back: the
//! checkpoint rewritten in place (truncated, then written in two parts, so a reader may catch
//! it half-written), each route's telemetry written when the route ends, a crash whose route is
//! dropped from the checkpoint on resume and run again, time compressed.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use monitor_host::report::json::json;
use monitor_host::{demo, score_labelled, Inputs, LabelFiles, NoProgress, RoundOutcome, Settings};
use monitor_host::{Report, Watcher};
use serde_json::Value;

/// The evaluator: the finished demo run in `src`, played back into `run`.
struct Evaluator {
    src: demo::DemoRun,
    run: PathBuf,
    checkpoint: Value,
    records: Vec<Value>,
}

impl Evaluator {
    fn new(dir: &Path) -> Evaluator {
        let src = demo::write(&dir.join("src")).unwrap();
        let run = dir.join("run");
        fs::create_dir_all(run.join("telemetry")).unwrap();
        let checkpoint: Value = serde_json::from_slice(&fs::read(&src.results).unwrap()).unwrap();
        let records = checkpoint["_checkpoint"]["records"]
            .as_array()
            .unwrap()
            .clone();
        Evaluator {
            src,
            run,
            checkpoint,
            records,
        }
    }

    fn results(&self) -> PathBuf {
        self.run.join("results.json")
    }

    fn inputs(&self) -> Inputs {
        Inputs {
            telemetry: Some(self.run.join("telemetry")),
            route_xml: Some(self.src.routes.clone()),
            maps: Some(self.src.maps.clone()),
            ..Inputs::new([self.results()])
        }
    }

    /// The route `k` ends: its telemetry folder copied into the run.
    fn telemetry(&self, k: usize) {
        let name = self.records[k]["save_name"].as_str().unwrap();
        let (from, to) = (
            self.src.telemetry.join(name),
            self.run.join("telemetry").join(name),
        );
        fs::create_dir_all(&to).unwrap();
        for f in fs::read_dir(&from).unwrap() {
            let f = f.unwrap();
            fs::copy(f.path(), to.join(f.file_name())).unwrap();
        }
    }

    /// The checkpoint holding `records`, as the leaderboard writes it.
    fn bytes(&self, records: &[Value]) -> Vec<u8> {
        let mut c = self.checkpoint.clone();
        c["_checkpoint"]["records"] = Value::Array(records.to_vec());
        c["_checkpoint"]["progress"] = serde_json::json!([records.len(), self.records.len()]);
        serde_json::to_vec_pretty(&c).unwrap()
    }

    /// Rewrites the checkpoint in place (truncate, then write): with `half`, only its first
    /// half, the way a reader catches it mid-write. Returns the rest.
    fn write(&self, records: &[Value], half: bool) -> Vec<u8> {
        let bytes = self.bytes(records);
        let cut = if half { bytes.len() / 2 } else { bytes.len() };
        let mut f = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(self.results())
            .unwrap();
        f.write_all(&bytes[..cut]).unwrap();
        bytes[cut..].to_vec()
    }

    fn finish(&self, rest: &[u8]) {
        let mut f = OpenOptions::new()
            .append(true)
            .open(self.results())
            .unwrap();
        f.write_all(rest).unwrap();
    }

    /// The record of route `k` after a crash: the route failed half-way.
    fn crashed(&self, k: usize) -> Value {
        let mut r = self.records[k].clone();
        r["status"] = "Failed - Agent crashed".into();
        r
    }
}

fn fresh(inputs: &Inputs) -> Report {
    score_labelled(
        inputs,
        &Settings::default(),
        &LabelFiles::default(),
        None,
        &NoProgress,
    )
    .unwrap()
    .report
}

/// One scored round: its report, the routes replayed, the routes reused.
fn scored(w: &mut Watcher) -> (Report, usize, usize, Vec<String>) {
    match w.round().unwrap() {
        RoundOutcome::Scored { scored, cache, .. } => {
            (scored.report, cache.rescored, cache.reused, cache.changed)
        }
        RoundOutcome::Retry { reason, .. } => panic!("round retried: {reason}"),
    }
}

fn retried(w: &mut Watcher) -> String {
    match w.round().unwrap() {
        RoundOutcome::Retry { reason, .. } => reason,
        RoundOutcome::Scored { .. } => panic!("a half-written checkpoint was scored"),
    }
}

#[test]
fn playback_rescored_only_when_changed() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::new(dir.path());
    let n = ev.records.len();
    let mut w = Watcher::new(
        ev.inputs(),
        Settings::default(),
        LabelFiles::default(),
        None,
        Duration::ZERO,
    );
    // Before the evaluator wrote anything: retried, not fatal.
    retried(&mut w);
    let crash = 4;
    let mut done: Vec<Value> = Vec::new();
    let mut total_rescored = 0;
    for k in 0..n {
        if k == crash {
            // The route crashes: its record is written without telemetry...
            let mut with_crash = done.clone();
            with_crash.push(ev.crashed(k));
            ev.write(&with_crash, false);
            let (report, rescored, reused, changed) = scored(&mut w);
            assert_eq!((rescored, reused), (1, k), "crash round");
            assert_eq!(changed, [ev.records[k]["route_id"].as_str().unwrap()]);
            assert_eq!(w.progress(&report).done, k + 1);
            total_rescored += rescored;
            // ... and on resume the evaluator drops it and runs the route again: the
            // checkpoint shrinks (retried once), then holds the earlier routes only.
            ev.write(&done, false);
            assert!(retried(&mut w).contains("shorter"));
            let (_, rescored, reused, _) = scored(&mut w);
            assert_eq!((rescored, reused), (0, k), "resume round");
        }
        ev.telemetry(k);
        done.push(ev.records[k].clone());
        // Every second route the reader catches the checkpoint half-written.
        let rest = ev.write(&done, k % 2 == 1);
        if k % 2 == 1 {
            let why = retried(&mut w);
            assert!(why.contains("results.json"), "{why}");
            ev.finish(&rest);
        }
        let (report, rescored, reused, mut changed) = scored(&mut w);
        // The first route is replayed again once: as a checkpoint's only record it may have
        // its telemetry beside the file, as one of several it may not.
        let again = usize::from(k == 1);
        assert_eq!(
            (rescored, reused),
            (1 + again, k - again),
            "round of route {k}"
        );
        changed.sort();
        let mut expected: Vec<&str> = vec![ev.records[k]["route_id"].as_str().unwrap()];
        if k == 1 {
            expected.insert(0, ev.records[0]["route_id"].as_str().unwrap());
        }
        assert_eq!(changed, expected);
        total_rescored += rescored;
        let p = w.progress(&report);
        assert_eq!((p.done, p.n, p.complete), (k + 1, n, k + 1 == n));
        // The partial figures: over the routes done, and over N with the rest as 0.
        let (d, all) = (
            p.over_done.driving_score.unwrap(),
            p.over_n.driving_score.unwrap(),
        );
        assert!(
            (d * (k + 1) as f64 - all * n as f64).abs() < 1e-9,
            "{d} {all}"
        );
        assert_eq!(report.summary.scores.driving_score, Some(all));
        // Nothing changed: nothing replayed, and the report is the same.
        let (again, rescored, reused, _) = scored(&mut w);
        assert_eq!((rescored, reused), (0, k + 1));
        assert_eq!(json(&again).unwrap(), json(&report).unwrap());
        // The report with the cache is the report without it.
        assert_eq!(json(&report).unwrap(), json(&fresh(&ev.inputs())).unwrap());
    }
    // Each route replayed once, the crashed one twice (its crashed record, then the rerun),
    // the first once more (no longer the only record).
    assert_eq!(total_rescored, n + 2);
    // Telemetry rewritten (same size, new time): that route only is replayed again.
    let name = ev.records[2]["save_name"].as_str().unwrap();
    let file = ev.run.join("telemetry").join(name).join("metric_info.json");
    let bytes = fs::read(&file).unwrap();
    std::thread::sleep(Duration::from_millis(20));
    fs::write(&file, &bytes).unwrap();
    let (_, rescored, _, changed) = scored(&mut w);
    assert_eq!((rescored, changed.len()), (1, 1));
}

/// Spawns `sds watch` over the evaluator's run.
fn spawn_watch(ev: &Evaluator, out: &Path, extra: &[&str]) -> std::process::Child {
    let s = |p: &Path| p.to_str().unwrap().to_string();
    Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(["watch", "--results", &s(&ev.results())])
        .args(["--telemetry", &s(&ev.run.join("telemetry"))])
        .args(["--routes", &s(&ev.src.routes), "--maps", &s(&ev.src.maps)])
        .args(["-o", &s(out), "--status-json"])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// `sds score` over the evaluator's run, written to `out`.
fn score_to(ev: &Evaluator, out: &Path, extra: &[&str]) -> i32 {
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let o = Command::new(env!("CARGO_BIN_EXE_sds"))
        .args(["score", "--results", &s(&ev.results())])
        .args(["--telemetry", &s(&ev.run.join("telemetry"))])
        .args(["--routes", &s(&ev.src.routes), "--maps", &s(&ev.src.maps)])
        .args(["-o", &s(out)])
        .args(extra)
        .output()
        .unwrap();
    o.status.code().unwrap()
}

fn wait(child: &mut std::process::Child, limit: Duration) -> std::process::Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("sds watch did not stop within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.stdout.take();
    let mut err = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
    let status = child.wait().unwrap();
    std::process::Output {
        status,
        stdout: Vec::new(),
        stderr: err.into_bytes(),
    }
}

#[test]
fn live_playback_ends_with_the_score_report() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::new(dir.path());
    let out = dir.path().join("live.json");
    let mut child = spawn_watch(&ev, &out, &["--interval", "0.03", "--timeout", "120"]);
    // The evaluation, time compressed: a route every 80 ms, each checkpoint write paused
    // half-way for 40 ms, a crash and a resume of route 3.
    let mut done: Vec<Value> = Vec::new();
    for k in 0..ev.records.len() {
        if k == 3 {
            let mut with_crash = done.clone();
            with_crash.push(ev.crashed(k));
            ev.write(&with_crash, false);
            std::thread::sleep(Duration::from_millis(80));
            ev.write(&done, false);
            std::thread::sleep(Duration::from_millis(80));
        }
        ev.telemetry(k);
        done.push(ev.records[k].clone());
        let rest = ev.write(&done, true);
        std::thread::sleep(Duration::from_millis(40));
        ev.finish(&rest);
        std::thread::sleep(Duration::from_millis(80));
    }
    let o = wait(&mut child, Duration::from_secs(120));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("sds: error"), "{err}");
    assert!(err.contains("the route set is complete"), "{err}");
    let rounds: Vec<Value> = err
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect();
    assert!(rounds
        .iter()
        .any(|r| r["done"] == 9 && r["complete"] == true));
    // Partial rounds were reported with both figures.
    assert!(rounds
        .iter()
        .any(|r| r["done"].as_u64().is_some_and(|d| d < 9)
            && r["ds_n"].as_f64() < r["ds_done"].as_f64()));
    let reference = dir.path().join("score.json");
    let code = score_to(&ev, &reference, &[]);
    assert_eq!(o.status.code(), Some(code));
    assert_eq!(fs::read(&out).unwrap(), fs::read(&reference).unwrap());
}

#[test]
fn ctrl_c_writes_the_final_report() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::new(dir.path());
    for k in 0..4 {
        ev.telemetry(k);
    }
    ev.write(&ev.records[..4], false);
    let out = dir.path().join("live.html");
    let mut child = spawn_watch(&ev, &out, &["--interval", "0.1", "--format", "html"]);
    let start = Instant::now();
    while !out.exists() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no report written"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    // While the watch runs the page reloads itself.
    let page = fs::read_to_string(&out).unwrap();
    assert!(page.contains("http-equiv=\"refresh\""));
    #[allow(unsafe_code)]
    // SAFETY: kill(2) on our own child's pid.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
    let o = wait(&mut child, Duration::from_secs(60));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("interrupted"), "{err}");
    let reference = dir.path().join("score.html");
    let code = score_to(&ev, &reference, &["--format", "html"]);
    assert_eq!(o.status.code(), Some(code), "{err}");
    let final_page = fs::read(&out).unwrap();
    assert!(!String::from_utf8_lossy(&final_page).contains("http-equiv=\"refresh\""));
    assert_eq!(final_page, fs::read(&reference).unwrap());
}
