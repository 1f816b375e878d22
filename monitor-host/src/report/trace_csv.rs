//! A collision trace (§10.2) as CSV: one line per frame, `t - t_k` first.

use std::fmt::Write;

use crate::route::trace::CollisionTrace;

/// The CSV header.
pub const HEADER: &str = "frame,t_minus_tk_s,speed_mps,a_lon_mps2,lat_err_m";

/// The trace as CSV text (an empty `lat_err_m` cell when unknown); floats are printed as the
/// shortest decimal that reads back to the same value.
///
/// ```
/// # use monitor_host::route::trace::{CollisionTrace, TracePoint, Verdict};
/// let t = CollisionTrace { route_id: "r".into(), event: 0, list: "collisions_vehicle",
///     type_id: None, frame: 1, time_s: 0.05, impact_speed: 2.0, verdict: Verdict::Decelerated,
///     window: Some((-0.05, -0.05)), threshold: -0.5,
///     points: vec![TracePoint { frame: 1, t: 0.0, speed: 2.0, a_lon: -1.5, lat_err: None }] };
/// assert_eq!(monitor_host::report::trace_csv::csv(&t),
///     "frame,t_minus_tk_s,speed_mps,a_lon_mps2,lat_err_m\n1,0,2,-1.5,\n");
/// ```
pub fn csv(t: &CollisionTrace) -> String {
    let mut s = String::with_capacity(40 * (t.points.len() + 1));
    s.push_str(HEADER);
    s.push('\n');
    for p in &t.points {
        // Writing to a String cannot fail.
        let _ = write!(s, "{},{},{},{},", p.frame, round_t(p.t), p.speed, p.a_lon);
        if let Some(e) = p.lat_err {
            let _ = write!(s, "{e}");
        }
        s.push('\n');
    }
    s
}

/// `t - t_k` is a difference of two products of the step period: round away the binary noise
/// (1e-9 s is far below any step period).
fn round_t(t: f64) -> f64 {
    let r = (t * 1e9).round() / 1e9;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// The files of a trace: `<route_id>_collision<event>`, with `.csv` or `.svg`.
///
/// ```
/// # use monitor_host::route::trace::{CollisionTrace, Verdict};
/// # let t = CollisionTrace { route_id: "RouteScenario_7_rep0".into(), event: 2,
/// #   list: "collisions_vehicle", type_id: None, frame: 1, time_s: 0.0, impact_speed: 0.0,
/// #   verdict: Verdict::Exempt, window: None, threshold: -0.5, points: vec![] };
/// assert_eq!(monitor_host::report::trace_csv::file_stem(&t), "RouteScenario_7_rep0_collision2");
/// ```
pub fn file_stem(t: &CollisionTrace) -> String {
    let safe: String = t
        .route_id
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{safe}_collision{}", t.event)
}
