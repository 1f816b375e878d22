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
        match u64::try_from(d) {
            Ok(d) => small(w, d),
            Err(_) => large(w, d),
        }
    };
    // The sign without a branch (it is as likely as not).
    Some(f64::from_bits(x.to_bits() | u64::from(neg) << 63))
}

/// `w / d` correctly rounded, for `d = 10^k < 2^64`: `n = w * 2^s` with bit lengths chosen so
/// that `2^62 < q = n / d < 2^64` (n has 63 + bit length of d bits), one 128-by-64-bit division.
#[inline]
fn small(w: u64, d: u64) -> f64 {
    let s = 63 + (64 - d.leading_zeros()) - (64 - w.leading_zeros());
    let n = u128::from(w) << s;
    let (q, r) = div_wide(n, d);
    round(q, r != 0, s)
}

/// `w / d` correctly rounded, for `d = 10^20` or `10^21`: `w` at the top of a u128, the quotient
/// (at least 57 bits) cut to 64 bits with what is cut off as sticky.
#[inline]
fn large(w: u64, d: u128) -> f64 {
    let s = w.leading_zeros() + 64;
    let n = u128::from(w) << s;
    let q = n / d;
    let r = n - q * d;
    let cut = 64u32.saturating_sub(q.leading_zeros());
    let sticky = r != 0 || q & ((1u128 << cut) - 1) != 0;
    round((q >> cut) as u64, sticky, s - cut)
}

/// `q * 2^-s` rounded to 53 bits, half to even; `sticky`: the exact value is above `q * 2^-s`.
/// `q` has at least 55 bits.
#[inline]
fn round(q: u64, sticky: bool, s: u32) -> f64 {
    let shift = 11 - q.leading_zeros();
    let mut m = q >> shift;
    let rem = q & ((1u64 << shift) - 1);
    let half = 1u64 << (shift - 1);
    let mut p = shift as i32 - s as i32;
    // Up when above half, or at half with something below or an odd m: no branch (as likely as
    // not).
    let up = (rem > half) | ((rem == half) & (sticky | (m & 1 == 1)));
    m += u64::from(up);
    if m == 1 << 53 {
        m >>= 1;
        p += 1;
    }
    // m < 2^53 and -127 <= p <= 11: both exact, the product normal and exact.
    m as f64 * f64::from_bits(((1023 + p) as u64) << 52)
}

/// `(n / d, n % d)` for a quotient below 2^64 (`n >> 64 < d`).
#[inline]
fn div_wide(n: u128, d: u64) -> (u64, u64) {
    #[cfg(target_arch = "x86_64")]
    if ((n >> 64) as u64) < d {
        let (q, r): (u64, u64);
        #[allow(unsafe_code)]
        // SAFETY: `div` divides rdx:rax by d; it faults only when the quotient does not fit 64
        // bits, which the check above rules out (n >> 64 < d). It touches no memory.
        // (The u128 division routine costs about twice as much here.)
        unsafe {
            std::arch::asm!(
                "div {d}",
                d = in(reg) d,
                inout("rax") n as u64 => q,
                inout("rdx") (n >> 64) as u64 => r,
                options(pure, nomem, nostack),
            );
        }
        return (q, r);
    }
    let q = n / u128::from(d);
    (q as u64, (n - q * u128::from(d)) as u64)
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
