//! Exact conversion of the decimal numbers Python writes to the nearest f64, from the digits the
//! scanner has already read: the same bits as `str::parse::<f64>` (round half to even), by
//! construction and by test.
//!
//! Python's `repr` of a CARLA float32 widened to double has 16 or 17 significant digits and a
//! decimal exponent between -21 and 0 (`0.49865996837615967`, `4.4775766582461074e-05`). For
//! such a number the mantissa `w` (at most 19 digits) fits a u64 and `10^k` (k <= 21) a u128, so
//! `w / 10^k` is found exactly in integers: `w` is shifted to the top of a u128, divided by
//! `10^k`, and the quotient (at least 57 bits) rounded to 53 bits with the remainder as the sticky
//! bit. Anything else (more digits, other exponents) goes to `str::parse`, which is exact too.

/// `10^k` for k = 0..=21.
const POW10: [u128; 22] = {
    let mut t = [1u128; 22];
    let mut k = 1;
    while k < 22 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
};

/// The value `w * 10^-k` correctly rounded, or `None` where this path does not apply (the caller
/// then parses the token with `str::parse`). `w` is the mantissa's digits without the decimal
/// point (exactly, so at most 19 significant digits).
#[inline]
pub(super) fn exact_div(w: u64, k: u32, neg: bool) -> Option<f64> {
    let x = if w == 0 {
        0.0
    } else {
        let d = *POW10.get(k as usize)?;
        // n = w * 2^s with the quotient below 2^64 when 10^k fits a u64 (one hardware division
        // in the u128 routine), else w at the top of the u128; either way q has >= 57 bits.
        // (With bit lengths a of w and b of 10^k, n has 63 + b bits and 2^62 < q < 2^64.)
        let s = if d >> 64 == 0 {
            63 + (128 - d.leading_zeros()) - (64 - w.leading_zeros())
        } else {
            w.leading_zeros() + 64
        };
        let n = u128::from(w) << s;
        let q = n / d;
        let r = n - q * d;
        let bits = 128 - q.leading_zeros();
        let shift = bits - 53;
        let mut m = (q >> shift) as u64;
        let rem = q & ((1u128 << shift) - 1);
        let half = 1u128 << (shift - 1);
        let mut p = shift as i32 - s as i32;
        if rem > half || (rem == half && (r != 0 || m & 1 == 1)) {
            m += 1;
            if m == 1 << 53 {
                m >>= 1;
                p += 1;
            }
        }
        // m < 2^53 and -127 <= p <= 75: both exact, the product normal and exact.
        m as f64 * f64::from_bits(((1023 + p) as u64) << 52)
    };
    Some(if neg { -x } else { x })
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
            let odd = (1u64 << 53) + (rng.next() % (1u64 << 53)) | 1;
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
