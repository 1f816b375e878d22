//! Distance, stationary time and moving comfort over a set of routes (docs/SCORE.md §10.0):
//! part of every [`crate::aggregate::aggregates::Scores`] (the summary, each group, the combined
//! row, each compared run).
//!
//! ```
//! use monitor_host::aggregate::motion::MotionAggregates;
//! let m = MotionAggregates::over(&[]);
//! assert_eq!((m.distance_km, m.mean_comfort_moving), (None, None));
//! assert!(m.stuck_routes.is_empty());
//! ```

use serde::{Deserialize, Serialize};

use crate::aggregate::counts::Counts;
use crate::input::record::KNOWN_LISTS;
use crate::route::row::RouteReport;

/// A route is stuck when it stood still for at least this share of its frames.
pub const STUCK_SHARE: f64 = 0.5;

/// The §8.5 aggregates.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MotionAggregates {
    /// Distance driven over the routes with frames, km; null when none has frames.
    pub distance_km: Option<f64>,
    /// Mean stationary share over the routes with frames.
    pub mean_stationary_share: Option<f64>,
    /// Mean moving comfort over the routes whose moving comfort is defined.
    pub mean_comfort_moving: Option<f64>,
    /// Routes that stood still for at least half of their frames.
    pub stuck_routes: Vec<String>,
    /// Per infraction list, entries per km of the Leaderboard's driven distance
    /// (`RC/100 * meta.route_length / 1000` summed over the routes with a record); null when
    /// that distance is 0.
    pub infractions_per_km: Counts<Option<f64>>,
}

impl MotionAggregates {
    /// The aggregates of `routes`, summed in this order.
    pub fn over(routes: &[&RouteReport]) -> Self {
        let (mut distance, mut with_frames, mut share) = (0.0, 0, 0.0);
        let (mut moving, mut moving_n) = (0.0, 0);
        let mut stuck = Vec::new();
        let mut km = 0.0;
        let mut entries = Counts::<usize>::default();
        for name in KNOWN_LISTS {
            entries.entry(name);
        }
        for r in routes {
            if let (Some(d), Some(s)) = (r.distance_m, r.stationary_share) {
                distance += d;
                share += s;
                with_frames += 1;
                if s >= STUCK_SHARE {
                    stuck.push(r.route_id.clone().unwrap_or_default());
                }
            }
            if let Some(m) = r.comfort.moving_score {
                moving += m;
                moving_n += 1;
            }
            if let Some(k) = r.driven_km {
                km += k;
                for (name, count) in &r.infractions.0 {
                    *entries.entry(name) += count;
                }
            }
        }
        let per = |sum: f64, n: usize| (n > 0).then(|| sum / n as f64);
        MotionAggregates {
            distance_km: (with_frames > 0).then(|| distance / 1000.0),
            mean_stationary_share: per(share, with_frames),
            mean_comfort_moving: per(moving, moving_n),
            stuck_routes: stuck,
            infractions_per_km: Counts(
                entries
                    .0
                    .into_iter()
                    .map(|(name, n)| (name, (km > 0.0).then(|| n as f64 / km)))
                    .collect(),
            ),
        }
    }
}
