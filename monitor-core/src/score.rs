//! DS_safe (docs/SCORE.md §9): penalty factors applied to the evaluator's recorded scores.
//!
//! Scores are f64 because they combine with the evaluator's f64 `score_route` and
//! `score_penalty`; the per-frame signals stay f32.

use crate::config::Factors;
use crate::summary::RouteSummary;

/// `base^n` by square-and-multiply, in a fixed order, so that every caller gets the same bits.
///
/// ```
/// assert_eq!(monitor_core::score::powu(0.5, 3), 0.125);
/// assert_eq!(monitor_core::score::powu(0.8, 0), 1.0);
/// ```
pub fn powu(base: f64, n: u32) -> f64 {
    let mut result = 1.0f64;
    let mut b = base;
    let mut e = n;
    while e > 0 {
        if e & 1 == 1 {
            result *= b;
        }
        e >>= 1;
        if e > 0 {
            b *= b;
        }
    }
    result
}

/// What the evaluator recorded for the route, plus its work-zone count (docs/SCORE.md §8).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RecordScores {
    /// `scores.score_route` (0..100).
    pub score_route: f64,
    /// `scores.score_penalty` (authoritative).
    pub score_penalty: f64,
    /// `N_wz`: work-zone contacts among `collisions_layout`, aligned or not.
    pub workzone: u32,
}

/// The route's safe scores.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SafeScore {
    /// `p_safe = score_penalty * (workzone / layout)^N_wz`.
    pub p_safe: f64,
    /// `DS_safe = score_route * p_safe * nodecel^N_nodecel * anomalous^N_anom * critical^N_crit`.
    pub ds_safe: f64,
}

/// DS_safe of one route, multiplied left to right as the spec writes it.
///
/// ```
/// use monitor_core::{score, Factors, RouteSummary};
/// let mut s = RouteSummary::default();
/// s.collisions.nodecel = 1;
/// let r = score::RecordScores { score_route: 100.0, score_penalty: 0.65, workzone: 1 };
/// let safe = score::ds_safe(&s, &r, &Factors::DEFAULT);
/// assert!((safe.p_safe - 0.5).abs() < 1e-12);
/// assert!((safe.ds_safe - 40.0).abs() < 1e-9);
/// ```
pub fn ds_safe(summary: &RouteSummary, record: &RecordScores, f: &Factors) -> SafeScore {
    let p_safe = record.score_penalty * powu(f.workzone / f.layout, record.workzone);
    let ds_safe = record.score_route
        * p_safe
        * powu(f.nodecel, summary.collisions.nodecel)
        * powu(f.anomalous, summary.lateral.anomalous)
        * powu(f.critical, summary.lateral.critical);
    SafeScore { p_safe, ds_safe }
}
