//! The frame rule of vehicle logs (docs/SCORE.md §2.4): ticks at a fixed period from the first pose,
//! each signal taking its latest message at or before the tick (zero-order hold), never across a
//! gap (poses more than `mcap.max_hold` apart: the log is cut into segments there); forward and
//! right from the yaw; the body-frame acceleration rotated into the world frame, so that §2's
//! dot products give it back; the yaw rate positive turning right, as telemetry's.

use crate::input::telemetry::{Telemetry, TelemetryError, TelemetryFrame};

/// A pose gap longer than this is said as a message far from the rest (a clock that was not
/// set, a stray stamp) **\[decision\]**: its ticks still count as gaps.
pub const FAR_NS: u64 = 3_600_000_000_000;

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

/// The world-frame motion from the odometry twist, one pose at a time (poses in time order):
/// differences of the twist rotated into the world frame between consecutive poses, and its
/// yaw rate. A pose's motion sample needs the pose after it (a segment's first pose takes its
/// second's difference), so each sample comes out one pose late, and the last one from
/// [`TwistMotion::finish`]. No difference reaches across a gap (two poses more than
/// `max_hold_ns` apart).
#[derive(Debug, Clone)]
pub struct TwistMotion {
    max_hold_ns: u64,
    /// The pose before the pending one.
    before: Option<PoseSample>,
    /// The pose whose sample waits for the next pose.
    pending: Option<PoseSample>,
    /// The last sample's acceleration.
    last: Option<[f64; 2]>,
}

impl TwistMotion {
    /// No pose yet.
    pub fn new(max_hold_ns: u64) -> Self {
        TwistMotion {
            max_hold_ns,
            before: None,
            pending: None,
            last: None,
        }
    }

    /// Takes the next pose; gives the motion sample of the pose before it.
    pub fn push(&mut self, p: PoseSample) -> Option<MotionSample> {
        let out = self.pending.map(|q| self.sample(q, Some(p)));
        self.before = self.pending.replace(p);
        out
    }

    /// The last pose's sample.
    pub fn finish(&mut self) -> Option<MotionSample> {
        let q = self.pending.take()?;
        let out = self.sample(q, None);
        self.before = Some(q);
        Some(out)
    }

    fn sample(&mut self, p: PoseSample, next: Option<PoseSample>) -> MotionSample {
        let world_v = |p: &PoseSample| {
            let [vx, vy, _] = p.twist.unwrap_or_default();
            let (s, c) = p.yaw.sin_cos();
            [vx * c - vy * s, vx * s + vy * c]
        };
        let near = |a: &PoseSample, b: &PoseSample| b.t - a.t <= self.max_hold_ns;
        let before = self.before.filter(|a| near(a, &p));
        let after = next.filter(|b| near(&p, b));
        let acc = match (before, after) {
            (Some(a), _) if p.t > a.t => {
                let (va, vb) = (world_v(&a), world_v(&p));
                let h = (p.t - a.t) as f64 * 1e-9;
                [(vb[0] - va[0]) / h, (vb[1] - va[1]) / h]
            }
            // Same time as the previous pose: keep its value.
            (Some(_), _) => self.last.unwrap_or([0.0; 2]),
            (None, Some(b)) if b.t > p.t => {
                let (va, vb) = (world_v(&p), world_v(&b));
                let h = (b.t - p.t) as f64 * 1e-9;
                [(vb[0] - va[0]) / h, (vb[1] - va[1]) / h]
            }
            (None, _) => [0.0; 2],
        };
        self.last = Some(acc);
        MotionSample {
            t: p.t,
            acc,
            world: true,
            yaw_rate: p.twist.map_or(0.0, |w| w[2]),
        }
    }
}

/// The frames of a log, with the tick time (ns) of each frame and the log's segments.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Framed {
    /// The frames (step = tick index), `gaps` the ticks missing inside gaps, `segments` the
    /// index of each segment's first frame.
    pub telemetry: Telemetry,
    /// Tick time (ns) of each frame.
    pub times: Vec<u64>,
    /// Gaps between pose messages longer than the hold.
    pub pose_gaps: u64,
}

