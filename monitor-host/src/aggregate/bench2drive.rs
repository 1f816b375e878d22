//! Bench2Drive's own benchmark metrics (docs/SCORE.md §10.1), beside SDS: driving score,
//! success rate, efficiency, smoothness and the multi-ability rates, with the routes the
//! ability rates could not count (`ability_missing`), could not decide (`ability_undecided`) or
//! decided close to the threshold (`ability_marginal`).

use serde::{Deserialize, Serialize};

use crate::aggregate::aggregates::{AbilityCount, AbilityRates, Aggregates, Counts};
use crate::route::ability::JunctionCredit;
use crate::route::row::RouteReport;

/// A route decided within [`crate::route::ability::MARGINAL_BAND`] of its threshold.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marginal {
    /// The route.
    pub route_id: String,
    /// `score_route / 100`.
    pub score: f64,
    /// Its `junction_completion`.
    pub junction_completion: f64,
    /// Whether it was credited.
    pub credited: bool,
}

/// A route whose junction credit could not be decided.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Undecided {
    /// The route.
    pub route_id: String,
    /// Its town.
    pub town: Option<String>,
    /// Why.
    pub reason: String,
}

/// `summary.bench2drive` of the report (docs/SCORE.md §10.1, docs/SCORE.md §13).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bench2Drive {
    /// docs/SCORE.md §10's driving score (Bench2Drive's merge rule).
    pub driving_score: Option<f64>,
    /// docs/SCORE.md §10's success rate, percent.
    pub success_rate: Option<f64>,
    /// Mean per-route efficiency.
    pub efficiency: Option<f64>,
    /// Mean `b2d-legacy` comfort: Bench2Drive's "Driving Smoothness".
    pub smoothness: Option<f64>,
    /// The five ability rates and their mean; null without a route XML.
    pub ability: Option<AbilityRates>,
    /// Routes and successes per ability.
    pub ability_counts: Counts<AbilityCount>,
    /// Routes of the route set without a record (Bench2Drive lists them as crashed).
    pub ability_missing: Vec<String>,
    /// Failed Traffic_Signs routes whose junction credit could not be decided: counted failed.
    pub ability_undecided: Vec<Undecided>,
    /// Routes whose `score_route / 100` is within 0.15 of their `junction_completion`.
    pub ability_marginal: Vec<Marginal>,
    /// The Traffic_Signs counting rule (`ability_rule`, docs/SCORE.md §10.1): `b2d-0.0.4` or `b2d-0.0.3`.
    #[serde(deserialize_with = "rule_name")]
    pub ability_rule: crate::named::Name,
}

name_field!(rule_name, crate::settings::AbilityRule::NAMES);

impl Bench2Drive {
    /// The block from the run's aggregates over every counted route (`combined`), the routes
    /// (for the per-route credit lists) and the route-set members without a record.
    pub fn new<'a>(
        all: &Aggregates,
        routes: impl IntoIterator<Item = &'a RouteReport>,
        missing: Vec<String>,
    ) -> Self {
        let id = |r: &RouteReport| r.route_id.clone().unwrap_or_default();
        let mut undecided = Vec::new();
        let mut marginal = Vec::new();
        for r in routes {
            match r.ability.as_ref().and_then(|a| a.junction.as_ref()) {
                Some(JunctionCredit::Undecided { undecided: why }) => undecided.push(Undecided {
                    route_id: id(r),
                    town: r.town.clone(),
                    reason: why.clone(),
                }),
                Some(JunctionCredit::Decided {
                    score,
                    junction_completion,
                    credited,
                    marginal: true,
                }) => marginal.push(Marginal {
                    route_id: id(r),
                    score: *score,
                    junction_completion: *junction_completion,
                    credited: *credited,
                }),
                _ => {}
            }
        }
        Bench2Drive {
            driving_score: all.scores.driving_score,
            success_rate: all.scores.success_rate,
            efficiency: all.efficiency,
            smoothness: all.smoothness,
            ability: all.ability.clone(),
            ability_counts: all.ability_counts.clone(),
            ability_missing: missing,
            ability_undecided: undecided,
            ability_marginal: marginal,
            ability_rule: crate::route::protocol::ability_rule::AbilityRule::default().name(),
        }
    }
}
