//! Savitzky–Golay coefficients and filter (docs/SCORE.md §5: window 7, order 2, mode "interp").
//!
//! The expected tables are worked out by hand from the least-squares quadratic through
//! `x = -3..=3` evaluated at `t = p - 3` (output position p of a 7-sample window):
//! value weight `(12 + 3tx + (t²-4)(x²-4)) / 84`, derivative weight `(3x + 2t(x²-4)) / 84`,
//! with `x² - 4 = [5, 0, -3, -4, -3, 0, 5]` and `3x = [-9, -6, -3, 0, 3, 6, 9]`.

use monitor_core::sg::{self, DERIVATIVE, HALF, VALUE, WINDOW};

/// Numerators over 84 of the value rows, by hand:
/// - t=-3: 12 - 9x + 5(x²-4): x=-3: 12+27+25=64, x=-2: 12+18+0=30, x=-1: 12+9-15=6,
///   x=0: 12-20=-8, x=1: 12-9-15=-12, x=2: 12-18=-6, x=3: 12-27+25=10 (sum 84);
/// - t=-2: t²-4=0, so 12 - 6x: 30, 24, 18, 12, 6, 0, -6;
/// - t=-1: 12 - 3x - 3(x²-4) = 24 - 3x - 3x²: 6, 18, 24, 24, 18, 6, -12;
/// - t=0: 28 - 4x²: -8, 12, 24, 28, 24, 12, -8 (= [-2,3,6,7,6,3,-2]/21);
/// - t=1, 2, 3: the mirror images of t=-1, -2, -3.
const VALUE_NUM: [[i32; 7]; 7] = [
    [64, 30, 6, -8, -12, -6, 10],
    [30, 24, 18, 12, 6, 0, -6],
    [6, 18, 24, 24, 18, 6, -12],
    [-8, 12, 24, 28, 24, 12, -8],
    [-12, 6, 18, 24, 24, 18, 6],
    [-6, 0, 6, 12, 18, 24, 30],
    [10, -6, -12, -8, 6, 30, 64],
];

/// Numerators over 84 of the derivative rows, by hand: 2t(x²-4) + 3x.
/// - t=-3: [-30,0,18,24,18,0,-30] + 3x = [-39,-6,15,24,21,6,-21] (sum 0, Σx·c = 84);
/// - t=-2: [-20,0,12,16,12,0,-20] + 3x = [-29,-6,9,16,15,6,-11];
/// - t=-1: [-10,0,6,8,6,0,-10] + 3x = [-19,-6,3,8,9,6,-1];
/// - t=0: 3x = [-9,-6,-3,0,3,6,9] (= [-3..3]/28);
/// - t=1: [10,0,-6,-8,-6,0,10] + 3x = [1,-6,-9,-8,-3,6,19];
/// - t=2: [20,0,-12,-16,-12,0,20] + 3x = [11,-6,-15,-16,-9,6,29];
/// - t=3: [30,0,-18,-24,-18,0,30] + 3x = [21,-6,-21,-24,-15,6,39].
const DERIV_NUM: [[i32; 7]; 7] = [
    [-39, -6, 15, 24, 21, 6, -21],
    [-29, -6, 9, 16, 15, 6, -11],
    [-19, -6, 3, 8, 9, 6, -1],
    [-9, -6, -3, 0, 3, 6, 9],
    [1, -6, -9, -8, -3, 6, 19],
    [11, -6, -15, -16, -9, 6, 29],
    [21, -6, -21, -24, -15, 6, 39],
];

#[test]
fn hand_tables_are_least_squares_rows() {
    // Sanity of the hand arithmetic itself: value rows reproduce 1, x, x² at t; derivative rows
    // give 0, 1, 2t (exact integer identities, times 84).
    for (p, (v, d)) in VALUE_NUM.iter().zip(&DERIV_NUM).enumerate() {
        let t = p as i32 - 3;
        let xs = -3..=3;
        let sum = |row: &[i32; 7], f: &dyn Fn(i32) -> i32| -> i32 {
            row.iter().zip(xs.clone()).map(|(c, x)| c * f(x)).sum()
        };
        assert_eq!(sum(v, &|_| 1), 84);
        assert_eq!(sum(v, &|x| x), 84 * t);
        assert_eq!(sum(v, &|x| x * x), 84 * t * t);
        assert_eq!(sum(d, &|_| 1), 0);
        assert_eq!(sum(d, &|x| x), 84);
        assert_eq!(sum(d, &|x| x * x), 84 * 2 * t);
    }
}

