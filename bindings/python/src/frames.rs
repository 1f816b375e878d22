//! `sds.frames`: the library's [`FramesRequest`] built from the typed keyword arguments, the
//! frames as `sds frames` prints them, each line read as `json.loads` reads it.

use std::path::PathBuf;

use monitor_host::report::frames::frame_lines;
use monitor_host::Inputs;
use monitor_host::{Frames, FramesRequest};
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::errors::{score_error, SdsError};
use crate::options::{warn_each, Overrides, Paths, Shared, Strings};

/// The monitor's input frames of one route, as ``sds frames`` prints them.
///
/// One dict per frame, as ``json.loads`` reads each line of ``sds frames``: the core's frame
/// (``a_lon``, ``a_lat``, ``a_mag``, ``yaw_rate``, ``speed``, ``lat_err``, ...) and ``host``,
/// the values behind it (``step``, ``dt``, ``reference``, and where the lateral error is known
/// ``lat_err``, ``slack``, ``lane_width``). The GIL is released while reading.
///
/// Args:
///     results: Results file(s) or folder(s), as for :func:`score`; none with ``mcap``.
///     route_id: The route, ``RouteScenario_<id>_rep<k>`` (``--route-id``).
///     mcap: A vehicle log instead of ``results`` (``--mcap``): an MCAP file or rosbag2 folder.
///     topics: The log's topics, ``"NAME=TOPIC"`` each, as for :func:`score`.
///     telemetry, routes, maps, profile, settings: As for :func:`score`.
///     duplicates: Which copy of a duplicated route id to read, as for :func:`score`.
///
/// Returns:
///     The frames, in order.
///
/// Warns:
///     SdsWarning: Each warning met reading the frames (``"<route>: <text>"``), at the caller's
///         line.
///
/// Raises:
///     InputError: No such route, an invalid record or log. ConfigError: A bad option or
///         setting, ``topics`` without ``mcap``, ``mcap`` with ``results``.
///
/// Example:
///     >>> f = sds.frames("results/", route_id="RouteScenario_1711_rep0", telemetry="eval/")  # doctest: +SKIP
///     >>> f[0]["host"]["step"]  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (results=None, *, route_id=None, mcap=None, topics=None, telemetry=None,
                    routes=None, maps=None, profile="physical", duplicates=None,
                    settings=None))]
#[allow(clippy::too_many_arguments)]
pub fn frames<'py>(
    py: Python<'py>,
    results: Option<Paths>,
    route_id: Option<String>,
    mcap: Option<PathBuf>,
    topics: Option<Strings>,
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    profile: &str,
    duplicates: Option<&str>,
    settings: Option<Overrides>,
) -> PyResult<Bound<'py, PyList>> {
    let run = Shared {
        profile,
        duplicates,
        settings,
        ..Shared::default()
    }
    .request()?;
    let request = FramesRequest {
        inputs: Inputs {
            results: results.map(Paths::into_vec).unwrap_or_default(),
            telemetry,
            route_xml: routes,
            maps,
        },
        settings: run,
        route_id,
        log: mcap,
        topics: topics
            .map(|t| t.list("topics"))
            .transpose()?
            .unwrap_or_default(),
    };
    let Frames { route_id, frames } = py
        .detach(|| request.frames())
        .map_err(|e| score_error(&e))?;
    let lines = frame_lines(&frames).map_err(SdsError::new_err)?;
    let text = String::from_utf8(lines).map_err(|e| SdsError::new_err(e.to_string()))?;
    // Python's own reader, so each number is the one `json.loads` reads from `sds frames`.
    let loads = py.import("json")?.getattr("loads")?;
    let out = PyList::empty(py);
    for line in text.lines().filter(|l| !l.is_empty()) {
        out.append(loads.call1((line,))?)?;
    }
    warn_each(
        py,
        frames.warnings.iter().map(|w| format!("{route_id}: {w}")),
    )?;
    Ok(out)
}
