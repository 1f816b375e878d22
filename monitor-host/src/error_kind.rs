//! What kind of error stopped a run, for front ends ([`ErrorKind`]): the one classification of
//! every library error (as embedded-hal's `ErrorKind`, as rustls-ffi's single `map_error`). The
//! `sds` command's exit code and the Python package's exception class are each one match on it;
//! a new error variant is classified here once and both front ends follow.

use crate::error::Error;
use crate::geometry::map::MapError;
use crate::input::labels::LabelsError;
use crate::input::results_file::ResultsError;
use crate::input::route_xml::RouteError;
use crate::merge::MergeError;
use crate::pipeline::live::LiveError;
use crate::settings::SettingsError;
use crate::stats::CompareError;

named_enum! {
    /// The kind of an error. `#[non_exhaustive]`: a front end's match ends with a default arm,
    /// and a kind added later gets that arm until the front end learns it.
    ///
    /// | kind | what | `sds` exit code | Python exception |
    /// |---|---|---|---|
    /// | `io` | a file or folder cannot be read | 1 | `IoError` |
    /// | `input` | an input is invalid (results, route XML, map, labels, a tick, a record) | 1 | `InputError` |
    /// | `option` | an option or setting is invalid (unknown, out of range, a combination) | 2 | `ConfigError` |
    /// | `needs-labels` | a breakdown needs a label map that was not given | 2 | `NeedsLabelsError` |
    /// | `missing-folder` | a folder an option names does not exist or is not a folder | 2 | `IoError` |
    /// | `refused` | the inputs do not fit the options: nothing is scored until one is chosen | 2 | `RefusedError` |
    /// | `empty-run` | the inputs hold no record at all | 4 | `InputError` |
    /// | `cancelled` | cancelled (Ctrl-C) before the work was done | 1 | `KeyboardInterrupt` |
    /// | `internal` | the system refused a resource (the worker threads) | 1 | `SdsError` |
    ///
    /// ```
    /// use monitor_host::{ErrorKind, Settings};
    /// let e = Settings::default().set("nope", "1").unwrap_err();
    /// assert_eq!(e.kind(), ErrorKind::Option);
    /// assert_eq!(ErrorKind::from_name("refused"), Some(ErrorKind::Refused));
    /// ```
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    #[non_exhaustive]
    pub enum ErrorKind {
        /// A file or folder cannot be read (or a map file is a FIFO, a folder, a dangling link).
        Io = "io",
        /// An input is invalid: a results file, a route XML, a map, a labels file, a telemetry
        /// tick, a route's record.
        Input = "input",
        /// An option or setting is invalid: an unknown name, a value out of range, a combination
        /// that cannot be (a label map without the breakdown that reads it).
        Option = "option",
        /// A breakdown needs a label map that was not given (an [`ErrorKind::Option`] error of
        /// its own kind, so a front end can say which map).
        NeedsLabels = "needs-labels",
        /// A folder an option names (the telemetry root, the maps) does not exist or is not a
        /// folder.
        MissingFolder = "missing-folder",
        /// The inputs do not fit the options, and which way to go is the user's choice: route
        /// ids given twice under `duplicates = error`, N smaller than the routes counted, a
        /// label map that matches no route, a route XML without routes, report parts that
        /// disagree. Both an input and an option problem.
        Refused = "refused",
        /// The inputs hold no record at all: nothing to score.
        EmptyRun = "empty-run",
        /// Cancelled before the work was done (Ctrl-C).
        Cancelled = "cancelled",
        /// The system refused a resource the run needs (the worker threads).
        Internal = "internal",
    }
}

impl Error {
    /// The kind of this error (of the run's own error for [`Error::InRun`]).
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::Results(e) => e.kind(),
            Error::RouteXml(e) => e.kind(),
            Error::Map(e) => e.kind(),
            Error::Settings(e) => e.kind(),
            Error::Labels(e) => e.kind(),
            Error::Compare(e) => e.kind(),
            Error::InRun { error, .. } => error.kind(),
            Error::NoRoute { .. }
            | Error::AmbiguousRoute { .. }
            | Error::InvalidRecord { .. }
            | Error::Telemetry { .. } => ErrorKind::Input,
            // A log that cannot be opened is an I/O error, two logs of one name a refusal; any
            // other problem of a log is an input's (its route is listed invalid, with the
            // file, topic and fix).
            Error::VehicleLog(e) => e.kind(),
            Error::Duplicates(_) | Error::TooFewRoutes { .. } => ErrorKind::Refused,
            Error::TelemetryRoot { .. } | Error::MapsFolder { .. } => ErrorKind::MissingFolder,
            Error::EmptyRun { .. } => ErrorKind::EmptyRun,
            Error::Cancelled => ErrorKind::Cancelled,
            Error::Threads(_) => ErrorKind::Internal,
            Error::NeedsLabels(_) => ErrorKind::NeedsLabels,
            Error::UnusedLabels => ErrorKind::Option,
        }
    }
}

