//! `sds.watch`: the library's [`Watcher`] as a Python iterator of partial reports. Each
//! `next()` sleeps the interval (not before the first round), runs one round and returns its
//! report, converted as `sds.score`'s ([`crate::pyser`]); a round that catches a results file
//! half-written is retried after another interval, never raised. The iterator stops once the
//! route set is complete and a further round found nothing new (as `sds watch`), or when the
//! timeout has passed (after one last round). The GIL is released while sleeping and scoring;
//! Python signals are checked every 50 ms (Ctrl-C raises `KeyboardInterrupt`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use monitor_host::{Inputs, RoundOutcome, Settings, Watcher};
use pyo3::exceptions::PyStopIteration;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{run_error, ConfigError, SdsError};
use crate::options::RunKwargs;
use crate::pyser::to_python;
use crate::score::breakdown;

/// How often signals are checked while sleeping or scoring.
const SIGNAL_POLL: Duration = Duration::from_millis(50);
/// Retries of the last round after the timeout when it finds a file half-written (as
/// `sds watch`), this far apart.
const LAST_TRIES: usize = 5;
const LAST_PAUSE: Duration = Duration::from_millis(200);

/// The keyword arguments of `sds.watch` beyond the shared ones ([`RunKwargs`]).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct WatchKwargs {
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    group_by: Option<String>,
    labels: Option<PathBuf>,
    interval: f64,
    timeout: Option<f64>,
    on_round: Option<Py<PyAny>>,
}

/// The iterator `sds.watch` returns (see the Python `sds.watch`).
#[pyclass(module = "sds._sds")]
pub struct Watch {
    watcher: Watcher,
    interval: Duration,
    timeout: Option<Duration>,
    start: Option<Instant>,
    finished: bool,
    status: Option<Py<PyAny>>,
    /// Called with `(status, report)` for each report yielded (`sds.watch(on_round=...)`).
    on_round: Option<Py<PyAny>>,
}

/// Why a sleep ended early.
enum Woke {
    Interval,
    Timeout,
    Signal(PyErr),
}

impl Watch {
    /// Sleeps until `until` (GIL released), or less: on the timeout, or on a Python signal.
    fn sleep_until(&self, py: Python<'_>, until: Instant) -> Woke {
        let (start, timeout) = (self.start, self.timeout);
        py.detach(|| loop {
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                return Woke::Signal(e);
            }
            let now = Instant::now();
            if let (Some(s), Some(t)) = (start, timeout) {
                if now.duration_since(s) >= t {
                    return Woke::Timeout;
                }
            }
            if now >= until {
                return Woke::Interval;
            }
            std::thread::sleep((until - now).min(SIGNAL_POLL));
        })
    }

    /// One round on a worker thread (GIL released) while this thread checks for signals; a
    /// signal is raised once the round has ended (a round cannot be cut short).
    fn round(&mut self, py: Python<'_>) -> PyResult<RoundOutcome> {
        let watcher = &mut self.watcher;
        let (result, signal) = py.detach(|| {
            std::thread::scope(|s| {
                let run = s.spawn(|| watcher.round());
                let mut signal = None;
                while !run.is_finished() {
                    std::thread::sleep(Duration::from_millis(5).min(SIGNAL_POLL));
                    if signal.is_none() {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            signal = Some(e);
                        }
                    }
                }
                (run.join(), signal)
            })
        });
        if let Some(e) = signal {
            return Err(e);
        }
        result
            .map_err(|_| SdsError::new_err("the watch round's thread panicked"))?
            .map_err(|e| run_error(&e))
    }

    /// Sets `stopped` on the last status dict.
    fn stop(&self, py: Python<'_>, why: &str) -> PyResult<()> {
        if let Some(st) = &self.status {
            st.bind(py).set_item("stopped", why)?;
        }
        Ok(())
    }
}

