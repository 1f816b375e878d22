//! Comparing runs (`sds compare`, docs/SCORE.md §10.3): models (one run, or the seeds of one
//! model) compared route by route against a baseline, with paired differences, a bootstrap
//! interval, a verdict per metric, the routes that flipped, and a regression gate.
//!
//! Each model and metric draws from its own generator seeded with `bootstrap_seed` (v1.4): the
//! same n gives the same resamples of route positions (common random numbers), so adding a model,
//! a metric or a protocol changes no other figure.
//!
//! [`compare`] works on reports already made; [`crate::CompareRequest`] scores the
//! runs and calls it. The pieces: [`route_values`] (keys, repetitions, seeds), [`splitmix`] (the
//! generator), [`bootstrap`] (one model and metric), [`flips`], [`models`] (mean ± std rows).
//!
//! ```
//! use monitor_host::stats::{compare, CompareOptions, Model, NamedRun};
//! use monitor_host::{demo, score_run, Inputs, Settings};
//! let dir = tempfile::tempdir()?;
//! let run = demo::write(dir.path())?;
//! let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
//! let report = score_run(&inputs, &Settings::default())?;
//! let model = |name: &str| Model {
//!     name: name.into(),
//!     runs: vec![NamedRun { name: name.into(), report: report.clone() }],
//! };
//! let c = compare(&[model("old"), model("new")], &CompareOptions::default())?;
//! assert_eq!(c.baseline, "old");
//! let ds = &c.paired[0]; // new vs old on ds: the same run, so no difference
//! assert_eq!((ds.model.as_str(), ds.metric.as_str(), ds.result.delta), ("new", "ds", Some(0.0)));
//! assert_eq!(ds.result.verdict.map(|v| v.name()), Some("within noise"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bootstrap;
pub mod flips;
pub mod models;
pub mod rank;
pub mod route_values;
pub mod seeds;
pub mod splitmix;
pub mod stat;
pub mod sweep;

use std::collections::HashSet;

use rayon::prelude::*;
use serde::Serialize;

use crate::aggregate::aggregates::Aggregates;
use crate::model::report::Report;
use crate::route::row::{counted_routes, RouteReport};
use bootstrap::{paired, Paired, Verdict, DRAW_BUDGET, SAMPLES};
use flips::{flipped, largest, Flips};
use models::{model_row, ModelRow};
use route_values::{mean_values, metric_names, route_key, run_values, RunValues, Values, METRICS};
use splitmix::SplitMix64;

/// The report's schema name.
pub const SCHEMA: &str = "sds-compare/1";

/// One run: its name and its report (from [`crate::score_run`]).
#[derive(Clone, Debug)]
pub struct NamedRun {
    /// The run's name.
    pub name: String,
    /// Its report.
    pub report: Report,
}

/// A model: one run, or the runs of its seeds (grouped only when asked: `--seeds`).
#[derive(Clone, Debug)]
pub struct Model {
    /// The model's name.
    pub name: String,
    /// Its runs, at least one.
    pub runs: Vec<NamedRun>,
}

/// The settings of a comparison (docs/SCORE.md §10.3; **\[decision\]**s keep the spec's defaults).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareOptions {
    /// The baseline model (`None`: the first model).
    pub baseline: Option<String>,
    /// Compare over the keys all runs share instead of refusing different route sets.
    pub common_routes: bool,
    /// Bootstrap resamples B (default 10000; [`bootstrap::SAMPLES`], and n × B at most
    /// [`bootstrap::DRAW_BUDGET`]).
    pub bootstrap_samples: usize,
    /// SplitMix64 seed (default 0).
    pub bootstrap_seed: u64,
    /// Metrics whose `worse` or `no data` verdict fails the gate (exit 5 of `sds compare`).
    pub fail_if_worse: Vec<String>,
    /// Rank the models with bootstrap intervals (`--rank`, docs/SCORE.md §10.3).
    pub rank: bool,
    /// `repro.halfwidth` h (default 1.0 DS point): `seeds_needed` sizes a 95 % interval of a
    /// model's mean DS no wider than ±h (docs/SCORE.md §10.3 **\[decision\]**; `--repro-halfwidth`).
    #[serde(rename = "repro.halfwidth")]
    pub repro_halfwidth: f64,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            baseline: None,
            common_routes: false,
            bootstrap_samples: 10_000,
            bootstrap_seed: 0,
            fail_if_worse: Vec::new(),
            rank: false,
            repro_halfwidth: 1.0,
        }
    }
}

