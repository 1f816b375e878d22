//! Everything that happened on a route that can be placed on its frame axis, in one list
//! (issue 28; the report's per-route `events`): its collisions (aligned by §5, or unplaced), the
//! evaluator's other infractions (red lights, stop signs, blocked, min speed, ... placed by
//! [`crate::pipeline::placement`]'s rules), its anomalous and critical lateral chunks (docs/SCORE.md §7), its
//! uncomfortable chunks (docs/SCORE.md §5) and its long stationary stretches, each with the frame and step it
//! starts at, the time from the route's first frame and a message. Sorted by frame (stable:
//! collisions, then infractions, then chunks, then stretches at one frame); events without a
//! frame come last, listed, never dropped.
//!
//! ```
//! use monitor_host::route::events::route_events;
//! assert!(route_events(&[], &[], None, 20, 0).is_empty());
//! ```

use monitor_core::{Band, Failures};
use serde::{Deserialize, Serialize};

use crate::pipeline::outcome::CollisionEvent;
use crate::pipeline::placement::{unplaced_reason, PlacedBy, PlacedEvent};
use crate::pipeline::timeline::RouteTimeline;

/// One event of a route.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RouteEvent {
    /// `collision`; an infraction's kind (`red_light`, `stop_sign`, `blocked`,
    /// `route_deviation`, `outside_lanes`, `min_speed`, `yield_emergency_vehicle`,
    /// `scenario_timeout`, `route_timeout`, `other`); `lateral_anomalous`, `lateral_critical`,
    /// `uncomfortable` (chunks) or `stationary` (a stretch).
    #[serde(deserialize_with = "kind_name")]
    pub kind: crate::named::Name,
    /// The results file's infraction list it comes from; null for what the monitor found.
    pub list: Option<String>,
    /// The frame (0-based): the collision's aligned frame, an infraction's placed frame, a
    /// chunk's or stretch's first frame; null when the event could not be placed.
    pub frame: Option<usize>,
    /// The first frame after a chunk or a stretch (null for events at one frame).
    pub end_frame: Option<usize>,
    /// That frame's step number; null when unplaced.
    pub step: Option<u64>,
    /// Seconds from the route's first frame, `(step − first step) × dt`; null when unplaced.
    pub time_s: Option<f64>,
    /// How it was placed: `infractions.json`, `nearest` (docs/SCORE.md §6's rule on the ego position in the
    /// message), `closest_approach` (to a traffic light or stop sign), `chunk`, `motion`;
    /// null when unplaced.
    #[serde(default, deserialize_with = "placed_by_name")]
    pub placed_by: Option<crate::named::Name>,
    /// From the placed frame to the position in the message, m (placed by position, except
    /// collisions, whose distance §5 bounds by `align_max_dist`).
    pub distance_m: Option<f64>,
    /// Index of the collision among the route's `collision_events` (its trace figure).
    pub collision: Option<usize>,
    /// What happened: the evaluator's message, or the chunk and what it failed.
    pub message: String,
}

/// Every event kind (`RouteEvent::kind`), as the report writes them.
pub const KINDS: [&str; 15] = [
    "collision",
    "red_light",
    "stop_sign",
    "blocked",
    "route_deviation",
    "outside_lanes",
    "min_speed",
    "yield_emergency_vehicle",
    "scenario_timeout",
    "route_timeout",
    "other",
    "lateral_anomalous",
    "lateral_critical",
    "uncomfortable",
    "stationary",
];

/// Every way an event is placed (`RouteEvent::placed_by`): a collision's alignment
/// ([`crate::pipeline::align::AlignedBy`]), an infraction's or a stretch's placement
/// ([`PlacedBy`]), or its chunk.
pub const PLACED_BY: [&str; 6] = [
    "infractions.json",
    "nearest",
    "log time",
    "closest_approach",
    "motion",
    "chunk",
];

name_field!(kind_name, KINDS);
name_field!(opt placed_by_name, PLACED_BY);

/// Whether a chunk failed a bound.
pub(crate) type Test = fn(&Failures) -> bool;

/// The bounds, in the report's order (also the rows of the HTML page's comfort timeline).
pub(crate) const BOUNDS: [(&str, Test); 6] = [
    ("lon_acc", |f| f.lon_acc),
    ("lat_acc", |f| f.lat_acc),
    ("mag_jerk", |f| f.mag_jerk),
    ("lon_jerk", |f| f.lon_jerk),
    ("yaw_acc", |f| f.yaw_acc),
    ("yaw_rate", |f| f.yaw_rate),
];

