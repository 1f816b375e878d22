//! Collision traces (docs/SCORE.md §14.4, the paper's Figure 2): for every aligned
//! collision at frame k, the frames from `t_k - 3 s` to `t_k + 1 s` with `t - t_k`, speed, raw
//! `a_lon` and `lat_err`, and what the verdict was drawn from (the deceleration window, frames
//! `k - decel_window .. k - 1`, and the threshold). Taken from the route's
//! [`RouteTimeline`]; the figures and CSV files are renderings of it
//! ([`crate::report::figure`], [`crate::report::trace_csv`]).

use serde::Serialize;

use crate::pipeline::outcome::CollisionEvent;
use crate::pipeline::timeline::RouteTimeline;

pub use crate::pipeline::timeline::{AFTER_S, BEFORE_S};

/// The verdict on a collision, as the figure's title names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Some frame of the window had `a_lon <= decel_threshold`.
    Decelerated,
    /// None did, and the ego was moving: penalised.
    NoDeceleration,
    /// Standing ego or the route's first frame.
    Exempt,
}

impl Verdict {
    /// The verdict of an aligned event (`None` when unaligned).
    pub fn of(e: &CollisionEvent) -> Option<Verdict> {
        match (e.exempt?, e.decelerated?) {
            (true, _) => Some(Verdict::Exempt),
            (false, true) => Some(Verdict::Decelerated),
            (false, false) => Some(Verdict::NoDeceleration),
        }
    }

    /// `decelerated`, `no deceleration` or `exempt`.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Decelerated => "decelerated",
            Verdict::NoDeceleration => "no deceleration",
            Verdict::Exempt => "exempt",
        }
    }
}

/// One frame of a trace.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TracePoint {
    /// Frame index in the route.
    pub frame: usize,
    /// `t - t_k`, s.
    pub t: f64,
    /// Speed, m/s.
    pub speed: f32,
    /// Raw longitudinal acceleration, m/s².
    pub a_lon: f32,
    /// Distance to the route reference, m; `None` when unknown.
    pub lat_err: Option<f32>,
}

/// The trace around one aligned collision.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CollisionTrace {
    /// The route.
    pub route_id: String,
    /// Index of the event among the route's collision events (names the files).
    pub event: usize,
    /// The list it came from.
    pub list: &'static str,
    /// The collided object's type (`type=` of the collision string).
    pub type_id: Option<String>,
    /// The collision frame k.
    pub frame: usize,
    /// `t_k`, s from the route's first frame.
    pub time_s: f64,
    /// Speed at impact, m/s.
    pub impact_speed: f32,
    /// The verdict.
    pub verdict: Verdict,
    /// `t - t_k` of the deceleration window's first and last frames (k - window, k - 1);
    /// `None` at the route's first frame.
    pub window: Option<(f64, f64)>,
    /// The deceleration threshold, m/s².
    pub threshold: f32,
    /// The frames from `t_k - 3 s` to `t_k + 1 s`.
    pub points: Vec<TracePoint>,
}

/// The most traces made for one route: each costs a pass over the route's frames and, under
/// `--traces`, two files (100,000 collisions in a results file kept `--traces` writing past
/// 120 s). Every collision stays in the JSON report's `collision_events` and `events`.
pub const TRACES_PER_ROUTE: usize = 100;

/// The traces of a route's aligned collisions, in event order, the first [`TRACES_PER_ROUTE`];
/// one per event (two events of one frame give two traces with the same points). `decel_window` and `threshold` are the
/// run's `decel_window` and `decel_threshold`.
///
/// ```
/// use monitor_host::route::trace::collision_traces;
/// use monitor_host::pipeline::timeline::RouteTimeline;
/// let t = RouteTimeline { dt: 0.05, ..Default::default() };
/// assert!(collision_traces("r", &t, &[], 20, -0.5).is_empty());
/// ```
pub fn collision_traces(
    route_id: &str,
    timeline: &RouteTimeline,
    events: &[CollisionEvent],
    decel_window: u16,
    threshold: f32,
) -> Vec<CollisionTrace> {
    events
        .iter()
        .enumerate()
        .filter_map(|(i, e)| {
            let k = e.frame?;
            let verdict = Verdict::of(e)?;
            let at = timeline.frame(k)?;
            // The step difference is exact, so t - t_k has a single rounding; steps may have
            // gaps: select by time, not by frame count.
            let rel = |step: u64| (step as f64 - at.step as f64) * timeline.dt;
            let points = timeline
                .kept
                .iter()
                .map(|f| (f, rel(f.step)))
                .filter(|&(_, t)| (-BEFORE_S - 1e-9..=AFTER_S + 1e-9).contains(&t))
                .map(|(f, t)| TracePoint {
                    frame: f.index,
                    t,
                    speed: f.frame.speed,
                    a_lon: f.frame.a_lon,
                    lat_err: f.frame.lat_err,
                })
                .collect();
            let first = k.saturating_sub(usize::from(decel_window));
            let window = match (
                timeline.frame(first),
                k.checked_sub(1).and_then(|p| timeline.frame(p)),
            ) {
                (Some(a), Some(b)) if k > 0 => Some((rel(a.step), rel(b.step))),
                _ => None,
            };
            Some(CollisionTrace {
                route_id: route_id.to_string(),
                event: i,
                list: e.list.name(),
                type_id: e.type_id.clone(),
                frame: k,
                time_s: timeline.time_s(at.step),
                impact_speed: at.frame.speed,
                verdict,
                window,
                threshold,
                points,
            })
        })
        .take(TRACES_PER_ROUTE)
        .collect()
}
