//! The paired bootstrap of one model and metric (docs/SCORE.md §10.3): the mean of the
//! per-route differences, B resamples of the n routes with replacement, the 95 % percentile
//! interval, `p_better` and the verdict (`no data` when no route could be compared). Also the
//! bounds on B ([`SAMPLES`], [`DRAW_BUDGET`]) that keep one comparison's time and memory in check.
//!
//! ```
//! use monitor_host::stats::bootstrap::{paired, Verdict};
//! use monitor_host::stats::splitmix::SplitMix64;
//! let mut rng = SplitMix64::new(0);
//! let p = paired(&[2.0, 3.0, 4.0, 3.0], 1000, &mut rng);
//! assert_eq!(p.delta, Some(3.0));
//! assert_eq!(p.verdict, Some(Verdict::Better)); // every resample's mean is at least 2
//! assert_eq!(p.p_better, Some(1.0));
//! ```

use serde::Serialize;

use crate::stats::splitmix::SplitMix64;

/// The verdict on one metric: is the model better than the baseline, beyond the spread over
/// routes?
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Verdict {
    /// The interval's lower end is above 0.
    #[serde(rename = "better")]
    Better,
    /// The interval's upper end is below 0.
    #[serde(rename = "worse")]
    Worse,
    /// The interval holds 0.
    #[serde(rename = "within noise")]
    WithinNoise,
    /// No route could be compared (n = 0: comfort undefined on every route, or no shared route
    /// key under `--common-routes`): nothing is known, and a gate on it fails (v1.4).
    #[serde(rename = "no data")]
    NoData,
}

impl Verdict {
    /// As the report writes it.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Better => "better",
            Verdict::Worse => "worse",
            Verdict::WithinNoise => "within noise",
            Verdict::NoData => "no data",
        }
    }
}

/// What the bootstrap says about one set of paired differences. With n = 0 every figure is
/// `None`, the verdict is [`Verdict::NoData`], and no number is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Paired {
    /// Routes compared.
    pub n: usize,
    /// Mean difference (model − baseline), summed in the baseline's route order.
    pub delta: Option<f64>,
    /// 95 % percentile interval of the resampled means.
    pub ci95: Option<[f64; 2]>,
    /// Share of resamples whose mean is > 0.
    pub p_better: Option<f64>,
    /// Better, worse, within noise, or no data (n = 0); `None` only when B = 0.
    pub verdict: Option<Verdict>,
}

/// The resamples B a comparison accepts (`--bootstrap-samples`, `bootstrap_samples`): below
/// 1,000 the interval's ends rest on a handful of resamples (B = 1 gives a one-point "interval");
/// above 1,000,000 the bounds no longer move while time and memory (8 bytes a resample) grow.
pub const SAMPLES: std::ops::RangeInclusive<usize> = 1_000..=1_000_000;

/// The most draws one model and metric may take, n × B (about a second of one core): B =
/// 1,000,000 over Bench2Drive's 220 routes, the default 10,000 over up to 25,000 routes.
pub const DRAW_BUDGET: u64 = 250_000_000;

/// The indices of the 95 % interval in the B sorted statistics: `floor(0.025 B)` and
/// `ceil(0.975 B) - 1`, in integers (0.025 = 1/40), so no rounding of a float decides them.
pub fn interval_indices(b: usize) -> (usize, usize) {
    let lo = b / 40;
    let hi = (39 * b).div_ceil(40).saturating_sub(1);
    (lo, hi)
}

