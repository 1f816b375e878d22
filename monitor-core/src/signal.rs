//! Per-frame signal kernels (docs/SCORE.md §3), shared bit for bit by the monitor, the host's
//! frame builder and the batch reference.
//!
//! micromath is called as a function (`F32Ext::sqrt(x)`), never as a method: on the host,
//! `x.sqrt()` would silently resolve to std's IEEE square root and the host and firmware
//! results would differ.

use micromath::F32Ext;

/// `pi / 180` in f32: degrees to radians.
pub const DEG_TO_RAD: f32 = core::f32::consts::PI / 180.0;

/// The unnormalised 2-D dot product `a[0]*b[0] + a[1]*b[1]`, in that order.
///
/// ```
/// assert_eq!(monitor_core::signal::dot2([3.0, 4.0], [0.5, -1.0]), -2.5);
/// ```
#[inline]
pub fn dot2(a: [f32; 2], b: [f32; 2]) -> f32 {
    a[0] * b[0] + a[1] * b[1]
}

/// `hypot(x, y)`: the magnitude of the 2-D acceleration.
///
/// micromath's square root is a one-instruction bit trick with up to ~6 % error
/// (`sqrt(2.0) == 1.5`). Each Newton step `r = 0.5 * (r + s / r)` squares the relative error
/// (6e-2 -> 1.7e-3 -> 1.5e-6 -> ~1e-12), so three steps in plain f32 arithmetic reach the
/// correctly rounded root within 1 ulp (two would leave up to ~13 ulp), and, being IEEE
/// operations in a fixed order, give the same bits on every target.
///
/// Steps: `s = x*x + y*y` (in that order); `s == 0` gives 0, NaN gives NaN, an infinite input
/// gives infinity. When `s` overflows (finite inputs beyond ~1.8e19) or falls below the normal
/// range (inputs below ~1e-19, where the bit trick is far off), `x` and `y` are first scaled by
/// `2^-100` or `2^100` and the root scaled back: powers of two, so the scaling itself is exact and
/// the normal range never takes that path.
///
/// ```
/// use monitor_core::signal::hypot2;
/// assert_eq!(hypot2(3.0, 4.0), 5.0);
/// assert_eq!(hypot2(0.0, 0.0), 0.0);
/// assert_eq!(hypot2(1e20, 0.0), 1e20);
/// assert!(hypot2(f32::NAN, 0.0).is_nan());
/// ```
#[inline]
pub fn hypot2(x: f32, y: f32) -> f32 {
    const TWO_100: f32 = 1_267_650_600_228_229_401_496_703_205_376.0; // 2^100
    const TWO_M100: f32 = 1.0 / TWO_100; // 2^-100, exact
    let s = x * x + y * y;
    if s.is_nan() {
        s
    } else if s == f32::INFINITY {
        if x.is_infinite() || y.is_infinite() {
            f32::INFINITY
        } else {
            let (a, b) = (x * TWO_M100, y * TWO_M100);
            newton_sqrt(a * a + b * b) * TWO_100
        }
    } else if s < f32::MIN_POSITIVE {
        if x == 0.0 && y == 0.0 {
            0.0
        } else {
            let (a, b) = (x * TWO_100, y * TWO_100);
            newton_sqrt(a * a + b * b) * TWO_M100
        }
    } else {
        newton_sqrt(s)
    }
}

/// The square root of a normal, finite, positive `s`: micromath's seed and three Newton steps.
#[inline]
fn newton_sqrt(s: f32) -> f32 {
    let mut r = F32Ext::sqrt(s);
    r = 0.5 * (r + s / r);
    r = 0.5 * (r + s / r);
    0.5 * (r + s / r)
}

/// Lateral excess `max(0, |lat_err| - slack)` (docs/SCORE.md §3); NaN stays NaN.
///
/// ```
/// assert_eq!(monitor_core::signal::excess(-1.0, 0.75), 0.25);
/// assert_eq!(monitor_core::signal::excess(0.5, 0.82), 0.0);
/// ```
#[inline]
pub fn excess(lat_err: f32, slack: f32) -> f32 {
    let d = if lat_err < 0.0 { -lat_err } else { lat_err };
    let e = d - slack;
    if e > 0.0 || e.is_nan() {
        e
    } else {
        0.0
    }
}

/// Round to the nearest integer, ties to even (numpy's `round`), exact for every f32.
///
/// Adding and subtracting 2^23 rounds in the FPU's default mode (nearest, ties to even); values
/// of magnitude 2^23 or more are integers already, and NaN passes through.
///
/// ```
/// use monitor_core::signal::round_half_even;
/// assert_eq!(round_half_even(0.5), 0.0);
/// assert_eq!(round_half_even(1.5), 2.0);
/// assert_eq!(round_half_even(-2.5), -2.0);
/// ```
#[inline]
pub fn round_half_even(x: f32) -> f32 {
    const MAGIC: f32 = 8_388_608.0; // 2^23
    if (0.0..MAGIC).contains(&x) {
        (x + MAGIC) - MAGIC
    } else if x < 0.0 && x > -MAGIC {
        (x - MAGIC) + MAGIC
    } else {
        x
    }
}

/// Phase unwrap with period 2π, restarted at `w[0]` (docs/SCORE.md §5, legacy profile):
/// `u_0 = w_0`, `u_i = w_i - 2π Σ_{j=1..i} round_half_even((w_j - w_{j-1}) / 2π)`.
/// Writes `min(w.len(), out.len())` values.
///
/// ```
/// let mut u = [0.0f32; 3];
/// monitor_core::signal::unwrap(&[0.0, 7.0, 7.5], &mut u);
/// assert_eq!(u[1], 7.0 - core::f32::consts::TAU);
/// ```
pub fn unwrap(w: &[f32], out: &mut [f32]) {
    const TAU: f32 = core::f32::consts::TAU;
    let mut turns = 0.0f32;
    let mut prev: Option<f32> = None;
    for (o, &x) in out.iter_mut().zip(w) {
        if let Some(p) = prev {
            turns += round_half_even((x - p) / TAU);
        }
        *o = x - TAU * turns;
        prev = Some(x);
    }
}
