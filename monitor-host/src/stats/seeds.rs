//! Seeds and flaky routes (docs/SCORE.md §10.3): per model, the spread of each compared
//! route's `ds` over its seeds and repetitions (each repetition a sample), the routes whose
//! success share lies strictly between 0 and 1 (flaky), each seed's DS, their sample std, and the
//! seeds a 95 % interval of the mean DS no wider than ±`repro.halfwidth` needs.
//!
//! ```
//! use monitor_host::stats::seeds::{seeds_needed, spread};
//! let s = spread("24785", &[(100.0, true), (40.0, false)]);
//! assert_eq!((s.ds_mean, s.ds_min, s.ds_max, s.success_share), (Some(70.0), Some(40.0), Some(100.0), Some(0.5)));
//! assert!(s.is_flaky());
//! // seed_std 5.1 DS points, ±1.0: ceil((1.96 × 5.1)²) = 100 seeds.
//! assert_eq!(seeds_needed(Some(5.1), 1.0), Some(100));
//! assert_eq!(seeds_needed(None, 1.0), None); // one seed: no spread to size from
//! ```

use std::collections::HashMap;

use serde::Serialize;

use crate::model::report::Report;
use crate::route::row::counted_routes;
use crate::stats::route_values::route_key;
use crate::stats::stat::Stat;

/// One compared route of one model: its `ds` over the model's samples (seeds × repetitions).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RouteSpread {
    /// The route key (XML id).
    pub route: String,
    /// Mean `ds` over the samples (summed in seed, then record order).
    pub ds_mean: Option<f64>,
    /// Sample standard deviation (n - 1); null for one sample.
    pub ds_std: Option<f64>,
    /// Lowest `ds`.
    pub ds_min: Option<f64>,
    /// Highest `ds`.
    pub ds_max: Option<f64>,
    /// Share of the samples that succeeded, 0..1.
    pub success_share: Option<f64>,
}

impl RouteSpread {
    /// Flaky: `0 < success_share < 1`.
    pub fn is_flaky(&self) -> bool {
        self.success_share.is_some_and(|s| s > 0.0 && s < 1.0)
    }
}

/// One sample of a flaky route, for the tables: the run, the record's id, `ds` and success.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The run (seed).
    pub run: String,
    /// `ds` of the record.
    pub ds: f64,
    /// Whether it succeeded.
    pub success: bool,
}

/// A flaky route with what the tables show: scenario, town, and each sample's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct FlakyRoute {
    /// The route key.
    pub route: String,
    /// Its scenario type (the first sample's record), if known.
    pub scenario: Option<String>,
    /// Its town, if known.
    pub town: Option<String>,
    /// Each sample, in seed then record order.
    pub outcomes: Vec<Outcome>,
}

/// A model's seeds (docs/SCORE.md §10.3): `routes`, `flaky_routes`, `seed_ds`, `seed_std`, `seeds_needed`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SeedStats {
    /// Per compared route, in the baseline's route order.
    pub routes: Vec<RouteSpread>,
    /// The keys of the flaky routes, in route order.
    pub flaky_routes: Vec<String>,
    /// Each seed's DS (docs/SCORE.md §10, over the compared routes), in seed order.
    pub seed_ds: Vec<Option<f64>>,
    /// Sample std of `seed_ds`; null for one seed.
    pub seed_std: Option<f64>,
    /// `ceil((1.96 seed_std / h)^2)`; null when `seed_std` is null.
    pub seeds_needed: Option<u64>,
    /// The flaky routes' samples (for the tables; not in the JSON report).
    #[serde(skip)]
    pub flaky: Vec<FlakyRoute>,
}

/// The spread of one route's samples `(ds, success)`.
pub fn spread(route: &str, samples: &[(f64, bool)]) -> RouteSpread {
    let ds: Vec<Option<f64>> = samples.iter().map(|(d, _)| Some(*d)).collect();
    let stat = Stat::of(&ds);
    let n = samples.len();
    let fold = |f: fn(f64, f64) -> f64| samples.iter().map(|(d, _)| *d).reduce(f);
    RouteSpread {
        route: route.to_string(),
        ds_mean: stat.mean,
        ds_std: stat.std,
        ds_min: fold(f64::min),
        ds_max: fold(f64::max),
        success_share: (n > 0)
            .then(|| samples.iter().filter(|(_, s)| *s).count() as f64 / n as f64),
    }
}

