//! Several runs side by side (`sds compare`): one row of aggregates per run, and runs of one
//! model (seeds) reduced to mean ± sample standard deviation.
//!
//! The runs are compared on the same routes: the routes present in every run, unless the route
//! set decides (a route XML or an expected route count: then each run is scored over the whole
//! set, absent routes counting as 0 / failed). The comparison says which.
//!
//! ```
//! use monitor_host::aggregate::compare::{model_name, Stat};
//! assert_eq!(model_name("tfpp_seed2"), "tfpp");
//! assert_eq!(model_name("uniad-3"), "uniad");
//! assert_eq!(model_name("vad"), "vad");
//! let s = Stat::of(&[Some(1.0), Some(2.0), Some(6.0)]);
//! assert_eq!((s.mean, s.std), (Some(3.0), Some(7.0f64.sqrt())));
//! ```

use std::collections::HashSet;

use serde::Serialize;

use crate::aggregate::aggregates::Aggregates;
use crate::aggregate::report::Report;
use crate::route::row::{counted_routes, RouteReport};

/// One run to compare: its name and its report (from [`crate::score_run`]).
#[derive(Clone, Debug)]
pub struct NamedRun {
    /// The run's name (`NAME=PATH`, or the results folder's name).
    pub name: String,
    /// The model it is a seed of (`None`: [`model_name`] of the name).
    pub model: Option<String>,
    /// Its report.
    pub report: Report,
}

/// Which routes the runs are compared on.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Scope {
    /// The route set decides: every run over its own N.
    RouteSet,
    /// The routes present in every run (`routes` of them); the others are listed per run.
    Common {
        /// Routes compared.
        routes: usize,
        /// Per run (in order), the routes left out because some other run lacks them.
        excluded: Vec<Excluded>,
    },
}

/// The routes of one run left out of a comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Excluded {
    /// The run.
    pub run: String,
    /// Its routes absent from some other run, in input order.
    pub routes: Vec<String>,
}

/// A mean and sample standard deviation over seeds (std null for one seed; both null when some
/// seed has no value).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Stat {
    /// Mean.
    pub mean: Option<f64>,
    /// Sample standard deviation (n - 1).
    pub std: Option<f64>,
}

impl Stat {
    /// The statistic of `values`, summed in order.
    pub fn of(values: &[Option<f64>]) -> Stat {
        let Some(xs) = values.iter().copied().collect::<Option<Vec<f64>>>() else {
            return Stat::default();
        };
        let n = xs.len();
        if n == 0 {
            return Stat::default();
        }
        let mean = xs.iter().fold(0.0, |a, x| a + x) / n as f64;
        let std = (n > 1).then(|| {
            let ss = xs.iter().fold(0.0, |a, x| a + (x - mean) * (x - mean));
            (ss / (n - 1) as f64).sqrt()
        });
        Stat {
            mean: Some(mean),
            std,
        }
    }
}

/// One run's row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunRow {
    /// The run.
    pub name: String,
    /// Its model.
    pub model: String,
    /// Its aggregates over the compared routes.
    #[serde(flatten)]
    pub aggregates: Aggregates,
}

/// One model's row: its seeds reduced to mean ± std.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelRow {
    /// The model.
    pub model: String,
    /// Its runs, in the order given.
    pub runs: Vec<String>,
    /// Driving score.
    pub driving_score: Stat,
    /// Success rate.
    pub success_rate: Stat,
    /// Mean DS_safe.
    pub mean_ds_safe: Stat,
    /// Mean comfort.
    pub mean_comfort: Stat,
    /// SDS.
    pub sds: Stat,
    /// Collision rate.
    pub collision_rate: Stat,
    /// Efficiency.
    pub efficiency: Stat,
    /// Smoothness.
    pub smoothness: Stat,
    /// Mean ability.
    pub ability_mean: Stat,
}

/// The comparison (`sds compare`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Which routes were compared.
    pub scope: Scope,
    /// One row per run, in the order given.
    pub runs: Vec<RunRow>,
    /// One row per model, in order of first appearance.
    pub models: Vec<ModelRow>,
}

/// The model a run name belongs to: the name without a trailing seed suffix (`_3`, `-3`,
/// `_seed3`, `-seed3`, `_s3`).
pub fn model_name(run: &str) -> &str {
    let digits = run.trim_end_matches(|c: char| c.is_ascii_digit());
    if digits.len() == run.len() {
        return run;
    }
    for tag in ["_seed", "-seed", "_s", "-s", "_", "-"] {
        if let Some(head) = digits.strip_suffix(tag) {
            if !head.is_empty() {
                return head;
            }
        }
    }
    run
}

