//! The error of a run: why [`crate::score_run`] produced no report at all. Problems of single
//! routes are not errors: they are route states and warnings in the report.

use crate::aggregate::groups::NeedsLabels;
use crate::geometry::map::MapError;
use crate::input::duplicates::DuplicatesError;
use crate::input::labels::LabelsError;
use crate::input::results_file::ResultsError;
use crate::input::route_xml::RouteError;
use crate::settings::SettingsError;

/// Why a run produced no report. Every message names the file, setting or resource.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A results file or directory could not be read.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// The route XML could not be read.
    #[error(transparent)]
    RouteXml(#[from] RouteError),
    /// A town's OpenDRIVE map was found but cannot be read (naming the file and element).
    #[error(transparent)]
    Map(#[from] MapError),
    /// The settings are invalid.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// A vehicle log that cannot be read (`sds score --mcap`, `sds frames --mcap`).
    #[error(transparent)]
    VehicleLog(Box<crate::input::mcap::McapError>),
    /// No record of this route in the results (for [`crate::route_frames`]).
    #[error("{}: no route {route}", file.display())]
    NoRoute {
        /// The (first) results file or directory.
        file: std::path::PathBuf,
        /// The route id looked for.
        route: String,
    },
    /// Several records of this route are kept under `--duplicates all` (for
    /// [`crate::route_frames`], which prints one route).
    #[error(
        "{route}: {copies} records are scored under duplicates = all; choose one copy with \
         duplicates = first|last"
    )]
    AmbiguousRoute {
        /// The route id.
        route: String,
        /// Records kept with that id.
        copies: usize,
    },
    /// The route's record is invalid (for [`crate::route_frames`]).
    #[error("{route}: invalid record")]
    InvalidRecord {
        /// The route id.
        route: String,
    },
    /// The route's telemetry is missing or invalid (for [`crate::route_frames`]).
    #[error("{route}: telemetry {state}")]
    Telemetry {
        /// The route id.
        route: String,
        /// What is wrong with it.
        state: crate::pipeline::outcome::TelemetryState,
    },
    /// Route ids appear more than once under `duplicates: error` (docs/SCORE.md §14.1).
    #[error(transparent)]
    Duplicates(#[from] DuplicatesError),
    /// N is smaller than the routes counted in the aggregates (docs/SCORE.md §14.1).
    #[error(
        "N = {n} is smaller than the {counted} routes counted in the aggregates (a mean over N \
         would exceed its scale){}",
        too_few_hint(*n, *counted, *missing, *from_option)
    )]
    TooFewRoutes {
        /// N.
        n: usize,
        /// Routes counted (kept records that are not foreign, and missing routes).
        counted: usize,
        /// Of those, routes of the route XML without a record (counted as missing).
        missing: usize,
        /// N came from `--expected-routes`.
        from_option: bool,
    },
    /// The telemetry root does not exist or is not a folder.
    #[error(
        "{given_as} {}: {reason}; give the folder that holds the <save_name>/metric_info.json \
         folders",
        path.display()
    )]
    TelemetryRoot {
        /// How the folder was given: `--telemetry` (`sds score`), or a compared run's
        /// `RESULTS:TELEMETRY` / `--telemetry-of`.
        given_as: &'static str,
        /// The path given.
        path: std::path::PathBuf,
        /// Why it cannot be used.
        reason: String,
    },
    /// The `--maps` folder does not exist or is not a folder.
    #[error(
        "maps {}: {reason}; give the folder that holds the towns' OpenDRIVE maps \
         (Town01.xodr, ... or a CARLA install's Maps folder)",
        path.display()
    )]
    MapsFolder {
        /// The path given.
        path: std::path::PathBuf,
        /// Why it cannot be used.
        reason: String,
    },
    /// The inputs hold no record at all: nothing to score.
    #[error(
        "no records in {}: every results file is empty (a run that crashed before any route \
         finished?); nothing was scored",
        inputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    EmptyRun {
        /// The results inputs.
        inputs: Vec<std::path::PathBuf>,
    },
    /// The run was cancelled ([`crate::Progress::cancelled`], e.g. Ctrl-C in Python) before
    /// every route was scored: no report.
    #[error("cancelled before every route was scored: no report")]
    Cancelled,
    /// The worker threads could not be started.
    #[error("cannot start the worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    /// The runs cannot be compared (`sds compare`, docs/SCORE.md §10.3).
    #[error(transparent)]
    Compare(#[from] crate::stats::CompareError),
    /// One run of a comparison could not be scored.
    #[error("run {run}: {error}")]
    InRun {
        /// The run's name.
        run: String,
        /// Why.
        error: Box<Error>,
    },
    /// A label file cannot be read, or matches no route (for [`crate::ScoreRequest`]).
    #[error(transparent)]
    Labels(#[from] LabelsError),
    /// A breakdown needs a label map that was not given (for [`crate::ScoreRequest`]).
    #[error(transparent)]
    NeedsLabels(#[from] NeedsLabels),
    /// A route label map was given without the breakdown by route that reads it.
    #[error("labels is the route label map of group_by = route: give group_by = route with it")]
    UnusedLabels,
}

/// What to do about [`Error::TooFewRoutes`]: when the records alone fit in N and the rest are
/// the route XML's routes without a record (a partial run scored against the whole route file),
/// `--route-subset found` is what was meant; otherwise raise `--expected-routes` or drop it.
fn too_few_hint(n: usize, counted: usize, missing: usize, from_option: bool) -> String {
    if !from_option {
        String::new()
    } else if missing > 0 && counted - missing <= n {
        format!(
            "; {missing} of them are routes of the route XML without a record, counted as missing: \
             to score only the {} route(s) found, set route_subset = found (N is then the \
             routes found, or expected_routes), or leave expected_routes out",
            counted - missing
        )
    } else {
        "; raise expected_routes or leave it out".into()
    }
}

impl Error {
    /// The error itself, or the one a run of a comparison met ([`Error::InRun`]).
    pub fn inner(&self) -> &Error {
        match self {
            Error::InRun { error, .. } => error.inner(),
            e => e,
        }
    }
}

/// The text a front end shows for an error that stops it (`sds: error: <text>`, the Python
/// exceptions' message): the error and each of its causes, joined by `": "`, a cause that the
/// text already ends with written once.
///
/// ```
/// use monitor_host::input::results_file::read_results;
/// let e = read_results(std::path::Path::new("/nonexistent")).unwrap_err();
/// assert_eq!(monitor_host::error::message(&e),
///            "/nonexistent: cannot read: No such file or directory (os error 2)");
/// ```
pub fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let c_text = c.to_string();
        if !text.ends_with(&c_text) {
            text.push_str(": ");
            text.push_str(&c_text);
        }
        cause = c.source();
    }
    text
}
