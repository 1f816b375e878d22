//! A collision trace (docs/SCORE.md §14.4) as CSV: one line per frame, `t - t_k` first.

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
    // At most STEM_ID_CHARS of the id: a file name has at most 255 bytes.
    let safe: String = t
        .route_id
        .chars()
        .take(STEM_ID_CHARS)
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

/// How many characters of a route id a trace's file name keeps.
pub const STEM_ID_CHARS: usize = 150;

/// The file stems of `traces` (each with its route's index in the report), unique: the
/// [`file_stem`] when no other trace has it (compared without case, for case-insensitive file
/// systems), else with `_route<index>` before `_collision` (ids that differ only in replaced
/// characters or beyond [`STEM_ID_CHARS`], copies under `--duplicates all`), numbered on if
/// still taken. Deterministic: the same report gives the same names.
///
/// ```
/// # use monitor_host::route::trace::{CollisionTrace, Verdict};
/// # let t = |id: &str| CollisionTrace { route_id: id.into(), event: 0,
/// #   list: "collisions_vehicle", type_id: None, frame: 1, time_s: 0.0, impact_speed: 0.0,
/// #   verdict: Verdict::Exempt, window: None, threshold: -0.5, points: vec![] };
/// use monitor_host::report::trace_csv::unique_stems;
/// let (a, b, c) = (t("R_1"), t("R/1"), t("R_2"));
/// assert_eq!(unique_stems(&[(0, &a), (1, &b), (2, &c)]),
///            ["R_1_route0_collision0", "R_1_route1_collision0", "R_2_collision0"]);
/// ```
pub fn unique_stems(traces: &[(usize, &CollisionTrace)]) -> Vec<String> {
    use std::collections::{HashMap, HashSet};
    let plain: Vec<String> = traces.iter().map(|(_, t)| file_stem(t)).collect();
    let mut count: HashMap<String, usize> = HashMap::new();
    for s in &plain {
        *count.entry(s.to_lowercase()).or_default() += 1;
    }
    let mut taken: HashSet<String> = HashSet::new();
    let mut out = Vec::with_capacity(plain.len());
    for ((route, t), stem) in traces.iter().zip(plain) {
        let mut name = stem.clone();
        if count[&stem.to_lowercase()] > 1 || taken.contains(&name.to_lowercase()) {
            let cut = stem.len() - format!("_collision{}", t.event).len();
            name = format!("{}_route{route}{}", &stem[..cut], &stem[cut..]);
            let mut k = 1;
            while taken.contains(&name.to_lowercase()) {
                name = format!("{}_route{route}_{k}{}", &stem[..cut], &stem[cut..]);
                k += 1;
            }
        }
        taken.insert(name.to_lowercase());
        out.push(name);
    }
    out
}
