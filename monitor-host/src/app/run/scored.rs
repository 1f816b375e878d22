//! A run scored with its breakdown (docs/SCORE.md §10.2): [`crate::score_run`], then the
//! label files read and checked against the report's routes, then the groups. The one function
//! every front end calls for `sds score` (the command line, the Python `sds.score`), so a label
//! file is checked the same way everywhere.

use std::path::{Path, PathBuf};

use crate::aggregate::groups::{route_label_key, GroupBy};
use crate::app::run::{score_run_cached, Inputs, Progress, ReplayCache};
use crate::error::Error;
use crate::input::labels::{check_coverage, read_labels, Labels, LabelsError};
use crate::input::warning::Warning;
use crate::model::report::Report;
use crate::route::row::counted_routes;
use crate::settings::Settings;

/// The label files of a run, one per kind of key (each optional).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LabelFiles {
    /// Scenario type -> family label(s) (`--families`): the map of [`GroupBy::Family`].
    pub families: Option<PathBuf>,
    /// Weather id -> label(s) (`--weathers`), or Bench2Drive's `weather.xml`.
    pub weathers: Option<PathBuf>,
    /// Route id -> label(s) (`--labels`): the map of [`GroupBy::Route`].
    pub routes: Option<PathBuf>,
}

impl LabelFiles {
    /// The files in the order they are read (families, weathers, routes): inputs a front end
    /// must never write over.
    pub fn files(&self) -> impl Iterator<Item = &PathBuf> {
        self.families
            .iter()
            .chain(&self.weathers)
            .chain(&self.routes)
    }
}

/// A report and the label maps read for it.
#[derive(Debug)]
pub struct Scored {
    /// The report (with its groups when a breakdown was asked for, and the label files'
    /// warnings).
    pub report: Report,
    /// The families map, read.
    pub families: Option<Labels>,
    /// The weathers map, read.
    pub weathers: Option<Labels>,
    /// The route label map, read.
    pub labels: Option<Labels>,
}

/// What a label file's keys are.
#[derive(Clone, Copy)]
enum LabelKey {
    Family,
    Weather,
    Route,
}

/// Scores a run ([`crate::app::run::score_run_with`]; `sds score` and `sds.score` call it through
/// [`crate::ScoreRequest`]), reads each label file and checks it against the report's
/// routes (no key matching any route is an error, routes without a label a warning in the
/// report), then breaks the routes down `by` (the report's `groups`) with its label map.
///
/// ```
/// use monitor_host::aggregate::groups::GroupBy;
/// use monitor_host::{demo, Inputs, NoProgress, ScoreRequest};
///
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let request = ScoreRequest { group_by: Some(GroupBy::Town), ..ScoreRequest::new(inputs) };
/// let scored = request.score(&NoProgress)?;
/// assert!(scored.report.groups.is_some());
/// // A grouping by family needs its map, checked before anything is scored.
/// let request = ScoreRequest { group_by: Some(GroupBy::Family), ..request };
/// let e = request.score(&NoProgress).unwrap_err();
/// assert_eq!(e.to_string(), "group_by = family needs its label map (families)");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// As [`crate::score_run`], and before scoring [`Error::UnusedLabels`] (a route label map
/// without `by` = [`GroupBy::Route`]) and [`Error::NeedsLabels`] (`by` needs a map not given);
/// after it [`Error::Labels`] (a label file cannot be read or matches no route).
pub(crate) fn score_labelled(
    inputs: &Inputs,
    settings: &Settings,
    files: &LabelFiles,
    by: Option<GroupBy>,
    progress: &dyn Progress,
) -> Result<Scored, Error> {
    score_labelled_cached(inputs, settings, files, by, progress, None)
}

/// [`score_labelled`] with a [`ReplayCache`] of the routes' replays (`sds watch`): the same
/// report, the unchanged routes not replayed again.
///
/// # Errors
/// As [`score_labelled`].
pub(crate) fn score_labelled_cached(
    inputs: &Inputs,
    settings: &Settings,
    files: &LabelFiles,
    by: Option<GroupBy>,
    progress: &dyn Progress,
    cache: Option<&dyn ReplayCache>,
) -> Result<Scored, Error> {
    // Usage errors of the grouping before the run is scored.
    if files.routes.is_some() && by != Some(GroupBy::Route) {
        return Err(Error::UnusedLabels);
    }
    if let Some(f) = files
        .families
        .as_deref()
        .filter(|f| crate::input::labels::names_safe2drive(f))
    {
        return Err(Error::Labels(LabelsError::Safe2DriveFamilies {
            path: f.to_path_buf(),
        }));
    }
    if let Some(by) = by {
        by.check_labels(
            label_of(
                by,
                files.families.as_ref(),
                files.weathers.as_ref(),
                files.routes.as_ref(),
            )
            .is_some(),
        )?;
    }
    let mut report = score_run_cached(inputs, settings, progress, cache)?;
    let mut read = |file: &Option<PathBuf>, what| {
        file.as_deref()
            .map(|f| label_file(&mut report, f, what))
            .transpose()
    };
    let families = read(&files.families, LabelKey::Family)?;
    let weathers = read(&files.weathers, LabelKey::Weather)?;
    let labels = read(&files.routes, LabelKey::Route)?;
    if let Some(by) = by {
        let map = label_of(by, families.as_ref(), weathers.as_ref(), labels.as_ref());
        report.group(by, map)?;
    }
    crate::app::run::diagnostics::add_notes(&mut report);
    Ok(Scored {
        report,
        families,
        weathers,
        labels,
    })
}

/// The label map (or file) of the grouping `by`: families, weathers, route labels, or none.
fn label_of<T>(
    by: GroupBy,
    families: Option<T>,
    weathers: Option<T>,
    routes: Option<T>,
) -> Option<T> {
    match by {
        GroupBy::Scenario | GroupBy::Town => None,
        GroupBy::Family => families,
        GroupBy::Weather => weathers,
        GroupBy::Route => routes,
    }
}

/// Reads a label file and checks it against the report's routes: no key matching is an error,
/// keys of some routes without a label a warning (added to the report).
fn label_file(report: &mut Report, file: &Path, what: LabelKey) -> Result<Labels, Error> {
    let labels = read_labels(file)?;
    report
        .inputs
        .provenance
        .files
        .push(crate::provenance::FileDigest::of(file, "labels"));
    let counted = counted_routes(&report.routes);
    let (keys, name, option): (Vec<&str>, _, _) = match what {
        LabelKey::Family => (
            counted.filter_map(|r| r.scenario_type.as_deref()).collect(),
            "scenario type",
            "families",
        ),
        LabelKey::Weather => (
            counted.filter_map(|r| r.weather_id.as_deref()).collect(),
            "weather id",
            "weathers",
        ),
        // A route counts as labelled when the map has any form of its id.
        LabelKey::Route => (
            counted
                .filter_map(|r| r.route_id.as_deref())
                .map(|id| route_label_key(id, &labels).unwrap_or(id))
                .collect(),
            "route id (1711, RouteScenario_1711 or RouteScenario_1711_rep0)",
            "labels",
        ),
    };
    let unlabelled = check_coverage(&labels, keys, file, name, option)?;
    if !unlabelled.is_empty() {
        report.warnings.push(Warning::LabelsMissKeys {
            file: file.to_path_buf(),
            count: unlabelled.len(),
            keys: unlabelled.into_iter().take(8).collect(),
        });
    }
    Ok(labels)
}
