//! `sds compare` for Python (spec v1.3 section 11): the command's options parsed by the CLI's
//! parser, the runs scored and compared by the library
//! ([`monitor_host::compare_runs::compare_runs`], through [`cli::compare::compare_report`]), the
//! `sds-compare/1` report returned as JSON text.

use std::ffi::OsString;

use monitor_host::cli::{self, compare::CompareUsage, error_message};
use monitor_host::Error;
use pyo3::prelude::*;

use crate::errors::{run_error, score_error, ConfigError, SdsError};

/// Compares runs given the arguments of `sds compare` (without `sds compare`); returns the
/// report `sds compare --format json` writes. The GIL is released while scoring.
#[pyfunction]
pub fn compare_json(py: Python<'_>, args: Vec<OsString>) -> PyResult<String> {
    let args = cli::compare::parse_compare_args(args)
        .map_err(|e| ConfigError::new_err(e.render().to_string().trim_end().to_string()))?;
    let (compared, _problems) = py
        .detach(|| cli::compare::compare_report(&args))
        .map_err(|e| {
            if e.downcast_ref::<CompareUsage>().is_some() {
                return ConfigError::new_err(error_message(&*e));
            }
            match e.downcast_ref::<Error>() {
                // Which runs and how they are compared: the caller's arguments.
                Some(Error::Compare(_)) => ConfigError::new_err(error_message(&*e)),
                // One run's own error, with the run's name in the message.
                Some(inner @ Error::InRun { .. }) => {
                    let class = run_error(inner.inner()).get_type(py);
                    PyErr::from_type(class, error_message(&*e))
                }
                _ => score_error(&e),
            }
        })?;
    serde_json::to_string_pretty(&compared.comparison).map_err(|e| SdsError::new_err(e.to_string()))
}
