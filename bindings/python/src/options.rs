//! The typed keyword arguments the package's functions share (`sds.score`, `sds.frames`,
//! `sds.compare`, `sds.watch`, `sds.merge`, `sds.link`): each function's `#[pyo3(signature)]`
//! names them, pyo3 converts them with the types below, and [`Shared::request`] maps them to
//! the library's [`RunSettings`] ([`RunSettings::settings`], as the command line's options are).
//! A name (`profile="physical"`) is read with the library's own names (`from_name`), and a
//! refusal lists the library's `choices()`, never a list spelled here.

use std::path::PathBuf;

use monitor_core::Profile;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::input::route_set::RouteSubset;
use monitor_host::named::choices;
use monitor_host::RunSettings;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyString};

use crate::errors::ConfigError;

/// One path or a list of paths (`results="run.json"`, `results=["a/", "b/"]`): a `str` or an
/// `os.PathLike`, or a sequence of them.
#[derive(FromPyObject)]
pub enum Paths {
    /// One path.
    One(PathBuf),
    /// Several, in order.
    Many(Vec<PathBuf>),
}

impl Paths {
    /// The paths, in order.
    pub fn into_vec(self) -> Vec<PathBuf> {
        match self {
            Paths::One(p) => vec![p],
            Paths::Many(v) => v,
        }
    }
}

/// A list of strings (`protocols=["lb2.1"]`); one string is kept aside and refused by
/// [`Strings::list`], which knows the option's name (it would read as a list of characters).
pub enum Strings {
    /// The list.
    List(Vec<String>),
    /// One string, as Python shows it (`'all'`).
    One(String),
}

impl<'a, 'py> FromPyObject<'a, 'py> for Strings {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if ob.is_instance_of::<PyString>() {
            return Ok(Strings::One(ob.repr()?.to_string()));
        }
        Ok(Strings::List(ob.extract()?))
    }
}

impl Strings {
    /// The list, or a [`ConfigError`] naming `option` for one string.
    pub fn list(self, option: &str) -> PyResult<Vec<String>> {
        match self {
            Strings::List(v) => Ok(v),
            Strings::One(s) => Err(ConfigError::new_err(format!(
                "{option}={s}: expected a list, e.g. [{s}]"
            ))),
        }
    }
}

/// A settings mapping (`{"slack": 0.9, "bounds.yaw_rate": 1.0}`) as the `(name, value)` pairs
/// the command line's `--set NAME=VALUE` gives (`True` → `true`, `0.9` → `0.9`), in order.
pub struct Overrides(pub Vec<(String, String)>);

impl<'a, 'py> FromPyObject<'a, 'py> for Overrides {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        Ok(Overrides(setting_pairs(Some(&ob.to_owned()))?))
    }
}

/// A value as the command line's text takes it: `True` → `true`, else `str(value)`.
pub fn text(v: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(match v.cast::<PyBool>() {
        Ok(b) => b.is_true().to_string(),
        Err(_) => v.str()?.to_string(),
    })
}

/// `(name, value)` pairs of a settings mapping, each value as the text the command line's
/// `--set NAME=VALUE` takes ([`text`]).
pub fn setting_pairs(settings: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, String)>> {
    let Some(map) = settings else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for item in map.call_method0("items")?.try_iter()? {
        let (k, v): (String, Bound<'_, PyAny>) = item?.extract()?;
        out.push((k, text(&v)?));
    }
    Ok(out)
}

/// The value of `option` named `value` (`from_name`), or a [`ConfigError`] listing the
/// library's choices: `profile="fast": expected physical, b2d-legacy or autoware`.
pub fn named<T>(
    option: &str,
    value: &str,
    from_name: impl Fn(&str) -> Option<T>,
    choices: impl Fn() -> String,
) -> PyResult<T> {
    from_name(value)
        .ok_or_else(|| ConfigError::new_err(format!("{option}={value:?}: expected {}", choices())))
}

/// The profile named `name` ([`Profile::ALL`]'s names).
fn profile(name: &str) -> PyResult<Profile> {
    named(
        "profile",
        name,
        |n| Profile::ALL.into_iter().find(|p| p.name() == n),
        || choices(&Profile::ALL.map(Profile::name)),
    )
}

/// The keyword arguments of a scored run (`sds.score`, `sds.compare`, `sds.watch`,
/// `sds.frames`, `sds.link`), as each function's signature received them.
#[derive(Default)]
pub struct Shared<'a> {
    /// A profile's name.
    pub profile: &'a str,
    /// A duplicate policy's name; None: the setting's default or a `settings` override.
    pub duplicates: Option<&'a str>,
    /// Benchmark size N.
    pub expected_routes: Option<usize>,
    /// Score routes without telemetry without telemetry terms.
    pub allow_missing_telemetry: bool,
    /// Overrides by name.
    pub settings: Option<Overrides>,
    /// Worker threads.
    pub jobs: Option<usize>,
    /// Scoring protocols to add (ids, or `["all"]`).
    pub protocols: Option<Strings>,
    /// `"all"` or `"found"`; None: the setting's default or a `settings` override.
    pub route_subset: Option<&'a str>,
}

impl Shared<'_> {
    /// The library's [`RunSettings`].
    ///
    /// # Errors
    /// [`ConfigError`]: an unknown profile, duplicate policy or route subset, one string for
    /// `protocols`.
    pub fn request(self) -> PyResult<RunSettings> {
        Ok(RunSettings {
            profile: profile(self.profile)?,
            expected_routes: self.expected_routes,
            duplicates: self
                .duplicates
                .map(|d| {
                    named(
                        "duplicates",
                        d,
                        DuplicatePolicy::from_name,
                        DuplicatePolicy::choices,
                    )
                })
                .transpose()?,
            allow_missing_telemetry: self.allow_missing_telemetry,
            jobs: self.jobs,
            route_subset: self
                .route_subset
                .map(|r| {
                    named(
                        "route_subset",
                        r,
                        RouteSubset::from_name,
                        RouteSubset::choices,
                    )
                })
                .transpose()?,
            protocols: self.protocols.map(|p| p.list("protocols")).transpose()?,
            overrides: self.settings.map(|s| s.0).unwrap_or_default(),
            // An option one function takes alone is set by that function on the result.
            ..RunSettings::default()
        })
    }
}

/// Warns each message as an `sds.SdsWarning` at the caller's line: called from Python, a
/// function of this module has no frame of its own, so stack level 1 is the line that called it.
/// A filter that makes the warning an error raises it here.
pub fn warn_each<I: IntoIterator<Item = String>>(py: Python<'_>, messages: I) -> PyResult<()> {
    let class = py.get_type::<crate::errors::SdsWarning>();
    for m in messages {
        let text = std::ffi::CString::new(m.replace('\0', "\\0"))
            .map_err(|e| ConfigError::new_err(e.to_string()))?;
        PyErr::warn(py, &class, &text, 1)?;
    }
    Ok(())
}

/// Warns each of a converted report's `warnings` ([`warn_each`]).
pub fn warn_report(report: &Bound<'_, PyAny>) -> PyResult<()> {
    let Ok(list) = report.get_item("warnings") else {
        return Ok(());
    };
    if list.is_none() {
        return Ok(());
    }
    let mut texts = Vec::new();
    for w in list.try_iter()? {
        texts.push(w?.str()?.to_string());
    }
    warn_each(report.py(), texts)
}
