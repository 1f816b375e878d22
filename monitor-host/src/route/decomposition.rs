//! One route's loss from DS to DS_safe, split over its SDS factors (issue 28; `docs/SCORE.md`
//! "Decomposition"). The route's DS_safe is `score_route × score_penalty × Π fᵢ^nᵢ` (docs/SCORE.md §9) with
//! four factors: the work-zone contact (`factors.workzone / factors.layout`, docs/SCORE.md §8), the collision
//! without deceleration, the anomalous and the critical lateral chunk. The loss
//! `score_route × score_penalty − DS_safe` is shared in proportion to `nᵢ · −ln fᵢ`, which does not
//! depend on the order of the product. A factor of 0 (applied at least once) takes the whole loss;
//! several such factors share it equally. The recorded `score_composed` differs from
//! `score_route × score_penalty` by the evaluator's rounding (up to 5e-5 in the Bench2Drive
//! records): that difference is its own step, `rounding`, so that the steps sum exactly.
//!
//! ```
//! use monitor_host::route::decomposition::{split, Applied};
//! use monitor_core::Factors;
//! let n = Applied { workzone: 0, nodecel: 1, anomalous: 0, critical: 0 };
//! let d = split(80.0, 100.0, 0.8, 64.0, n, &Factors::DEFAULT);
//! assert_eq!((d.nodecel, d.workzone, d.rounding), (16.0, 0.0, 0.0));
//! ```

use monitor_core::Factors;
use serde::{Deserialize, Serialize};

/// How often each SDS factor applies on a route (`N_wz`, `N_nodecel`, `N_anom`, `N_crit`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Applied {
    /// Work-zone contacts.
    pub workzone: u32,
    /// Collisions without deceleration.
    pub nodecel: u32,
    /// Anomalous lateral chunks.
    pub anomalous: u32,
    /// Critical lateral chunks.
    pub critical: u32,
}

/// A route's (or, summed over N, a set's) loss from DS to DS_safe, step by step. The steps sum
/// exactly: `ds − rounding − workzone − nodecel − anomalous − critical = ds_safe`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Losses {
    /// The recorded `score_composed` minus `score_route × score_penalty`: the evaluator's
    /// rounding, not a factor.
    pub rounding: f64,
    /// Lost to work-zone contacts (`factors.workzone / factors.layout` per contact).
    pub workzone: f64,
    /// Lost to collisions without deceleration.
    pub nodecel: f64,
    /// Lost to anomalous lateral chunks.
    pub anomalous: f64,
    /// Lost to critical lateral chunks.
    pub critical: f64,
}

impl Losses {
    /// The four factor losses together (`rounding` not included).
    pub fn factors(&self) -> f64 {
        self.workzone + self.nodecel + self.anomalous + self.critical
    }

    /// Every step together: `ds − ds_safe`.
    pub fn total(&self) -> f64 {
        self.rounding + self.factors()
    }

    /// Adds `o` step by step.
    pub fn add(&mut self, o: &Losses) {
        self.rounding += o.rounding;
        self.workzone += o.workzone;
        self.nodecel += o.nodecel;
        self.anomalous += o.anomalous;
        self.critical += o.critical;
    }

    /// Every step divided by `n`.
    pub fn per(&self, n: f64) -> Losses {
        Losses {
            rounding: self.rounding / n,
            workzone: self.workzone / n,
            nodecel: self.nodecel / n,
            anomalous: self.anomalous / n,
            critical: self.critical / n,
        }
    }
}

