//! The outside-lanes factor `f_out` of a route (docs/PROTOCOLS.md), recovered exactly.
//!
//! The message `... (<Q>% of the completed route)` rounds the percentage; the recorded
//! `score_penalty` holds the unrounded factor. So when the route's Bench2Drive penalty
//! re-check agrees (docs/SCORE.md §9), `f_out = score_penalty / prod(fixed factors)`, clamped to [0, 1];
//! otherwise `f_out = 1 - Q/100` from the first entry's message, with a warning.
//!
//! ```
//! use monitor_host::input::record::Record;
//! use monitor_host::route::protocol::outside_lanes::{outside_lanes_factor, FOutSource};
//! let r = Record::from_value(&serde_json::json!({
//!     "route_id": "RouteScenario_1_rep0", "status": "Completed",
//!     "infractions": {"collisions_vehicle": ["hit"], "outside_route_lanes": [
//!         "Agent went outside its route lanes for about 4.1 meters (10.91% of the completed route)"]},
//!     "scores": {"score_route": 100, "score_penalty": 0.534594, "score_composed": 53.4594}}))?;
//! let f = outside_lanes_factor(&r);
//! assert_eq!(f.source, FOutSource::RecordedPenalty);
//! assert!((f.factor - 0.534594 / 0.6).abs() < 1e-12); // 0.89099, not the message's 0.8909
//! # Ok::<(), monitor_host::input::record::InvalidRecord>(())
//! ```

use serde::Serialize;

use crate::input::message::{outside_lanes_percent_text, percent_of, Percent};
use crate::input::record::Record;
use crate::route::penalty::check_penalty;
use crate::route::protocol::terms::FIXED_TERMS;
use crate::settings::PenaltyFlavour;

/// The list of outside-lanes entries.
pub const OUTSIDE_LIST: &str = "outside_route_lanes";

/// Where a route's `f_out` came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FOutSource {
    /// The route has no outside-lanes entry: `f_out = 1`.
    NoEntry,
    /// The recorded penalty divided by the fixed factors (exact).
    RecordedPenalty,
    /// `1 - Q/100` from the first entry's (rounded) percentage.
    Message,
    /// Neither could be read: `f_out = 1`.
    Unknown,
}

/// A route's outside-lanes factor.
#[derive(Clone, Debug, PartialEq)]
pub struct OutsideLanes {
    /// `f_out` in [0, 1].
    pub factor: f64,
    /// Where it came from.
    pub source: FOutSource,
    /// Why the exact recovery was not used (the warning), when it was not.
    pub warning: Option<String>,
}

/// The product of the fixed factors of a record's lists (docs/SCORE.md §9, Bench2Drive's).
pub fn fixed_factor_product(record: &Record) -> f64 {
    let mut p = 1.0f64;
    for t in FIXED_TERMS {
        for _ in record.infractions.list(t.list) {
            p *= t.factor;
        }
    }
    p
}

/// The outside-lanes factor of `record` (docs/PROTOCOLS.md).
pub fn outside_lanes_factor(record: &Record) -> OutsideLanes {
    let entries = record.infractions.list(OUTSIDE_LIST);
    let Some(first) = entries.first() else {
        return OutsideLanes {
            factor: 1.0,
            source: FOutSource::NoEntry,
            warning: None,
        };
    };
    let check = check_penalty(record, PenaltyFlavour::Bench2Drive);
    if check.agrees {
        let f = record.score_penalty / fixed_factor_product(record);
        // Beyond [0, 1] by more than rounding: an edited record (a factor no evaluator makes).
        let clamped = !(-CLAMP_SLACK..=1.0 + CLAMP_SLACK).contains(&f);
        return OutsideLanes {
            factor: f.clamp(0.0, 1.0),
            source: FOutSource::RecordedPenalty,
            warning: clamped.then(|| {
                format!(
                    "f_out = score_penalty / fixed factors = {f} clamped to [0, 1] (its \
                     outside_route_lanes percentages are impossible: {first:?})"
                )
            }),
        };
    }
    let why = if check.recomputed.is_nan() {
        "its outside-lanes percentage cannot be read".to_string()
    } else {
        format!(
            "its recorded score_penalty {} disagrees with its infraction lists ({})",
            record.score_penalty, check.recomputed
        )
    };
    match percent_of(first, outside_lanes_percent_text) {
        Percent::Possible(q) => {
            let f = 1.0 - q / 100.0;
            let clamp = if (0.0..=1.0).contains(&f) {
                String::new()
            } else {
                format!("; 1 - {q}/100 = {f} clamped to [0, 1]")
            };
            OutsideLanes {
                factor: f.clamp(0.0, 1.0),
                source: FOutSource::Message,
                warning: Some(format!(
                    "f_out from the first outside_route_lanes message ({q}%, rounded), because \
                     {why}{clamp}"
                )),
            }
        }
        Percent::Impossible => OutsideLanes {
            factor: 1.0,
            source: FOutSource::Unknown,
            warning: Some(format!(
                "f_out unknown (taken as 1): an impossible percentage (negative or not finite) \
                 refused in {first:?}, and {why}"
            )),
        },
        Percent::Unreadable => OutsideLanes {
            factor: 1.0,
            source: FOutSource::Unknown,
            warning: Some(format!(
                "f_out unknown (taken as 1): no percentage in {first:?}, and {why}"
            )),
        },
    }
}

/// How far past [0, 1] a recovered `f_out` may lie before its clamp is warned (rounding of the
/// recorded penalty, 6 decimals, divided by a product of factors).
const CLAMP_SLACK: f64 = 1e-4;
