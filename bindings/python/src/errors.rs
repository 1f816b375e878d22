//! The exception classes, and the host's typed errors mapped onto them. Every message is the
//! text the `sds` command prints after `sds: error: `.

use monitor_host::aggregate::groups::NeedsLabels;
use monitor_host::cli::{error_message, UnknownInfraction, UnusedLabels};
use monitor_host::geometry::map::MapError;
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

/// The exception for an error of [`monitor_host::score_run`].
pub fn run_error(e: &Error) -> PyErr {
    let msg = error_message(e);
    match e {
        Error::Results(ResultsError::Io { .. })
        | Error::RouteXml(RouteError::Io { .. })
        | Error::Map(MapError::Io { .. }) => IoError::new_err(msg),
        Error::TelemetryRoot { .. } | Error::MapsFolder { .. } => IoError::new_err(msg),
        Error::Settings(_) | Error::TooFewRoutes { .. } => ConfigError::new_err(msg),
        Error::Threads(_) => SdsError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}

/// The exception for an error of `sds score` ([`monitor_host::cli::score_report`]): the typed
/// error inside tells the class.
pub fn score_error(e: &anyhow::Error) -> PyErr {
    if let Some(e) = e.downcast_ref::<Error>() {
        return run_error(e);
    }
    if let Some(e) = e.downcast_ref::<LabelsError>() {
        return labels_error(e);
    }
    let msg = error_message(&**e);
    // The CLI's usage errors (exit 2).
    if e.downcast_ref::<NeedsLabels>().is_some() {
        return NeedsLabelsError::new_err(msg);
    }
    if e.downcast_ref::<SettingsError>().is_some()
        || e.downcast_ref::<UnusedLabels>().is_some()
        || e.downcast_ref::<UnknownInfraction>().is_some()
    {
        return ConfigError::new_err(msg);
    }
    SdsError::new_err(msg)
}

/// The exception for a labels file that cannot be used.
pub fn labels_error(e: &LabelsError) -> PyErr {
    let msg = error_message(e);
    match e {
        LabelsError::Io { .. } => IoError::new_err(msg),
        _ => InputError::new_err(msg),
    }
}
