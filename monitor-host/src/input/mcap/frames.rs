//! The frame rule of vehicle logs (spec v1.4 §16): ticks at a fixed period from the first pose,
//! each signal taking its latest message at or before the tick (zero-order hold); forward and
//! right from the yaw; the body-frame acceleration rotated into the world frame, so that §2's
//! dot products give it back.

use crate::input::telemetry::{Telemetry, TelemetryError, TelemetryFrame};

/// One pose, decoded, at its log time (ns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseSample {
    /// Log time, ns.
    pub t: u64,
    /// Position x, y, z (m).
    pub position: [f64; 3],
    /// Yaw (rad).
    pub yaw: f64,
    /// Body twist (vx, vy m/s, yaw rate rad/s), from odometry.
    pub twist: Option<[f64; 3]>,
}

/// Acceleration and yaw rate at a log time: from the IMU (body frame), or from the odometry
/// twist's differences (already in the world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionSample {
    /// Log time, ns.
    pub t: u64,
    /// Acceleration x, y (m/s²): body frame (forward, left) from an IMU; world frame from the
    /// twist.
    pub acc: [f64; 2],
    /// Whether `acc` is in the world frame.
    pub world: bool,
    /// Yaw rate (rad/s).
    pub yaw_rate: f64,
}

/// A held signal older than this at a tick does not make a frame: the tick is a gap (a missing
/// step, as in telemetry), not a frame repeated across a recorder's pause **\[decision\]**.
pub const STALE_NS: u64 = 500_000_000;

/// The world-frame motion from the odometry twist: differences of the twist rotated into the
/// world frame between consecutive poses (the first pose takes the second's), and its yaw rate.
pub fn twist_motion(poses: &[PoseSample]) -> Vec<MotionSample> {
    let world_v = |p: &PoseSample| {
        let [vx, vy, _] = p.twist.unwrap_or_default();
        let (s, c) = p.yaw.sin_cos();
        [vx * c - vy * s, vx * s + vy * c]
    };
    let mut out: Vec<MotionSample> = Vec::with_capacity(poses.len());
    for (i, p) in poses.iter().enumerate() {
        let acc = match (i.checked_sub(1).map(|j| &poses[j]), poses.get(i + 1)) {
            (Some(a), _) if p.t > a.t => {
                let (va, vb) = (world_v(a), world_v(p));
                let h = (p.t - a.t) as f64 * 1e-9;
                [(vb[0] - va[0]) / h, (vb[1] - va[1]) / h]
            }
            // Same time as the previous pose: keep its value.
            (Some(_), _) => out.last().map_or([0.0; 2], |m| m.acc),
            (None, Some(b)) if b.t > p.t => {
                let (va, vb) = (world_v(p), world_v(b));
                let h = (b.t - p.t) as f64 * 1e-9;
                [(vb[0] - va[0]) / h, (vb[1] - va[1]) / h]
            }
            (None, _) => [0.0; 2],
        };
        out.push(MotionSample {
            t: p.t,
            acc,
            world: true,
            yaw_rate: p.twist.map_or(0.0, |w| w[2]),
        });
    }
    out
}

