//! The adversarial trial of issue 12 (`docs/RELIABILITY.md`, "Nothing destroyed, nothing lost,
//! nothing hangs"): special files, FIFOs, symbolic links, signals and hostile numbers, each made
//! in a temporary folder (never the real `/dev`). Runs as root or not: where root ignores a mode
//! bit, the test uses what fails for root too.

use std::ffi::CString;
use std::fs;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common::{code, stderr};

const SDS: &str = env!("CARGO_BIN_EXE_sds");

fn cstr(p: &Path) -> CString {
    CString::new(p.as_os_str().as_bytes()).unwrap()
}

fn mkfifo(p: &Path) {
    // SAFETY: a valid NUL-terminated path.
    let r = unsafe { libc::mkfifo(cstr(p).as_ptr(), 0o644) };
    assert_eq!(r, 0, "mkfifo {}", p.display());
}

/// A character device node equal to `/dev/zero` (1, 5) at `p`; `false` when this process may
/// not create device nodes (not root, or a container without CAP_MKNOD).
fn mk_zero_device(p: &Path) -> bool {
    // SAFETY: a valid NUL-terminated path.
    let r = unsafe { libc::mknod(cstr(p).as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 5)) };
    r == 0
}

/// Runs `sds` and waits at most `secs`; a run still going then is killed and the test fails
/// (the tool hung).
fn run_bounded(args: &[&dyn AsRef<std::ffi::OsStr>], secs: u64) -> Output {
    let mut c = Command::new(SDS);
    for a in args {
        c.arg(a);
    }
    let child = c
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sds");
    wait_bounded(child, secs)
}

fn wait_bounded(mut child: Child, secs: u64) -> Output {
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let o = child.wait_with_output().unwrap();
            panic!(
                "sds hung for {secs} s; stderr: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

struct Demo {
    dir: PathBuf,
    results: PathBuf,
    telemetry: PathBuf,
    routes: PathBuf,
}

fn demo(dir: &Path) -> Demo {
    let o = run_bounded(&[&"demo", &dir], 60);
    assert_eq!(code(&o), 0, "sds demo failed: {}", stderr(&o));
    Demo {
        dir: dir.to_path_buf(),
        results: dir.join("results.json"),
        telemetry: dir.join("telemetry"),
        routes: dir.join("routes.xml"),
    }
}

/// The first telemetry folder of the demo (sorted by name).
fn first_telemetry(d: &Demo) -> PathBuf {
    let mut dirs: Vec<_> = fs::read_dir(&d.telemetry)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    dirs.remove(0)
}

fn score_json(d: &Demo, extra: &[&dyn AsRef<std::ffi::OsStr>]) -> (Output, Option<Value>) {
    let mut args: Vec<&dyn AsRef<std::ffi::OsStr>> = vec![
        &"score",
        &"--results",
        &d.results,
        &"--telemetry",
        &d.telemetry,
        &"--routes",
        &d.routes,
    ];
    args.extend_from_slice(extra);
    let o = run_bounded(&args, 60);
    let report = serde_json::from_slice(&o.stdout).ok();
    (o, report)
}

/// A route's state and reason as one text (`invalid: <reason>`).
fn state_of(r: &Value) -> String {
    match r["reason"].as_str() {
        Some(why) => format!("{}: {why}", r["state"].as_str().unwrap()),
        None => r["state"].as_str().unwrap().to_string(),
    }
}

fn route_with_source<'a>(report: &'a Value, id: &str) -> &'a Value {
    report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["route_id"] == id)
        .unwrap_or_else(|| panic!("no route {id} in the report"))
}

// ---------------------------------------------------------------------------------------------
// Reading: only regular files, bounded per kind.

