//! The streaming `metric_info.json` parser: serde visitors over the bytes, no JSON DOM, no
//! allocation per frame or per key. Each frame is validated and reduced to a
//! [`TelemetryFrame`] as it is read.

use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

use super::{FieldProblem, TelemetryError, TelemetryFrame};

// ---------------------------------------------------------------------------------------------
// Streaming parser internals.

/// Parser context: where we are (for error messages) and the precise error, if a visitor of ours
/// rejected the input (serde's error type cannot carry it).
pub(super) struct Ctx {
    pub(super) step: Option<u64>,
    pub(super) field: Option<&'static str>,
    pub(super) in_array: bool,
    pub(super) error: Option<TelemetryError>,
}

impl Ctx {
    fn fail<E: de::Error>(&mut self, err: TelemetryError) -> E {
        self.error = Some(err);
        E::custom("invalid telemetry")
    }
}

fn truncate_key(key: &str) -> String {
    key.chars().take(40).collect()
}

/// The line-and-column part of serde_json's message stripped off.
fn bare_message(e: &serde_json::Error) -> String {
    let s = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    match s.strip_suffix(&suffix) {
        Some(m) => m.to_string(),
        None => s,
    }
}

/// Is this syntax error a Python `NaN` / `Infinity` / `-Infinity` token or an overflowing number?
/// Decided from the bytes at the error's position, not from the parser's message text.
pub(super) fn is_non_finite(bytes: &[u8], e: &serde_json::Error) -> bool {
    // Byte offset of the error: start of line `line` plus `column`.
    let mut start = 0usize;
    let mut line = 1usize;
    while line < e.line() {
        match bytes[start..].iter().position(|&b| b == b'\n') {
            Some(p) => {
                start += p + 1;
                line += 1;
            }
            None => return false,
        }
    }
    let at = start.saturating_add(e.column()).min(bytes.len());
    let lo = at.saturating_sub(9);
    let hi = at.saturating_add(9).min(bytes.len());
    let window = &bytes[lo..hi];
    [&b"NaN"[..], b"Infinity"]
        .iter()
        .any(|tok| window.windows(tok.len()).any(|w| w == *tok))
        || overflowing_number_near(bytes, at)
}

/// Is there a number literal ending at or just before `at` that overflows f64 (`1e999`)?
fn overflowing_number_near(bytes: &[u8], at: usize) -> bool {
    let is_num = |b: &u8| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-');
    // The parser stops on the literal's last byte or the one after it.
    let Some(end) = (at.saturating_sub(2)..at.min(bytes.len()))
        .rev()
        .find(|&i| is_num(&bytes[i]))
    else {
        return false;
    };
    let begin = bytes[..=end]
        .iter()
        .rposition(|b| !is_num(b))
        .map_or(0, |i| i + 1);
    let end = end + bytes[end..].iter().take_while(|b| is_num(b)).count();
    std::str::from_utf8(&bytes[begin..end])
        .ok()
        .and_then(|t| t.parse::<f64>().ok())
        .is_some_and(f64::is_infinite)
}

pub(super) fn json_error(bytes: &[u8], e: &serde_json::Error, step: Option<u64>) -> TelemetryError {
    if e.is_syntax() && is_non_finite(bytes, e) {
        return TelemetryError::NonFinite {
            step,
            line: e.line(),
            column: e.column(),
        };
    }
    TelemetryError::Json {
        line: e.line(),
        column: e.column(),
        message: bare_message(e),
    }
}

pub(super) struct TopVisitor<'c> {
    pub(super) ctx: &'c mut Ctx,
    pub(super) frames: &'c mut Vec<TelemetryFrame>,
    pub(super) sorted: &'c mut bool,
}

impl<'de> Visitor<'de> for TopVisitor<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an object of frames keyed by step")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let ctx = self.ctx;
        let mut last: Option<u64> = None;
        loop {
            ctx.step = None;
            ctx.field = None;
            let Some(step) = map.next_key_seed(StepKey { ctx: &mut *ctx })? else {
                return Ok(());
            };
            ctx.step = Some(step);
            let frame = map.next_value_seed(FrameSeed {
                ctx: &mut *ctx,
                step,
            })?;
            if let Some(prev) = last {
                if step <= prev {
                    *self.sorted = false;
                }
            }
            last = Some(step);
            self.frames.push(frame);
        }
    }
}

/// A step key: decimal digits, parsed without allocating.
struct StepKey<'c> {
    pub(super) ctx: &'c mut Ctx,
}

impl<'de> DeserializeSeed<'de> for StepKey<'_> {
    type Value = u64;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<u64, D::Error> {
        d.deserialize_str(self)
    }
}