/// The bootstrap of the differences `d` (in the baseline's route order) with `b` resamples,
/// drawing from `rng`: resample by resample, n indices each. A comparison gives each model and
/// metric a generator of its own, seeded with `bootstrap_seed` (v1.4). `b` must be at least 1
/// (the verdict is `None` when it is 0); n = 0 draws nothing and says [`Verdict::NoData`].
pub fn paired(d: &[f64], b: usize, rng: &mut SplitMix64) -> Paired {
    let n = d.len();
    if n == 0 || b == 0 {
        return Paired {
            n,
            delta: None,
            ci95: None,
            p_better: None,
            verdict: (n == 0).then_some(Verdict::NoData),
        };
    }
    let delta = d.iter().fold(0.0, |a, x| a + x) / n as f64;
    let mut stats = Vec::with_capacity(b);
    for _ in 0..b {
        let mut sum = 0.0;
        for _ in 0..n {
            sum += d[rng.index(n)];
        }
        stats.push(sum / n as f64);
    }
    let better = stats.iter().filter(|s| **s > 0.0).count();
    stats.sort_unstable_by(f64::total_cmp);
    let (lo, hi) = interval_indices(b);
    let ci = [stats[lo], stats[hi]];
    let verdict = if ci[0] > 0.0 {
        Verdict::Better
    } else if ci[1] < 0.0 {
        Verdict::Worse
    } else {
        Verdict::WithinNoise
    };
    Paired {
        n,
        delta: Some(delta),
        ci95: Some(ci),
        p_better: Some(better as f64 / b as f64),
        verdict: Some(verdict),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_indices_as_written() {
        assert_eq!(interval_indices(10_000), (250, 9_749));
        assert_eq!(interval_indices(1_000), (25, 974));
        assert_eq!(interval_indices(1), (0, 0));
        assert_eq!(interval_indices(39), (0, 38)); // ceil(38.025) - 1
        assert_eq!(interval_indices(40), (1, 38));
        for b in 1..5_000usize {
            let (lo, hi) = interval_indices(b);
            assert_eq!(lo, (0.025 * b as f64).floor() as usize, "B = {b}");
            // 0.975 B is exact enough in f64 below 2^40 for ceil to agree.
            assert_eq!(hi, (0.975 * b as f64 - 1e-9).ceil() as usize - 1, "B = {b}");
            assert!(lo <= hi && hi < b);
        }
    }

    /// Resamples of a by-hand generator: the statistics are the means of the drawn indices in
    /// draw order, resample by resample.
    #[test]
    fn draw_order_resample_by_resample() {
        let d = [1.0, -2.0, 4.0];
        let b = 7;
        let mut rng = SplitMix64::new(42);
        let got = paired(&d, b, &mut rng);
        let mut by_hand = SplitMix64::new(42);
        let mut stats: Vec<f64> = (0..b)
            .map(|_| {
                let i0 = by_hand.index(3);
                let i1 = by_hand.index(3);
                let i2 = by_hand.index(3);
                ((d[i0] + d[i1]) + d[i2]) / 3.0
            })
            .collect();
        // The generator has moved by exactly n * B draws.
        assert_eq!(rng, by_hand);
        let p = stats.iter().filter(|s| **s > 0.0).count() as f64 / b as f64;
        stats.sort_by(f64::total_cmp);
        assert_eq!(got.ci95, Some([stats[0], stats[6]]));
        assert_eq!(got.p_better, Some(p));
        assert_eq!(got.delta, Some(1.0));
    }

    #[test]
    fn known_deltas_and_verdicts() {
        let mut rng = SplitMix64::new(0);
        // Every difference -5: every resample -5, worse.
        let p = paired(&[-5.0; 30], 2_000, &mut rng);
        assert_eq!(p.delta, Some(-5.0));
        assert_eq!(p.ci95, Some([-5.0, -5.0]));
        assert_eq!(p.p_better, Some(0.0));
        assert_eq!(p.verdict, Some(Verdict::Worse));
        // Half +1, half -1: delta 0, the interval holds 0.
        let d: Vec<f64> = (0..40)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let p = paired(&d, 2_000, &mut rng);
        assert_eq!(p.delta, Some(0.0));
        let [lo, hi] = p.ci95.unwrap();
        assert!(lo < 0.0 && hi > 0.0, "{lo} {hi}");
        assert_eq!(p.verdict, Some(Verdict::WithinNoise));
        let pb = p.p_better.unwrap();
        assert!(pb > 0.3 && pb < 0.6, "{pb}");
        // One large gain among zeros: delta 1, but resamples without that route have mean 0.
        let mut d = vec![0.0; 19];
        d.push(20.0);
        let p = paired(&d, 2_000, &mut rng);
        assert_eq!(p.delta, Some(1.0));
        assert_eq!(p.ci95.unwrap()[0], 0.0);
        assert_eq!(p.verdict, Some(Verdict::WithinNoise));
    }

    #[test]
    fn one_route_and_no_route() {
        let mut rng = SplitMix64::new(0);
        let p = paired(&[3.5], 100, &mut rng);
        assert_eq!((p.n, p.delta, p.ci95), (1, Some(3.5), Some([3.5, 3.5])));
        assert_eq!(p.verdict, Some(Verdict::Better));
        let before = rng;
        let p = paired(&[], 100, &mut rng);
        assert_eq!(p.n, 0);
        assert_eq!(
            (p.delta, p.ci95, p.p_better, p.verdict),
            (None, None, None, Some(Verdict::NoData))
        );
        assert_eq!(rng, before, "n = 0 draws nothing");
    }

    #[test]
    fn ties_are_not_better() {
        let mut rng = SplitMix64::new(7);
        let p = paired(&[0.0; 12], 500, &mut rng);
        assert_eq!(p.delta, Some(0.0));
        assert_eq!(p.ci95, Some([0.0, 0.0]));
        assert_eq!(p.p_better, Some(0.0), "a mean of exactly 0 is not > 0");
        assert_eq!(p.verdict, Some(Verdict::WithinNoise));
    }
}
