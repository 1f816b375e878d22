//! A number token of the shape Python writes, read sixteen bytes at a time (SSE2, which every
//! x86-64 processor has): where its digits end and their value, without a loop or a branch per
//! digit. The scanner's frames-by-layout path uses it for every number; anything it is not
//! sure of (another shape, the end of the bytes near) is left to the scanner's byte-wise
//! `Cursor::number`, which this must agree with wherever it answers.
//!
//! The shape: `-? int . frac ([eE] [+-]? exp)?` with 1-15 integer digits (no leading zero but a
//! lone `0`), 1-31 fraction digits and 1-3 exponent digits. The token ends where the JSON
//! grammar ends it (the first byte that cannot continue it), as `Cursor::number` does.

#[cfg(target_arch = "x86_64")]
use core::arch::x86_64::{
    __m128i, _mm_add_epi16, _mm_and_si128, _mm_andnot_si128, _mm_cmpeq_epi8, _mm_cmplt_epi8,
    _mm_cvtsi128_si32, _mm_madd_epi16, _mm_max_epu8, _mm_movemask_epi8, _mm_mullo_epi16,
    _mm_packs_epi32, _mm_set1_epi16, _mm_set1_epi8, _mm_set_epi16, _mm_set_epi64x, _mm_setr_epi8,
    _mm_srli_epi16, _mm_srli_si128, _mm_sub_epi8,
};

/// What [`token`] read: the token's end, its digits' extents and its exponent.
#[derive(Clone, Copy, Debug)]
pub(super) struct Token {
    /// The byte after the token.
    pub end: usize,
    /// Whether it starts with `-`.
    pub neg: bool,
    /// Where the integer digits start, and how many there are.
    pub int_at: usize,
    /// Integer digits (1-15).
    pub int_len: usize,
    /// Fraction digits (1-31); they start at `int_at + int_len + 1`.
    pub frac_len: usize,
    /// The written exponent (0 when absent).
    pub exp: i32,
}

/// `10^k` as u64, k <= 19.
#[inline(always)]
fn pow10(k: usize) -> u64 {
    super::float::POW10[k] as u64
}

/// The run of 1 to `max` ASCII digits that starts `b`: its length and value (`None` when there
/// is none, or more than `max` digits; `max` <= 19, so the value fits).
#[inline]
pub(super) fn digit_run(b: &[u8], max: usize) -> Option<(usize, u64)> {
    let n = b
        .iter()
        .take(max + 1)
        .take_while(|c| c.is_ascii_digit())
        .count();
    if n == 0 || n > max {
        return None;
    }
    Some((
        n,
        b[..n].iter().fold(0, |v, &c| v * 10 + u64::from(c - b'0')),
    ))
}

/// Sixteen bytes from `i`, if there are sixteen.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
#[inline]
fn load(b: &[u8], i: usize) -> Option<__m128i> {
    let x = u128::from_le_bytes(b.get(i..i.checked_add(16)?)?.try_into().ok()?);
    // Two halves into one register (compiled to one unaligned load).
    Some(_mm_set_epi64x((x >> 64) as i64, x as i64))
}

/// Bit j set when byte j of `v` is an ASCII digit.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
#[inline]
fn digit_mask(v: __m128i) -> u32 {
    let t = _mm_sub_epi8(v, _mm_set1_epi8(b'0' as i8));
    let nine = _mm_set1_epi8(9);
    // Unsigned t <= 9 exactly for '0'..='9'.
    _mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(t, nine), nine)) as u32
}

/// How many of the 16 bytes at `i` are '0' before any other (16: all).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
#[inline]
fn leading_zeros(b: &[u8], i: usize) -> Option<usize> {
    let zeros = _mm_movemask_epi8(_mm_cmpeq_epi8(load(b, i)?, _mm_set1_epi8(b'0' as i8))) as u32;
    Some((!zeros).trailing_zeros().min(16) as usize)
}

/// Byte-wise targets count nothing here (never reached: [`token`] answers `None` there).
#[cfg(not(target_arch = "x86_64"))]
#[inline]
fn leading_zeros(_b: &[u8], _i: usize) -> Option<usize> {
    None
}

