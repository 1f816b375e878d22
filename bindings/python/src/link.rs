//! `sds.link` (docs/SCORE.md, "Live link"): the library's [`LinkRequest`], the report converted
//! to Python objects ([`crate::pyser`]).

use std::path::PathBuf;

use monitor_host::live_link::{Inject, Pace, Target};
use monitor_host::Inputs;
use monitor_host::RunSettings;
use monitor_host::{LinkError, LinkRequest};
use pyo3::prelude::*;

use crate::errors::{request_error, run_error, settings_error, ConfigError, IoError};
use crate::pyser::to_python;

/// Plays a run to a checker (see the Python `sds.link`); returns the report as Python objects.
/// The GIL is released while playing.
#[pyfunction]
#[pyo3(signature = (results, telemetry, to, pace, inject, tap, overrides))]
#[allow(clippy::too_many_arguments)]
pub fn link<'py>(
    py: Python<'py>,
    results: Vec<PathBuf>,
    telemetry: Option<PathBuf>,
    to: &str,
    pace: &str,
    inject: &str,
    tap: Option<PathBuf>,
    overrides: Vec<(String, String)>,
) -> PyResult<Bound<'py, PyAny>> {
    let target: Target =
        to.parse()
            .map_err(|e: monitor_host::live_link::transport::TargetError| {
                ConfigError::new_err(e.to_string())
            })?;
    let pace = Pace::from_name(pace).ok_or_else(|| {
        ConfigError::new_err(format!("pace={pace:?}: expected {}", Pace::choices()))
    })?;
    let inject: Inject =
        inject
            .parse()
            .map_err(|e: monitor_host::live_link::inject::InjectError| {
                ConfigError::new_err(e.to_string())
            })?;
    let request = LinkRequest {
        inputs: Inputs {
            telemetry,
            ..Inputs::new(results)
        },
        mcap: Vec::new(),
        topics: Vec::new(),
        settings: RunSettings {
            overrides,
            ..RunSettings::default()
        },
        target,
        pace,
        inject,
        tap,
    };
    let report = py.detach(|| request.run()).map_err(|e| match e {
        LinkError::Settings(e) => settings_error(&e),
        LinkError::Run(e) => run_error(&e),
        LinkError::Request(e) => request_error(&e),
        other => IoError::new_err(monitor_host::error::message(&other)),
    })?;
    to_python(py, &report)
}
