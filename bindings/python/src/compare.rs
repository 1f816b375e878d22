//! `sds.compare` (docs/SCORE.md §10.3): the library's [`CompareRequest`] built from the typed
//! keyword arguments (the shared ones through [`Shared`], as `sds.score`), the `sds-compare/1`
//! report converted to Python objects directly ([`crate::pyser`]), the warnings `sds compare`
//! prints raised as `sds.SdsWarning`. No command line in between. Ctrl-C stops it between
//! routes, runs and bootstrap blocks, as `sds.score` (`interrupt.rs`).

use std::path::PathBuf;

use monitor_host::error::message;
use monitor_host::stats::sweep::SweepAxis;
use monitor_host::stats::{CompareError, CompareOptions};
use monitor_host::{CompareRequest, CompareWarning, RunSpec, Seeds};
use monitor_host::{NoProgress, Progress};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyInt, PyMapping, PyString};

use crate::errors::{score_error, ConfigError};
use crate::interrupt::with_signals;
use crate::options::{text, warn_each, Overrides, Shared, Strings};
use crate::pyser::to_python;
use crate::score::{follow, Follow};

/// The sweep's axes from `{name: [v1, v2, ...]}`, each value as the text `--sweep` takes
/// (`True` → `true`, `0.9` → `0.9`), in the mapping's order.
fn sweep_axes(sweep: Option<&Bound<'_, PyMapping>>) -> PyResult<Vec<SweepAxis>> {
    let Some(map) = sweep else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for item in map.items()?.iter() {
        let (key, values): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
        if values.is_instance_of::<PyString>() || values.is_instance_of::<PyBytes>() {
            // One string would read as a list of characters.
            return Err(ConfigError::new_err(format!(
                "sweep[{}]={}: expected a list of values, e.g. [0.5, 0.65]",
                key.repr()?,
                values.repr()?
            )));
        }
        let name: String = key.extract()?;
        let mut texts = Vec::new();
        for v in values.try_iter()? {
            texts.push(text(&v?)?);
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

/// A run of `runs`: its results (file or folder; telemetry looked for beside it), or
/// `(results, telemetry)`.
#[derive(FromPyObject)]
pub enum RunArg {
    /// `(results, telemetry)`.
    Pair(PathBuf, PathBuf),
    /// The results alone.
    Results(PathBuf),
}

/// Compares runs route by route; returns the ``sds-compare/1`` report as a dict.
///
/// The library is called directly (no command line in between) and the report converted to
/// Python objects as ``json.loads`` would read ``sds compare --format json``. Each run is
/// scored as :func:`sds.score` would; models (a run, or the seeds of one model)
/// are compared with the baseline on the routes' paired differences, with a bootstrap interval
/// and a verdict per metric (``ds``, ``success``, ``ds_safe``, ``comfort``). The GIL is
/// released while scoring.
///
/// Args:
///     runs: Run name -> results (file or folder; telemetry looked for beside it) or
///         ``(results, telemetry)``. In order: the first model is the baseline.
///     seeds: Model name -> the names of its runs (``--seeds``). Runs are grouped only here.
///     baseline: The baseline model (``--baseline``; default the first).
///     routes: The route XML every run is scored against (``--routes``).
///     maps: A folder of OpenDRIVE maps (``--maps``).
///     profile: ``"physical"``, ``"b2d-legacy"`` or ``"autoware"``.
///     expected_routes: The benchmark's size N (``--expected-routes``).
///     allow_missing_telemetry: Score routes without telemetry without telemetry terms.
///     common_routes: Compare over the routes every run holds instead of refusing runs whose
///         route sets differ (``--common-routes``).
///     fail_if_worse: Metrics of the gate (``--fail-if-worse``): check
///         ``report["paired"]`` for a ``"worse"`` or ``"no data"`` verdict on them (the CLI
///         exits 5 on either: a gate never passes by checking nothing).
///     bootstrap_samples: Resamples B, 1000 to 1000000 (and n x B at most 250 million per
///         model and metric); None: 10000. bootstrap_seed: The SplitMix64 seed; each model and metric
///         draws from its own generator seeded with it.
///     settings: Setting overrides, as for :func:`sds.score` (there is no ``duplicates``
///         option, as ``sds compare`` has none: ``settings={"duplicates": ...}``).
///     jobs: Worker threads.
///     protocols: Also score every run's routes under these scoring protocols, as for
///         :func:`sds.score` (``--protocol``; ids, or ``["all"]``); the paired comparison
///         stays on ``ds``, ``success``, ``ds_safe``, ``comfort``.
///     rank: Rank every model by its mean DS over the compared routes (``--rank``): the
///         report's ``ranking`` lists, by rank (ties by name), each model's ``mean_ds``,
///         ``rank``, ``rank_ci95`` (95 % bootstrap interval of its rank, one generator seeded
///         with ``bootstrap_seed``) and ``p_best`` (share of resamples where it ranks first).
///     repro_halfwidth: h of each model's ``seeds_needed`` (``--repro-halfwidth``): the seeds
///         for a 95 % interval of its mean DS no wider than +-h DS points (above 0).
///     progress: Called with ``(done, total)`` after each route of the run being scored (the
///         count starts again with each run); an exception it raises stops the comparison
///         between routes and is raised here.
///     route_subset: Which routes of ``routes`` make each run's route set
///         (``--route-subset``): ``"all"`` (a route without a record counts as 0) or
///         ``"found"`` (those with a record), as for :func:`sds.score`. None: the setting
///         ``route_subset`` (default ``"all"``, or from ``settings``).
///     sweep: Setting name -> its values (``--sweep NAME=V1,V2,...``): every model is scored
///         at every point of the grid (the product of the lists, at most 64 points; a setting
///         that changes a route's figures, e.g. ``{"critical_excess": [0.5, 0.65, 0.8]}``).
///         The report's ``sweep`` holds ``settings``, ``points`` (each point's ``values`` and
///         every model's ``ds_safe``, ``comfort``, ``sds``, ``rank``), ``pairs`` (``a``,
///         ``b``, ``order_stable``, ``flips``: point indices) and ``ranges`` (each model's
///         ``sds_min``, ``sds_max``).
///
/// Returns:
///     ``schema``, ``baseline``, ``models`` (mean and std over seeds), ``paired`` (``model``,
///     ``metric``, ``n``, ``delta``, ``ci95``, ``p_better``, ``verdict``), ``flips``,
///     ``scope``, ``routes`` (per route key, each model's values), ``config``, ``notes``,
///     ``warnings``; each model also has its seeds' figures (``routes`` with ``ds_mean``,
///     ``ds_std``, ``ds_min``, ``ds_max``, ``success_share`` per route, ``flaky_routes``,
///     ``seed_ds``, ``seed_std``, ``seeds_needed``), with ``rank`` the report has
///     ``ranking``, and with ``sweep`` it has ``sweep``.
///
/// Warns:
///     SdsWarning: Each warning ``sds compare`` prints: each run's report's (``"<run>: ..."``;
///         a missing map per run, where the command says it once), then the comparison's own
///         ``warnings``, at the caller's line.
///
/// Raises:
///     ConfigError: A ``sweep`` setting that does not exist or changes no route's figures
///         (the message lists those that do), a value it refuses, more than 64 points;
///         fewer than two models, a bad name in ``seeds`` or ``baseline``, an
///         unknown metric, route sets that differ without ``common_routes``,
///         ``bootstrap_samples`` out of range, a ``repro_halfwidth`` not above 0; an invalid
///         ``profile``, ``settings`` or ``protocols``.
///     InputError, IoError: A run's inputs, as for :func:`sds.score` (the message names the run).
///     KeyboardInterrupt: Ctrl-C, which stops the comparison between routes, runs and
///         bootstrap blocks.
///
/// Example:
///     >>> c = sds.compare({"base": "base/", "new": "new/"}, routes="bench2drive220.xml")  # doctest: +SKIP
///     >>> [p["verdict"] for p in c["paired"] if p["metric"] == "ds"]  # doctest: +SKIP
///     >>> c = sds.compare({"ep10": "ep10/", "ep20": "ep20/", "ep30": "ep30/"}, rank=True)  # doctest: +SKIP
///     >>> [(r["model"], r["rank"], r["rank_ci95"]) for r in c["ranking"]]  # doctest: +SKIP
///     >>> c = sds.compare({"a": "a/", "b": "b/"}, sweep={"critical_excess": [0.5, 0.65]})  # doctest: +SKIP
///     >>> [p["order_stable"] for p in c["sweep"]["pairs"]]  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (runs, *, seeds=None, baseline=None, routes=None, maps=None,
                    profile="physical", expected_routes=None, allow_missing_telemetry=false,
                    common_routes=false, fail_if_worse=None, bootstrap_samples=None,
                    bootstrap_seed=0, settings=None, jobs=None, protocols=None, rank=false,
                    repro_halfwidth=1.0, progress=None, route_subset=None, sweep=None))]
