//! `sds watch`: the report of an evaluation kept current while it runs (spec §12), over the
//! library's [`crate::watch::Watcher`]. Rounds every `--interval` seconds; after each scored
//! round the report is written atomically to `-o` (the HTML page with a refresh tag while the
//! watch runs) and one status line is printed; the last round's report, written when the route
//! set is complete, on `--timeout`, or on Ctrl-C / SIGTERM, is `sds score`'s, byte for byte.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;

use super::args::{Format, ScoreArgs};
use super::output::{self, write_output};
use crate::watch::{RoundOutcome, Watcher};

/// How recent a telemetry file may be and still be trusted unchanged by its stamp.
const RACY: Duration = Duration::from_secs(1);

/// Arguments of `sds watch`.
#[derive(Debug, clap::Args)]
pub struct WatchArgs {
    /// The inputs and options of `sds score` (`-o` is required).
    #[command(flatten)]
    pub score: ScoreArgs,
    /// Seconds between rounds (fractions allowed).
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS")]
    pub interval: f64,
    /// One round, then the final report.
    #[arg(long)]
    pub once: bool,
    /// Stop after this many seconds (with the final report).
    #[arg(long, value_name = "SECONDS")]
    pub timeout: Option<f64>,
    /// Print each round's status as one JSON object per line (standard error) instead of text.
    #[arg(long)]
    pub status_json: bool,
}

/// Why the watch stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    Complete,
    Once,
    Timeout,
    Signal,
}

/// Runs `sds watch`; returns the exit code (as `sds score`'s for the final report).
pub fn watch(args: &WatchArgs) -> Result<i32> {
    let a = &args.score;
    let Some(out) = a.output.clone() else {
        say!("sds: error: sds watch writes its report with -o FILE (standard output would repeat it every round)");
        return Ok(super::EXIT_USAGE);
    };
    if !(args.interval.is_finite() && args.interval > 0.0) {
        say!(
            "sds: error: --interval {}: a number of seconds above 0",
            args.interval
        );
        return Ok(super::EXIT_USAGE);
    }
    let settings = super::settings(a)?;
    if let Some(bad) = a
        .infractions
        .iter()
        .find(|l| !crate::input::record::KNOWN_LISTS.contains(&l.as_str()))
    {
        return Err(super::UnknownInfraction(bad.clone()).into());
    }
    let tables = super::style(a.format).is_some();
    let by = match (a.group_by, tables) {
        (Some(g), _) => Some(super::group_by(g)),
        (None, true) => Some(crate::aggregate::groups::GroupBy::Scenario),
        (None, false) => None,
    };
    output::defer_signals();
    let mut watcher = Watcher::new(super::inputs(a), settings, super::label_files(a), by, RACY);
    let start = Instant::now();
    let interval = Duration::from_secs_f64(args.interval);
    let timeout = args.timeout.map(|t| Duration::from_secs_f64(t.max(0.0)));
    let mut round = 0usize;
    let mut last = None;
    let stop = loop {
        round += 1;
        let began = Instant::now();
        let outcome = watcher.round()?;
        let took = began.elapsed();
        let complete = match outcome {
            RoundOutcome::Retry { reason, failures } => {
                status_retry(args, round, &reason, failures);
                false
            }
            RoundOutcome::Scored {
                scored,
                cache,
                changed,
            } => {
                let p = watcher.progress(&scored.report);
                status(args, round, &p, &scored.report, &cache, changed, took);
                write_round(a, &out, &scored.report, Some(args.interval))?;
                last = Some(scored.report);
                // Complete, and one more round that found nothing new: the files are final.
                p.complete && !changed
            }
        };
        if complete {
            break Stop::Complete;
        }
        if args.once {
            break Stop::Once;
        }
        match sleep(interval, start, timeout) {
            Some(stop) => break stop,
            None => continue,
        }
    };
    // After a signal or a timeout the inputs are read once more (they may have changed since
    // the last round), retried a few times on a half-written file; else the last good report
    // stands.
    if matches!(stop, Stop::Timeout | Stop::Signal) {
        for _ in 0..5 {
            match watcher.round()? {
                RoundOutcome::Scored { scored, .. } => {
                    last = Some(scored.report);
                    break;
                }
                RoundOutcome::Retry { .. } => std::thread::sleep(Duration::from_millis(200)),
            }
        }
    }
    let Some(report) = last else {
        say!("sds: watch: no round could be scored; no report written");
        return Ok(1);
    };
    let mut inputs_read = report.files_read.clone();
    inputs_read.extend(super::label_files(a).files().cloned());
    if let Some(dir) = &a.traces {
        let n = output::write_traces(dir, &report, &inputs_read)?;
        say!("sds: wrote {n} collision trace(s) to {}", dir.display());
    }
    write_round(a, &out, &report, None)?;
    // The routes to run again, from the final report (v1.4 §13).
    if let Some(file) = &a.rerun_list {
        super::write_rerun_list(file, &report, &inputs_read)?;
    }
    for w in &report.warnings {
        say!("sds: warning: {w}");
    }
    let why = match stop {
        Stop::Complete => "the route set is complete",
        Stop::Once => "--once",
        Stop::Timeout => "--timeout",
        Stop::Signal => "interrupted",
    };
    say!("sds: watch stopped ({why}); final report {}", out.display());
    Ok(if report.has_problems() {
        super::EXIT_ROUTE_PROBLEMS
    } else {
        0
    })
}

