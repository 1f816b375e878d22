//! The min-speed entries that count as events (docs/PROTOCOLS.md, "The min-speed grid"):
//! the percentages `P` of `Average speed is P% of the surrounding traffic's one`, read on the
//! checkpoint grid the record was logged on.
//!
//! The Leaderboard's `MinimumSpeedRouteTest` checks 4 checkpoints (and one past 95 % of the
//! route) and logs a checkpoint only below its success value 100 %. Bench2Drive's copy checks
//! 20 and logs every one (values above 26,000,000 % occur). So a record on Bench2Drive's grid
//! (setting `min_speed_grid`: `auto` decides per record) has its entries with a number taken, in
//! record order, in groups of 5: each group is one Leaderboard checkpoint at the harmonic mean of
//! its values. The Leaderboard's value over a stretch is `100 × ΣA / ΣR` (ego speed A, mean
//! background speed R, per frame); the five sub-stretches are equally long (`ΣA·dt` each), so
//! the value over the five is the harmonic mean of theirs. Only checkpoints below 100 % are
//! events.
//!
//! ```
//! use monitor_host::route::protocol::min_speed::{min_speed_events, MinSpeedGrid};
//! use monitor_host::settings::MinSpeedGridSetting;
//! let e = min_speed_events(&[
//!     "Average speed is 80.5% of the surrounding traffic's one".into(),
//!     "Average speed is 100% of the surrounding traffic's one".into(),   // not an event
//!     "Average speed is 1098.69% of the surrounding traffic's one".into(), // not an event
//!     "Average speed is slow".into(),                                    // skipped, warned
//!     "Average speed is -300% of the surrounding traffic's one".into(),  // refused, warned
//! ], MinSpeedGridSetting::Lb4);
//! assert_eq!((e.grid, e.percents.as_slice()), (MinSpeedGrid::Lb4, &[80.5][..]));
//! assert_eq!(e.unreadable, ["Average speed is slow"]);
//! assert_eq!(e.impossible.len(), 1);
//! // On Bench2Drive's grid the three values with a number are one checkpoint: 3 / (1/80.5 +
//! // 1/100 + 1/1098.69) = 138.2 %, not an event.
//! let e = min_speed_events(&[
//!     "Average speed is 80.5% of the surrounding traffic's one".into(),
//!     "Average speed is 100% of the surrounding traffic's one".into(),
//!     "Average speed is 1098.69% of the surrounding traffic's one".into(),
//! ], MinSpeedGridSetting::Auto);
//! assert_eq!(e.grid, MinSpeedGrid::B2d20);
//! assert!(e.percents.is_empty());
//! ```

use serde::{Deserialize, Serialize};

use crate::input::message::{min_speed_percent_text, percent_of, Percent};
use crate::settings::MinSpeedGridSetting;

/// A min-speed percentage at or above this is not an event.
pub const SUCCESS_PERCENT: f64 = 100.0;

/// Bench2Drive's entries per Leaderboard checkpoint: 20 checkpoints against the Leaderboard's 4.
pub const GROUP: usize = 5;

/// Under `auto`, a record with more entries with a number than this is on Bench2Drive's grid
/// (the Leaderboard logs at most 4 checkpoints and a last one).
pub const LB_MAX_ENTRIES: usize = 5;

/// The checkpoint grid a record's min-speed entries were logged on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum MinSpeedGrid {
    /// Bench2Drive's 20 checkpoints, every one logged (`b2d-20`).
    #[serde(rename = "b2d-20")]
    B2d20,
    /// The Leaderboard's 4, logged below 100 % only (`lb-4`).
    #[serde(rename = "lb-4")]
    Lb4,
}

impl MinSpeedGrid {
    /// `b2d-20` or `lb-4`.
    pub fn name(self) -> &'static str {
        match self {
            MinSpeedGrid::B2d20 => "b2d-20",
            MinSpeedGrid::Lb4 => "lb-4",
        }
    }
}

/// The min-speed entries of one route, as the protocols read them.
#[derive(Clone, Debug, PartialEq)]
pub struct MinSpeedEvents {
    /// The grid the record was read on.
    pub grid: MinSpeedGrid,
    /// The percentages of the Leaderboard checkpoints below 100, in record order: the events
    /// charged.
    pub percents: Vec<f64>,
    /// Entries without a readable percentage (skipped, with a warning).
    pub unreadable: Vec<String>,
    /// Entries with an impossible percentage, negative or not finite (refused, with a warning).
    pub impossible: Vec<String>,
}

impl Default for MinSpeedEvents {
    fn default() -> Self {
        MinSpeedEvents {
            grid: MinSpeedGrid::Lb4,
            percents: Vec::new(),
            unreadable: Vec::new(),
            impossible: Vec::new(),
        }
    }
}

