//! A route's timeline: the frames the monitor saw, their steps and period, and the per-chunk
//! verdicts it emitted as it went (comfort: which bounds each chunk failed; lateral: which chunks
//! were anomalous or critical). The report's collision traces (docs/SCORE.md §14.4) and the HTML report's
//! timelines are drawn from it; nothing here is recomputed, only kept.

use monitor_core::{ComfortVerdict, Event, Events, Frame, LateralVerdict};

/// The monitor's per-chunk events of one route, in the order it emitted them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChunkLog {
    /// One verdict per comfort chunk (comfortable ones included).
    pub comfort: Vec<ComfortVerdict>,
    /// The anomalous and critical lateral chunks.
    pub lateral: Vec<LateralVerdict>,
}

impl ChunkLog {
    /// Keeps the chunk events of one `push` or `finish`.
    ///
    /// ```
    /// let mut log = monitor_host::pipeline::timeline::ChunkLog::default();
    /// log.record(&monitor_core::Events::new());
    /// assert!(log.comfort.is_empty() && log.lateral.is_empty());
    /// ```
    pub fn record(&mut self, events: &Events) {
        for e in events {
            match e {
                Event::Comfort(c) => self.comfort.push(*c),
                Event::Lateral(l) => self.lateral.push(*l),
                Event::Collision(_) => {}
            }
        }
    }
}

/// Seconds of trace kept before a collision (docs/SCORE.md §14.4).
pub const BEFORE_S: f64 = 3.0;
/// Seconds of trace kept after a collision (docs/SCORE.md §14.4).
pub const AFTER_S: f64 = 1.0;

/// One frame kept for the collision traces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeptFrame {
    /// Index of the frame in the route.
    pub index: usize,
    /// Its step number.
    pub step: u64,
    /// The frame.
    pub frame: Frame,
}

/// What the monitor saw of a route around its collisions, and what it said per chunk. Only the
/// frames a collision trace needs are kept (those within `BEFORE_S` before to `AFTER_S` after an
/// aligned collision, and its deceleration window), so that a run's memory does not grow with
/// its routes' length.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RouteTimeline {
    /// The kept frames, in index order.
    pub kept: Vec<KeptFrame>,
    /// The route's first step.
    pub first_step: u64,
    /// The route's step period, s.
    pub dt: f64,
    /// The per-chunk verdicts.
    pub chunks: ChunkLog,
    /// The step of each chunk's first frame (chunk `c` starts at frame `c × chunk_len`), for the
    /// route's `events` (filled by the replay).
    pub chunk_steps: Vec<u64>,
    /// The index of each chunk's first frame, when it is not `c × chunk_len` (a vehicle log's
    /// segments, docs/SCORE.md §2.4); empty otherwise.
    pub chunk_frames: Vec<usize>,
}

impl RouteTimeline {
    /// Keeps the frames around the collision frames `at` (indices into `frames`), the
    /// `decel_window` frames before each included.
    ///
    /// ```
    /// use monitor_host::pipeline::timeline::{ChunkLog, RouteTimeline};
    /// let frames = vec![monitor_core::Frame::default(); 500];
    /// let steps: Vec<u64> = (0..500).collect();
    /// let t = RouteTimeline::around(&frames, &steps, 0.05, &[100], 20, ChunkLog::default());
    /// assert_eq!(t.kept.first().map(|k| k.index), Some(40));  // 3 s before
    /// assert_eq!(t.kept.last().map(|k| k.index), Some(120));  // 1 s after
    /// ```
    pub fn around(
        frames: &[Frame],
        steps: &[u64],
        dt: f64,
        at: &[usize],
        decel_window: u16,
        chunks: ChunkLog,
    ) -> RouteTimeline {
        let first_step = steps.first().copied().unwrap_or(0);
        let rel = |j: usize, k: usize| (steps[j] as f64 - steps[k] as f64) * dt;
        let n = frames.len().min(steps.len());
        let mut keep = vec![false; n];
        for &k in at.iter().filter(|&&k| k < n) {
            let from = k.saturating_sub(usize::from(decel_window));
            for (j, flag) in keep.iter_mut().enumerate() {
                let t = rel(j, k);
                if (from..=k).contains(&j) || (-BEFORE_S - 1e-9..=AFTER_S + 1e-9).contains(&t) {
                    *flag = true;
                }
            }
        }
        let kept = keep
            .iter()
            .enumerate()
            .filter(|(_, &k)| k)
            .map(|(index, _)| KeptFrame {
                index,
                step: steps[index],
                frame: frames[index],
            })
            .collect();
        RouteTimeline {
            kept,
            first_step,
            dt,
            chunks,
            chunk_steps: Vec::new(),
            chunk_frames: Vec::new(),
        }
    }