#[test]
fn value_rows_equal_the_exact_rationals() {
    for p in 0..WINDOW {
        for k in 0..WINDOW {
            // n / 84 with n and 84 exact in f32: the division is correctly rounded.
            let want = VALUE_NUM[p][k] as f32 / 84.0;
            assert_eq!(VALUE[p][k].to_bits(), want.to_bits(), "VALUE[{p}][{k}]");
            // ... and equal to the rational rounded once (via f64, exact to 2^-53 here).
            assert_eq!(VALUE[p][k], (VALUE_NUM[p][k] as f64 / 84.0) as f32);
        }
    }
    // The centre row as the textbook writes it: [-2, 3, 6, 7, 6, 3, -2] / 21.
    let centre = [-2.0f32, 3.0, 6.0, 7.0, 6.0, 3.0, -2.0].map(|n| n / 21.0);
    assert_eq!(VALUE[HALF], centre);
}

#[test]
fn derivative_rows_equal_the_exact_rationals() {
    for p in 0..WINDOW {
        for k in 0..WINDOW {
            let want = DERIV_NUM[p][k] as f32 / 84.0;
            assert_eq!(
                DERIVATIVE[p][k].to_bits(),
                want.to_bits(),
                "DERIVATIVE[{p}][{k}]"
            );
        }
    }
    // Centre derivative: [-3, -2, -1, 0, 1, 2, 3] / 28.
    let centre = [-3.0f32, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0].map(|n| n / 28.0);
    assert_eq!(DERIVATIVE[HALF], centre);
}

/// Solves the 3x3 system `m c = r` by Gaussian elimination with partial pivoting (f64).
fn solve3(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> [f64; 3] {
    for col in 0..3 {
        let piv = (col..3)
            .max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))
            .unwrap();
        m.swap(col, piv);
        r.swap(col, piv);
        for row in col + 1..3 {
            let f = m[row][col] / m[col][col];
            let pivot = m[col];
            for (mj, pj) in m[row].iter_mut().zip(pivot).skip(col) {
                *mj -= f * pj;
            }
            r[row] -= f * r[col];
        }
    }
    let mut c = [0.0; 3];
    for i in (0..3).rev() {
        let s: f64 = (i + 1..3).map(|j| m[i][j] * c[j]).sum();
        c[i] = (r[i] - s) / m[i][i];
    }
    c
}

/// An independent fit: the polynomial `c0 + c1 s + c2 s²` over samples at `s = 0..7` (raw
/// monomials, not the orthogonal basis of the crate), from the normal equations, for the unit
/// impulse at sample k; returns its value and slope at `s = p`.
fn polyfit_weight(p: usize, k: usize) -> (f64, f64) {
    let s: Vec<f64> = (0..WINDOW).map(|i| i as f64).collect();
    let mut ata = [[0.0; 3]; 3];
    for &si in &s {
        let row = [1.0, si, si * si];
        for a in 0..3 {
            for b in 0..3 {
                ata[a][b] += row[a] * row[b];
            }
        }
    }
    let sk = s[k];
    let aty = [1.0, sk, sk * sk]; // Aᵀ e_k
    let c = solve3(ata, aty);
    let t = p as f64;
    (c[0] + c[1] * t + c[2] * t * t, c[1] + 2.0 * c[2] * t)
}

#[test]
fn every_row_matches_an_independent_least_squares_fit() {
    for p in 0..WINDOW {
        for k in 0..WINDOW {
            let (v, d) = polyfit_weight(p, k);
            assert!(
                (VALUE[p][k] as f64 - v).abs() < 1e-7,
                "value p={p} k={k}: {v}"
            );
            assert!(
                (DERIVATIVE[p][k] as f64 - d).abs() < 1e-7,
                "deriv p={p} k={k}: {d}"
            );
            // Rounded once to f32, the f64 fit gives the same bits as the table (the fit's
            // rounding noise, ~1e-16, is snapped to the exact zeros of the table).
            let snap = |w: f64| if w.abs() < 1e-12 { 0.0 } else { w as f32 };
            assert_eq!(VALUE[p][k], snap(v), "value bits p={p} k={k}");
            assert_eq!(DERIVATIVE[p][k], snap(d), "deriv bits p={p} k={k}");
        }
    }
}

/// Bound on the rounding error of one output: coefficients (each within 2^-24 relative), seven
/// products and seven additions, all at most `sum |c| |y|` in size: 16 · 2^-24 · that sum.
fn tol(row: &[f32; 7], y: &[f32]) -> f32 {
    let s: f32 = row.iter().zip(y).map(|(c, v)| (c * v).abs()).sum();
    16.0 * f32::EPSILON / 2.0 * s.max(f32::MIN_POSITIVE)
}

