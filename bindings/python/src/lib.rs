//! `sds._sds`: the extension module of the Python package `sds`, a thin layer over
//! `monitor-host` and `monitor-core` (no scoring logic here).
//!
//! The entry points `score`, `frames`, `compare`, `watch`, `merge` and `link` are the package's
//! own functions (`sds.score` is `_sds.score`): typed keyword arguments
//! (`#[pyo3(signature = ...)]`; the shared ones and the named choices in `options.rs`), their
//! docs in their doc comments (`__doc__`), their types in `_sds.pyi`, the report's warnings
//! raised as `sds.SdsWarning` at the caller's line. Each builds its command's request:
//!
//! - `score` (`score.rs`): the library's `ScoreRequest` (results or vehicle logs), the report
//!   converted to Python objects directly (`pyser.rs`), GIL released while scoring;
//! - `frames` (`frames.rs`): the library's `FramesRequest` (a route of a run, or a vehicle
//!   log), the frames as `sds frames` prints them;
//! - `compare` (`compare.rs`): the library's `CompareRequest`, the `sds-compare/1` report
//!   converted by `pyser.rs`, GIL released while scoring;
//! - `watch` (`watch.rs`): the library's watch `Session` as an iterator of partial
//!   reports (`Watch`), one round per `next()`, GIL released while sleeping and scoring;
//! - `merge` (`merge.rs`): the library's `MergeRequest` over `sds score` JSON reports, GIL
//!   released while merging;
//! - `link` (`link.rs`): the library's `LinkRequest`, the options of `sds link`;
//! - `long_tables` (`tables.rs`): the library's long-table builder over a report's JSON text,
//!   typed columns for `sds.to_pandas` and `sds.to_parquet`;
//! - `render` (`render.rs`): a report file's HTML page and figures, for `sds.log`;
//! - `FileSet`, `refuse_unsafe` (`files.rs`): the library's write rules, for `sds._files`;
//! - `Monitor` (`monitor.rs`): the streaming monitor fed one `get_metric_info()` dict per tick,
//!   its frames built by the library's [`monitor_host::pipeline::live`];
//! - `cli_main`: the package's `sds` command: the user's own argument list handed unchanged to
//!   the command line (the one use of the `sds-cli` crate: the installed `sds` is the binary's
//!   program, run in-process);
//! - `errors.rs`: the exception classes; `interrupt.rs`: Ctrl-C while `score` or `compare`
//!   works (the calling thread watches for signals, the library stops between routes).
#![deny(missing_docs)]

mod compare;
mod convert;
mod errors;
mod files;
mod frames;
mod interrupt;
mod link;
mod merge;
mod monitor;
mod options;
mod pyser;
mod render;
mod score;
mod tables;
mod watch;

use std::ffi::OsString;

use pyo3::prelude::*;

/// Runs the `sds` command line with `argv` (program name first) and returns its exit code.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> i32 {
    py.detach(|| sds_cli::main(argv))
}

/// The extension module.
#[pymodule]
fn _sds(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(score::score, m)?)?;
    m.add_function(wrap_pyfunction!(frames::frames, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(watch::watch, m)?)?;
    m.add_function(wrap_pyfunction!(merge::merge, m)?)?;
    m.add_function(wrap_pyfunction!(link::link, m)?)?;
    m.add_function(wrap_pyfunction!(tables::long_tables, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(files::refuse_special, m)?)?;
    m.add_class::<files::FileSet>()?;
    m.add_class::<watch::Watch>()?;
    m.add_class::<monitor::Monitor>()?;
    m.add(
        "FIELDS",
        monitor_host::input::telemetry::TelemetryFrame::FIELDS.to_vec(),
    )?;
    m.add("SdsError", py.get_type::<errors::SdsError>())?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("ConfigError", py.get_type::<errors::ConfigError>())?;
    m.add(
        "NeedsLabelsError",
        py.get_type::<errors::NeedsLabelsError>(),
    )?;
    m.add("IoError", py.get_type::<errors::IoError>())?;
    m.add("SdsWarning", py.get_type::<errors::SdsWarning>())?;
    m.add("RefusedError", errors::refused_error(py)?)?;
    m.add_function(wrap_pyfunction!(errors::error_table, m)?)?;
    m.add(
        "FeatureUnavailableError",
        py.get_type::<errors::FeatureUnavailableError>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
