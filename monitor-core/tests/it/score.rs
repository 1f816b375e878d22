//! DS_safe (docs/SCORE.md §8, 8):
//! `p_safe = score_penalty · (0.5/0.65)^N_wz`,
//! `DS_safe = score_route · p_safe · 0.8^N_nodecel · 0.95^N_anom · 0.9^N_crit`.

use monitor_core::score::{ds_safe, powu, RecordScores};
use monitor_core::{Factors, RouteSummary};

fn summary(nodecel: u32, anom: u32, crit: u32) -> RouteSummary {
    let mut s = RouteSummary::default();
    s.collisions.nodecel = nodecel;
    s.lateral.anomalous = anom;
    s.lateral.critical = crit;
    s
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn a_route_with_every_penalty() {
    // score_route 100, score_penalty 0.39, N_wz 2, N_nodecel 3, N_anom 2, N_crit 1.
    // (0.5/0.65)^2 = (10/13)^2 = 100/169 = 0.591715976...
    // p_safe = 0.39 · 100/169 = 39/169 = 3/13 = 0.230769230769...
    // 0.8^3 = 0.512, 0.95^2 = 0.9025, 0.9^1 = 0.9
    // DS_safe = 100 · 3/13 · 0.512 · 0.9025 · 0.9 = 100 · 3 · 0.415872 / 13 = 124.7616 / 13
    //         = 9.597046153846...
    let r = RecordScores {
        score_route: 100.0,
        score_penalty: 0.39,
        workzone: 2,
    };
    let s = ds_safe(&summary(3, 2, 1), &r, &Factors::DEFAULT);
    assert!(rel(s.p_safe, 3.0 / 13.0) < 1e-15, "{}", s.p_safe);
    assert!(rel(s.ds_safe, 124.7616 / 13.0) < 1e-14, "{}", s.ds_safe);
}

#[test]
fn each_factor_alone() {
    let f = Factors::DEFAULT;
    let r = |wz| RecordScores {
        score_route: 100.0,
        score_penalty: 1.0,
        workzone: wz,
    };
    // Nothing: DS_safe = score_route · score_penalty = 100.
    assert_eq!(ds_safe(&summary(0, 0, 0), &r(0), &f).ds_safe, 100.0);
    // One work-zone contact: 0.5/0.65 = 0.769230769... -> 76.923076923...
    let s = ds_safe(&summary(0, 0, 0), &r(1), &f);
    assert!(rel(s.ds_safe, 1000.0 / 13.0) < 1e-15);
    // One nodecel: 100 · 0.8 = 80; three: 100 · 0.512 = 51.2.
    assert!(rel(ds_safe(&summary(1, 0, 0), &r(0), &f).ds_safe, 80.0) < 1e-15);
    assert!(rel(ds_safe(&summary(3, 0, 0), &r(0), &f).ds_safe, 51.2) < 1e-15);
    // Two anomalous: 100 · 0.9025 = 90.25; one critical: 90.
    assert!(rel(ds_safe(&summary(0, 2, 0), &r(0), &f).ds_safe, 90.25) < 1e-15);
    assert!(rel(ds_safe(&summary(0, 0, 1), &r(0), &f).ds_safe, 90.0) < 1e-15);
    // score_route 85.23, penalty 0.6, one anomalous and two critical:
    // 85.23 · 0.6 · 0.95 · 0.81 = 51.138 · 0.7695 = 39.350691.
    let r2 = RecordScores {
        score_route: 85.23,
        score_penalty: 0.6,
        workzone: 0,
    };
    assert!(rel(ds_safe(&summary(0, 1, 2), &r2, &f).ds_safe, 39.350691) < 1e-14);
}

#[test]
fn the_product_is_taken_left_to_right() {
    // The spec's order, bit for bit: ((((route · p_safe) · nodecel^n) · anom^a) · crit^c).
    let f = Factors::DEFAULT;
    let r = RecordScores {
        score_route: 73.1,
        score_penalty: 0.42,
        workzone: 3,
    };
    let s = ds_safe(&summary(2, 3, 4), &r, &f);
    let p = 0.42 * powu(0.5 / 0.65, 3);
    assert_eq!(s.p_safe.to_bits(), p.to_bits());
    let want = 73.1 * p * powu(0.8, 2) * powu(0.95, 3) * powu(0.9, 4);
    assert_eq!(s.ds_safe.to_bits(), want.to_bits());
}

#[test]
fn powu_is_exact_where_it_can_be() {
    // x^0 = 1, x^1 = x (bits), x^2 = fl(x·x), x^3 = fl(x · fl(x·x)) (= fl(fl(x·x)·x)).
    for x in [0.8f64, 0.95, 0.9, 0.5 / 0.65, 0.3, 1.7] {
        assert_eq!(powu(x, 0), 1.0);
        assert_eq!(powu(x, 1).to_bits(), x.to_bits());
        assert_eq!(powu(x, 2).to_bits(), (x * x).to_bits());
        assert_eq!(powu(x, 3).to_bits(), (x * x * x).to_bits());
        // x^4 = fl(fl(x·x)·fl(x·x)) by squaring.
        assert_eq!(powu(x, 4).to_bits(), ((x * x) * (x * x)).to_bits());
    }
    // Powers of two are exact: 0.5^10 = 1/1024, 2^30, 0.5^1074 = the smallest subnormal.
    assert_eq!(powu(0.5, 10), 1.0 / 1024.0);
    assert_eq!(powu(2.0, 30), 1_073_741_824.0);
    assert_eq!(powu(0.5, 1074), f64::from_bits(1));
    assert_eq!(powu(0.5, 1075), 0.0);
    // 0.8^3 = 0.512 to within an ulp, 0.95^2 = 0.9025 likewise.
    assert!(rel(powu(0.8, 3), 0.512) <= f64::EPSILON);
    assert!(rel(powu(0.95, 2), 0.9025) <= f64::EPSILON);
    // Large counts do not overflow or loop long: 0.8^u32::MAX underflows to 0.
    assert_eq!(powu(0.8, u32::MAX), 0.0);
    assert_eq!(powu(1.0, u32::MAX), 1.0);
}

#[test]
fn custom_factors_apply() {
    // workzone factor = layout factor: no work-zone penalty; nodecel 0.5 twice: /4.
    let f = Factors {
        workzone: 0.65,
        nodecel: 0.5,
        ..Factors::DEFAULT
    };
    let r = RecordScores {
        score_route: 100.0,
        score_penalty: 0.5,
        workzone: 4,
    };
    let s = ds_safe(&summary(2, 0, 0), &r, &f);
    assert_eq!(s.p_safe, 0.5);
    assert_eq!(s.ds_safe, 12.5);
}