#[test]
fn a_quadratic_is_reproduced_at_every_position_including_edges() {
    // y(i) = 0.5 + 0.25 i - 0.125 i² for i = 0..20: every value is exact in f32 (multiples of
    // 1/8 below 2^20); SG of order 2 reproduces any quadratic.
    let n = 20;
    let y: Vec<f32> = (0..n)
        .map(|i| {
            let i = i as f32;
            0.5 + 0.25 * i - 0.125 * i * i
        })
        .collect();
    let mut out = vec![f32::NAN; n];
    assert!(sg::filter(&y, &VALUE, None, &mut out));
    for (i, (&o, &w)) in out.iter().zip(&y).enumerate() {
        let row = if i < 3 {
            &VALUE[i]
        } else if i >= n - 3 {
            &VALUE[i - (n - 7)]
        } else {
            &VALUE[3]
        };
        let win = &y[i.saturating_sub(3).min(n - 7)..][..7];
        assert!((o - w).abs() <= tol(row, win), "i={i}: {o} vs {w}");
    }
    // The first and the last output come from the edge fits (rows 0 and 6): check they are not
    // the centred formula applied to a shifted window: still the quadratic.
    assert!((out[0] - 0.5).abs() <= 1e-6);
    assert!((out[n - 1] - y[n - 1]).abs() <= 4e-5);
}

#[test]
fn the_derivative_of_a_quadratic_is_exact_at_the_edges() {
    // y(i) = 3 - 2 i + 0.5 i² sampled with spacing h = 0.05: dy/dt = (-2 + i) / h.
    // At i=0: -2/0.05 = -40; i=1: -20; i=2: 0; i=17: 300; i=18: 320; i=19: 340.
    let n = 20;
    let h = 0.05f32;
    let y: Vec<f32> = (0..n)
        .map(|i| {
            let i = i as f32;
            3.0 - 2.0 * i + 0.5 * i * i
        })
        .collect();
    let mut d = vec![f32::NAN; n];
    assert!(sg::filter(&y, &DERIVATIVE, Some(h), &mut d));
    let want = [
        (0, -40.0f32),
        (1, -20.0),
        (2, 0.0),
        (17, 300.0),
        (18, 320.0),
        (19, 340.0),
    ];
    for (i, w) in want {
        assert!(
            (d[i] - w).abs() <= 2e-4 * w.abs().max(1.0),
            "i={i}: {} vs {w}",
            d[i]
        );
    }
    for (i, &v) in d.iter().enumerate() {
        let w = (-2.0 + i as f32) / h;
        assert!(
            (v - w).abs() <= 2e-4 * w.abs().max(1.0),
            "i={i}: {v} vs {w}"
        );
    }
}

#[test]
fn a_seven_sample_chunk_uses_edge_rows_and_one_centre() {
    // n = 7: outputs 0..3 from rows 0..2 of the (only) window, 3 from the centre row, 4..7 from
    // rows 4..6; every output is the dot product of its row with the whole input.
    let y = [1.0f32, -2.0, 0.5, 4.0, 3.0, -1.0, 2.0];
    let mut out = [0.0f32; 7];
    assert!(sg::filter(&y, &VALUE, None, &mut out));
    for p in 0..7 {
        assert_eq!(out[p].to_bits(), sg::dot7(&VALUE[p], &y).to_bits(), "p={p}");
    }
    // Division by the spacing for derivatives: exactly dot7 / h.
    let mut d = [0.0f32; 7];
    assert!(sg::filter(&y, &DERIVATIVE, Some(0.1), &mut d));
    for p in 0..7 {
        assert_eq!(
            d[p].to_bits(),
            (sg::dot7(&DERIVATIVE[p], &y) / 0.1).to_bits()
        );
    }
}

#[test]
fn dot7_sums_in_tap_order() {
    // 1e8 + 1 - 1e8 ... in order: ((((((0 + 1e8) + 1) + -1e8) + 1) ...: the 1s vanish into 1e8
    // (ulp 8) except the ones added after it is cancelled: taps 3..7 add 1+1+1+1 = 4 after the
    // cancellation at tap 2 leaves 0; total 4. Summing in another order would give 5 or 0.
    let row = [1.0f32; 7];
    let x = [1e8f32, 1.0, -1e8, 1.0, 1.0, 1.0, 1.0];
    assert_eq!(sg::dot7(&row, &x), 4.0);
}

#[test]
fn filter_refuses_short_input_or_output_and_writes_nothing() {
    let y = [1.0f32; 6];
    let mut out = [9.0f32; 6];
    assert!(!sg::filter(&y, &VALUE, None, &mut out));
    assert_eq!(out, [9.0; 6]);
    let y = [1.0f32; 8];
    let mut short = [9.0f32; 7];
    assert!(!sg::filter(&y, &VALUE, None, &mut short));
    assert_eq!(short, [9.0; 7]);
    // A longer output is fine: only the first n are written.
    let mut long = [9.0f32; 10];
    assert!(sg::filter(&y, &VALUE, None, &mut long));
    assert_eq!(&long[8..], &[9.0, 9.0]);
}
