//! Collision strings of the evaluator's infraction lists (docs/SCORE.md §6, docs/SCORE.md §8): the three
//! collision lists, the parsed string (type, actor id, location), and work-zone contacts.
//!
//! ```
//! use monitor_host::input::collision::{is_workzone, parse_collision};
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

use crate::input::record::Infractions;
use monitor_core::Collisions;

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

    /// The list the leaderboard's collision test files a contact with an actor of this CARLA
    /// blueprint `type_id` under: static objects and traffic props (sidewalks aside) are
    /// `collisions_layout`, then vehicles, then walkers; anything else is not an infraction.
    /// For live front ends that see the collision sensor's `other_actor.type_id`.
    ///
    /// ```
    /// use monitor_host::input::collision::CollisionList;
    /// assert_eq!(CollisionList::of_actor("vehicle.audi.tt"), Some(CollisionList::Vehicle));
    /// assert_eq!(CollisionList::of_actor("walker.pedestrian.0001"), Some(CollisionList::Pedestrian));
    /// assert_eq!(CollisionList::of_actor("static.prop.constructioncone"), Some(CollisionList::Layout));
    /// assert_eq!(CollisionList::of_actor("sensor.other.collision"), None);
    /// ```
    pub fn of_actor(type_id: &str) -> Option<Self> {
        if (type_id.contains("static") || type_id.contains("traffic"))
            && !type_id.contains("sidewalk")
        {
            Some(CollisionList::Layout)
        } else if type_id.contains("vehicle") {
            Some(CollisionList::Vehicle)
        } else if type_id.contains("walker") {
            Some(CollisionList::Pedestrian)
        } else {
            None
        }
    }

    /// Counts one collision of this list in a frame's [`Collisions`] (a `workzone` contact of
    /// `collisions_layout` in its own slot).
    ///
    /// ```
    /// use monitor_core::Collisions;
    /// use monitor_host::input::collision::CollisionList;
    /// let mut c = Collisions::NONE;
    /// CollisionList::Layout.count_in(true, &mut c);
    /// CollisionList::Vehicle.count_in(false, &mut c);
    /// assert_eq!((c.workzone, c.vehicle, c.layout), (1, 1, 0));
    /// ```
    pub fn count_in(self, workzone: bool, c: &mut Collisions) {
        let slot = match (self, workzone) {
            (CollisionList::Pedestrian, _) => &mut c.pedestrian,
            (CollisionList::Vehicle, _) => &mut c.vehicle,
            (CollisionList::Layout, true) => &mut c.workzone,
            (CollisionList::Layout, false) => &mut c.layout,
        };
        *slot = slot.saturating_add(1);
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
pub(crate) fn parse_python_float(s: &str) -> Option<f64> {
    let ok_chars = s
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E'));
    if s.is_empty() || !ok_chars || !s.bytes().any(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The substrings that make a `static.prop.` type a work-zone object (docs/SCORE.md §8), case-sensitive.
pub const WORKZONE_KEYWORDS: [&str; 6] = [
    "cone",
    "trafficwarning",
    "warningconstruction",
    "warningaccident",
    "barrier",
    "barrel",
];

/// docs/SCORE.md §8: `type_id` starts with `static.prop.` and contains one of [`WORKZONE_KEYWORDS`]
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

#[cfg(test)]
mod tests {
    use super::*;

    fn inf(lists: &[(&str, &[&str])]) -> Infractions {
        Infractions::of(lists)
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
}