/// Why two or more runs cannot be compared.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CompareError {
    /// Nothing to compare.
    #[error("a comparison needs at least two models (runs, or seeds groups); got {0}")]
    TooFewModels(usize),
    /// A model without runs.
    #[error("model {0} has no run")]
    EmptyModel(String),
    /// Two models or two runs of one name.
    #[error("two {what} are named {name}: name them apart")]
    DuplicateName {
        /// `models` or `runs`.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A run named in two seed groups: it would count in the first only.
    #[error("seeds: run {run} is a seed of {first} and of {second}; a run belongs to one model")]
    SeedOfTwo {
        /// The run.
        run: String,
        /// The first model naming it.
        first: String,
        /// The second.
        second: String,
    },
    /// `--seeds` names a run that is not given.
    #[error("seeds names {0}, which is not a run")]
    UnknownRun(String),
    /// `--baseline` names no model.
    #[error("baseline {0} is not a model (models: {1})")]
    UnknownBaseline(String, String),
    /// An unknown metric name.
    #[error("unknown metric {0} (known: {known}, and ds@<protocol> for a protocol of the protocols setting)", known = METRICS.join(", "))]
    UnknownMetric(String),
    /// A protocol metric (`ds@<id>`) whose protocol was not asked.
    #[error("metric {0} compares a protocol's scores: score the runs with it (protocols = {1})")]
    ProtocolNotAsked(String, String),
    /// `bootstrap_samples` outside [`bootstrap::SAMPLES`] (the value as given).
    #[error(
        "bootstrap_samples = {0}: B must be between {lo} and {hi} \
         resamples (fewer leave the interval's ends to a handful of resamples; more cost time \
         and memory without moving them)",
        lo = SAMPLES.start(), hi = SAMPLES.end()
    )]
    SamplesOutOfRange(String),
    /// n × B above [`bootstrap::DRAW_BUDGET`] for a model and metric.
    #[error(
        "bootstrap_samples = {b} over the {n} routes of {model} on {metric} \
         is {draws} draws, above the budget of {DRAW_BUDGET} per model and metric (n × B): use \
         at most {most} resamples for {n} routes",
        draws = (*n as u128) * (*b as u128), most = DRAW_BUDGET / (*n).max(1) as u64
    )]
    DrawBudget {
        /// The model.
        model: String,
        /// The metric.
        metric: String,
        /// Routes compared.
        n: usize,
        /// Resamples asked.
        b: usize,
    },
    /// `repro.halfwidth` not a positive finite number (the value as given).
    #[error(
        "repro.halfwidth = {0}: the half-width of the mean DS's 95 % interval \
         that seeds_needed sizes must be a positive number of DS points (default 1.0)"
    )]
    HalfwidthOutOfRange(String),
    /// The comparison was cancelled ([`crate::Progress::cancelled`], e.g. Ctrl-C in Python)
    /// before every model and metric was drawn.
    #[error("cancelled before every model and metric was compared: no report")]
    Cancelled,
    /// The runs' route sets differ.
    #[error(
        "the runs do not hold the same routes: {differ} route key(s) are not in every run \
         (first: {first}); {per_run}. Compare over the routes all runs share with \
         common_routes, or give every run the same route set (the same route XML, routes)",
        first = first.join(", "),
        per_run = per_run.iter().map(|(r, n)| format!("{r} lacks {n}")).collect::<Vec<_>>().join(", ")
    )]
    RouteSetsDiffer {
        /// Keys not in every run.
        differ: usize,
        /// The first few of them (byte-wise order).
        first: Vec<String>,
        /// Per run, how many of those keys it lacks.
        per_run: Vec<(String, usize)>,
    },
    /// A sweep refused (`--sweep`): its setting, a value, or the grid's size.
    #[error("{0}")]
    Sweep(sweep::SweepError),
}

