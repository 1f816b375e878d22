//! `sds.score`: the library's [`ScoreRequest`] built from the typed keyword arguments
//! ([`Inputs`], the shared options of `options.rs`, [`LabelFiles`]), the report converted to
//! Python objects directly ([`crate::pyser`]), its warnings raised as `sds.SdsWarning` at the
//! caller's line. No command line in between.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use monitor_host::aggregate::groups::GroupBy;
use monitor_host::settings::LateralReference;
use monitor_host::{Inputs, LabelFiles, NoProgress, Progress, RunSettings, ScoreRequest};
use pyo3::prelude::*;

use crate::errors::{request_error, score_error, ConfigError};
use crate::interrupt::{with_signals, Hook};
use crate::options::{named, warn_report, Overrides, Paths, Shared, Strings};
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
        .map(|g| named("group_by", g, GroupBy::from_name, GroupBy::choices))
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

/// What `progress=` asks for.
pub(crate) enum Follow {
    Nothing,
    Bar,
    Call(Hook),
}

/// `progress=`: a bool (the bar or nothing), None, or a callable taking `(done, total)`.
pub(crate) fn follow(progress: Option<&Bound<'_, PyAny>>, bars: bool) -> PyResult<Follow> {
    let Some(p) = progress else {
        return Ok(Follow::Nothing);
    };
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

/// What a scored run reads beside its settings (`sds.score`'s and `sds.watch`'s arguments).
pub(crate) struct Run<'a> {
    /// Results files or folders (none with `mcap`).
    pub results: Option<Paths>,
    /// The telemetry root.
    pub telemetry: Option<PathBuf>,
    /// The route XML.
    pub routes: Option<PathBuf>,
    /// The OpenDRIVE maps.
    pub maps: Option<PathBuf>,
    /// The grouping's name.
    pub group_by: Option<&'a str>,
    /// Its label map.
    pub labels: Option<PathBuf>,
    /// Vehicle logs scored instead of results.
    pub mcap: Option<Paths>,
    /// The logs' topics, `NAME=TOPIC` each.
    pub topics: Option<Strings>,
}

impl Run<'_> {
    /// The library's request of this run under `settings`.
    pub(crate) fn request(self, settings: RunSettings) -> PyResult<ScoreRequest> {
        let (group_by, labels) = breakdown(self.group_by, self.labels)?;
        Ok(ScoreRequest {
            inputs: Inputs {
                results: self.results.map(Paths::into_vec).unwrap_or_default(),
                telemetry: self.telemetry,
                route_xml: self.routes,
                maps: self.maps,
            },
            settings,
            labels,
            group_by,
            infractions: Vec::new(),
            logs: self.mcap.map(Paths::into_vec).unwrap_or_default(),
            topics: self
                .topics
                .map(|t| t.list("topics"))
                .transpose()?
                .unwrap_or_default(),
        })
    }
}

