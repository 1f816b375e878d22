//! Every aggregate of a set of routes (docs/SCORE.md §10, docs/SCORE.md §10.1, docs/SCORE.md §10.2), computed from the
//! report's routes: one breakdown group, the `combined` row, one run of a comparison. f64,
//! summed in the order the routes are given (input order).
//!
//! ```
//! use monitor_host::aggregate::aggregates::Aggregates;
//! let a = Aggregates::over(&[], 0);
//! assert_eq!((a.routes, a.scores.driving_score, a.ability), (0, None, None));
//! ```

use serde::{Deserialize, Serialize};

pub use crate::aggregate::counts::Counts;
use crate::aggregate::decomposition::Decomposition;
use crate::aggregate::motion::MotionAggregates;
use crate::input::record::KNOWN_LISTS;
use crate::route::ability::ABILITIES;
use crate::route::decomposition::Losses;
use crate::route::row::RouteReport;

/// Rates of the five abilities (0..1, null when no route counts in one) and their mean.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AbilityRates {
    /// Overtaking.
    #[serde(rename = "Overtaking")]
    pub overtaking: Option<f64>,
    /// Merging.
    #[serde(rename = "Merging")]
    pub merging: Option<f64>,
    /// Emergency braking.
    #[serde(rename = "Emergency_Brake")]
    pub emergency_brake: Option<f64>,
    /// Giving way.
    #[serde(rename = "Give_Way")]
    pub give_way: Option<f64>,
    /// Traffic signs (junction credits included).
    #[serde(rename = "Traffic_Signs")]
    pub traffic_signs: Option<f64>,
    /// Mean of the five that are not null.
    pub mean: Option<f64>,
}

impl AbilityRates {
    /// The five rates in [`ABILITIES`] order.
    pub fn rates(&self) -> [Option<f64>; 5] {
        [
            self.overtaking,
            self.merging,
            self.emergency_brake,
            self.give_way,
            self.traffic_signs,
        ]
    }
}

/// Successes and routes of one ability.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AbilityCount {
    /// Routes counting in the ability.
    pub routes: usize,
    /// Of those, successes.
    pub successes: usize,
}

/// The §8.1 scores of a set of routes over N: the numbers the run's summary, every breakdown
/// group, the `combined` row and every compared run share (one computation: [`Scores::over`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Routes with defined comfort.
    pub comfort_routes: usize,
    /// Σ score_composed / N.
    pub driving_score: Option<f64>,
    /// 100 × successes / N.
    pub success_rate: Option<f64>,
    /// Σ DS_safe / N; null when some route has no DS_safe.
    pub mean_ds_safe: Option<f64>,
    /// Mean comfort over the routes with defined comfort.
    pub mean_comfort: Option<f64>,
    /// mean_ds_safe × mean_comfort.
    pub sds: Option<f64>,
    /// 100 × routes with a collision / N.
    pub collision_rate: Option<f64>,
    /// From DS to SDS in additive steps (`docs/SCORE.md` "Decomposition"); null when
    /// `mean_ds_safe` is.
    pub decomposition: Option<Decomposition>,
    /// Distance, stationary time and moving comfort (docs/SCORE.md §10.0).
    #[serde(flatten)]
    pub motion: MotionAggregates,
}

/// Every §8.1 and §8.2 aggregate over a set of routes, with `N = routes`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Aggregates {
    /// N.
    pub routes: usize,
    /// The §8.1 scores.
    #[serde(flatten)]
    pub scores: Scores,
    /// Mean per-route efficiency over the routes that have one (docs/SCORE.md §10.1).
    pub efficiency: Option<f64>,
    /// Mean `b2d-legacy` comfort over the routes where it is defined (docs/SCORE.md §10.1).
    pub smoothness: Option<f64>,
    /// Ability rates; null when no route has a route XML entry.
    pub ability: Option<AbilityRates>,
    /// Routes and successes per ability (the fractions behind `ability`).
    pub ability_counts: Counts<AbilityCount>,
    /// Per infraction list (the 12 known ones, then any other), the routes with at least one
    /// entry.
    pub infraction_routes: Counts<usize>,
    /// Every asked scoring protocol's aggregates (docs/PROTOCOLS.md); absent when none is asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocols: Option<crate::route::protocol::aggregate::ProtocolScores>,
}

fn mean(sum: f64, n: usize) -> Option<f64> {
    (n > 0).then(|| sum / n as f64)
}

