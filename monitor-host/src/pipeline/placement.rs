//! The evaluator's other infractions, and the stationary stretches, placed on a route's frame
//! axis (issue 28; the report's per-route `events`). Collisions have their own rule (docs/SCORE.md §6,
//! [`crate::pipeline::align`]); nothing here changes a score.
//!
//! Each infraction is placed, in this order:
//! 1. by LEAD's step-exact `infractions.json` (the first unused entry with the same message
//!    whose step is a telemetry step), as collisions are;
//! 2. by the position its message ends with, which CARLA's criteria fill differently per list:
//!    - `vehicle_blocked`, `route_dev` (and unknown lists): the ego's own location, so §5's rule
//!      applies (the nearest frame within `align_max_dist`, ties to the earliest: a blocked car
//!      is placed where it came to a stop);
//!    - `red_light`, `stop_infraction`: the traffic light's or the stop sign's location (the
//!      actor's transform): the frame of the ego's closest approach to it, within
//!      `events.signal_reach` (30 m) **\[decision\]**. The evaluator fires when the ego's tail
//!      crosses the stop line, so this frame is near the infraction, not on it; the report says
//!      `closest_approach` and the distance;
//!    - the others (`outside_route_lanes`, `min_speed_infractions`, timeouts, yield to an
//!      emergency vehicle) carry no position and stay unplaced without `infractions.json`.
//!
//! An event that cannot be placed is kept, unplaced. Only min-speed entries below 100 % are
//! events (the others are checkpoints the ego kept up at, as §8.4's protocols count them).
//!
//! ```
//! use monitor_host::input::record::Infractions;
//! use monitor_host::pipeline::placement::{infraction_events, place, PlacedBy};
//! use monitor_host::settings::Settings;
//!
//! let inf = Infractions::from_lists([(
//!     "red_light",
//!     vec!["Agent ran a red light 7 at (x=20.0, y=6.0, z=0.0)".to_string()],
//! )]);
//! let mut events = infraction_events(&inf);
//! let steps: Vec<u64> = (0..50).collect();
//! let locations: Vec<[f64; 2]> = (0..50).map(|i| [i as f64, 0.0]).collect();
//! place(&mut events, &steps, &locations, None, &Settings::default(), 0.05);
//! assert_eq!(events[0].frame, Some(20)); // 6 m beside the road: the closest approach
//! assert_eq!(events[0].placed_by, Some(PlacedBy::ClosestApproach));
//! assert_eq!(events[0].distance_m, Some(6.0));
//! ```

use crate::input::lead_infractions::StepInfraction;
use crate::input::message::{message_position, min_speed_percent};
use crate::input::record::Infractions;
use crate::pipeline::align::{align_events, AlignedBy, EventRef};
use crate::settings::Settings;

/// How an event was placed on the frame axis (the report's `placed_by`: [`PlacedBy::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlacedBy {
    /// The step of a matching `infractions.json` entry.
    InfractionsJson,
    /// The frame nearest to the ego position in the message (docs/SCORE.md §6's rule).
    Nearest,
    /// The frame of the closest approach to a traffic light or stop sign.
    ClosestApproach,
    /// A stationary stretch: its first frame.
    Motion,
}

impl PlacedBy {
    /// The report's string: `infractions.json`, `nearest`, `closest_approach`, `motion`.
    pub fn name(self) -> &'static str {
        match self {
            PlacedBy::InfractionsJson => "infractions.json",
            PlacedBy::Nearest => "nearest",
            PlacedBy::ClosestApproach => "closest_approach",
            PlacedBy::Motion => "motion",
        }
    }
}

/// What a message's position is, by list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reach {
    /// The ego's location: docs/SCORE.md §6's `align_max_dist`.
    Ego,
    /// A traffic light's or a stop sign's location: `events.signal_reach`.
    Signal,
    /// No position.
    None,
}

/// The event kind of a (non-collision) infraction list, and what its position is.
fn kind_of(list: &str) -> (&'static str, Reach) {
    match list {
        "red_light" => ("red_light", Reach::Signal),
        "stop_infraction" => ("stop_sign", Reach::Signal),
        "vehicle_blocked" => ("blocked", Reach::Ego),
        "route_dev" => ("route_deviation", Reach::Ego),
        "outside_route_lanes" => ("outside_lanes", Reach::None),
        "min_speed_infractions" => ("min_speed", Reach::None),
        "yield_emergency_vehicle_infractions" => ("yield_emergency_vehicle", Reach::None),
        "scenario_timeouts" => ("scenario_timeout", Reach::None),
        "route_timeout" => ("route_timeout", Reach::None),
        _ => ("other", Reach::Ego),
    }
}

