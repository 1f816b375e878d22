//! A route's telemetry, whatever file it was read from (docs/SCORE.md §2.2): the frames
//! ([`TelemetryFrame`], [`Telemetry`]) and why a file is invalid ([`TelemetryError`]). The one
//! place that picks the reader for a file is [`format`](mod@format) ([`format::read_telemetry`]).
//! Bench2Drive's `metric_info.json` ([`crate::input::metric_info`]) is the one format today; a
//! second one (another simulator's logs) is a new variant of [`format::TelemetryFormat`] and its
//! reader, giving the same types.

pub mod format;

use std::fmt;
use std::path::PathBuf;

/// One telemetry frame, reduced to what the monitor and the host geometry need.
///
/// World-frame 2-D parts only (index 0 and 1 of each vector, docs/SCORE.md §3). Positions stay
/// f64 (maps reach ~10 km); the per-frame signal inputs are rounded to f32 once, here.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TelemetryFrame {
    /// The step number (the JSON key).
    pub step: u64,
    /// `location` x, y in metres.
    pub location: [f64; 2],
    /// `location` z in metres: chooses the lane under an overpass when a map is given (docs/SCORE.md §14.3).
    pub z: f64,
    /// `acceleration` x, y in m/s².
    pub acc: [f32; 2],
    /// `forward_vector` x, y.
    pub fwd: [f32; 2],
    /// `right_vector` x, y.
    pub right: [f32; 2],
    /// `angular_velocity[2]` in deg/s (CARLA's unit).
    pub yaw_rate_deg: f32,
}

impl TelemetryFrame {
    /// The required fields of a frame, in the order [`TelemetryFrame::from_raw`] takes them:
    /// `acceleration`, `angular_velocity`, `forward_vector`, `right_vector`, `location`.
    pub const FIELDS: [&'static str; 5] = [
        "acceleration",
        "angular_velocity",
        "forward_vector",
        "right_vector",
        "location",
    ];

    /// Reduces one raw frame (the five 3-vectors of [`TelemetryFrame::FIELDS`], as CARLA gives
    /// them in f64) to its 2-D parts, rounding the signal inputs to f32 once. The file reader
    /// and the bindings' per-tick entry both go through here.
    ///
    /// ```
    /// use monitor_host::input::metric_info::TelemetryFrame;
    /// let raw = [[0.5, 0.25, 9.8], [0.0, 0.0, 3.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///            [10.0, 5.0, 0.2]];
    /// let f = TelemetryFrame::from_raw(7, raw)?;
    /// assert_eq!((f.step, f.acc, f.yaw_rate_deg, f.location), (7, [0.5, 0.25], 3.0, [10.0, 5.0]));
    /// let too_big = TelemetryFrame::from_raw(7, [[1e300; 3], raw[1], raw[2], raw[3], raw[4]]);
    /// assert_eq!(too_big.unwrap_err().to_string(),
    ///            "step 7: field acceleration: value too large for f32");
    /// # Ok::<(), monitor_host::input::metric_info::TelemetryError>(())
    /// ```
    ///
    /// # Errors
    /// [`TelemetryError::Field`] naming the step and field: a NaN or infinite value
    /// ([`FieldProblem::NonFinite`]), or a value stored as f32 that overflows it
    /// ([`FieldProblem::OutOfF32Range`]).
    pub fn from_raw(step: u64, raw: [[f64; 3]; 5]) -> Result<TelemetryFrame, TelemetryError> {
        let fail = |i: usize, problem| TelemetryError::Field {
            step,
            field: Self::FIELDS[i],
            problem,
        };
        if let Some(i) = raw.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(fail(i, FieldProblem::NonFinite));
        }
        let [acc, angvel, fwd, right, loc] = raw;
        // Values stored as f32 must stay finite after rounding.
        let f32_checks: [(usize, &[f64]); 4] = [
            (0, &acc[..2]),
            (1, &angvel[2..]),
            (2, &fwd[..2]),
            (3, &right[..2]),
        ];
        for (i, vs) in f32_checks {
            if vs.iter().any(|&v| !(v as f32).is_finite()) {
                return Err(fail(i, FieldProblem::OutOfF32Range));
            }
        }
        Ok(TelemetryFrame {
            step,
            location: [loc[0], loc[1]],
            z: loc[2],
            acc: [acc[0] as f32, acc[1] as f32],
            fwd: [fwd[0] as f32, fwd[1] as f32],
            right: [right[0] as f32, right[1] as f32],
            yaw_rate_deg: angvel[2] as f32,
        })
    }
}

