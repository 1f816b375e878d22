//! `sds.merge` (spec v1.4 §13): the library's [`MergeRequest`] over the parts' files, the merged report converted to Python objects directly ([`crate::pyser`]).

use std::path::PathBuf;

use monitor_host::app::merged::MergeRequest;
use monitor_host::error::message;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::merge::MergeError;
use pyo3::prelude::*;

use crate::errors::{ConfigError, InputError, IoError};
use crate::pyser::to_python;

/// The exception for an error of the merge: a part that cannot be read [`IoError`], an
/// unusable `duplicates` or N [`ConfigError`], parts that are no reports or disagree
/// [`InputError`].
fn merge_error(e: &MergeError) -> PyErr {
    let msg = message(e);
    match e {
        MergeError::Read { .. } => IoError::new_err(msg),
        MergeError::Policy(_) | MergeError::TooFewRoutes { .. } => ConfigError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}

/// Merges `sds score` JSON reports (see the Python `sds.merge`); returns the merged report as
/// Python objects. The GIL is released while reading and merging.
#[pyfunction]
pub fn merge<'py>(
    py: Python<'py>,
    parts: Vec<PathBuf>,
    duplicates: &str,
    host: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let policy = DuplicatePolicy::from_name(duplicates).ok_or_else(|| {
        ConfigError::new_err(format!(
            "duplicates={duplicates:?}: expected \"error\", \"first\", \"last\" or \"all\""
        ))
    })?;
    let request = MergeRequest {
        duplicates: policy,
        host,
        ..MergeRequest::new(parts)
    };
    let report = py.detach(|| request.merge()).map_err(|e| merge_error(&e))?;
    to_python(py, &report)
}