/// One line of the paired table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairedRow {
    /// The model compared with the baseline.
    pub model: String,
    /// The metric (`ds`, `success`, `ds_safe`, `comfort`, `ds@<protocol>`).
    pub metric: String,
    /// Delta, interval, `p_better`, verdict.
    #[serde(flatten)]
    pub result: Paired,
}

/// One compared route: its key and each model's values (in [`Comparison::metrics`] order).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RouteRow {
    /// The route key (XML id).
    pub key: String,
    /// Per model (in model order), its values over seeds and repetitions.
    pub values: Vec<Values>,
    /// Per run (in run order, models in order), the route ids of its records of this key.
    pub route_ids: Vec<Vec<String>>,
}

/// Which routes were compared.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scope {
    /// Keys compared.
    pub routes: usize,
    /// True when only the keys all runs share were compared (`--common-routes`).
    pub common_routes: bool,
    /// Per run, the keys it holds that were left out (only under `--common-routes`).
    pub left_out: Vec<(String, Vec<String>)>,
}

/// The comparison: the `sds-compare/1` report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// `sds-compare/1`.
    pub schema: &'static str,
    /// The baseline model.
    pub baseline: String,
    /// One row per model: its runs and every aggregate as mean and sample std over seeds.
    pub models: Vec<ModelRow>,
    /// Per model (other than the baseline) and metric: n, delta, 95 % interval, p_better, verdict.
    pub paired: Vec<PairedRow>,
    /// Per model (other than the baseline): regressed, fixed, largest moves.
    pub flips: Vec<Flips>,
    /// The routes compared.
    pub scope: Scope,
    /// Per compared key (the baseline's route order), each model's values.
    pub routes: Vec<RouteRow>,
    /// The metrics, in the order of [`RouteRow::values`]: [`METRICS`], then `ds@<id>` per
    /// protocol the runs were scored with.
    pub metrics: Vec<String>,
    /// With `--rank` (docs/SCORE.md §10.3): every model's mean `ds`, rank, rank interval and `p_best`, by
    /// rank, ties by name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranking: Option<Vec<rank::RankRow>>,
    /// With `--sweep` (docs/SCORE.md §10.4): every model's figures at every point of the grid, the range
    /// of its SDS, and whether each pair's order holds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep: Option<sweep::SweepReport>,
    /// The settings of the comparison.
    pub config: CompareOptions,
    /// What a reader should know (grouping, one-seed intervals, left-out routes).
    pub notes: Vec<String>,
    /// Warnings (`--common-routes`, routes without an id).
    pub warnings: Vec<String>,
}

/// Why a gated metric fails the gate.
#[derive(Clone, Debug, PartialEq)]
pub enum GateReason {
    /// The verdict is `worse`: the interval lies below 0.
    Worse {
        /// The delta.
        delta: f64,
        /// The interval.
        ci95: [f64; 2],
    },
    /// The verdict is `no data` (n = 0): the metric could not be compared, and a gate must
    /// never pass by checking nothing (v1.4).
    NoData {
        /// Why no route could be compared.
        why: String,
    },
}

/// A failed gate: a model worse than the baseline on a gated metric, or not comparable on it.
#[derive(Clone, Debug, PartialEq)]
pub struct GateFailure {
    /// The model.
    pub model: String,
    /// The metric.
    pub metric: String,
    /// Worse, or no data.
    pub reason: GateReason,
}