#[test]
fn a_fifo_input_never_blocks() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));

    // A FIFO as --results, as --routes, as a label file: an error naming the path, at once.
    let fifo = tmp.path().join("fifo.json");
    mkfifo(&fifo);
    let o = run_bounded(&[&"score", &"--results", &fifo], 20);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("fifo.json: cannot read: a FIFO, not a regular file"));
    let o = run_bounded(
        &[
            &"score",
            &"--results",
            &d.results,
            &"--telemetry",
            &d.telemetry,
            &"--routes",
            &fifo,
        ],
        20,
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a FIFO, not a regular file"),
        "{}",
        stderr(&o)
    );
    let o = run_bounded(
        &[
            &"score",
            &"--results",
            &d.results,
            &"--telemetry",
            &d.telemetry,
            &"--format",
            &"table",
            &"--group-by",
            &"family",
            &"--families",
            &fifo,
        ],
        20,
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a FIFO, not a regular file"),
        "{}",
        stderr(&o)
    );

    // A FIFO in place of one route's metric_info.json: that route is invalid, the rest scored.
    let folder = first_telemetry(&d);
    let mi = folder.join("metric_info.json");
    fs::remove_file(&mi).unwrap();
    mkfifo(&mi);
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let report = report.unwrap();
    let states: Vec<String> = report["routes"]
        .as_array()
        .unwrap()
        .iter()
        .map(state_of)
        .collect();
    assert_eq!(
        states.iter().filter(|s| s.starts_with("invalid")).count(),
        1,
        "{states:?}"
    );
    let text = serde_json::to_string(&report).unwrap();
    assert!(text.contains("a FIFO, not a regular file"), "{text}");
    let _ = d.dir;

    // An OpenDRIVE map that is a FIFO (the library's map reader goes through the same guard).
    let (tx, rx) = std::sync::mpsc::channel();
    let map_fifo = tmp.path().join("Town01.xodr");
    mkfifo(&map_fifo);
    std::thread::spawn(move || {
        let _ = tx.send(monitor_host::geometry::map::Map::load(&map_fifo).map(|_| ()));
    });
    let e = rx
        .recv_timeout(Duration::from_secs(20))
        .expect("Map::load hung on a FIFO")
        .unwrap_err();
    assert!(e.to_string().contains("a FIFO, not a regular file"), "{e}");
}

#[test]
fn a_device_or_huge_input_is_refused_not_read() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));

    // A sparse label file one byte over its 16 MiB bound: refused without reading it.
    let big = tmp.path().join("families.json");
    let f = fs::File::create(&big).unwrap();
    f.set_len(16 * 1024 * 1024 + 1).unwrap();
    let o = run_bounded(
        &[
            &"score",
            &"--results",
            &d.results,
            &"--format",
            &"table",
            &"--group-by",
            &"family",
            &"--families",
            &big,
            &"--allow-missing-telemetry",
        ],
        20,
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("over the 16 MiB limit for a label file"),
        "{}",
        stderr(&o)
    );

    // A metric_info.json that is a zero device (made here, not the real /dev/zero), or a link
    // to one: refused at once, not read until memory runs out.
    let zero = tmp.path().join("zero");
    if !mk_zero_device(&zero) {
        crate::common::skipped(
            "the device half: cannot create a device node here (needs CAP_MKNOD)",
        );
        return;
    }
    let folder = first_telemetry(&d);
    let mi = folder.join("metric_info.json");
    fs::remove_file(&mi).unwrap();
    std::os::unix::fs::symlink(&zero, &mi).unwrap();
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let text = serde_json::to_string(&report.unwrap()).unwrap();
    assert!(
        text.contains("a character device, not a regular file"),
        "{text}"
    );
    let o = run_bounded(&[&"score", &"--results", &zero], 20);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("a character device, not a regular file"));
}

// ---------------------------------------------------------------------------------------------
// Output: only regular files, never an input, umask mode, no temporary file left, no lost report.

fn score_to(d: &Demo, out: &Path) -> Output {
    run_bounded(
        &[
            &"score",
            &"--results",
            &d.results,
            &"--telemetry",
            &d.telemetry,
            &"--routes",
            &d.routes,
            &"-o",
            &out,
        ],
        60,
    )
}

