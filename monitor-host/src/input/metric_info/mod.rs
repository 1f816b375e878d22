//! Bench2Drive per-step telemetry (`metric_info.json`, docs/SCORE.md §2.2).
//!
//! `metric_info.json` is a JSON object whose keys are decimal step numbers and whose values hold
//! the ego's `acceleration`, `angular_velocity`, `forward_vector`, `right_vector` and `location`
//! (3-vectors; `rotation` and any other key are ignored). Real files are ~1 KB of indented JSON per
//! frame and thousands of frames per route, so nothing builds a JSON DOM or allocates per frame
//! or per key. Two paths read the same bytes: a strict scanner for the layout Bench2Drive
//! writes (about 3x the speed: it learns a frame's layout and then reads only the numbers of the
//! frames after it), and, for any input it is not sure of, a serde_json visitor,
//! which alone decides every error and its message. Both give the same frames bit for bit
//! (`tests/tests/it/metric_info_fast_path.rs`). Each frame is reduced to the 2-D parts the monitor
//! needs ([`TelemetryFrame`]).
//!
//! ```
//! use monitor_host::geometry::kinematics::speeds;
//! use monitor_host::input::metric_info::parse_metric_info;
//!
//! let json = br#"{
//!   "12": {"acceleration": [0.5, 0.0, 0.0], "angular_velocity": [0, 0, 3.0],
//!          "forward_vector": [1, 0, 0], "right_vector": [0, 1, 0],
//!          "location": [10.0, 5.0, 0.2], "rotation": [0, 0, 0]},
//!   "11": {"acceleration": [0.0, 0.0, 0.0], "angular_velocity": [0, 0, 0],
//!          "forward_vector": [1, 0, 0], "right_vector": [0, 1, 0],
//!          "location": [9.5, 5.0, 0.2]}
//! }"#;
//! let t = parse_metric_info(json)?;
//! assert_eq!(t.frames.len(), 2);
//! assert_eq!((t.frames[0].step, t.frames[1].step), (11, 12)); // sorted by step
//! assert_eq!(t.gaps, 0);
//! assert_eq!(t.frames[1].yaw_rate_deg, 3.0);
//! assert_eq!(speeds(&t.frames, 0.05), vec![0.0, 10.0]); // 0.5 m in one 0.05 s step
//!
//! let bad = parse_metric_info(br#"{"7": {"acceleration": [1, 2]}}"#).unwrap_err();
//! assert_eq!(bad.to_string(), "step 7: field acceleration: fewer than 3 numbers");
//! # Ok::<(), monitor_host::input::metric_info::TelemetryError>(())
//! ```

use std::path::Path;

use serde::de::{Deserializer, IgnoredAny};

mod float;
mod layout;
mod number;
mod scan;
mod visitor;

use visitor::{is_non_finite, json_error, Ctx, TopVisitor};

// The telemetry types are the format-neutral ones of `input::telemetry`; named here too, where
// they were first defined.
pub use crate::input::telemetry::{FieldProblem, Telemetry, TelemetryError, TelemetryFrame};

