//! Eight-point Gauss–Legendre quadrature: exact for polynomials of degree 15, so integrals of
//! smooth integrands over a metre or two (clothoid positions, polynomial arc lengths) come out
//! exact to rounding.

const NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// `∫ f` over `[a, b]`.
#[inline]
pub(crate) fn integrate(a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    let h = 0.5 * (b - a);
    let m = 0.5 * (a + b);
    let mut sum = 0.0;
    for i in 0..4 {
        sum += WEIGHTS[i] * (f(m - h * NODES[i]) + f(m + h * NODES[i]));
    }
    sum * h
}

/// `∫ (f0, f1)` over `[a, b]` for a function with two components.
#[inline]
pub(crate) fn integrate2(a: f64, b: f64, mut f: impl FnMut(f64) -> [f64; 2]) -> [f64; 2] {
    let h = 0.5 * (b - a);
    let m = 0.5 * (a + b);
    let mut sum = [0.0; 2];
    for i in 0..4 {
        let l = f(m - h * NODES[i]);
        let r = f(m + h * NODES[i]);
        sum[0] += WEIGHTS[i] * (l[0] + r[0]);
        sum[1] += WEIGHTS[i] * (l[1] + r[1]);
    }
    [sum[0] * h, sum[1] * h]
}

#[cfg(test)]
mod tests {
    #[test]
    fn exact_on_degree_15_and_sine() {
        let v = super::integrate(0.0, 2.0, |x| x.powi(15));
        assert!((v - 2f64.powi(16) / 16.0).abs() < 1e-9);
        let s = super::integrate(0.0, 1.0, f64::cos);
        assert!((s - 1f64.sin()).abs() < 1e-15);
    }
}