impl Scores {
    /// The §8.1 scores of `routes` (summed in this order) over `n` routes: `n` is the set's
    /// size, which exceeds `routes.len()` when routes are expected but absent (they count as
    /// 0 / failed). A route without a record adds 0 to the sums and leaves `mean_ds_safe` null.
    ///
    /// ```
    /// use monitor_host::aggregate::aggregates::Scores;
    /// let s = Scores::over(&[], 220);
    /// assert_eq!((s.driving_score, s.success_rate, s.mean_comfort), (Some(0.0), Some(0.0), None));
    /// assert_eq!(Scores::over(&[], 0).driving_score, None);
    /// ```
    pub fn over(routes: &[&RouteReport], n: usize) -> Scores {
        let per = |total: f64| (n > 0).then(|| total / n as f64);
        let (mut composed, mut ds_safe, mut comfort) = (0.0, 0.0, 0.0);
        let (mut successes, mut collided, mut comfort_n) = (0, 0, 0);
        let mut all_safe = true;
        let mut losses = Losses::default();
        let mut all_split = true;
        for r in routes {
            composed += r.score_composed.unwrap_or(0.0);
            successes += usize::from(r.success);
            collided += usize::from(!r.collision_events.is_empty());
            match r.ds_safe {
                Some(d) => ds_safe += d,
                None => all_safe = false,
            }
            match &r.decomposition {
                Some(l) => losses.add(l),
                None => all_split = false,
            }
            if let Some(c) = r.comfort.score {
                comfort += c;
                comfort_n += 1;
            }
        }
        let mean_ds_safe = if all_safe { per(ds_safe) } else { None };
        let mean_comfort = mean(comfort, comfort_n);
        let decomposition = match (per(composed), mean_ds_safe) {
            (Some(ds), Some(safe)) if all_split => Some(Decomposition::of(
                ds,
                losses.per(n as f64),
                safe,
                mean_comfort,
            )),
            _ => None,
        };
        Scores {
            comfort_routes: comfort_n,
            driving_score: per(composed),
            success_rate: per(100.0 * successes as f64),
            sds: mean_ds_safe.zip(mean_comfort).map(|(d, c)| d * c),
            mean_ds_safe,
            mean_comfort,
            collision_rate: per(100.0 * collided as f64),
            decomposition,
            motion: MotionAggregates::over(routes),
        }
    }
}

impl Aggregates {
    /// The aggregates of `routes` (in this order) over `n` routes: the §8.1 [`Scores`] over
    /// `n`, and the §8.2 means and rates, which do not depend on `n`.
    pub fn over(routes: &[&RouteReport], n: usize) -> Aggregates {
        let (mut eff, mut smooth) = (0.0, 0.0);
        let (mut eff_n, mut smooth_n) = (0, 0);
        let mut has_ability = false;
        let mut counts = Counts::<AbilityCount>::default();
        for (name, _) in ABILITIES {
            counts.entry(name);
        }
        let mut inf = Counts::<usize>::default();
        for name in KNOWN_LISTS {
            inf.entry(name);
        }
        for r in routes {
            if let Some(e) = r.efficiency {
                eff += e;
                eff_n += 1;
            }
            if let Some(s) = r.smoothness {
                smooth += s;
                smooth_n += 1;
            }
            if let Some(a) = &r.ability {
                has_ability = true;
                for e in &a.abilities {
                    let c = counts.entry(e.ability);
                    c.routes += 1;
                    c.successes += usize::from(e.success);
                }
            }
            for (name, count) in &r.infractions.0 {
                let c = inf.entry(name);
                *c += usize::from(*count > 0);
            }
        }
        let ability = has_ability.then(|| {
            let rate = |name: &str| {
                let c = counts.get(name);
                (c.routes > 0).then(|| c.successes as f64 / c.routes as f64)
            };
            let mut a = AbilityRates {
                overtaking: rate(ABILITIES[0].0),
                merging: rate(ABILITIES[1].0),
                emergency_brake: rate(ABILITIES[2].0),
                give_way: rate(ABILITIES[3].0),
                traffic_signs: rate(ABILITIES[4].0),
                mean: None,
            };
            let known: Vec<f64> = a.rates().into_iter().flatten().collect();
            a.mean = mean(known.iter().sum(), known.len());
            a
        });
        Aggregates {
            routes: n,
            scores: Scores::over(routes, n),
            efficiency: mean(eff, eff_n),
            smoothness: mean(smooth, smooth_n),
            ability,
            ability_counts: counts,
            infraction_routes: inf,
            protocols: crate::route::protocol::aggregate::ProtocolScores::over(
                routes.iter().filter_map(|r| {
                    r.protocols
                        .as_ref()
                        .map(|p| (r.score_route.unwrap_or(0.0), p))
                }),
                n,
            ),
        }
    }
}