#[test]
fn output_never_replaces_a_special_file() {
    use std::os::unix::fs::FileTypeExt;
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));

    // A FIFO: refused (not replaced, and no hang waiting for a reader).
    let fifo = tmp.path().join("out.fifo");
    mkfifo(&fifo);
    let o = score_to(&d, &fifo);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a FIFO, not a regular file"),
        "{}",
        stderr(&o)
    );
    assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());

    // A link like /dev/stdout (to /proc/self/fd/1: here a pipe): refused, the link stays.
    let link = tmp.path().join("stdout");
    std::os::unix::fs::symlink("/proc/self/fd/1", &link).unwrap();
    let o = score_to(&d, &link);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());

    // A directory: refused.
    let o = score_to(&d, tmp.path());
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("a directory, not a regular file"));

    // A null device node made here (not the real /dev/null): refused, still a device.
    let null = tmp.path().join("null");
    // SAFETY: a valid NUL-terminated path.
    let made = unsafe {
        libc::mknod(
            cstr(&null).as_ptr(),
            libc::S_IFCHR | 0o666,
            libc::makedev(1, 3),
        )
    } == 0;
    if made {
        let o = score_to(&d, &null);
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains("a character device, not a regular file"));
        assert!(fs::symlink_metadata(&null)
            .unwrap()
            .file_type()
            .is_char_device());
    } else {
        crate::common::skipped("the device node case: cannot create a device node here");
    }

    // A link to a regular file: the link stays, its target gets the report.
    let target = tmp.path().join("target.json");
    fs::write(&target, "old").unwrap();
    let link = tmp.path().join("report-link.json");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = score_to(&d, &link);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(fs::read_to_string(&target)
        .unwrap()
        .contains("sds-report/1"));
}

#[test]
fn output_never_writes_over_an_input() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let mi = first_telemetry(&d).join("metric_info.json");
    let families = tmp.path().join("families.json");
    fs::write(&families, r#"{"DemoCruising": "cruise"}"#).unwrap();
    let linked = tmp.path().join("results-link.json");
    std::os::unix::fs::symlink(&d.results, &linked).unwrap();
    let before: Vec<Vec<u8>> = [&d.results, &d.routes, &mi, &families]
        .iter()
        .map(|p| fs::read(p).unwrap())
        .collect();
    for out in [&d.results, &d.routes, &mi, &linked] {
        let o = score_to(&d, out);
        assert_eq!(code(&o), 1, "{}: {}", out.display(), stderr(&o));
        assert!(
            stderr(&o).contains("is one of the run's inputs"),
            "{}",
            stderr(&o)
        );
    }
    let o = run_bounded(
        &[
            &"score",
            &"--results",
            &d.results,
            &"--telemetry",
            &d.telemetry,
            &"--format",
            &"table",
            &"--group-by",
            &"family",
            &"--families",
            &families,
            &"-o",
            &families,
        ],
        60,
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("is one of the run's inputs"));
    let id = "RouteScenario_900001_rep0";
    for out in [&d.results, &mi] {
        let o = run_bounded(
            &[
                &"frames",
                &"--results",
                &d.results,
                &"--telemetry",
                &d.telemetry,
                &"--route-id",
                &id,
                &"-o",
                &out,
            ],
            60,
        );
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains("is one of the run's inputs"));
    }
    // A results file without records (a crashed run) in a --results folder is an input too.
    let folder = tmp.path().join("results-folder");
    fs::create_dir(&folder).unwrap();
    fs::copy(&d.results, folder.join("run.json")).unwrap();
    let crashed = folder.join("crashed.json");
    fs::write(
        &crashed,
        r#"{"_checkpoint": {"records": []}, "entry_status": "Crashed"}"#,
    )
    .unwrap();
    let o = run_bounded(
        &[
            &"score",
            &"--results",
            &folder,
            &"--telemetry",
            &d.telemetry,
            &"-o",
            &crashed,
        ],
        60,
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is one of the run's inputs"),
        "{}",
        stderr(&o)
    );
    assert!(fs::read_to_string(&crashed).unwrap().contains("Crashed"));
    let after: Vec<Vec<u8>> = [&d.results, &d.routes, &mi, &families]
        .iter()
        .map(|p| fs::read(p).unwrap())
        .collect();
    assert!(before == after, "an input was changed");
}

#[test]
fn demo_refuses_to_overwrite_a_run_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    demo(&dir);
    fs::write(dir.join("results.json"), "my precious run").unwrap();
    let o = run_bounded(&[&"demo", &dir], 60);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("already holds a run"), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"));
    assert_eq!(
        fs::read_to_string(dir.join("results.json")).unwrap(),
        "my precious run"
    );
    let o = run_bounded(&[&"demo", &dir, &"--force"], 60);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(fs::read_to_string(dir.join("results.json"))
        .unwrap()
        .contains("_checkpoint"));
}

