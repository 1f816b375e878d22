//! The ranking of many models (docs/SCORE.md §10.3, `--rank`): B resamples of the n compared
//! routes (the route order and draw rule of §11, ONE generator seeded with `bootstrap_seed`, n
//! draws per resample); per resample each model's mean `ds` over the drawn positions and its rank
//! `1 + #(models with a strictly greater mean)`. Per model: `rank` on the full route set, the 95 %
//! interval of its B ranks, and `p_best` (share of resamples where it ranks first; a first place
//! shared by k models counts 1/k to each, so the `p_best` of all models add up to 1). Listed by
//! rank, ties by name; with no compared route the ranks are null.
//!
//! ```
//! use monitor_host::stats::rank::ranking;
//! // Three models over four routes (their ds, route by route).
//! let ds = vec![vec![50.0, 60.0, 70.0, 80.0], vec![90.0, 95.0, 100.0, 85.0], vec![50.0, 60.0, 70.0, 80.0]];
//! let r = ranking(&["a", "b", "c"], &ds, 1000, 0);
//! assert_eq!(r[0].model, "b");
//! assert_eq!((r[0].rank, r[0].rank_ci95, r[0].p_best), (Some(1), Some([1, 1]), Some(1.0)));
//! // a and c tie everywhere: both rank 2 (no model has a strictly greater mean but b), by name.
//! assert_eq!((r[1].model.as_str(), r[1].rank, r[2].model.as_str(), r[2].rank), ("a", Some(2), "c", Some(2)));
//! ```

use serde::Serialize;

use crate::stats::bootstrap::interval_indices;
use crate::stats::splitmix::SplitMix64;

/// One model's place (`ranking[]` of the report).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RankRow {
    /// The model.
    pub model: String,
    /// Its mean `ds` over the compared routes (null when no route was compared).
    pub mean_ds: Option<f64>,
    /// Its rank on the full route set: 1 + the models with a strictly greater mean (null when
    /// no route was compared: there is nothing to rank on).
    pub rank: Option<usize>,
    /// `[r[floor(0.025 B)], r[ceil(0.975 B) - 1]]` of its B resampled ranks, sorted ascending
    /// (null when no route was compared).
    pub rank_ci95: Option<[usize; 2]>,
    /// Share of resamples where it ranks first, a first place shared by k models counting 1/k
    /// (null when no route was compared).
    pub p_best: Option<f64>,
}

/// 1 + the number of `means` strictly greater than `means[i]`.
fn rank_of(means: &[f64], i: usize) -> usize {
    1 + means.iter().filter(|m| **m > means[i]).count()
}

/// The ranking of `names` from their per-route `ds` (`ds[m][r]`, every model over the same n
/// routes in the baseline's route order), with `b` resamples from one SplitMix64 seeded with
/// `seed`. With n = 0 every rank and figure is null (listed by name); `b` = 0 leaves the
/// intervals null.
pub fn ranking(names: &[&str], ds: &[Vec<f64>], b: usize, seed: u64) -> Vec<RankRow> {
    let m = names.len().min(ds.len());
    let n = ds.iter().map(Vec::len).min().unwrap_or(0);
    let full: Vec<f64> = ds[..m]
        .iter()
        .map(|x| x[..n].iter().fold(0.0, |a, v| a + v) / n as f64)
        .collect();
    let mut rows: Vec<RankRow> = (0..m)
        .map(|i| RankRow {
            model: names[i].to_string(),
            mean_ds: (n > 0).then_some(full[i]),
            rank: (n > 0).then(|| rank_of(&full, i)),
            rank_ci95: None,
            p_best: None,
        })
        .collect();
    if n > 0 && b > 0 {
        let mut rng = SplitMix64::new(seed);
        let mut idx = vec![0usize; n];
        let mut means = vec![0.0f64; m];
        let mut ranks: Vec<Vec<usize>> = vec![Vec::with_capacity(b); m];
        // First places, a place shared by k models counting 1/k to each (summed in resample
        // order): ties split, so the shares add up to 1 (three identical models: 1/3 each).
        let mut best = vec![0.0f64; m];
        for _ in 0..b {
            for slot in idx.iter_mut() {
                *slot = rng.index(n);
            }
            for (mean, x) in means.iter_mut().zip(ds) {
                // Summed in draw order, as §11's resample statistic.
                *mean = idx.iter().fold(0.0, |a, &i| a + x[i]) / n as f64;
            }
            for (i, r) in ranks.iter_mut().enumerate() {
                r.push(rank_of(&means, i));
            }
            let firsts = ranks.iter().filter(|r| r.last() == Some(&1)).count();
            for (share, r) in best.iter_mut().zip(&ranks) {
                if r.last() == Some(&1) {
                    *share += 1.0 / firsts as f64;
                }
            }
        }
        let (lo, hi) = interval_indices(b);
        for ((row, mut r), share) in rows.iter_mut().zip(ranks).zip(best) {
            r.sort_unstable();
            row.rank_ci95 = Some([r[lo], r[hi]]);
            row.p_best = Some(share / b as f64);
        }
    }
    rows.sort_by(|a, b| a.rank.cmp(&b.rank).then_with(|| a.model.cmp(&b.model)));
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn r4_12_no_route_gives_null_ranks() {
        let r = ranking(&["b", "a"], &[vec![], vec![]], 1000, 0);
        // Issue 47 item 12: nothing to rank on, so no rank (every model was ranked 1).
        assert_eq!(
            (r[0].model.as_str(), r[0].rank, r[0].rank_ci95),
            ("a", None, None)
        );
        assert!(r
            .iter()
            .all(|x| x.rank.is_none() && x.mean_ds.is_none() && x.p_best.is_none()));
    }

    #[test]
    fn close_models_share_the_first_place_across_resamples() {
        let ds = vec![vec![100.0, 0.0, 100.0, 0.0], vec![0.0, 100.0, 0.0, 100.0]];
        let r = ranking(&["x", "y"], &ds, 2000, 0);
        // Equal means on the full set: both rank 1; resamples split the first place.
        assert_eq!((r[0].rank, r[1].rank), (Some(1), Some(1)));
        assert_eq!(r[0].rank_ci95, Some([1, 2]));
        let p: f64 = r.iter().map(|x| x.p_best.unwrap_or(0.0)).sum();
        assert!((p - 1.0).abs() < 1e-12, "ties split: {p}");
    }

    /// Issue 47 item 12: three identical models summed to 3.0; a shared first place is split.
    #[test]
    fn r4_12_identical_models_split_the_first_place() {
        let x = vec![10.0, 90.0, 40.0, 70.0];
        let r = ranking(&["a", "b", "c"], &[x.clone(), x.clone(), x], 1000, 3);
        for row in &r {
            assert_eq!((row.rank, row.rank_ci95), (Some(1), Some([1, 1])));
            assert!((row.p_best.unwrap() - 1.0 / 3.0).abs() < 1e-12, "{row:?}");
        }
        let p: f64 = r.iter().map(|x| x.p_best.unwrap()).sum();
        assert!((p - 1.0).abs() < 1e-12, "{p}");
    }
}
