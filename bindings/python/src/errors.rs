//! The exception classes, and the host's typed errors mapped onto them. Every message is the
//! text the `sds` command prints after `sds: error: `.

use monitor_host::app::request::{RequestError, ScoreError};
use monitor_host::error::message;
use monitor_host::geometry::map::MapError;
use monitor_host::pipeline::live::LiveError;
use monitor_host::{Error, LabelsError, ResultsError, RouteError, SettingsError};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::PyErr;

create_exception!(
    sds,
    SdsError,
    PyException,
    "Base class of every error the sds package raises."
);
create_exception!(
    sds,
    InputError,
    SdsError,
    "An input is invalid: a results file, route XML, labels file or telemetry frame."
);
create_exception!(
    sds,
    ConfigError,
    SdsError,
    "An option or setting is invalid (an unknown setting, a value out of range)."
);
create_exception!(
    sds,
    NeedsLabelsError,
    ConfigError,
    "A grouping needs a label map that was not given (`group_by=\"family\"` or `\"route\"` without `labels`)."
);
create_exception!(sds, IoError, SdsError, "A file or folder cannot be read.");
create_exception!(
    sds,
    FeatureUnavailableError,
    SdsError,
    "An option this build of sds does not have yet (its message names the feature)."
);

/// The exception for an error of [`monitor_host::score_run`] or
/// [`monitor_host::score_labelled`].
pub fn run_error(e: &Error) -> PyErr {
    let msg = message(e);
    match e {
        Error::Results(ResultsError::Io { .. })
        | Error::RouteXml(RouteError::Io { .. })
        | Error::Map(MapError::Io { .. }) => IoError::new_err(msg),
        Error::TelemetryRoot { .. } | Error::MapsFolder { .. } => IoError::new_err(msg),
        Error::Settings(_) | Error::TooFewRoutes { .. } | Error::UnusedLabels => {
            ConfigError::new_err(msg)
        }
        Error::NeedsLabels(_) => NeedsLabelsError::new_err(msg),
        Error::Labels(l) => labels_error(l),
        Error::Threads(_) => SdsError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}

/// The exception for settings the library refuses.
pub fn settings_error(e: &SettingsError) -> PyErr {
    ConfigError::new_err(message(e))
}

/// The exception for a labels file that cannot be used.
pub fn labels_error(e: &LabelsError) -> PyErr {
    let msg = message(e);
    match e {
        LabelsError::Io { .. } => IoError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}

/// The exception for a live monitor that cannot be set up, or a tick it refuses.
pub fn live_error(e: &LiveError) -> PyErr {
    let msg = message(e);
    match e {
        LiveError::Map(MapError::Io { .. }) | LiveError::NoMap(_) => IoError::new_err(msg),
        LiveError::NeedsTown { .. } | LiveError::LaneWithoutMap => ConfigError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}

/// A request refused before any work: always the caller's ([`ConfigError`]), the option named as
/// Python spells it.
pub fn request_error(e: &RequestError) -> PyErr {
    match e {
        RequestError::Settings(s) => settings_error(s),
        RequestError::Interval { given, bound } => {
            ConfigError::new_err(format!("interval={given}: {bound}"))
        }
        RequestError::Timeout { given, bound } => {
            ConfigError::new_err(format!("timeout={given}: {bound}"))
        }
        _ => ConfigError::new_err(message(e)),
    }
}

/// A request's error: refused ([`request_error`]), the run's ([`run_error`]), or a table.
pub fn score_error(e: &ScoreError) -> PyErr {
    match e {
        ScoreError::Request(r) => request_error(r),
        ScoreError::Run(r) => run_error(r),
        ScoreError::Tables(m) => SdsError::new_err(m.clone()),
    }
}