/// The value of the `n` (<= 16) digits that end at `end`: the 16 bytes before `end` read at
/// once, those before the `n` digits taken as zeros. `None` when `end < 16`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
#[inline]
fn value_of(b: &[u8], end: usize, n: usize) -> Option<u64> {
    let v = load(b, end.checked_sub(16)?)?;
    let d = _mm_sub_epi8(v, _mm_set1_epi8(b'0' as i8));
    // Bytes before the digits: index < 16 - n (n <= 16, so the count fits an i8).
    let index = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    let before = _mm_cmplt_epi8(index, _mm_set1_epi8((16 - n) as i8));
    let d = _mm_andnot_si128(before, d);
    // Pairs of digits (the first in the low byte of each 16-bit lane): first * 10 + second.
    let p = _mm_add_epi16(
        _mm_mullo_epi16(_mm_and_si128(d, _mm_set1_epi16(0xFF)), _mm_set1_epi16(10)),
        _mm_srli_epi16(d, 8),
    );
    // Fours: pair * 100 + next pair, in 32-bit lanes.
    let q = _mm_madd_epi16(p, _mm_set_epi16(1, 100, 1, 100, 1, 100, 1, 100));
    // Eights: back to 16-bit lanes (each < 10,000), four * 10,000 + next four.
    let r = _mm_madd_epi16(
        _mm_packs_epi32(q, q),
        _mm_set_epi16(1, 10_000, 1, 10_000, 1, 10_000, 1, 10_000),
    );
    let hi = _mm_cvtsi128_si32(r) as u32;
    let lo = _mm_cvtsi128_si32(_mm_srli_si128(r, 4)) as u32;
    Some(u64::from(hi) * 100_000_000 + u64::from(lo))
}

