//! Collision event → telemetry frame alignment (docs/SCORE.md §6).
//!
//! An event is aligned by LEAD's step-exact `infractions.json` when one is available (first
//! unused entry with the exact same message, whose step exists in the telemetry); otherwise by
//! position: the frame whose 2-D location is nearest to the event's (x, y), if at most 1.0 m away,
//! with every frame within 1e-3 m of the smallest distance counted as a tie and ties going to the
//! earliest frame.
//!
//! ```
//! use monitor_host::input::lead_infractions::StepInfraction;
//! use monitor_host::pipeline::align::{align_events, AlignedBy, EventRef};
//!
//! let steps = [10, 11, 12, 13];
//! let locations = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
//! let events = [
//!     EventRef { message: "hit A", location: Some([2.1, 0.0]) },
//!     EventRef { message: "hit B", location: Some([2.9, 0.2]) },
//! ];
//! let entries = [StepInfraction { step: 11, message: "hit A".into() }];
//! let a = align_events(&events, &steps, &locations, Some(&entries), 1.0, 1e-3);
//! assert_eq!((a[0].frame, a[0].by), (Some(1), Some(AlignedBy::InfractionsJson)));
//! assert_eq!((a[1].frame, a[1].by), (Some(3), Some(AlignedBy::Nearest)));
//! ```

use std::collections::{HashMap, VecDeque};

use crate::geometry::nearest::NearestIndex;
use crate::input::lead_infractions::StepInfraction;

/// How an event was aligned to a frame (the report's `aligned_by`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum AlignedBy {
    /// By nearest 2-D position (`"nearest"`).
    #[serde(rename = "nearest")]
    Nearest,
    /// By the step of a matching `infractions.json` entry (`"infractions.json"`).
    #[serde(rename = "infractions.json")]
    InfractionsJson,
    /// By the log time of a vehicle log's event message (`"log time"`, docs/SCORE.md §2.4).
    #[serde(rename = "log time")]
    LogTime,
}

impl AlignedBy {
    /// The report's string for this method.
    pub fn name(self) -> &'static str {
        match self {
            AlignedBy::Nearest => "nearest",
            AlignedBy::InfractionsJson => "infractions.json",
            AlignedBy::LogTime => "log time",
        }
    }
}

/// The alignment of one event: the frame index (into the telemetry's frames) and how it was
/// found; both `None` when the event is unaligned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Alignment {
    /// Frame index, or `None` (unaligned: not penalised, still counted).
    pub frame: Option<usize>,
    /// How it was aligned (`None` iff `frame` is `None`).
    pub by: Option<AlignedBy>,
}

/// The frame nearest to (x, y) in 2-D, or `None` if there is no frame or the smallest distance
/// exceeds `max_dist` (inclusive bound: exactly `max_dist` aligns).
///
/// Every frame whose distance is within `tie` of the smallest distance is a tie; ties go to the
/// earliest frame. Distances are `sqrt(dx² + dy²)` in f64 on the raw coordinates. Non-finite
/// inputs never align.
///
/// ```
/// use monitor_host::pipeline::align::nearest_frame;
/// let locs = [[0.0, 0.0], [5.0, 0.0], [5.0005, 0.0], [5.0, 0.0]];
/// assert_eq!(nearest_frame(&locs, 5.0006, 0.0, 1.0, 1e-3), Some(1)); // 1, 2, 3 tie
/// assert_eq!(nearest_frame(&locs, 7.5, 0.0, 1.0, 1e-3), None);         // 2.4995 m away
/// ```
///
/// For one query; [`align_events`] builds the [`NearestIndex`] once for all events of a route.
pub fn nearest_frame(
    locations: &[[f64; 2]],
    x: f64,
    y: f64,
    max_dist: f64,
    tie: f64,
) -> Option<usize> {
    NearestIndex::new(locations).nearest(x, y, max_dist, tie)
}

/// A collision event to align: its message (the evaluator's infraction string) and the ego
/// position parsed from it, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventRef<'a> {
    /// The infraction string, compared exactly with `infractions.json` messages.
    pub message: &'a str,
    /// The (x, y) of the event, if parseable.
    pub location: Option<[f64; 2]>,
}