/// Runs `sds` through `sh -c` (umask, closed descriptors), bounded.
fn run_sh(script: &str, args: &[&dyn AsRef<std::ffi::OsStr>], env: &[(&str, &str)]) -> Child {
    let mut c = Command::new("sh");
    c.arg("-c").arg(script).arg(SDS);
    for a in args {
        c.arg(a);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sh")
}

#[test]
fn report_mode_follows_the_umask_and_an_existing_file_keeps_its_mode() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let out = tmp.path().join("report.json");
    let args: [&dyn AsRef<std::ffi::OsStr>; 9] = [
        &"score",
        &"--results",
        &d.results,
        &"--telemetry",
        &d.telemetry,
        &"--routes",
        &d.routes,
        &"-o",
        &out,
    ];
    let o = wait_bounded(run_sh("umask 027; exec \"$0\" \"$@\"", &args, &[]), 60);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        fs::metadata(&out).unwrap().permissions().mode() & 0o777,
        0o640
    );
    fs::set_permissions(&out, fs::Permissions::from_mode(0o604)).unwrap();
    let o = wait_bounded(run_sh("umask 077; exec \"$0\" \"$@\"", &args, &[]), 60);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        fs::metadata(&out).unwrap().permissions().mode() & 0o777,
        0o604
    );
}