/// Scores a run; returns the report of ``sds score --format json`` as a dict.
///
/// The library is called directly (no command line in between) and the report converted to
/// Python objects as ``json.loads`` would read the JSON report, keys in its order. Every route
/// is replayed through the streaming monitor (on ``jobs`` threads, default all cores, with the
/// GIL released) and checked against the batch reference.
///
/// Args:
///     results: Evaluator results: a raw file, a merged file, or a folder of per-route files;
///         or a list of them (``--results``, repeated).
///     telemetry: The folder holding ``<save_name>/metric_info.json`` (``--telemetry``).
///     routes: Bench2Drive's route XML, the lateral reference (``--routes``).
///     maps: A folder of CARLA OpenDRIVE maps (``--maps``).
///     profile: ``"physical"``, ``"b2d-legacy"`` or ``"autoware"`` (``--profile``).
///     duplicates: Routes recorded more than once: ``"error"`` (score nothing, name them),
///         keep the ``"first"`` or ``"last"`` copy or the ``"newest"`` run, or score ``"all"``
///         (``--duplicates``).
///     expected_routes: The benchmark's size N, e.g. 220 (``--expected-routes``).
///     allow_missing_telemetry: Score routes without telemetry without telemetry terms.
///     settings: Overrides, e.g. ``{"slack": 0.9, "bounds.yaw_rate": 1.0}`` (``--set``; names
///         are those of the report's ``config`` block).
///     group_by: The breakdown (the report's ``groups``): ``scenario``, ``family``, ``town``,
///         ``weather`` or ``route`` (``--group-by``).
///     labels: The label map of the grouping, read and checked here: scenario type -> family
///         for ``family`` (``--families``), weather id -> label for ``weather``
///         (``--weathers``), route id -> label for ``route`` (``--labels``; keys ``"1711"``,
///         ``"RouteScenario_1711"`` or ``"RouteScenario_1711_rep0"``, e.g. a difficulty or
///         train/test split). ``family`` and ``route`` need one.
///     jobs: Worker threads (``--jobs``).
///     progress: ``True``: draw a progress bar on standard error (when it is a terminal). A
///         callable: called with ``(done, total)`` after each route (from the worker threads,
///         one call at a time), e.g. to drive a notebook's bar; an exception it raises stops
///         the run between routes and is raised here. ``None`` or ``False``: nothing.
///     protocols: Also score every route under these scoring protocols: ids among ``"b2d"``,
///         ``"lb2.0"``, ``"lb2.1"``, ``"lead-nds"``, ``"f2d"``, or ``["all"]`` (``--protocol``;
///         the report's per-route and summary ``protocols``). The recorded events under other
///         arithmetic, not a re-run.
///     route_subset: Which routes of ``routes`` make the route set (``--route-subset``):
///         ``"all"`` (every route of the XML; one without a record counts as 0) or ``"found"``
///         (those with a record: a run of 20 routes scored over 20). None: the setting
///         ``route_subset`` (default ``"all"``, or from ``settings``).
///     lateral_reference: What the lateral error is measured against
///         (``--lateral-reference``): ``"route"`` (the route polyline, its junction gaps filled
///         by the map) or ``"lane"`` (the nearest driving lane of the map; a town without a map
///         falls back to the route, with a warning). None: the setting ``lateral_reference``
///         (default ``"route"``, or from ``settings``).
///     mcap: Vehicle logs scored instead of ``results`` (``--mcap``): MCAP files of ROS 2
///         messages or rosbag2 folders, each one route named by its file stem. The report
///         holds no driving score, success rate, DS_safe or SDS (a log has no Leaderboard
///         record; its warnings say so).
///     topics: The logs' topics, ``"NAME=TOPIC"`` each (``--topic``): ``pose=/odom``,
///         ``imu=/imu``, ``event=TOPIC``, ``path=TOPIC``; defaults ``pose=/odom``, ``imu=/imu``.
///
/// Returns:
///     The report (``schema``, ``profile``, ``config``, ``routes``, ``summary``, ``warnings``).
///     Routes with problems are in it with their ``state``; the CLI would exit with 3.
///
/// Warns:
///     SdsWarning: Each of the report's ``warnings`` (what ``sds score`` prints as
///         ``sds: warning: ...``), at the caller's line.
///
/// Raises:
///     InputError: A results file, the route XML or a labels file is invalid; the inputs hold no
///         record.
///     IoError: A file or folder cannot be read (a ``telemetry`` folder that does not exist).
///     ConfigError: An option or setting is invalid (an unknown ``profile``, ``duplicates``,
///         ``route_subset`` or ``group_by``; one string for ``protocols`` or ``topics``); its
///         subclass :class:`NeedsLabelsError`: ``group_by="family"`` or ``"route"`` without
///         ``labels``.
///     RefusedError: The inputs do not fit the options (an :class:`InputError` and a
///         :class:`ConfigError`): route ids duplicated under ``duplicates="error"``,
///         ``expected_routes`` below the routes counted, a label map that matches no route.
///
/// Example:
///     >>> report = sds.score("results/", telemetry="eval/", routes="bench2drive220.xml")  # doctest: +SKIP
///     >>> report["summary"]["sds"]  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (results=None, *, telemetry=None, routes=None, maps=None, profile="physical",
                    duplicates="error", expected_routes=None, allow_missing_telemetry=false,
                    settings=None, group_by=None, labels=None, jobs=None, progress=None,
                    protocols=None, route_subset=None, lateral_reference=None, mcap=None,
                    topics=None))]
#[allow(clippy::too_many_arguments)]
pub fn score<'py>(
    py: Python<'py>,
    results: Option<Paths>,
    telemetry: Option<PathBuf>,
    routes: Option<PathBuf>,
    maps: Option<PathBuf>,
    profile: &str,
    duplicates: &str,
    expected_routes: Option<usize>,
    allow_missing_telemetry: bool,
    settings: Option<Overrides>,
    group_by: Option<&str>,
    labels: Option<PathBuf>,
    jobs: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    protocols: Option<Strings>,
    route_subset: Option<&str>,
    lateral_reference: Option<&str>,
    mcap: Option<Paths>,
    topics: Option<Strings>,
) -> PyResult<Bound<'py, PyAny>> {
    let settings = RunSettings {
        lateral_reference: lateral_reference
            .map(|r| {
                named(
                    "lateral_reference",
                    r,
                    LateralReference::from_name,
                    LateralReference::choices,
                )
            })
            .transpose()?,
        ..Shared {
            profile,
            duplicates: Some(duplicates),
            expected_routes,
            allow_missing_telemetry,
            settings,
            jobs,
            protocols,
            route_subset,
        }
        .request()?
    };
    let request = Run {
        results,
        telemetry,
        routes,
        maps,
        group_by,
        labels,
        mcap,
        topics,
    }
    .request(settings)?;
    // Settings refused before the run starts, as before any work.
    request.validate().map_err(|e| request_error(&e))?;
    let follow = follow(progress.as_ref(), true)?;
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
    let report = to_python(py, &scored.report)?;
    warn_report(&report)?;
    Ok(report)
}