/// Aligns each event, in order (docs/SCORE.md §6).
///
/// With `infractions` given, the first *unused* entry whose `message` equals the event's exactly
/// is consumed; if its step is one of `steps` (sorted, as the telemetry's), that frame is used
/// ([`AlignedBy::InfractionsJson`]). Otherwise (no entry, or the step is absent) the event falls
/// back to [`nearest_frame`] on its location ([`AlignedBy::Nearest`]), and is unaligned when it
/// has no location or no frame is within `max_dist`.
///
/// `steps` and `locations` are per frame, same length and order. Cost: O((events + entries)
/// + frames log frames) (an index by message, a [`NearestIndex`] by position).
pub fn align_events(
    events: &[EventRef<'_>],
    steps: &[u64],
    locations: &[[f64; 2]],
    infractions: Option<&[StepInfraction]>,
    max_dist: f64,
    tie: f64,
) -> Vec<Alignment> {
    // The unused entries of each message, in file order: the first one is consumed.
    let mut unused: HashMap<&str, VecDeque<&StepInfraction>> = HashMap::new();
    for e in infractions.unwrap_or(&[]) {
        unused.entry(e.message.as_str()).or_default().push_back(e);
    }
    let mut index: Option<NearestIndex> = None;
    events
        .iter()
        .map(|ev| {
            if let Some(entry) = unused.get_mut(ev.message).and_then(VecDeque::pop_front) {
                if let Ok(frame) = steps.binary_search(&entry.step) {
                    return Alignment {
                        frame: Some(frame),
                        by: Some(AlignedBy::InfractionsJson),
                    };
                }
            }
            let frame = ev.location.and_then(|[x, y]| {
                index
                    .get_or_insert_with(|| NearestIndex::new(locations))
                    .nearest(x, y, max_dist, tie)
            });
            Alignment {
                frame,
                by: frame.map(|_| AlignedBy::Nearest),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_plain() {
        let locs = [[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]];
        assert_eq!(nearest_frame(&locs, 3.2, 4.1, 1.0, 1e-3), Some(1));
        assert_eq!(nearest_frame(&locs, 5.9, 8.0, 1.0, 1e-3), Some(2));
        assert_eq!(nearest_frame(&[], 0.0, 0.0, 1.0, 1e-3), None);
        assert_eq!(nearest_frame(&locs, f64::NAN, 0.0, 1.0, 1e-3), None);
    }

    #[test]
    fn ties_within_a_millimetre_go_to_the_earliest() {
        // Frame 3 is the nearest (0.0002 m); frames 1 and 2 are within 1e-3 of it, frame 0 not.
        let locs = [
            [100.0, 50.0],
            [100.5009, 50.0],
            [100.5005, 50.0],
            [100.5002, 50.0],
        ];
        assert_eq!(nearest_frame(&locs, 100.5, 50.0, 1.0, 1e-3), Some(1));
        // Just outside the tie band: 0.0013 - 0.0002 = 0.0011 > 1e-3.
        let locs = [[100.5013, 50.0], [100.5002, 50.0]];
        assert_eq!(nearest_frame(&locs, 100.5, 50.0, 1.0, 1e-3), Some(1));
        // Without a tie band the strict nearest is taken.
        let locs = [[100.5009, 50.0], [100.5002, 50.0]];
        assert_eq!(nearest_frame(&locs, 100.5, 50.0, 1.0, 0.0), Some(1));
    }

    #[test]
    fn max_distance_is_inclusive() {
        let locs = [[10.0, 20.0]];
        assert_eq!(nearest_frame(&locs, 11.0, 20.0, 1.0, 1e-3), Some(0));
        assert_eq!(nearest_frame(&locs, 10.0, 19.0, 1.0, 1e-3), Some(0));
        assert_eq!(nearest_frame(&locs, 11.0001, 20.0, 1.0, 1e-3), None);
    }

    #[test]
    fn infractions_use_first_unused_entry() {
        let steps = [100, 101, 102, 103, 104];
        let locs = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]];
        let entries = vec![
            StepInfraction {
                step: 101,
                message: "same".into(),
            },
            StepInfraction {
                step: 103,
                message: "same".into(),
            },
            StepInfraction {
                step: 104,
                message: "other".into(),
            },
        ];
        let ev = |m| EventRef {
            message: m,
            location: Some([0.0, 0.0]),
        };
        let a = align_events(
            &[ev("same"), ev("same"), ev("same"), ev("other")],
            &steps,
            &locs,
            Some(&entries),
            1.0,
            1e-3,
        );
        let got: Vec<_> = a.iter().map(|a| (a.frame, a.by)).collect();
        assert_eq!(
            got,
            vec![
                (Some(1), Some(AlignedBy::InfractionsJson)),
                (Some(3), Some(AlignedBy::InfractionsJson)),
                // Entries used up: falls back to position (0, 0) -> frame 0.
                (Some(0), Some(AlignedBy::Nearest)),
                (Some(4), Some(AlignedBy::InfractionsJson)),
            ]
        );
    }

    #[test]
    fn absent_step_falls_back_to_position() {
        let steps = [100, 101, 103];
        let locs = [[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]];
        let entries = vec![StepInfraction {
            step: 102,
            message: "m".into(),
        }];
        let events = [
            EventRef {
                message: "m",
                location: Some([2.9, 0.0]),
            },
            EventRef {
                message: "n",
                location: None,
            },
            EventRef {
                message: "n",
                location: Some([50.0, 0.0]),
            },
        ];
        let a = align_events(&events, &steps, &locs, Some(&entries), 1.0, 1e-3);
        assert_eq!(
            a[0],
            Alignment {
                frame: Some(2),
                by: Some(AlignedBy::Nearest)
            }
        );
        assert_eq!(a[1], Alignment::default());
        assert_eq!(a[2], Alignment::default());
        // Messages match exactly only: no trimming, case-sensitive.
        let events = [EventRef {
            message: "M",
            location: None,
        }];
        let a = align_events(&events, &steps, &locs, Some(&entries), 1.0, 1e-3);
        assert_eq!(a[0], Alignment::default());
        // Without infractions.json, position only.
        let events = [EventRef {
            message: "m",
            location: Some([1.2, 0.1]),
        }];
        let a = align_events(&events, &steps, &locs, None, 1.0, 1e-3);
        assert_eq!(
            a[0],
            Alignment {
                frame: Some(1),
                by: Some(AlignedBy::Nearest)
            }
        );
    }

    #[test]
    fn aligned_by_serialises_as_report_strings() {
        assert_eq!(
            serde_json::to_string(&[AlignedBy::Nearest, AlignedBy::InfractionsJson]).unwrap(),
            r#"["nearest","infractions.json"]"#
        );
        assert_eq!(AlignedBy::InfractionsJson.name(), "infractions.json");
    }
}