/// The frames of a log (docs/SCORE.md §2.4): tick `k` at `t0 + k * dt_ns` for `t0` the first pose's
/// time, step number `k`, each signal taking its latest message at or before the tick. Two
/// consecutive poses more than `max_hold_ns` apart make a gap: no tick inside it, nothing held
/// across it, the frames after it a new segment. A tick whose motion message is missing, older
/// than `max_hold_ns` or from before its segment's first pose is not made either, and the frames
/// after it start a new segment too. Only the ticks of segments are visited: a gap of years
/// costs nothing.
///
/// Both inputs are sorted by time (stable: of two messages with one time, the later in the file
/// wins). The frames are made by [`Framer`], as a log streams.
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
    let mut framer = Framer::new(dt_ns, max_hold_ns);
    let mut out = Framed::default();
    let (mut frames, mut segments, mut times) = (Vec::new(), Vec::new(), Vec::new());
    let mut each = |tick: Tick| {
        if tick.new_segment {
            segments.push(frames.len());
        }
        frames.push(tick.frame);
        times.push(tick.t);
    };
    // Both streams merged by time (a pose before a motion sample of the same time).
    let mut im = 0usize;
    for p in poses {
        while im < motion.len() && motion[im].t < p.t {
            framer.push(Sample::Motion(motion[im]), &mut each)?;
            im += 1;
        }
        framer.push(Sample::Pose(*p), &mut each)?;
    }
    for m in &motion[im..] {
        framer.push(Sample::Motion(*m), &mut each)?;
    }
    let done = framer.finish(&mut each)?;
    out.pose_gaps = done.pose_gap_count;
    out.telemetry = Telemetry {
        frames,
        gaps: done.missing,
        segments,
    };
    out.times = times;
    Ok(out)
}

/// One message of a log's signals, for [`Framer`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sample {
    /// A pose.
    Pose(PoseSample),
    /// An acceleration and yaw rate.
    Motion(MotionSample),
}

impl Sample {
    /// Its log time, ns.
    pub fn t(&self) -> u64 {
        match self {
            Sample::Pose(p) => p.t,
            Sample::Motion(m) => m.t,
        }
    }
}

/// One frame made by [`Framer`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// The frame (step = tick index).
    pub frame: TelemetryFrame,
    /// Tick time, ns.
    pub t: u64,
    /// The frame starts a segment (the log's first frame included).
    pub new_segment: bool,
}

/// What [`Framer::finish`] says of the whole log.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FramerDone {
    /// Frames made.
    pub frames: u64,
    /// Ticks missing between the first frame and the last (inside gaps).
    pub missing: u64,
    /// Segments.
    pub segments: u64,
    /// Gaps between pose messages longer than the hold.
    pub pose_gap_count: u64,
    /// The gaps longer than [`FAR_NS`], whatever their number (a note each).
    pub far_gaps: Vec<(u64, u64)>,
}

/// [`frames`] as a log streams: the poses and motion samples come in one at a time, merged in
/// time order, and each tick is made as soon as what decides it has come in: its pose and
/// motion (every message before the tick's time) and, past the latest pose, whether the next
/// pose comes within `max_hold_ns` (a gap otherwise). It holds the motion samples of at most
/// `max_hold_ns` (and the latest), never the log.
#[derive(Debug, Clone)]
pub struct Framer {
    dt_ns: u64,
    hold_ns: u64,
    t0: u64,
    /// The latest pose, and its segment's first pose time.
    pose: Option<PoseSample>,
    start: u64,
    /// The next tick to decide.
    k: u64,
    /// The next frame starts a segment.
    fresh: bool,
    /// Motion samples not yet passed by the ticks (the first: the latest at or before the tick).
    motion: std::collections::VecDeque<MotionSample>,
    first_step: Option<u64>,
    last_step: u64,
    done: FramerDone,
}

