//! Helpers shared by the feature modules: a route run through the monitor, frames, verdicts.

use monitor_core::{Config, Event, Finished, Frame, Monitor};

/// Every event of a route (pushes then finish), plus the finish result.
pub fn run(config: Config, frames: &[Frame]) -> (Vec<Event>, Finished) {
    let mut m: Monitor = Monitor::new(config).expect("valid config");
    let mut events = Vec::new();
    for f in frames {
        events.extend(m.push(f).expect("valid frame").iter().copied());
    }
    let done = m.finish().expect("first finish");
    events.extend(done.events.iter().copied());
    (events, done)
}

/// A cruising frame: 5 m/s, nothing else.
pub fn cruise() -> Frame {
    Frame {
        speed: 5.0,
        ..Frame::default()
    }
}

/// The comfort verdicts of a route's events, in order.
pub fn comfort_verdicts(events: &[Event]) -> Vec<monitor_core::ComfortVerdict> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Comfort(v) => Some(*v),
            _ => None,
        })
        .collect()
}

/// The lateral verdicts of a route's events, in order.
pub fn lateral_verdicts(events: &[Event]) -> Vec<monitor_core::LateralVerdict> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Lateral(v) => Some(*v),
            _ => None,
        })
        .collect()
}

/// The collision verdicts of a route's events, in order.
pub fn collision_verdicts(events: &[Event]) -> Vec<monitor_core::CollisionVerdict> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Collision(v) => Some(*v),
            _ => None,
        })
        .collect()
}