impl SettingsError {
    /// Always [`ErrorKind::Option`].
    pub fn kind(&self) -> ErrorKind {
        ErrorKind::Option
    }
}

impl crate::app::score::RequestError {
    /// Always [`ErrorKind::Option`]: a request refused before any work is the caller's.
    pub fn kind(&self) -> ErrorKind {
        ErrorKind::Option
    }
}

impl crate::app::run::rerun::RerunError {
    /// [`ErrorKind::Io`] for a route XML that cannot be read, [`ErrorKind::Input`] for
    /// malformed XML.
    pub fn kind(&self) -> ErrorKind {
        match self {
            crate::app::run::rerun::RerunError::Read { .. } => ErrorKind::Io,
            crate::app::run::rerun::RerunError::Xml { .. } => ErrorKind::Input,
        }
    }
}

impl crate::app::score::ScoreError {
    /// The refusal's or the run's kind; a table that cannot be built [`ErrorKind::Internal`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            crate::app::score::ScoreError::Request(e) => e.kind(),
            crate::app::score::ScoreError::Run(e) => e.kind(),
            crate::app::score::ScoreError::Tables(_) => ErrorKind::Internal,
        }
    }
}

impl crate::input::mcap::McapError {
    /// The kind of the error: a log that cannot be opened [`ErrorKind::Io`],
    /// two logs of one name [`ErrorKind::Refused`], a setting out of range
    /// [`ErrorKind::Option`], else [`ErrorKind::Input`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            crate::input::mcap::McapError::Unreadable { .. } => ErrorKind::Io,
            crate::input::mcap::McapError::Duplicate { .. } => ErrorKind::Refused,
            crate::input::mcap::McapError::Period { .. }
            | crate::input::mcap::McapError::MaxHold { .. }
            | crate::input::mcap::McapError::Options(_) => ErrorKind::Option,
            _ => ErrorKind::Input,
        }
    }
}

impl ResultsError {
    /// [`ErrorKind::Io`] for a file that cannot be read, else [`ErrorKind::Input`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            ResultsError::Io { .. } => ErrorKind::Io,
            _ => ErrorKind::Input,
        }
    }
}

impl RouteError {
    /// [`ErrorKind::Io`] for a file that cannot be read, [`ErrorKind::Refused`] for a file
    /// without a single route (not a route XML: every record would be a foreign route), else
    /// [`ErrorKind::Input`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            RouteError::Io { .. } => ErrorKind::Io,
            RouteError::NoRoutes { .. } => ErrorKind::Refused,
            _ => ErrorKind::Input,
        }
    }
}

impl MapError {
    /// [`ErrorKind::Io`] for a map that cannot be read, else [`ErrorKind::Input`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            MapError::Io { .. } => ErrorKind::Io,
            _ => ErrorKind::Input,
        }
    }
}

impl LabelsError {
    /// [`ErrorKind::Io`] for a file that cannot be read, [`ErrorKind::Refused`] for a map that
    /// matches no route or names the Safe2Drive paper instead of a file, else
    /// [`ErrorKind::Input`].
    pub fn kind(&self) -> ErrorKind {
        match self {
            LabelsError::Io { .. } => ErrorKind::Io,
            LabelsError::NoMatch { .. } | LabelsError::Safe2DriveFamilies { .. } => {
                ErrorKind::Refused
            }
            _ => ErrorKind::Input,
        }
    }
}

impl CompareError {
    /// [`ErrorKind::Cancelled`] for a cancelled comparison, else [`ErrorKind::Option`]: how
    /// the runs are compared is the caller's choice.
    pub fn kind(&self) -> ErrorKind {
        match self {
            CompareError::Cancelled => ErrorKind::Cancelled,
            _ => ErrorKind::Option,
        }
    }
}

impl MergeError {
    /// [`ErrorKind::Io`] for a part that cannot be read, [`ErrorKind::Option`] for a policy
    /// the merge cannot apply, else [`ErrorKind::Refused`] (parts that are not reports or do
    /// not fit together).
    pub fn kind(&self) -> ErrorKind {
        match self {
            MergeError::Read { .. } => ErrorKind::Io,
            MergeError::Policy(_) => ErrorKind::Option,
            _ => ErrorKind::Refused,
        }
    }
}

impl LiveError {
    /// [`ErrorKind::Io`] for a map that cannot be read or found, [`ErrorKind::Option`] for a
    /// set-up that cannot work (a maps folder without the town, the lane reference without a
    /// map), else [`ErrorKind::Input`] (a refused tick).
    pub fn kind(&self) -> ErrorKind {
        match self {
            LiveError::Map(e) => e.kind(),
            LiveError::NoMap(_) => ErrorKind::Io,
            LiveError::NeedsTown { .. } | LiveError::LaneWithoutMap => ErrorKind::Option,
            _ => ErrorKind::Input,
        }
    }
}

