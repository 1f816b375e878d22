//! Infraction strings: collision events, work-zone contacts (`SDS-SPEC.md` §7) and the
//! re-check of the recorded `score_penalty` against the infraction lists (§8).
//!
//! ```
//! use monitor_host::infraction::{is_workzone, parse_collision};
//! let c = parse_collision(
//!     "Agent collided against object with type=static.prop.trafficwarning and id=122 \
//!      at (x=-1.5, y=1e-05, z=200.0)",
//! )?;
//! assert_eq!(c.type_id, "static.prop.trafficwarning");
//! assert_eq!(c.actor_id, Some(122));
//! assert_eq!(c.location, Some([-1.5, 1e-05, 200.0]));
//! assert!(is_workzone(&c.type_id));
//! assert!(!is_workzone("static.prop.mesh"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::results::{Infractions, Record};

/// The three collision lists of a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CollisionList {
    /// `collisions_pedestrian`.
    Pedestrian,
    /// `collisions_vehicle`.
    Vehicle,
    /// `collisions_layout` (static objects; work-zone contacts are among these).
    Layout,
}

impl CollisionList {
    /// All three, in the spec's order.
    pub const ALL: [CollisionList; 3] = [
        CollisionList::Pedestrian,
        CollisionList::Vehicle,
        CollisionList::Layout,
    ];

    /// The list's name in a record: `collisions_pedestrian`, `collisions_vehicle`,
    /// `collisions_layout`.
    pub fn name(self) -> &'static str {
        match self {
            CollisionList::Pedestrian => "collisions_pedestrian",
            CollisionList::Vehicle => "collisions_vehicle",
            CollisionList::Layout => "collisions_layout",
        }
    }

    /// The list named `name`, if it is one of the three.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.name() == name)
    }
}

/// One parsed collision string.
#[derive(Debug, Clone, PartialEq)]
pub struct Collision {
    /// CARLA blueprint type, e.g. `static.prop.constructioncone`, `vehicle.audi.tt`.
    pub type_id: String,
    /// CARLA actor id, when the string has `and id=<n>`.
    pub actor_id: Option<u64>,
    /// The ego's location `[x, y, z]` (m, CARLA world) at the collision, when given.
    pub location: Option<[f64; 3]>,
}

/// A collision string that does not have the expected form.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot parse collision {input:?}: {reason}")]
pub struct CollisionParseError {
    /// The string.
    pub input: String,
    /// What is wrong with it.
    pub reason: String,
}

const COLLISION_PREFIX: &str = "Agent collided against object with type=";

/// Parses `Agent collided against object with type=<type_id> and id=<actor_id> at (x=<x>,
/// y=<y>, z=<z>)`. The ` and id=..` and ` at (..)` parts may be absent; when present they must
/// be well formed. Coordinates are Python floats (`-1.5`, `1e-05`, `200.0`) and must be finite.
pub fn parse_collision(s: &str) -> Result<Collision, CollisionParseError> {
    let err = |reason: &str| CollisionParseError {
        input: s.to_string(),
        reason: reason.to_string(),
    };
    let rest = s
        .strip_prefix(COLLISION_PREFIX)
        .ok_or_else(|| err("does not start with \"Agent collided against object with type=\""))?;
    let type_end = rest.find(char::is_whitespace).unwrap_or(rest.len());
    let type_id = &rest[..type_end];
    if type_id.is_empty() {
        return Err(err("empty type"));
    }
    let mut rest = &rest[type_end..];

    let mut actor_id = None;
    if let Some(after) = rest.strip_prefix(" and id=") {
        let end = after
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(after.len());
        if end == 0 {
            return Err(err("id is not a non-negative integer"));
        }
        actor_id = Some(
            after[..end]
                .parse::<u64>()
                .map_err(|_| err("id does not fit in 64 bits"))?,
        );
        rest = &after[end..];
    }

    let mut location = None;
    if let Some(after) = rest.strip_prefix(" at (") {
        let inner = after
            .strip_suffix(')')
            .ok_or_else(|| err("location does not end with ')'"))?;
        let mut xyz = [0.0f64; 3];
        let mut parts = inner.split(", ");
        for (slot, axis) in xyz.iter_mut().zip(["x=", "y=", "z="]) {
            let part = parts
                .next()
                .ok_or_else(|| err("location has fewer than 3 coordinates"))?;
            let num = part.strip_prefix(axis).ok_or_else(|| {
                err(&format!(
                    "location: expected \"{axis}<number>\", got {part:?}"
                ))
            })?;
            *slot = parse_python_float(num)
                .ok_or_else(|| err(&format!("location: {axis}{num:?} is not a finite number")))?;
        }
        if parts.next().is_some() {
            return Err(err("location has more than 3 coordinates"));
        }
        location = Some(xyz);
        rest = "";
    }
    if !rest.is_empty() {
        return Err(err(&format!("unexpected text {rest:?} after the type/id")));
    }
    Ok(Collision {
        type_id: type_id.to_string(),
        actor_id,
        location,
    })
}

