//! Per-frame kernels (docs/SCORE.md §3) and the micromath policy: the core calls micromath's
//! square root explicitly, and `hypot2` refines it with three Newton steps.

use monitor_core::signal::{dot2, hypot2, round_half_even, DEG_TO_RAD};
use monitor_core::{Collisions, Frame};

#[test]
fn micromath_sqrt_is_pinned_and_differs_from_std() {
    // micromath: from_bits((bits(2.0) + 0x3f80_0000) >> 1) = from_bits((0x4000_0000 +
    // 0x3f80_0000) >> 1) = from_bits(0x3fc0_0000) = 1.5. std's IEEE sqrt(2) = 1.4142135.
    let m = micromath::F32Ext::sqrt(2.0f32);
    assert_eq!(m.to_bits(), 0x3fc0_0000);
    assert_eq!(m, 1.5);
    let s = 2.0f32.sqrt();
    assert_ne!(s.to_bits(), m.to_bits());
    assert_eq!(s.to_bits(), 0x3fb5_04f3);
}

/// micromath's seed, written out: the bit trick of its documentation.
fn seed(s: f32) -> f32 {
    f32::from_bits((s.to_bits() + 0x3f80_0000) >> 1)
}

/// hypot2's documented steps for a normal `s`, with a given seed.
fn replay(x: f32, y: f32, seed: fn(f32) -> f32) -> f32 {
    let s = x * x + y * y;
    let mut r = seed(s);
    for _ in 0..3 {
        r = 0.5 * (r + s / r);
    }
    r
}

/// Deterministic pseudo-random f32 in [lo, hi) (64-bit LCG, top 24 bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (self.0 >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
}

#[test]
fn hypot2_by_hand_for_one_one() {
    // s = 2; r0 = 1.5 (micromath);
    // r1 = 0.5 (1.5 + 2/1.5) = 0.5 (1.5 + 1.3333334) = 1.4166667;
    // r2 = 0.5 (1.4166667 + 2/1.4166667) = 0.5 (1.4166667 + 1.4117647) = 1.4142157;
    // r3 = 0.5 (1.4142157 + 2/1.4142157) = 1.4142135 = the correctly rounded sqrt(2).
    let r0 = micromath::F32Ext::sqrt(2.0f32);
    let r1 = 0.5 * (r0 + 2.0 / r0);
    let r2 = 0.5 * (r1 + 2.0 / r1);
    let r3 = 0.5 * (r2 + 2.0 / r2);
    assert_eq!((r0, r1, r2), (1.5, 1.416_666_7, 1.414_215_7));
    assert_eq!(r3, core::f32::consts::SQRT_2);
    assert_eq!(hypot2(1.0, 1.0).to_bits(), r3.to_bits());
    assert_eq!(hypot2(-1.0, 1.0).to_bits(), r3.to_bits());
}

#[test]
fn hypot2_replays_its_documented_steps_with_the_micromath_seed() {
    let mut rng = Lcg(7);
    let mut differs_from_std_seed = 0;
    for _ in 0..100_000 {
        let x = rng.next(-40.0, 40.0);
        let y = rng.next(-40.0, 40.0);
        if x * x + y * y < f32::MIN_POSITIVE {
            continue;
        }
        let h = hypot2(x, y);
        assert_eq!(h.to_bits(), replay(x, y, seed).to_bits(), "({x}, {y})");
        if h.to_bits() != replay(x, y, f32::sqrt).to_bits() {
            differs_from_std_seed += 1;
        }
    }
    // Three Newton steps converge from either seed: a std-seeded replay gives the same bits on
    // these inputs (counted, for the record). Two steps would not (see the next test), which
    // is why the seed must be micromath's on every target.
    eprintln!("hypot2: {differs_from_std_seed} of 100000 differ from a std-seeded replay");
}

#[test]
fn two_newton_steps_would_depend_on_the_seed_and_miss_by_many_ulps() {
    // After two steps from micromath's seed sqrt(2) is 1.4142157 (18 ulp above 1.4142135);
    // from std's seed it is already exact. Hence the third step.
    let two = |s: f32, r0: f32| {
        let r1 = 0.5 * (r0 + s / r0);
        0.5 * (r1 + s / r1)
    };
    assert_eq!(two(2.0, seed(2.0)), 1.414_215_7);
    assert_eq!(two(2.0, 2.0f32.sqrt()), core::f32::consts::SQRT_2);
    let ulps = 1.414_215_7f32.to_bits() - core::f32::consts::SQRT_2.to_bits();
    assert_eq!(ulps, 18);
}

