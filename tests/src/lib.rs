//! Shared helpers of the test suite.
//!
//! - [`stream`] runs a route through the streaming [`Monitor`] and keeps every event, so a test
//!   can compare it with the batch reference (`monitor_host::reference::batch`).
//! - [`SPECIAL_VALUES`] lists the f32 values a property test should hit on purpose: zeros,
//!   subnormals, huge values, values on and next to the comfort bounds.
//!
//! (proptest is a dev-dependency of this crate, so its strategies live in the test files.)
#![deny(missing_docs)]

use monitor_core::{
    CollisionVerdict, ComfortVerdict, Config, ConfigError, Event, Frame, LateralVerdict, Monitor,
    MonitorError, RouteSummary,
};

/// Everything the streaming monitor reported for one route.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Streamed {
    /// The summary returned by [`Monitor::finish`].
    pub summary: RouteSummary,
    /// Every [`Event::Collision`], in order.
    pub collisions: Vec<CollisionVerdict>,
    /// Every [`Event::Comfort`], in order (including the short route's, from `finish`).
    pub comfort: Vec<ComfortVerdict>,
    /// Every [`Event::Lateral`], in order (including the trailing chunk's, from `finish`).
    pub lateral: Vec<LateralVerdict>,
}

impl Streamed {
    /// Files one event under its kind.
    pub fn record(&mut self, event: &Event) {
        match *event {
            Event::Collision(v) => self.collisions.push(v),
            Event::Comfort(v) => self.comfort.push(v),
            Event::Lateral(v) => self.lateral.push(v),
        }
    }
}

/// Why [`stream`] stopped.
#[derive(Debug, PartialEq)]
pub enum StreamError {
    /// The configuration does not fit a default monitor.
    Config(ConfigError),
    /// A frame (by index) or `finish` was refused.
    Monitor(Option<usize>, MonitorError),
}

/// Pushes every frame through a default-capacity [`Monitor`] and finishes the route.
///
/// ```
/// use monitor_core::{Config, Frame};
/// let s = sds_tests::stream(&[Frame::default(); 25], &Config::DEFAULT).unwrap();
/// assert_eq!(s.summary.frames, 25);
/// assert_eq!(s.summary.lateral.chunks, 2);
/// ```
pub fn stream(frames: &[Frame], config: &Config) -> Result<Streamed, StreamError> {
    let mut monitor: Monitor = Monitor::new(*config).map_err(StreamError::Config)?;
    let mut out = Streamed::default();
    for (i, frame) in frames.iter().enumerate() {
        let events = monitor
            .push(frame)
            .map_err(|e| StreamError::Monitor(Some(i), e))?;
        events.iter().for_each(|e| out.record(e));
    }
    let done = monitor
        .finish()
        .map_err(|e| StreamError::Monitor(None, e))?;
    done.events.iter().for_each(|e| out.record(e));
    out.summary = done.summary;
    Ok(out)
}

/// Finite f32 values worth hitting on purpose: signed zeros, subnormals, tiny and huge
/// magnitudes, `±f32::MAX` (which overflow the filter to infinity or NaN), the default comfort
/// bounds and their neighbours, and the stationary speed.
pub const SPECIAL_VALUES: &[f32] = &[
    0.0,
    -0.0,
    1e-45, // the smallest subnormal
    -1e-45,
    1.0e-40, // a subnormal
    -1.0e-40,
    f32::MIN_POSITIVE,
    1e-30,
    -1e-30,
    1e30,
    -1e30,
    1e19, // squares overflow
    -1e19,
    3.0e38,
    f32::MAX,
    -f32::MAX,
    2.39999,
    2.4,
    2.4f32.next_up(),
    2.4f32.next_down(),
    -4.05,
    (-4.05f32).next_up(),
    (-4.05f32).next_down(),
    4.89,
    -4.89,
    8.37,
    -8.37,
    4.13,
    -4.13,
    1.93,
    -1.93,
    0.95,
    -0.95,
    0.5,
    0.5f32.next_down(),
    0.5f32.next_up(),
    -0.5,
    (-0.5f32).next_down(),
    180.0,
    -180.0,
    360.0,
    6.283_185_5,
];