/// A finite decimal/scientific float as Python's `repr` writes it; `nan`/`inf` are refused.
fn parse_python_float(s: &str) -> Option<f64> {
    let ok_chars = s
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E'));
    if s.is_empty() || !ok_chars || !s.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The substrings that make a `static.prop.` type a work-zone object (§7), case-sensitive.
pub const WORKZONE_KEYWORDS: [&str; 6] = [
    "cone",
    "trafficwarning",
    "warningconstruction",
    "warningaccident",
    "barrier",
    "barrel",
];

/// §7: `type_id` starts with `static.prop.` and contains one of [`WORKZONE_KEYWORDS`]
/// (case-sensitive). `static.prop.mesh` (a parked car) and `static.prop.dirtdebris*` are not.
pub fn is_workzone(type_id: &str) -> bool {
    type_id.starts_with("static.prop.") && WORKZONE_KEYWORDS.iter().any(|k| type_id.contains(k))
}

/// The number of `collisions_layout` entries that parse and are work-zone contacts (`N_wz`).
/// Unparseable strings are not counted (see [`parse_collision`] to report them).
pub fn count_workzone(inf: &Infractions) -> usize {
    inf.list(CollisionList::Layout.name())
        .iter()
        .filter_map(|s| parse_collision(s).ok())
        .filter(|c| is_workzone(&c.type_id))
        .count()
}

/// Which evaluator's penalty rules to re-check against (§8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PenaltyFlavour {
    /// Bench2Drive: min-speed infractions carry no factor.
    Bench2Drive,
    /// CARLA Leaderboard 2.0: each min-speed infraction multiplies by `1 - 0.3 (1 - pct/100)`.
    Leaderboard20,
}

impl PenaltyFlavour {
    /// `"bench2drive"` or `"leaderboard20"` (the name used in reports and on the command line).
    pub fn name(self) -> &'static str {
        match self {
            PenaltyFlavour::Bench2Drive => "bench2drive",
            PenaltyFlavour::Leaderboard20 => "leaderboard20",
        }
    }

    /// The flavour named `name` (see [`PenaltyFlavour::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        [PenaltyFlavour::Bench2Drive, PenaltyFlavour::Leaderboard20]
            .into_iter()
            .find(|f| f.name() == name)
    }
}

/// Per-event factors of the lists with a constant factor (§8), in a fixed order.
pub const PENALTY_FACTORS: [(&str, f64); 7] = [
    ("collisions_pedestrian", 0.5),
    ("collisions_vehicle", 0.6),
    ("collisions_layout", 0.65),
    ("red_light", 0.7),
    ("stop_infraction", 0.8),
    ("scenario_timeouts", 0.7),
    ("yield_emergency_vehicle_infractions", 0.7),
];