/// One infraction (or stationary stretch) and where it sits on the frame axis.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedEvent {
    /// `red_light`, `stop_sign`, `blocked`, `route_deviation`, `outside_lanes`, `min_speed`,
    /// `yield_emergency_vehicle`, `scenario_timeout`, `route_timeout`, `other` (a list this
    /// tool does not know) or `stationary`.
    pub kind: &'static str,
    /// The results file's list it comes from; `None` for a stationary stretch.
    pub list: Option<String>,
    /// The evaluator's message (for a stationary stretch, a description).
    pub message: String,
    /// The (x, y) in the message, if any.
    pub location: Option<[f64; 2]>,
    /// The frame (0-based), or `None` when unplaced.
    pub frame: Option<usize>,
    /// That frame's step.
    pub step: Option<u64>,
    /// Seconds from the route's first frame.
    pub time_s: Option<f64>,
    /// The first frame after it (stationary stretches only: they span frames).
    pub end_frame: Option<usize>,
    /// How it was placed; `None` when unplaced.
    pub placed_by: Option<PlacedBy>,
    /// The 2-D distance from the placed frame to the message's position, m (placed by position).
    pub distance_m: Option<f64>,
    reach: Reach,
}

/// Why an event (a collision or another infraction) stays off the frame axis, as the report's
/// `events` say it: the route was not replayed (`no telemetry`: none found, or none usable), its
/// message gives no position (and no `infractions.json` step placed it), or no frame lies near
/// that position (docs/SCORE.md §6's `align_max_dist`, or `events.signal_reach` for a light or a stop sign).
///
/// ```
/// use monitor_host::pipeline::placement::unplaced_reason;
/// assert_eq!(unplaced_reason(false, Some([1.0, 2.0])), "no telemetry");
/// assert_eq!(unplaced_reason(true, None), "no position in the message");
/// assert_eq!(unplaced_reason(true, Some([1.0, 2.0])), "no frame near its position");
/// ```
pub fn unplaced_reason(replayed: bool, position: Option<[f64; 2]>) -> &'static str {
    match (replayed, position) {
        (false, _) => "no telemetry",
        (true, None) => "no position in the message",
        (true, Some(_)) => "no frame near its position",
    }
}

/// A record's non-collision infractions as events, unplaced, in the record's list order (the
/// collision lists are left to §5).
///
/// ```
/// use monitor_host::input::record::Infractions;
/// use monitor_host::pipeline::placement::infraction_events;
/// let inf = Infractions::from_lists([(
///     "min_speed_infractions",
///     vec!["Average speed is 140.88% of the surrounding traffic's one".to_string(),
///          "Average speed is 79.78% of the surrounding traffic's one".to_string()],
/// )]);
/// let e = infraction_events(&inf);
/// assert_eq!(e.len(), 1); // only the entry below 100 %
/// assert_eq!((e[0].kind, e[0].frame), ("min_speed", None));
/// ```
pub fn infraction_events(infractions: &Infractions) -> Vec<PlacedEvent> {
    let mut out = Vec::new();
    for (list, entries) in infractions.all() {
        if list.starts_with("collisions_") {
            continue;
        }
        let (kind, reach) = kind_of(list);
        for m in entries {
            if list == "min_speed_infractions" && min_speed_percent(m).is_some_and(|p| p >= 100.0) {
                continue;
            }
            out.push(PlacedEvent {
                kind,
                list: Some(list.to_string()),
                message: m.clone(),
                location: message_position(m).map(|[x, y, _]| [x, y]),
                frame: None,
                step: None,
                time_s: None,
                end_frame: None,
                placed_by: None,
                distance_m: None,
                reach,
            });
        }
    }
    out
}

