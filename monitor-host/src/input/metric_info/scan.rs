//! The fast path of the `metric_info.json` parser: a strict scanner for the files Bench2Drive
//! writes, which accepts only what it is sure of.
//!
//! It recognises a subset of JSON: the top-level object of frames keyed by decimal steps, each
//! frame an object whose keys are plain ASCII (no escapes), whose five required fields are
//! arrays of exactly three numbers, and whose other fields are a number or a flat array of
//! numbers; JSON whitespace anywhere between tokens. Numbers follow JSON's grammar exactly and
//! the 15 that are kept are converted by `str::parse::<f64>`, which rounds correctly, as
//! serde_json does with `float_roundtrip`: the same bits (integers included, which serde_json
//! converts exactly and `as f64` rounds correctly). Numbers of other fields are checked, not
//! converted, as serde_json's `IgnoredAny` does.
//!
//! It never produces an error. On anything else (a string or nested value, an escape, a
//! non-ASCII byte, a missing, repeated, short or long required vector, a value that is not
//! finite or does not fit f32, a non-decimal step key, a repeated step) it returns `None` and
//! the caller parses the same bytes with the serde_json visitor, which alone decides errors and
//! their messages. The test `metric_info_fast_path` checks both paths on the fuzz corpus and on
//! generated, mutated and arbitrary inputs: same frames bit for bit, never accepting more.

use super::visitor::{field_index, step_number};
use super::TelemetryFrame;

/// A position in the bytes.
struct Cursor<'a> {
    b: &'a [u8],
    i: usize,
}

impl<'a> Cursor<'a> {
    /// Skips JSON whitespace (eight spaces at a time: `json.dump(indent=4)` indents a lot).
    #[inline]
    fn ws(&mut self) {
        loop {
            if let Some(chunk) = self.b.get(self.i..self.i + 8) {
                if chunk == b"        " {
                    self.i += 8;
                    continue;
                }
            }
            match self.b.get(self.i) {
                Some(b' ' | b'\n' | b'\r' | b'\t') => self.i += 1,
                _ => return,
            }
        }
    }

    #[inline]
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    #[inline]
    fn eat(&mut self, c: u8) -> Option<()> {
        (self.peek()? == c).then(|| self.i += 1)
    }

    /// A key without escapes or non-ASCII bytes.
    #[inline]
    fn key(&mut self) -> Option<&'a [u8]> {
        self.eat(b'"')?;
        let start = self.i;
        let len = self.b.get(start..)?.iter().position(|&c| c == b'"')?;
        let text = &self.b[start..start + len];
        if text
            .iter()
            .any(|&c| c == b'\\' || !(0x20..0x80).contains(&c))
        {
            return None;
        }
        self.i = start + len + 1;
        Some(text)
    }

    #[inline]
    fn digits(&mut self) -> usize {
        let start = self.i;
        while self.b.get(self.i).is_some_and(u8::is_ascii_digit) {
            self.i += 1;
        }
        self.i - start
    }

    /// A number token in JSON's grammar, `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`;
    /// returns the index where it starts.
    #[inline]
    fn number(&mut self) -> Option<usize> {
        let start = self.i;
        if self.peek() == Some(b'-') {
            self.i += 1;
        }
        match self.peek()? {
            b'0' => self.i += 1,
            b'1'..=b'9' => {
                self.digits();
            }
            _ => return None,
        }
        if self.peek() == Some(b'.') {
            self.i += 1;
            if self.digits() == 0 {
                return None;
            }
        }
        if matches!(self.peek(), Some(b'e' | b'E')) {
            self.i += 1;
            if matches!(self.peek(), Some(b'+' | b'-')) {
                self.i += 1;
            }
            if self.digits() == 0 {
                return None;
            }
        }
        Some(start)
    }

    /// A number token's value, correctly rounded (`None` if not finite).
    #[inline]
    #[allow(unsafe_code)]
    fn value(&mut self) -> Option<f64> {
        let start = self.number()?;
        let token = &self.b[start..self.i];
        debug_assert!(token.is_ascii());
        // SAFETY: `number` admitted only the ASCII bytes `-+.eE0-9`, which are valid UTF-8.
        // (`str::from_utf8` here cost 11 % of the whole replay.)
        let text = unsafe { std::str::from_utf8_unchecked(token) };
        let x: f64 = text.parse().ok()?;
        x.is_finite().then_some(x)
    }

    /// A required vector: exactly three finite numbers.
    fn vec3(&mut self) -> Option<[f64; 3]> {
        self.eat(b'[')?;
        let mut v = [0.0f64; 3];
        for (k, slot) in v.iter_mut().enumerate() {
            if k > 0 {
                self.ws();
                self.eat(b',')?;
            }
            self.ws();
            *slot = self.value()?;
        }
        self.ws();
        self.eat(b']')?;
        Some(v)
    }

    /// Another field's value: a number or a flat array of numbers, checked only.
    fn other(&mut self) -> Option<()> {
        if self.eat(b'[').is_none() {
            return self.number().map(|_| ());
        }
        self.ws();
        if self.eat(b']').is_some() {
            return Some(());
        }
        loop {
            self.number()?;
            self.ws();
            match self.peek()? {
                b',' => {
                    self.i += 1;
                    self.ws();
                }
                b']' => {
                    self.i += 1;
                    return Some(());
                }
                _ => return None,
            }
        }
    }

    /// One frame object.
    fn frame(&mut self, step: u64) -> Option<TelemetryFrame> {
        self.eat(b'{')?;
        let mut vals = [[0.0f64; 3]; 5];
        let mut seen = 0u8;
        loop {
            self.ws();
            let name = self.key()?;
            self.ws();
            self.eat(b':')?;
            self.ws();
            match field_index(name) {
                Some(idx) => {
                    if seen & (1 << idx) != 0 {
                        return None;
                    }
                    seen |= 1 << idx;
                    vals[idx] = self.vec3()?;
                }
                None => self.other()?,
            }
            self.ws();
            match self.peek()? {
                b',' => self.i += 1,
                b'}' => {
                    self.i += 1;
                    break;
                }
                _ => return None,
            }
        }
        if seen != 0b1_1111 {
            return None;
        }
        TelemetryFrame::from_raw(step, vals).ok()
    }
}

/// The frames of `bytes` in file order and whether their steps increase, or `None` when the
/// serde_json path must decide.
pub(super) fn parse(bytes: &[u8]) -> Option<(Vec<TelemetryFrame>, bool)> {
    let mut c = Cursor { b: bytes, i: 0 };
    c.ws();
    c.eat(b'{')?;
    // About 830 bytes per frame in Bench2Drive's layout; the estimate only avoids regrowth.
    let mut frames: Vec<TelemetryFrame> = Vec::with_capacity((bytes.len() / 700).min(1 << 20));
    let mut sorted = true;
    loop {
        c.ws();
        let step = step_number(std::str::from_utf8(c.key()?).ok()?).ok()?;
        c.ws();
        c.eat(b':')?;
        c.ws();
        let frame = c.frame(step)?;
        if frames.last().is_some_and(|p| step <= p.step) {
            sorted = false;
        }
        frames.push(frame);
        c.ws();
        match c.peek()? {
            b',' => c.i += 1,
            b'}' => {
                c.i += 1;
                break;
            }
            _ => return None,
        }
    }
    c.ws();
    (c.i == bytes.len()).then_some((frames, sorted))
}
