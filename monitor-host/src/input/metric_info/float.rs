//! Exact conversion of the decimal numbers Python writes to the nearest f64, from the digits the
//! scanner has already read: the same bits as `str::parse::<f64>` (round half to even), by
//! construction and by test.
//!
//! Python's `repr` of a CARLA float32 widened to double has 16 or 17 significant digits and a
//! decimal exponent between -21 and 0 (`0.49865996837615967`, `4.4775766582461074e-05`). For
//! such a number the mantissa `w` (at most 19 digits) fits a u64, and `w / 10^k` (k <= 21) is
//! found in integers: `w` times a 128-bit reciprocal of `10^k`, whose product's top 64 bits and
//! sticky bit are known exactly (see [`by_reciprocal`] for why), rounded to 53 bits half to
//! even (a division, even Clinger's one `divsd` for short mantissas, costs more). Anything else
//! (more digits, other exponents) goes to `str::parse`, exact too.

/// `10^k` for k = 0..=21 (the scanner's digit assembly uses it too).
pub(super) const POW10: [u128; 22] = {
    let mut t = [1u128; 22];
    let mut k = 1;
    while k < 22 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
};

/// `floor(2^(127 + L) / 10^k)` for k = 1..=21, where L is the bit length of `10^k`: the
/// reciprocal of `10^k` with its top bit at bit 127 (for k = 0, unused).
const RECIP: [u128; 22] = {
    let mut t = [0u128; 22];
    let mut k = 1;
    while k < 22 {
        let d = POW10[k];
        let bits = 127 + (128 - d.leading_zeros());
        // Long division of 2^bits by d, one bit at a time (d < 2^70: no overflow).
        let (mut r, mut q) = (1u128, 0u128);
        let mut i = 0;
        while i < bits {
            r <<= 1;
            q <<= 1;
            if r >= d {
                r -= d;
                q |= 1;
            }
            i += 1;
        }
        t[k] = q;
        k += 1;
    }
    t
};

/// The value `w * 10^-k` correctly rounded, or `None` where this path does not apply (the caller
/// then parses the token with `str::parse`). `w` is the mantissa's digits without the decimal
/// point (exactly, so at most 19 significant digits).
#[inline]
pub(super) fn exact_div(w: u64, k: u32, neg: bool) -> Option<f64> {
    if k > 21 {
        return None;
    }
    // All three cases computed and one picked without a branch (which case it is varies from
    // number to number): an integer (k = 0; the cast rounds correctly, half to even), zero, or
    // the quotient.
    let x = if w == 0 {
        0
    } else if k == 0 {
        (w as f64).to_bits()
    } else {
        by_reciprocal(w, k)?.to_bits()
    };
    // The sign without a branch (it is as likely as not).
    Some(f64::from_bits(x | u64::from(neg) << 63))
}