/// The number token at `b[i..]` if it has the shape above and sixteen bytes can be read past
/// each part of it; else `None` (the caller reads it byte by byte).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn token(b: &[u8], i: usize) -> Option<Token> {
    #[allow(unsafe_code)]
    // SAFETY: the only requirement of a `target_feature` function is that the processor has
    // the feature, and SSE2 is part of x86-64 itself (every x86-64 processor has it; Rust's
    // x86_64 targets enable it). The functions read memory only through checked slices.
    unsafe {
        token_sse2(b, i)
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
#[inline]
fn token_sse2(b: &[u8], i: usize) -> Option<Token> {
    let neg = *b.get(i)? == b'-';
    let int_at = i + usize::from(neg);
    // 32 bytes from the first digit hold the whole mantissa of what Python writes: the digit
    // masks of both parts come from the same two loads, in parallel.
    let (v0, v1) = (load(b, int_at)?, load(b, int_at + 16)?);
    let m = digit_mask(v0) | digit_mask(v1) << 16;
    let int_len = (!m).trailing_zeros() as usize;
    // 1-15 digits, no leading zero, then the point.
    if int_len == 0
        || int_len > 15
        || (int_len > 1 && b[int_at] == b'0')
        || b.get(int_at + int_len) != Some(&b'.')
    {
        return None;
    }
    let frac_at = int_at + int_len + 1;
    let mut frac_len = (!(m >> (int_len + 1))).trailing_zeros() as usize;
    if int_len + 1 + frac_len >= 32 {
        // The fraction may go on past the 32 bytes: its own 32.
        let m = digit_mask(load(b, frac_at)?) | digit_mask(load(b, frac_at + 16)?) << 16;
        frac_len = (!m).trailing_zeros() as usize;
    }
    if frac_len == 0 || frac_len == 32 {
        return None;
    }
    let mut end = frac_at + frac_len;
    let mut exp = 0;
    if matches!(b.get(end), Some(b'e' | b'E')) {
        let sign = b.get(end + 1).copied();
        let at = end + 1 + usize::from(matches!(sign, Some(b'-' | b'+')));
        let (n, e) = digit_run(b.get(at..)?, 3)?;
        // At most 999.
        let e = e as i32;
        exp = if sign == Some(b'-') { -e } else { e };
        end = at + n;
    }
    Some(Token {
        end,
        neg,
        int_at,
        int_len,
        frac_len,
        exp,
    })
}

/// Byte-wise targets have no fast reader: every number goes to the scanner's own.
#[cfg(not(target_arch = "x86_64"))]
#[inline]
pub(super) fn token(_b: &[u8], _i: usize) -> Option<Token> {
    None
}

/// Byte-wise targets convert nothing here (never reached: [`token`] answers `None` there).
#[cfg(not(target_arch = "x86_64"))]
#[inline]
fn value_of(_b: &[u8], _end: usize, _n: usize) -> Option<u64> {
    None
}

impl Token {
    /// The token's value, correctly rounded, when its significant digits number at most 19
    /// and its exponent of ten (`exp - frac_len`) lies in -21..=0 (`float::exact_div`'s
    /// domain); else `None` (the caller converts the token otherwise).
    #[inline(always)]
    pub(super) fn value(&self, b: &[u8]) -> Option<f64> {
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as in `token`: SSE2 is part of x86-64.
        unsafe {
            self.value_sse2(b)
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.value_sse2(b)
    }

    #[cfg_attr(target_arch = "x86_64", target_feature(enable = "sse2"))]
    #[inline]
    fn value_sse2(&self, b: &[u8]) -> Option<f64> {
        // Few branches: the digit counts vary from number to number, and a mispredicted
        // branch costs more than the work it would save.
        let k = self.frac_len as i32 - self.exp;
        let frac_at = self.int_at + self.int_len + 1;
        let frac_end = frac_at + self.frac_len;
        let int_zero = self.int_len == 1 && b.get(self.int_at) == Some(&b'0');
        // Significant digits: the fraction's leading zeros are not, after "0." (counted among
        // its first 16 bytes; after 16 zeros more may follow: not known here).
        let sig = if int_zero {
            let lead = leading_zeros(b, frac_at)?;
            if lead == 16 {
                return None;
            }
            self.frac_len - lead.min(self.frac_len)
        } else {
            self.int_len + self.frac_len
        };
        if !(0..=21).contains(&k) || sig > 19 {
            return None;
        }
        let frac = if self.frac_len <= 16 {
            value_of(b, frac_end, self.frac_len)?
        } else {
            let head = value_of(b, frac_end - 16, self.frac_len - 16)?;
            head.wrapping_mul(pow10(16))
                .wrapping_add(value_of(b, frac_end, 16)?)
        };
        let w = if int_zero {
            frac
        } else {
            value_of(b, self.int_at + self.int_len, self.int_len)?
                .wrapping_mul(pow10(self.frac_len.min(19)))
                .wrapping_add(frac)
        };
        super::float::exact_div(w, k as u32, self.neg)
    }

    /// Whether the value is finite, known without converting: below `10^(int_len + exp)`.
    #[inline]
    pub(super) fn surely_finite(&self) -> bool {
        self.int_len as i32 + self.exp.max(0) <= 308
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::{token, value_of};

    #[test]
    fn sixteen_digits_at_a_time() {
        let text = b"xxxxxxxxxxxxxxxx1234567890123456789,yyyyyyyyyyyyyyyy";
        let at = 16;
        for n in 0..=16 {
            let end = at + n;
            let want: u64 = std::str::from_utf8(&text[at..end])
                .expect("ascii")
                .parse()
                .unwrap_or(0);
            #[allow(unsafe_code)]
            // SAFETY: SSE2 is part of x86-64 (see `token`).
            let got = unsafe { value_of(text, end, n) };
            assert_eq!(got, Some(want), "{n} digits");
        }
    }

    #[test]
    fn tokens_end_where_json_ends_them() {
        let pad = " ".repeat(40);
        // Last: whether `value` converts it (<= 19 significant digits, 10^-21..=10^0).
        for (t, end, neg, int_len, frac_len, exp, converts) in [
            ("0.49865996837615967,", 19, false, 1, 17, 0, true),
            ("-4.4775766582461074e-5\n", 22, true, 1, 16, -5, true),
            ("1520.0]", 6, false, 4, 1, 0, true),
            ("-3310.25E+012 ", 13, true, 4, 2, 12, false),
            ("7.5.", 3, false, 1, 1, 0, true),
            // Mantissas reaching past the first 32 bytes.
            (
                "123456789012345.12345678901234567,",
                33,
                false,
                15,
                17,
                0,
                false,
            ),
            (
                "-0.0000000000000000000000000000012 ",
                34,
                true,
                1,
                31,
                0,
                false,
            ),
            (
                "0.0000000000000012345678901234567e3]",
                35,
                false,
                1,
                31,
                3,
                false,
            ),
        ] {
            // Bytes before the token too, as in a file: the digits are read 16 bytes back from
            // where they end.
            let text = format!("{pad}{t}{pad}");
            let got = token(text.as_bytes(), pad.len()).expect(t);
            assert_eq!(
                (
                    got.end - pad.len(),
                    got.neg,
                    got.int_len,
                    got.frac_len,
                    got.exp
                ),
                (end, neg, int_len, frac_len, exp),
                "{t}"
            );
            let value: f64 = t[..end].parse().expect("a number");
            assert_eq!(
                got.value(text.as_bytes()).map(f64::to_bits),
                converts.then(|| value.to_bits()),
                "{t}"
            );
        }
        for t in [
            "01.5", "1", "1.", ".5", "1.5e", "1.5e+", "1.5e1234", "-", "+1.5", "1.5e-x",
        ] {
            assert!(token(format!("{t}{pad}").as_bytes(), 0).is_none(), "{t}");
        }
    }
}
