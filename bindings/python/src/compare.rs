//! `sds.compare` (spec v1.4 section 11): the library's [`compare_runs`] called with the runs,
//! [`Settings`] and [`CompareOptions`] built from the keyword arguments (the shared ones through
//! [`RunKwargs`], as `sds.score`), the `sds-compare/1` report converted to Python objects
//! directly ([`crate::pyser`]). No command line in between. Ctrl-C stops it between routes,
//! runs and bootstrap blocks, as `sds.score` (`interrupt.rs`).

use std::path::PathBuf;

use monitor_host::aggregate::compare::{CompareError, CompareOptions};
use monitor_host::compare_runs::{compare_runs, telemetry_beside, RunInputs, Seeds};
use monitor_host::error::message;
use monitor_host::{Inputs, NoProgress, Settings};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyInt};

use crate::errors::{run_error, ConfigError};
use crate::interrupt::with_signals;
use crate::options::RunKwargs;
use crate::pyser::to_python;

/// The keyword arguments of `sds.compare` beyond the shared ones ([`RunKwargs`]).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct CompareKwargs<'py> {
    seeds: Vec<(String, Vec<String>)>,
    baseline: Option<String>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    common_routes: bool,
    fail_if_worse: Vec<String>,
    /// Any int: one beyond a machine word is out of range, said as the library says it.
    bootstrap_samples: Bound<'py, PyInt>,
    bootstrap_seed: u64,
}

/// B as the library takes it, or the library's out-of-range error (any int that is not a
/// machine word is out of range too: `2**64`, `-1`).
fn samples(b: &Bound<'_, PyInt>) -> PyResult<usize> {
    b.extract::<usize>().map_err(|_| {
        let shown = b.str().map_or_else(|_| "?".into(), |s| s.to_string());
        ConfigError::new_err(message(&CompareError::SamplesOutOfRange(shown)))
    })
}

/// Compares runs (see the Python `sds.compare`, which passes each run as `(name, results,
/// telemetry or None)` and its keyword arguments as the dict `options`); returns the report
/// `sds compare --format json` writes, as Python objects. The GIL is released while scoring.
#[pyfunction]
pub fn compare<'py>(
    py: Python<'py>,
    runs: Vec<(String, PathBuf, Option<PathBuf>)>,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let settings: Settings = options.extract::<RunKwargs<'_>>()?.settings()?;
    let kw: CompareKwargs<'_> = options.extract()?;
    let bootstrap_samples = samples(&kw.bootstrap_samples)?;
    let runs: Vec<RunInputs> = runs
        .into_iter()
        .map(|(name, results, telemetry)| RunInputs {
            name,
            inputs: Inputs {
                telemetry: Some(telemetry.unwrap_or_else(|| telemetry_beside(&results))),
                results: vec![results],
                route_xml: kw.routes.clone(),
                maps: kw.maps.clone(),
            },
        })
        .collect();
    let seeds: Vec<Seeds> = kw
        .seeds
        .into_iter()
        .map(|(model, runs)| Seeds { model, runs })
        .collect();
    let options = CompareOptions {
        baseline: kw.baseline,
        common_routes: kw.common_routes,
        bootstrap_samples,
        bootstrap_seed: kw.bootstrap_seed,
        fail_if_worse: kw
            .fail_if_worse
            .iter()
            .map(|m| m.trim().to_string())
            .collect(),
        ..CompareOptions::default()
    };
    let compared = py
        .detach(|| {
            with_signals(&NoProgress, |p| {
                compare_runs(&runs, &seeds, &settings, &options, p)
            })
        })?
        .map_err(|e| run_error(&e))?;
    to_python(py, &compared.comparison)
}
