//! `sds.score`: the library's [`ScoreRequest`] built from the keyword arguments ([`Inputs`],
//! options, [`LabelFiles`]), the report converted to Python objects
//! directly ([`crate::pyser`]). No command line in between.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use monitor_host::aggregate::groups::GroupBy;
use monitor_host::ScoreRequest;
use monitor_host::{Inputs, LabelFiles, NoProgress, Progress};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{request_error, score_error, ConfigError};
use crate::interrupt::{with_signals, Hook};
use crate::options::RunKwargs;
use crate::pyser::to_python;

/// A progress bar on standard error (hidden when it is not a terminal), as the command draws.
struct Bar(ProgressBar);

impl Bar {
    fn new() -> Self {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} routes {elapsed_precise} eta {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Bar(bar)
    }
}

impl Progress for Bar {
    fn start(&self, routes: usize) {
        self.0.set_length(routes as u64);
    }
    fn route_done(&self) {
        self.0.inc(1);
    }
}

/// The grouping named `name`, and the label files with `labels` as its map.
pub(crate) fn breakdown(
    group_by: Option<&str>,
    labels: Option<PathBuf>,
) -> PyResult<(Option<GroupBy>, LabelFiles)> {
    let by = group_by
        .map(|g| {
            GroupBy::from_name(g).ok_or_else(|| {
                ConfigError::new_err(format!(
                    "group_by={g:?}: expected one of {}",
                    GroupBy::NAMES.join(", ")
                ))
            })
        })
        .transpose()?;
    let mut files = LabelFiles::default();
    if let Some(l) = labels {
        match by {
            Some(GroupBy::Family) => files.families = Some(l),
            Some(GroupBy::Weather) => files.weathers = Some(l),
            Some(GroupBy::Route) => files.routes = Some(l),
            _ => {
                return Err(ConfigError::new_err(
                    "labels: give group_by='family' (scenario families), 'weather' (weather \
                     names) or 'route' (labels of route ids)",
                ))
            }
        }
    }
    Ok((by, files))
}

/// The keyword arguments of `sds.score` (and `sds.watch`) beyond the shared ones
/// ([`RunKwargs`]).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct ScoreKwargs {
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    group_by: Option<String>,
    labels: Option<PathBuf>,
    /// `sds.score` only (`sds.watch` draws no bar): `True` (a bar), a callable ([`Hook`]), or
    /// `False` / `None`.
    #[pyo3(default)]
    progress: Option<Py<PyAny>>,
    /// `sds.score` only: vehicle logs scored instead of results.
    #[pyo3(default)]
    mcap: Option<Vec<PathBuf>>,
    /// `sds.score` only: the logs' topics, `NAME=TOPIC` each.
    #[pyo3(default)]
    topics: Option<Vec<String>>,
}

/// What `progress=` asks for.
pub(crate) enum Follow {
    Nothing,
    Bar,
    Call(Hook),
}

/// `progress=`: a bool (the bar or nothing), None, or a callable taking `(done, total)`.
pub(crate) fn follow(py: Python<'_>, progress: Option<&Py<PyAny>>, bars: bool) -> PyResult<Follow> {
    let Some(p) = progress else {
        return Ok(Follow::Nothing);
    };
    let p = p.bind(py);
    if p.is_none() {
        return Ok(Follow::Nothing);
    }
    if bars {
        if let Ok(b) = p.cast::<pyo3::types::PyBool>() {
            return Ok(if b.is_true() {
                Follow::Bar
            } else {
                Follow::Nothing
            });
        }
    }
    if p.is_callable() {
        return Ok(Follow::Call(Hook::new(p.clone().unbind())));
    }
    let expected = if bars {
        "True, False or a callable taking (done, total)"
    } else {
        "None or a callable taking (done, total)"
    };
    Err(ConfigError::new_err(format!(
        "progress={}: expected {expected}",
        p.repr().map_or_else(|_| "?".into(), |r| r.to_string())
    )))
}

/// Scores a run (see the Python `sds.score`, which passes its keyword arguments as the dict
/// `options`): the library's [`ScoreRequest`]; returns the report as Python objects, keys in
/// the JSON report's order. The GIL is released while scoring.
#[pyfunction]
pub fn score<'py>(
    py: Python<'py>,
    results: Vec<PathBuf>,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let kw: ScoreKwargs = options.extract()?;
    let request = score_request(results, options, &kw)?;
    // Settings refused before the run starts, as before any work.
    request.validate().map_err(|e| request_error(&e))?;
    let follow = follow(py, kw.progress.as_ref(), true)?;
    // Ctrl-C stops the run between routes and raises `KeyboardInterrupt` (`interrupt.rs`).
    let scored = py.detach(|| {
        let bar = matches!(follow, Follow::Bar).then(Bar::new);
        let inner: &dyn Progress = match (&bar, &follow) {
            (Some(b), _) => b,
            (None, Follow::Call(h)) => h,
            _ => &NoProgress,
        };
        let r = with_signals(inner, |p| request.score(p));
        if let Some(b) = bar {
            b.0.finish_and_clear();
        }
        r
    })?;
    // The callable's exception (it stopped the run) before the run's own error.
    if let Follow::Call(h) = &follow {
        if let Some(e) = h.take_error() {
            return Err(e);
        }
    }
    let scored = scored.map_err(|e| score_error(&e))?;
    to_python(py, &scored.report)
}

/// The request of `sds.score`'s (or `sds.watch`'s) keyword arguments.
pub(crate) fn score_request(
    results: Vec<PathBuf>,
    options: &Bound<'_, PyDict>,
    kw: &ScoreKwargs,
) -> PyResult<ScoreRequest> {
    let settings = options.extract::<RunKwargs<'_>>()?.request()?;
    let (group_by, labels) = breakdown(kw.group_by.as_deref(), kw.labels.clone())?;
    Ok(ScoreRequest {
        inputs: Inputs {
            results,
            telemetry: kw.telemetry.clone(),
            route_xml: kw.routes.clone(),
            maps: kw.maps.clone(),
        },
        settings,
        labels,
        group_by,
        infractions: Vec::new(),
        logs: kw.mcap.clone().unwrap_or_default(),
        topics: kw.topics.clone().unwrap_or_default(),
    })
}
