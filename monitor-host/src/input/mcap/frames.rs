//! The frame rule of vehicle logs (spec v1.5 §16): ticks at a fixed period from the first pose,
//! each signal taking its latest message at or before the tick (zero-order hold), never across a
//! gap (poses more than `mcap.max_hold` apart: the log is cut into segments there); forward and
//! right from the yaw; the body-frame acceleration rotated into the world frame, so that §2's
//! dot products give it back; the yaw rate positive turning right, as telemetry's.

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

/// The world-frame motion from the odometry twist: differences of the twist rotated into the
/// world frame between consecutive poses (the first pose of a segment takes its second's), and
/// its yaw rate. No difference reaches across a gap (two poses more than `max_hold_ns` apart).
pub fn twist_motion(poses: &[PoseSample], max_hold_ns: u64) -> Vec<MotionSample> {
    let world_v = |p: &PoseSample| {
        let [vx, vy, _] = p.twist.unwrap_or_default();
        let (s, c) = p.yaw.sin_cos();
        [vx * c - vy * s, vx * s + vy * c]
    };
    let near = |a: &PoseSample, b: &PoseSample| b.t - a.t <= max_hold_ns;
    let mut out: Vec<MotionSample> = Vec::with_capacity(poses.len());
    for (i, p) in poses.iter().enumerate() {
        let before = i.checked_sub(1).map(|j| &poses[j]).filter(|a| near(a, p));
        let after = poses.get(i + 1).filter(|b| near(p, b));
        let acc = match (before, after) {
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

/// The frames of a log, with the tick time (ns) of each frame and the log's segments.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Framed {
    /// The frames (step = tick index), `gaps` the ticks missing inside gaps, `segments` the
    /// index of each segment's first frame.
    pub telemetry: Telemetry,
    /// Tick time (ns) of each frame.
    pub times: Vec<u64>,
    /// The gaps between pose messages longer than the hold: (last pose before, first after), ns.
    pub gaps: Vec<(u64, u64)>,
}

/// The frames of a log (spec v1.5 §16): tick `k` at `t0 + k * dt_ns` for `t0` the first pose's
/// time, step number `k`, each signal taking its latest message at or before the tick. Two
/// consecutive poses more than `max_hold_ns` apart make a gap: no tick inside it, nothing held
/// across it, the frames after it a new segment. A tick whose motion message is missing, older
/// than `max_hold_ns` or from before its segment's first pose is not made either, and the frames
/// after it start a new segment too. Only the ticks of segments are visited: a gap of years
/// costs nothing.
///
/// Both inputs are sorted by time (stable: of two messages with one time, the later in the file
/// wins).
///
/// # Errors
/// [`TelemetryError::Field`] naming the tick of a value that is not finite (or overflows f32);
/// [`TelemetryError::NoFrames`] when no tick has every signal.
pub fn frames(
    poses: &[PoseSample],
    motion: &[MotionSample],
    dt_ns: u64,
    max_hold_ns: u64,
) -> Result<Framed, TelemetryError> {
    let Some(first) = poses.first() else {
        return Err(TelemetryError::NoFrames);
    };
    let dt_ns = dt_ns.max(1);
    let t0 = first.t;
    let mut out = Framed::default();
    let (mut frames, mut segments, mut times) = (Vec::new(), Vec::new(), Vec::new());
    let mut im = 0usize;
    let mut a = 0usize;
    while a < poses.len() {
        // The pose segment [a, b): consecutive poses at most max_hold_ns apart.
        let mut b = a + 1;
        while b < poses.len() && poses[b].t - poses[b - 1].t <= max_hold_ns {
            b += 1;
        }
        if b < poses.len() {
            out.gaps.push((poses[b - 1].t, poses[b].t));
        }
        let (start, end) = (poses[a].t, poses[b - 1].t);
        let mut ip = a;
        let mut fresh = true;
        for k in (start - t0).div_ceil(dt_ns)..=(end - t0) / dt_ns {
            let t = t0 + k * dt_ns;
            while ip + 1 < b && poses[ip + 1].t <= t {
                ip += 1;
            }
            while im < motion.len() && motion[im].t <= t {
                im += 1;
            }
            let p = &poses[ip];
            let m = im
                .checked_sub(1)
                .map(|j| &motion[j])
                .filter(|m| m.t >= start && t - m.t <= max_hold_ns);
            let Some(m) = m else {
                fresh = true;
                continue;
            };
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
            // The frames' yaw rate is positive turning right, as telemetry's (CARLA's z points
            // up in a left-handed frame); ROS's is positive turning left (REP 103).
            let raw = [
                [acc[0], acc[1], 0.0],
                [0.0, 0.0, -m.yaw_rate.to_degrees()],
                [fwd[0], fwd[1], 0.0],
                [right[0], right[1], 0.0],
                p.position,
            ];
            if fresh {
                segments.push(frames.len());
                fresh = false;
            }
            frames.push(TelemetryFrame::from_raw(k, raw)?);
            times.push(t);
        }
        a = b;
    }
    let gaps = match (frames.first(), frames.last()) {
        (Some(a), Some(b)) => b.step - a.step + 1 - frames.len() as u64,
        _ => return Err(TelemetryError::NoFrames),
    };
    out.telemetry = Telemetry {
        frames,
        gaps,
        segments,
    };
    out.times = times;
    Ok(out)
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
        let framed = frames(&poses, &motion, 50 * ms, 250 * ms).unwrap();
        let (tel, times) = (framed.telemetry, framed.times);
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
        let framed = frames(&poses, &motion, s / 20, s / 4).unwrap();
        let tel = framed.telemetry;
        // Tick 0, then nothing held across the 3 s: tick 60 starts a new segment.
        assert_eq!(tel.frames.len(), 2);
        assert_eq!(tel.gaps, 59);
        assert_eq!(tel.segments, vec![0, 1]);
        assert_eq!(framed.gaps, vec![(0, 3 * s)]);
        assert_eq!(tel.frames.last().unwrap().step, 60);
    }

    #[test]
    fn ticks_in_a_gap_of_years_are_counted_not_visited() {
        let s = 1_000_000_000u64;
        let far = (1u64 << 37) * (s / 20);
        let poses = [pose(0, 0.0), pose(far, 1.0), pose(far + s / 20, 1.0)];
        let motion = [imu(0, 0.0), imu(far, 0.0)];
        let tel = frames(&poses, &motion, s / 20, s / 4).unwrap().telemetry;
        assert_eq!(tel.frames.len(), 3);
        assert_eq!(tel.gaps, far / (s / 20) - 1);
    }

    #[test]
    fn an_imu_message_from_before_the_gap_is_not_held_into_the_next_segment() {
        let s = 1_000_000_000;
        let poses = [pose(0, 0.0), pose(s, 1.0), pose(s + s / 20, 1.0)];
        // The IMU resumes 50 ms after the pose: the segment's first tick has no motion.
        let motion = [imu(0, -55.5), imu(s + s / 20, 0.0)];
        let tel = frames(&poses, &motion, s / 20, s / 4).unwrap().telemetry;
        let acc: Vec<f32> = tel.frames.iter().map(|f| f.acc[0]).collect();
        assert_eq!(acc, vec![-55.5, 0.0]);
        assert_eq!(tel.segments, vec![0, 1]);
    }

    #[test]
    fn body_acceleration_comes_back_through_the_dot_products() {
        let mut p = pose(0, 0.0);
        p.yaw = 0.7;
        let tel = frames(&[p], &[imu(0, 2.0)], 1, 1).unwrap().telemetry;
        let f = tel.frames[0];
        let a_lon = f.acc[0] * f.fwd[0] + f.acc[1] * f.fwd[1];
        assert!((a_lon - 2.0).abs() < 1e-6);
    }
}
