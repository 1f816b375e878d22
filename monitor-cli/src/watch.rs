//! `sds watch`: the report of an evaluation kept current while it runs (spec §12), over the
//! library's [`monitor_host::watch::Watcher`]. Rounds every `--interval` seconds; after each scored
//! round the report is written atomically to `-o` (the HTML page with a refresh tag while the
//! watch runs) and one status line is printed; the last round's report, written when the route
//! set is complete, on `--timeout`, or on Ctrl-C / SIGTERM, is `sds score`'s, byte for byte.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Result;

use super::args::{Format, ScoreArgs, WatchArgs};
use super::output::{self, write_output};
use monitor_host::watch::{RoundOutcome, StatusLine, Watcher, RACY};

/// Why the watch stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    Complete,
    Once,
    Timeout,
    Signal,
}

impl Stop {
    /// The status line's `stopped`.
    fn name(self) -> &'static str {
        match self {
            Stop::Complete => "complete",
            Stop::Once => "once",
            Stop::Timeout => "timeout",
            Stop::Signal => "interrupted",
        }
    }
}

/// Runs `sds watch`; returns the exit code (as `sds score`'s for the final report).
pub fn watch(args: &WatchArgs) -> Result<i32> {
    let a = &args.score;
    let Some(out) = a.output.clone() else {
        say!("sds: error: sds watch writes its report with -o FILE (standard output would repeat it every round)");
        return Ok(super::exit::USAGE);
    };
    let interval = match monitor_host::watch::interval(args.interval) {
        Ok(d) => d,
        Err(bound) => {
            say!("sds: error: --interval {}: {bound}", args.interval);
            return Ok(super::exit::USAGE);
        }
    };
    let timeout = match args.timeout.map(monitor_host::watch::timeout).transpose() {
        Ok(t) => t,
        Err(bound) => {
            say!(
                "sds: error: --timeout {}: {bound}",
                args.timeout.unwrap_or_default()
            );
            return Ok(super::exit::USAGE);
        }
    };
    let settings = super::settings(a)?;
    if let Some(bad) = a
        .infractions
        .iter()
        .find(|l| !monitor_host::input::record::KNOWN_LISTS.contains(&l.as_str()))
    {
        return Err(super::UnknownInfraction(bad.clone()).into());
    }
    let tables = super::style(a.format).is_some();
    let by = match (a.group_by, tables) {
        (Some(g), _) => Some(super::group_by(g)),
        (None, true) => Some(monitor_host::aggregate::groups::GroupBy::Scenario),
        (None, false) => None,
    };
    output::defer_signals();
    super::refuse_output_clashes(a)?;
    let mut watcher = Watcher::new(super::inputs(a), settings, super::label_files(a), by, RACY);
    let start = Instant::now();
    let mut last = None;
    let stop = loop {
        // An error no later round can mend (a mistyped --routes, duplicate ids...) stops here,
        // as `sds score` would.
        let complete = match watcher.round()? {
            RoundOutcome::Retry {
                reason,
                failures,
                status,
            } => {
                status_retry(args, &status, &reason, failures);
                false
            }
            RoundOutcome::Scored {
                scored,
                changed,
                status,
                ..
            } => {
                status_line(args, &status);
                // A live round that cannot be written is retried next round; only the final
                // write is fatal.
                if let Err(e) = write_round(a, &out, &scored.report, Some((args.interval, &status)))
                {
                    say!(
                        "sds: warning: watch round {}: {}; written again next round",
                        status.round,
                        super::error_message(&*e)
                    );
                }
                last = Some((scored.report, status.round));
                // Complete, and one more round that found nothing new: the files are final.
                status.complete && !changed
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
    // the last round), retried a few times on a half-written file.
    let mut stale = None;
    if matches!(stop, Stop::Timeout | Stop::Signal) {
        for _ in 0..5 {
            match watcher.round()? {
                RoundOutcome::Scored { scored, status, .. } => {
                    last = Some((scored.report, status.round));
                    stale = None;
                    break;
                }
                RoundOutcome::Retry { reason, .. } => {
                    stale = Some(reason);
                    std::thread::sleep(Duration::from_millis(200));
                }
            }
        }
    }
    let Some((report, round)) = last else {
        say!("sds: watch: no round could be scored; no report written");
        return Ok(1);
    };
    let mut inputs_read = report.files_read.clone();
    inputs_read.extend(super::label_files(a).files().cloned());
    // As `sds score`: the traces, the figures, the tables, then the report, all or nothing.
    super::write_all(a, &report, &inputs_read, || {
        write_round(a, &out, &report, None)
    })?;
    for w in &report.warnings {
        say!("sds: warning: {w}");
    }
    if args.status_json {
        let end = monitor_host::watch::StatusLine {
            stopped: Some(stop.name().into()),
            ..watcher.last_status().clone()
        };
        print_line(&end.json());
    }
    if let Some(reason) = stale {
        say!(
            "sds: error: {reason}: a results file was still half-written when the watch stopped; \
             {} holds the report of round {round}, not of the final files (run `sds score` once \
             the file is complete)",
            out.display()
        );
        return Ok(1);
    }
    let why = match stop {
        Stop::Complete => "the route set is complete",
        Stop::Once => "--once",
        Stop::Timeout => "--timeout",
        Stop::Signal => "interrupted",
    };
    say!("sds: watch stopped ({why}); final report {}", out.display());
    Ok(if report.has_problems() {
        super::exit::ROUTE_PROBLEMS
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

/// Writes a round's report; `live`: while the watch runs, the HTML page reloads itself every
/// so many seconds and says that it is live (never in the final report).
fn write_round(
    a: &ScoreArgs,
    out: &std::path::Path,
    report: &monitor_host::Report,
    live: Option<(f64, &StatusLine)>,
) -> Result<()> {
    let mut bytes = super::render(a, report)?;
    if let (Format::Html, Some((secs, status))) = (a.format, live) {
        bytes =
            monitor_host::report::html::live_page(&String::from_utf8_lossy(&bytes), status, secs)
                .into_bytes();
    }
    let mut inputs: Vec<PathBuf> = report.files_read.clone();
    inputs.extend(super::label_files(a).files().cloned());
    write_output(Some(out), &bytes, &inputs)
}

fn pct(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.1}"))
}

/// One line on standard error, never a panic (a closed pipe loses the line, not the report).
fn print_line(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// One status line (spec §12): JSON (serde_json, valid whatever the route ids hold) or text.
fn status_line(args: &WatchArgs, s: &StatusLine) {
    if args.status_json {
        print_line(&s.json());
        return;
    }
    let last = s.last_route.as_ref().map_or_else(
        || "-".to_string(),
        |id| {
            format!(
                "{id} {} DS {}",
                s.last_state.as_deref().unwrap_or("-"),
                pct(s.last_ds)
            )
        },
    );
    say!(
        "sds watch #{}: {}/{} routes | DS {} done, {} of N | SDS {} done, {} of N | last {last} | {} left | rescored {}",
        s.round,
        s.done,
        s.n,
        pct(s.ds_done),
        pct(s.ds_n),
        pct(s.sds_done),
        pct(s.sds_n),
        s.seconds_left.map_or_else(|| "?".into(), monitor_host::watch::duration_text),
        s.rescored
    );
}

fn status_retry(args: &WatchArgs, s: &StatusLine, reason: &str, failures: usize) {
    let round = s.round;
    if args.status_json {
        print_line(&s.json());
    } else if failures >= 3 {
        say!(
            "sds: warning: watch round {round}: {reason} ({failures} rounds in a row; retrying; \
             the figures are those of the last good reading)"
        );
    } else {
        say!("sds watch #{round}: {reason}; retried next round");
    }
}