/// Splits one route's loss: `composed` is the recorded DS, `score_route × score_penalty` the
/// DS before the SDS factors, `ds_safe` the route's DS_safe, `n` the factors' counts.
pub fn split(
    composed: f64,
    score_route: f64,
    score_penalty: f64,
    ds_safe: f64,
    n: Applied,
    f: &Factors,
) -> Losses {
    // The same product as `score::ds_safe` starts with, so a route without factors loses
    // exactly 0.
    let base = score_route * score_penalty;
    let loss = base - ds_safe;
    let factors = [
        (n.workzone, f.workzone / f.layout),
        (n.nodecel, f.nodecel),
        (n.anomalous, f.anomalous),
        (n.critical, f.critical),
    ];
    let mut share = [0.0f64; 4];
    let zeros = factors.iter().filter(|(k, v)| *k > 0 && *v == 0.0).count();
    let weights: [f64; 4] = factors.map(|(k, v)| if k > 0 { -f64::from(k) * v.ln() } else { 0.0 });
    let total: f64 = weights.iter().sum();
    let applied = factors.iter().filter(|(k, _)| *k > 0).count();
    for (i, (k, v)) in factors.iter().enumerate() {
        share[i] = if zeros > 0 {
            // A factor 0 wipes the route out alone; several share the blame equally.
            if *k > 0 && *v == 0.0 {
                loss / zeros as f64
            } else {
                0.0
            }
        } else if applied == 1 {
            // Exactly the whole loss, not loss × w / w.
            if *k > 0 {
                loss
            } else {
                0.0
            }
        } else if total != 0.0 && total.is_finite() {
            loss * weights[i] / total
        } else if applied > 0 {
            // Gains and losses that cancel (a work-zone factor above the layout one): equal
            // shares keep the sum exact.
            if *k > 0 {
                loss / applied as f64
            } else {
                0.0
            }
        } else {
            0.0
        };
    }
    Losses {
        rounding: composed - base,
        workzone: share[0],
        nodecel: share[1],
        anomalous: share[2],
        critical: share[3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const F: Factors = Factors::DEFAULT;

    fn applied(workzone: u32, nodecel: u32, anomalous: u32, critical: u32) -> Applied {
        Applied {
            workzone,
            nodecel,
            anomalous,
            critical,
        }
    }

    fn safe(route: f64, penalty: f64, n: Applied, f: &Factors) -> f64 {
        let r = monitor_core::score::RecordScores {
            score_route: route,
            score_penalty: penalty,
            workzone: n.workzone,
        };
        let mut s = monitor_core::RouteSummary::default();
        s.collisions.nodecel = n.nodecel;
        s.lateral.anomalous = n.anomalous;
        s.lateral.critical = n.critical;
        monitor_core::score::ds_safe(&s, &r, f).ds_safe
    }

    #[test]
    fn single_factor_takes_the_whole_loss() {
        let n = applied(0, 0, 3, 0);
        let s = safe(90.0, 0.7, n, &F);
        let d = split(63.00002, 90.0, 0.7, s, n, &F);
        assert_eq!(d.anomalous, 90.0 * 0.7 - s);
        assert_eq!((d.workzone, d.nodecel, d.critical), (0.0, 0.0, 0.0));
        assert!((d.rounding - 0.00002).abs() < 1e-12);
        assert!((63.00002 - d.total() - s).abs() < 1e-9);
    }

    #[test]
    fn shares_follow_minus_log_of_the_factors() {
        let n = applied(1, 2, 1, 1);
        let s = safe(100.0, 0.65, n, &F);
        let d = split(65.0, 100.0, 0.65, s, n, &F);
        assert!((65.0 - d.total() - s).abs() < 1e-9);
        let w = |k: f64, f: f64| -k * f.ln();
        let ratio = d.nodecel / d.critical;
        assert!((ratio - w(2.0, 0.8) / w(1.0, 0.9)).abs() < 1e-9);
        let ratio = d.workzone / d.anomalous;
        assert!((ratio - w(1.0, 0.5 / 0.65) / w(1.0, 0.95)).abs() < 1e-9);
    }

    #[test]
    fn a_zero_factor_takes_the_whole_loss() {
        let f = Factors { critical: 0.0, ..F };
        let n = applied(0, 1, 2, 1);
        let s = safe(80.0, 1.0, n, &f);
        assert_eq!(s, 0.0);
        let d = split(80.0, 80.0, 1.0, s, n, &f);
        assert_eq!((d.critical, d.nodecel, d.anomalous), (80.0, 0.0, 0.0));
        // Two zero factors share it equally.
        let f = Factors { nodecel: 0.0, ..f };
        let d = split(80.0, 80.0, 1.0, 0.0, n, &f);
        assert_eq!((d.critical, d.nodecel, d.anomalous), (40.0, 40.0, 0.0));
        // A zero factor that does not apply takes nothing.
        let n = applied(0, 0, 1, 0);
        let s = safe(80.0, 1.0, n, &f);
        let d = split(80.0, 80.0, 1.0, s, n, &f);
        assert_eq!((d.critical, d.nodecel, d.anomalous), (0.0, 0.0, 80.0 - s));
    }

    #[test]
    fn no_factor_no_loss() {
        let n = applied(0, 0, 0, 0);
        let s = safe(73.1, 0.6, n, &F);
        let d = split(43.86, 73.1, 0.6, s, n, &F);
        assert_eq!(d.factors(), 0.0);
        assert_eq!(43.86 - d.total(), s);
    }

    #[test]
    fn cancelling_gains_keep_the_sum() {
        // factors.workzone above factors.layout is a gain; it can cancel a loss.
        let f = Factors {
            workzone: 0.9,
            layout: 0.5,
            ..F
        };
        let n = applied(1, 1, 0, 0);
        let s = safe(100.0, 0.5, n, &f);
        let d = split(50.0, 100.0, 0.5, s, n, &f);
        assert!((50.0 - d.total() - s).abs() < 1e-9);
    }
}