/// Recomputes the infraction penalty from the lists with the §8 factors: constant factors
/// ([`PENALTY_FACTORS`]) per entry, `outside_route_lanes` `× (1 - pct/100)` per entry, and for
/// [`PenaltyFlavour::Leaderboard20`] `min_speed_infractions` `× (1 - 0.3 (1 - pct/100))` per
/// entry. Other lists (route_dev, vehicle_blocked, route_timeout, unknown ones) carry no factor.
/// A string whose percentage cannot be read is an error naming the list and the string.
///
/// The factor is applied as the spec states it, also for `pct > 100` (a factor above 1).
pub fn recompute_penalty(inf: &Infractions, flavour: PenaltyFlavour) -> Result<f64, String> {
    let mut penalty = 1.0f64;
    for (name, factor) in PENALTY_FACTORS {
        for _ in inf.list(name) {
            penalty *= factor;
        }
    }
    for s in inf.list("outside_route_lanes") {
        let pct = outside_lanes_percent(s)
            .ok_or_else(|| format!("outside_route_lanes: no percentage in {s:?}"))?;
        penalty *= 1.0 - pct / 100.0;
    }
    if flavour == PenaltyFlavour::Leaderboard20 {
        for s in inf.list("min_speed_infractions") {
            let pct = min_speed_percent(s)
                .ok_or_else(|| format!("min_speed_infractions: no percentage in {s:?}"))?;
            penalty *= 1.0 - 0.3 * (1.0 - pct / 100.0);
        }
    }
    Ok(penalty)
}

/// The percentage of `Agent went outside its route lanes for about <m> meters (<pct>% of the
/// completed route)`.
pub fn outside_lanes_percent(s: &str) -> Option<f64> {
    let open = s.rfind('(')?;
    let inner = &s[open + 1..];
    let end = inner.find("% of the completed route)")?;
    parse_python_float(&inner[..end])
}

/// The percentage of `Average speed is <pct>% of the surrounding traffic's one`.
pub fn min_speed_percent(s: &str) -> Option<f64> {
    let rest = s.strip_prefix("Average speed is ")?;
    let end = rest.find('%')?;
    parse_python_float(&rest[..end])
}

/// The result of re-checking a record's `score_penalty`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PenaltyCheck {
    /// The recomputed penalty; NaN when a percentage could not be read (call
    /// [`recompute_penalty`] for the reason).
    pub recomputed: f64,
    /// The recorded `scores.score_penalty`.
    pub recorded: f64,
    /// `|recomputed - recorded| <= 1e-3` (false when `recomputed` is NaN).
    pub agrees: bool,
}

/// Tolerance of the penalty re-check (§8).
pub const PENALTY_TOLERANCE: f64 = 1e-3;

