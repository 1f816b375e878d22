//! `sds.watch`: the library's [`Watcher`] as a Python iterator of partial reports. Each
//! `next()` sleeps the interval (not before the first round), runs one round and returns its
//! report, converted as `sds.score`'s ([`crate::pyser`]); a round that catches a results file
//! half-written is retried after another interval, never raised. The iterator stops once the
//! route set is complete and a further round found nothing new (as `sds watch`), or when the
//! timeout has passed (after one last round). The GIL is released while sleeping and scoring;
//! Python signals are checked every 50 ms (Ctrl-C raises `KeyboardInterrupt`).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use monitor_host::watch::WatchStatus;
use monitor_host::{Inputs, RoundOutcome, Settings, Watcher};
use pyo3::exceptions::PyStopIteration;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{run_error, ConfigError, SdsError};
use crate::options::RunKwargs;
use crate::pyser::to_python;
use crate::score::breakdown;

/// How recent a telemetry file may be and still be trusted unchanged (as `sds watch`).
const RACY: Duration = Duration::from_secs(1);
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
}

/// The iterator `sds.watch` returns (see the Python `sds.watch`).
#[pyclass(module = "sds._sds")]
pub struct Watch {
    watcher: Watcher,
    interval: Duration,
    timeout: Option<Duration>,
    start: Option<Instant>,
    round: usize,
    retries: usize,
    finished: bool,
    status: Option<Py<PyDict>>,
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
    fn round(&mut self, py: Python<'_>) -> PyResult<(RoundOutcome, Duration)> {
        let watcher = &mut self.watcher;
        let (result, signal) = py.detach(|| {
            std::thread::scope(|s| {
                let run = s.spawn(|| {
                    let began = Instant::now();
                    watcher.round().map(|o| (o, began.elapsed()))
                });
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
        self.round += 1;
        result
            .map_err(|_| SdsError::new_err("the watch round's thread panicked"))?
            .map_err(|e| run_error(&e))
    }

    /// The round's figures as the `status` dict.
    #[allow(clippy::too_many_arguments)]
    fn status_dict<'py>(
        &self,
        py: Python<'py>,
        p: &WatchStatus,
        cache: &monitor_host::watch::CacheRound,
        changed: bool,
        took: Duration,
        stopped: Option<&str>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("round", self.round)?;
        d.set_item("done", p.done)?;
        d.set_item("n", p.n)?;
        d.set_item("ds_done", p.over_done.driving_score)?;
        d.set_item("ds_n", p.over_n.driving_score)?;
        d.set_item("sds_done", p.over_done.sds)?;
        d.set_item("sds_n", p.over_n.sds)?;
        d.set_item("complete", p.complete)?;
        d.set_item("seconds_left", p.seconds_left)?;
        d.set_item("changed", changed)?;
        d.set_item("rescored", cache.rescored)?;
        d.set_item("reused", cache.reused)?;
        let mut ids = cache.changed.clone();
        ids.sort();
        d.set_item("rescored_routes", ids)?;
        d.set_item("retries", self.retries)?;
        d.set_item("round_ms", took.as_secs_f64() * 1e3)?;
        d.set_item("stopped", stopped)?;
        Ok(d)
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
            let tries = if last { LAST_TRIES } else { 1 };
            let mut scored = None;
            for i in 0..tries {
                if i > 0 {
                    py.detach(|| std::thread::sleep(LAST_PAUSE));
                }
                match self.round(py)? {
                    (RoundOutcome::Retry { .. }, _) => self.retries += 1,
                    (
                        RoundOutcome::Scored {
                            scored: s,
                            cache,
                            changed,
                        },
                        took,
                    ) => {
                        scored = Some((s, cache, changed, took));
                        break;
                    }
                }
            }
            let Some((s, cache, changed, took)) = scored else {
                if last {
                    self.finished = true;
                    return Err(PyStopIteration::new_err(()));
                }
                continue;
            };
            let p = self.watcher.progress(&s.report);
            // Complete and nothing new since the report yielded: the files are final.
            if (p.complete && !changed && !first) || (last && !changed) {
                self.finished = true;
                if let Some(st) = &self.status {
                    st.bind(py)
                        .set_item("stopped", if last { "timeout" } else { "complete" })?;
                }
                return Err(PyStopIteration::new_err(()));
            }
            let stopped = last.then_some("timeout");
            let status = self.status_dict(py, &p, &cache, changed, took, stopped)?;
            self.status = Some(status.unbind());
            self.retries = 0;
            if last {
                self.finished = true;
            }
            return to_python(py, &s.report);
        }
    }

    /// The figures of the round that made the last report (None before the first).
    #[getter]
    fn status(&self, py: Python<'_>) -> Option<Py<PyDict>> {
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
    if !(kw.interval.is_finite() && kw.interval > 0.0) {
        return Err(ConfigError::new_err(format!(
            "interval={}: a number of seconds above 0",
            kw.interval
        )));
    }
    let timeout = match kw.timeout {
        Some(t) if t.is_nan() => {
            return Err(ConfigError::new_err(
                "timeout=nan: a number of seconds, or None",
            ))
        }
        Some(t) => Some(Duration::try_from_secs_f64(t.max(0.0)).unwrap_or(Duration::MAX)),
        None => None,
    };
    let (by, files) = breakdown(kw.group_by.as_deref(), kw.labels)?;
    let inputs = Inputs {
        results,
        telemetry: kw.telemetry,
        route_xml: kw.routes,
        maps: kw.maps,
    };
    let interval = Duration::try_from_secs_f64(kw.interval)
        .map_err(|_| ConfigError::new_err(format!("interval={}: too long", kw.interval)))?;
    Ok(Watch {
        watcher: Watcher::new(inputs, settings, files, by, RACY),
        interval,
        timeout,
        start: None,
        round: 0,
        retries: 0,
        finished: false,
        status: None,
    })
}
