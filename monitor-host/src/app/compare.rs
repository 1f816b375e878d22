//! Comparing runs end to end (`sds compare`, docs/SCORE.md §10.3): score each run with
//! [`crate::score_run`], group the runs into models as asked (`seeds`; never by name), and
//! compare them ([`crate::stats::compare`]). Every front end calls this.

use std::path::{Path, PathBuf};

use crate::app::run::{Inputs, Progress};
use crate::app::score::{RequestError, ScoreError};
use crate::error::Error;
use crate::input::warning::Warning;
use crate::settings::Settings;
use crate::stats::stat::Stat;
use crate::stats::sweep::{self, SweepAxis, SweepError};
use crate::stats::{
    check_options, compare_cancellable, CompareError, CompareOptions, Comparison, Model, NamedRun,
};

/// One run to compare: its name and its inputs (results, telemetry, route XML, maps).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunInputs {
    /// The run's name (unique).
    pub name: String,
    /// Its files.
    pub inputs: Inputs,
}

/// The telemetry root of a run given none: the folder of its results file (or the results
/// folder itself), where Bench2Drive writes a run's `<save_name>/metric_info.json`. Every front
/// end of `sds compare` uses this default.
///
/// ```
/// use monitor_host::app::compare::telemetry_beside;
/// use std::path::Path;
/// assert_eq!(telemetry_beside(Path::new("out/results.json")), Path::new("out"));
/// assert_eq!(telemetry_beside(Path::new("results.json")), Path::new("."));
/// ```
pub fn telemetry_beside(results: &Path) -> PathBuf {
    if results.is_dir() {
        results.to_path_buf()
    } else {
        results
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf()
    }
}

/// Seeds of one model: `model` = the runs named in `runs` (`--seeds MODEL=RUN,RUN`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Seeds {
    /// The model's name.
    pub model: String,
    /// Its runs' names, in the order given.
    pub runs: Vec<String>,
}

/// The comparison and the scored runs behind it (for renderings that show each run).
#[derive(Clone, Debug)]
pub struct Compared {
    /// The `sds-compare/1` report.
    pub comparison: Comparison,
    /// The models, each with its runs' reports.
    pub models: Vec<Model>,
}

/// One warning of a comparison, said the same way by every front end ([`Compared::warnings`]).
#[derive(Clone, Debug, PartialEq)]
pub enum CompareWarning<'a> {
    /// A run's own warning (its report's), named by the run.
    Run {
        /// The run's name.
        run: &'a str,
        /// The warning.
        warning: &'a Warning,
    },
    /// A line about the whole comparison: the towns without a map of every run, said once
    /// ([`maps_warning`]); the comparison's own warnings.
    Comparison(String),
}

impl Compared {
    /// Every warning of the comparison, in order: each run's (the missing maps left out), then
    /// the runs' missing maps said once for all of them (every run is scored against the same
    /// `maps` folder), then the comparison's own.
    pub fn warnings(&self, maps: Option<&Path>) -> Vec<CompareWarning<'_>> {
        let mut out = Vec::new();
        let mut no_maps: Vec<(&str, &Warning)> = Vec::new();
        for r in self.models.iter().flat_map(|m| &m.runs) {
            for w in &r.report.warnings {
                if matches!(w, Warning::NoMap { .. } | Warning::NoMaps { .. }) {
                    no_maps.push((&r.name, w));
                } else {
                    out.push(CompareWarning::Run {
                        run: &r.name,
                        warning: w,
                    });
                }
            }
        }
        out.extend(maps_warning(&no_maps, maps).map(CompareWarning::Comparison));
        out.extend(
            self.comparison
                .warnings
                .iter()
                .map(|w| CompareWarning::Comparison(w.clone())),
        );
        out
    }
}