#[test]
fn hypot2_is_within_one_ulp() {
    // Against the f64 hypot rounded to f32, over many magnitudes (1e-30 .. 1e30) and signs.
    let mut rng = Lcg(11);
    let mut worst = 0u32;
    for _ in 0..200_000 {
        let e = rng.next(-30.0, 30.0);
        let x = rng.next(-1.0, 1.0) * 10f32.powf(e);
        let y = rng.next(-1.0, 1.0) * 10f32.powf(e + rng.next(-3.0, 3.0));
        let want = (x as f64).hypot(y as f64) as f32;
        let got = hypot2(x, y);
        let ulps = (got.to_bits() as i64 - want.to_bits() as i64).unsigned_abs() as u32;
        worst = worst.max(ulps);
        assert!(ulps <= 1, "hypot2({x:e}, {y:e}) = {got:e}, want {want:e}");
    }
    eprintln!("hypot2: worst error {worst} ulp");
}

#[test]
fn hypot2_special_values() {
    assert_eq!(hypot2(0.0, 0.0), 0.0);
    assert_eq!(hypot2(-0.0, 0.0).to_bits(), 0.0f32.to_bits());
    assert_eq!(hypot2(3.0, 4.0), 5.0);
    assert!(hypot2(f32::NAN, 0.0).is_nan());
    assert!(hypot2(1.0, f32::NAN).is_nan());
    assert_eq!(hypot2(f32::INFINITY, 1.0), f32::INFINITY);
    assert_eq!(hypot2(1.0, f32::NEG_INFINITY), f32::INFINITY);
    // Squares that overflow: scaled by 2^-100, exact; the true value 1e20 comes back.
    assert_eq!(hypot2(1e20, 0.0), 1e20);
    assert_eq!(hypot2(0.0, -3e30), 3e30);
    assert_eq!(hypot2(f32::MAX, 0.0), f32::MAX);
    // sqrt(2) · MAX overflows: infinity, as the true hypot does.
    assert_eq!(hypot2(f32::MAX, f32::MAX), f32::INFINITY);
    // Squares that underflow: scaled by 2^100; subnormal inputs included.
    assert_eq!(hypot2(3e-25, 4e-25), 5e-25);
    let tiny = f32::from_bits(1); // 2^-149
    assert_eq!(hypot2(tiny, 0.0), tiny);
    assert_eq!(hypot2(1e-40, 0.0), 1e-40);
    assert_eq!(hypot2(-1e-20, 0.0), 1e-20);
}

#[test]
fn frame_from_vectors_uses_the_kernels() {
    // acc (3, 4), fwd (0.6, 0.8), right (0.8, -0.6): a_lon = 1.8 + 3.2 = 5, a_lat = 2.4 - 2.4 = 0,
    // a_mag = 5.
    let f = Frame::from_vectors(
        [3.0, 4.0],
        [0.6, 0.8],
        [0.8, -0.6],
        12.0,
        2.5,
        Some(0.4),
        Collisions::NONE,
    );
    assert_eq!(f.a_lon, dot2([3.0, 4.0], [0.6, 0.8]));
    assert!((f.a_lon - 5.0).abs() < 1e-6);
    assert!(f.a_lat.abs() < 1e-6);
    assert_eq!(f.a_mag, 5.0);
    assert_eq!((f.yaw_rate, f.speed, f.lat_err), (12.0, 2.5, Some(0.4)));
}

#[test]
fn dot2_sums_in_order() {
    // a0·b0 + a1·b1, in that order: (1e8·1) + (1·1) = 1e8 (the 1 is lost at ulp 8).
    assert_eq!(dot2([1e8, 1.0], [1.0, 1.0]), 1e8);
    assert_eq!(dot2([3.0, 4.0], [0.5, -1.0]), -2.5);
}

#[test]
fn round_half_even_by_hand() {
    // Ties go to the even neighbour; everything else to the nearest.
    let cases = [
        (0.5f32, 0.0f32),
        (1.5, 2.0),
        (2.5, 2.0),
        (-0.5, 0.0),
        (-1.5, -2.0),
        (-2.5, -2.0),
        (0.49999997, 0.0),
        (0.50000006, 1.0),
        (1234.5, 1234.0),
        (1235.5, 1236.0),
        (8_388_607.5, 8_388_608.0), // 2^23 - 0.5 -> even 2^23
        (8_388_609.0, 8_388_609.0), // integers at and above 2^23 unchanged
        (-8_388_607.5, -8_388_608.0),
        (1e30, 1e30),
        (f32::INFINITY, f32::INFINITY),
    ];
    for (x, want) in cases {
        assert_eq!(round_half_even(x), want, "round({x})");
    }
    assert!(round_half_even(f32::NAN).is_nan());
}

#[test]
fn degrees_to_radians() {
    // π_f32 / 180 = 0.017453292; 180 deg -> π within an ulp.
    assert_eq!(DEG_TO_RAD, core::f32::consts::PI / 180.0);
    assert!((180.0 * DEG_TO_RAD - core::f32::consts::PI).abs() <= f32::EPSILON * 4.0);
}
