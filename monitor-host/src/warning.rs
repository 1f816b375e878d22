//! Warnings: problems that do not stop a run or a route from being scored. Typed, naming the
//! file and route they concern; the report prints them with [`std::fmt::Display`].

use std::path::PathBuf;

use crate::input::collision::CollisionList;
use crate::input::route_xml::RouteError;

/// One warning. Run-level warnings sit in [`crate::Report::warnings`], route-level ones in
/// each route's `warnings`.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// A results file with no records (a crashed or empty run).
    NoRecords {
        /// The results file.
        file: PathBuf,
        /// Its `entry_status`, if any.
        entry_status: Option<String>,
        /// Its `progress`, as written (`[0, 220]`), if any.
        progress: Option<String>,
        /// The run stopped before any route finished.
        crashed: bool,
    },
    /// Fewer records than the file's `progress` total: the run did not finish.
    Unfinished {
        /// The results file.
        file: PathBuf,
        /// Its `progress`, as written.
        progress: String,
        /// Records found.
        recorded: usize,
        /// The progress total.
        total: u64,
    },
    /// A merged file's stored totals could not be read.
    StoredTotalsIgnored {
        /// The merged file.
        file: PathBuf,
        /// Why.
        reason: String,
    },
    /// A record with a status the evaluator does not write.
    UnknownStatus {
        /// The results file.
        file: PathBuf,
        /// The record's index in it.
        index: usize,
        /// The route id.
        route: String,
        /// The status.
        status: String,
    },
    /// A results file in a directory that could not be read (it is reported as an invalid
    /// route).
    UnreadableResults {
        /// The full reason, naming the file.
        reason: String,
    },
    /// A merged file skipped because raw evaluator files lie beside it.
    MergedSkipped {
        /// The merged file.
        file: PathBuf,
        /// How many raw files were found.
        raw_files: usize,
    },
    /// A folder that could not be listed.
    CannotList {
        /// The folder.
        dir: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// A directory entry that could not be read (e.g. a dangling link).
    CannotRead {
        /// The entry.
        path: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// Two records with the same route id (both are kept as separate routes).
    DuplicateRoute {
        /// The route id.
        route: String,
        /// The first record: file and index.
        first: (PathBuf, usize),
        /// The later record: file and index.
        second: (PathBuf, usize),
    },
    /// `expected_routes` is smaller than the routes found.
    ExpectedRoutesTooSmall {
        /// The setting.
        expected: usize,
        /// Routes found.
        found: usize,
    },
    /// LEAD's `infractions.json` beside the telemetry is unreadable.
    LeadInfractions {
        /// The file.
        file: PathBuf,
        /// Why.
        reason: String,
    },
    /// The route XML has no usable reference for this route.
    NoReference(RouteError),
    /// A collision string that does not parse.
    UnparseableCollision {
        /// Its list.
        list: CollisionList,
        /// Why.
        reason: String,
    },
    /// Routes whose group key has no label in the label map: grouped as `(unmapped)` (§8.3).
    Unmapped {
        /// The grouping (`family`, `weather`).
        by: &'static str,
        /// The first few keys that matched nothing.
        keys: Vec<String>,
        /// Routes concerned.
        routes: usize,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::NoRecords {
                file,
                entry_status,
                progress,
                crashed,
            } => {
                write!(f, "{}: no records", file.display())?;
                let details: Vec<String> = entry_status
                    .iter()
                    .map(|s| format!("entry_status {s}"))
                    .chain(progress.iter().map(|p| format!("progress {p}")))
                    .collect();
                if !details.is_empty() {
                    write!(f, " ({})", details.join(", "))?;
                }
                if *crashed {
                    f.write_str(": the run crashed before any route finished")?;
                }
                Ok(())
            }
            Warning::Unfinished {
                file,
                progress,
                recorded,
                total,
            } => write!(
                f,
                "{}: progress {progress} but only {recorded} of {total} routes recorded: the run \
                 did not finish",
                file.display()
            ),
            Warning::StoredTotalsIgnored { file, reason } => {
                write!(f, "{}: stored totals ignored: {reason}", file.display())
            }
            Warning::UnknownStatus {
                file,
                index,
                route,
                status,
            } => write!(
                f,
                "{}: record {index} ({route}): unknown status {status:?} (counted as not \
                 successful)",
                file.display()
            ),
            Warning::UnreadableResults { reason } => {
                write!(f, "skipped unreadable results file: {reason}")
            }
            Warning::MergedSkipped { file, raw_files } => write!(
                f,
                "{}: skipped: a Bench2Drive merged file (has \"driving score\") beside {raw_files} \
                 raw evaluator file(s); reading both would count its routes twice",
                file.display()
            ),
            Warning::CannotList { dir, reason } => {
                write!(f, "{}: cannot list: {reason}", dir.display())
            }
            Warning::CannotRead { path, reason } => {
                write!(f, "{}: cannot read: {reason}", path.display())
            }
            Warning::DuplicateRoute {
                route,
                first,
                second,
            } => write!(
                f,
                "duplicate route id {route}: record {} of {} and record {} of {} (both kept as \
                 separate routes)",
                first.1,
                first.0.display(),
                second.1,
                second.0.display()
            ),
            Warning::ExpectedRoutesTooSmall { expected, found } => write!(
                f,
                "--expected-routes {expected} is smaller than the {found} routes found"
            ),
            Warning::LeadInfractions { file, reason } => write!(
                f,
                "{}: {reason}; collisions aligned by position instead",
                file.display()
            ),
            Warning::NoReference(e) => write!(f, "{e}: lateral excess unknown for this route"),
            Warning::UnparseableCollision { list, reason } => write!(
                f,
                "{}: unparseable collision string ({reason}): counted, not aligned",
                list.name()
            ),
            Warning::Unmapped { by, keys, routes } => write!(
                f,
                "--group-by {by}: {routes} route(s) whose key has no label are grouped as \
                 \"(unmapped)\"; keys without a label: {}",
                keys.join(", ")
            ),
        }
    }
}

impl serde::Serialize for Warning {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}