/// The runs' missing-map warnings ([`Warning::NoMap`], [`Warning::NoMaps`]) said once for the
/// whole comparison: every run is scored against the same `maps` folder, so the towns are
/// listed once, and each run's count of routes in them (instead of one long line per run).
///
/// ```
/// use monitor_host::app::compare::maps_warning;
/// use monitor_host::Warning;
/// let w = |towns: &[(&str, usize)]| Warning::NoMaps {
///     towns: towns.iter().map(|(t, n)| (t.to_string(), *n)).collect(),
///     reason: "no map for Town03 in maps (looked for maps/Town03.xodr)".into(),
///     lane_fallback: false,
/// };
/// let a = w(&[("Town03", 11), ("Town12", 104)]);
/// let b = w(&[("Town03", 11), ("Town12", 100)]);
/// let line = maps_warning(&[("uniad", &a), ("vad", &b)], Some(std::path::Path::new("maps"))).unwrap();
/// assert_eq!(line, "no map in maps for 2 towns (Town03, Town12): their routes (uniad 115, vad 111) \
///     fall back to the route XML's straight segments; add the towns' .xodr to --maps to use their lanes");
/// ```
pub fn maps_warning(runs: &[(&str, &Warning)], maps: Option<&Path>) -> Option<String> {
    let mut towns = std::collections::BTreeSet::new();
    let mut per_run: Vec<(&str, usize)> = Vec::new();
    let mut lane = false;
    for (run, w) in runs {
        let (listed, lane_fallback) = match w {
            Warning::NoMap {
                town,
                routes,
                lane_fallback,
                ..
            } => (vec![(town.as_str(), *routes)], *lane_fallback),
            Warning::NoMaps {
                towns,
                lane_fallback,
                ..
            } => (
                towns.iter().map(|(t, n)| (t.as_str(), *n)).collect(),
                *lane_fallback,
            ),
            _ => continue,
        };
        lane |= lane_fallback;
        towns.extend(listed.iter().map(|(t, _)| *t));
        let routes: usize = listed.iter().map(|(_, n)| n).sum();
        match per_run.iter_mut().find(|(r, _)| r == run) {
            Some((_, n)) => *n += routes,
            None => per_run.push((run, routes)),
        }
    }
    if towns.is_empty() {
        return None;
    }
    let names: Vec<&str> = towns.into_iter().collect();
    let folder = maps.map_or_else(String::new, |m| format!(" in {}", m.display()));
    let counts: Vec<String> = per_run.iter().map(|(r, n)| format!("{r} {n}")).collect();
    Some(format!(
        "no map{folder} for {} town{} ({}): their routes ({}) fall back to the route XML's \
         straight segments{}; add the towns' .xodr to --maps to use their lanes",
        names.len(),
        if names.len() == 1 { "" } else { "s" },
        names.join(", "),
        counts.join(", "),
        if lane {
            " (lateral_reference=lane falls back to route)"
        } else {
            ""
        }
    ))
}

/// Groups the runs into models: each `seeds` entry is one model, at the place of its first run;
/// every other run is a model of its own name.
///
/// # Errors
/// [`CompareError::DuplicateName`] when a run is in two seed groups or a model's name is taken.
pub fn group_runs(runs: Vec<NamedRun>, seeds: &[Seeds]) -> Result<Vec<Model>, Error> {
    let unknown = |name: &str| Error::Compare(CompareError::UnknownRun(name.to_string()));
    for s in seeds {
        for r in &s.runs {
            if !runs.iter().any(|x| &x.name == r) {
                return Err(unknown(r));
            }
            let mut groups = seeds.iter().filter(|t| t.runs.contains(r));
            if let (Some(first), Some(second)) = (groups.next(), groups.next()) {
                return Err(Error::Compare(CompareError::SeedOfTwo {
                    run: r.clone(),
                    first: first.model.clone(),
                    second: second.model.clone(),
                }));
            }
        }
    }
    // (model, from a seed group): a run of a group joins only its group's model, so a group
    // named like another run stays a model of its own (and `compare` refuses the two names).
    let mut grouped: Vec<(Model, bool)> = Vec::new();
    for run in runs {
        let group = seeds.iter().find(|s| s.runs.contains(&run.name));
        let name = group.map_or_else(|| run.name.clone(), |g| g.model.clone());
        match grouped
            .iter_mut()
            .find(|(m, from_group)| *from_group && group.is_some() && m.name == name)
        {
            Some((m, _)) => m.runs.push(run),
            None => grouped.push((
                Model {
                    name,
                    runs: vec![run],
                },
                group.is_some(),
            )),
        }
    }
    let mut models: Vec<Model> = grouped.into_iter().map(|(m, _)| m).collect();
    // Seeds in the order `--seeds` names them.
    for s in seeds {
        if let Some(m) = models.iter_mut().find(|m| m.name == s.model) {
            m.runs
                .sort_by_key(|r| s.runs.iter().position(|x| *x == r.name));
        }
    }
    Ok(models)
}