#[pymethods]
impl Watch {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        if self.finished {
            return Err(PyStopIteration::new_err(()));
        }
        let first = self.start.is_none();
        let start = *self.start.get_or_insert_with(Instant::now);
        let mut wait = !first;
        loop {
            let mut last = false;
            if wait {
                match self.sleep_until(py, Instant::now() + self.interval) {
                    Woke::Interval => {}
                    Woke::Timeout => last = true,
                    Woke::Signal(e) => return Err(e),
                }
            } else if self.timeout.is_some_and(|t| start.elapsed() >= t) {
                last = true;
            }
            wait = true;
            // After the timeout: one last round, retried a few times on a half-written file.
            // An error no later round can mend raises here, as `sds.score` would.
            let tries = if last { LAST_TRIES } else { 1 };
            let mut scored = None;
            let mut stale = None;
            for i in 0..tries {
                if i > 0 {
                    py.detach(|| std::thread::sleep(LAST_PAUSE));
                }
                match self.round(py)? {
                    RoundOutcome::Retry { reason, .. } => stale = Some(reason),
                    RoundOutcome::Scored {
                        scored: s,
                        changed,
                        status,
                        ..
                    } => {
                        scored = Some((s, changed, status));
                        break;
                    }
                }
            }
            let Some((s, changed, mut status)) = scored else {
                if last {
                    self.finished = true;
                    self.stop(py, "timeout")?;
                    if let Some(reason) = stale {
                        // The last report yielded is not of the final files: say so.
                        let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                        PyErr::warn(
                            py,
                            &category,
                            &std::ffi::CString::new(format!(
                                "sds.watch: {reason}: a results file was still half-written at \
                                 the timeout; the last report is not of the final files (run \
                                 sds.score once the file is complete)"
                            ))
                            .unwrap_or_default(),
                            1,
                        )?;
                    }
                    return Err(PyStopIteration::new_err(()));
                }
                continue;
            };
            let p = self.watcher.progress(&s.report);
            // Complete and nothing new since the report yielded: the files are final.
            if (p.complete && !changed && !first) || (last && !changed) {
                self.finished = true;
                self.stop(py, if last { "timeout" } else { "complete" })?;
                return Err(PyStopIteration::new_err(()));
            }
            if last {
                status.stopped = Some("timeout".into());
                self.finished = true;
            }
            let status = to_python(py, &status)?;
            self.status = Some(status.clone().unbind());
            let report = to_python(py, &s.report)?;
            if let Some(f) = &self.on_round {
                f.call1(py, (status, report.clone()))?;
            }
            return Ok(report);
        }
    }

    /// The figures of the round that made the last report (None before the first).
    #[getter]
    fn status(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.status.as_ref().map(|s| s.clone_ref(py))
    }

    /// True once the iterator has stopped.
    #[getter]
    fn finished(&self) -> bool {
        self.finished
    }
}

/// A watch of a run (see the Python `sds.watch`, which passes its keyword arguments as the dict
/// `options`). Nothing is read until the first `next()`.
#[pyfunction]
pub fn watch(results: Vec<PathBuf>, options: &Bound<'_, PyDict>) -> PyResult<Watch> {
    let settings: Settings = options.extract::<RunKwargs<'_>>()?.settings()?;
    let kw: WatchKwargs = options.extract()?;
    let interval = monitor_host::watch::interval(kw.interval)
        .map_err(|bound| ConfigError::new_err(format!("interval={}: {bound}", kw.interval)))?;
    let timeout = kw
        .timeout
        .map(|t| {
            monitor_host::watch::timeout(t)
                .map_err(|bound| ConfigError::new_err(format!("timeout={t}: {bound}")))
        })
        .transpose()?;
    let (by, files) = breakdown(kw.group_by.as_deref(), kw.labels)?;
    let inputs = Inputs {
        results,
        telemetry: kw.telemetry,
        route_xml: kw.routes,
        maps: kw.maps,
    };
    Ok(Watch {
        watcher: Watcher::new(inputs, settings, files, by, monitor_host::watch::RACY),
        interval,
        timeout,
        start: None,
        finished: false,
        status: None,
        on_round: kw.on_round,
    })
}
