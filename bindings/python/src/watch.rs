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

use crate::errors::{request_error, run_error, SdsError};
use crate::options::{Overrides, Paths, Shared, Strings};
use crate::pyser::to_python;
use crate::score::Run;

/// How often signals are checked while the session waits.
const SIGNAL_POLL: Duration = Duration::from_millis(50);
/// How often signals are checked while a round runs.
const ROUND_POLL: Duration = Duration::from_millis(5);

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

/// Watches an evaluation while it runs; returns an iterator of partial reports.
///
/// The library's watch of ``sds watch`` (no command line in between), one round per
/// ``next()``: the inputs read again, each route replayed again only when its record or its
/// telemetry changed, the report made. Each report is a dict of the same shape as
/// :func:`sds.score`'s (routes without a record yet are ``missing``); the figures of the round
/// that made it are in the iterator's ``status`` dict:
///
/// - ``round``: the round's number (rounds retried on a half-written file count too);
///   ``time``: when it ran (UTC, ``2026-11-27T17:45:33Z``);
/// - ``done``, ``n``: routes with a record, and the benchmark's size N;
/// - ``ds_done``, ``sds_done``: DS and SDS over the routes done; ``ds_n``, ``sds_n``: over N,
///   the routes not done counting 0 (the two "so far" figures of the status line);
/// - ``last_route``, ``last_state``, ``last_ds``: the last route replayed (else the last with a
///   record), its state and DS;
/// - ``crashes``: routes whose record says the run broke, the rerun list's classes but
///   ``missing`` and ``timeout`` (a ``Failed - TickRuntime`` route is not a crash);
/// - ``complete``: every route of the set has a record (a route XML or ``expected_routes``
///   gives the set; without one, every checkpoint's ``progress`` says done);
/// - ``seconds_left``: the routes' mean ``meta.duration_system`` times the routes left, or None
///   (no usable duration: negative ones are left out; or every shard done with routes left);
/// - ``changed``, ``rescored``, ``reused``, ``rescored_routes``: whether anything changed since
///   the previous report, the routes replayed (and their ids) and those taken from the cache;
/// - ``retries``: rounds since the previous report that caught a results file half-written
///   (retried, never raised); ``round_ms``: the round's time;
/// - ``stopped``: None, or why the iterator stopped (``"complete"``, ``"timeout"``).
///
/// These are the fields of ``sds watch --status-json``, one schema for both.
///
/// The first ``next()`` scores at once; each later one first sleeps ``interval`` seconds (and
/// again after a retried round). The iterator stops once the route set is complete and one
/// more round found nothing new, or when ``timeout`` seconds have passed since the first
/// ``next()`` (after one last round, yielded if it found something new). The last report is
/// then :func:`sds.score`'s over the same files. The GIL is released while sleeping and
/// scoring; Ctrl-C (any Python signal) raises from ``next()`` within 50 ms of the sleep, or
/// when the round under way ends.
///
/// Args:
///     results: Evaluator results as for :func:`sds.score`: a checkpoint the evaluator
///         rewrites in place, a folder of shard checkpoints or of per-route folders, or a list.
///     telemetry, routes, maps: As for :func:`sds.score`.
///     interval: Seconds between rounds (fractions allowed; ``--interval``).
///     timeout: Stop after this many seconds (``--timeout``); None: until complete.
///     profile, duplicates, expected_routes, allow_missing_telemetry, settings, group_by,
///         labels, jobs, protocols, route_subset: As for :func:`sds.score`.
///     on_round: Called with ``(status, report)`` for each report the iterator yields, before
///         it is yielded (an exception it raises comes out of ``next()``); e.g. a
///         :class:`sds.Tracker`'s ``on_round``, which logs the round to W&B, TensorBoard or
///         MLflow.
///     stall_factor: K of the stalled-shard rule (``--stall-factor``): a shard is said stalled
///         after K times its median route time without a new record; None: the default, 5.
///
/// Returns:
///     The iterator (its ``status`` property: the figures above; ``finished``: True once it
///     stopped).
///
/// Raises:
///     ConfigError: An invalid option, as :func:`sds.score`, an ``interval`` not in
///         (0, 86400] or a ``timeout`` not in [0, 31536000] seconds (at once). From ``next()``,
///         at once, the errors no later write of the evaluator can mend, as :func:`sds.score`
///         raises them: an invalid setting, route XML or label file (a missing one, a null
///         label), duplicate route ids, a ``telemetry`` or ``maps`` folder that does not exist,
///         a results file that is not JSON from its first byte. A results file that ends early,
///         shrank or is not there yet is retried, never raised; one still half-written at the
///         timeout gives a ``RuntimeWarning``.
///
/// Example:
///     >>> w = sds.watch("eval/results.json", telemetry="eval/", routes="bench2drive220.xml",
///     ...               interval=30)  # doctest: +SKIP
///     >>> for report in w:  # doctest: +SKIP
///     ...     s = w.status
///     ...     print(f"{s['done']}/{s['n']} routes, SDS {s['sds_done']} so far")
///     >>> report == sds.score("eval/results.json", telemetry="eval/",
///     ...                     routes="bench2drive220.xml")  # doctest: +SKIP
///     True
#[pyfunction]
#[pyo3(signature = (results, *, telemetry=None, routes=None, maps=None, interval=10.0,
                    timeout=None, profile="physical", duplicates="error", expected_routes=None,
                    allow_missing_telemetry=false, settings=None, group_by=None, labels=None,
                    jobs=None, protocols=None, on_round=None, route_subset=None,
                    stall_factor=None))]
#[allow(clippy::too_many_arguments)]
pub fn watch(
    results: Paths,
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    interval: f64,
    timeout: Option<f64>,
    profile: &str,
    duplicates: &str,
    expected_routes: Option<usize>,
    allow_missing_telemetry: bool,
    settings: Option<Overrides>,
    group_by: Option<&str>,
    labels: Option<PathBuf>,
    jobs: Option<usize>,
    protocols: Option<Strings>,
    on_round: Option<Py<PyAny>>,
    route_subset: Option<&str>,
    stall_factor: Option<f64>,
) -> PyResult<Watch> {
    let settings = Shared {
        profile,
        duplicates: Some(duplicates),
        expected_routes,
        allow_missing_telemetry,
        settings,
        jobs,
        protocols,
        route_subset,
    }
    .request()?;
    let score = Run {
        results: Some(results),
        telemetry,
        routes,
        maps,
        group_by,
        labels,
        mcap: None,
        topics: None,
    }
    .request(settings)?;
    let request = WatchRequest {
        score,
        interval,
        timeout,
        once: false,
        stall_factor: stall_factor.unwrap_or(monitor_host::model::shard_stall::DEFAULT_FACTOR),
    };
    Ok(Watch {
        session: request.session().map_err(|e| request_error(&e))?,
        finished: false,
        status: None,
        on_round,
    })
}
