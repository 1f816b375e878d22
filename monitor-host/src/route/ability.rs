//! Bench2Drive's multi-ability rates (docs/SCORE.md §10.1): which abilities a route counts
//! in (by the scenario `type` of its route XML entry), whether it is a success in each, and the
//! Traffic_Signs junction credit of a failed route.
//!
//! ```
//! use monitor_host::route::ability::{abilities_of, ABILITIES};
//! assert_eq!(abilities_of("OppositeVehicleTakingPriority"), vec!["Emergency_Brake", "Traffic_Signs"]);
//! assert_eq!(abilities_of("InvadingTurn"), vec!["Give_Way"]);
//! assert!(abilities_of("NoSuchScenario").is_empty());
//! assert_eq!(ABILITIES.len(), 5);
//! ```

use serde::{Deserialize, Serialize};

use crate::geometry::junctions::JunctionSamples;
use crate::input::record::Record;

/// The five abilities and their scenario types, in Bench2Drive's order (docs/SCORE.md §10.1).
pub const ABILITIES: [(&str, &[&str]); 5] = [
    (
        "Overtaking",
        &[
            "Accident",
            "AccidentTwoWays",
            "ConstructionObstacle",
            "ConstructionObstacleTwoWays",
            "HazardAtSideLaneTwoWays",
            "HazardAtSideLane",
            "ParkedObstacleTwoWays",
            "ParkedObstacle",
            "VehicleOpensDoorTwoWays",
        ],
    ),
    (
        "Merging",
        &[
            "CrossingBicycleFlow",
            "EnterActorFlow",
            "HighwayExit",
            "InterurbanActorFlow",
            "HighwayCutIn",
            "InterurbanAdvancedActorFlow",
            "MergerIntoSlowTrafficV2",
            "MergerIntoSlowTraffic",
            "NonSignalizedJunctionLeftTurn",
            "NonSignalizedJunctionRightTurn",
            "NonSignalizedJunctionLeftTurnEnterFlow",
            "ParkingExit",
            "SequentialLaneChange",
            "SignalizedJunctionLeftTurn",
            "SignalizedJunctionRightTurn",
            "SignalizedJunctionLeftTurnEnterFlow",
        ],
    ),
    (
        "Emergency_Brake",
        &[
            "BlockedIntersection",
            "DynamicObjectCrossing",
            "HardBreakRoute",
            "OppositeVehicleTakingPriority",
            "OppositeVehicleRunningRedLight",
            "ParkingCutIn",
            "PedestrianCrossing",
            "ParkingCrossingPedestrian",
            "StaticCutIn",
            "VehicleTurningRoute",
            "VehicleTurningRoutePedestrian",
            "ControlLoss",
        ],
    ),
    ("Give_Way", &["InvadingTurn", "YieldToEmergencyVehicle"]),
    (
        TRAFFIC_SIGNS,
        &[
            "BlockedIntersection",
            "OppositeVehicleTakingPriority",
            "OppositeVehicleRunningRedLight",
            "PedestrianCrossing",
            "VehicleTurningRoute",
            "VehicleTurningRoutePedestrian",
            "EnterActorFlow",
            "CrossingBicycleFlow",
            "NonSignalizedJunctionLeftTurn",
            "NonSignalizedJunctionRightTurn",
            "NonSignalizedJunctionLeftTurnEnterFlow",
            "SignalizedJunctionLeftTurn",
            "SignalizedJunctionRightTurn",
            "SignalizedJunctionLeftTurnEnterFlow",
            "T_Junction",
            "VanillaNonSignalizedTurn",
            "VanillaSignalizedTurnEncounterGreenLight",
            "VanillaSignalizedTurnEncounterRedLight",
            "VanillaNonSignalizedTurnEncounterStopsign",
        ],
    ),
];

/// The ability whose failed routes may earn the junction credit.
pub const TRAFFIC_SIGNS: &str = "Traffic_Signs";

/// Samples added to the first junction sample's count in `junction_completion` (docs/SCORE.md §10.1).
pub const JUNCTION_MARGIN_SAMPLES: f64 = 8.0;

/// A route whose `score_route / 100` lies within this of its `junction_completion` is marginal.
pub const MARGINAL_BAND: f64 = 0.15;

