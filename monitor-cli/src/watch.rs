//! `sds watch`: the report of an evaluation kept current while it runs (docs/USAGE.md §8), over the
//! library's [`monitor_host::Session`] (the rounds, the stop rule, the final reading);
//! this file is the command's spelling, its wait (signals) and its output. Rounds every `--interval` seconds; after each scored
//! round the report is written atomically to `-o` (the HTML page with a refresh tag while the
//! watch runs) and one status line is printed; the last round's report, written when the route
//! set is complete, on `--timeout`, or on Ctrl-C / SIGTERM, is `sds score`'s, byte for byte.

use std::time::{Duration, Instant};

use anyhow::Result;

use super::args::{ScoreArgs, WatchArgs};
use super::output;
use monitor_host::RequestError;
use monitor_host::{RoundOutcome, RoundStatus};
use monitor_host::{Step, Stop, Wake, WatchRequest};

/// Runs `sds watch`; returns the exit code (as `sds score`'s for the final report).
pub fn watch(args: &WatchArgs) -> Result<i32> {
    let a = &args.score;
    let Some(out) = a.output.clone() else {
        say!("sds: error: sds watch writes its report with -o FILE (standard output would repeat it every round)");
        return Ok(super::exit::USAGE);
    };
    let request = WatchRequest {
        score: super::request(a)?,
        interval: args.interval,
        timeout: args.timeout,
        once: args.once,
        stall_factor: args.stall_factor,
    };
    let mut session = match request.session() {
        Ok(s) => s,
        Err(RequestError::Interval { given, bound }) => {
            say!("sds: error: --interval {given}: {bound}");
            return Ok(super::exit::USAGE);
        }
        Err(RequestError::Timeout { given, bound }) => {
            say!("sds: error: --timeout {given}: {bound}");
            return Ok(super::exit::USAGE);
        }
        Err(RequestError::StallFactor { given }) => {
            say!(
                "sds: error: --stall-factor {given}: expected a number above 0 (default {})",
                monitor_host::model::shard_stall::DEFAULT_FACTOR
            );
            return Ok(super::exit::USAGE);
        }
        Err(e) => return Err(e.into()),
    };
    output::defer_signals();
    super::refuse_output_clashes(a)?;
    let mut stalled_seen = std::collections::HashSet::new();
    let mut last = None;
    // The round whose status line was printed last: a stop found by that round is said on that
    // line (`stopped`), not by printing the round again (issue 46 item 6).
    let mut printed = None;
    let end = loop {
        // An error no later round can mend (a mistyped --routes, duplicate ids...) stops here,
        // as `sds score` would.
        match session.next(&mut wait)? {
            Step::Round {
                outcome:
                    RoundOutcome::Retry {
                        reason,
                        failures,
                        status,
                    },
                ..
            } => {
                status_retry(args, &status, &reason, failures);
                printed = Some(status.round);
            }
            Step::Round {
                outcome: RoundOutcome::Scored { scored, status, .. },
                stops,
            } => {
                let status = RoundStatus {
                    stopped: stops.map(|s| s.name().into()),
                    ..status
                };
                status_line(args, &status);
                printed = Some(status.round);
                for s in monitor_host::model::shard_stall::newly_stalled(
                    &mut stalled_seen,
                    &status.stalled,
                ) {
                    say!("sds: warning: {}", s.message(args.stall_factor));
                }
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
            }
            Step::Stopped(end) => break end,
            // The command's wait never aborts.
            Step::Aborted => return Ok(1),
        }
    };
    if let Some((scored, status)) = end.reread {
        last = Some((scored.report, status.round));
    }
    let Some((report, round)) = last else {
        say!("sds: watch: no round could be scored; no report written");
        return Ok(1);
    };
    let inputs_read = request.score.inputs_read(&report);
    // As `sds score`: the traces, the figures, the tables, then the report, all or nothing.
    super::write_all(a, &report, &inputs_read, || {
        write_round(a, &out, &report, None)
    })?;
    for w in &report.warnings {
        say!("sds: {}", super::spelling::line(w));
    }
    // The final reading's line (a timeout, a signal); a round already printed with its stop is
    // not printed again.
    if args.status_json && printed != Some(end.status.round) {
        print_line(&end.status.json());
    }
    if let Some(reason) = end.stale {
        say!(
            "sds: error: {reason}: a results file was still half-written when the watch stopped; \
             {} holds the report of round {round}, not of the final files (run `sds score` once \
             the file is complete)",
            out.display()
        );
        return Ok(1);
    }
    let why = match end.stop {
        Stop::Complete => "the route set is complete",
        Stop::Once => "--once",
        Stop::Timeout => "--timeout",
        Stop::Interrupted => "interrupted",
    };
    say!("sds: watch stopped ({why}); final report {}", out.display());
    Ok(if report.has_problems() {
        super::exit::ROUTE_PROBLEMS
    } else {
        0
    })
}

/// The command's wait between rounds: sleeps in short steps, [`Wake::Stop`] on Ctrl-C or
/// SIGTERM.
fn wait(d: Duration) -> Wake {
    let until = Instant::now() + d;
    loop {
        if output::stop_requested() {
            return Wake::Stop;
        }
        let now = Instant::now();
        if now >= until {
            return Wake::Elapsed;
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
    live: Option<(f64, &RoundStatus)>,
) -> Result<()> {
    let inputs_read = super::request(a)?.inputs_read(report);
    super::write_report(a, Some(out), report, live, &inputs_read)
}

fn pct(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.1}"))
}

/// One line on standard error, never a panic (a closed pipe loses the line, not the report).
fn print_line(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// One status line (docs/USAGE.md §8): JSON (serde_json, valid whatever the route ids hold) or text.
fn status_line(args: &WatchArgs, s: &RoundStatus) {
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
        s.seconds_left.map_or_else(|| "?".into(), monitor_host::report::status::duration_text),
        s.rescored
    );
}

fn status_retry(args: &WatchArgs, s: &RoundStatus, reason: &str, failures: usize) {
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