impl<'de> Visitor<'de> for StepKey<'_> {
    type Value = u64;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a decimal step number")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<u64, E> {
        step_number(v).map_err(|e| self.ctx.fail(e))
    }
}

/// A step key's number: decimal digits that fit u64 (shared by both parse paths).
pub(super) fn step_number(v: &str) -> Result<u64, TelemetryError> {
    if v.is_empty() || !v.bytes().all(|b| b.is_ascii_digit()) {
        return Err(TelemetryError::BadStepKey {
            key: truncate_key(v),
        });
    }
    let mut n: u64 = 0;
    for b in v.bytes() {
        match n
            .checked_mul(10)
            .and_then(|n| n.checked_add(u64::from(b - b'0')))
        {
            Some(m) => n = m,
            None => {
                return Err(TelemetryError::StepOutOfRange {
                    key: truncate_key(v),
                })
            }
        }
    }
    Ok(n)
}

pub(crate) const FIELD_NAMES: [&str; 5] = TelemetryFrame::FIELDS;

/// The index in [`FIELD_NAMES`] of a frame key, `None` for a key that is ignored.
pub(super) fn field_index(name: &[u8]) -> Option<usize> {
    FIELD_NAMES.iter().position(|n| n.as_bytes() == name)
}

/// A frame key: `Some(index in FIELD_NAMES)` or `None` (ignored).
struct FieldKey;

impl<'de> DeserializeSeed<'de> for FieldKey {
    type Value = Option<usize>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Option<usize>, D::Error> {
        d.deserialize_str(self)
    }
}

impl<'de> Visitor<'de> for FieldKey {
    type Value = Option<usize>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a field name")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Option<usize>, E> {
        Ok(field_index(v.as_bytes()))
    }
}

struct FrameSeed<'c> {
    pub(super) ctx: &'c mut Ctx,
    step: u64,
}

impl<'de> DeserializeSeed<'de> for FrameSeed<'_> {
    type Value = TelemetryFrame;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<TelemetryFrame, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for FrameSeed<'_> {
    type Value = TelemetryFrame;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a frame object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<TelemetryFrame, A::Error> {
        let ctx = self.ctx;
        let step = self.step;
        let mut vals: [Option<[f64; 3]>; 5] = [None; 5];
        while let Some(field) = map.next_key_seed(FieldKey)? {
            let Some(idx) = field else {
                map.next_value::<IgnoredAny>()?;
                continue;
            };
            let name = FIELD_NAMES[idx];
            if vals[idx].is_some() {
                return Err(ctx.fail(TelemetryError::Field {
                    step,
                    field: name,
                    problem: FieldProblem::Duplicate,
                }));
            }
            ctx.field = Some(name);
            ctx.in_array = false;
            let v = map.next_value_seed(Vec3 {
                ctx: &mut *ctx,
                step,
                field: name,
            })?;
            ctx.field = None;
            vals[idx] = Some(v);
        }
        let mut out = [[0.0f64; 3]; 5];
        for (i, (slot, name)) in vals.iter().zip(FIELD_NAMES).enumerate() {
            match slot {
                Some(v) => out[i] = *v,
                None => {
                    return Err(ctx.fail(TelemetryError::Field {
                        step,
                        field: name,
                        problem: FieldProblem::Missing,
                    }))
                }
            }
        }
        TelemetryFrame::from_raw(step, out).map_err(|e| ctx.fail(e))
    }
}

/// A required 3-vector: an array of at least 3 finite numbers; extra elements are ignored.
struct Vec3<'c> {
    pub(super) ctx: &'c mut Ctx,
    step: u64,
    field: &'static str,
}

impl<'de> DeserializeSeed<'de> for Vec3<'_> {
    type Value = [f64; 3];
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<[f64; 3], D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for Vec3<'_> {
    type Value = [f64; 3];

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of 3 numbers")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; 3], A::Error> {
        self.ctx.in_array = true;
        let mut v = [0.0f64; 3];
        for slot in &mut v {
            match seq.next_element::<f64>()? {
                Some(x) if x.is_finite() => *slot = x,
                Some(_) => {
                    return Err(self.ctx.fail(TelemetryError::Field {
                        step: self.step,
                        field: self.field,
                        problem: FieldProblem::NonFinite,
                    }))
                }
                None => {
                    return Err(self.ctx.fail(TelemetryError::Field {
                        step: self.step,
                        field: self.field,
                        problem: FieldProblem::TooShort,
                    }))
                }
            }
        }
        while seq.next_element::<IgnoredAny>()?.is_some() {}
        self.ctx.in_array = false;
        Ok(v)
    }
}