/// The abilities a scenario type belongs to, in [`ABILITIES`] order.
pub fn abilities_of(scenario_type: &str) -> Vec<&'static str> {
    ABILITIES
        .iter()
        .filter(|(_, types)| types.contains(&scenario_type))
        .map(|(name, _)| *name)
        .collect()
}

/// One ability a route counts in, and whether it counts as a success there.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct AbilityEntry {
    /// The ability.
    #[serde(deserialize_with = "ability_name")]
    pub ability: crate::named::Name,
    /// A success for this ability (the §8.1 rule, or the junction credit for Traffic_Signs).
    pub success: bool,
    /// Under `ability_rule = b2d-0.0.3`, the second count of a Traffic_Signs route (its
    /// junction credit alone); see [`crate::route::protocol::ability_rule`].
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub second_count: bool,
}

name_field!(ability_name, ABILITIES.map(|(name, _)| name));

/// The junction credit of a failed Traffic_Signs route with no red-light or stop infraction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum JunctionCredit {
    /// Decided with the route's dense route on its town's map.
    Decided {
        /// `score_route / 100`.
        score: f64,
        /// `(c + 8) / n_samples`.
        junction_completion: f64,
        /// `score > junction_completion`.
        credited: bool,
        /// `|score - junction_completion| <= 0.15`: the decision may differ from
        /// Bench2Drive's (its samples are anchored differently, docs/SCORE.md §14.3).
        marginal: bool,
    },
    /// Cannot be decided; the route counts as failed.
    Undecided {
        /// Why (no map for the town, no junction sample).
        undecided: String,
    },
}

/// What a route contributes to the ability rates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RouteAbility {
    /// The scenario type of the route's XML entry.
    pub scenario_type: String,
    /// Every ability the type belongs to, in [`ABILITIES`] order (empty: the type is in none).
    pub abilities: Vec<AbilityEntry>,
    /// The Traffic_Signs junction credit, when it was considered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub junction: Option<JunctionCredit>,
}

impl RouteAbility {
    /// The entry of `ability`, if the route counts in it.
    pub fn get(&self, ability: &str) -> Option<&AbilityEntry> {
        self.abilities.iter().find(|e| e.ability == ability)
    }

    /// The credit could not be decided.
    pub fn undecided(&self) -> bool {
        matches!(self.junction, Some(JunctionCredit::Undecided { .. }))
    }
}

/// `junction_completion = (c + 8) / n_samples`, `c` = 1 + the index of the first sample in a
/// junction; `None` without a junction sample.
///
/// ```
/// use monitor_host::route::ability::junction_completion;
/// assert_eq!(junction_completion(&[false, false, true, false]), Some((3.0 + 8.0) / 4.0));
/// assert_eq!(junction_completion(&[false; 3]), None);
/// ```
pub fn junction_completion(in_junction: &[bool]) -> Option<f64> {
    let first = in_junction.iter().position(|&j| j)?;
    Some((first as f64 + 1.0 + JUNCTION_MARGIN_SAMPLES) / in_junction.len() as f64)
}

/// The route's abilities (docs/SCORE.md §10.1): `scenario_type` is the `type` of its route XML entry;
/// `samples` is called only for a failed Traffic_Signs route without red-light and stop
/// infractions, the one case where the junction credit decides.
///
/// ```
/// use monitor_host::route::ability::{route_ability, JunctionCredit};
/// use monitor_host::input::record::Record;
/// let r = Record::from_value(&serde_json::json!({
///     "route_id": "RouteScenario_1_rep0", "status": "Failed - Agent got blocked",
///     "infractions": {"vehicle_blocked": ["blocked"]},
///     "scores": {"score_route": 60.0, "score_penalty": 1.0, "score_composed": 60.0}}))?;
/// // 20 samples, the first in a junction is sample 2: (3 + 8) / 20 = 0.55 < 0.60: credited.
/// let a = route_ability(&r, "T_Junction", || Ok((0..20).map(|i| i == 2).collect()));
/// assert!(a.get("Traffic_Signs").unwrap().success);
/// assert!(matches!(a.junction, Some(JunctionCredit::Decided { marginal: true, .. })));
/// let a = route_ability(&r, "T_Junction", || Err("no map for Town12".into()));
/// assert!(!a.get("Traffic_Signs").unwrap().success && a.undecided());
/// # Ok::<(), monitor_host::input::record::InvalidRecord>(())
/// ```
pub fn route_ability(
    record: &Record,
    scenario_type: &str,
    samples: impl FnOnce() -> JunctionSamples,
) -> RouteAbility {
    let success = record.is_success();
    let names = abilities_of(scenario_type);
    let mut junction = None;
    if !success && names.contains(&TRAFFIC_SIGNS) && credit_eligible(record) {
        junction = Some(junction_credit(record.score_route / 100.0, samples));
    }
    let credited = matches!(
        junction,
        Some(JunctionCredit::Decided { credited: true, .. })
    );
    RouteAbility {
        scenario_type: scenario_type.to_string(),
        abilities: names
            .into_iter()
            .map(|ability| AbilityEntry {
                ability,
                success: success || (ability == TRAFFIC_SIGNS && credited),
                second_count: false,
            })
            .collect(),
        junction,
    }
}

