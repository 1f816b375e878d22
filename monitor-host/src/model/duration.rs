//! Durations as people read them in status lines and warnings.

/// Seconds as a short duration: `42m`, `3h05m` (rounded to the minute).
///
/// ```
/// assert_eq!(monitor_host::model::duration::duration_text(3900.0), "1h05m");
/// assert_eq!(monitor_host::model::duration::duration_text(150.0), "2m");
/// ```
pub fn duration_text(secs: f64) -> String {
    let s = secs.clamp(0.0, 1e12).round() as u64;
    match (s / 3600, (s % 3600) / 60) {
        (0, m) => format!("{m}m"),
        (h, m) => format!("{h}h{m:02}m"),
    }
}
