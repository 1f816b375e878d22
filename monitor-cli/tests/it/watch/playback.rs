//! `sds watch` (docs/USAGE.md §8) against a small evaluator simulator that plays the demo run back: the
//! checkpoint rewritten in place (truncated, then written in two parts, so a reader may catch
//! it half-written), each route's telemetry written when the route ends, a crash whose route is
//! dropped from the checkpoint on resume and run again, time compressed.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use monitor_host::report::json::json;
use monitor_host::{demo, Inputs, LabelFiles, RoundOutcome, Settings};

use super::fresh;
use monitor_host::{Report, Watcher};
use serde_json::Value;

/// How the evaluator writes its records (docs/SCORE.md §2.1's three input shapes).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Layout {
    /// One raw checkpoint, rewritten in place.
    Raw,
    /// Two GPUs: one checkpoint per shard, routes dealt in turn.
    Shards,
    /// One folder per route with its own checkpoint.
    PerRoute,
}

/// The evaluator: the finished demo run in `src`, played back into `run`.
struct Evaluator {
    src: demo::DemoRun,
    run: PathBuf,
    layout: Layout,
    checkpoint: Value,
    records: Vec<Value>,
}

impl Evaluator {
    fn new(dir: &Path) -> Evaluator {
        Evaluator::with(dir, Layout::Raw)
    }