    /// The kept frame of index `k`.
    pub fn frame(&self, k: usize) -> Option<&KeptFrame> {
        self.kept
            .binary_search_by_key(&k, |f| f.index)
            .ok()
            .map(|i| &self.kept[i])
    }

    /// Seconds from the route's first frame to a step: `(step - first_step) * dt`.
    ///
    /// ```
    /// use monitor_host::pipeline::timeline::RouteTimeline;
    /// let t = RouteTimeline { first_step: 10, dt: 0.05, ..Default::default() };
    /// assert!((t.time_s(13) - 0.15).abs() < 1e-12);
    /// ```
    pub fn time_s(&self, step: u64) -> f64 {
        step.saturating_sub(self.first_step) as f64 * self.dt
    }
}

/// [`RouteTimeline::around`] as a long drive streams (issue 51): the frames come one at a time,
/// each said to be a collision frame or not, and only those a collision trace needs are kept;
/// between collisions it holds the last `BEFORE_S` seconds (and `decel_window` frames), never
/// the drive.
///
/// ```
/// use monitor_host::pipeline::timeline::{ChunkLog, RouteTimeline, TimelineKeeper};
/// let frames = vec![monitor_core::Frame::default(); 500];
/// let steps: Vec<u64> = (0..500).collect();
/// let mut keeper = TimelineKeeper::new(0.05, 20);
/// for (i, f) in frames.iter().enumerate() {
///     keeper.push(i, steps[i], *f, i == 100);
/// }
/// let whole = RouteTimeline::around(&frames, &steps, 0.05, &[100], 20, ChunkLog::default());
/// assert_eq!(keeper.finish(ChunkLog::default()), whole);
/// ```
#[derive(Clone, Debug)]
pub struct TimelineKeeper {
    dt: f64,
    decel_window: usize,
    first_step: Option<u64>,
    /// Recent frames, each flagged when a collision's trace takes it.
    recent: std::collections::VecDeque<(KeptFrame, bool)>,
    /// Collision frames (index, step) whose trace may still take frames after them.
    open: Vec<(usize, u64)>,
    kept: Vec<KeptFrame>,
}

impl TimelineKeeper {
    /// A keeper for a route of step period `dt` (s) and the deceleration window.
    pub fn new(dt: f64, decel_window: u16) -> Self {
        TimelineKeeper {
            dt,
            decel_window: usize::from(decel_window),
            first_step: None,
            recent: std::collections::VecDeque::new(),
            open: Vec::new(),
            kept: Vec::new(),
        }
    }

    /// The next frame (index order); `collision`: an aligned collision falls on it.
    pub fn push(&mut self, index: usize, step: u64, frame: Frame, collision: bool) {
        let dt = self.dt;
        // The expression of `around`, to the bit.
        let within = move |j: u64, k: u64| {
            let t = (j as f64 - k as f64) * dt;
            (-BEFORE_S - 1e-9..=AFTER_S + 1e-9).contains(&t)
        };
        self.first_step.get_or_insert(step);
        let after = self.open.iter().any(|&(_, k)| within(step, k));
        self.recent
            .push_back((KeptFrame { index, step, frame }, after));
        if collision {
            let from = index.saturating_sub(self.decel_window);
            for (f, flag) in &mut self.recent {
                if (from..=index).contains(&f.index) || within(f.step, step) {
                    *flag = true;
                }
            }
            self.open.push((index, step));
        }
        // A collision's trace ends AFTER_S after it; a frame further back than BEFORE_S and the
        // deceleration window is taken by no later collision.
        self.open.retain(|&(_, k)| within(step, k) || step < k);
        while let Some((f, _)) = self.recent.front() {
            let gone = f.index + self.decel_window <= index
                && (f.step as f64 - step as f64) * dt < -BEFORE_S - 1e-9;
            if !gone {
                break;
            }
            if let Some((f, true)) = self.recent.pop_front() {
                self.kept.push(f);
            }
        }
    }

    /// The timeline, with the monitor's chunk verdicts.
    pub fn finish(mut self, chunks: ChunkLog) -> RouteTimeline {
        for (f, flag) in self.recent.drain(..) {
            if flag {
                self.kept.push(f);
            }
        }
        RouteTimeline {
            kept: self.kept,
            first_step: self.first_step.unwrap_or(0),
            dt: self.dt,
            chunks,
            chunk_steps: Vec::new(),
            chunk_frames: Vec::new(),
        }
    }
}
