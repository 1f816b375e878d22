//! Bench2Drive's efficiency of one route (docs/SCORE.md §10.1): how fast it drove compared
//! with the surrounding traffic, from its `min_speed_infractions`.
//!
//! ```
//! use monitor_host::route::efficiency::route_efficiency;
//! let e = route_efficiency(&[
//!     "Average speed is 80% of the surrounding traffic's one".into(),
//!     "Average speed is 1098.69% of the surrounding traffic's one".into(), // an outlier
//!     "Average speed is 100% of the surrounding traffic's one".into(),
//! ]);
//! assert_eq!(e, Some(90.0));
//! assert_eq!(route_efficiency(&[]), None);
//! ```

use crate::route::penalty::min_speed_percent;

/// Percentages above this are outliers, left out of a route's efficiency (docs/SCORE.md §10.1).
pub const EFFICIENCY_MAX: f64 = 1000.0;

/// A route's efficiency: the mean of the `Average speed is X% ...` percentages of its
/// `min_speed_infractions` with `X <= 1000`, in list order; `None` when it has none.
pub fn route_efficiency(min_speed_infractions: &[String]) -> Option<f64> {
    let values: Vec<f64> = min_speed_infractions
        .iter()
        .filter_map(|s| min_speed_percent(s))
        .filter(|x| *x <= EFFICIENCY_MAX)
        .collect();
    let n = values.len();
    (n > 0).then(|| values.iter().fold(0.0, |a, x| a + x) / n as f64)
}
