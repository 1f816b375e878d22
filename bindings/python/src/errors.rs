//! The exception classes, and the host's errors mapped onto them: one match on the library's
//! [`ErrorKind`] ([`exception`]), as the `sds` command's exit code is. Every message is the text
//! the `sds` command prints after `sds: error: ` (without the command's option spellings).

use monitor_host::error::message;
use monitor_host::merge::MergeError;
use monitor_host::pipeline::live::LiveError;
use monitor_host::{Error, ErrorKind, SettingsError};
use monitor_host::{RequestError, ScoreError};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyboardInterrupt, PyUserWarning};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyType};

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

create_exception!(
    sds,
    SdsWarning,
    PyUserWarning,
    "A warning of the report (its `warnings`): a problem that did not stop scoring, as the `sds` command prints it after `sds: warning: `."
);

/// `RefusedError`: a subclass of both [`InputError`] and [`ConfigError`] (so code that caught
/// either before keeps catching it), made once per interpreter.
static REFUSED: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// The class `sds.RefusedError` ([`REFUSED`]).
pub fn refused_error(py: Python<'_>) -> PyResult<Bound<'_, PyType>> {
    let t = REFUSED.get_or_try_init(py, || -> PyResult<Py<PyType>> {
        let dict = PyDict::new(py);
        dict.set_item("__module__", "sds")?;
        dict.set_item(
            "__doc__",
            "The inputs do not fit the options (route ids given twice under \
             duplicates=\"error\", N smaller than the routes counted, a label map that matches \
             no route, report parts that disagree): both an InputError and a ConfigError.",
        )?;
        let bases = (py.get_type::<InputError>(), py.get_type::<ConfigError>());
        let class = py
            .get_type::<PyType>()
            .call1(("RefusedError", bases, dict))?
            .cast_into::<PyType>()?;
        Ok(class.unbind())
    })?;
    Ok(t.bind(py).clone())
}

/// The exception class of an error kind. Pinned, with the `sds` command's exit codes, by
/// `error_table` and the package's tests.
pub fn class(py: Python<'_>, kind: ErrorKind) -> PyResult<Bound<'_, PyType>> {
    Ok(match kind {
        ErrorKind::Io | ErrorKind::MissingFolder => py.get_type::<IoError>(),
        ErrorKind::Input | ErrorKind::EmptyRun => py.get_type::<InputError>(),
        ErrorKind::Option => py.get_type::<ConfigError>(),
        ErrorKind::NeedsLabels => py.get_type::<NeedsLabelsError>(),
        ErrorKind::Refused => refused_error(py)?,
        ErrorKind::Cancelled => py.get_type::<PyKeyboardInterrupt>(),
        // `Internal`, and a kind this package does not know yet.
        _ => py.get_type::<SdsError>(),
    })
}

/// The exception of an error of this kind with this message.
pub fn exception(kind: ErrorKind, msg: String) -> PyErr {
    Python::attach(|py| match class(py, kind) {
        Ok(t) => PyErr::from_type(t, msg),
        Err(e) => e,
    })
}

/// The exception for an error of the library's run-level functions (of the run's own error,
/// its message naming the run, for a run of a comparison).
pub fn run_error(e: &Error) -> PyErr {
    exception(e.kind(), message(e))
}

/// The exception for settings the library refuses.
pub fn settings_error(e: &SettingsError) -> PyErr {
    exception(e.kind(), message(e))
}

/// The exception for a merge that cannot be done.
pub fn merge_error(e: &MergeError) -> PyErr {
    exception(e.kind(), message(e))
}

/// The exception for a live monitor that cannot be set up, or a tick it refuses.
pub fn live_error(e: &LiveError) -> PyErr {
    exception(e.kind(), message(e))
}

/// Every error kind with the `sds` command's exit code and this package's exception class, for
/// the test that pins the table (`tests/test_errors.py`).
#[pyfunction]
pub fn error_table(py: Python<'_>) -> PyResult<Vec<(&'static str, i32, Bound<'_, PyType>)>> {
    ErrorKind::ALL
        .iter()
        .map(|k| Ok((k.name(), sds_cli::exit::code(*k), class(py, *k)?)))
        .collect()
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
        RequestError::StallFactor { given } => ConfigError::new_err(format!(
            "stall_factor={given}: expected a number above 0 (default {})",
            monitor_host::model::shard_stall::DEFAULT_FACTOR
        )),
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