/// The events of a route: its `collisions` (as the report lists them), its `placed`
/// infractions and stretches, and the chunk verdicts of its `timeline` (none when it was not
/// replayed), chunks of `chunk_len` frames, `frames` frames in all.
pub fn route_events(
    collisions: &[CollisionEvent],
    placed: &[PlacedEvent],
    timeline: Option<&RouteTimeline>,
    chunk_len: u16,
    frames: usize,
) -> Vec<RouteEvent> {
    let replayed = timeline.is_some();
    let mut out: Vec<RouteEvent> = collisions
        .iter()
        .enumerate()
        .map(|(i, e)| RouteEvent {
            kind: "collision",
            list: Some(e.list.name().to_string()),
            frame: e.frame,
            end_frame: None,
            step: e.step,
            time_s: e.time_s,
            placed_by: e.aligned_by.map(|a| a.name()),
            distance_m: None,
            collision: Some(i),
            message: format!(
                "{}: {} ({})",
                e.list.name(),
                e.message,
                match (e.frame, e.exempt, e.decelerated) {
                    (None, _, _) => {
                        format!("not placed: {}", unplaced_reason(replayed, e.location))
                    }
                    (_, Some(true), _) => "exempt: standing".into(),
                    (_, _, Some(true)) => "decelerated".into(),
                    _ => "no deceleration".into(),
                }
            ),
        })
        .collect();
    let (infractions, stretches): (Vec<&PlacedEvent>, Vec<&PlacedEvent>) =
        placed.iter().partition(|p| p.list.is_some());
    let of_placed = |p: &PlacedEvent| RouteEvent {
        kind: p.kind,
        list: p.list.clone(),
        frame: p.frame,
        end_frame: p.end_frame,
        step: p.step,
        time_s: p.time_s,
        placed_by: p.placed_by.map(PlacedBy::name),
        distance_m: p.distance_m,
        collision: None,
        message: match (&p.list, p.frame, p.placed_by, p.distance_m) {
            (Some(list), None, _, _) => format!(
                "{list}: {} (not placed: {})",
                p.message,
                unplaced_reason(replayed, p.location)
            ),
            (Some(list), Some(_), Some(PlacedBy::ClosestApproach), Some(d)) => {
                format!(
                    "{list}: {} (placed at the closest approach, {d:.1} m)",
                    p.message
                )
            }
            (Some(list), _, _, _) => format!("{list}: {}", p.message),
            (None, _, _, _) => p.message.clone(),
        },
    };
    out.extend(infractions.into_iter().map(of_placed));
    if let Some(t) = timeline {
        let len = usize::from(chunk_len.max(1));
        let place = |chunk: u32| {
            let frame = t
                .chunk_frames
                .get(chunk as usize)
                .copied()
                .unwrap_or(chunk as usize * len);
            let step = t.chunk_steps.get(chunk as usize).copied();
            (
                step.map(|_| frame),
                step.map(|_| (frame + len).min(frames.max(frame + 1))),
                step,
                step.map(|s| (s as f64 - t.first_step as f64) * t.dt),
            )
        };
        for l in &t.chunks.lateral {
            let (frame, end_frame, step, time_s) = place(l.chunk);
            let (kind, band) = match l.band {
                Band::Critical => ("lateral_critical", "critical"),
                _ => ("lateral_anomalous", "anomalous"),
            };
            out.push(RouteEvent {
                kind,
                list: None,
                frame,
                end_frame,
                step,
                time_s,
                placed_by: frame.map(|_| "chunk"),
                distance_m: None,
                collision: None,
                message: format!(
                    "lateral chunk {}: max excess {:.2} m ({band})",
                    l.chunk, l.max_excess
                ),
            });
        }
        for c in t.chunks.comfort.iter().filter(|c| !c.failed.comfortable()) {
            let (frame, _, step, time_s) = place(c.chunk);
            let failed: Vec<&str> = BOUNDS
                .iter()
                .filter(|(_, test)| test(&c.failed))
                .map(|(name, _)| *name)
                .collect();
            out.push(RouteEvent {
                kind: "uncomfortable",
                list: None,
                frame,
                end_frame: frame.map(|f| f + usize::from(c.frames).max(1)),
                step,
                time_s,
                placed_by: frame.map(|_| "chunk"),
                distance_m: None,
                collision: None,
                message: format!("comfort chunk {} failed {}", c.chunk, failed.join(", ")),
            });
        }
    }
    out.extend(stretches.into_iter().map(of_placed));
    // Placed events by frame, unplaced last; stable, so a list's own order stays.
    out.sort_by_key(|e| e.frame.map_or((1, 0), |f| (0, f)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::collision::CollisionList;
    use crate::pipeline::timeline::ChunkLog;
    use monitor_core::{ComfortVerdict, LateralVerdict};

    fn collision(frame: Option<usize>) -> CollisionEvent {
        CollisionEvent {
            list: CollisionList::Vehicle,
            type_id: None,
            workzone: false,
            frame,
            step: frame.map(|f| f as u64 + 10),
            aligned_by: None,
            time_s: frame.map(|f| f as f64 * 0.05),
            impact_speed: None,
            decelerated: Some(false),
            exempt: Some(false),
            parse_error: None,
            message: "hit".into(),
            location: None,
        }
    }

    #[test]
    fn placed_by_frame_unplaced_last() {
        let t = RouteTimeline {
            first_step: 10,
            dt: 0.05,
            chunks: ChunkLog {
                comfort: vec![ComfortVerdict {
                    chunk: 1,
                    frames: 20,
                    failed: Failures {
                        yaw_rate: true,
                        ..Failures::default()
                    },
                }],
                lateral: vec![LateralVerdict {
                    chunk: 0,
                    max_excess: 0.3,
                    band: Band::Anomalous,
                }],
            },
            chunk_steps: vec![10, 30],
            ..RouteTimeline::default()
        };
        let e = route_events(
            &[collision(None), collision(Some(25))],
            &[],
            Some(&t),
            20,
            40,
        );
        let got: Vec<(&str, Option<usize>)> = e.iter().map(|e| (e.kind, e.frame)).collect();
        assert_eq!(
            got,
            [
                ("lateral_anomalous", Some(0)),
                ("uncomfortable", Some(20)),
                ("collision", Some(25)),
                ("collision", None)
            ]
        );
        assert_eq!((e[1].step, e[1].time_s), (Some(30), Some(1.0)));
        assert_eq!(e[1].message, "comfort chunk 1 failed yaw_rate");
        assert_eq!((e[0].end_frame, e[1].end_frame), (Some(20), Some(40)));
        assert_eq!((e[2].collision, e[3].collision), (Some(1), Some(0)));
    }
}
