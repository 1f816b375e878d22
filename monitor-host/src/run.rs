//! Scoring a run: the one entry point every front end calls (the `sds` binary, tests, and the
//! Python and C bindings to come).

use std::path::PathBuf;

use rayon::prelude::*;

use crate::error::Error;
use crate::geometry::junctions::TownMaps;
use crate::input::record::{InvalidRecord, LoadedRecord};
use crate::input::results_file::read_results;
use crate::input::route_xml::read_route_xml;
use crate::pipeline::replay::{read_telemetry, replay};
use crate::report::model::{build, Report};
use crate::settings::Settings;
use crate::warning::Warning;
use monitor_core::Frame;

/// The files of a run.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Inputs {
    /// Results: raw evaluator files, merged files, or directories of per-route files, read in
    /// this order.
    pub results: Vec<PathBuf>,
    /// Telemetry root holding `<save_name>/metric_info.json`.
    pub telemetry: Option<PathBuf>,
    /// Bench2Drive route XML (the lateral reference, the route set and the abilities' scenario
    /// types).
    pub route_xml: Option<PathBuf>,
    /// Folder of the towns' OpenDRIVE maps (§1.4).
    pub maps: Option<PathBuf>,
}

impl Inputs {
    /// Inputs with these results files and nothing else.
    pub fn new<I: IntoIterator<Item = P>, P: Into<PathBuf>>(results: I) -> Self {
        Inputs {
            results: results.into_iter().map(Into::into).collect(),
            ..Inputs::default()
        }
    }
}

/// Hears how far a run is: [`Progress::start`] once with the number of routes, then
/// [`Progress::route_done`] once per route, from the worker threads. For a progress bar, or for
/// bindings that report progress or check for interruption.
pub trait Progress: Sync {
    /// The routes are read: `routes` will be scored.
    fn start(&self, routes: usize) {
        let _ = routes;
    }
    /// One more route is scored (called from a worker thread, in any order).
    fn route_done(&self) {}
}

/// A [`Progress`] that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// Scores a run: reads the results (and the route XML), replays every route through the
/// streaming monitor on a thread pool, checks it against the batch reference, and builds the
/// report. See [`score_run_with`] to follow the progress.
///
/// A front end decides its exit status from the report's data ([`Report::has_problems`],
/// [`Report::problem_routes`]), never from its rendering.
///
/// ```
/// use monitor_host::{demo, score_run, Inputs, Settings};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs {
///     telemetry: Some(run.telemetry),
///     route_xml: Some(run.routes),
///     ..Inputs::new([run.results])
/// };
/// let report = score_run(&inputs, &Settings::default())?;
/// assert_eq!(report.routes.len(), run.route_ids.len());
/// assert!(report.summary.sds.is_some());
/// assert!(!report.has_problems());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`Error`] when no report can be made: invalid settings, unreadable results or route XML.
pub fn score_run(inputs: &Inputs, settings: &Settings) -> Result<Report, Error> {
    score_run_with(inputs, settings, &NoProgress)
}

/// [`score_run`], telling `progress` how far it is.
///
/// # Errors
/// As [`score_run`].
pub fn score_run_with(
    inputs: &Inputs,
    settings: &Settings,
    progress: &dyn Progress,
) -> Result<Report, Error> {
    settings.validate()?;
    let mut records = Vec::new();
    let mut warnings = Vec::new();
    for path in &inputs.results {
        let set = read_results(path)?;
        warnings.extend(set.warnings);
        records.extend(set.records);
        // A results file that cannot be read still appears, as an invalid entry: its routes
        // are unknown, but nothing found is silently lost.
        records.extend(
            set.broken_files
                .into_iter()
                .map(|(source, reason)| LoadedRecord {
                    source,
                    index: 0,
                    records_in_file: 0,
                    entry: Err(InvalidRecord {
                        route_id: None,
                        reason,
                    }),
                }),
        );
    }
    let routes = inputs
        .route_xml
        .as_deref()
        .map(read_route_xml)
        .transpose()?;
    if let Some(expected) = settings.expected_routes {
        if expected < records.len() {
            warnings.push(Warning::ExpectedRoutesTooSmall {
                expected,
                found: records.len(),
            });
        }
    }

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.threads.unwrap_or(0))
        .build()?;
    progress.start(records.len());
    let telemetry = inputs.telemetry.as_deref();
    let outcomes: Vec<_> = pool.install(|| {
        records
            .par_iter()
            .map(|r| {
                let o = replay(r, routes.as_ref(), telemetry, settings);
                progress.route_done();
                o
            })
            .collect()
    });
    let maps = TownMaps::new(inputs.maps.clone());
    let report = build(&outcomes, settings, warnings, routes.as_ref(), &maps);
    match maps.into_broken() {
        Some(e) => Err(e.into()),
        None => Ok(report),
    }
}

/// The monitor's input frames of one route, as [`score_run`] would stream them, and the warnings
/// met while reading its telemetry.
#[derive(Clone, Debug, PartialEq)]
pub struct RouteFrames {
    /// One frame per telemetry step, in step order.
    pub frames: Vec<Frame>,
    /// Problems that did not stop the frames from being made.
    pub warnings: Vec<Warning>,
}

/// The frames of the route `route_id` (`RouteScenario_<id>_rep<k>`): the first valid record
/// with this id in the results, its telemetry read and prepared.
///
/// # Errors
/// As [`score_run`], or [`Error::NoRoute`], [`Error::InvalidRecord`], [`Error::Telemetry`].
pub fn route_frames(
    inputs: &Inputs,
    route_id: &str,
    settings: &Settings,
) -> Result<RouteFrames, Error> {
    settings.validate()?;
    let mut records = Vec::new();
    for path in &inputs.results {
        records.extend(read_results(path)?.records);
    }
    let routes = inputs
        .route_xml
        .as_deref()
        .map(read_route_xml)
        .transpose()?;
    let loaded = records
        .into_iter()
        .find(|r| r.entry.as_ref().is_ok_and(|r| r.route_id == route_id))
        .ok_or_else(|| Error::NoRoute {
            file: inputs.results.first().cloned().unwrap_or_default(),
            route: route_id.into(),
        })?;
    let Ok(record) = &loaded.entry else {
        return Err(Error::InvalidRecord {
            route: route_id.into(),
        });
    };
    let mut warnings = Vec::new();
    let telemetry = read_telemetry(
        &loaded,
        record,
        routes.as_ref(),
        inputs.telemetry.as_deref(),
        settings,
        &mut warnings,
    )
    .map_err(|state| Error::Telemetry {
        route: route_id.into(),
        state,
    })?;
    Ok(RouteFrames {
        frames: telemetry.prepared.frames,
        warnings,
    })
}
