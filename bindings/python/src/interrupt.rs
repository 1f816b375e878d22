//! Ctrl-C while the library works: Python runs signal handlers on its main thread only, so the
//! work runs on a worker thread while the calling thread checks for signals every 10 ms; on
//! one, the work's [`Progress`] says [`Progress::cancelled`] (the library stops between routes,
//! runs and bootstrap blocks) and the signal's exception (`KeyboardInterrupt`) is raised. Used by
//! `sds.score`, `sds.compare` (with their `progress` callables, [`Hook`]) and `sds.merge`.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use monitor_host::Progress;
use pyo3::prelude::*;

/// How often the calling thread looks for a signal (Ctrl-C) while the work runs: often enough
/// that Ctrl-C stops a run within a few routes' time (a 4,000-frame route is scored in about
/// 3 ms) and a short call does not wait long for its end to be noticed (the loop sleeps before
/// it looks).
const SIGNAL_POLL: Duration = Duration::from_millis(10);

/// A [`Progress`] that forwards to another (a bar, a callable, or nothing) and is cancelled by
/// a flag or by the other.
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
        self.cancel.load(Ordering::SeqCst) || self.inner.cancelled()
    }
}

/// The `progress` callable of `sds.score` / `sds.compare`: called with `(done, total)` after
/// each route (from the worker threads, the GIL taken for the call); `start` resets the count
/// (`sds.compare` scores its runs one after the other). An exception it raises stops the run
/// between routes and is raised by the call ([`Hook::take_error`]).
pub(crate) struct Hook {
    callable: Py<PyAny>,
    done: AtomicUsize,
    total: AtomicUsize,
    error: Mutex<Option<PyErr>>,
}

impl Hook {
    /// A hook calling `callable`.
    pub(crate) fn new(callable: Py<PyAny>) -> Self {
        Hook {
            callable,
            done: AtomicUsize::new(0),
            total: AtomicUsize::new(0),
            error: Mutex::new(None),
        }
    }

    /// The exception the callable raised, if it did (raised instead of the run's result).
    pub(crate) fn take_error(&self) -> Option<PyErr> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }
}

impl Progress for Hook {
    fn start(&self, routes: usize) {
        self.total.store(routes, Ordering::SeqCst);
        self.done.store(0, Ordering::SeqCst);
    }
    fn route_done(&self) {
        if self.cancelled() {
            return;
        }
        let done = self.done.fetch_add(1, Ordering::SeqCst) + 1;
        let total = self.total.load(Ordering::SeqCst);
        if let Err(e) = Python::attach(|py| self.callable.call1(py, (done, total)).map(drop)) {
            if let Ok(mut slot) = self.error.lock() {
                slot.get_or_insert(e);
            }
        }
    }
    fn cancelled(&self) -> bool {
        self.error.lock().map_or(true, |e| e.is_some())
    }
}

/// Runs `work` on a worker thread with a [`Progress`] forwarding to `inner` that is cancelled
/// on a signal; call it with the GIL released (`py.detach`). Returns the work's result, or
/// the signal's exception when one arrived (the work's result is then dropped), or an error when
/// the worker panicked.
pub(crate) fn with_signals<T: Send>(
    inner: &dyn Progress,
    work: impl FnOnce(&dyn Progress) -> T + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    let watched = Cancellable {
        inner,
        cancel: &cancel,
    };
    let (r, signal) = std::thread::scope(|s| {
        let run = s.spawn(|| work(&watched));
        let mut signal = None;
        while !run.is_finished() {
            std::thread::sleep(SIGNAL_POLL);
            if signal.is_none() {
                // The flag is set while the GIL is still held: a `progress` callable that saw
                // the signal handled (it needs the GIL to go on) finds the run cancelled.
                signal = Python::attach(|py| {
                    py.check_signals().err().inspect(|_| {
                        cancel.store(true, Ordering::SeqCst);
                    })
                });
            }
        }
        (run.join(), signal)
    });
    if let Some(e) = signal {
        return Err(e);
    }
    r.map_err(|_| crate::errors::SdsError::new_err("the worker thread panicked"))
}