    fn with(dir: &Path, layout: Layout) -> Evaluator {
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
            layout,
            checkpoint,
            records,
        }
    }

    fn results(&self) -> PathBuf {
        match self.layout {
            Layout::Raw => self.run.join("results.json"),
            Layout::Shards => self.run.join("shards"),
            Layout::PerRoute => self.run.join("per_route"),
        }
    }

    /// Each file of the layout holding `records` and its records (position in `records`).
    fn files(&self, records: &[Value]) -> Vec<(PathBuf, Vec<Value>)> {
        match self.layout {
            Layout::Raw => vec![(self.results(), records.to_vec())],
            Layout::Shards => (0..2)
                .map(|s| {
                    let mine = records.iter().skip(s).step_by(2).cloned().collect();
                    (
                        self.results().join(format!("eval_bench2drive220_{s}.json")),
                        mine,
                    )
                })
                .collect(),
            Layout::PerRoute => records
                .iter()
                .map(|r| {
                    let id = r["route_id"].as_str().unwrap();
                    let f = self.results().join(id).join("checkpoint_endpoint.json");
                    (f, vec![r.clone()])
                })
                .collect(),
        }
    }

    /// Per route id: its file, index and whether it is its file's only record.
    fn places(&self, records: &[Value]) -> Vec<(String, PathBuf, usize, bool)> {
        let mut out = Vec::new();
        for (f, rs) in self.files(records) {
            for (i, r) in rs.iter().enumerate() {
                let id = r["route_id"].as_str().unwrap().to_string();
                out.push((id, f.clone(), i, rs.len() == 1));
            }
        }
        out
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

    /// Rewrites the checkpoint files that changed in place (truncate, then write), removes
    /// those no longer holding a record: with `half`, the last file written gets only its first
    /// half, the way a reader catches it mid-write. Returns that file and the rest.
    fn write(&self, records: &[Value], half: bool) -> (PathBuf, Vec<u8>) {
        let files = self.files(records);
        if self.layout == Layout::PerRoute && self.results().exists() {
            for d in fs::read_dir(self.results()).unwrap() {
                let d = d.unwrap().path();
                if !files.iter().any(|(f, _)| f.starts_with(&d)) {
                    fs::remove_dir_all(d).unwrap();
                }
            }
        }
        let mut last = (self.results(), Vec::new());
        let changed: Vec<(PathBuf, Vec<u8>)> = files
            .into_iter()
            .map(|(f, rs)| {
                let bytes = self.bytes(&rs);
                (f, bytes)
            })
            .filter(|(f, bytes)| fs::read(f).ok().as_ref() != Some(bytes))
            .collect();
        let n = changed.len();
        for (i, (f, bytes)) in changed.into_iter().enumerate() {
            let cut = if half && i + 1 == n {
                bytes.len() / 2
            } else {
                bytes.len()
            };
            fs::create_dir_all(f.parent().unwrap()).unwrap();
            let mut file = OpenOptions::new()
                .write(true)
                .create(true)
                .truncate(true)
                .open(&f)
                .unwrap();
            file.write_all(&bytes[..cut]).unwrap();
            last = (f, bytes[cut..].to_vec());
        }
        last
    }

    fn finish(&self, (file, rest): &(PathBuf, Vec<u8>)) {
        let mut f = OpenOptions::new().append(true).open(file).unwrap();
        f.write_all(rest).unwrap();
    }

    /// The record of route `k` after a crash: the route failed half-way.
    fn crashed(&self, k: usize) -> Value {
        let mut r = self.records[k].clone();
        r["status"] = "Failed - Agent crashed".into();
        r
    }
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

/// The route ids a round must replay: new, or moved, or no longer (or newly) their file's
/// only record, between the places `before` and `after`.
fn expected_changes(
    before: &[(String, PathBuf, usize, bool)],
    after: &[(String, PathBuf, usize, bool)],
) -> Vec<String> {
    let mut ids: Vec<String> = after
        .iter()
        .filter(|p| !before.contains(p))
        .map(|p| p.0.clone())
        .collect();
    ids.sort();
    ids
}

/// A scored round, after at most one retry whose reason holds `why`.
fn scored_after_retry(w: &mut Watcher, why: &str) -> (Report, usize, usize, Vec<String>) {
    match w.round().unwrap() {
        RoundOutcome::Scored { scored, cache, .. } => {
            (scored.report, cache.rescored, cache.reused, cache.changed)
        }
        RoundOutcome::Retry { reason, .. } => {
            assert!(reason.contains(why), "{reason}");
            scored(w)
        }
    }
}

/// A watcher of the evaluator's run with the default settings (no racy-clean delay).
fn watcher(ev: &Evaluator) -> Watcher {
    Watcher::new(
        ev.inputs(),
        Settings::default(),
        LabelFiles::default(),
        None,
        Duration::ZERO,
    )
}

fn playback(layout: Layout) {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::with(dir.path(), layout);
    let n = ev.records.len();
    let mut w = watcher(&ev);
    // Before the evaluator wrote anything: retried, not fatal.
    retried(&mut w);
    let crash = 4;
    let mut done: Vec<Value> = Vec::new();
    let mut places = Vec::new();
    let mut total_rescored = 0;
    let mut replays_expected = 0;
    for k in 0..n {
        if k == crash {
            // The route crashes: its record is written without telemetry...
            let mut with_crash = done.clone();
            with_crash.push(ev.crashed(k));
            ev.write(&with_crash, false);
            let (report, rescored, reused, mut changed) = scored(&mut w);
            changed.sort();
            let now = ev.places(&with_crash);
            let expected = expected_changes(&places, &now);
            assert_eq!(changed, expected, "{layout:?} crash round");
            assert_eq!((rescored, reused), (expected.len(), k + 1 - expected.len()));
            assert_eq!(w.progress(&report).done, k + 1);
            total_rescored += rescored;
            replays_expected += expected.len();
            // ... and on resume the evaluator drops it and runs the route again: the
            // checkpoint shrinks (retried once), then holds the earlier routes only.
            ev.write(&done, false);
            let (_, rescored, _, mut changed) = scored_after_retry(&mut w, "shorter");
            changed.sort();
            let expected = expected_changes(&now, &ev.places(&done));
            assert_eq!(changed, expected, "{layout:?} resume round");
            total_rescored += rescored;
            replays_expected += expected.len();
            places = ev.places(&done);
        }
        ev.telemetry(k);
        done.push(ev.records[k].clone());
        // Every second route the reader catches a checkpoint half-written.
        let rest = ev.write(&done, k % 2 == 1);
        if k % 2 == 1 {
            let why = retried(&mut w);
            let file = rest.0.file_name().unwrap().to_string_lossy().into_owned();
            assert!(why.contains(&file), "{layout:?}: {why}");
            ev.finish(&rest);
        }
        let (report, rescored, reused, mut changed) = scored(&mut w);
        changed.sort();
        let now = ev.places(&done);
        let expected = expected_changes(&places, &now);
        assert!(expected.contains(&ev.records[k]["route_id"].as_str().unwrap().to_string()));
        assert_eq!(changed, expected, "{layout:?} round of route {k}");
        assert_eq!((rescored, reused), (expected.len(), k + 1 - expected.len()));
        total_rescored += rescored;
        replays_expected += expected.len();
        places = now;
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
    // Each route replayed once, the crashed one twice (its crashed record, then the rerun), and
    // those whose file changed from one record to several once more.
    assert_eq!(total_rescored, replays_expected);
    assert!(total_rescored > n);
    // Telemetry rewritten (same size, new time): that route only is replayed again.
    let name = ev.records[2]["save_name"].as_str().unwrap();
    let file = ev.run.join("telemetry").join(name).join("metric_info.json");
    let bytes = fs::read(&file).unwrap();
    let before = fs::metadata(&file).unwrap().modified().unwrap();
    fs::write(&file, &bytes).unwrap();
    // A second later than before, set rather than waited for: a coarse clock cannot hide it.
    let f = OpenOptions::new().write(true).open(&file).unwrap();
    f.set_modified(before + Duration::from_secs(1)).unwrap();
    let (_, rescored, _, changed) = scored(&mut w);
    assert_eq!(
        (rescored, changed),
        (
            1,
            vec![ev.records[2]["route_id"].as_str().unwrap().to_string()]
        )
    );
}

#[test]
fn playback_raw_checkpoint_rescored_only_when_changed() {
    playback(Layout::Raw);
}

#[test]
fn playback_shard_checkpoints_rescored_only_when_changed() {
    playback(Layout::Shards);
}

#[test]
fn playback_per_route_folders_rescored_only_when_changed() {
    playback(Layout::PerRoute);
}

/// `sds watch` over the evaluator's run, its status lines in JSON.
fn watch_args(ev: &Evaluator, out: &Path, extra: &[&str]) -> Vec<String> {
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let mut args = vec!["watch".to_string(), "--results".into(), s(&ev.results())];
    args.extend(["--telemetry".into(), s(&ev.run.join("telemetry"))]);
    args.extend([
        "--routes".into(),
        s(&ev.src.routes),
        "--maps".into(),
        s(&ev.src.maps),
    ]);
    args.extend(["-o".into(), s(out), "--status-json".into()]);
    args.extend(extra.iter().map(|a| a.to_string()));
    args
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

/// A scored (not retried) round with `done` routes done.
fn round_of(done: usize) -> impl Fn(&Value) -> bool {
    move |l| l["done"] == done && l.get("retry").is_none()
}

#[test]
fn live_playback_ends_with_the_score_report() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::new(dir.path());
    let out = dir.path().join("live.json");
    let mut live = super::Live::spawn(&watch_args(&ev, &out, &["--interval", "0.03"]));
    // The evaluation in lockstep with the watch: each state of the run is written once the
    // watch said it scored the one before (a status line), never after a pause, so the rounds
    // seen do not depend on how busy the machine is (issue 48; pauses raced them before).
    let mut done: Vec<Value> = Vec::new();
    for k in 0..ev.records.len() {
        if k == 3 {
            // Route 3 crashes: its record is written and scored, then on resume the evaluator
            // drops it (the checkpoint shrinks) and runs the route again.
            let mut with_crash = done.clone();
            with_crash.push(ev.crashed(k));
            ev.write(&with_crash, false);
            live.status("round of the crashed record", round_of(k + 1));
            ev.write(&done, false);
            live.status("round after the resume", round_of(k));
        }
        ev.telemetry(k);
        done.push(ev.records[k].clone());
        // Written in two parts: a round may catch the checkpoint half-written and retry.
        let rest = ev.write(&done, true);
        ev.finish(&rest);
        live.status("round of the route", round_of(k + 1));
    }
    let o = live.finish(Duration::from_secs(120));
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
    let mut live = super::Live::spawn(&watch_args(
        &ev,
        &out,
        &["--interval", "0.1", "--format", "html"],
    ));
    // A round's status line comes before its report is written: the second round's line says
    // the first round's page is on disk.
    live.status("first round", round_of(4));
    live.status("second round", round_of(4));
    // While the watch runs the page reloads itself.
    let page = fs::read_to_string(&out).unwrap();
    assert!(page.contains("http-equiv=\"refresh\""));
    live.interrupt();
    let o = live.finish(Duration::from_secs(60));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("interrupted"), "{err}");
    let reference = dir.path().join("score.html");
    let code = score_to(&ev, &reference, &["--format", "html"]);
    assert_eq!(o.status.code(), Some(code), "{err}");
    let final_page = fs::read(&out).unwrap();
    assert!(!String::from_utf8_lossy(&final_page).contains("http-equiv=\"refresh\""));
    assert_eq!(final_page, fs::read(&reference).unwrap());
}

#[test]
fn without_a_route_set_the_checkpoint_progress_ends_the_watch() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::new(dir.path());
    let n = ev.records.len();
    let inputs = Inputs {
        route_xml: None,
        ..ev.inputs()
    };
    let mut w = Watcher::new(
        inputs,
        Settings::default(),
        LabelFiles::default(),
        None,
        Duration::ZERO,
    );
    for k in 0..n {
        ev.telemetry(k);
    }
    ev.write(&ev.records[..4], false);
    let (report, ..) = scored(&mut w);
    // progress [4, 9]: not done, though every route read has its record.
    assert_eq!(w.progress(&report).done, 4);
    assert!(!w.progress(&report).complete);
    ev.write(&ev.records, false);
    let (report, ..) = scored(&mut w);
    assert!(w.progress(&report).complete);
}

