//! `sds score` for Python: the CLI's options parsed by the CLI's parser, the run scored by the
//! library, the report rendered by the CLI's JSON renderer.

use std::ffi::OsString;

use monitor_host::cli::{self, error_message, progress::Bar};
use monitor_host::report::json;
use monitor_host::NoProgress;
use pyo3::prelude::*;

use crate::errors::{score_error, ConfigError, SdsError};

/// Scores a run given the arguments of `sds score` (without `sds score`), as the command does
/// ([`cli::score_report`]); returns the report as the JSON text `sds score --format json` writes. The GIL is released while scoring; a progress
/// bar is drawn on standard error when `progress` is true (and standard error is a terminal).
#[pyfunction]
#[pyo3(signature = (args, progress=false))]
pub fn score_json(py: Python<'_>, args: Vec<OsString>, progress: bool) -> PyResult<String> {
    let args = cli::parse_score_args(args)
        .map_err(|e| ConfigError::new_err(e.render().to_string().trim_end().to_string()))?;
    let scored = py
        .detach(|| {
            if progress {
                let bar = Bar::new();
                let r = cli::score_report(&args, &bar);
                bar.finish();
                r
            } else {
                cli::score_report(&args, &NoProgress)
            }
        })
        .map_err(|e| score_error(&e))?;
    let report = scored.report;
    let bytes = json::json(&report).map_err(|e| SdsError::new_err(error_message(&e)))?;
    String::from_utf8(bytes).map_err(|e| SdsError::new_err(e.to_string()))
}

/// The long names of the options `sds score` has in this build.
#[pyfunction]
pub fn score_options() -> Vec<String> {
    cli::score_options()
}