/// Reads and parses a `metric_info.json` file (see [`parse_metric_info`]).
///
/// # Errors
/// [`TelemetryError::Io`] if the file cannot be read, otherwise as [`parse_metric_info`].
pub fn read_metric_info(path: &Path) -> Result<Telemetry, TelemetryError> {
    // Held against the run's budget of bytes in flight until parsed (`read_input_held`).
    let bytes = crate::input::read::read_input_held(path, crate::input::read::FileKind::MetricInfo)
        .map_err(|source| TelemetryError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    parse_metric_info(&bytes)
}

/// Parses the bytes of a `metric_info.json` file: validates every frame (docs/SCORE.md §2.2),
/// sorts the frames by step (stable) and counts the gaps.
///
/// Never panics, on any input. Keys other than the five required vectors (`rotation`,
/// `velocity`, ...) are skipped after a syntax check only: a bare `NaN` / `Infinity` token there
/// still makes the file invalid (it is not JSON), but an overflowing literal such as `1e999`
/// there is not evaluated.
///
/// # Errors
/// Every invalid-telemetry case of the spec, as a [`TelemetryError`] whose `Display` names the
/// step and the field.
pub fn parse_metric_info(bytes: &[u8]) -> Result<Telemetry, TelemetryError> {
    // The fast path reads what it is sure of; every other input, and every error, is the
    // serde_json visitor's to decide (see `scan.rs`).
    if let Some(t) = parse_metric_info_fast(bytes) {
        return Ok(t);
    }
    parse_metric_info_serde(bytes)
}

/// The fast path alone: `Some` where it is sure of the answer, `None` where
/// [`parse_metric_info`] defers to serde_json. Public for the equivalence test
/// (`tests/tests/it/metric_info_fast_path.rs`), not for users.
#[doc(hidden)]
pub fn parse_metric_info_fast(bytes: &[u8]) -> Option<Telemetry> {
    scan::parse(bytes).and_then(|(frames, sorted)| finish(frames, sorted).ok())
}

/// [`parse_metric_info`] without the fast path: serde_json and the streaming visitor alone. The
/// reference the fast path is tested against; the results are identical by construction (see
/// the test `metric_info_fast_path`).
///
/// ```
/// use monitor_host::input::metric_info::{parse_metric_info, parse_metric_info_serde};
/// let json = br#"{"1": {"acceleration": [0, 0, 0], "angular_velocity": [0, 0, 0],
///     "forward_vector": [1, 0, 0], "right_vector": [0, 1, 0], "location": [-0, 2.5, 0]}}"#;
/// assert_eq!(parse_metric_info_serde(json)?, parse_metric_info(json)?);
/// # Ok::<(), monitor_host::input::metric_info::TelemetryError>(())
/// ```
///
/// # Errors
/// As [`parse_metric_info`].
pub fn parse_metric_info_serde(bytes: &[u8]) -> Result<Telemetry, TelemetryError> {
    let first = bytes
        .iter()
        .position(|b| !matches!(b, b' ' | b'\t' | b'\n' | b'\r'));
    if first.map(|i| bytes[i]) != Some(b'{') {
        // Not an object: tell "valid JSON of another kind" from "not JSON at all".
        return match serde_json::from_slice::<IgnoredAny>(bytes) {
            Ok(_) => Err(TelemetryError::NotObject),
            Err(e) => Err(json_error(bytes, &e, None)),
        };
    }
    let mut ctx = Ctx {
        step: None,
        field: None,
        in_array: false,
        error: None,
    };
    // About 1 KB per frame in real files; the estimate only avoids regrowth.
    let mut frames = Vec::with_capacity((bytes.len() / 700).min(1 << 20));
    let mut sorted = true;
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let parsed = de
        .deserialize_map(TopVisitor {
            ctx: &mut ctx,
            frames: &mut frames,
            sorted: &mut sorted,
        })
        .and_then(|()| de.end());
    if let Err(e) = parsed {
        if let Some(err) = ctx.error.take() {
            return Err(err);
        }
        return Err(match e.classify() {
            serde_json::error::Category::Data => match (ctx.step, ctx.field) {
                (Some(step), Some(field)) => TelemetryError::Field {
                    step,
                    field,
                    problem: if ctx.in_array {
                        FieldProblem::NonNumeric
                    } else {
                        FieldProblem::NotAnArray
                    },
                },
                (Some(step), None) => TelemetryError::FrameNotObject { step },
                _ => json_error(bytes, &e, ctx.step),
            },
            _ => match (ctx.step, ctx.field) {
                (Some(step), Some(field)) if is_non_finite(bytes, &e) => TelemetryError::Field {
                    step,
                    field,
                    problem: FieldProblem::NonFinite,
                },
                _ => json_error(bytes, &e, ctx.step),
            },
        });
    }
    finish(frames, sorted)
}

/// Sorts the frames by step (stable), rejects a repeated step and counts the gaps.
fn finish(mut frames: Vec<TelemetryFrame>, sorted: bool) -> Result<Telemetry, TelemetryError> {
    if frames.is_empty() {
        return Err(TelemetryError::NoFrames);
    }
    if !sorted {
        frames.sort_by_key(|f: &TelemetryFrame| f.step);
    }
    if let Some(w) = frames.windows(2).find(|w| w[0].step == w[1].step) {
        return Err(TelemetryError::DuplicateStep { step: w[0].step });
    }
    // Steps are unique and sorted, so last - first >= n - 1 (written to never overflow).
    let n = frames.len() as u64;
    let gaps = (frames[frames.len() - 1].step - frames[0].step) - (n - 1);
    Ok(Telemetry {
        frames,
        gaps,
        segments: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid frame body with location (x, y).
    fn body(x: f64, y: f64) -> String {
        format!(
            r#"{{"acceleration": [1.5, -2.0, 9.8], "angular_velocity": [0.1, 0.2, 12.5],
                "forward_vector": [0.6, 0.8, 0.0], "right_vector": [-0.8, 0.6, 0.0],
                "location": [{x}, {y}, 0.3], "rotation": [0.0, 0.0, 53.1], "velocity": [1, 2, 3]}}"#
        )
    }

    fn file(entries: &[(&str, String)]) -> Vec<u8> {
        let parts: Vec<String> = entries
            .iter()
            .map(|(k, v)| format!("  \"{k}\": {v}"))
            .collect();
        format!("{{\n{}\n}}\n", parts.join(",\n")).into_bytes()
    }

    fn err(bytes: &[u8]) -> String {
        parse_metric_info(bytes).unwrap_err().to_string()
    }

    #[test]
    fn parses_fields_and_ignores_extras() {
        let t = parse_metric_info(&file(&[("1", body(100.25, -3.5))])).unwrap();
        assert_eq!(t.gaps, 0);
        assert_eq!(
            t.frames,
            vec![TelemetryFrame {
                step: 1,
                location: [100.25, -3.5],
                z: 0.3,
                acc: [1.5, -2.0],
                fwd: [0.6, 0.8],
                right: [-0.8, 0.6],
                yaw_rate_deg: 12.5,
            }]
        );
    }

    #[test]
    fn longer_vectors_take_first_three() {
        let b = br#"{"3": {"acceleration": [1, 2, 3, "x", [4]], "angular_velocity": [0, 0, 7, 8],
            "forward_vector": [1, 0, 0], "right_vector": [0, 1, 0], "location": [5, 6, 7, 8]}}"#;
        let t = parse_metric_info(b).unwrap();
        assert_eq!(t.frames[0].acc, [1.0, 2.0]);
        assert_eq!(t.frames[0].yaw_rate_deg, 7.0);
        assert_eq!(t.frames[0].location, [5.0, 6.0]);
    }

    #[test]
    fn shuffled_keys_are_sorted_by_numeric_step() {
        let b = file(&[
            ("10", body(10.0, 0.0)),
            ("9", body(9.0, 0.0)),
            ("11", body(11.0, 0.0)),
            ("2", body(2.0, 0.0)),
        ]);
        let t = parse_metric_info(&b).unwrap();
        let steps: Vec<u64> = t.frames.iter().map(|f| f.step).collect();
        assert_eq!(steps, vec![2, 9, 10, 11]);
        // Each frame keeps its own payload.
        let xs: Vec<f64> = t.frames.iter().map(|f| f.location[0]).collect();
        assert_eq!(xs, vec![2.0, 9.0, 10.0, 11.0]);
        // 2..=11 is 10 step numbers, 4 present.
        assert_eq!(t.gaps, 6);
    }

    #[test]
    fn steps_starting_at_500_with_gaps() {
        let b = file(&[
            ("500", body(0.0, 0.0)),
            ("501", body(0.0, 0.0)),
            ("503", body(0.0, 0.0)),
            ("507", body(0.0, 0.0)),
        ]);
        let t = parse_metric_info(&b).unwrap();
        assert_eq!(t.frames[0].step, 500);
        assert_eq!(t.gaps, 507 - 500 + 1 - 4);
        assert_eq!(t.gaps, 4);
        assert_eq!(t.steps(), vec![500, 501, 503, 507]);
    }

    #[test]
    fn extreme_steps_do_not_overflow_the_gap_count() {
        let b = file(&[
            ("0", body(0.0, 0.0)),
            ("18446744073709551615", body(0.0, 0.0)),
        ]);
        let t = parse_metric_info(&b).unwrap();
        assert_eq!(t.frames[1].step, u64::MAX);
        assert_eq!(t.gaps, u64::MAX - 1);
    }

    #[test]
    fn leading_zero_key_is_its_integer_value() {
        let t = parse_metric_info(&file(&[("007", body(0.0, 0.0))])).unwrap();
        assert_eq!(t.frames[0].step, 7);
    }

    #[test]
    fn unreadable_file() {
        let e = read_metric_info(Path::new("/nonexistent/dir/metric_info.json")).unwrap_err();
        let s = e.to_string();
        assert!(
            s.starts_with("cannot read /nonexistent/dir/metric_info.json: "),
            "{s}"
        );
    }

    #[test]
    fn read_from_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("metric_info.json");
        std::fs::write(&p, file(&[("4", body(1.0, 2.0))])).unwrap();
        assert_eq!(read_metric_info(&p).unwrap().frames[0].location, [1.0, 2.0]);
    }

    #[test]
    fn not_json() {
        assert_eq!(
            err(b"{\"1\": {\"acceleration\": [1, 2, 3]"),
            "not valid JSON at line 1 column 32: EOF while parsing an object"
        );
        assert!(err(b"hello").starts_with("not valid JSON at line 1 column 1: "));
        assert!(err(b"").starts_with("not valid JSON at line 1 column 0: "));
        assert!(err(b"{} trailing").starts_with("not valid JSON at line 1 column 4: "));
    }

    #[test]
    fn top_level_not_object() {
        assert_eq!(err(b"[1, 2]"), "top level is not an object");
        assert_eq!(err(b"  42 "), "top level is not an object");
        assert_eq!(err(b"null"), "top level is not an object");
    }

    #[test]
    fn empty_object_has_no_frames() {
        assert_eq!(err(b"{}"), "no frames");
        assert_eq!(err(b" {\n } \n"), "no frames");
    }

    #[test]
    fn non_decimal_step_key() {
        assert_eq!(
            err(&file(&[("12a", body(0.0, 0.0))])),
            r#"step key "12a" is not decimal digits"#
        );
        assert_eq!(
            err(&file(&[("-1", body(0.0, 0.0))])),
            r#"step key "-1" is not decimal digits"#
        );
        assert_eq!(
            err(&file(&[("", body(0.0, 0.0))])),
            r#"step key "" is not decimal digits"#
        );
        assert_eq!(
            err(&file(&[("99999999999999999999", body(0.0, 0.0))])),
            r#"step key "99999999999999999999" is out of range"#
        );
    }

    #[test]
    fn duplicate_integer_steps() {
        assert_eq!(
            err(&file(&[
                ("6", body(0.0, 0.0)),
                ("7", body(0.0, 0.0)),
                ("8", body(0.0, 0.0)),
                ("007", body(0.0, 0.0)),
            ])),
            "step 7 appears twice"
        );
        assert_eq!(
            err(&file(&[("12", body(0.0, 0.0)), ("12", body(0.0, 0.0))])),
            "step 12 appears twice"
        );
    }

    #[test]
    fn missing_required_vector() {
        for name in TelemetryFrame::FIELDS {
            let b = body(0.0, 0.0);
            let start = b.find(&format!("\"{name}\"")).unwrap();
            let end = start + b[start..].find(']').unwrap() + 2; // past "],"
            let without = format!("{}{}", &b[..start], &b[end..]);
            let got = err(&file(&[("39", body(0.0, 0.0)), ("40", without)]));
            assert_eq!(got, format!("step 40: field {name}: missing"));
        }
    }

    #[test]
    fn rotation_is_not_required() {
        let b = br#"{"1": {"acceleration": [0,0,0], "angular_velocity": [0,0,0],
            "forward_vector": [1,0,0], "right_vector": [0,1,0], "location": [0,0,0]}}"#;
        assert!(parse_metric_info(b).is_ok());
    }

    #[test]
    fn short_vector() {
        let b = body(0.0, 0.0).replace("[0, 0, 0.3]", "[0, 1]");
        assert!(b.contains(r#""location": [0, 1]"#), "{b}");
        assert_eq!(
            err(&file(&[("40", b)])),
            "step 40: field location: fewer than 3 numbers"
        );
        assert_eq!(
            err(&file(&[(
                "3",
                body(0.0, 0.0).replace("[0.1, 0.2, 12.5]", "[]")
            )])),
            "step 3: field angular_velocity: fewer than 3 numbers"
        );
    }

    #[test]
    fn non_numeric_vector() {
        assert_eq!(
            err(&file(&[(
                "5",
                body(0.0, 0.0).replace("[0.6, 0.8, 0.0]", r#"[0.6, "0.8", 0.0]"#)
            )])),
            "step 5: field forward_vector: non-numeric value"
        );
        assert_eq!(
            err(&file(&[(
                "5",
                body(0.0, 0.0).replace("[-0.8, 0.6, 0.0]", "[-0.8, null, 0.0]")
            )])),
            "step 5: field right_vector: non-numeric value"
        );
        assert_eq!(
            err(&file(&[(
                "5",
                body(0.0, 0.0).replace("[-0.8, 0.6, 0.0]", r#""east""#)
            )])),
            "step 5: field right_vector: not an array of numbers"
        );
        assert_eq!(
            err(&file(&[("5", "[1, 2]".to_string())])),
            "step 5: frame is not an object"
        );
    }

    #[test]
    fn nan_and_infinity_tokens() {
        for tok in ["NaN", "Infinity", "-Infinity"] {
            let b = body(0.0, 0.0).replace("[1.5, -2.0, 9.8]", &format!("[1.5, {tok}, 9.8]"));
            assert_eq!(
                err(&file(&[("6", body(0.0, 0.0)), ("7", b)])),
                "step 7: field acceleration: NaN or infinite value",
                "{tok}"
            );
        }
        // In an ignored field: still invalid, named by step and position.
        let b = body(0.0, 0.0).replace("[0.0, 0.0, 53.1]", "[0.0, NaN, 53.1]");
        let got = err(&file(&[("9", b)]));
        assert!(
            got.starts_with("step 9: NaN or infinite value at line "),
            "{got}"
        );
    }

    #[test]
    fn overflowing_literal() {
        let b = body(0.0, 0.0).replace("[1.5, -2.0, 9.8]", "[1e999, -2.0, 9.8]");
        assert_eq!(
            err(&file(&[("7", b)])),
            "step 7: field acceleration: NaN or infinite value"
        );
        // An ignored key's numbers are skipped, not evaluated (documented on parse_metric_info).
        let b = body(0.0, 0.0).replace("[0.0, 0.0, 53.1]", "[0.0, -1e999, 53.1]");
        assert!(parse_metric_info(&file(&[("8", b)])).is_ok());
        // Finite in f64 but not in f32.
        let b = body(0.0, 0.0).replace("[1.5, -2.0, 9.8]", "[1e300, -2.0, 9.8]");
        assert_eq!(
            err(&file(&[("7", b)])),
            "step 7: field acceleration: value too large for f32"
        );
    }

    #[test]
    fn duplicate_field_in_frame() {
        let b = body(0.0, 0.0).replace(r#""rotation""#, r#""location""#);
        assert_eq!(
            err(&file(&[("2", b)])),
            "step 2: field location: appears twice"
        );
    }

    #[test]
    fn escaped_keys_are_handled() {
        // "\u0031" is "1": serde_json hands an unescaped temporary to the key visitor.
        let b = format!("{{\"\\u0031\": {}}}", body(0.0, 0.0));
        assert_eq!(parse_metric_info(b.as_bytes()).unwrap().frames[0].step, 1);
    }
}