/// Two GPUs, two shard checkpoints side by side: the time left is that of the shard with the
/// most routes left (its `progress`), not of all the routes left one after another.
#[test]
fn time_left_with_shards_is_the_slowest_shards() {
    let dir = tempfile::tempdir().unwrap();
    let ev = Evaluator::with(dir.path(), Layout::Shards);
    let shards = ev.results();
    fs::create_dir_all(&shards).unwrap();
    // Shard 0 holds routes 0, 1 of its 5; shard 1 routes 2, 3 of its 4.
    for (s, (from, to, total)) in [(0, 2, 5), (2, 4, 4)].into_iter().enumerate() {
        let mut c = ev.checkpoint.clone();
        c["_checkpoint"]["records"] = Value::Array(ev.records[from..to].to_vec());
        c["_checkpoint"]["progress"] = serde_json::json!([to - from, total]);
        let f = shards.join(format!("eval_bench2drive220_{s}.json"));
        fs::write(f, serde_json::to_vec_pretty(&c).unwrap()).unwrap();
    }
    for k in 0..4 {
        ev.telemetry(k);
    }
    let mut w = watcher(&ev);
    let (report, ..) = scored(&mut w);
    let p = w.progress(&report);
    assert_eq!((p.done, p.n), (4, 9));
    let mean = (0..4)
        .map(|k| ev.records[k]["meta"]["duration_system"].as_f64().unwrap())
        .sum::<f64>()
        / 4.0;
    // Shard 0 has 3 routes left, shard 1 has 2: 3 routes' time, not the 5 left in all.
    let left = p.seconds_left.unwrap();
    assert!((left - 3.0 * mean).abs() < 1e-9, "{left} vs {}", 3.0 * mean);
}