/// The grid of a record whose entries with a (possible) number are `values`, under `setting`.
pub fn grid_of(setting: MinSpeedGridSetting, values: &[f64]) -> MinSpeedGrid {
    match setting {
        MinSpeedGridSetting::B2d20 => MinSpeedGrid::B2d20,
        MinSpeedGridSetting::Lb4 => MinSpeedGrid::Lb4,
        MinSpeedGridSetting::Auto
            if values.len() > LB_MAX_ENTRIES || values.iter().any(|&p| p >= SUCCESS_PERCENT) =>
        {
            MinSpeedGrid::B2d20
        }
        MinSpeedGridSetting::Auto => MinSpeedGrid::Lb4,
    }
}

/// The harmonic mean `n / Σ 1/P_j` of a group's values; 0 when any is 0 (and for none).
///
/// ```
/// use monitor_host::route::protocol::min_speed::harmonic_percent;
/// assert_eq!(harmonic_percent(&[50.0, 200.0]), 80.0);
/// assert_eq!(harmonic_percent(&[0.0, 200.0]), 0.0);
/// ```
pub fn harmonic_percent(values: &[f64]) -> f64 {
    if values.is_empty() || values.iter().any(|&p| p <= 0.0) {
        return 0.0;
    }
    values.len() as f64 / values.iter().map(|p| 1.0 / p).sum::<f64>()
}

/// The Leaderboard checkpoints of `values` (in record order) on `grid`: the values themselves
/// on the Leaderboard's, the harmonic mean of each group of [`GROUP`] on Bench2Drive's (the
/// last group may be shorter).
pub fn checkpoints(grid: MinSpeedGrid, values: &[f64]) -> Vec<f64> {
    match grid {
        MinSpeedGrid::Lb4 => values.to_vec(),
        MinSpeedGrid::B2d20 => values.chunks(GROUP).map(harmonic_percent).collect(),
    }
}

/// The possible percentages of a route's `min_speed_infractions`, in record order, with the
/// entries skipped: `(values, unreadable, impossible)`.
fn read(entries: &[String]) -> (Vec<f64>, Vec<String>, Vec<String>) {
    let (mut values, mut unreadable, mut impossible) = (Vec::new(), Vec::new(), Vec::new());
    for s in entries {
        match percent_of(s, min_speed_percent_text) {
            Percent::Possible(p) => values.push(p),
            Percent::Impossible => impossible.push(s.clone()),
            Percent::Unreadable => unreadable.push(s.clone()),
        }
    }
    (values, unreadable, impossible)
}

/// The grid a route's `min_speed_infractions` are read on under `setting`.
pub fn min_speed_grid(entries: &[String], setting: MinSpeedGridSetting) -> MinSpeedGrid {
    grid_of(setting, &read(entries).0)
}

/// Reads a route's `min_speed_infractions` on the grid `setting` gives it.
pub fn min_speed_events(entries: &[String], setting: MinSpeedGridSetting) -> MinSpeedEvents {
    let (values, unreadable, impossible) = read(entries);
    let grid = grid_of(setting, &values);
    MinSpeedEvents {
        grid,
        percents: checkpoints(grid, &values)
            .into_iter()
            .filter(|&p| p < SUCCESS_PERCENT)
            .collect(),
        unreadable,
        impossible,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(ps: &[f64]) -> Vec<String> {
        ps.iter()
            .map(|p| format!("Average speed is {p}% of the surrounding traffic's one"))
            .collect()
    }

    #[test]
    fn auto_grid() {
        let g = |ps: &[f64]| min_speed_events(&entries(ps), MinSpeedGridSetting::Auto).grid;
        assert_eq!(g(&[10.0; 5]), MinSpeedGrid::Lb4);
        assert_eq!(g(&[10.0; 6]), MinSpeedGrid::B2d20);
        assert_eq!(g(&[100.0]), MinSpeedGrid::B2d20);
        assert_eq!(g(&[]), MinSpeedGrid::Lb4);
    }

    #[test]
    fn groups_of_five_last_shorter() {
        let ps = [50.0, 50.0, 50.0, 50.0, 50.0, 200.0, 200.0, 40.0];
        let e = min_speed_events(&entries(&ps), MinSpeedGridSetting::Auto);
        // 50 for the first five; 3 / (2/200 + 1/40) = 85.714... for the last three.
        assert_eq!(e.percents.len(), 2);
        assert!((e.percents[0] - 50.0).abs() < 1e-12);
        assert!((e.percents[1] - 3.0 / 0.035).abs() < 1e-12);
        // The Leaderboard's grid charges every entry below 100.
        let e = min_speed_events(&entries(&ps), MinSpeedGridSetting::Lb4);
        assert_eq!(e.percents.len(), 6);
    }

    #[test]
    fn impossible_percentages_are_refused() {
        let mut es = entries(&[50.0]);
        es.push("Average speed is -1e300% of the surrounding traffic's one".into());
        es.push("Average speed is 1e999% of the surrounding traffic's one".into());
        let e = min_speed_events(&es, MinSpeedGridSetting::Auto);
        assert_eq!(e.percents, [50.0]);
        assert_eq!(e.impossible.len(), 2);
    }
}
