//! The fast path of the `metric_info.json` parser: a strict scanner for the files Bench2Drive
//! writes, which accepts only what it is sure of.
//!
//! It recognises a subset of JSON: the top-level object of frames keyed by decimal steps, each
//! frame an object whose keys are plain ASCII (no escapes), whose five required fields are
//! arrays of exactly three numbers, and whose other fields are a number or a flat array of
//! numbers; JSON whitespace anywhere between tokens. Numbers follow JSON's grammar exactly and
//! the 10 a frame keeps are converted to the correctly rounded f64 (`float.rs`, else
//! `str::parse::<f64>`), as serde_json does with `float_roundtrip`: the same bits (integers
//! included, which serde_json converts exactly and `as f64` rounds correctly). The other
//! numbers are checked, not converted, as serde_json's `IgnoredAny` does.
//!
//! Token by token, one frame at a time, here; the frames after one read so are read by its
//! layout (`layout.rs`): their bytes between numbers compared with that frame's, their numbers
//! read sixteen bytes at a time (`number.rs`), any departure read token by token again.
//!
//! It never produces an error. On anything else (a string or nested value, an escape, a
//! non-ASCII byte, a missing, repeated, short or long required vector, a value that is not
//! finite or does not fit f32, a non-decimal step key, a repeated step) it returns `None` and
//! the caller parses the same bytes with the serde_json visitor, which alone decides errors and
//! their messages. The test `metric_info_fast_path` checks both paths on the fuzz corpus and on
//! generated, mutated and arbitrary inputs: same frames bit for bit, never accepting more.

use super::layout::{same, Layout, Mark, Role, Sep};
use super::number;
use super::visitor::{field_index, step_number};
use super::TelemetryFrame;

/// Which components of each required vector (`TelemetryFrame::FIELDS` order) a frame keeps:
/// acceleration x, y; angular velocity z; forward and right x, y; location x, y, z. The other
/// five are checked to be finite, as `TelemetryFrame::from_raw` requires, without converting.
const KEPT: [u8; 5] = [0b011, 0b100, 0b011, 0b011, 0b111];

/// The value of eight ASCII digits (the first in the lowest byte), in a few multiplications.
#[inline]
fn eight_digits(x: u64) -> u64 {
    let x = x.wrapping_sub(splat(b'0'));
    let x = x.wrapping_mul(10).wrapping_add(x >> 8);
    (x & 0x0000_00FF_0000_00FF)
        .wrapping_mul(100 + (1_000_000 << 32))
        .wrapping_add(((x >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32)))
        >> 32
}

/// The mantissa of a number token as an integer, from its integer digits `int` and its `frac`
/// fraction digits at `b[at..]`, with its count of significant digits (from the first non-zero
/// one); the integer is exact when that count is at most 19. Eight fraction digits at a time,
/// the last few too (padded with leading '0's), without a branch per digit. `None` when the
/// count cannot be known cheaply (eight or more leading zeros after `0.`, or the token at the
/// very end of the bytes): the caller then takes the general path.
#[inline]
fn mantissa(int: &[u8], b: &[u8], at: usize, frac: usize) -> Option<(u64, usize)> {
    let word =
        |i: usize| -> Option<u64> { Some(u64::from_le_bytes(b.get(i..i + 8)?.try_into().ok()?)) };
    let mut w: u64 = 0;
    for &c in int {
        w = w.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
    }
    let sig = if w != 0 || int.len() > 1 {
        int.len() + frac
    } else {
        // "0.": the fraction's leading zeros do not count (bytes after the digits are not '0').
        let zeros = (word(at)? ^ splat(b'0')).trailing_zeros() as usize / 8;
        if zeros >= frac.min(8) {
            return None;
        }
        frac - zeros
    };
    let mut i = at;
    let end = at + frac;
    while i + 8 <= end {
        w = w
            .wrapping_mul(100_000_000)
            .wrapping_add(eight_digits(word(i)?));
        i += 8;
    }
    let r = end - i;
    if r > 0 {
        // The r digits moved to the top of the word, '0's below them.
        let x = (word(i)? << (8 * (8 - r))) | (splat(b'0') >> (8 * r));
        w = w
            .wrapping_mul(super::float::POW10[r] as u64)
            .wrapping_add(eight_digits(x));
    }
    Some((w, sig))
}

