//! `sds.link` (docs/SCORE.md, "Live link"): the library's [`LinkRequest`] built from the typed
//! keyword arguments, the options of `sds link` (the shared ones through [`Shared`], as
//! `sds.score`), the report converted to Python objects ([`crate::pyser`]).

use std::path::PathBuf;

use monitor_host::live_link::{Inject, Pace, Target};
use monitor_host::{Inputs, LinkError, LinkRequest};
use pyo3::prelude::*;

use crate::errors::{request_error, run_error, settings_error, ConfigError, IoError};
use crate::options::{named, Overrides, Paths, Shared, Strings};
use crate::pyser::to_python;

/// Plays a run to a checker over a byte stream; returns the report of ``sds link``.
///
/// Each route is played to the checker (``to``: ``"serial:DEVICE[@BAUD]"``,
/// ``"tcp:HOST:PORT"`` or ``"exec:COMMAND"``, e.g. ``"exec:sds checker"``), and its events are
/// compared with the replay of the frames the checker accepted, cut into the segments it
/// started (docs/SCORE.md, "Live link"). The GIL is released while playing.
///
/// Args:
///     results: Results file(s) or folder(s), as for :func:`score`; none with ``mcap``.
///     to: The checker.
///     telemetry, routes, maps, profile, expected_routes, allow_missing_telemetry, jobs,
///         protocols, route_subset: As for :func:`score` (``sds link`` takes the options of
///         ``sds score``).
///     duplicates: Which copy of a duplicated route id to play, as for :func:`score`; None:
///         the setting ``duplicates`` (default ``"error"``, or from ``settings``).
///     mcap: Vehicle logs played instead of ``results`` (``--mcap``), each one route, as for
///         :func:`score`.
///     topics: The logs' topics, ``"NAME=TOPIC"`` each (``--topic``), as for :func:`score`.
///     pace: ``"fast"`` (as fast as the checker reads) or ``"realtime"`` (one frame a period).
///     inject: Faults, ``"drop=P,corrupt=P,duplicate=P,reorder=P,stall=SECONDS,seed=N"``.
///     tap: A folder for ``sent.bin`` and ``received.bin``.
///     settings: Settings by name (as ``--set``), the link's too (``link.max_delta``,
///         ``link.timeout``, ``link.window``, ``link.max_errors``; they must match the
///         checker's, e.g. ``to="exec:sds checker --set link.window=10"``).
///
/// Returns:
///     The report: ``routes`` (each with its ``link`` object) and ``summary``
///     (``equal_routes`` of ``routes``).
///
/// Raises:
///     ConfigError: A bad ``to``, ``pace``, ``inject``, option or setting; ``topics`` without
///         ``mcap``, ``mcap`` with ``results``.
///     InputError: A results file, route XML or log is invalid.
///     IoError: The checker cannot be reached or stops answering.
///
/// Example:
///     >>> r = sds.link("results.json", telemetry="telemetry", to="exec:sds checker")  # doctest: +SKIP
///     >>> r["summary"]["equal_routes"] == r["summary"]["routes"]  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (results=None, *, to, telemetry=None, routes=None, maps=None, mcap=None,
                    topics=None, profile="physical", duplicates=None, expected_routes=None,
                    allow_missing_telemetry=false, settings=None, jobs=None, protocols=None,
                    route_subset=None, pace="fast", inject=None, tap=None))]
#[allow(clippy::too_many_arguments)]
pub fn link<'py>(
    py: Python<'py>,
    results: Option<Paths>,
    to: &str,
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    mcap: Option<Paths>,
    topics: Option<Strings>,
    profile: &str,
    duplicates: Option<&str>,
    expected_routes: Option<usize>,
    allow_missing_telemetry: bool,
    settings: Option<Overrides>,
    jobs: Option<usize>,
    protocols: Option<Strings>,
    route_subset: Option<&str>,
    pace: &str,
    inject: Option<&str>,
    tap: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    // The `link.*` overrides stay in the settings: the request reads them (`link_config`).
    let settings = Shared {
        profile,
        duplicates,
        expected_routes,
        allow_missing_telemetry,
        settings,
        jobs,
        protocols,
        route_subset,
    }
    .request()?;
    let target: Target =
        to.parse()
            .map_err(|e: monitor_host::live_link::transport::TargetError| {
                ConfigError::new_err(e.to_string())
            })?;
    let inject: Inject = inject.unwrap_or("").parse().map_err(
        |e: monitor_host::live_link::inject::InjectError| ConfigError::new_err(e.to_string()),
    )?;
    let results = results.map(Paths::into_vec).unwrap_or_default();
    let mcap = mcap.map(Paths::into_vec).unwrap_or_default();
    let request = LinkRequest {
        inputs: Inputs {
            results,
            telemetry,
            route_xml: routes,
            maps,
        },
        mcap,
        topics: topics
            .map(|t| t.list("topics"))
            .transpose()?
            .unwrap_or_default(),
        settings,
        target,
        pace: named("pace", pace, Pace::from_name, Pace::choices)?,
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
