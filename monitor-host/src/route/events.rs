//! Everything that happened on a route that can be placed on its frame axis, in one list
//! (issue 28; the report's per-route `events`): its collisions (aligned by §5, or unplaced), its
//! anomalous and critical lateral chunks (§6) and its uncomfortable chunks (§4), each with the
//! frame and step it starts at, the time from the route's first frame and a message. Sorted by
//! frame (stable: collisions before chunks at one frame); events without a frame come last,
//! listed, never dropped.
//!
//! ```
//! use monitor_host::route::events::route_events;
//! assert!(route_events(&[], None, 20).is_empty());
//! ```

use monitor_core::{Band, Failures};
use serde::Serialize;

use crate::pipeline::outcome::CollisionEvent;
use crate::pipeline::timeline::RouteTimeline;

/// One event of a route.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RouteEvent {
    /// `collision`, `lateral_anomalous`, `lateral_critical` or `uncomfortable`.
    pub kind: &'static str,
    /// The frame (0-based): the collision's aligned frame, a chunk's first frame; null when
    /// the event could not be placed.
    pub frame: Option<usize>,
    /// That frame's step number; null when unplaced.
    pub step: Option<u64>,
    /// Seconds from the route's first frame, `(step − first step) × dt`; null when unplaced.
    pub time_s: Option<f64>,
    /// What happened: the evaluator's collision string, or the chunk and what it failed.
    pub message: String,
}

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

/// The events of a route: its `collisions` (as the report lists them) and the chunk verdicts of
/// its `timeline` (none when it was not replayed), chunks of `chunk_len` frames.
pub fn route_events(
    collisions: &[CollisionEvent],
    timeline: Option<&RouteTimeline>,
    chunk_len: u16,
) -> Vec<RouteEvent> {
    let mut out: Vec<RouteEvent> = collisions
        .iter()
        .map(|e| RouteEvent {
            kind: "collision",
            frame: e.frame,
            step: e.step,
            time_s: e.time_s,
            message: format!(
                "{}: {}{}",
                e.list.name(),
                e.message,
                match (e.frame, e.exempt, e.decelerated) {
                    (None, _, _) => " (not placed: no usable position)",
                    (_, Some(true), _) => " (exempt: standing)",
                    (_, _, Some(true)) => " (decelerated)",
                    _ => " (no deceleration)",
                }
            ),
        })
        .collect();
    if let Some(t) = timeline {
        let len = usize::from(chunk_len.max(1));
        let place = |chunk: u32| {
            let frame = chunk as usize * len;
            let step = t.chunk_steps.get(chunk as usize).copied();
            (
                step.map(|_| frame),
                step,
                step.map(|s| (s as f64 - t.first_step as f64) * t.dt),
            )
        };
        for l in &t.chunks.lateral {
            let (frame, step, time_s) = place(l.chunk);
            let (kind, band) = match l.band {
                Band::Critical => ("lateral_critical", "critical"),
                _ => ("lateral_anomalous", "anomalous"),
            };
            out.push(RouteEvent {
                kind,
                frame,
                step,
                time_s,
                message: format!(
                    "lateral chunk {}: max excess {:.2} m ({band})",
                    l.chunk, l.max_excess
                ),
            });
        }
        for c in t.chunks.comfort.iter().filter(|c| !c.failed.comfortable()) {
            let (frame, step, time_s) = place(c.chunk);
            let failed: Vec<&str> = BOUNDS
                .iter()
                .filter(|(_, test)| test(&c.failed))
                .map(|(name, _)| *name)
                .collect();
            out.push(RouteEvent {
                kind: "uncomfortable",
                frame,
                step,
                time_s,
                message: format!("comfort chunk {} failed {}", c.chunk, failed.join(", ")),
            });
        }
    }
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
        let e = route_events(&[collision(None), collision(Some(25))], Some(&t), 20);
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
    }
}