#[allow(clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    runs: &Bound<'py, PyMapping>,
    seeds: Option<Bound<'py, PyMapping>>,
    baseline: Option<String>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    profile: &str,
    expected_routes: Option<usize>,
    allow_missing_telemetry: bool,
    common_routes: bool,
    fail_if_worse: Option<Strings>,
    bootstrap_samples: Option<Bound<'py, PyInt>>,
    bootstrap_seed: u64,
    settings: Option<Overrides>,
    jobs: Option<usize>,
    protocols: Option<Strings>,
    rank: bool,
    repro_halfwidth: f64,
    progress: Option<Bound<'py, PyAny>>,
    route_subset: Option<&str>,
    sweep: Option<Bound<'py, PyMapping>>,
) -> PyResult<Bound<'py, PyAny>> {
    // No `duplicates` option, as `sds compare` has none: the setting's default or `settings`.
    let run_settings = Shared {
        profile,
        duplicates: None,
        expected_routes,
        allow_missing_telemetry,
        settings,
        jobs,
        protocols,
        route_subset,
    }
    .request()?;
    let mut specs = Vec::new();
    for item in runs.items()?.iter() {
        let (name, run): (String, RunArg) = item.extract()?;
        let (results, telemetry) = match run {
            RunArg::Pair(r, t) => (r, Some(t)),
            RunArg::Results(r) => (r, None),
        };
        specs.push(RunSpec {
            name,
            results,
            telemetry,
        });
    }
    let mut groups = Vec::new();
    if let Some(seeds) = &seeds {
        for item in seeds.items()?.iter() {
            let (model, names): (String, Strings) = item.extract()?;
            let runs = names.list(&format!("seeds[{model:?}]"))?;
            groups.push(Seeds { model, runs });
        }
    }
    let request = CompareRequest {
        sweep: sweep_axes(sweep.as_ref())?,
        runs: specs,
        seeds: groups,
        routes,
        maps,
        settings: run_settings,
        options: CompareOptions {
            baseline,
            common_routes,
            bootstrap_samples: bootstrap_samples
                .as_ref()
                .map_or(Ok(CompareOptions::default().bootstrap_samples), samples)?,
            bootstrap_seed,
            fail_if_worse: fail_if_worse
                .map(|f| f.list("fail_if_worse"))
                .transpose()?
                .unwrap_or_default(),
            rank,
            repro_halfwidth,
        },
    };
    // Settings refused before any run is scored.
    request.validate().map_err(|e| score_error(&e))?;
    let follow = follow(progress.as_ref(), false)?;
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
    let report = to_python(py, &compared.comparison)?;
    // Each run's warnings, named by the run, then the comparison's own, as `sds compare` prints.
    warn_each(
        py,
        compared
            .warnings(request.maps.as_deref())
            .into_iter()
            .map(|w| match w {
                CompareWarning::Run { run, warning } => format!("{run}: {warning}"),
                CompareWarning::Comparison(text) => text,
            }),
    )?;
    Ok(report)
}
