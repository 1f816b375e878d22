//! Flips (docs/SCORE.md §10.3): the routes a model newly fails or newly passes against the
//! baseline, and the routes whose DS moved most.
//!
//! ```
//! use monitor_host::stats::flips::largest;
//! let keys = ["a", "b", "c"].map(String::from);
//! let top = largest(&keys, &[Some(1.0), Some(-3.0), Some(3.0)], &[Some(0.0); 3], 2);
//! assert_eq!(top.iter().map(|m| m.key.as_str()).collect::<Vec<_>>(), ["b", "c"]); // tie: by key
//! ```

use serde::Serialize;

/// One route's change on `ds`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Move {
    /// The route key.
    pub key: String,
    /// The baseline's value.
    pub baseline: f64,
    /// The model's value.
    pub model: f64,
    /// model − baseline.
    pub delta: f64,
}

/// One model's flips against the baseline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Flips {
    /// The model.
    pub model: String,
    /// Keys whose success fraction went from 1 to 0, in the baseline's route order.
    pub regressed: Vec<String>,
    /// Keys whose success fraction went from 0 to 1, in the baseline's route order.
    pub fixed: Vec<String>,
    /// The keys with the largest |d| on `ds` (top 10, ties by key byte-wise).
    pub largest: Vec<Move>,
}

/// Keys (in order) whose value went from `from` to `to`.
pub fn flipped(
    keys: &[String],
    model: &[Option<f64>],
    base: &[Option<f64>],
    from: f64,
    to: f64,
) -> Vec<String> {
    keys.iter()
        .zip(model.iter().zip(base))
        .filter(|(_, (m, b))| **b == Some(from) && **m == Some(to))
        .map(|(k, _)| k.clone())
        .collect()
}

/// The `top` keys with the largest |model − base| (both defined), ties by key.
pub fn largest(
    keys: &[String],
    model: &[Option<f64>],
    base: &[Option<f64>],
    top: usize,
) -> Vec<Move> {
    let mut moves: Vec<Move> = keys
        .iter()
        .zip(model.iter().zip(base))
        .filter_map(|(k, (m, b))| {
            let (m, b) = ((*m)?, (*b)?);
            Some(Move {
                key: k.clone(),
                baseline: b,
                model: m,
                delta: m - b,
            })
        })
        .collect();
    moves.sort_by(|x, y| {
        y.delta
            .abs()
            .total_cmp(&x.delta.abs())
            .then_with(|| x.key.as_bytes().cmp(y.key.as_bytes()))
    });
    moves.truncate(top);
    moves
}