impl std::fmt::Display for GateFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.reason {
            GateReason::Worse { delta, ci95 } => write!(
                f,
                "{} is worse than the baseline on {}: delta {delta:.4}, 95 % interval [{:.4}, \
                 {:.4}]",
                self.model, self.metric, ci95[0], ci95[1]
            ),
            GateReason::NoData { why } => write!(
                f,
                "{} could not be compared with the baseline on {} (no data, n = 0): {why}; a \
                 gate that checks nothing fails",
                self.model, self.metric
            ),
        }
    }
}

impl Comparison {
    /// The gate (`--fail-if-worse`): every model and listed metric whose verdict is `worse` or
    /// `no data` (v1.4).
    ///
    /// ```
    /// use monitor_host::stats::{compare, CompareOptions, GateReason, Model, NamedRun};
    /// use monitor_host::{demo, score_run, Inputs, Settings};
    /// let dir = tempfile::tempdir()?;
    /// let run = demo::write(dir.path())?;
    /// // Without telemetry, comfort is undefined on every route: n = 0.
    /// let settings = Settings { allow_missing_telemetry: true, ..Settings::default() };
    /// let report = score_run(&Inputs::new([run.results]), &settings)?;
    /// let m = |n: &str| Model { name: n.into(), runs: vec![NamedRun { name: n.into(), report: report.clone() }] };
    /// let options = CompareOptions { fail_if_worse: vec!["comfort".into()], ..CompareOptions::default() };
    /// let c = compare(&[m("base"), m("new")], &options)?;
    /// let failed = c.gate_failures();
    /// assert!(matches!(failed[0].reason, GateReason::NoData { .. }));
    /// assert!(failed[0].to_string().contains("could not be compared"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn gate_failures(&self) -> Vec<GateFailure> {
        self.paired
            .iter()
            .filter(|p| self.config.fail_if_worse.contains(&p.metric))
            .filter_map(|p| {
                let reason = match (p.result.verdict?, p.result.delta, p.result.ci95) {
                    (Verdict::Worse, Some(delta), Some(ci95)) => GateReason::Worse { delta, ci95 },
                    (Verdict::NoData, _, _) => GateReason::NoData {
                        why: self.no_data_why(&p.metric),
                    },
                    _ => return None,
                };
                Some(GateFailure {
                    model: p.model.clone(),
                    metric: p.metric.clone(),
                    reason,
                })
            })
            .collect()
    }

    /// Why a metric has no compared route.
    fn no_data_why(&self, metric: &str) -> String {
        if self.scope.routes == 0 {
            if self.scope.common_routes {
                "the runs share no route key (common_routes)".into()
            } else {
                "no route key to compare".into()
            }
        } else if metric == "comfort" {
            "comfort is undefined on every route of the baseline or the model (it needs the \
             routes' telemetry)"
                .into()
        } else {
            format!("{metric} is undefined on every route of the baseline or the model")
        }
    }
}

/// Checks a metric name: one of [`METRICS`] or `ds@<protocol id>`.
///
/// ```
/// use monitor_host::stats::check_metric;
/// assert!(check_metric("ds_safe").is_ok() && check_metric("ds@lb2.1").is_ok());
/// assert!(check_metric("ds@lb9").is_err() && check_metric("sds").is_err());
/// ```
///
/// # Errors
/// [`CompareError::UnknownMetric`].
pub fn check_metric(name: &str) -> Result<(), CompareError> {
    let protocol = name
        .strip_prefix("ds@")
        .and_then(crate::settings::Protocol::from_id);
    if METRICS.contains(&name) || protocol.is_some() {
        Ok(())
    } else {
        Err(CompareError::UnknownMetric(name.to_string()))
    }
}

