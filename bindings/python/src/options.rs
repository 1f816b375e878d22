//! Python keyword arguments → the library's [`RunSettings`]: the options every scored-run
//! function of the package takes (`sds.score`, `sds.compare`, `sds.watch`), spelled as Python
//! spells them; the library maps them to settings ([`RunSettings::settings`]).

use monitor_core::Profile;
use monitor_host::input::duplicates::DuplicatePolicy;
use monitor_host::input::route_set::RouteSubset;
use monitor_host::RunSettings;
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
    /// A profile's name: `"physical"`, `"b2d-legacy"` or `"autoware"`.
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
    /// The library's [`RunSettings`] (mapped to settings by the library, as the command line's
    /// options are).
    ///
    /// # Errors
    /// [`ConfigError`]: an unknown profile, duplicate policy or route subset; a settings mapping
    /// whose items are not `(str, value)` pairs.
    pub fn request(&self) -> PyResult<RunSettings> {
        let profile = choice(
            "profile",
            &self.profile,
            &Profile::ALL.map(|p| (p.name(), p)),
        )?;
        let named: Vec<(&str, DuplicatePolicy)> = DuplicatePolicy::ALL
            .iter()
            .map(|p| (p.name(), *p))
            .collect();
        let subsets: Vec<(&str, RouteSubset)> =
            RouteSubset::ALL.iter().map(|r| (r.name(), *r)).collect();
        Ok(RunSettings {
            profile,
            expected_routes: self.expected_routes,
            duplicates: self
                .duplicates
                .as_deref()
                .map(|d| choice("duplicates", d, &named))
                .transpose()?,
            allow_missing_telemetry: self.allow_missing_telemetry,
            jobs: self.jobs,
            route_subset: self
                .route_subset
                .as_deref()
                .map(|r| choice("route_subset", r, &subsets))
                .transpose()?,
            protocols: self.protocols.clone(),
            ability_rule: None,
            overrides: setting_pairs(self.settings.as_ref())?,
        })
    }
}
