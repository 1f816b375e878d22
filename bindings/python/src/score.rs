//! `sds.score`: the library's [`score_labelled`] called with [`Inputs`], [`Settings`] and
//! [`LabelFiles`] built from the keyword arguments, the report converted to Python objects
//! directly ([`crate::pyser`]). No command line in between.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use monitor_host::aggregate::groups::GroupBy;
use monitor_host::{score_labelled, Inputs, LabelFiles, NoProgress, Progress, Settings};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{run_error, ConfigError};
use crate::interrupt::with_signals;
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
            [
                GroupBy::Scenario,
                GroupBy::Family,
                GroupBy::Town,
                GroupBy::Weather,
                GroupBy::Route,
            ]
            .into_iter()
            .find(|b| b.name() == g)
            .ok_or_else(|| {
                ConfigError::new_err(format!(
                    "group_by={g:?}: expected one of scenario, family, town, weather, route"
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

/// The keyword arguments of `sds.score` beyond the shared ones ([`RunKwargs`]).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct ScoreKwargs {
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    group_by: Option<String>,
    labels: Option<PathBuf>,
    progress: bool,
}

/// Scores a run (see the Python `sds.score`, which passes its keyword arguments as the dict
/// `options`); returns the report as Python objects, keys in the JSON report's order. The GIL
/// is released while scoring.
#[pyfunction]
pub fn score<'py>(
    py: Python<'py>,
    results: Vec<PathBuf>,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    let settings: Settings = options.extract::<RunKwargs<'_>>()?.settings()?;
    let kw: ScoreKwargs = options.extract()?;
    let (by, files) = breakdown(kw.group_by.as_deref(), kw.labels)?;
    let inputs = Inputs {
        results,
        telemetry: kw.telemetry,
        route_xml: kw.routes,
        maps: kw.maps,
    };
    let progress = kw.progress;
    // Ctrl-C stops the run between routes and raises `KeyboardInterrupt` (`interrupt.rs`).
    let scored = py.detach(|| {
        let bar = progress.then(Bar::new);
        let inner: &dyn Progress = match &bar {
            Some(b) => b,
            None => &NoProgress,
        };
        let r = with_signals(inner, |p| score_labelled(&inputs, &settings, &files, by, p));
        if let Some(b) = bar {
            b.0.finish_and_clear();
        }
        r
    })?;
    let scored = scored.map_err(|e| run_error(&e))?;
    to_python(py, &scored.report)
}