/// No red-light and no stop infraction: the junction credit may apply.
pub fn credit_eligible(r: &Record) -> bool {
    r.infractions.list("stop_infraction").is_empty() && r.infractions.list("red_light").is_empty()
}

/// The junction credit of a route whose `score_route / 100` is `score`, decided on its dense
/// route's junction flags (`samples`), or undecided when they are not known.
pub fn junction_credit(score: f64, samples: impl FnOnce() -> JunctionSamples) -> JunctionCredit {
    match samples() {
        Err(why) => JunctionCredit::Undecided { undecided: why },
        Ok(flags) => match junction_completion(&flags) {
            None => JunctionCredit::Undecided {
                undecided: format!("no junction sample among {} samples", flags.len()),
            },
            Some(c) => JunctionCredit::Decided {
                score,
                junction_completion: c,
                credited: score > c,
                marginal: (score - c).abs() <= MARGINAL_BAND,
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_type_of_the_spec_is_listed_once_per_ability() {
        let total: usize = ABILITIES.iter().map(|(_, t)| t.len()).sum();
        assert_eq!(total, 9 + 16 + 12 + 2 + 19);
        for (_, types) in ABILITIES {
            let mut t = types.to_vec();
            t.sort_unstable();
            t.dedup();
            assert_eq!(t.len(), types.len());
        }
    }

    fn record(status: &str, lists: serde_json::Value, score_route: f64) -> Record {
        Record::from_value(&serde_json::json!({
            "route_id": "RouteScenario_1_rep0", "status": status, "infractions": lists,
            "scores": {"score_route": score_route, "score_penalty": 1.0, "score_composed": score_route}}))
        .unwrap()
    }

    #[test]
    fn credit_rules() {
        let never = || -> JunctionSamples { panic!("the map is not needed") };
        // A success needs no map.
        let ok = record("Completed", serde_json::json!({}), 100.0);
        let a = route_ability(&ok, "SignalizedJunctionLeftTurn", never);
        assert_eq!(a.abilities.len(), 2);
        assert!(a.abilities.iter().all(|e| e.success) && a.junction.is_none());
        // A red light decides the failure without a map.
        let red = record("Completed", serde_json::json!({"red_light": ["r"]}), 100.0);
        let a = route_ability(&red, "T_Junction", never);
        assert!(!a.get(TRAFFIC_SIGNS).unwrap().success && a.junction.is_none());
        // A failed route of another ability never asks for the map.
        let failed = record("Failed", serde_json::json!({}), 90.0);
        assert!(!route_ability(&failed, "Accident", never).abilities[0].success);
        // Strictly greater: equal is not credited.
        let at = record("Failed", serde_json::json!({}), 50.0);
        let a = route_ability(&at, "T_Junction", || Ok((0..22).map(|i| i >= 2).collect()));
        assert_eq!(
            a.junction,
            Some(JunctionCredit::Decided {
                score: 0.5,
                junction_completion: 0.5,
                credited: false,
                marginal: true
            })
        );
        let a = route_ability(&at, "T_Junction", || Ok(vec![false; 5]));
        assert!(a.undecided());
        // Merging and Traffic_Signs: the credit only counts for Traffic_Signs.
        let a = route_ability(&failed, "EnterActorFlow", || {
            Ok((0..100).map(|i| i == 0).collect())
        });
        assert!(!a.get("Merging").unwrap().success && a.get(TRAFFIC_SIGNS).unwrap().success);
    }
}
