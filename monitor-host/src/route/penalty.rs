//! The re-check of a record's `score_penalty` against its infraction lists (docs/SCORE.md
//! §9). It only reports: the recorded penalty stays authoritative.
//!
//! ```
//! use monitor_host::route::penalty::recompute_penalty;
//! use monitor_host::settings::PenaltyFlavour;
//! use monitor_host::input::record::Infractions;
//! let inf = Infractions::from_lists([("collisions_vehicle", vec!["hit".to_string()])]);
//! assert_eq!(recompute_penalty(&inf, PenaltyFlavour::Bench2Drive), Ok(0.6));
//! ```

use crate::input::record::{Infractions, Record};
use crate::settings::PenaltyFlavour;

/// Per-event factors of the lists with a constant factor (docs/SCORE.md §9), in a fixed order.
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

pub use crate::input::message::{min_speed_percent, outside_lanes_percent};

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

/// Tolerance of the penalty re-check (docs/SCORE.md §9).
pub const PENALTY_TOLERANCE: f64 = 1e-3;

/// Re-checks `record.score_penalty` against its infraction lists (docs/SCORE.md §9). It only reports.
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
        Infractions::of(lists)
    }

    #[test]
    fn flavour_names() {
        for f in [PenaltyFlavour::Bench2Drive, PenaltyFlavour::Leaderboard20] {
            assert_eq!(PenaltyFlavour::from_name(f.name()), Some(f));
        }
        assert_eq!(PenaltyFlavour::from_name("b2d"), None);
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