/// Scores every run (in order, each on the thread pool [`crate::score_run`] makes) and compares
/// them; with a sweep (`axes` not empty, docs/SCORE.md §10.4) also every model's figures at
/// every point of the grid ([`crate::stats::sweep`]) in [`Comparison::sweep`]: each run is
/// scored once at the given settings and at every point ([`crate::app::run::score_run_points`],
/// which re-uses what a point does not change); the rest of the report is that of the given
/// settings. `progress` hears each run's routes; once it says [`Progress::cancelled`], the run
/// being scored stops between routes and no further run or bootstrap block starts
/// ([`Error::Cancelled`]). The options and the grid are checked before any run is scored.
///
/// # Errors
/// A run's [`Error`] (naming it is the caller's: the order is the order given),
/// [`Error::Compare`] ([`CompareError::Sweep`] for a refused grid or a run given as a report),
/// or [`Error::Cancelled`].
pub(crate) fn compare_runs(
    runs: &[RunInputs],
    seeds: &[Seeds],
    settings: &Settings,
    options: &CompareOptions,
    axes: &[SweepAxis],
    progress: &dyn Progress,
) -> Result<Compared, Error> {
    check_options(options)?;
    let grid = if axes.is_empty() {
        Vec::new()
    } else {
        sweep::grid(settings, axes).map_err(|e| Error::Compare(CompareError::Sweep(e)))?
    };
    if !grid.is_empty() {
        if let Some((r, f)) = runs.iter().find_map(|r| match r.inputs.results.as_slice() {
            [f] if crate::app::run::scored_by::is_report(f) => Some((r, f)),
            _ => None,
        }) {
            return Err(Error::Compare(CompareError::Sweep(SweepError::Report {
                run: r.name.clone(),
                file: f.display().to_string(),
            })));
        }
    }
    // The given settings first, then every point.
    let points: Vec<Settings> = std::iter::once(settings.clone())
        .chain(grid.iter().cloned())
        .collect();
    let mut scored = Vec::new();
    let mut scored_by = Vec::new();
    // Per run, its reports at the grid's points, cut to what the figures read.
    let mut at_points: Vec<Vec<crate::model::report::Report>> = Vec::new();
    for r in runs {
        if progress.cancelled() {
            return Err(Error::Cancelled);
        }
        if scored.iter().any(|x: &NamedRun| x.name == r.name) {
            return Err(Error::Compare(CompareError::DuplicateName {
                what: "runs",
                name: r.name.clone(),
            }));
        }
        let scored_here = if grid.is_empty() {
            crate::app::run::scored_by::score_or_read(&r.inputs, settings, progress)
        } else {
            crate::app::run::score_run_points(&r.inputs, &points, progress).map(|mut reports| {
                let main = reports.remove(0);
                at_points.push(reports.into_iter().map(sweep_figures_only).collect());
                let by = crate::app::run::scored_by::ScoredBy::of(&main);
                (main, by)
            })
        };
        let (report, by) = scored_here.map_err(|e| match e {
            Error::Cancelled => e,
            // `sds compare` has no `--telemetry`: name the way a run's folder is given.
            Error::TelemetryRoot { path, reason, .. } => Error::InRun {
                run: r.name.clone(),
                error: Box::new(Error::TelemetryRoot {
                    given_as: "telemetry folder",
                    path,
                    reason,
                }),
            },
            e => Error::InRun {
                run: r.name.clone(),
                error: Box::new(e),
            },
        })?;
        scored_by.push(by);
        scored.push(NamedRun {
            name: r.name.clone(),
            report,
        });
    }
    let models = group_runs(scored, seeds)?;
    let mut comparison =
        compare_cancellable(&models, options, &|| progress.cancelled()).map_err(|e| match e {
            CompareError::Cancelled => Error::Cancelled,
            e => Error::Compare(e),
        })?;
    if !grid.is_empty() {
        comparison.sweep = Some(sweep_report(runs, &models, axes, &grid, at_points));
    }
    // Runs scored by another sds version or other settings (reports given as runs).
    let by: Vec<(&str, &crate::app::run::scored_by::ScoredBy)> = runs
        .iter()
        .map(|r| r.name.as_str())
        .zip(&scored_by)
        .collect();
    comparison
        .warnings
        .extend(crate::app::run::scored_by::differences(&by));
    // One results file given as two runs: as seeds their spread is 0 and says nothing.
    let real = |r: &RunInputs| -> Vec<PathBuf> {
        r.inputs
            .results
            .iter()
            .map(|p| std::fs::canonicalize(p).unwrap_or_else(|_| p.clone()))
            .collect()
    };
    for (i, b) in runs.iter().enumerate() {
        if let Some(a) = runs[..i].iter().find(|a| real(a) == real(b)) {
            comparison.warnings.push(format!(
                "runs {} and {} are the same results ({}): as seeds of one model their ± is 0 \
                 and says nothing about the spread",
                a.name,
                b.name,
                b.inputs
                    .results
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    Ok(Compared { comparison, models })
}

/// A report cut to what a sweep's figures read (its rows without events, chunks or traces): a
/// sweep keeps every run's report at every point until all runs are scored.
fn sweep_figures_only(mut report: crate::model::report::Report) -> crate::model::report::Report {
    for r in &mut report.routes {
        r.chunks = None;
        r.events = Vec::new();
        r.collision_events = Vec::new();
        r.traces = Vec::new();
        r.stationary = Vec::new();
        r.warnings = Vec::new();
    }
    report.warnings = Vec::new();
    report
}

/// The sweep's report: per point, each model's figures as [`compare_cancellable`]'s model rows
/// aggregate them (the mean over its seeds, over the compared routes).
fn sweep_report(
    runs: &[RunInputs],
    models: &[Model],
    axes: &[SweepAxis],
    grid: &[Settings],
    at_points: Vec<Vec<crate::model::report::Report>>,
) -> sweep::SweepReport {
    let names: Vec<String> = axes.iter().map(|a| a.name.clone()).collect();
    let main: Vec<&crate::model::report::Report> = models
        .iter()
        .flat_map(|m| m.runs.iter().map(|r| &r.report))
        .collect();
    let (shared, common) = crate::stats::shared_keys(&main);
    // Per run (in the order given), its figures at each point.
    let figures: Vec<Vec<[Option<f64>; 3]>> = at_points
        .iter()
        .map(|reports| {
            reports
                .iter()
                .map(|r| crate::stats::run_figures(r, &shared, common))
                .collect()
        })
        .collect();
    let points = grid
        .iter()
        .enumerate()
        .map(|(p, settings)| {
            let per_model = models
                .iter()
                .map(|m| {
                    let seeds: Vec<[Option<f64>; 3]> = m
                        .runs
                        .iter()
                        .filter_map(|r| runs.iter().position(|x| x.name == r.name))
                        .map(|i| figures[i][p])
                        .collect();
                    let stat =
                        |k: usize| Stat::of(&seeds.iter().map(|f| f[k]).collect::<Vec<_>>()).mean;
                    [stat(0), stat(1), stat(2)]
                })
                .collect();
            (sweep::values_at(&names, settings), per_model)
        })
        .collect();
    let model_names: Vec<String> = models.iter().map(|m| m.name.clone()).collect();
    sweep::report(&names, &model_names, points)
}

/// One run of a [`CompareRequest`]: its name, its results and its telemetry root (`None`: the
/// folder of its results, [`telemetry_beside`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunSpec {
    /// The run's name (unique).
    pub name: String,
    /// Its results file or folder.
    pub results: PathBuf,
    /// Its telemetry root.
    pub telemetry: Option<PathBuf>,
}

/// Runs to compare (`sds compare`, `sds.compare`): the runs, their seed groups, the files every
/// run shares, the options each run is scored with and those of the comparison.
///
/// ```
/// use monitor_host::app::compare::{CompareRequest, RunSpec};
/// use monitor_host::{demo, NoProgress};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let spec = |name: &str| RunSpec { name: name.into(), results: run.results.clone(),
///                                   telemetry: Some(run.telemetry.clone()) };
/// let request = CompareRequest { runs: vec![spec("base"), spec("new")],
///                                ..CompareRequest::default() };
/// let c = request.compare(&NoProgress)?;
/// assert_eq!(c.comparison.paired.len(), 4); // new vs base: ds, success, ds_safe, comfort
/// assert!(c.comparison.gate_failures().is_empty());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompareRequest {
    /// The runs, in order (the first model is the baseline unless `options.baseline` names one).
    pub runs: Vec<RunSpec>,
    /// The seed groups.
    pub seeds: Vec<Seeds>,
    /// The route XML every run is scored against.
    pub routes: Option<PathBuf>,
    /// The maps folder every run is scored with.
    pub maps: Option<PathBuf>,
    /// The options each run is scored with.
    pub settings: crate::settings::RunSettings,
    /// The comparison's options (`fail_if_worse` names are trimmed).
    pub options: CompareOptions,
    /// The sweep (`--sweep`, docs/SCORE.md §10.4): each setting and its values; empty for none.
    pub sweep: Vec<SweepAxis>,
}

impl CompareRequest {
    /// Checks the request before any run is scored; returns the runs' settings.
    ///
    /// # Errors
    /// [`ScoreError::Request`] for the settings, [`ScoreError::Run`] ([`Error::Compare`]) for
    /// the comparison's options.
    pub fn validate(&self) -> Result<Settings, ScoreError> {
        let settings = self.settings.settings().map_err(RequestError::from)?;
        check_options(&self.options()).map_err(Error::Compare)?;
        if !self.sweep.is_empty() {
            sweep::grid(&settings, &self.sweep)
                .map_err(|e| Error::Compare(CompareError::Sweep(e)))?;
        }
        Ok(settings)
    }

    /// The runs' inputs: each run's results and telemetry (by default beside its results), the
    /// shared route XML and maps.
    pub fn run_inputs(&self) -> Vec<RunInputs> {
        self.runs
            .iter()
            .map(|r| RunInputs {
                name: r.name.clone(),
                inputs: Inputs {
                    telemetry: Some(
                        r.telemetry
                            .clone()
                            .unwrap_or_else(|| telemetry_beside(&r.results)),
                    ),
                    results: vec![r.results.clone()],
                    route_xml: self.routes.clone(),
                    maps: self.maps.clone(),
                },
            })
            .collect()
    }

    /// The comparison's options, `fail_if_worse` trimmed.
    fn options(&self) -> CompareOptions {
        CompareOptions {
            fail_if_worse: self
                .options
                .fail_if_worse
                .iter()
                .map(|m| m.trim().to_string())
                .collect(),
            ..self.options.clone()
        }
    }

    /// Scores and compares the runs.
    ///
    /// # Errors
    /// As [`CompareRequest::validate`], then the runs' own errors.
    pub fn compare(&self, progress: &dyn Progress) -> Result<Compared, ScoreError> {
        let settings = self.validate()?;
        Ok(compare_runs(
            &self.run_inputs(),
            &self.seeds,
            &settings,
            &self.options(),
            &self.sweep,
            progress,
        )?)
    }
}

#[cfg(test)]
mod request_tests {
    use super::*;
    use crate::app::run::NoProgress;

    /// A sweep through the request: every point scored, the same run twice tied everywhere.
    #[test]
    fn sweep_scores_every_point() {
        let dir = tempfile::tempdir().unwrap();
        let run = crate::demo::write(dir.path()).unwrap();
        let spec = |name: &str| RunSpec {
            name: name.into(),
            results: run.results.clone(),
            telemetry: Some(run.telemetry.clone()),
        };
        let request = CompareRequest {
            runs: vec![spec("base"), spec("new")],
            sweep: vec![SweepAxis::parse("critical_excess=0.45,0.65").unwrap()],
            ..CompareRequest::default()
        };
        let sweep = request
            .compare(&NoProgress)
            .unwrap()
            .comparison
            .sweep
            .expect("swept");
        assert_eq!(sweep.points.len(), 2);
        assert!(sweep.pairs[0].order_stable);
    }
}
