//! Python keyword arguments → the library's [`RunOptions`] and [`Settings`]: the options every
//! scored-run function of the package takes (`sds.score`, `sds.compare`), mapped
//! once, as the command line maps its shared options ([`RunOptions::settings`]).

use monitor_core::Profile;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::input::route_set::RouteSubset;
use monitor_host::settings::{protocols_of, RunOptions};
use monitor_host::Settings;
use pyo3::prelude::*;
use pyo3::types::PyBool;

use crate::errors::ConfigError;

/// `(name, value)` pairs of a settings mapping, each value as the text the command line's
/// `--set NAME=VALUE` takes (`True` → `true`, `0.9` → `0.9`).
pub fn setting_pairs(settings: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, String)>> {
    let Some(map) = settings else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for item in map.call_method0("items")?.try_iter()? {
        let (k, v): (String, Bound<'_, PyAny>) = item?.extract()?;
        let value = match v.cast::<PyBool>() {
            Ok(b) => b.is_true().to_string(),
            Err(_) => v.str()?.to_string(),
        };
        out.push((k, value));
    }
    Ok(out)
}

/// A named choice, or a [`ConfigError`] listing the choices.
fn choice<T: Copy>(option: &str, value: &str, choices: &[(&str, T)]) -> PyResult<T> {
    choices
        .iter()
        .find(|(n, _)| *n == value)
        .map(|(_, v)| *v)
        .ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(n, _)| *n).collect();
            ConfigError::new_err(format!(
                "{option}={value:?}: expected one of {}",
                names.join(", ")
            ))
        })
}

/// The keyword arguments every scored-run function of the package shares (`sds.score`,
/// `sds.compare`), read by name from the dict the Python layer passes: `profile`,
/// `duplicates`, `expected_routes`, `allow_missing_telemetry`, `settings`, `jobs`, `protocols`,
/// `route_subset`.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunKwargs<'py> {
    /// `"physical"` or `"b2d-legacy"`.
    pub profile: String,
    /// `"error"`, `"first"`, `"last"`, `"newest"` or `"all"`; None (`sds.compare`, as
    /// `sds compare`): the setting's default or a `settings` override.
    pub duplicates: Option<String>,
    /// Benchmark size N.
    pub expected_routes: Option<usize>,
    /// Score routes without telemetry without telemetry terms.
    pub allow_missing_telemetry: bool,
    /// Overrides by name (a mapping), or None.
    pub settings: Option<Bound<'py, PyAny>>,
    /// Worker threads.
    pub jobs: Option<usize>,
    /// Scoring protocols to add (ids, or `["all"]`), or None.
    pub protocols: Option<Vec<String>>,
    /// Which routes of `routes` make the route set: `"all"` or `"found"` (`--route-subset`);
    /// None: the setting's default or a `settings` override.
    pub route_subset: Option<String>,
}

impl RunKwargs<'_> {
    /// The library's options.
    ///
    /// # Errors
    /// [`ConfigError`]: an unknown profile, duplicate policy or route subset; a settings mapping whose items
    /// are not `(str, value)` pairs.
    pub fn options(&self) -> PyResult<RunOptions> {
        let profile = choice(
            "profile",
            &self.profile,
            &[
                (Profile::Physical.name(), Profile::Physical),
                (Profile::B2dLegacy.name(), Profile::B2dLegacy),
            ],
        )?;
        let named: Vec<(&str, DuplicatePolicy)> = DuplicatePolicy::ALL
            .iter()
            .map(|p| (p.name(), *p))
            .collect();
        let subsets: Vec<(&str, RouteSubset)> =
            RouteSubset::ALL.iter().map(|r| (r.name(), *r)).collect();
        let route_subset = self
            .route_subset
            .as_deref()
            .map(|r| choice("route_subset", r, &subsets))
            .transpose()?;
        Ok(RunOptions {
            profile,
            expected_routes: self.expected_routes,
            duplicates: self
                .duplicates
                .as_deref()
                .map(|d| choice("duplicates", d, &named))
                .transpose()?,
            allow_missing_telemetry: self.allow_missing_telemetry,
            threads: self.jobs,
            // The typed list, as it is: never joined into text and parsed back.
            protocols: self
                .protocols
                .as_deref()
                .map(protocols_of)
                .transpose()
                .map_err(|e| crate::errors::settings_error(&e))?,
            // `route_subset` first, as the setting of that name (as the command line's option):
            // `settings` can override it (and `protocols`).
            overrides: route_subset
                .map(|r| ("route_subset".to_string(), r.name().to_string()))
                .into_iter()
                .chain(setting_pairs(self.settings.as_ref())?)
                .collect(),
        })
    }

    /// The settings: [`RunKwargs::options`], then [`RunOptions::settings`] (the mapping the
    /// command line's shared options go through too).
    ///
    /// # Errors
    /// As [`RunKwargs::options`], and a setting the library refuses ([`ConfigError`], the
    /// command's message for the same `--set`).
    pub fn settings(&self) -> PyResult<Settings> {
        self.options()?
            .settings()
            .map_err(|e| crate::errors::settings_error(&e))
    }
}
