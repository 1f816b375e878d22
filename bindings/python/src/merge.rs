//! `sds.merge` (spec v1.4 §13): the library's [`MergeRequest`] over the parts' files, the merged report converted to Python objects directly ([`crate::pyser`]).

use std::path::PathBuf;

use monitor_host::app::merged::MergeRequest;
use monitor_host::input::duplicates::DuplicatePolicy;
use pyo3::prelude::*;

use crate::errors::{merge_error, ConfigError};
use crate::pyser::to_python;

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
            "duplicates={duplicates:?}: expected \"error\", \"first\", \"last\", \"newest\" or \"all\""
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
