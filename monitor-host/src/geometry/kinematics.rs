//! Kinematics of the ego from its telemetry, in f64 (`SDS-SPEC.md` v1.2 §2): the per-frame
//! speed from displacement. The yaw-rate unit of the comfort terms is
//! [`monitor_core::Profile::comfort_yaw_rate`], shared with the core.

use crate::input::metric_info::TelemetryFrame;

/// Per-frame speed (`SDS-SPEC.md` §2): `speed_0 = 0`,
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
    if frames.is_empty() {
        return out;
    }
    out.push(0.0);
    for w in frames.windows(2) {
        let dx = w[1].location[0] - w[0].location[0];
        let dy = w[1].location[1] - w[0].location[1];
        let steps = w[1].step.saturating_sub(w[0].step) as f64;
        out.push((dx * dx + dy * dy).sqrt() / (dt * steps));
    }
    out
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
