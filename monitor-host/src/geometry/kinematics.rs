//! Kinematics of the ego from its telemetry, in f64 (docs/SCORE.md §3): the per-frame
//! speed from displacement. The yaw-rate unit of the comfort terms is
//! [`monitor_core::Profile::comfort_yaw_rate`], shared with the core.

use crate::input::metric_info::TelemetryFrame;

/// Per-frame speed (docs/SCORE.md §3): `speed_0 = 0`,
/// `speed_i = |loc_i - loc_{i-1}| / (dt * (step_i - step_{i-1}))`, 2-D, in f64.
///
/// The distance is `sqrt(dx² + dy²)` (IEEE-exact operations, so every platform agrees). Frames
/// must be sorted by strictly increasing step, as
/// [`crate::input::metric_info::parse_metric_info`] returns them.
///
/// ```
/// use monitor_host::geometry::kinematics::speeds;
/// use monitor_host::input::metric_info::TelemetryFrame;
/// let f = |step, x| TelemetryFrame { step, location: [x, 0.0], ..Default::default() };
/// assert_eq!(speeds(&[f(1, 0.0), f(2, 1.0), f(4, 3.0)], 0.05), vec![0.0, 20.0, 20.0]);
/// ```
pub fn speeds(frames: &[TelemetryFrame], dt: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(frames.len());
    let mut prev = None;
    for f in frames {
        out.push(speed_after(prev, f, dt));
        prev = Some(f);
    }
    out
}

/// The speed at frame `cur` given the frame before it (`None` for a route's first frame, whose
/// speed is 0): the one formula behind [`speeds`] and the streaming
/// [`crate::pipeline::frame::FrameBuilder`].
///
/// ```
/// use monitor_host::geometry::kinematics::speed_after;
/// use monitor_host::input::metric_info::TelemetryFrame;
/// let a = TelemetryFrame { step: 3, location: [0.0, 0.0], ..Default::default() };
/// let b = TelemetryFrame { step: 4, location: [3.0, 4.0], ..Default::default() };
/// assert_eq!(speed_after(None, &a, 0.05), 0.0);
/// assert_eq!(speed_after(Some(&a), &b, 0.05), 100.0);
/// ```
pub fn speed_after(prev: Option<&TelemetryFrame>, cur: &TelemetryFrame, dt: f64) -> f64 {
    let Some(prev) = prev else {
        return 0.0;
    };
    let dx = cur.location[0] - prev.location[0];
    let dy = cur.location[1] - prev.location[1];
    let steps = cur.step.saturating_sub(prev.step) as f64;
    (dx * dx + dy * dy).sqrt() / (dt * steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speeds_from_displacement() {
        let f = |step, x: f64, y: f64| TelemetryFrame {
            step,
            location: [x, y],
            ..Default::default()
        };
        // 3-4-5 triangle: 5 m in one step of 0.05 s = 100 m/s; then 5 m over 2 steps = 50 m/s.
        let v = speeds(&[f(10, 0.0, 0.0), f(11, 3.0, 4.0), f(13, 6.0, 8.0)], 0.05);
        assert_eq!(v[0], 0.0);
        assert!((v[1] - 100.0).abs() < 1e-9, "{v:?}");
        assert!((v[2] - 50.0).abs() < 1e-9, "{v:?}");
        assert!(speeds(&[], 0.05).is_empty());
        assert_eq!(speeds(&[f(1, 5.0, 5.0)], 0.05), vec![0.0]);
    }
}