/// A position in the bytes.
pub(super) struct Cursor<'a> {
    pub(super) b: &'a [u8],
    pub(super) i: usize,
    /// Whether the numbers read are noted in `marks`.
    pub(super) learning: bool,
    /// While a frame is read token by token: where each of its numbers was and what it was for,
    /// to learn the frame's [`Layout`].
    pub(super) marks: Vec<Mark>,
}

/// Eight copies of a byte, for comparing eight bytes at once.
const fn splat(c: u8) -> u64 {
    u64::from_ne_bytes([c; 8])
}

/// What the scanner saw of one number token.
pub(super) struct Token {
    /// Where it starts.
    start: usize,
    /// Digits of the integer part.
    int: usize,
    /// Digits after the point.
    frac: usize,
    /// The explicit exponent, if written and short (`None` if absent, `Some(None)` if too long
    /// to read here).
    exp: Option<Option<i32>>,
}

impl<'a> Cursor<'a> {
    /// Eight bytes from `i` as one little-endian word, if there are eight.
    #[inline]
    fn word(&self, i: usize) -> Option<u64> {
        let chunk = self.b.get(i..i + 8)?;
        Some(u64::from_le_bytes(chunk.try_into().ok()?))
    }

    /// Skips JSON whitespace; runs of spaces (`json.dump(indent=4)` indents a lot) eight bytes
    /// at a time.
    #[inline]
    fn ws(&mut self) {
        loop {
            if let Some(x) = self.word(self.i) {
                let y = x ^ splat(b' ');
                if y == 0 {
                    self.i += 8;
                    continue;
                }
                self.i += (y.trailing_zeros() / 8) as usize;
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

    /// A key without escapes or non-ASCII bytes: eight bytes at a time, up to the first that is
    /// a quote, a backslash, a control character or not ASCII, which must be the closing quote.
    #[inline]
    fn key(&mut self) -> Option<&'a [u8]> {
        self.eat(b'"')?;
        let start = self.i;
        let mut i = start;
        let end = loop {
            let Some(x) = self.word(i) else {
                // Near the end of the bytes: one at a time.
                let rest = self.b.get(i..)?;
                let k = rest
                    .iter()
                    .position(|&c| c == b'"' || c == b'\\' || !(0x20..0x80).contains(&c))?;
                break i + k;
            };
            // High bit per byte: a quote or backslash (zero after the xor), a control byte
            // (< 0x20) or a non-ASCII byte (high bit set already).
            let zero = |y: u64| y.wrapping_sub(splat(1)) & !y;
            let hit =
                (zero(x ^ splat(b'"')) | zero(x ^ splat(b'\\')) | x.wrapping_sub(splat(0x20)) | x)
                    & splat(0x80);
            if hit == 0 {
                i += 8;
                continue;
            }
            break i + (hit.trailing_zeros() / 8) as usize;
        };
        if self.b[end] != b'"' {
            return None;
        }
        self.i = end + 1;
        Some(&self.b[start..end])
    }

    /// Skips a run of ASCII digits, eight at a time; returns its length.
    #[inline]
    fn digits(&mut self) -> usize {
        let start = self.i;
        loop {
            let Some(x) = self.word(self.i) else {
                while self.b.get(self.i).is_some_and(u8::is_ascii_digit) {
                    self.i += 1;
                }
                return self.i - start;
            };
            // Per byte, without carries between bytes: a = c ^ '0' is 0..=9 for a digit; the
            // high bit of ((a & 0x7f) + 0x76) | a is set exactly for the other bytes.
            let a = x ^ splat(b'0');
            let other = (((a & splat(0x7f)) + splat(0x76)) | a) & splat(0x80);
            if other == 0 {
                self.i += 8;
                continue;
            }
            self.i += (other.trailing_zeros() / 8) as usize;
            return self.i - start;
        }
    }

    /// A number token in JSON's grammar, `-? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?`.
    #[inline]
    pub(super) fn number(&mut self) -> Option<Token> {
        let start = self.i;
        // Branch-free: the sign is as likely as not.
        self.i += usize::from(self.peek() == Some(b'-'));
        let int = match self.peek()? {
            b'0' => {
                self.i += 1;
                1
            }
            b'1'..=b'9' => self.digits(),
            _ => return None,
        };
        let mut frac = 0;
        if self.peek() == Some(b'.') {
            self.i += 1;
            frac = self.digits();
            if frac == 0 {
                return None;
            }
        }
        let mut exp = None;
        if matches!(self.peek(), Some(b'e' | b'E')) {
            self.i += 1;
            let neg = match self.peek() {
                Some(b'-') => {
                    self.i += 1;
                    true
                }
                Some(b'+') => {
                    self.i += 1;
                    false
                }
                _ => false,
            };
            let at = self.i;
            let n = self.digits();
            if n == 0 {
                return None;
            }
            exp = Some((n <= 4).then(|| {
                let e = self.b[at..at + n]
                    .iter()
                    .fold(0i32, |e, &c| e * 10 + i32::from(c - b'0'));
                if neg {
                    -e
                } else {
                    e
                }
            }));
        }
        Some(Token {
            start,
            int,
            frac,
            exp,
        })
    }

    /// The token just read, parsed by `str::parse` (`None` if not finite).
    #[inline]
    #[allow(unsafe_code)]
    fn parse(&self, start: usize) -> Option<f64> {
        let token = &self.b[start..self.i];
        debug_assert!(token.is_ascii());
        // SAFETY: `number` admitted only the ASCII bytes `-+.eE0-9`, which are valid UTF-8.
        // (`str::from_utf8` here cost 11 % of the whole replay.)
        let text = unsafe { std::str::from_utf8_unchecked(token) };
        let x: f64 = text.parse().ok()?;
        x.is_finite().then_some(x)
    }

    /// A number token's value, correctly rounded (`None` if not finite): the digits Python
    /// writes go through `float::exact_div`, the rest through `str::parse`; the same bits.
    #[inline]
    pub(super) fn value(&mut self) -> Option<f64> {
        let t = self.number()?;
        let neg = self.b[t.start] == b'-';
        let int_at = t.start + usize::from(neg);
        let int = &self.b[int_at..int_at + t.int];
        let Some((w, sig)) = mantissa(int, self.b, int_at + t.int + 1, t.frac) else {
            return self.parse(t.start);
        };
        let e = match t.exp {
            None => 0,
            Some(Some(e)) => e,
            Some(None) => return self.parse(t.start),
        };
        let k = t.frac as i64 - i64::from(e);
        if sig <= 19 && (0..=21).contains(&k) {
            return super::float::exact_div(w, k as u32, neg);
        }
        self.parse(t.start)
    }

    /// A number that is checked and known to be finite but not converted (`None` if it is not
    /// finite): a required vector's component the frame does not keep.
    #[inline]
    pub(super) fn finite(&mut self) -> Option<()> {
        let t = self.number()?;
        // Below 10^(int + exp) <= 10^308 < f64::MAX: finite without converting.
        let magnitude = match t.exp {
            None => Some(0),
            Some(e) => e.map(|e| e.max(0)),
        };
        if magnitude.is_some_and(|m| t.int as i64 + i64::from(m) <= 308) {
            return Some(());
        }
        self.parse(t.start).map(|_| ())
    }

    /// Notes a number token from `start` to here, when learning a layout.
    #[inline]
    fn mark(&mut self, start: usize, role: Role) {
        if self.learning {
            let end = self.i;
            self.marks.push(Mark { start, end, role });
        }
    }

    /// A required vector: exactly three finite numbers, those of `keep` (bit k for component
    /// k) converted, the others left 0.0 (`TelemetryFrame::from_raw` reads only the kept ones).
    fn vec3(&mut self, field: usize, keep: u8) -> Option<[f64; 3]> {
        self.eat(b'[')?;
        let mut v = [0.0f64; 3];
        for (k, slot) in v.iter_mut().enumerate() {
            if k > 0 {
                self.ws();
                self.eat(b',')?;
            }
            self.ws();
            let start = self.i;
            if keep & (1 << k) != 0 {
                *slot = self.value()?;
                // field < 5, k < 3.
                let (field, comp) = (field as u8, k as u8);
                self.mark(start, Role::Keep { field, comp });
            } else {
                self.finite()?;
                self.mark(start, Role::Finite);
            }
        }
        self.ws();
        self.eat(b']')?;
        Some(v)
    }

    /// Another field's value: a number or a flat array of numbers, checked only.
    fn other(&mut self) -> Option<()> {
        if self.eat(b'[').is_none() {
            let start = self.i;
            self.number()?;
            self.mark(start, Role::Other);
            return Some(());
        }
        self.ws();
        if self.eat(b']').is_some() {
            return Some(());
        }
        loop {
            let start = self.i;
            self.number()?;
            self.mark(start, Role::Other);
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
    pub(super) fn frame(&mut self, step: u64) -> Option<TelemetryFrame> {
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
                    vals[idx] = self.vec3(idx, KEPT[idx])?;
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

impl Cursor<'_> {
    // Frames by their learned layout (see `layout.rs`).

    /// The learned separator `s` at the cursor, skipped.
    #[inline(always)]
    fn expect(&mut self, layout: &Layout, s: Sep) -> Option<()> {
        layout.matches(self.b, self.i, s).then(|| self.i += s.len)
    }

    /// One frame object read by its learned layout (`None` where it departs from it: the
    /// caller reads the frame token by token from the same place).
    #[inline]
    pub(super) fn frame_by(&mut self, layout: &Layout, step: u64) -> Option<TelemetryFrame> {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as in `same`: SSE2 is part of x86-64. (Compiled with it, the number reader
        // and the comparisons inline here.)
        return unsafe { self.frame_by_sse2(layout, step) };
        #[cfg(not(target_arch = "x86_64"))]
        return self.frame_by_body(layout, step);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "sse2")]
    fn frame_by_sse2(&mut self, layout: &Layout, step: u64) -> Option<TelemetryFrame> {
        self.frame_by_body(layout, step)
    }

    #[inline(always)]
    fn frame_by_body(&mut self, layout: &Layout, step: u64) -> Option<TelemetryFrame> {
        let mut vals = [[0.0f64; 3]; 5];
        for &(sep, role) in &layout.steps {
            self.expect(layout, sep)?;
            // The number, sixteen bytes at a time where `number::token` can (one call site:
            // it inlines), else byte by byte.
            let t = number::token(self.b, self.i);
            match role {
                Role::Keep { field, comp } => {
                    let v = match t.and_then(|t| Some((t.end, t.value(self.b)?))) {
                        Some((end, v)) => {
                            self.i = end;
                            v
                        }
                        None => self.value()?,
                    };
                    // Learned in bounds (field < 5, comp < 3); `get_mut` keeps it panic-free.
                    *vals
                        .get_mut(usize::from(field))?
                        .get_mut(usize::from(comp))? = v;
                }
                Role::Finite => match t {
                    Some(t) if t.surely_finite() => self.i = t.end,
                    _ => self.finite()?,
                },
                Role::Other => match t {
                    Some(t) => self.i = t.end,
                    None => {
                        self.number()?;
                    }
                },
            }
        }
        self.expect(layout, layout.last?)?;
        TelemetryFrame::from_raw(step, vals).ok()
    }

    /// One frame object read token by token, its layout learned into `layout`.
    pub(super) fn frame_learning(
        &mut self,
        layout: &mut Layout,
        step: u64,
    ) -> Option<TelemetryFrame> {
        let start = self.i;
        self.marks.clear();
        self.learning = true;
        let frame = self.frame(step);
        self.learning = false;
        if frame.is_some() {
            layout.learn(self.b, start, self.i, &self.marks);
        }
        frame
    }
}

impl Cursor<'_> {
    /// A step key read by the learned gap around it: `before`, 1-19 ASCII digits, `after`
    /// (which starts with the closing quote), whitespace; `None`, the cursor unmoved, on any
    /// departure.
    /// The token-by-token path reads the same bytes into the same step: `before` and `after`
    /// are bytes it read once already, and the digits are a key `step_number` accepts.
    #[inline]
    fn key_by(&mut self, before: &[u8], after: &[u8]) -> Option<u64> {
        let d = self.i + before.len();
        if !same(self.b.get(self.i..d)?, before) {
            return None;
        }
        let (n, step) = number::digit_run(self.b.get(d..)?, 19)?;
        let end = d + n + after.len();
        if !same(self.b.get(d + n..end)?, after) {
            return None;
        }
        // Token by token, whitespace after the colon is skipped whatever its length: `after`
        // may end before some of it (learned where there was less).
        self.i = end;
        self.ws();
        Some(step)
    }
}

/// The frames of `bytes` in file order and whether their steps increase, or `None` when the
/// serde_json path must decide.
pub(super) fn parse(bytes: &[u8]) -> Option<(Vec<TelemetryFrame>, bool)> {
    scan(bytes, true).map(|(frames, sorted, _)| (frames, sorted))
}

/// [`parse`], with frames and step keys read by their learned layout when `by_layout` (else
/// token by token), and the count of frames read by layout.
fn scan(bytes: &[u8], by_layout: bool) -> Option<(Vec<TelemetryFrame>, bool, usize)> {
    let mut c = Cursor {
        b: bytes,
        i: 0,
        learning: false,
        marks: Vec::new(),
    };
    let mut layout = Layout::default();
    c.ws();
    c.eat(b'{')?;
    // About 830 bytes per frame in Bench2Drive's layout; the estimate only avoids regrowth.
    let mut frames: Vec<TelemetryFrame> = Vec::with_capacity((bytes.len() / 700).min(1 << 20));
    let mut sorted = true;
    let mut laid = 0;
    // The bytes between one frame and the next one's step number (`,\n    "`) and between the
    // number and the frame (`": `), learned from the first pair of frames read token by token
    // (as a frame's layout is): the step keys after it are read by comparing those bytes.
    let mut gap: Option<(Vec<u8>, Vec<u8>)> = None;
    let mut from = c.i;
    let mut first = true;
    loop {
        let by_gap = if first || !by_layout {
            None
        } else {
            gap.as_ref()
        };
        let step = match by_gap.and_then(|(before, after)| c.key_by(before, after)) {
            Some(step) => step,
            None => {
                c.i = from;
                if !first {
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
                let quote = c.i;
                let step = step_number(std::str::from_utf8(c.key()?).ok()?).ok()?;
                let close = c.i - 1;
                c.ws();
                c.eat(b':')?;
                c.ws();
                if !first {
                    gap = Some((bytes[from..=quote].to_vec(), bytes[close..c.i].to_vec()));
                }
                step
            }
        };
        let at = c.i;
        let frame = match c.frame_by(&layout, step).filter(|_| by_layout) {
            Some(f) => {
                laid += 1;
                f
            }
            None => {
                c.i = at;
                c.frame_learning(&mut layout, step)?
            }
        };
        if frames.last().is_some_and(|p| step <= p.step) {
            sorted = false;
        }
        frames.push(frame);
        from = c.i;
        first = false;
    }
    c.ws();
    (c.i == bytes.len()).then_some((frames, sorted, laid))
}

#[cfg(test)]
mod tests {
    use super::scan;

    /// A frame in `json.dump(indent=4)`'s layout, numbers varied by `i`.
    fn frame(i: usize) -> String {
        let x = |k: usize| format!("{}.{}", (i * 7 + k) % 13, 1 + (i * 31 + k * 17) % 997);
        let v = |a: usize| {
            format!(
                "[\n            {},\n            -{},\n            {}e-5\n        ]",
                x(a),
                x(a + 1),
                x(a + 2)
            )
        };
        format!(
            "{{\n        \"acceleration\": {},\n        \"angular_velocity\": {},\n        \
             \"forward_vector\": {},\n        \"right_vector\": {},\n        \
             \"location\": {},\n        \"rotation\": {}\n    }}",
            v(0),
            v(3),
            v(6),
            v(9),
            v(12),
            v(15)
        )
    }

    fn file(frames: &[String]) -> String {
        let body: Vec<String> = frames
            .iter()
            .enumerate()
            .map(|(i, f)| format!("    \"{}\": {f}", i + 1))
            .collect();
        format!("{{\n{}\n}}", body.join(",\n"))
    }

    /// Frames read by layout give what token-by-token reading gives, on files whose frames keep
    /// the first one's layout and on files where one frame departs from it in every way the
    /// layout could be fooled by; and the layout is used where it holds.
    #[test]
    fn frames_by_layout_are_frames_token_by_token() {
        let plain: Vec<String> = (0..6).map(frame).collect();
        let (a, sa, laid) = scan(file(&plain).as_bytes(), true).expect("valid");
        let (b, sb, none) = scan(file(&plain).as_bytes(), false).expect("valid");
        assert_eq!((a, sa), (b, sb));
        assert_eq!((laid, none), (5, 0), "frames 2-6 by layout");

        let departures: [(&str, &str); 12] = [
            (
                "\"acceleration\"",
                "\"speed\": 2.5,\n        \"acceleration\"",
            ),
            ("\"rotation\": [", "\"rotation\": [1, "),
            ("\n            ", "\n  "),
            ("\"location\"", "\"locatiom\""),
            ("\"rotation\"", "\"location\""),
            ("e-5", "E-5"),
            ("e-5", "e-999"),
            ("e-5", "e+400"),
            (".", "e3."),
            ("-", "--"),
            ("-", "+"),
            (",", ""),
        ];
        for (from, to) in departures {
            for at in [1, 3, 5] {
                let mut frames = plain.clone();
                frames[at] = frames[at].replacen(from, to, 1);
                let text = file(&frames);
                let with = scan(text.as_bytes(), true);
                let without = scan(text.as_bytes(), false);
                assert_eq!(
                    with.as_ref().map(|(f, s, _)| (f, s)),
                    without.as_ref().map(|(f, s, _)| (f, s)),
                    "{from:?} -> {to:?} in frame {}",
                    at + 1
                );
            }
        }
        // Step keys and the bytes around them.
        let text = file(&plain);
        for (from, to) in [
            (",\n    \"3\": {", ",\n  \"3\": {"),
            (",\n    \"3\": {", ", \"3\" : {"),
            ("\"3\": {", "\"03\": {"),
            ("\"3\": {", "\"3\":{"),
            ("\"3\": {", "\"99999999999999999999\": {"),
            ("\"3\": {", "\"18446744073709551615\": {"),
            ("\"3\": {", "\"3x\": {"),
            ("\"3\": {", "\"\": {"),
            ("\"6\": {", "\"2\": {"),
            ("\n}", ",\n}"),
        ] {
            let text = text.replacen(from, to, 1);
            let with = scan(text.as_bytes(), true);
            let without = scan(text.as_bytes(), false);
            assert_eq!(
                with.as_ref().map(|(f, s, _)| (f, s)),
                without.as_ref().map(|(f, s, _)| (f, s)),
                "{from:?} -> {to:?}"
            );
        }
        // A departure that is valid is learned: the frames after it are read by its layout.
        let mut frames = plain.clone();
        for f in &mut frames[3..] {
            *f = f.replacen(
                "\"acceleration\"",
                "\"speed\": 2.5,\n        \"acceleration\"",
                1,
            );
        }
        let (_, _, laid) = scan(file(&frames).as_bytes(), true).expect("valid");
        assert_eq!(laid, 4, "frames 2, 3 and 5, 6 by layout");
    }
}
