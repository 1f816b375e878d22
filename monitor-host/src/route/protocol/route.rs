//! One route under every asked protocol (docs/PROTOCOLS.md): its penalty, its score
//! `RC × penalty` and its success, from the record alone.
//!
//! ```
//! use monitor_host::input::record::Record;
//! use monitor_host::route::protocol::route::score_record;
//! use monitor_host::route::protocol::Protocol;
//! use monitor_host::settings::MinSpeedGridSetting;
//! let r = Record::from_value(&serde_json::json!({
//!     "route_id": "RouteScenario_1_rep0", "status": "Completed",
//!     "infractions": {"collisions_pedestrian": ["a", "b"]},
//!     "scores": {"score_route": 100, "score_penalty": 0.25, "score_composed": 25.0}}))?;
//! let (s, warnings) = score_record(&r, &[Protocol::Lb21], MinSpeedGridSetting::Auto);
//! let lb21 = s.get(Protocol::Lb21).unwrap();
//! assert!((lb21.score - 100.0 / 3.0).abs() < 1e-12 && !lb21.success && warnings.is_empty());
//! # Ok::<(), monitor_host::input::record::InvalidRecord>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::input::message::{outside_lanes_percent_text, percent_of, Percent};
use crate::input::record::{Record, MIN_SPEED_LIST};
use crate::input::warning::Warning;
use crate::route::protocol::min_speed::{min_speed_events, MinSpeedEvents};
use crate::route::protocol::outside_lanes::{outside_lanes_factor, OutsideLanes, OUTSIDE_LIST};
use crate::route::protocol::terms::{
    lb20_min_speed_factor, lb21_min_speed_cost, FIXED_TERMS, LEAD_SCALE,
};
use crate::route::protocol::Protocol;
use crate::settings::MinSpeedGridSetting;

/// A route under one protocol.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RouteScore {
    /// The protocol's penalty (0..1); null for a route without a valid record.
    pub penalty: Option<f64>,
    /// `RC × penalty` (0..100); 0 without a valid record.
    pub score: f64,
    /// A success under the protocol's rule.
    pub success: bool,
    /// The min-speed events the protocol charged (docs/PROTOCOLS.md v1.4): Leaderboard checkpoints below
    /// 100 % under `lb2.0`, `lb2.1` and `lead-nds`; 0 under `b2d` and `f2d`, which charge none.
    pub min_speed_events: usize,
}

/// A route under every asked protocol, in [`Protocol::ALL`] order: the report's per-route
/// `protocols` object `{id: {penalty, score, success}}`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RouteProtocols(pub Vec<(Protocol, RouteScore)>);

impl RouteProtocols {
    /// The route under `p`, when it was asked.
    pub fn get(&self, p: Protocol) -> Option<&RouteScore> {
        self.0.iter().find(|(q, _)| *q == p).map(|(_, s)| s)
    }

    /// A route without a valid record (missing or invalid): penalty null, score 0, failed.
    pub fn without_record(protocols: &[Protocol]) -> Self {
        RouteProtocols(
            protocols
                .iter()
                .map(|p| {
                    (
                        *p,
                        RouteScore {
                            penalty: None,
                            score: 0.0,
                            success: false,
                            min_speed_events: 0,
                        },
                    )
                })
                .collect(),
        )
    }
}

impl Serialize for RouteProtocols {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|(p, r)| (p.id(), r)))
    }
}

impl<'de> Deserialize<'de> for RouteProtocols {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::named::pairs(d)?
            .into_iter()
            .map(|(id, s)| Ok((Protocol::of_key(&id)?, s)))
            .collect::<Result<_, _>>()
            .map(RouteProtocols)
    }
}

/// Fail2Drive's success: every infraction list empty except `min_speed_infractions` and
/// `outside_route_lanes` (unknown lists included); the status is not consulted.
pub fn f2d_success(record: &Record) -> bool {
    record
        .infractions
        .all()
        .all(|(name, list)| name == MIN_SPEED_LIST || name == OUTSIDE_LIST || list.is_empty())
}

/// LEAD's driven kilometres: `RC/100 × route_length / 1000` (0 without a route length).
pub fn driven_km(record: &Record) -> f64 {
    record.score_route / 100.0 * record.meta.route_length.unwrap_or(0.0) / 1000.0
}

/// Leaderboard 2.0's penalty: `f_out × prod v_e × prod (1 - 0.3 (1 - P/100))`.
pub fn lb20_penalty(record: &Record, f_out: f64, min_speed: &MinSpeedEvents) -> f64 {
    let mut p = f_out;
    for t in FIXED_TERMS {
        for _ in record.infractions.list(t.list) {
            p *= t.factor;
        }
    }
    for &pct in &min_speed.percents {
        p *= lb20_min_speed_factor(pct);
    }
    p
}

/// Leaderboard 2.1's penalty: `f_out / (1 + sum c_e + sum 0.4 (1 - P/100))`.
pub fn lb21_penalty(record: &Record, f_out: f64, min_speed: &MinSpeedEvents) -> f64 {
    let mut cost = 0.0f64;
    for t in FIXED_TERMS {
        cost += t.cost * record.infractions.list(t.list).len() as f64;
    }
    for &pct in &min_speed.percents {
        cost += lb21_min_speed_cost(pct);
    }
    f_out / (1.0 + cost)
}