/// Sleeps one interval in short steps; `Some` when the watch must stop.
fn sleep(interval: Duration, start: Instant, timeout: Option<Duration>) -> Option<Stop> {
    let until = Instant::now() + interval;
    loop {
        if output::stop_requested() {
            return Some(Stop::Signal);
        }
        if timeout.is_some_and(|t| start.elapsed() >= t) {
            return Some(Stop::Timeout);
        }
        let now = Instant::now();
        if now >= until {
            return None;
        }
        std::thread::sleep((until - now).min(Duration::from_millis(50)));
    }
}

/// Writes a round's report; `refresh`: the HTML page reloads itself every so many seconds
/// (while the watch runs; never in the final report).
fn write_round(
    a: &ScoreArgs,
    out: &std::path::Path,
    report: &crate::Report,
    refresh: Option<f64>,
) -> Result<()> {
    let mut bytes = super::render(a, report)?;
    if let (Format::Html, Some(secs)) = (a.format, refresh) {
        bytes = with_refresh(&bytes, secs);
    }
    let mut inputs: Vec<PathBuf> = report.files_read.clone();
    inputs.extend(super::label_files(a).files().cloned());
    write_output(Some(out), &bytes, &inputs)
}

/// The page with `<meta http-equiv="refresh">` after its `<head>` tag.
fn with_refresh(page: &[u8], secs: f64) -> Vec<u8> {
    let text = String::from_utf8_lossy(page);
    let tag = format!(
        "<meta http-equiv=\"refresh\" content=\"{}\">",
        secs.ceil().max(1.0)
    );
    match text.find("<head>") {
        Some(i) => {
            let at = i + "<head>".len();
            format!("{}{tag}{}", &text[..at], &text[at..]).into_bytes()
        }
        None => format!("{tag}{text}").into_bytes(),
    }
}

fn pct(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.1}"))
}

fn duration(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    match (s / 3600, (s % 3600) / 60) {
        (0, m) => format!("{m}m"),
        (h, m) => format!("{h}h{m:02}m"),
    }
}

/// One status line (spec §12).
fn status(
    args: &WatchArgs,
    round: usize,
    p: &crate::watch::WatchStatus,
    report: &crate::Report,
    cache: &crate::watch::CacheRound,
    changed: bool,
    took: Duration,
) {
    // The last route: the last changed one in report order, else the last with a record.
    let last = report
        .routes
        .iter()
        .rev()
        .find(|r| {
            r.route_id
                .as_ref()
                .is_some_and(|id| cache.changed.contains(id))
        })
        .or_else(|| {
            report
                .routes
                .iter()
                .rev()
                .find(|r| !matches!(r.state, crate::RouteState::Missing))
        });
    let od = (p.over_done.driving_score, p.over_done.sds);
    let on = (p.over_n.driving_score, p.over_n.sds);
    if args.status_json {
        let v = serde_json::json!({
            "round": round,
            "done": p.done,
            "n": p.n,
            "ds_done": od.0, "ds_n": on.0,
            "sds_done": od.1, "sds_n": on.1,
            "last_route": last.and_then(|r| r.route_id.clone()),
            "last_state": last.map(|r| r.state.to_string()),
            "last_ds": last.and_then(|r| r.score_composed),
            "seconds_left": p.seconds_left,
            "rescored": cache.rescored,
            "reused": cache.reused,
            "changed": changed,
            "complete": p.complete,
            "round_ms": took.as_secs_f64() * 1e3,
        });
        say!("{v}");
        return;
    }
    let last = last.map_or_else(
        || "-".to_string(),
        |r| {
            format!(
                "{} {} DS {}",
                r.route_id.as_deref().unwrap_or("<no route_id>"),
                r.state,
                pct(r.score_composed)
            )
        },
    );
    say!(
        "sds watch #{round}: {}/{} routes | DS {} done, {} of N | SDS {} done, {} of N | last {last} | {} left | rescored {}",
        p.done,
        p.n,
        pct(od.0),
        pct(on.0),
        pct(od.1),
        pct(on.1),
        p.seconds_left.map_or_else(|| "?".into(), duration),
        cache.rescored
    );
}

fn status_retry(args: &WatchArgs, round: usize, reason: &str, failures: usize) {
    if args.status_json {
        say!(
            "{}",
            serde_json::json!({"round": round, "retry": reason, "failures": failures})
        );
    } else if failures >= 3 {
        say!("sds: warning: watch round {round}: {reason} ({failures} rounds in a row; retrying)");
    } else {
        say!("sds watch #{round}: {reason}; retried next round");
    }
}
