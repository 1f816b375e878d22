//! A route's timeline: the frames the monitor saw, their steps and period, and the per-chunk
//! verdicts it emitted as it went (comfort: which bounds each chunk failed; lateral: which chunks
//! were anomalous or critical). The report's collision traces (§10.2) and the HTML report's
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

/// What the monitor saw of a route and what it said per chunk.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RouteTimeline {
    /// The frames, in step order.
    pub frames: Vec<Frame>,
    /// Step number of each frame.
    pub steps: Vec<u64>,
    /// The route's step period, s.
    pub dt: f64,
    /// The per-chunk verdicts.
    pub chunks: ChunkLog,
}

impl RouteTimeline {
    /// Seconds from the route's first frame to frame `k`: `(step - first_step) * dt`.
    ///
    /// ```
    /// use monitor_host::pipeline::timeline::RouteTimeline;
    /// let t = RouteTimeline { steps: vec![10, 11, 13], dt: 0.05, ..Default::default() };
    /// assert!((t.time_s(2) - 0.15).abs() < 1e-12);
    /// ```
    pub fn time_s(&self, k: usize) -> f64 {
        let first = self.steps.first().copied().unwrap_or(0);
        self.steps
            .get(k)
            .map_or(0.0, |s| (s.saturating_sub(first)) as f64 * self.dt)
    }
}
