//! Frame building (docs/SCORE.md §3): one telemetry frame at a time → the monitor's
//! [`Frame`]. The batch pipeline ([`crate::pipeline::prepare`]) and the streaming front ends (the
//! Python `Monitor`) build every frame here, so they agree to the bit.

use monitor_core::{Collisions, Frame};

use crate::geometry::kinematics::speed_after;
use crate::input::telemetry::TelemetryFrame;

/// Builds a route's frames in step order: signals from the raw vectors through the core's f32
/// kernels ([`Frame::from_vectors`]), speed from the previous frame's location in f64
/// ([`speed_after`]), and the lateral error rounded to f32 once.
///
/// ```
/// use monitor_core::Collisions;
/// use monitor_host::input::metric_info::TelemetryFrame;
/// use monitor_host::pipeline::frame::FrameBuilder;
///
/// let mut b = FrameBuilder::new(0.05);
/// let t = |step, x| TelemetryFrame { step, location: [x, 0.0], acc: [1.0, 2.0],
///                                   fwd: [1.0, 0.0], right: [0.0, 1.0], ..Default::default() };
/// let f0 = b.push(&t(10, 0.0), None, Collisions::NONE);
/// let f1 = b.push(&t(11, 0.5), Some(0.25), Collisions::NONE);
/// assert_eq!((f0.speed, f1.speed), (0.0, 10.0));
/// assert_eq!((f1.a_lon, f1.a_lat, f1.lat_err), (1.0, 2.0, Some(0.25)));
/// assert_eq!(b.last_step(), Some(11));
/// ```
#[derive(Clone, Debug)]
pub struct FrameBuilder {
    dt: f64,
    prev: Option<TelemetryFrame>,
}

impl FrameBuilder {
    /// A builder for a new route, with the simulator step `dt` in seconds (the setting `dt`).
    pub fn new(dt: f32) -> Self {
        FrameBuilder {
            dt: f64::from(dt),
            prev: None,
        }
    }

    /// The step of the last frame built, if any. Frames must come in strictly increasing step
    /// order (a repeated step would give an infinite speed, which the monitor refuses).
    pub fn last_step(&self) -> Option<u64> {
        self.prev.map(|p| p.step)
    }

    /// Starts a new segment (docs/SCORE.md §2.4): the next frame has no predecessor (speed 0).
    pub fn restart(&mut self) {
        self.prev = None;
    }

    /// Builds the next frame of the route.
    pub fn push(
        &mut self,
        t: &TelemetryFrame,
        lat_err: Option<f64>,
        collisions: Collisions,
    ) -> Frame {
        let speed = speed_after(self.prev.as_ref(), t, self.dt);
        self.prev = Some(*t);
        Frame::from_vectors(
            t.acc,
            t.fwd,
            t.right,
            t.yaw_rate_deg,
            speed as f32,
            lat_err.map(|e| e as f32),
            collisions,
        )
    }
}
