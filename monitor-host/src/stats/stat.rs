//! The statistic over a model's seeds: mean and sample standard deviation (docs/SCORE.md
//! §10.3), shared by the model rows ([`crate::stats::models`]) and the seed spread
//! ([`crate::stats::seeds`]).

use serde::Serialize;

/// A mean and sample standard deviation over seeds (std null for one seed; both null when some
/// seed has no value).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Stat {
    /// Mean.
    pub mean: Option<f64>,
    /// Sample standard deviation (n - 1).
    pub std: Option<f64>,
}

impl Stat {
    /// The statistic of `values`, summed in order.
    pub fn of(values: &[Option<f64>]) -> Stat {
        let Some(xs) = values.iter().copied().collect::<Option<Vec<f64>>>() else {
            return Stat::default();
        };
        let n = xs.len();
        if n == 0 {
            return Stat::default();
        }
        let mean = xs.iter().fold(0.0, |a, x| a + x) / n as f64;
        let std = (n > 1).then(|| {
            let ss = xs.iter().fold(0.0, |a, x| a + (x - mean) * (x - mean));
            (ss / (n - 1) as f64).sqrt()
        });
        Stat {
            mean: Some(mean),
            std,
        }
    }
}