/// A route's telemetry: frames sorted by step, and the number of missing step numbers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Telemetry {
    /// Frames in increasing step order (steps are unique).
    pub frames: Vec<TelemetryFrame>,
    /// `last_step - first_step + 1 - frames.len()` (docs/SCORE.md §2.2).
    pub gaps: u64,
    /// The index of each segment's first frame, for a vehicle log cut at its gaps (spec v1.5
    /// docs/SCORE.md §2.4: each segment is monitored as a fresh start); empty for a telemetry file, whose
    /// frames are one run chunked consecutively across missing steps (docs/SCORE.md §2.2).
    pub segments: Vec<usize>,
}

impl Telemetry {
    /// The step numbers, in frame order (for [`crate::pipeline::align::align_events`]).
    pub fn steps(&self) -> Vec<u64> {
        self.frames.iter().map(|f| f.step).collect()
    }

    /// The frame ranges of the segments of `n` frames whose first frames are `segments` (one
    /// range of every frame when `segments` is empty).
    ///
    /// ```
    /// use monitor_host::input::telemetry::Telemetry;
    /// assert_eq!(Telemetry::ranges(&[], 5), vec![0..5]);
    /// assert_eq!(Telemetry::ranges(&[0, 3], 5), vec![0..3, 3..5]);
    /// ```
    pub fn ranges(segments: &[usize], n: usize) -> Vec<std::ops::Range<usize>> {
        if segments.is_empty() {
            return std::iter::once(0..n).collect();
        }
        segments
            .iter()
            .zip(segments.iter().skip(1).chain([&n]))
            .map(|(&a, &b)| a..b)
            .collect()
    }

    /// The 2-D locations, in frame order (for [`crate::pipeline::align::nearest_frame`]).
    pub fn locations(&self) -> Vec<[f64; 2]> {
        self.frames.iter().map(|f| f.location).collect()
    }
}

/// What is wrong with one required field of one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldProblem {
    /// The field is absent.
    Missing,
    /// The field is given twice in the same frame.
    Duplicate,
    /// The field is not an array.
    NotAnArray,
    /// The array has fewer than 3 elements.
    TooShort,
    /// One of the first 3 elements is not a number.
    NonNumeric,
    /// A NaN or infinite value (including literals such as `1e999` that overflow).
    NonFinite,
    /// A finite value too large to be represented as f32 (the monitor's float type).
    OutOfF32Range,
}

impl fmt::Display for FieldProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FieldProblem::Missing => "missing",
            FieldProblem::Duplicate => "appears twice",
            FieldProblem::NotAnArray => "not an array of numbers",
            FieldProblem::TooShort => "fewer than 3 numbers",
            FieldProblem::NonNumeric => "non-numeric value",
            FieldProblem::NonFinite => "NaN or infinite value",
            FieldProblem::OutOfF32Range => "value too large for f32",
        })
    }
}

/// Why a telemetry file is invalid. The `Display` text is the reason reported as
/// `invalid: <reason>` (docs/SCORE.md §2.2): it names the step and the field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TelemetryError {
    /// The file cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// Not syntactically valid JSON (other than a NaN / infinite token, see [`Self::NonFinite`]).
    #[error("not valid JSON at line {line} column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// Column (bytes into the line).
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The JSON top level is not an object.
    #[error("top level is not an object")]
    NotObject,
    /// The top-level object is empty.
    #[error("no frames")]
    NoFrames,
    /// A key that is not decimal digits.
    #[error("step key {key:?} is not decimal digits")]
    BadStepKey {
        /// The key (truncated to 40 characters).
        key: String,
    },
    /// A decimal key too large for u64.
    #[error("step key {key:?} is out of range")]
    StepOutOfRange {
        /// The key (truncated to 40 characters).
        key: String,
    },
    /// Two keys with the same integer value (e.g. `"007"` and `"7"`).
    #[error("step {step} appears twice")]
    DuplicateStep {
        /// The step.
        step: u64,
    },
    /// A frame value that is not an object.
    #[error("step {step}: frame is not an object")]
    FrameNotObject {
        /// The step.
        step: u64,
    },
    /// A required field is missing or malformed.
    #[error("step {step}: field {field}: {problem}")]
    Field {
        /// The step.
        step: u64,
        /// The field name (`acceleration`, `angular_velocity`, `forward_vector`,
        /// `right_vector`, `location`).
        field: &'static str,
        /// What is wrong.
        problem: FieldProblem,
    },
    /// A bare `NaN` / `Infinity` / `-Infinity` token (as Python's `json` writes them) or a number
    /// literal that overflows to infinity, outside a required field (or before any step).
    #[error("{}NaN or infinite value at line {line} column {column}", step_prefix(*.step))]
    NonFinite {
        /// The step whose value holds the token, if known.
        step: Option<u64>,
        /// 1-based line.
        line: usize,
        /// Column (bytes into the line).
        column: usize,
    },
}

fn step_prefix(step: Option<u64>) -> String {
    match step {
        Some(s) => format!("step {s}: "),
        None => String::new(),
    }
}
