//! From DS to SDS in additive steps that sum exactly (issue 28; `docs/SCORE.md`
//! "Decomposition"): `ds`, minus the evaluator's rounding and the loss to each SDS factor (each
//! the sum of the routes' [`crate::route::decomposition`] over N), is `ds_safe`; minus the loss
//! to comfort (`ds_safe × (1 − mean_comfort)`) is `sds`.
//!
//! ```
//! use monitor_host::aggregate::decomposition::Decomposition;
//! use monitor_host::route::decomposition::Losses;
//! let l = Losses { nodecel: 10.0, ..Losses::default() };
//! let d = Decomposition::of(70.0, l, 60.0, Some(0.5));
//! assert_eq!((d.comfort, d.sds), (Some(30.0), Some(30.0)));
//! ```

use serde::{Deserialize, Serialize};

use crate::route::decomposition::Losses;

/// The steps from DS to SDS of a set of routes (the summary, a group, `combined`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Decomposition {
    /// DS: Σ score_composed / N.
    pub ds: f64,
    /// Σ of the routes' losses / N, step by step; `ds − Σ losses = ds_safe`.
    #[serde(flatten)]
    pub losses: Losses,
    /// `mean_ds_safe`.
    pub ds_safe: f64,
    /// Lost to comfort: `ds_safe × (1 − mean_comfort)`; null when comfort is undefined.
    pub comfort: Option<f64>,
    /// SDS = `ds_safe − comfort`; null when comfort is undefined.
    pub sds: Option<f64>,
}

impl Decomposition {
    /// The steps of a set with DS `ds`, the routes' summed losses over N `losses`, its
    /// `mean_ds_safe` and `mean_comfort`.
    pub fn of(ds: f64, losses: Losses, ds_safe: f64, mean_comfort: Option<f64>) -> Decomposition {
        Decomposition {
            ds,
            losses,
            ds_safe,
            comfort: mean_comfort.map(|c| ds_safe * (1.0 - c)),
            sds: mean_comfort.map(|c| ds_safe * c),
        }
    }
}
