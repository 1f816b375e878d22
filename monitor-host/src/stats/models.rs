//! One row per model (docs/SCORE.md §10.3 `models`): every §8.1 / docs/SCORE.md §10.1 aggregate (and §8.5's
//! moving comfort, stationary share and distance) as the mean
//! and sample standard deviation over the model's seeds.
//!
//! ```
//! use monitor_host::stats::models::Stat;
//! let s = Stat::of(&[Some(1.0), Some(2.0), Some(6.0)]);
//! assert_eq!((s.mean, s.std), (Some(3.0), Some(7.0f64.sqrt())));
//! assert_eq!(Stat::of(&[Some(4.0)]).std, None); // one seed: no spread
//! ```

use serde::Serialize;

use crate::aggregate::aggregates::Aggregates;
use crate::stats::seeds::SeedStats;
pub use crate::stats::stat::Stat;

/// One model's row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelRow {
    /// The model.
    pub name: String,
    /// Its runs (seeds), in the order given.
    pub runs: Vec<String>,
    /// Routes each run was aggregated over (N). v1.4 gives `routes` to the per-route spread
    /// ([`SeedStats::routes`], docs/SCORE.md §10.3), so the counts are `route_counts`.
    pub route_counts: Vec<usize>,
    /// Driving score (docs/SCORE.md §10).
    pub driving_score: Stat,
    /// Success rate, % (docs/SCORE.md §10).
    pub success_rate: Stat,
    /// Mean DS_safe (docs/SCORE.md §10).
    pub mean_ds_safe: Stat,
    /// Mean comfort (docs/SCORE.md §10).
    pub mean_comfort: Stat,
    /// SDS (docs/SCORE.md §10).
    pub sds: Stat,
    /// Collision rate, % (docs/SCORE.md §10).
    pub collision_rate: Stat,
    /// Efficiency (docs/SCORE.md §10.1).
    pub efficiency: Stat,
    /// Smoothness (docs/SCORE.md §10.1), 0..1.
    pub smoothness: Stat,
    /// Ability rates (docs/SCORE.md §10.1), 0..1.
    pub ability: AbilityStats,
    /// The Traffic_Signs counting rule its runs were scored with (`ability_rule`, docs/SCORE.md §10.1).
    pub ability_rule: &'static str,
    /// Mean moving comfort (docs/SCORE.md §10.0).
    pub mean_comfort_moving: Stat,
    /// Mean stationary share (docs/SCORE.md §10.0), 0..1.
    pub mean_stationary_share: Stat,
    /// Distance driven, km (docs/SCORE.md §10.0).
    pub distance_km: Stat,
    /// Seeds and flaky routes (docs/SCORE.md §10.3): `routes`, `flaky_routes`, `seed_ds`, `seed_std`,
    /// `seeds_needed`.
    #[serde(flatten)]
    pub seeds: SeedStats,
    /// Each run's Bench2Drive block over the compared routes, for the tables' notes (the
    /// Traffic Sign bracket and the undecided junction credits `sds score`'s table states);
    /// not in the JSON report (each run's figures are its `sds score` report's).
    #[serde(skip)]
    pub bench2drive: Vec<(String, crate::aggregate::bench2drive::Bench2Drive)>,
}

/// The five ability rates and their mean, over seeds.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AbilityStats {
    /// Merging.
    #[serde(rename = "Merging")]
    pub merging: Stat,
    /// Overtaking.
    #[serde(rename = "Overtaking")]
    pub overtaking: Stat,
    /// Emergency brake.
    #[serde(rename = "Emergency_Brake")]
    pub emergency_brake: Stat,
    /// Give way.
    #[serde(rename = "Give_Way")]
    pub give_way: Stat,
    /// Traffic signs.
    #[serde(rename = "Traffic_Signs")]
    pub traffic_signs: Stat,
    /// Mean of the five.
    pub mean: Stat,
}

/// The row of a model from its runs' aggregates (in seed order), scored under the ability rule
/// `ability_rule`.
pub fn model_row(
    name: &str,
    runs: &[(String, Aggregates)],
    ability_rule: &'static str,
) -> ModelRow {
    let stat = |f: &dyn Fn(&Aggregates) -> Option<f64>| {
        Stat::of(&runs.iter().map(|(_, a)| f(a)).collect::<Vec<_>>())
    };
    let ab = |f: &dyn Fn(&crate::aggregate::aggregates::AbilityRates) -> Option<f64>| {
        stat(&|a| a.ability.as_ref().and_then(f))
    };
    ModelRow {
        name: name.to_string(),
        runs: runs.iter().map(|(n, _)| n.clone()).collect(),
        route_counts: runs.iter().map(|(_, a)| a.routes).collect(),
        driving_score: stat(&|a| a.scores.driving_score),
        success_rate: stat(&|a| a.scores.success_rate),
        mean_ds_safe: stat(&|a| a.scores.mean_ds_safe),
        mean_comfort: stat(&|a| a.scores.mean_comfort),
        sds: stat(&|a| a.scores.sds),
        collision_rate: stat(&|a| a.scores.collision_rate),
        efficiency: stat(&|a| a.efficiency),
        smoothness: stat(&|a| a.smoothness),
        ability: AbilityStats {
            merging: ab(&|x| x.merging),
            overtaking: ab(&|x| x.overtaking),
            emergency_brake: ab(&|x| x.emergency_brake),
            give_way: ab(&|x| x.give_way),
            traffic_signs: ab(&|x| x.traffic_signs),
            mean: ab(&|x| x.mean),
        },
        ability_rule,
        mean_comfort_moving: stat(&|a| a.scores.motion.mean_comfort_moving),
        mean_stationary_share: stat(&|a| a.scores.motion.mean_stationary_share),
        distance_km: stat(&|a| a.scores.motion.distance_km),
        seeds: SeedStats::default(),
        bench2drive: Vec::new(),
    }
}
