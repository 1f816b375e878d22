//! `sds frames`' output (JSON lines): per frame, the core's frame (serde-json-core, what the
//! firmware and `monitor_core::json::decode_frame` read; unknown keys are ignored there) with
//! one more key, `host`: the step, the step period, the lateral reference, and, where the
//! lateral error is known, the distance to the reference (`lat_err`, m, f64), the slack and the
//! lane width behind the core's value. `sds score --tables` writes the same values as the rows
//! of `frames.csv` ([`super::long_tables`]).

use crate::model::frames::RouteFrames;

/// The frames of one route as JSON lines, one object per frame, each ending in `\n`.
///
/// # Errors
/// A frame the core's encoder cannot write (it needs more than 512 bytes), named by its step.
///
/// ```
/// use monitor_host::{demo, report::frames::frame_lines, route_frames, Inputs, Settings};
/// let dir = std::env::temp_dir().join(format!("sds-frames-doc-{}", std::process::id()));
/// let run = demo::write(&dir).unwrap();
/// let inputs = Inputs { telemetry: Some(run.telemetry.clone()), ..Inputs::new([run.results.clone()]) };
/// let frames = route_frames(&inputs, "RouteScenario_900001_rep0", &Settings::default()).unwrap();
/// let text = String::from_utf8(frame_lines(&frames).unwrap()).unwrap();
/// assert_eq!(text.lines().count(), frames.frames.len());
/// assert!(text.starts_with("{\"a_lon\":"));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn frame_lines(run: &RouteFrames) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut buf = [0u8; 512];
    for (k, f) in run.frames.iter().enumerate() {
        let n = monitor_core::json::encode(f, &mut buf).map_err(|e| {
            format!(
                "cannot encode the frame at step {}: {e}",
                run.steps.get(k).copied().unwrap_or_default()
            )
        })?;
        // The core's object without its closing brace, then `,"host":{...}}`.
        out.extend_from_slice(&buf[..n.saturating_sub(1)]);
        let mut host = serde_json::json!({
            "step": run.steps.get(k),
            "dt": crate::settings::decimal(run.dt),
            "reference": run.reference.name(),
        });
        if let Some(Some(s)) = run.lateral.get(k) {
            host["lat_err"] = s.lat_err.into();
            host["slack"] = s.slack.into();
            host["lane_width"] = s.lane_width.map(|w| w.width).into();
            host["lane_width_from"] = s
                .lane_width
                .map(|w| if w.from_map { "map" } else { "setting" })
                .into();
        }
        out.extend_from_slice(b",\"host\":");
        serde_json::to_writer(&mut out, &host).map_err(|e| e.to_string())?;
        out.extend_from_slice(b"}\n");
    }
    Ok(out)
}