/// `w / 10^k` correctly rounded by multiplying with the truncated reciprocal [`RECIP`] (two
/// 64-by-64-bit multiplications, no division), for 1 <= k <= 21 and w > 0.
///
/// With `w` shifted to its top bit (`v = w << z`, `2^63 <= v < 2^64`) and `R = RECIP[k]`, the
/// exact scaled value `T = v * 2^(127 + L) / 10^k` (L: the bit length of `10^k`) is
/// `T = P + d` with `0 < d < v < 2^64`, for the product `P = v * R` (192 bits, `hi:mid:lo`):
/// `R` is `2^(127 + L) / 10^k` cut to an integer, and that quotient is never an integer for
/// k >= 1.
///
/// What lies below `T`'s top 64 bits, `T mod 2^128`, is a multiple of `2^128 / 5^k` (since
/// `127 + L >= 128 + k`, `T mod 2^128 = 2^128 * j / 5^k` for an integer `j < 5^k`), and
/// `2^128 / 5^k > 2^79` for k <= 21. So either `T` is exact in 64 bits (`j = 0`), and then
/// `P = T - d` borrows: `mid` is all ones and `T`'s top bits are `hi + 1`; or `T mod 2^128`
/// lies in `[2^79, 2^128 - 2^79]`, and then `P`'s part below `hi` is that minus `d`: no borrow,
/// `mid` is not all ones, `hi` is `T`'s top bits and something non-zero lies below them. Either
/// way the top bits and the sticky bit are known exactly, and [`round`] rounds them. The test
/// `bit_identical_to_str_parse_on_random_numbers` checks it against `str::parse`, exact values
/// (`exact_binary_values`) included.
#[inline]
fn by_reciprocal(w: u64, k: u32) -> Option<f64> {
    if k == 0 || w == 0 {
        return None;
    }
    // (k <= 21: both tables have the entry.)
    let r = *RECIP.get(k as usize)?;
    let l = 128 - POW10.get(k as usize)?.leading_zeros();
    let z = w.leading_zeros();
    let v = u128::from(w << z);
    let p_hi = v * (r >> 64);
    let p_lo = v * (r & u128::from(u64::MAX));
    // P = p_hi << 64 + p_lo: its top two words.
    let (mid, carry) = (p_hi as u64).overflowing_add((p_lo >> 64) as u64);
    let hi = ((p_hi >> 64) as u64) + u64::from(carry);
    // The value is T's top bits times 2^-(L + z - 1).
    let s = l + z - 1;
    let exact = mid == u64::MAX;
    Some(round(hi.wrapping_add(u64::from(exact)), !exact, s))
}

/// `q * 2^-s` rounded to 53 bits, half to even; `sticky`: the exact value is above `q * 2^-s`.
/// `q` has at least 55 bits.
#[inline]
fn round(q: u64, sticky: bool, s: u32) -> f64 {
    let shift = 11 - q.leading_zeros();
    let mut m = q >> shift;
    let rem = q & ((1u64 << shift) - 1);
    let half = 1u64 << (shift - 1);
    let p = shift as i32 - s as i32;
    // Up when above half, or at half with something below or an odd m: no branch (as likely as
    // not).
    let up = (rem > half) | ((rem == half) & (sticky | (m & 1 == 1)));
    m += u64::from(up);
    // The value is m * 2^p with 2^52 <= m <= 2^53 and -127 <= p <= 11: normal. Its bits are
    // the biased exponent of 2^(p + 52) (1075 + p) above m's 52 stored bits; adding m to
    // (1074 + p) << 52 puts m's leading bit into the exponent, and m = 2^53 (rounded up past
    // 53 bits) carries into it as it should.
    f64::from_bits((((1074 + p) as u64) << 52) + m)
}

#[cfg(test)]
mod tests {
    use super::exact_div;

