//! The error of a run: why [`crate::score_run`] produced no report at all. Problems of single
//! routes are not errors: they are route states and warnings in the report.

use crate::geometry::map::MapError;
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
    /// No record of this route in the results (for [`crate::route_frames`]).
    #[error("{}: no route {route}", file.display())]
    NoRoute {
        /// The (first) results file or directory.
        file: std::path::PathBuf,
        /// The route id looked for.
        route: String,
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
    /// The worker threads could not be started.
    #[error("cannot start the worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
}
