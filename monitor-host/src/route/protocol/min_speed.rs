//! The min-speed entries that count as events (`SDS-SPEC.md` v1.3 §8.4): the percentages `P`
//! of `Average speed is P% of the surrounding traffic's one` below 100. The Leaderboard's own
//! `MinimumSpeedRouteTest` logs a checkpoint only below 100 %; Bench2Drive's copy logs every
//! checkpoint (values above 26,000,000 % occur), which no protocol may count.
//!
//! ```
//! use monitor_host::route::protocol::min_speed::min_speed_events;
//! let e = min_speed_events(&[
//!     "Average speed is 80.5% of the surrounding traffic's one".into(),
//!     "Average speed is 100% of the surrounding traffic's one".into(),   // not an event
//!     "Average speed is 1098.69% of the surrounding traffic's one".into(), // not an event
//!     "Average speed is slow".into(),                                    // skipped, warned
//! ]);
//! assert_eq!(e.percents, [80.5]);
//! assert_eq!(e.unreadable, ["Average speed is slow"]);
//! ```

use crate::route::penalty::min_speed_percent;

/// A min-speed percentage at or above this is not an event.
pub const SUCCESS_PERCENT: f64 = 100.0;

/// The min-speed entries of one route, as the protocols read them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MinSpeedEvents {
    /// The percentages below 100, in list order.
    pub percents: Vec<f64>,
    /// Entries without a readable percentage (skipped, with a warning).
    pub unreadable: Vec<String>,
}

/// Reads a route's `min_speed_infractions`.
pub fn min_speed_events(entries: &[String]) -> MinSpeedEvents {
    let mut out = MinSpeedEvents::default();
    for s in entries {
        match min_speed_percent(s) {
            Some(p) if p < SUCCESS_PERCENT => out.percents.push(p),
            Some(_) => {}
            None => out.unreadable.push(s.clone()),
        }
    }
    out
}