/// Re-checks `record.score_penalty` against its infraction lists (§8). It only reports.
pub fn check_penalty(record: &Record, flavour: PenaltyFlavour) -> PenaltyCheck {
    let recorded = record.score_penalty;
    match recompute_penalty(&record.infractions, flavour) {
        Ok(recomputed) => PenaltyCheck {
            recomputed,
            recorded,
            agrees: (recomputed - recorded).abs() <= PENALTY_TOLERANCE,
        },
        Err(_) => PenaltyCheck {
            recomputed: f64::NAN,
            recorded,
            agrees: false,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inf(lists: &[(&str, &[&str])]) -> Infractions {
        Infractions::from_lists(
            lists
                .iter()
                .map(|(n, l)| (*n, l.iter().map(|s| s.to_string()).collect())),
        )
    }

    #[test]
    fn flavour_names() {
        for f in [PenaltyFlavour::Bench2Drive, PenaltyFlavour::Leaderboard20] {
            assert_eq!(PenaltyFlavour::from_name(f.name()), Some(f));
        }
        assert_eq!(PenaltyFlavour::from_name("b2d"), None);
    }

    #[test]
    fn list_names() {
        for l in CollisionList::ALL {
            assert_eq!(CollisionList::from_name(l.name()), Some(l));
        }
        assert_eq!(CollisionList::Vehicle.name(), "collisions_vehicle");
        assert_eq!(CollisionList::from_name("red_light"), None);
    }

    #[test]
    fn parses_full_collision() {
        let c = parse_collision(
            "Agent collided against object with type=vehicle.lincoln.mkz_2020 and id=4211 at (x=6315.271, y=-4998.388, z=172.663)",
        )
        .unwrap();
        assert_eq!(c.type_id, "vehicle.lincoln.mkz_2020");
        assert_eq!(c.actor_id, Some(4211));
        assert_eq!(c.location, Some([6315.271, -4998.388, 172.663]));
    }

    #[test]
    fn tolerates_missing_parts() {
        let c = parse_collision(
            "Agent collided against object with type=static.prop.mesh and id=325426",
        )
        .unwrap();
        assert_eq!((c.actor_id, c.location), (Some(325426), None));
        let c = parse_collision("Agent collided against object with type=static.fence").unwrap();
        assert_eq!(
            (c.type_id.as_str(), c.actor_id, c.location),
            ("static.fence", None, None)
        );
        let c = parse_collision(
            "Agent collided against object with type=static.pole at (x=1E+3, y=0.0, z=-0.001)",
        )
        .unwrap();
        assert_eq!(c.location, Some([1000.0, 0.0, -0.001]));
    }

    #[test]
    fn rejects_bad_strings() {
        let bad = [
            "",
            "Agent ran a red light 12 at (x=1.0, y=2.0, z=3.0)",
            "Agent collided against object with type=",
            "Agent collided against object with type= and id=3",
            "Agent collided against object with type=static.pole and id=abc",
            "Agent collided against object with type=static.pole and id=-4",
            "Agent collided against object with type=static.pole and id=99999999999999999999999",
            "Agent collided against object with type=static.pole and id=3 at (x=1.0, y=2.0)",
            "Agent collided against object with type=static.pole and id=3 at (x=1.0, y=2.0, z=3.0",
            "Agent collided against object with type=static.pole and id=3 at (x=nan, y=2.0, z=3.0)",
            "Agent collided against object with type=static.pole and id=3 at (x=inf, y=2.0, z=3.0)",
            "Agent collided against object with type=static.pole and id=3 at (x=1.0, y=2.0, z=3.0, w=4.0)",
            "Agent collided against object with type=static.pole and id=3 at (y=1.0, x=2.0, z=3.0)",
            "Agent collided against object with type=static.pole and id=3 at (x=1..0, y=2.0, z=3.0)",
            "Agent collided against object with type=static.pole and id=3 somewhere",
        ];
        for s in bad {
            let e = parse_collision(s).expect_err(s);
            assert_eq!(e.input, s);
            assert!(!e.reason.is_empty());
        }
        let e = parse_collision(
            "Agent collided against object with type=static.pole and id=3 at (x=1.0, y=2.0)",
        )
        .unwrap_err();
        assert_eq!(e.reason, "location has fewer than 3 coordinates");
    }

    #[test]
    fn workzone_types() {
        for t in [
            "static.prop.constructioncone",
            "static.prop.trafficwarning",
            "static.prop.warningconstruction",
            "static.prop.warningaccident",
            "static.prop.streetbarrier",
            "static.prop.barrel",
            "static.prop.trafficcone01",
        ] {
            assert!(is_workzone(t), "{t}");
        }
        for t in [
            "static.prop.mesh",
            "static.prop.dirtdebris01",
            "static.prop.ConstructionCone",
            "static.prop.TrafficWarning",
            "static.cone",
            "vehicle.prop.constructioncone",
            "static.guardrail",
            "static.prop.",
            "",
        ] {
            assert!(!is_workzone(t), "{t}");
        }
    }

    #[test]
    fn counts_workzone_contacts() {
        let i = inf(&[
            (
                "collisions_layout",
                &[
                    "Agent collided against object with type=static.prop.constructioncone and id=1 at (x=1.0, y=2.0, z=3.0)",
                    "Agent collided against object with type=static.prop.mesh and id=2 at (x=1.0, y=2.0, z=3.0)",
                    "garbage",
                    "Agent collided against object with type=static.prop.barrel and id=3",
                ],
            ),
            (
                "collisions_vehicle",
                &["Agent collided against object with type=static.prop.barrel and id=4"],
            ),
        ]);
        assert_eq!(count_workzone(&i), 2);
    }

    #[test]
    fn percentages() {
        assert_eq!(
            outside_lanes_percent("Agent went outside its route lanes for about 4.001 meters (10.91% of the completed route)"),
            Some(10.91)
        );
        assert_eq!(
            outside_lanes_percent("Agent went outside its route lanes"),
            None
        );
        assert_eq!(outside_lanes_percent("(x% of the completed route)"), None);
        assert_eq!(
            min_speed_percent("Average speed is 1098.69% of the surrounding traffic's one"),
            Some(1098.69)
        );
        assert_eq!(
            min_speed_percent("Average speed is 100% of the surrounding traffic's one"),
            Some(100.0)
        );
        assert_eq!(min_speed_percent("Average speed is fast"), None);
        assert_eq!(min_speed_percent("Speed is 10% of it"), None);
    }

    #[test]
    fn recompute_factors() {
        let i = inf(&[
            ("collisions_pedestrian", &["p"]),
            ("collisions_vehicle", &["v", "v"]),
            ("collisions_layout", &["l"]),
            ("red_light", &["r"]),
            ("stop_infraction", &["s"]),
            ("scenario_timeouts", &["t"]),
            ("yield_emergency_vehicle_infractions", &["y"]),
            ("route_dev", &["d"]),
            ("vehicle_blocked", &["b"]),
            ("route_timeout", &["Route timeout."]),
            ("made_up", &["m"]),
            (
                "outside_route_lanes",
                &["Agent went outside its route lanes for about 3.0 meters (20% of the completed route)"],
            ),
            ("min_speed_infractions", &["Average speed is 50% of the surrounding traffic's one"]),
        ]);
        let b2d = 0.5 * 0.6 * 0.6 * 0.65 * 0.7 * 0.8 * 0.7 * 0.7 * 0.8;
        let got = recompute_penalty(&i, PenaltyFlavour::Bench2Drive).unwrap();
        assert!((got - b2d).abs() < 1e-12, "{got} vs {b2d}");
        let got = recompute_penalty(&i, PenaltyFlavour::Leaderboard20).unwrap();
        assert!((got - b2d * 0.85).abs() < 1e-12, "{got}");
        assert_eq!(
            recompute_penalty(&Infractions::new(), PenaltyFlavour::Leaderboard20),
            Ok(1.0)
        );
    }

    #[test]
    fn recompute_reports_unreadable_percentages() {
        let i = inf(&[(
            "outside_route_lanes",
            &["Agent went outside its route lanes"],
        )]);
        let e = recompute_penalty(&i, PenaltyFlavour::Bench2Drive).unwrap_err();
        assert!(e.starts_with("outside_route_lanes: no percentage"), "{e}");
        let i = inf(&[("min_speed_infractions", &["slow"])]);
        // Bench2Drive ignores min speed entirely; Leaderboard 2.0 needs the percentage
        assert_eq!(recompute_penalty(&i, PenaltyFlavour::Bench2Drive), Ok(1.0));
        let e = recompute_penalty(&i, PenaltyFlavour::Leaderboard20).unwrap_err();
        assert!(e.starts_with("min_speed_infractions: no percentage"), "{e}");
    }

    fn record(penalty: f64, lists: &[(&str, &[&str])]) -> Record {
        Record {
            route_id: "RouteScenario_1_rep0".into(),
            scenario_name: "Accident_1".into(),
            weather_id: None,
            save_name: None,
            town_name: None,
            status: "Completed".into(),
            infractions: inf(lists),
            score_route: 100.0,
            score_penalty: penalty,
            score_composed: 100.0 * penalty,
            meta: Default::default(),
        }
    }

    #[test]
    fn check_penalty_tolerance() {
        let lists: &[(&str, &[&str])] = &[("collisions_layout", &["a", "b", "c"])];
        let c = check_penalty(&record(0.274625, lists), PenaltyFlavour::Bench2Drive);
        assert!(c.agrees && (c.recomputed - 0.274625).abs() < 1e-12);
        assert!(check_penalty(&record(0.2756, lists), PenaltyFlavour::Bench2Drive).agrees);
        let c = check_penalty(&record(0.2757, lists), PenaltyFlavour::Bench2Drive);
        assert!(!c.agrees);
        assert_eq!(c.recorded, 0.2757);
        let c = check_penalty(
            &record(1.0, &[("outside_route_lanes", &["?"])]),
            PenaltyFlavour::Bench2Drive,
        );
        assert!(!c.agrees && c.recomputed.is_nan());
    }
}