/// The options an error's message names, by their neutral names (the setting's or the option's
/// name, as the Python keywords spell them): a front end adds its own spelling of them (`sds`
/// appends its flags, `(--expected-routes, --route-subset)`).
///
/// ```
/// use monitor_host::error_kind::options;
/// use monitor_host::{Error, Settings};
/// let e = Error::from(Settings::default().apply(&["slack".into()]).unwrap_err());
/// assert_eq!(options(&e), ["set"]);
/// ```
pub fn options(e: &Error) -> &'static [&'static str] {
    match e {
        Error::InRun { error, .. } => options(error),
        Error::Settings(e) => settings_options(e),
        Error::AmbiguousRoute { .. } | Error::Duplicates(_) => &["duplicates"],
        Error::TooFewRoutes {
            from_option: true,
            missing,
            ..
        } if *missing > 0 => &["expected_routes", "route_subset"],
        Error::TooFewRoutes {
            from_option: true, ..
        } => &["expected_routes"],
        Error::TelemetryRoot {
            given_as: "telemetry",
            ..
        } => &["telemetry"],
        Error::MapsFolder { .. } => &["maps"],
        Error::UnusedLabels => &["labels", "group_by"],
        Error::NeedsLabels(n) if n.option == "families" => &["group_by", "families"],
        Error::NeedsLabels(_) => &["group_by", "labels"],
        Error::Labels(LabelsError::Safe2DriveFamilies { .. }) => &["families"],
        Error::Labels(LabelsError::NoMatch { option, .. }) => match *option {
            "families" => &["families"],
            "weathers" => &["weathers"],
            _ => &["labels"],
        },
        Error::RouteXml(RouteError::NoRoutes { .. }) => &["routes"],
        Error::Compare(e) => match e {
            CompareError::SeedOfTwo { .. } | CompareError::UnknownRun(_) => &["seeds"],
            CompareError::UnknownBaseline(..) => &["baseline"],
            CompareError::ProtocolNotAsked(..) => &["protocols"],
            CompareError::SamplesOutOfRange(_) | CompareError::DrawBudget { .. } => {
                &["bootstrap_samples"]
            }
            CompareError::HalfwidthOutOfRange(_) => &["repro.halfwidth"],
            CompareError::RouteSetsDiffer { .. } => &["common_routes", "routes"],
            CompareError::Sweep(_) => &["sweep"],
            _ => &[],
        },
        _ => &[],
    }
}

/// The options a warning's message names, by the library's neutral name, as [`options`] does
/// for errors: a front end adds its own spelling (`sds` appends `(--maps, --set dt=SECONDS)`).
/// A setting is named with the value it takes (`dt=SECONDS`).
///
/// ```
/// use monitor_host::error_kind::warning_options;
/// use monitor_host::warning::Warning;
/// let w = Warning::StepPeriodUnknown { span: 10, duration_game: 1.0, dt: 0.05 };
/// assert_eq!(warning_options(&w), ["dt=SECONDS"]);
/// ```
pub fn warning_options(w: &crate::input::warning::Warning) -> &'static [&'static str] {
    use crate::input::warning::Warning as W;
    match w {
        W::Route { warning, .. } => warning_options(warning),
        W::DuplicatesScored { .. }
        | W::DuplicatesDropped { .. }
        | W::NewestByOrder { .. }
        | W::NewestYearWrap { .. } => &["duplicates"],
        W::StepPeriodUnknown { .. } | W::StepPeriodPartial { .. } => &["dt=SECONDS"],
        W::NoTelemetry { .. } => &["telemetry", "allow_missing_telemetry"],
        W::AllGaps { .. } => &["gap_max=METRES"],
        W::NoMap {
            lane_fallback: true,
            ..
        }
        | W::NoMaps {
            lane_fallback: true,
            ..
        } => &["maps", "lateral_reference=route"],
        W::NoMap { .. } | W::NoMaps { .. } => &["maps"],
        W::MapNotServing {
            lane_fallback: true,
            ..
        } => &["lateral_reference=route"],
        W::LabelsMissKeys { .. } => &["labels"],
        W::Unmapped { .. } => &["group_by"],
        W::ForeignRoute { .. } => &["routes"],
        W::MinSpeedRegrouped { .. } => &["min_speed_grid=lb-4"],
        _ => &[],
    }
}

/// The options a settings error's message names, as [`options`].
pub fn settings_options(e: &SettingsError) -> &'static [&'static str] {
    match e {
        SettingsError::Syntax(_) => &["set"],
        SettingsError::Range {
            name: "threads", ..
        } => &["jobs"],
        _ => &[],
    }
}

/// The options a merge error's message names, as [`options`].
pub fn merge_options(e: &MergeError) -> &'static [&'static str] {
    match e {
        MergeError::Duplicate { .. } | MergeError::Policy(_) => &["duplicates"],
        MergeError::Groups { .. } => &["group_by"],
        MergeError::RouteSets { .. } => &["routes", "route_subset"],
        _ => &[],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_a_name_that_reads_back() {
        assert_eq!(ErrorKind::ALL.len(), ErrorKind::NAMES.len());
        for k in ErrorKind::ALL {
            assert_eq!(ErrorKind::from_name(k.name()), Some(*k));
        }
    }
}