/// The seeds a 95 % interval of the mean DS no wider than ±`halfwidth` needs (docs/SCORE.md §10.3
/// **\[decision\]**): `ceil((1.96 seed_std / h)^2)`; `None` without a std or with h <= 0.
pub fn seeds_needed(seed_std: Option<f64>, halfwidth: f64) -> Option<u64> {
    let sd = seed_std?;
    if !(halfwidth.is_finite() && halfwidth > 0.0 && sd.is_finite()) {
        return None;
    }
    let x = (1.96 * sd / halfwidth).powi(2).ceil();
    // A seed count beyond u64 is no count; saturate (the float is finite and >= 0).
    Some(if x >= u64::MAX as f64 {
        u64::MAX
    } else {
        x as u64
    })
}

/// One run's samples by key, with the first record's scenario and town.
struct RunSamples<'a> {
    samples: HashMap<&'a str, Vec<(f64, bool)>>,
    place: HashMap<&'a str, (Option<&'a str>, Option<&'a str>)>,
}

fn run_samples(report: &Report) -> RunSamples<'_> {
    let mut out = RunSamples {
        samples: HashMap::new(),
        place: HashMap::new(),
    };
    for r in counted_routes(&report.routes) {
        let Some(id) = r.route_id.as_deref() else {
            continue;
        };
        let key = route_key(id);
        out.samples
            .entry(key)
            .or_default()
            .push((r.score_composed.unwrap_or(0.0), r.success));
        out.place
            .entry(key)
            .or_insert((r.scenario_type.as_deref(), r.town.as_deref()));
    }
    out
}

/// A model's [`SeedStats`] over the compared `keys` (baseline route order): `runs` are its
/// seeds (name and report), `seed_ds` each seed's DS over the compared routes.
pub fn seed_stats(
    runs: &[(&str, &Report)],
    keys: &[String],
    seed_ds: Vec<Option<f64>>,
    halfwidth: f64,
) -> SeedStats {
    let per_run: Vec<RunSamples> = runs.iter().map(|(_, r)| run_samples(r)).collect();
    let mut routes = Vec::with_capacity(keys.len());
    let mut flaky = Vec::new();
    for k in keys {
        let mut all = Vec::new();
        let mut outcomes = Vec::new();
        for ((name, _), rs) in runs.iter().zip(&per_run) {
            for &(ds, success) in rs.samples.get(k.as_str()).map_or(&[][..], |v| v) {
                all.push((ds, success));
                outcomes.push(Outcome {
                    run: name.to_string(),
                    ds,
                    success,
                });
            }
        }
        let s = spread(k, &all);
        if s.is_flaky() {
            let (scenario, town) = per_run
                .iter()
                .find_map(|rs| rs.place.get(k.as_str()).copied())
                .unwrap_or((None, None));
            flaky.push(FlakyRoute {
                route: k.clone(),
                scenario: scenario.map(str::to_string),
                town: town.map(str::to_string),
                outcomes,
            });
        }
        routes.push(s);
    }
    let seed_std = Stat::of(&seed_ds).std;
    SeedStats {
        flaky_routes: flaky.iter().map(|f| f.route.clone()).collect(),
        routes,
        seed_ds,
        seed_std,
        seeds_needed: seeds_needed(seed_std, halfwidth),
        flaky,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_has_no_std_and_is_never_flaky() {
        let s = spread("1", &[(55.0, false)]);
        assert_eq!((s.ds_std, s.success_share), (None, Some(0.0)));
        assert!(!s.is_flaky());
        assert!(!spread("1", &[(100.0, true), (100.0, true)]).is_flaky());
        assert_eq!(spread("1", &[]).ds_mean, None);
    }

    #[test]
    fn seeds_needed_rounds_up_and_refuses_no_width() {
        // (1.96 × 2 / 1)² = 15.3664 → 16.
        assert_eq!(seeds_needed(Some(2.0), 1.0), Some(16));
        assert_eq!(seeds_needed(Some(0.0), 1.0), Some(0));
        assert_eq!(seeds_needed(Some(2.0), 0.0), None);
        assert_eq!(seeds_needed(Some(2.0), f64::NAN), None);
    }
}
