//! `sds.compare` (docs/SCORE.md §10.3): the library's [`CompareRequest`] built from the keyword
//! arguments (the shared ones through [`RunKwargs`], as `sds.score`), the `sds-compare/1` report converted to Python objects
//! directly ([`crate::pyser`]). No command line in between. Ctrl-C stops it between routes,
//! runs and bootstrap blocks, as `sds.score` (`interrupt.rs`).

use std::path::PathBuf;

use monitor_host::error::message;
use monitor_host::stats::sweep::SweepAxis;
use monitor_host::stats::{CompareError, CompareOptions};
use monitor_host::{CompareRequest, CompareWarning, RunSpec, Seeds};
use monitor_host::{NoProgress, Progress};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt};

use crate::errors::{score_error, ConfigError};
use crate::interrupt::with_signals;
use crate::options::RunKwargs;
use crate::pyser::to_python;
use crate::score::{follow, Follow};

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
    /// `--rank`: the bootstrap ranking of every model (docs/SCORE.md §10.3).
    rank: bool,
    /// `--repro-halfwidth`: h of `seeds_needed` (docs/SCORE.md §10.3).
    repro_halfwidth: f64,
    /// A callable taking `(done, total)` of the run being scored, or None.
    #[pyo3(default)]
    progress: Option<Py<PyAny>>,
    /// `--sweep`: a mapping of setting name to its values (docs/SCORE.md §10.4), or None.
    sweep: Option<Bound<'py, PyAny>>,
}

/// The sweep's axes from `{name: [v1, v2, ...]}`, each value as the text `--sweep` takes
/// (`True` → `true`, `0.9` → `0.9`), in the mapping's order.
fn sweep_axes(sweep: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<SweepAxis>> {
    let Some(map) = sweep else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for item in map.call_method0("items")?.try_iter()? {
        let (name, values): (String, Bound<'_, PyAny>) = item?.extract()?;
        let mut texts = Vec::new();
        for v in values.try_iter()? {
            let v = v?;
            texts.push(match v.cast::<PyBool>() {
                Ok(b) => b.is_true().to_string(),
                Err(_) => v.str()?.to_string(),
            });
        }
        // `--sweep`'s own check: an empty name or value is refused here as there.
        out.push(SweepAxis::new(&name, &texts).map_err(|e| ConfigError::new_err(message(&e)))?);
    }
    Ok(out)
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
/// telemetry or None)` and its keyword arguments as the dict `options`): the library's
/// [`CompareRequest`]; returns the report `sds compare --format json` writes, as Python
/// objects, and the warnings `sds compare` prints (each run's, named by the run, then the
/// comparison's own; a missing map is said per run, where the command says it once), which
/// `sds.compare` raises as Python warnings. The GIL is released while scoring.
#[pyfunction]
pub fn compare<'py>(
    py: Python<'py>,
    runs: Vec<(String, PathBuf, Option<PathBuf>)>,
    options: &Bound<'py, PyDict>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    let settings = options.extract::<RunKwargs<'_>>()?.request()?;
    let kw: CompareKwargs<'_> = options.extract()?;
    let request = CompareRequest {
        sweep: sweep_axes(kw.sweep.as_ref())?,
        runs: runs
            .into_iter()
            .map(|(name, results, telemetry)| RunSpec {
                name,
                results,
                telemetry,
            })
            .collect(),
        seeds: kw
            .seeds
            .into_iter()
            .map(|(model, runs)| Seeds { model, runs })
            .collect(),
        routes: kw.routes,
        maps: kw.maps,
        settings,
        options: CompareOptions {
            baseline: kw.baseline,
            common_routes: kw.common_routes,
            bootstrap_samples: samples(&kw.bootstrap_samples)?,
            bootstrap_seed: kw.bootstrap_seed,
            fail_if_worse: kw.fail_if_worse,
            rank: kw.rank,
            repro_halfwidth: kw.repro_halfwidth,
        },
    };
    // Settings refused before any run is scored.
    request.validate().map_err(|e| score_error(&e))?;
    let follow = follow(py, kw.progress.as_ref(), false)?;
    let inner: &dyn Progress = match &follow {
        Follow::Call(h) => h,
        _ => &NoProgress,
    };
    let compared = py.detach(|| with_signals(inner, |p| request.compare(p)))?;
    // The callable's exception (it stopped the comparison) before the comparison's own error.
    if let Follow::Call(h) = &follow {
        if let Some(e) = h.take_error() {
            return Err(e);
        }
    }
    let compared = compared.map_err(|e| score_error(&e))?;
    let warnings: Vec<String> = compared
        .warnings(request.maps.as_deref())
        .into_iter()
        .map(|w| match w {
            CompareWarning::Run { run, warning } => format!("{run}: {warning}"),
            CompareWarning::Comparison(text) => text,
        })
        .collect();
    Ok((to_python(py, &compared.comparison)?, warnings))
}
