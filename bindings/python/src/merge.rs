//! `sds.merge` (spec v1.4 §13): the library's [`monitor_host::merge::merge`] over the parts'
//! files, the merged report converted to Python objects directly ([`crate::pyser`]).

use std::path::PathBuf;

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
            "duplicates={duplicates:?}: expected \"error\", \"first\", \"last\" or \"all\""
        ))
    })?;
    let report = py
        .detach(|| monitor_host::merge::merge(&parts, policy, host))
        .map_err(|e| merge_error(&e))?;
    to_python(py, &report)
}
