//! `sds.frames`: the library's [`FramesRequest`] built from the keyword arguments, the frames
//! as `sds frames` prints them (JSON lines, parsed by the Python layer).

use std::path::PathBuf;

use monitor_host::report::frames::frame_lines;
use monitor_host::Inputs;
use monitor_host::{Frames, FramesRequest};
use pyo3::prelude::*;

use crate::errors::{score_error, SdsError};
use crate::options::RunKwargs;

/// The frames of one route (see the Python `sds.frames`): their JSON lines, as `sds frames`
/// prints them, and the warnings met reading them (`"<route>: <text>"`, as the command prints
/// them after `sds: warning: `). The GIL is released while reading.
#[pyfunction]
#[pyo3(signature = (results, *, route_id=None, mcap=None, topics=Vec::new(), telemetry=None,
                    routes=None, maps=None, profile="physical".to_string(), duplicates=None,
                    settings=None))]
#[allow(clippy::too_many_arguments)]
pub fn frames(
    py: Python<'_>,
    results: Vec<PathBuf>,
    route_id: Option<String>,
    mcap: Option<PathBuf>,
    topics: Vec<String>,
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    profile: String,
    duplicates: Option<String>,
    settings: Option<Bound<'_, PyAny>>,
) -> PyResult<(String, Vec<String>)> {
    let run = RunKwargs {
        profile,
        duplicates,
        expected_routes: None,
        allow_missing_telemetry: false,
        settings,
        jobs: None,
        protocols: None,
        route_subset: None,
    }
    .request()?;
    let request = FramesRequest {
        inputs: Inputs {
            results,
            telemetry,
            route_xml: routes,
            maps,
        },
        settings: run,
        route_id,
        log: mcap,
        topics,
    };
    let Frames { route_id, frames } = py
        .detach(|| request.frames())
        .map_err(|e| score_error(&e))?;
    let lines = frame_lines(&frames).map_err(SdsError::new_err)?;
    let text = String::from_utf8(lines).map_err(|e| SdsError::new_err(e.to_string()))?;
    let warnings = frames
        .warnings
        .iter()
        .map(|w| format!("{route_id}: {w}"))
        .collect();
    Ok((text, warnings))
}
