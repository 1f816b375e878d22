//! `sds.watch`: the library's watch [`Session`] as a Python iterator of partial reports. Each
//! `next()` is one step of the session (it waits the interval, not before the first round, and
//! runs a round), its report converted as `sds.score`'s ([`crate::pyser`]); a round that catches
//! a results file half-written is retried after another interval, never raised. The session
//! stops once the route set is complete and a further round found nothing new (as `sds watch`),
//! or when the timeout has passed (after one last reading). Here only the wait and the
//! rendering: the session runs on a worker thread with the GIL released, and this thread
//! checks Python's signals every few ms (Ctrl-C raises `KeyboardInterrupt` within 50 ms of the
//! wait, or when the round under way ends).

use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use monitor_host::{Error, RoundOutcome};
use monitor_host::{Session, Step, Stop, Wake, WatchRequest};
use pyo3::exceptions::PyStopIteration;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{request_error, run_error, SdsError};
use crate::pyser::to_python;
use crate::score::{score_request, ScoreKwargs};

/// How often signals are checked while the session waits.
const SIGNAL_POLL: Duration = Duration::from_millis(50);
/// How often signals are checked while a round runs.
const ROUND_POLL: Duration = Duration::from_millis(5);

/// The keyword arguments of `sds.watch` beyond those of `sds.score`.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct WatchKwargs {
    interval: f64,
    timeout: Option<f64>,
    on_round: Option<Py<PyAny>>,
    /// K of the stalled-shard rule; None: the library's default.
    #[pyo3(default)]
    stall_factor: Option<f64>,
}

/// The iterator `sds.watch` returns (see the Python `sds.watch`).
#[pyclass(module = "sds._sds")]
pub struct Watch {
    session: Session,
    finished: bool,
    status: Option<Py<PyAny>>,
    /// Called with `(status, report)` for each report yielded (`sds.watch(on_round=...)`).
    on_round: Option<Py<PyAny>>,
}

/// Sleeps `d` (called with the GIL released) checking Python's signals; the signal, if one
/// came.
fn sleep_checking(d: Duration) -> Option<PyErr> {
    let until = Instant::now() + d;
    loop {
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            return Some(e);
        }
        let now = Instant::now();
        if now >= until {
            return None;
        }
        std::thread::sleep((until - now).min(SIGNAL_POLL));
    }
}

impl Watch {
    /// One step of the session on a worker thread (GIL released) while this thread checks for
    /// signals and does the session's waits; a signal during a round is raised once the round
    /// has ended (a round cannot be cut short), one during a wait at once.
    fn step(&mut self, py: Python<'_>) -> PyResult<Step> {
        let session = &mut self.session;
        let (result, signal) = py.detach(|| {
            let (asks, asked) = mpsc::channel::<Duration>();
            let (wakes, woken) = mpsc::channel::<Wake>();
            std::thread::scope(|s| {
                let run = s.spawn(move || {
                    let mut wait = |d: Duration| {
                        if asks.send(d).is_err() {
                            return Wake::Abort;
                        }
                        woken.recv().unwrap_or(Wake::Abort)
                    };
                    session.next(&mut wait)
                });
                let mut signal: Option<PyErr> = None;
                loop {
                    match asked.recv_timeout(ROUND_POLL) {
                        Ok(d) => {
                            if signal.is_none() {
                                signal = sleep_checking(d);
                            }
                            let wake = if signal.is_some() {
                                Wake::Abort
                            } else {
                                Wake::Elapsed
                            };
                            let _ = wakes.send(wake);
                        }
                        Err(mpsc::RecvTimeoutError::Timeout) => {
                            if signal.is_none() {
                                if let Err(e) = Python::attach(|py| py.check_signals()) {
                                    signal = Some(e);
                                }
                            }
                        }
                        Err(mpsc::RecvTimeoutError::Disconnected) => break,
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
            .map_err(|e: Error| run_error(&e))
    }

    /// Sets `stopped` on the last status dict.
    fn stop(&self, py: Python<'_>, why: Stop) -> PyResult<()> {
        if let Some(st) = &self.status {
            st.bind(py).set_item("stopped", why.name())?;
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
        loop {
            // An error no later round can mend raises here, as `sds.score` would.
            let (scored, status) = match self.step(py)? {
                Step::Round {
                    outcome: RoundOutcome::Retry { .. },
                    ..
                } => continue,
                // Complete and nothing new since the report yielded: the files are final.
                Step::Round {
                    stops: Some(stop), ..
                } => {
                    self.finished = true;
                    self.stop(py, stop)?;
                    return Err(PyStopIteration::new_err(()));
                }
                Step::Round {
                    outcome: RoundOutcome::Scored { scored, status, .. },
                    stops: None,
                } => (scored, status),
                Step::Stopped(end) => {
                    self.finished = true;
                    match end.reread {
                        // The final reading found something new: yielded, the last.
                        Some((scored, _)) if end.changed => (scored, end.status),
                        _ => {
                            self.stop(py, end.stop)?;
                            if let Some(reason) = end.stale {
                                // The last report yielded is not of the final files: say so.
                                let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
                                PyErr::warn(
                                    py,
                                    &category,
                                    &std::ffi::CString::new(format!(
                                        "sds.watch: {reason}: a results file was still \
                                         half-written at the timeout; the last report is not of \
                                         the final files (run sds.score once the file is \
                                         complete)"
                                    ))
                                    .unwrap_or_default(),
                                    1,
                                )?;
                            }
                            return Err(PyStopIteration::new_err(()));
                        }
                    }
                }
                Step::Aborted => {
                    self.finished = true;
                    return Err(PyStopIteration::new_err(()));
                }
            };
            let status = to_python(py, &status)?;
            self.status = Some(status.clone().unbind());
            let report = to_python(py, &scored.report)?;
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
/// `options`): the library's [`WatchRequest`], checked at once. Nothing is read until the first
/// `next()`.
#[pyfunction]
pub fn watch(results: Vec<PathBuf>, options: &Bound<'_, PyDict>) -> PyResult<Watch> {
    let kw: ScoreKwargs = options.extract()?;
    let score = score_request(results, options, &kw)?;
    let watch: WatchKwargs = options.extract()?;
    let request = WatchRequest {
        score,
        interval: watch.interval,
        timeout: watch.timeout,
        once: false,
        stall_factor: watch
            .stall_factor
            .unwrap_or(monitor_host::model::shard_stall::DEFAULT_FACTOR),
    };
    Ok(Watch {
        session: request.session().map_err(|e| request_error(&e))?,
        finished: false,
        status: None,
        on_round: watch.on_round,
    })
}