fn counted(report: &Report) -> impl Iterator<Item = &RouteReport> {
    counted_routes(&report.routes)
}

/// Compares the runs (see the module docs). With `route_set` each run is aggregated over its
/// own N (the route set's size); otherwise over the routes present in every run.
///
/// ```
/// use monitor_host::aggregate::compare::{compare, NamedRun, Scope};
/// use monitor_host::{demo, score_run, Inputs, Settings};
/// let dir = tempfile::tempdir()?;
/// let run = demo::write(dir.path())?;
/// let inputs = Inputs { telemetry: Some(run.telemetry), ..Inputs::new([run.results]) };
/// let report = score_run(&inputs, &Settings::default())?;
/// let runs: Vec<NamedRun> = ["a_1", "a_2"]
///     .iter()
///     .map(|n| NamedRun { name: n.to_string(), model: None, report: report.clone() })
///     .collect();
/// let c = compare(&runs, false);
/// assert!(matches!(c.scope, Scope::Common { .. }));
/// assert_eq!(c.models.len(), 1);
/// assert_eq!(c.models[0].driving_score.std, Some(0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compare(runs: &[NamedRun], route_set: bool) -> Comparison {
    let (scope, rows) = if route_set {
        let rows = runs
            .iter()
            .map(|r| {
                let routes: Vec<&RouteReport> = counted(&r.report).collect();
                Aggregates::over(&routes, r.report.summary.routes.max(routes.len()))
            })
            .collect::<Vec<_>>();
        (Scope::RouteSet, rows)
    } else {
        let ids = |r: &NamedRun| -> HashSet<String> {
            counted(&r.report)
                .filter_map(|x| x.route_id.clone())
                .collect()
        };
        let mut common: Option<HashSet<String>> = None;
        for r in runs {
            let these = ids(r);
            common = Some(match common {
                None => these,
                Some(c) => c.intersection(&these).cloned().collect(),
            });
        }
        let common = common.unwrap_or_default();
        let is_common = |x: &RouteReport| x.route_id.as_ref().is_some_and(|id| common.contains(id));
        let rows = runs
            .iter()
            .map(|r| {
                let routes: Vec<&RouteReport> =
                    counted(&r.report).filter(|x| is_common(x)).collect();
                Aggregates::over(&routes, routes.len())
            })
            .collect();
        let excluded = runs
            .iter()
            .map(|r| Excluded {
                run: r.name.clone(),
                routes: counted(&r.report)
                    .filter(|x| !is_common(x))
                    .map(|x| {
                        x.route_id.clone().unwrap_or_else(|| {
                            x.source
                                .as_ref()
                                .map_or_else(String::new, ToString::to_string)
                        })
                    })
                    .collect(),
            })
            .collect();
        (
            Scope::Common {
                routes: common.len(),
                excluded,
            },
            rows,
        )
    };
    let runs: Vec<RunRow> = runs
        .iter()
        .zip(rows)
        .map(|(r, aggregates)| RunRow {
            name: r.name.clone(),
            model: r
                .model
                .clone()
                .unwrap_or_else(|| model_name(&r.name).to_string()),
            aggregates,
        })
        .collect();
    let mut models: Vec<ModelRow> = Vec::new();
    let mut order: Vec<&str> = Vec::new();
    for r in &runs {
        if !order.contains(&r.model.as_str()) {
            order.push(&r.model);
        }
    }
    for model in order {
        let mine: Vec<&RunRow> = runs.iter().filter(|r| r.model == model).collect();
        let stat = |f: &dyn Fn(&Aggregates) -> Option<f64>| {
            Stat::of(&mine.iter().map(|r| f(&r.aggregates)).collect::<Vec<_>>())
        };
        models.push(ModelRow {
            model: model.to_string(),
            runs: mine.iter().map(|r| r.name.clone()).collect(),
            driving_score: stat(&|a| a.scores.driving_score),
            success_rate: stat(&|a| a.scores.success_rate),
            mean_ds_safe: stat(&|a| a.scores.mean_ds_safe),
            mean_comfort: stat(&|a| a.scores.mean_comfort),
            sds: stat(&|a| a.scores.sds),
            collision_rate: stat(&|a| a.scores.collision_rate),
            efficiency: stat(&|a| a.efficiency),
            smoothness: stat(&|a| a.smoothness),
            ability_mean: stat(&|a| a.ability.as_ref().and_then(|x| x.mean)),
        });
    }
    Comparison {
        scope,
        runs,
        models,
    }
}
