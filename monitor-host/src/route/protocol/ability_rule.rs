//! Which Bench2Drive release's ability rule counts the Traffic_Signs routes (docs/SCORE.md
//! §10.1, setting `ability_rule`).
//!
//! - `b2d-0.0.4` (default): a Traffic_Signs route counts once; a failed one without red-light
//!   and stop infractions is a success when `score_route / 100 > junction_completion`.
//! - `b2d-0.0.3` (the table most papers cite): every Traffic_Signs route counts **twice** —
//!   once with its success, once more as a success iff `score_route / 100 >
//!   junction_completion` and it has no red-light and no stop infraction, whatever its success.
//!   The denominator is twice the routes: TransFuser++'s 0.8211 is 156/190 (95 routes: 67
//!   successes, each credited again, and 22 failed routes credited), not 78/95.
//!
//! ```
//! use monitor_host::route::ability::route_ability;
//! use monitor_host::input::record::Record;
//! use monitor_host::route::protocol::ability_rule::{apply_rule, AbilityRule};
//! let ok = Record::from_value(&serde_json::json!({
//!     "route_id": "RouteScenario_1_rep0", "status": "Completed", "infractions": {},
//!     "scores": {"score_route": 100, "score_penalty": 1.0, "score_composed": 100.0}}))?;
//! let flags = || Ok((0..20).map(|i| i == 2).collect()); // junction_completion 0.55
//! let a = apply_rule(AbilityRule::B2d003, route_ability(&ok, "T_Junction", flags), &ok, flags);
//! let ts: Vec<bool> = a.abilities.iter().filter(|e| e.ability == "Traffic_Signs").map(|e| e.success).collect();
//! assert_eq!(ts, [true, true]); // counted twice, credited twice
//! assert_eq!(AbilityRule::from_name("b2d-0.0.3"), Some(AbilityRule::B2d003));
//! # Ok::<(), monitor_host::input::record::InvalidRecord>(())
//! ```

use crate::geometry::junctions::JunctionSamples;
use crate::input::record::Record;
use crate::route::ability::{
    credit_eligible, junction_credit, AbilityEntry, JunctionCredit, RouteAbility, TRAFFIC_SIGNS,
};

pub use crate::settings::AbilityRule;

/// A route's abilities under `rule`, from those under `b2d-0.0.4`
/// ([`crate::route::ability::route_ability`]). Under `b2d-0.0.3` a Traffic_Signs route's
/// first count is its plain success, and a second entry (`second_count`) holds its junction
/// credit, decided now with `samples` for a route that had no decision yet (a success).
pub fn apply_rule(
    rule: AbilityRule,
    mut ability: RouteAbility,
    record: &Record,
    samples: impl FnOnce() -> JunctionSamples,
) -> RouteAbility {
    if rule == AbilityRule::B2d004 {
        return ability;
    }
    let Some(i) = ability
        .abilities
        .iter()
        .position(|e| e.ability == TRAFFIC_SIGNS)
    else {
        return ability;
    };
    ability.abilities[i].success = record.is_success();
    let credited = if credit_eligible(record) {
        let j = ability
            .junction
            .take()
            .unwrap_or_else(|| junction_credit(record.score_route / 100.0, samples));
        let credited = matches!(j, JunctionCredit::Decided { credited: true, .. });
        ability.junction = Some(j);
        credited
    } else {
        false
    };
    ability.abilities.insert(
        i + 1,
        AbilityEntry {
            ability: TRAFFIC_SIGNS,
            success: credited,
            second_count: true,
        },
    );
    ability
}
