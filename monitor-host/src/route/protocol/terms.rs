//! The fixed per-event terms of the protocols (docs/PROTOCOLS.md): per infraction list,
//! the Leaderboard 2.0 / Bench2Drive factor `v` and the Leaderboard 2.1 cost `c`, and the
//! min-speed weights. One table, so that no protocol can drift from another.
//!
//! ```
//! use monitor_host::route::protocol::terms::{lb20_min_speed_factor, lb21_min_speed_cost, FIXED_TERMS};
//! assert_eq!(FIXED_TERMS.len(), 7);
//! assert_eq!(lb20_min_speed_factor(50.0), 0.85);
//! assert_eq!(lb21_min_speed_cost(50.0), 0.2);
//! ```

/// One infraction list with a constant term per entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedTerm {
    /// The infraction list.
    pub list: &'static str,
    /// Leaderboard 2.0's (and Bench2Drive's) factor per entry.
    pub factor: f64,
    /// Leaderboard 2.1's cost per entry.
    pub cost: f64,
}

/// The seven lists with a constant term, in the order of §8.
pub const FIXED_TERMS: [FixedTerm; 7] = [
    FixedTerm {
        list: "collisions_pedestrian",
        factor: 0.5,
        cost: 1.0,
    },
    FixedTerm {
        list: "collisions_vehicle",
        factor: 0.6,
        cost: 0.7,
    },
    FixedTerm {
        list: "collisions_layout",
        factor: 0.65,
        cost: 0.6,
    },
    FixedTerm {
        list: "red_light",
        factor: 0.7,
        cost: 0.4,
    },
    FixedTerm {
        list: "stop_infraction",
        factor: 0.8,
        cost: 0.25,
    },
    FixedTerm {
        list: "scenario_timeouts",
        factor: 0.7,
        cost: 0.4,
    },
    FixedTerm {
        list: "yield_emergency_vehicle_infractions",
        factor: 0.7,
        cost: 0.4,
    },
];

/// Leaderboard 2.0's min-speed weight: a factor `1 - 0.3 (1 - P/100)` per entry.
pub const LB20_MIN_SPEED_WEIGHT: f64 = 0.3;

/// Leaderboard 2.1's min-speed weight: a cost `0.4 (1 - P/100)` per entry.
pub const LB21_MIN_SPEED_WEIGHT: f64 = 0.4;

/// LEAD's scale of the fixed factors: `(0.2 v)^(n / km)`.
pub const LEAD_SCALE: f64 = 0.2;

/// Leaderboard 2.0's factor of one min-speed entry at `p` percent.
pub fn lb20_min_speed_factor(p: f64) -> f64 {
    1.0 - LB20_MIN_SPEED_WEIGHT * (1.0 - p / 100.0)
}

/// Leaderboard 2.1's cost of one min-speed entry at `p` percent.
pub fn lb21_min_speed_cost(p: f64) -> f64 {
    LB21_MIN_SPEED_WEIGHT * (1.0 - p / 100.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::penalty::PENALTY_FACTORS;

    #[test]
    fn factors_are_the_penalty_checks() {
        // Leaderboard 2.0's factors are the ones §8's penalty re-check uses.
        for (t, (list, factor)) in FIXED_TERMS.iter().zip(PENALTY_FACTORS) {
            assert_eq!((t.list, t.factor), (list, factor));
        }
    }
}
