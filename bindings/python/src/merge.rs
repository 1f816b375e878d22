//! `sds.merge` (docs/SCORE.md §13.2): the library's [`MergeRequest`] over the parts' files, the merged report converted to Python objects directly ([`crate::pyser`]).

use std::path::PathBuf;

use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::MergeRequest;
use monitor_host::NoProgress;
use pyo3::prelude::*;

use crate::errors::{merge_error, ConfigError};
use crate::interrupt::with_signals;
use crate::pyser::to_python;

/// Merges `sds score` JSON reports (see the Python `sds.merge`); returns the merged report as
/// Python objects. The GIL is released while reading and merging; Ctrl-C raises
/// `KeyboardInterrupt`.
#[pyfunction]
pub fn merge<'py>(
    py: Python<'py>,
    parts: Vec<PathBuf>,
    duplicates: &str,
    host: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let policy = DuplicatePolicy::from_name(duplicates).ok_or_else(|| {
        ConfigError::new_err(format!(
            "duplicates={duplicates:?}: expected \"error\", \"first\", \"last\", \"newest\" or \"all\""
        ))
    })?;
    let request = MergeRequest {
        duplicates: policy,
        host,
        ..MergeRequest::new(parts)
    };
    // The parts are read on a worker thread while this one looks for signals: Ctrl-C raises
    // `KeyboardInterrupt` (`interrupt.rs`); each read is bounded, so the worker ends soon.
    let report = py
        .detach(|| with_signals(&NoProgress, |_| request.merge()))?
        .map_err(|e| merge_error(&e))?;
    to_python(py, &report)
}