impl Framer {
    /// A framer at period `dt_ns`, holding a message at most `max_hold_ns`.
    pub fn new(dt_ns: u64, max_hold_ns: u64) -> Self {
        Framer {
            dt_ns: dt_ns.max(1),
            hold_ns: max_hold_ns,
            t0: 0,
            pose: None,
            start: 0,
            k: 0,
            fresh: true,
            motion: std::collections::VecDeque::new(),
            first_step: None,
            last_step: 0,
            done: FramerDone::default(),
        }
    }

    /// Takes the next sample (time order); gives the ticks it decides to `each`.
    ///
    /// # Errors
    /// [`TelemetryError::Field`] naming the tick of a value that is not finite.
    pub fn push(&mut self, s: Sample, each: &mut impl FnMut(Tick)) -> Result<(), TelemetryError> {
        let t = s.t();
        self.ticks(Some(&s), each)?;
        match s {
            Sample::Pose(p) => {
                match self.pose {
                    None => {
                        self.t0 = p.t;
                        self.start = p.t;
                        self.k = 0;
                        self.fresh = true;
                    }
                    Some(l) if p.t - l.t > self.hold_ns => {
                        if p.t - l.t > FAR_NS {
                            self.done.far_gaps.push((l.t, p.t));
                        }
                        self.done.pose_gap_count += 1;
                        self.start = p.t;
                        self.k = (p.t - self.t0).div_ceil(self.dt_ns);
                        self.fresh = true;
                    }
                    Some(_) => {}
                }
                self.pose = Some(p);
            }
            Sample::Motion(m) => {
                // Before the first pose, or past the hold after the latest one, the ticks wait
                // for a new segment, whose ticks take only samples from its own first pose on:
                // the latest is enough.
                if self.pose.is_none_or(|l| t - l.t > self.hold_ns) {
                    self.motion.clear();
                }
                self.motion.push_back(m);
            }
        }
        Ok(())
    }

    /// The ticks left (up to the last pose), and the log's figures.
    ///
    /// # Errors
    /// As [`Framer::push`]; [`TelemetryError::NoFrames`] when no tick has every signal.
    pub fn finish(mut self, each: &mut impl FnMut(Tick)) -> Result<FramerDone, TelemetryError> {
        self.ticks(None, each)?;
        let Some(first) = self.first_step else {
            return Err(TelemetryError::NoFrames);
        };
        self.done.missing = self.last_step - first + 1 - self.done.frames;
        Ok(self.done)
    }

    /// Decides the ticks before `next`'s time (all of them up to the last pose at the end).
    fn ticks(
        &mut self,
        next: Option<&Sample>,
        each: &mut impl FnMut(Tick),
    ) -> Result<(), TelemetryError> {
        let Some(pose) = self.pose else {
            return Ok(());
        };
        loop {
            let t = self.t0 + self.k * self.dt_ns;
            if next.is_some_and(|s| t >= s.t()) {
                return Ok(());
            }
            if t > pose.t {
                // Past the latest pose: a tick of this segment only if the next pose is within
                // the hold; a motion sample within the hold does not decide it yet.
                let within = match next {
                    Some(Sample::Pose(p)) => p.t - pose.t <= self.hold_ns,
                    _ => false,
                };
                if !within {
                    return Ok(());
                }
            }
            while self.motion.len() > 1 && self.motion[1].t <= t {
                self.motion.pop_front();
            }
            let m = self
                .motion
                .front()
                .filter(|m| m.t <= t && m.t >= self.start && t - m.t <= self.hold_ns)
                .copied();
            let k = self.k;
            self.k += 1;
            let Some(m) = m else {
                self.fresh = true;
                continue;
            };
            let (s, c) = pose.yaw.sin_cos();
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
                pose.position,
            ];
            let frame = TelemetryFrame::from_raw(k, raw)?;
            let new_segment = std::mem::take(&mut self.fresh);
            self.first_step.get_or_insert(k);
            self.last_step = k;
            self.done.frames += 1;
            self.done.segments += u64::from(new_segment);
            each(Tick {
                frame,
                t,
                new_segment,
            });
        }
    }
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
        assert_eq!(framed.pose_gaps, 1);
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