    /// SplitMix64, for reproducible cases without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
    }

    /// The digits of `text` as the scanner reads them (sign, mantissa, digits after the point,
    /// exponent) converted by `exact_div`, when the path applies.
    fn via_digits(text: &str) -> Option<f64> {
        let (neg, t) = match text.strip_prefix('-') {
            Some(t) => (true, t),
            None => (false, text),
        };
        let (mant, exp) = match t.find(['e', 'E']) {
            Some(i) => (&t[..i], t[i + 1..].parse::<i32>().ok()?),
            None => (t, 0),
        };
        let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
        let digits = format!("{int}{frac}");
        let sig = digits.trim_start_matches('0');
        if sig.len() > 19 {
            return None;
        }
        let w: u64 = if sig.is_empty() { 0 } else { sig.parse().ok()? };
        let k = frac.len() as i32 - exp;
        if k < 0 {
            return None;
        }
        exact_div(w, k as u32, neg)
    }

    fn check(text: &str, hits: &mut usize) {
        let want: f64 = text.parse().unwrap();
        if let Some(got) = via_digits(text) {
            *hits += 1;
            assert_eq!(got.to_bits(), want.to_bits(), "{text}: {got:e} vs {want:e}");
        }
    }

    #[test]
    fn bit_identical_to_str_parse_on_random_numbers() {
        let mut rng = Rng(0x5D5_2026);
        let mut hits = 0;
        let cases = std::env::var("SDS_FLOAT_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(300_000);
        for _ in 0..cases {
            // Python's repr of a float32 widened to double (Rust's shortest form: same digits).
            let f = f32::from_bits(rng.next() as u32);
            if f.is_finite() {
                let x = f64::from(f);
                check(&format!("{x}"), &mut hits);
                check(&format!("{x:e}"), &mut hits);
            }
            // Any double, shortest and with 17 digits.
            let x = f64::from_bits(rng.next());
            if x.is_finite() {
                check(&format!("{x:e}"), &mut hits);
                check(&format!("{x:.16e}"), &mut hits);
            }
            // Scaled like sensor values: 1e-22 .. 1e4.
            let y = (rng.next() >> 11) as f64 / (1u64 << 53) as f64
                * 10f64.powi((rng.next() % 27) as i32 - 22);
            check(&format!("{y}"), &mut hits);
            check(&format!("{y:.17}"), &mut hits);
            // Random digit strings: 1-19 digits, a point anywhere, an exponent or none.
            let n = 1 + (rng.next() % 19) as usize;
            let mut s: String = (0..n)
                .map(|_| char::from(b'0' + (rng.next() % 10) as u8))
                .collect();
            let at = (rng.next() % (n as u64 + 1)) as usize;
            if at < n {
                s.insert(at, '.');
                if s.starts_with('.') {
                    s.insert(0, '0');
                }
            }
            match rng.next() % 3 {
                0 => s.push_str(&format!("e-{}", rng.next() % 25)),
                1 => s.push_str(&format!("e{}", rng.next() % 5)),
                _ => {}
            }
            check(&s, &mut hits);
            // Exact ties and their neighbours: (2^53 + odd) * 5^j / 10^j, j <= 4.
            let odd = ((1u64 << 53) + (rng.next() % (1u64 << 53))) | 1;
            let j = (rng.next() % 5) as u32;
            let w = odd * 5u64.pow(j);
            for w in [w - 1, w, w + 1] {
                let mut t = w.to_string();
                if j > 0 {
                    t.insert(t.len() - j as usize, '.');
                }
                check(&t, &mut hits);
            }
        }
        assert!(hits > cases, "the exact path was taken {hits} times");
    }

    /// Values exact in binary (a CARLA float32 such as `1520.4012451171875` is printed exactly
    /// when its expansion is short): the reciprocal's product borrows there
    /// (`by_reciprocal`'s `mid` all ones); their decimal neighbours do not.
    #[test]
    fn exact_binary_values() {
        let mut rng = Rng(0xE8AC7);
        let mut hits = 0;
        for _ in 0..200_000 {
            // m * 2^-e, m below 2^(24..=60), written exactly: m * 5^e with a point e digits in.
            let e = (rng.next() % 20) as u32;
            let m = rng.next() >> (4 + rng.next() % 40);
            let Some(digits) = u128::from(m).checked_mul(5u128.pow(e)) else {
                continue;
            };
            for d in [digits.saturating_sub(1), digits, digits + 1] {
                let mut t = format!("{d:0>width$}", width = e as usize + 1);
                if e > 0 {
                    t.insert(t.len() - e as usize, '.');
                }
                check(&t, &mut hits);
            }
        }
        assert!(hits > 300_000, "the exact path was taken {hits} times");
    }

    #[test]
    fn edges() {
        let mut hits = 0;
        for t in [
            "0",
            "-0",
            "0.0",
            "-0.0",
            "0e5",
            "1",
            "9007199254740993",
            "9007199254740995",
            "18446744073709551615",
            "1e-21",
            "9999999999999999999e-21",
            "0.49865996837615967",
            "-0.0015013996744528413",
            "4.4775766582461074e-05",
            "1520.0",
            "-3310.0",
            "0.000000000000000000001",
            "1.7976931348623157",
            "2.2250738585072014",
        ] {
            check(t, &mut hits);
        }
        assert!(hits >= 17, "{hits}");
    }
}