#[test]
fn a_signal_during_the_final_write_leaves_no_temporary_file() {
    for (sig, name) in [(libc::SIGTERM, "SIGTERM"), (libc::SIGINT, "SIGINT")] {
        let tmp = tempfile::tempdir().unwrap();
        let d = demo(&tmp.path().join("run"));
        let outdir = tmp.path().join("out");
        fs::create_dir(&outdir).unwrap();
        let out = outdir.join("report.json");
        let args: [&dyn AsRef<std::ffi::OsStr>; 9] = [
            &"score",
            &"--results",
            &d.results,
            &"--telemetry",
            &d.telemetry,
            &"--routes",
            &d.routes,
            &"-o",
            &out,
        ];
        let child = run_sh("exec \"$0\" \"$@\"", &args, &[("SDS_TEST_WRITE_HOLD", "1")]);
        // Wait until the temporary file is written, then interrupt.
        let start = Instant::now();
        while fs::read_dir(&outdir).unwrap().next().is_none() {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "no temporary file appeared"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
        // SAFETY: signalling our own child.
        assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
        let o = wait_bounded(child, 15);
        assert!(!o.status.success(), "{name}: {:?}", o.status);
        let left: Vec<_> = fs::read_dir(&outdir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        assert!(left.is_empty(), "{name} left {left:?}");
    }
}

#[test]
fn a_closed_standard_output_is_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let args: [&dyn AsRef<std::ffi::OsStr>; 7] = [
        &"score",
        &"--results",
        &d.results,
        &"--telemetry",
        &d.telemetry,
        &"--routes",
        &d.routes,
    ];
    let o = wait_bounded(run_sh("exec \"$0\" \"$@\" >&-", &args, &[]), 60);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("standard output is closed"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn jobs_are_bounded_by_the_work() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let (o, _) = score_json(&d, &[&"--jobs", &"0"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--jobs") && stderr(&o).contains("at least 1"),
        "{}",
        stderr(&o)
    );
    // 9 routes: 9 threads, not 100,000 (which aborted with a panic message).
    let (o, report) = score_json(&d, &[&"--jobs", &"100000"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"));
    assert_eq!(report.unwrap()["routes"].as_array().unwrap().len(), 9);
}

// ---------------------------------------------------------------------------------------------
// Scores and keys: range-checked, never resolved silently.

/// The demo's results as text, with `f` applied to the parsed document.
fn edit_results(d: &Demo, f: impl FnOnce(&mut Value)) {
    let mut doc: Value = serde_json::from_slice(&fs::read(&d.results).unwrap()).unwrap();
    f(&mut doc);
    fs::write(&d.results, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
}

#[test]
fn out_of_range_scores_make_the_record_invalid() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let cases = [
        (
            "score_route",
            serde_json::json!(1e308),
            "scores.score_route: 1e308 is outside 0..=100",
        ),
        (
            "score_route",
            serde_json::json!(-50),
            "scores.score_route: -50.0 is outside 0..=100",
        ),
        (
            "score_penalty",
            serde_json::json!(-3),
            "scores.score_penalty: -3.0 is outside 0..=1",
        ),
        (
            "score_penalty",
            serde_json::json!(5),
            "scores.score_penalty: 5.0 is outside 0..=1",
        ),
    ];
    edit_results(&d, |doc| {
        let recs = doc["_checkpoint"]["records"].as_array_mut().unwrap();
        for (i, (field, v, _)) in cases.iter().enumerate() {
            recs[i]["scores"][*field] = v.clone();
        }
        // A composed score that is not route x penalty: warned, still scored.
        let r = &mut recs[5]["scores"];
        r["score_composed"] = serde_json::json!(12.5);
    });
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let report = report.unwrap();
    let routes = report["routes"].as_array().unwrap();
    for (i, (_, _, reason)) in cases.iter().enumerate() {
        let state = state_of(&routes[i]);
        assert!(
            state.starts_with("invalid") && state.contains(reason),
            "{state}"
        );
    }
    assert_eq!(routes[5]["state"], "scored");
    // Aggregates stay finite and in range.
    for key in ["driving_score", "mean_ds_safe", "sds"] {
        let v = &report["summary"][key];
        assert!(
            v.is_null() || (0.0..=100.0).contains(&v.as_f64().unwrap()),
            "{key}: {v}"
        );
    }
    let text = serde_json::to_string(&report["warnings"]).unwrap();
    assert!(
        text.contains("score_composed 12.5 is not score_route"),
        "{text}"
    );
}

#[test]
fn duplicate_keys_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let text = fs::read_to_string(&d.results).unwrap();
    let cases = [
        (
            text.replacen("{", "{\n  \"_checkpoint\": {\"records\": []},", 1),
            "field _checkpoint: duplicate key",
        ),
        (
            text.replacen("\"records\": [", "\"records\": [], \"records\": [", 1),
            "field _checkpoint.records: duplicate key",
        ),
        (
            text.replacen(
                "\"route_id\": \"RouteScenario_900001_rep0\",",
                "\"route_id\": \"RouteScenario_900001_rep0\", \"route_id\": \"RouteScenario_1_rep0\",",
                1,
            ),
            "field _checkpoint.records[0].route_id: duplicate key",
        ),
    ];
    for (bad, want) in cases {
        assert_ne!(bad, text);
        fs::write(&d.results, &bad).unwrap();
        let (o, _) = score_json(&d, &[]);
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains(want), "{want}: {}", stderr(&o));
    }
    // Label files too.
    fs::write(&d.results, &text).unwrap();
    {
        let f = tmp.path().join("f.json");
        fs::write(&f, "{\"A\": \"x\", \"A\": \"y\"}").unwrap();
        let (o, _) = score_json(
            &d,
            &[
                &"--format",
                &"table",
                &"--group-by",
                &"family",
                &"--families",
                &f,
            ],
        );
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        assert!(
            stderr(&o).contains("key \"A\" is given twice"),
            "{}",
            stderr(&o)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// A results directory: nothing lost without an entry, nothing pulled in from outside.

/// Runs `sds score` on a results directory; as root, as user `nobody` (root ignores mode bits,
/// so an unreadable folder is only unreadable to someone else). `nobody` may not be able to
/// reach the build folder (a clone inside root's 0700 home), so it runs a copy of the binary
/// placed in `scratch`, a folder of the test's that others can enter.
fn score_dir_as_user(results: &Path, telemetry: &Path, scratch: &Path) -> (Output, Value) {
    use std::os::unix::process::CommandExt;
    // SAFETY: geteuid has no preconditions.
    let as_root = unsafe { libc::geteuid() } == 0;
    let program = if as_root {
        let copy = scratch.join("sds-copy");
        fs::copy(SDS, &copy).unwrap();
        fs::set_permissions(&copy, fs::Permissions::from_mode(0o755)).unwrap();
        copy
    } else {
        PathBuf::from(SDS)
    };
    let mut c = Command::new(&program);
    c.args(["score", "--results"])
        .arg(results)
        .arg("--telemetry")
        .arg(telemetry)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if as_root {
        c.uid(65534).gid(65534);
    }
    let o = wait_bounded(c.spawn().expect("run sds"), 60);
    let report = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|_| panic!("no report; stderr: {}", stderr(&o)));
    (o, report)
}

#[test]
fn a_results_directory_loses_nothing_silently() {
    let tmp = tempfile::tempdir().unwrap();
    fs::set_permissions(tmp.path(), fs::Permissions::from_mode(0o755)).unwrap();
    let d = demo(&tmp.path().join("run"));
    let doc: Value = serde_json::from_slice(&fs::read(&d.results).unwrap()).unwrap();
    let records = doc["_checkpoint"]["records"].as_array().unwrap().clone();
    let res = tmp.path().join("run/res");
    let write = |dir: &Path, recs: &[Value]| {
        fs::create_dir_all(dir).unwrap();
        let doc = serde_json::json!({"_checkpoint": {"progress": [1, 1], "records": recs},
                                     "entry_status": "Finished"});
        fs::write(dir.join("checkpoint.json"), doc.to_string()).unwrap();
    };
    for (i, r) in records.iter().enumerate().take(4) {
        write(&res.join(format!("r{i}")), std::slice::from_ref(r));
    }
    // Folders with results that cannot be listed (no r) or searched (no x).
    write(&res.join("r4_unlistable"), &records[4..5]);
    fs::set_permissions(res.join("r4_unlistable"), fs::Permissions::from_mode(0o300)).unwrap();
    write(&res.join("r5_unsearchable"), &records[5..6]);
    fs::set_permissions(
        res.join("r5_unsearchable"),
        fs::Permissions::from_mode(0o644),
    )
    .unwrap();
    // A dangling and two looping *.json links.
    std::os::unix::fs::symlink("gone.json", res.join("dangling.json")).unwrap();
    std::os::unix::fs::symlink("loop_b.json", res.join("loop_a.json")).unwrap();
    std::os::unix::fs::symlink("loop_a.json", res.join("loop_b.json")).unwrap();
    // Another run beside this one, reachable through a link leading out of the root.
    write(&tmp.path().join("other"), &records[6..7]);
    std::os::unix::fs::symlink("../..", res.join("up")).unwrap();
    // Everything readable by others, except the two locked folders.
    for dir in [
        tmp.path().join("run"),
        tmp.path().join("other"),
        d.telemetry.clone(),
    ] {
        for e in walk(&dir) {
            let m = fs::symlink_metadata(&e).unwrap();
            let name = e.to_string_lossy();
            if m.is_symlink() || name.contains("r4_unlistable") || name.contains("r5_unsearchable")
            {
                continue;
            }
            let mode = if m.is_dir() { 0o755 } else { 0o644 };
            fs::set_permissions(&e, fs::Permissions::from_mode(mode)).unwrap();
        }
    }

    let (o, report) = score_dir_as_user(&res, &d.telemetry, tmp.path());
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let routes = report["routes"].as_array().unwrap();
    let by_source = |part: &str| -> Vec<&Value> {
        routes
            .iter()
            .filter(|r| r["source"]["file"].as_str().unwrap().contains(part))
            .collect()
    };
    for (part, reason) in [
        ("r4_unlistable", "cannot list this folder"),
        ("r5_unsearchable", "Permission denied"),
        ("dangling.json", "a symbolic link that cannot be followed"),
        ("loop_a.json", "a symbolic link that cannot be followed"),
        ("loop_b.json", "a symbolic link that cannot be followed"),
    ] {
        let found = by_source(part);
        assert_eq!(found.len(), 1, "{part}: {routes:?}");
        let state = state_of(found[0]);
        assert!(
            state.starts_with("invalid") && state.contains(reason),
            "{part}: {state}"
        );
    }
    // The four healthy routes are scored; the other run is not pulled in.
    let ok = routes.iter().filter(|r| r["state"] == "scored").count();
    assert_eq!(ok, 4, "{routes:?}");
    let other_id = records[6]["route_id"].as_str().unwrap();
    assert!(routes.iter().all(|r| r["route_id"] != other_id));
    let warnings = serde_json::to_string(&report["warnings"]).unwrap();
    assert!(
        warnings.contains("a folder link leading out of the results folder"),
        "{warnings}"
    );
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = vec![dir.to_path_buf()];
    if fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        for e in fs::read_dir(dir).unwrap() {
            out.extend(walk(&e.unwrap().path()));
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Route XML problems are reported on their routes, never a silent loss of the lateral term.

fn replace_route(xml: &str, id: &str, with: &str) -> String {
    let start = xml.find(&format!("<route id=\"{id}\"")).unwrap();
    let end = start + xml[start..].find("</route>").unwrap() + "</route>".len();
    format!("{}{with}{}", &xml[..start], &xml[end..])
}

#[test]
fn route_xml_problems_are_reported() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let xml = fs::read_to_string(&d.routes).unwrap();
    let xml = replace_route(
        &xml,
        "900002",
        r#"<route id="900002" town="Town01"><waypoints><position x="1" y="2" z="0"/></waypoints></route>"#,
    );
    let xml = replace_route(
        &xml,
        "900003",
        r#"<route id="900003" town="Town01"><waypoints><position x="0" y="0" z="0"/><position x="50" y="0" z="0"/><position x="100" y="0" z="0"/></waypoints></route>"#,
    );
    let xml = xml.replace(
        "</routes>",
        r#"<route id="900001" town="Town01"><waypoints><position x="0" y="0" z="0"/><position x="1" y="0" z="0"/></waypoints></route></routes>"#,
    );
    fs::write(&d.routes, xml).unwrap();
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let report = report.unwrap();
    for (id, want) in [
        (
            "RouteScenario_900001_rep0",
            "route 900001: id appears twice (ambiguous",
        ),
        (
            "RouteScenario_900002_rep0",
            "route 900002: a single waypoint",
        ),
        (
            "RouteScenario_900003_rep0",
            "route 900003: every segment is longer than gap_max = 8 m",
        ),
    ] {
        let r = route_with_source(&report, id);
        let w = serde_json::to_string(&r["warnings"]).unwrap();
        assert!(w.contains(want), "{id}: {w}");
        assert!(stderr(&o).contains(want), "{}", stderr(&o));
    }
}

#[test]
fn a_save_name_pointing_at_another_route_is_detected() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let mut other = String::new();
    edit_results(&d, |doc| {
        let recs = doc["_checkpoint"]["records"].as_array_mut().unwrap();
        other = recs[1]["save_name"].as_str().unwrap().to_string();
        recs[0]["save_name"] = Value::String(other.clone());
    });
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let report = report.unwrap();
    let r = route_with_source(&report, "RouteScenario_900001_rep0");
    let state = state_of(r);
    assert!(
        state.starts_with("invalid")
            && state.contains(&format!("save_name {other:?} names the telemetry of route RouteScenario_900002_rep0, not of this record's RouteScenario_900001_rep0")),
        "{state}"
    );
    assert_eq!(r["frames"], 0);
}

// ---------------------------------------------------------------------------------------------
// Invalid telemetry names the field of the file; dt is bounded.

#[test]
fn an_overflowing_derived_value_names_the_files_field() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let mi = first_telemetry(&d).join("metric_info.json");
    let mut doc: Value = serde_json::from_slice(&fs::read(&mi).unwrap()).unwrap();
    let mut steps: Vec<u64> = doc
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.parse().unwrap())
        .collect();
    steps.sort();
    let step = steps[12];
    // Finite f32 values whose magnitude |a| overflows f32.
    doc[step.to_string()]["acceleration"] = serde_json::json!([3e38, 3e38, 0.0]);
    fs::write(&mi, serde_json::to_vec(&doc).unwrap()).unwrap();
    let (o, report) = score_json(&d, &[]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let r = route_with_source(&report.unwrap(), "RouteScenario_900001_rep0").clone();
    let state = state_of(&r);
    assert!(
        state.contains(&format!(
            "acceleration at step {step} is too large: |a| overflows f32"
        )),
        "{state}"
    );
}

#[test]
fn dt_is_bounded() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    for dt in ["1e-45", "0.0009", "1.5", "-0.05"] {
        let set = format!("dt={dt}");
        let (o, _) = score_json(&d, &[&"--set", &set]);
        assert_eq!(code(&o), 2, "dt={dt}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("dt must lie in 0.001..=1 s"),
            "{}",
            stderr(&o)
        );
    }
    for dt in ["0.001", "0.1", "1"] {
        let set = format!("dt={dt}");
        let (o, _) = score_json(&d, &[&"--set", &set]);
        assert!(code(&o) == 0 || code(&o) == 3, "dt={dt}: {}", stderr(&o));
    }
}

#[test]
fn host_settings_are_validated_like_core_settings() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    for (set, want) in [
        ("gap_max=-1", "gap_max must be finite and positive"),
        ("gap_max=inf", "gap_max must be finite and positive"),
        ("lookahead=-1", "lookahead must be finite and not negative"),
        (
            "align_max_dist=-1",
            "align_max_dist must be finite and not negative",
        ),
        ("align_tie=NaN", "align_tie must be finite and not negative"),
    ] {
        let (o, _) = score_json(&d, &[&"--set", &set]);
        assert_eq!(code(&o), 2, "{set}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{set}: {}", stderr(&o));
    }
}

// ---------------------------------------------------------------------------------------------
// Output that could be turned against its reader: CSV and terminal.

#[test]
fn csv_cells_are_quoted_and_neutralised() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    edit_results(&d, |doc| {
        let recs = doc["_checkpoint"]["records"].as_array_mut().unwrap();
        recs[0]["scenario_name"] = Value::String("=HYPERLINK(\"http://x\",\"a,b\")_1".into());
        recs[1]["status"] = Value::String("Failed\r- Agent\ncrashed".into());
        recs[2]["town_name"] = Value::String("@SUM(A1)".into());
        recs[3]["weather_id"] = Value::String("-2+3".into());
        recs[4]["scenario_name"] = Value::String("+cmd|' /C calc'!A0_1".into());
        recs[5]["town_name"] = Value::String("\tTown".into());
    });
    let (o, _) = score_json(&d, &[&"--format", &"csv"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let mut r = csv::ReaderBuilder::new().from_reader(&o.stdout[..]);
    let header = r.headers().unwrap().clone();
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    // Every row is whole: CR and LF inside a cell did not split it.
    assert_eq!(rows.len(), 9);
    assert!(rows.iter().all(|row| row.len() == header.len()));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    assert_eq!(
        &rows[0][col("scenario_type")],
        "'=HYPERLINK(\"http://x\",\"a,b\")"
    );
    // Control characters are escaped in CSV too (issue 29): the row stays one line.
    assert_eq!(&rows[1][col("status")], "Failed\\r- Agent\\ncrashed");
    assert_eq!(&rows[2][col("town")], "'@SUM(A1)");
    assert_eq!(&rows[3][col("weather_id")], "'-2+3");
    assert_eq!(&rows[4][col("scenario_type")], "'+cmd|' /C calc'!A0");
    assert_eq!(&rows[5][col("town")], "'\\tTown");
    // Numbers stay numbers, negative ones included (none are strings from the inputs).
    for row in &rows {
        let v = &row[col("score_route")];
        assert!(v.parse::<f64>().is_ok(), "{v}");
    }
    let raw = String::from_utf8(o.stdout).unwrap();
    assert!(
        !raw.contains('\r') && raw.lines().count() == 10,
        "a raw CR or LF in a cell"
    );
}

#[test]
fn strings_from_inputs_reach_the_terminal_escaped() {
    let tmp = tempfile::tempdir().unwrap();
    let d = demo(&tmp.path().join("run"));
    let evil = "RouteScenario_9_rep0\u{1b}[2K\r\u{1b}[1Aall fine";
    edit_results(&d, |doc| {
        let recs = doc["_checkpoint"]["records"].as_array_mut().unwrap();
        recs[0]["route_id"] = Value::String(evil.into());
        recs[0]["scores"] = Value::String("broken".into()); // an invalid record: printed
        recs[1]["scenario_name"] = Value::String("Evil\u{1b}]0;owned\u{7}_1".into());
    });
    let (o, _) = score_json(&d, &[&"--format", &"table"]);
    assert_ne!(code(&o), 1, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains('\u{1b}') && !err.contains('\r'), "{err:?}");
    assert!(
        err.contains("RouteScenario_9_rep0\\u{1b}[2K\\r\\u{1b}[1Aall fine"),
        "{err}"
    );
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(!out.contains('\u{1b}') && !out.contains('\u{7}'), "{out:?}");
    assert!(out.contains("Evil\\u{1b}]0;owned\\u{7}"), "{out}");
}
