//! `sds score` for Python: the CLI's options parsed by the CLI's parser, the run scored by the
//! library, the report rendered by the CLI's JSON renderer.

use std::ffi::OsString;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use monitor_host::cli::{self, error_message, progress::Bar};
use monitor_host::report::json;
use monitor_host::{NoProgress, Progress};
use pyo3::prelude::*;

use crate::errors::{score_error, ConfigError, SdsError};

/// A [`Progress`] that forwards to a bar (or nothing) and is cancelled by a flag.
struct Cancellable<'a> {
    inner: &'a dyn Progress,
    cancel: &'a AtomicBool,
}

impl Progress for Cancellable<'_> {
    fn start(&self, routes: usize) {
        self.inner.start(routes);
    }
    fn route_done(&self) {
        self.inner.route_done();
    }
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// How often the calling thread looks for a signal (Ctrl-C) while the run is scored.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Scores a run given the arguments of `sds score` (without `sds score`), as the command does
/// ([`cli::score_report`]); returns the report as the JSON text `sds score --format json` writes. The GIL is released while scoring; a progress
/// bar is drawn on standard error when `progress` is true (and standard error is a terminal).
///
/// Ctrl-C: Python runs signal handlers on its main thread only, so the run is scored on a
/// worker thread while the calling thread checks for signals every 50 ms; on one, the run stops
/// between routes (the routes being scored finish) and the signal's exception
/// (`KeyboardInterrupt`) is raised.
#[pyfunction]
#[pyo3(signature = (args, progress=false))]
pub fn score_json(py: Python<'_>, args: Vec<OsString>, progress: bool) -> PyResult<String> {
    let args = cli::parse_score_args(args)
        .map_err(|e| ConfigError::new_err(e.render().to_string().trim_end().to_string()))?;
    let cancel = AtomicBool::new(false);
    let (scored, signal) = py.detach(|| {
        let bar = progress.then(Bar::new);
        let inner: &dyn Progress = match &bar {
            Some(b) => b,
            None => &NoProgress,
        };
        let watched = Cancellable {
            inner,
            cancel: &cancel,
        };
        let (r, signal) = std::thread::scope(|s| {
            let run = s.spawn(|| cli::score_report(&args, &watched));
            let mut signal = None;
            while !run.is_finished() {
                std::thread::sleep(SIGNAL_POLL);
                if signal.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        cancel.store(true, Ordering::Relaxed);
                        signal = Some(e);
                    }
                }
            }
            let r = run
                .join()
                .unwrap_or_else(|_| Err(anyhow::anyhow!("the scoring thread panicked")));
            (r, signal)
        });
        if let Some(b) = bar {
            b.finish();
        }
        (r, signal)
    });
    if let Some(e) = signal {
        return Err(e);
    }
    let scored = scored.map_err(|e| score_error(&e))?;
    let report = scored.report;
    let bytes = json::json(&report).map_err(|e| SdsError::new_err(error_message(&e)))?;
    String::from_utf8(bytes).map_err(|e| SdsError::new_err(e.to_string()))
}

/// The long names of the options `sds score` has in this build.
#[pyfunction]
pub fn score_options() -> Vec<String> {
    cli::score_options()
}