/// LEAD's normalised penalty: `prod_k (0.2 v_k)^(n_k / km)` (1 when `km = 0`), the
/// Leaderboard 2.0 min-speed factors, and `1 - Q/100` per outside-lanes entry, `Q` read from
/// its message, the factor clamped to [0, 1]. Entries without a percentage or with an
/// impossible one (negative, not finite) are skipped; what was skipped or clamped is returned
/// as warnings.
pub fn lead_penalty(record: &Record, min_speed: &MinSpeedEvents) -> (f64, Vec<String>) {
    let km = driven_km(record);
    let mut p = 1.0f64;
    if km > 0.0 {
        for t in FIXED_TERMS {
            let n = record.infractions.list(t.list).len();
            if n > 0 {
                p *= (LEAD_SCALE * t.factor).powf(n as f64 / km);
            }
        }
    }
    for &pct in &min_speed.percents {
        p *= lb20_min_speed_factor(pct);
    }
    let mut warnings = Vec::new();
    for s in record.infractions.list(OUTSIDE_LIST) {
        match percent_of(s, outside_lanes_percent_text) {
            Percent::Possible(q) => {
                let f = 1.0 - q / 100.0;
                if !(0.0..=1.0).contains(&f) {
                    warnings.push(format!(
                        "lead-nds: outside_route_lanes factor 1 - {q}/100 = {f} clamped to [0, 1]: \
                         {s:?}"
                    ));
                }
                p *= f.clamp(0.0, 1.0);
            }
            Percent::Impossible => warnings.push(format!(
                "lead-nds: outside_route_lanes entry with an impossible percentage (negative or \
                 not finite), refused: {s:?}"
            )),
            Percent::Unreadable => warnings.push(format!(
                "lead-nds: outside_route_lanes entry without a percentage, skipped: {s:?}"
            )),
        }
    }
    (p, warnings)
}

/// The record under each of `protocols` (in the order given), its min-speed entries read on the
/// grid `grid` gives it, and the warnings met: min-speed entries without a number or with an
/// impossible one, `f_out` not recovered from the recorded penalty, LEAD's outside-lanes entries
/// without a percentage or with an impossible one, factors clamped, LEAD without a route length.
pub fn score_record(
    record: &Record,
    protocols: &[Protocol],
    grid: MinSpeedGridSetting,
) -> (RouteProtocols, Vec<Warning>) {
    let mut warnings = Vec::new();
    let rc = record.score_route;
    let needs_events = protocols
        .iter()
        .any(|p| matches!(p, Protocol::Lb20 | Protocol::Lb21 | Protocol::LeadNds));
    let min_speed = if needs_events {
        let m = min_speed_events(record.infractions.list(MIN_SPEED_LIST), grid);
        for s in &m.unreadable {
            warnings.push(Warning::Protocol(format!(
                "min_speed_infractions entry without a percentage, skipped: {s:?}"
            )));
        }
        for s in &m.impossible {
            warnings.push(Warning::Protocol(format!(
                "min_speed_infractions entry with an impossible percentage (negative or not \
                 finite), refused: {s:?}"
            )));
        }
        m
    } else {
        MinSpeedEvents::default()
    };
    let needs_f_out = protocols
        .iter()
        .any(|p| matches!(p, Protocol::Lb20 | Protocol::Lb21));
    let f_out = if needs_f_out {
        let f = outside_lanes_factor(record);
        warnings.extend(f.warning.clone().map(Warning::Protocol));
        f
    } else {
        OutsideLanes {
            factor: 1.0,
            source: crate::route::protocol::outside_lanes::FOutSource::NoEntry,
            warning: None,
        }
    };
    let mut out = Vec::with_capacity(protocols.len());
    for &p in protocols {
        let (penalty, success) = match p {
            Protocol::B2d => (record.score_penalty, record.is_success()),
            Protocol::Lb20 => (
                lb20_penalty(record, f_out.factor, &min_speed),
                record.is_success(),
            ),
            Protocol::Lb21 => (
                lb21_penalty(record, f_out.factor, &min_speed),
                record.is_success(),
            ),
            Protocol::LeadNds => {
                let (penalty, skipped) = lead_penalty(record, &min_speed);
                warnings.extend(skipped.into_iter().map(Warning::Protocol));
                if record.meta.route_length.is_none()
                    && record
                        .infractions
                        .all()
                        .any(|(n, l)| !l.is_empty() && FIXED_TERMS.iter().any(|t| t.list == n))
                {
                    warnings.push(Warning::Protocol(
                        "lead-nds: no meta.route_length: driven km taken as 0, collision and \
                         rule terms left out"
                            .into(),
                    ));
                }
                (penalty, record.is_success())
            }
            Protocol::F2d => (record.score_penalty, f2d_success(record)),
        };
        let score = if p == Protocol::B2d || p == Protocol::F2d {
            record.score_composed
        } else {
            rc * penalty
        };
        let charged = match p {
            Protocol::Lb20 | Protocol::Lb21 | Protocol::LeadNds => min_speed.percents.len(),
            Protocol::B2d | Protocol::F2d => 0,
        };
        out.push((
            p,
            RouteScore {
                penalty: Some(penalty),
                score,
                success,
                min_speed_events: charged,
            },
        ));
    }
    (RouteProtocols(out), warnings)
}