/// Places `events` on the frames (`steps` and 2-D `locations`, per frame, step order; `dt` the
/// route's step period, s): see the module's rules. Events already placed are placed again.
pub fn place(
    events: &mut [PlacedEvent],
    steps: &[u64],
    locations: &[[f64; 2]],
    infractions: Option<&[StepInfraction]>,
    settings: &Settings,
    dt: f64,
) {
    for reach in [Reach::Ego, Reach::Signal, Reach::None] {
        let max_dist = match reach {
            Reach::Ego => settings.align_max_dist,
            Reach::Signal => settings.events.signal_reach,
            Reach::None => 0.0,
        };
        let at: Vec<usize> = (0..events.len())
            .filter(|&i| events[i].reach == reach && events[i].list.is_some())
            .collect();
        let refs: Vec<EventRef> = at
            .iter()
            .map(|&i| EventRef {
                message: &events[i].message,
                location: events[i].location.filter(|_| reach != Reach::None),
            })
            .collect();
        let aligned = align_events(
            &refs,
            steps,
            locations,
            infractions,
            max_dist,
            settings.align_tie,
        );
        for (i, a) in at.into_iter().zip(aligned) {
            let e = &mut events[i];
            let k = a.frame.filter(|&k| k < steps.len() && k < locations.len());
            e.frame = k;
            e.step = k.map(|k| steps[k]);
            e.time_s = k.map(|k| (steps[k] - steps[0]) as f64 * dt);
            e.placed_by = a.by.filter(|_| k.is_some()).map(|by| match (by, reach) {
                (AlignedBy::InfractionsJson | AlignedBy::LogTime, _) => PlacedBy::InfractionsJson,
                (_, Reach::Signal) => PlacedBy::ClosestApproach,
                _ => PlacedBy::Nearest,
            });
            e.distance_m = match (e.placed_by, k, e.location) {
                (Some(PlacedBy::Nearest | PlacedBy::ClosestApproach), Some(k), Some([x, y])) => {
                    Some((locations[k][0] - x).hypot(locations[k][1] - y))
                }
                _ => None,
            };
        }
    }
}

/// The stationary stretches (frame ranges `[start, end)`, as [`crate::pipeline::motion`] finds
/// them) that last at least `settings.events.min_standing` seconds, as events: placed at their
/// first frame, lasting from it to the first frame after them (or to the last frame).
///
/// ```
/// use monitor_host::pipeline::placement::standing_events;
/// use monitor_host::settings::Settings;
/// let steps: Vec<u64> = (100..200).collect();
/// let e = standing_events(&[(10, 20), (40, 90)], &steps, &Settings::default(), 0.05);
/// assert_eq!(e.len(), 1); // 0.5 s is too short
/// assert_eq!((e[0].frame, e[0].time_s, e[0].end_frame), (Some(40), Some(2.0), Some(90)));
/// assert_eq!(e[0].message, "standing for 2.5 s (frames 40-89)");
/// ```
pub fn standing_events(
    stationary: &[(u32, u32)],
    steps: &[u64],
    settings: &Settings,
    dt: f64,
) -> Vec<PlacedEvent> {
    let (Some(&first), Some(&last)) = (steps.first(), steps.last()) else {
        return Vec::new();
    };
    standing_events_by(
        stationary,
        |i| steps.get(i).copied(),
        first,
        last,
        settings,
        dt,
    )
}

