//! Savitzky–Golay filter: window 7, polynomial order 2, edge mode "interp" (docs/SCORE.md §5).
//!
//! The least-squares quadratic through 7 samples at `x = -3..=3` is written with the orthogonal
//! polynomials `1, x, x² - 4` (norms 7, 28, 84). Its value at position `t` weighs sample `x` by
//! `(12 + 3tx + (t² - 4)(x² - 4)) / 84` and its derivative by `(3x + 2t(x² - 4)) / 84`. Every
//! coefficient is one integer divided by 84, so each f32 table entry is correctly rounded.
//!
//! Rows 0..=2 give the first three outputs of a chunk (fit to its first 7 samples), row 3 the
//! centred filter, rows 4..=6 the last three outputs (fit to its last 7 samples).
//! Sums run over the 7 taps in order: every caller gets the same bits.

/// Filter window (samples).
pub const WINDOW: usize = 7;
/// Half the window: outputs at each edge that come from the edge fit.
pub const HALF: usize = 3;

/// A table of 7 rows of 7 taps.
pub type Rows = [[f32; WINDOW]; WINDOW];

const fn p2(x: i32) -> i32 {
    x * x - 4
}

const fn table(derivative: bool) -> Rows {
    let mut rows = [[0.0f32; WINDOW]; WINDOW];
    let mut p = 0;
    while p < WINDOW {
        let t = p as i32 - HALF as i32;
        let mut k = 0;
        while k < WINDOW {
            let x = k as i32 - HALF as i32;
            let num = if derivative {
                3 * x + 2 * t * p2(x)
            } else {
                12 + 3 * t * x + p2(t) * p2(x)
            };
            rows[p][k] = num as f32 / 84.0;
            k += 1;
        }
        p += 1;
    }
    rows
}

/// Value rows (smoothing): row 3 is `[-2, 3, 6, 7, 6, 3, -2] / 21`.
pub const VALUE: Rows = table(false);
/// First-derivative rows per unit spacing: row 3 is `[-3, -2, -1, 0, 1, 2, 3] / 28`.
pub const DERIVATIVE: Rows = table(true);

/// The 7-tap dot product, summed in tap order.
///
/// ```
/// let ones = [1.0f32; 7];
/// assert_eq!(monitor_core::sg::dot7(&ones, &ones), 7.0);
/// ```
#[inline]
pub fn dot7(row: &[f32; WINDOW], x: &[f32]) -> f32 {
    let mut s = 0.0f32;
    for (c, v) in row.iter().zip(x) {
        s += c * v;
    }
    s
}

/// Filters `input` (at least [`WINDOW`] samples) into `out[..input.len()]` with `rows`, dividing
/// each output by `h` when `h` is `Some` (derivatives). Returns `false`, writing nothing, when
/// `input` is shorter than the window or `out` shorter than `input`.
///
/// ```
/// use monitor_core::sg;
/// // A straight line is reproduced exactly, its slope too.
/// let x: [f32; 8] = core::array::from_fn(|i| i as f32);
/// let mut v = [0.0; 8];
/// let mut d = [0.0; 8];
/// assert!(sg::filter(&x, &sg::VALUE, None, &mut v));
/// assert!(sg::filter(&x, &sg::DERIVATIVE, Some(0.5), &mut d));
/// assert!(v.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-5));
/// assert!(d.iter().all(|&s| (s - 2.0).abs() < 1e-4));
/// ```
pub fn filter(input: &[f32], rows: &Rows, h: Option<f32>, out: &mut [f32]) -> bool {
    let n = input.len();
    if n < WINDOW || out.len() < n {
        return false;
    }
    let (Some(head), Some(tail)) = (input.get(..WINDOW), input.get(n - WINDOW..)) else {
        return false;
    };
    let scale = |s: f32| match h {
        Some(h) => s / h,
        None => s,
    };
    let [r0, r1, r2, centre, r4, r5, r6] = rows;
    for (o, row) in out.iter_mut().zip([r0, r1, r2]) {
        *o = scale(dot7(row, head));
    }
    if let Some(mid) = out.get_mut(HALF..n - HALF) {
        for (o, w) in mid.iter_mut().zip(input.windows(WINDOW)) {
            *o = scale(dot7(centre, w));
        }
    }
    if let Some(end) = out.get_mut(n - HALF..n) {
        for (o, row) in end.iter_mut().zip([r4, r5, r6]) {
            *o = scale(dot7(row, tail));
        }
    }
    true
}