/// The frames of a log: tick `k` at `t0 + k * dt_ns` for `t0` the first pose's time, up to the
/// last pose; step number `k`. A tick where a signal has no message yet, or only one older than
/// [`STALE_NS`], is skipped (a gap). Returns the telemetry and each frame's tick time (ns).
///
/// Both inputs are sorted by time (stable: of two messages with one time, the later in the file
/// wins).
///
/// # Errors
/// [`TelemetryError::Field`] naming the tick of a value that is not finite (or overflows f32).
pub fn frames(
    poses: &[PoseSample],
    motion: &[MotionSample],
    dt_ns: u64,
) -> Result<(Telemetry, Vec<u64>), TelemetryError> {
    let (Some(first), Some(last)) = (poses.first(), poses.last()) else {
        return Err(TelemetryError::NoFrames);
    };
    let dt_ns = dt_ns.max(1);
    let t0 = first.t;
    let ticks = (last.t - t0) / dt_ns + 1;
    let (mut ip, mut im) = (0usize, 0usize);
    let mut out = Vec::new();
    let mut times = Vec::new();
    for k in 0..ticks {
        let t = t0 + k * dt_ns;
        while ip + 1 < poses.len() && poses[ip + 1].t <= t {
            ip += 1;
        }
        while im < motion.len() && motion[im].t <= t {
            im += 1;
        }
        let p = &poses[ip];
        let Some(m) = im.checked_sub(1).map(|j| &motion[j]) else {
            continue;
        };
        if t - p.t > STALE_NS || t - m.t > STALE_NS {
            continue;
        }
        let (s, c) = p.yaw.sin_cos();
        let fwd = [c, s];
        let left = [-s, c];
        let right = [s, -c];
        let acc = if m.world {
            m.acc
        } else {
            [
                m.acc[0] * fwd[0] + m.acc[1] * left[0],
                m.acc[0] * fwd[1] + m.acc[1] * left[1],
            ]
        };
        let raw = [
            [acc[0], acc[1], 0.0],
            [0.0, 0.0, m.yaw_rate.to_degrees()],
            [fwd[0], fwd[1], 0.0],
            [right[0], right[1], 0.0],
            p.position,
        ];
        out.push(TelemetryFrame::from_raw(k, raw)?);
        times.push(t);
    }
    let gaps = match (out.first(), out.last()) {
        (Some(a), Some(b)) => b.step - a.step + 1 - out.len() as u64,
        _ => return Err(TelemetryError::NoFrames),
    };
    Ok((Telemetry { frames: out, gaps }, times))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(t: u64, x: f64) -> PoseSample {
        PoseSample {
            t,
            position: [x, 0.0, 0.0],
            yaw: 0.0,
            twist: None,
        }
    }

    fn imu(t: u64, ax: f64) -> MotionSample {
        MotionSample {
            t,
            acc: [ax, 0.0],
            world: false,
            yaw_rate: 0.0,
        }
    }

    #[test]
    fn zero_order_hold_takes_the_latest_message_at_or_before_each_tick() {
        let ms = 1_000_000;
        let poses = [pose(0, 0.0), pose(30 * ms, 1.0), pose(100 * ms, 2.0)];
        let motion = [imu(0, 1.0), imu(50 * ms, 2.0), imu(51 * ms, 3.0)];
        let (tel, times) = frames(&poses, &motion, 50 * ms).unwrap();
        assert_eq!(times, vec![0, 50 * ms, 100 * ms]);
        let xs: Vec<f64> = tel.frames.iter().map(|f| f.location[0]).collect();
        assert_eq!(xs, vec![0.0, 1.0, 2.0]);
        let acc: Vec<f32> = tel.frames.iter().map(|f| f.acc[0]).collect();
        assert_eq!(acc, vec![1.0, 2.0, 3.0]);
        assert_eq!(tel.gaps, 0);
    }

    #[test]
    fn a_recorder_pause_is_a_gap_not_held_frames() {
        let s = 1_000_000_000;
        let poses = [pose(0, 0.0), pose(3 * s, 1.0)];
        let motion = [imu(0, 0.0), imu(3 * s, 0.0)];
        let (tel, _) = frames(&poses, &motion, s / 20).unwrap();
        // Ticks 0..=10 hold the first pose (0.5 s), 11..59 are stale, 60 is the second pose.
        assert_eq!(tel.frames.len(), 12);
        assert_eq!(tel.gaps, 49);
        assert_eq!(tel.frames.last().unwrap().step, 60);
    }

    #[test]
    fn body_acceleration_comes_back_through_the_dot_products() {
        let mut p = pose(0, 0.0);
        p.yaw = 0.7;
        let (tel, _) = frames(&[p], &[imu(0, 2.0)], 1).unwrap();
        let f = tel.frames[0];
        let a_lon = f.acc[0] * f.fwd[0] + f.acc[1] * f.fwd[1];
        assert!((a_lon - 2.0).abs() < 1e-6);
    }
}
