//! `sds._sds`: the extension module of the Python package `sds`, a thin layer over
//! `monitor-host` and `monitor-core` (no scoring logic here).
//!
//! - `score_json` (`score.rs`): `sds score` through the library's [`monitor_host::score_run`], the
//!   report as the CLI's JSON text (the Python layer parses it), GIL released while scoring;
//! - `compare_json` (`compare.rs`): `sds compare` through the library's `compare_runs`, the
//!   `sds-compare/1` report as JSON text;
//! - `Monitor` (`monitor.rs`): the streaming monitor fed one `get_metric_info()` dict per tick;
//! - `cli_main`: the package's `sds` command, the same command line as the binary;
//! - `errors.rs`: the exception classes.
#![deny(missing_docs)]

mod compare;
mod convert;
mod errors;
mod monitor;
mod score;

use std::ffi::OsString;

use pyo3::prelude::*;

/// Runs the `sds` command line with `argv` (program name first) and returns its exit code.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> i32 {
    py.detach(|| monitor_host::cli::main(argv))
}

/// The extension module.
#[pymodule]
fn _sds(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(score::score_json, m)?)?;
    m.add_function(wrap_pyfunction!(score::score_options, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare_json, m)?)?;
    m.add_class::<monitor::Monitor>()?;
    m.add_function(wrap_pyfunction!(monitor::settings_args, m)?)?;
    m.add(
        "FIELDS",
        monitor_host::input::metric_info::TelemetryFrame::FIELDS.to_vec(),
    )?;
    m.add("SdsError", py.get_type::<errors::SdsError>())?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("ConfigError", py.get_type::<errors::ConfigError>())?;
    m.add(
        "NeedsLabelsError",
        py.get_type::<errors::NeedsLabelsError>(),
    )?;
    m.add("IoError", py.get_type::<errors::IoError>())?;
    m.add(
        "FeatureUnavailableError",
        py.get_type::<errors::FeatureUnavailableError>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