/// The protocols every run was scored with, in the first run's order.
fn asked_protocols(models: &[Model]) -> Vec<crate::settings::Protocol> {
    let mut runs = models.iter().flat_map(|m| &m.runs);
    let Some(first) = runs.next() else {
        return Vec::new();
    };
    let mut out = first.report.config.protocols.clone();
    for r in runs {
        out.retain(|p| r.report.config.protocols.contains(p));
    }
    out
}

/// Compares the models (see the module docs).
///
/// # Errors
/// [`CompareError`]: fewer than two models, duplicate names, an unknown baseline or metric,
/// B outside [`bootstrap::SAMPLES`] or n × B above [`bootstrap::DRAW_BUDGET`], or different
/// route sets without `common_routes`.
pub fn compare(models: &[Model], options: &CompareOptions) -> Result<Comparison, CompareError> {
    compare_cancellable(models, options, &|| false)
}

/// [`compare`], stopping between models and metrics once `cancelled` says so (a binding's
/// Ctrl-C): then [`CompareError::Cancelled`].
///
/// # Errors
/// As [`compare`], and [`CompareError::Cancelled`].
pub fn compare_cancellable(
    models: &[Model],
    options: &CompareOptions,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Comparison, CompareError> {
    check(models, options)?;
    let protocols = asked_protocols(models);
    let metrics = metric_names(&protocols);
    if let Some(m) = options.fail_if_worse.iter().find(|m| !metrics.contains(m)) {
        let id = m.strip_prefix("ds@").unwrap_or(m);
        return Err(CompareError::ProtocolNotAsked(m.clone(), id.to_string()));
    }
    let base = match &options.baseline {
        None => 0,
        Some(b) => models.iter().position(|m| &m.name == b).ok_or_else(|| {
            let names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
            CompareError::UnknownBaseline(b.clone(), names.join(", "))
        })?,
    };
    let runs: Vec<(&Model, &NamedRun, RunValues)> = models
        .iter()
        .flat_map(|m| m.runs.iter().map(move |r| (m, r)))
        .map(|(m, r)| (m, r, run_values(&r.report, &protocols)))
        .collect();
    let mut warnings = Vec::new();
    for (_, r, v) in &runs {
        if v.without_id > 0 {
            warnings.push(format!(
                "{}: {} counted route(s) without a route id (unreadable files) have no key and \
                 are left out of the paired comparison",
                r.name, v.without_id
            ));
        }
    }
    // The same-route-set rule.
    let sets: Vec<HashSet<&str>> = runs
        .iter()
        .map(|(_, _, v)| v.order.iter().map(String::as_str).collect())
        .collect();
    let all: HashSet<&str> = sets.iter().flatten().copied().collect();
    let shared: HashSet<&str> = all
        .iter()
        .copied()
        .filter(|k| sets.iter().all(|s| s.contains(k)))
        .collect();
    let mut left_out = Vec::new();
    let differs = shared.len() != all.len();
    if differs {
        let mut differ: Vec<&str> = all.difference(&shared).copied().collect();
        differ.sort_unstable();
        if !options.common_routes {
            return Err(CompareError::RouteSetsDiffer {
                differ: differ.len(),
                first: differ.iter().take(5).map(|s| s.to_string()).collect(),
                per_run: runs
                    .iter()
                    .zip(&sets)
                    .map(|((_, r, _), s)| {
                        (
                            r.name.clone(),
                            differ.iter().filter(|k| !s.contains(*k)).count(),
                        )
                    })
                    .filter(|(_, n)| *n > 0)
                    .collect(),
            });
        }
        warnings.push(format!(
            "common_routes: compared over the {} route key(s) every run holds; {} key(s) left \
             out (first: {})",
            shared.len(),
            differ.len(),
            differ
                .iter()
                .take(5)
                .copied()
                .collect::<Vec<_>>()
                .join(", ")
        ));
        for (_, r, v) in &runs {
            let gone: Vec<String> = v
                .order
                .iter()
                .filter(|k| !shared.contains(k.as_str()))
                .cloned()
                .collect();
            if !gone.is_empty() {
                left_out.push((r.name.clone(), gone));
            }
        }
    }
    // Keys in the baseline's route order: its first seed's report.
    let first_base = runs
        .iter()
        .position(|(m, _, _)| std::ptr::eq(*m, &models[base]))
        .unwrap_or(0);
    let keys: Vec<String> = runs[first_base]
        .2
        .order
        .iter()
        .filter(|k| shared.contains(k.as_str()))
        .cloned()
        .collect();
    // Per model and key: the mean over seeds.
    let per_model: Vec<Vec<Values>> = models
        .iter()
        .map(|m| {
            let mine: Vec<&RunValues> = runs
                .iter()
                .filter(|(x, _, _)| std::ptr::eq(*x, m))
                .map(|(_, _, v)| v)
                .collect();
            keys.iter()
                .map(|k| {
                    let seeds: Vec<Values> = mine.iter().map(|v| v.values[k].clone()).collect();
                    mean_values(&seeds, metrics.len())
                })
                .collect()
        })
        .collect();
    // The model rows: each run aggregated over the compared routes.
    let rows: Vec<ModelRow> = models
        .iter()
        .map(|m| {
            let aggs: Vec<(String, Aggregates)> = m
                .runs
                .iter()
                .map(|r| (r.name.clone(), aggregate(&r.report, &shared, differs)))
                .collect();
            let rule = m.runs.first().map(|r| r.report.config.ability_rule);
            let mut row = model_row(&m.name, &aggs, rule.unwrap_or_default().name());
            let runs: Vec<(&str, &Report)> = m
                .runs
                .iter()
                .map(|r| (r.name.as_str(), &r.report))
                .collect();
            let seed_ds = aggs.iter().map(|(_, a)| a.scores.driving_score).collect();
            row.seeds = seeds::seed_stats(&runs, &keys, seed_ds, options.repro_halfwidth);
            // Each run's Bench2Drive block over the compared routes: the tables' Traffic Sign
            // notes, as `sds score`'s.
            row.bench2drive = m
                .runs
                .iter()
                .zip(&aggs)
                .map(|(r, (name, agg))| {
                    let kept = compared_routes(&r.report, &shared, differs);
                    let mut b =
                        crate::aggregate::bench2drive::Bench2Drive::new(agg, kept, Vec::new());
                    b.ability_rule = r.report.config.ability_rule.name();
                    (name.clone(), b)
                })
                .collect();
            row
        })
        .collect();
    let (paired_rows, flips) = pair(
        models, base, &keys, &per_model, &metrics, options, cancelled,
    )?;
    // No bootstrap work starts after a cancel, the ranking's included.
    if options.rank && cancelled() {
        return Err(CompareError::Cancelled);
    }
    let ranking = options.rank.then(|| {
        let names: Vec<&str> = models.iter().map(|m| m.name.as_str()).collect();
        // `ds` is defined on every compared route (a missing route 0).
        let ds: Vec<Vec<f64>> = per_model
            .iter()
            .map(|v| v.iter().map(|x| x[0].unwrap_or(0.0)).collect())
            .collect();
        rank::ranking(
            &names,
            &ds,
            options.bootstrap_samples,
            options.bootstrap_seed,
        )
    });
    let mut notes = Vec::new();
    for m in models.iter().filter(|m| m.runs.len() > 1) {
        let names: Vec<&str> = m.runs.iter().map(|r| r.name.as_str()).collect();
        notes.push(format!(
            "{} = the mean over the seeds {} (grouped by seeds)",
            m.name,
            names.join(", ")
        ));
    }
    if models.iter().any(|m| m.runs.len() == 1) {
        notes.push(
            "a model with one run: its interval measures the spread across routes only; seeds \
             (several runs per model) would tighten it"
                .to_string(),
        );
    }
    let route_rows = keys
        .iter()
        .enumerate()
        .map(|(i, k)| RouteRow {
            key: k.clone(),
            values: per_model.iter().map(|v| v[i].clone()).collect(),
            route_ids: runs
                .iter()
                .map(|(_, _, v)| v.route_ids.get(k).cloned().unwrap_or_default())
                .collect(),
        })
        .collect();
    Ok(Comparison {
        schema: SCHEMA,
        baseline: models[base].name.clone(),
        models: rows,
        paired: paired_rows,
        flips,
        scope: Scope {
            routes: keys.len(),
            common_routes: differs,
            left_out,
        },
        routes: route_rows,
        metrics,
        ranking,
        sweep: None,
        config: options.clone(),
        notes,
        warnings,
    })
}

/// Checks the options that need no run: B within [`bootstrap::SAMPLES`] and the gate's metric
/// names. Front ends call it before scoring, so that a typo costs no scoring.
///
/// ```
/// use monitor_host::stats::{check_options, CompareOptions};
/// assert!(check_options(&CompareOptions::default()).is_ok());
/// let one = CompareOptions { bootstrap_samples: 1, ..CompareOptions::default() };
/// assert!(check_options(&one).unwrap_err().to_string().contains("between 1000 and 1000000"));
/// ```
///
/// # Errors
/// [`CompareError::SamplesOutOfRange`], [`CompareError::HalfwidthOutOfRange`],
/// [`CompareError::UnknownMetric`].
pub fn check_options(options: &CompareOptions) -> Result<(), CompareError> {
    if !SAMPLES.contains(&options.bootstrap_samples) {
        return Err(CompareError::SamplesOutOfRange(
            options.bootstrap_samples.to_string(),
        ));
    }
    if !(options.repro_halfwidth.is_finite() && options.repro_halfwidth > 0.0) {
        return Err(CompareError::HalfwidthOutOfRange(
            options.repro_halfwidth.to_string(),
        ));
    }
    for m in &options.fail_if_worse {
        check_metric(m)?;
    }
    Ok(())
}

fn check(models: &[Model], options: &CompareOptions) -> Result<(), CompareError> {
    if models.len() < 2 {
        return Err(CompareError::TooFewModels(models.len()));
    }
    check_options(options)?;
    let mut names = HashSet::new();
    let mut runs = HashSet::new();
    for m in models {
        if m.runs.is_empty() {
            return Err(CompareError::EmptyModel(m.name.clone()));
        }
        if !names.insert(m.name.as_str()) {
            return Err(CompareError::DuplicateName {
                what: "models",
                name: m.name.clone(),
            });
        }
        for r in &m.runs {
            if !runs.insert(r.name.as_str()) {
                return Err(CompareError::DuplicateName {
                    what: "runs",
                    name: r.name.clone(),
                });
            }
        }
    }
    Ok(())
}

/// The route keys every report holds, and whether some report holds others (then, under
/// `common_routes`, each run is aggregated over the shared keys only): as [`compare`] decides.
pub(crate) fn shared_keys(reports: &[&Report]) -> (HashSet<String>, bool) {
    let sets: Vec<HashSet<&str>> = reports
        .iter()
        .map(|r| {
            counted_routes(&r.routes)
                .filter_map(|r| r.route_id.as_deref().map(route_key))
                .collect()
        })
        .collect();
    let all: HashSet<&str> = sets.iter().flatten().copied().collect();
    let shared: HashSet<String> = all
        .iter()
        .filter(|k| sets.iter().all(|s| s.contains(*k)))
        .map(|k| k.to_string())
        .collect();
    let differs = shared.len() != all.len();
    (shared, differs)
}

/// A run's DS_safe, comfort and SDS as [`compare`]'s model rows aggregate them (`shared`,
/// `common` from [`shared_keys`]).
pub(crate) fn run_figures(
    report: &Report,
    shared: &HashSet<String>,
    common: bool,
) -> [Option<f64>; 3] {
    let shared: HashSet<&str> = shared.iter().map(String::as_str).collect();
    let s = aggregate(report, &shared, common).scores;
    [s.mean_ds_safe, s.mean_comfort, s.sds]
}

/// A run's aggregates over the compared routes: its whole route set (over its own N) when every
/// run holds the same keys, else the routes of the shared keys (over their number).
fn aggregate(report: &Report, shared: &HashSet<&str>, common: bool) -> Aggregates {
    let kept = compared_routes(report, shared, common);
    if !common {
        return Aggregates::over(&kept, report.summary.routes.max(kept.len()));
    }
    Aggregates::over(&kept, kept.len())
}

/// The counted routes of `report` that are compared: all of them, or with `common` those whose
/// key every run holds.
fn compared_routes<'a>(
    report: &'a Report,
    shared: &HashSet<&str>,
    common: bool,
) -> Vec<&'a RouteReport> {
    counted_routes(&report.routes)
        .filter(|r| {
            !common
                || r.route_id
                    .as_deref()
                    .is_some_and(|id| shared.contains(route_key(id)))
        })
        .collect()
}