/// [`standing_events`] with the steps given by `step_at` (frame index → step, `None` past the
/// last frame) and the route's `first` and `last` steps: a drive scored as it streams keeps
/// only the steps at the stretches' ends ([`crate::pipeline::motion::MotionMeter::finish`]).
pub fn standing_events_by(
    stationary: &[(u32, u32)],
    step_at: impl Fn(usize) -> Option<u64>,
    first: u64,
    last: u64,
    settings: &Settings,
    dt: f64,
) -> Vec<PlacedEvent> {
    stationary
        .iter()
        .filter_map(|&(a, b)| {
            let start = step_at(a as usize)?;
            let end = step_at(b as usize).unwrap_or(last);
            let duration = (end - start) as f64 * dt;
            (duration >= settings.events.min_standing).then(|| PlacedEvent {
                kind: "stationary",
                list: None,
                message: format!("standing for {duration:.1} s (frames {a}-{})", b - 1),
                location: None,
                frame: Some(a as usize),
                step: Some(start),
                time_s: Some((start - first) as f64 * dt),
                end_frame: Some(b as usize),
                placed_by: Some(PlacedBy::Motion),
                distance_m: None,
                reach: Reach::None,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inf(lists: &[(&str, &[&str])]) -> Infractions {
        Infractions::of(lists)
    }

    /// 100 frames along x at 0.5 m per step, the car standing at x = 30 for frames 60..80.
    fn drive() -> (Vec<u64>, Vec<[f64; 2]>) {
        let steps: Vec<u64> = (0..100).collect();
        let locations = (0..100)
            .map(|i: u32| [0.5 * f64::from(i.min(60) + i.saturating_sub(80)), 0.0])
            .collect();
        (steps, locations)
    }

    #[test]
    fn each_list_by_its_own_rule() {
        let (steps, locations) = drive();
        let mut e = infraction_events(&inf(&[
            ("collisions_vehicle", &["Agent collided against object with type=vehicle.a and id=1 at (x=1.0, y=0.0, z=0.0)"]),
            ("red_light", &["Agent ran a red light 3 at (x=10.2, y=7.5, z=1.0)", "Agent ran a red light 4 at (x=10.0, y=35.0, z=1.0)"]),
            ("stop_infraction", &["Agent ran a stop with id=5 at (x=35.0, y=-4.0, z=0.0)"]),
            ("vehicle_blocked", &["Agent got blocked at (x=30.0, y=0.0, z=0.0)", "Agent got blocked at (x=30.0, y=3.0, z=0.0)"]),
            ("outside_route_lanes", &["Agent went outside its route lanes for about 2.0 meters (1.64% of the completed route)"]),
            ("min_speed_infractions", &["Average speed is 50% of the surrounding traffic's one", "Average speed is 100.0% of the surrounding traffic's one", "Average speed is fast"]),
        ]));
        place(&mut e, &steps, &locations, None, &Settings::default(), 0.05);
        let got: Vec<(&str, Option<usize>, Option<PlacedBy>)> =
            e.iter().map(|e| (e.kind, e.frame, e.placed_by)).collect();
        use PlacedBy::*;
        assert_eq!(
            got,
            [
                // 7.5 m beside the road at x = 10.2: frame 20 (x = 10.0) is closest.
                ("red_light", Some(20), Some(ClosestApproach)),
                // 35 m away: beyond the 30 m reach.
                ("red_light", None, None),
                ("stop_sign", Some(90), Some(ClosestApproach)),
                ("outside_lanes", None, None),
                ("min_speed", None, None),
                // A min-speed entry without a number is kept (unplaced, never dropped).
                ("min_speed", None, None),
                // Standing at x = 30 from frame 60: ties go to the earliest.
                ("blocked", Some(60), Some(Nearest)),
                // 3 m from the ego's track: not the ego's position.
                ("blocked", None, None),
            ]
        );
        assert!((e[0].distance_m.unwrap() - 0.2f64.hypot(7.5)).abs() < 1e-12);
        assert_eq!(e[0].time_s, Some(1.0));
        assert_eq!(e[2].distance_m, Some(4.0));
    }

    #[test]
    fn infractions_json_places_any_list_and_reach_is_a_setting() {
        let (steps, locations) = drive();
        let msg = "Agent went outside its route lanes for about 2.0 meters (1.64% of the completed route)";
        let mut e = infraction_events(&inf(&[
            ("outside_route_lanes", &[msg]),
            (
                "red_light",
                &["Agent ran a red light 4 at (x=10.0, y=35.0, z=1.0)"],
            ),
        ]));
        let entries = [StepInfraction {
            step: 42,
            message: msg.into(),
        }];
        let mut settings = Settings::default();
        settings.set("events.signal_reach", "40").unwrap();
        // The record's list order: red_light before outside_route_lanes.
        place(&mut e, &steps, &locations, Some(&entries), &settings, 0.05);
        assert_eq!(
            (e[1].frame, e[1].placed_by),
            (Some(42), Some(PlacedBy::InfractionsJson))
        );
        assert_eq!(e[1].distance_m, None);
        assert_eq!(
            (e[0].frame, e[0].placed_by),
            (Some(20), Some(PlacedBy::ClosestApproach))
        );
    }

    #[test]
    fn no_frames_places_nothing() {
        let mut e = infraction_events(&inf(&[(
            "red_light",
            &["Agent ran a red light 3 at (x=10.2, y=7.5, z=1.0)"],
        )]));
        place(&mut e, &[], &[], None, &Settings::default(), 0.05);
        assert_eq!((e[0].frame, e[0].step, e[0].time_s), (None, None, None));
        assert!(standing_events(&[(0, 5)], &[], &Settings::default(), 0.05).is_empty());
    }

    #[test]
    fn a_stretch_to_the_end_lasts_to_the_last_frame() {
        let steps: Vec<u64> = (0..100).collect();
        let e = standing_events(&[(60, 100)], &steps, &Settings::default(), 0.1);
        assert_eq!(e[0].end_frame, Some(100));
        assert_eq!(e[0].message, "standing for 3.9 s (frames 60-99)");
    }
}
