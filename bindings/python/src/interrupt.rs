//! Ctrl-C while the library works: Python runs signal handlers on its main thread only, so the
//! work runs on a worker thread while the calling thread checks for signals every 50 ms; on
//! one, the work's [`Progress`] says [`Progress::cancelled`] (the library stops between routes,
//! runs and bootstrap blocks) and the signal's exception (`KeyboardInterrupt`) is raised. Used by
//! `sds.score`, `sds.compare` and `sds.merge`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use monitor_host::Progress;
use pyo3::prelude::*;

/// How often the calling thread looks for a signal (Ctrl-C) while the work runs: often enough
/// that Ctrl-C stops a run within a few routes' time (a 4,000-frame route is scored in about
/// 3 ms) and a short call does not wait long for its end to be noticed (the loop sleeps before
/// it looks).
const SIGNAL_POLL: Duration = Duration::from_millis(10);

/// A [`Progress`] that forwards to another (a bar, or nothing) and is cancelled by a flag.
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
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    cancel.store(true, Ordering::Relaxed);
                    signal = Some(e);
                }
            }
        }
        (run.join(), signal)
    });
    if let Some(e) = signal {
        return Err(e);
    }
    r.map_err(|_| crate::errors::SdsError::new_err("the worker thread panicked"))
}