/// The paired table and the flips. Each model and metric (a block) draws from its own
/// generator seeded with `bootstrap_seed` (v1.4): no block's figures depend on which other
/// models, metrics or protocols are compared, and the blocks run in parallel. Every block's
/// n × B is checked against [`DRAW_BUDGET`] before anything is drawn; `cancelled` is asked
/// before each block.
#[allow(clippy::too_many_arguments)]
fn pair(
    models: &[Model],
    base: usize,
    keys: &[String],
    per_model: &[Vec<Values>],
    metrics: &[String],
    options: &CompareOptions,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<(Vec<PairedRow>, Vec<Flips>), CompareError> {
    let b = options.bootstrap_samples;
    let mut blocks = Vec::new();
    for (mi, _) in models.iter().enumerate().filter(|(i, _)| *i != base) {
        for (k, metric) in metrics.iter().enumerate() {
            let d: Vec<f64> = per_model[mi]
                .iter()
                .zip(&per_model[base])
                .filter_map(|(x, y)| Some(x[k]? - y[k]?))
                .collect();
            if (d.len() as u128) * (b as u128) > u128::from(DRAW_BUDGET) {
                return Err(CompareError::DrawBudget {
                    model: models[mi].name.clone(),
                    metric: metric.clone(),
                    n: d.len(),
                    b,
                });
            }
            blocks.push((mi, metric.as_str(), d));
        }
    }
    let results: Vec<Option<Paired>> = blocks
        .par_iter()
        .map(|(_, _, d)| {
            if cancelled() {
                return None;
            }
            Some(paired(d, b, &mut SplitMix64::new(options.bootstrap_seed)))
        })
        .collect();
    let results: Vec<Paired> = results
        .into_iter()
        .collect::<Option<_>>()
        .ok_or(CompareError::Cancelled)?;
    let paired_rows = blocks
        .iter()
        .zip(results)
        .map(|((mi, metric, _), result)| PairedRow {
            model: models[*mi].name.clone(),
            metric: metric.to_string(),
            result,
        })
        .collect();
    let column =
        |mi: usize, k: usize| -> Vec<Option<f64>> { per_model[mi].iter().map(|v| v[k]).collect() };
    let flips = (0..models.len())
        .filter(|i| *i != base)
        .map(|mi| {
            let (ms, bs) = (column(mi, 1), column(base, 1));
            Flips {
                model: models[mi].name.clone(),
                regressed: flipped(keys, &ms, &bs, 1.0, 0.0),
                fixed: flipped(keys, &ms, &bs, 0.0, 1.0),
                largest: largest(keys, &column(mi, 0), &column(base, 0), 10),
            }
        })
        .collect();
    Ok((paired_rows, flips))
}
