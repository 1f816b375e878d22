//! The bounds on a map's numbers: what no CARLA town comes near is refused when the map is
//! read, so that the work per map follows its real extent and a slack cannot become infinite.
//! A small file can otherwise describe a huge amount of geometry (an arc of curvature 1e300
//! coiled over 100 km, a road with 100 lanes), and the lane network samples every lane every
//! 2 m: a 546-byte arc cost 7-14 s per run, a 10 KB road 2.9 GB.
//!
//! | bound | value | the largest in CARLA's towns 01, 02, 04, 06, 10HD |
//! |---|---|---|
//! | `arc` / `spiral` curvature | at most [`MAX_CURVATURE`] = 2 m⁻¹ (radius 0.5 m) | 0.8 m⁻¹ |
//! | turning of one geometry, `∫ abs(κ) ds` | at most [`MAX_TURN`] = 2π (one full circle) | 1.84 rad |
//! | lanes on one side of a lane section | at most [`MAX_LANES_PER_SIDE`] = 32 | 10 |
//! | a driving lane's width (`width` records, anywhere in their range) | at most [`MAX_LANE_WIDTH`] = 20 m | 6 m |
//! | total length of driving lanes (lanes x section lengths) | at most [`MAX_LANE_LENGTH`] = 2,000 km | 74 km |
//!
//! Road and geometry lengths are bounded by `MAX_LENGTH` (100 km) in the reader.

use super::cubic::Cubic;

/// Largest `arc` or `spiral` curvature accepted (1/m).
pub const MAX_CURVATURE: f64 = 2.0;

/// Largest total turning of one geometry accepted (rad).
pub const MAX_TURN: f64 = std::f64::consts::TAU;

/// Most lanes on one side of a lane section.
pub const MAX_LANES_PER_SIDE: usize = 32;

/// Widest driving lane accepted (m).
pub const MAX_LANE_WIDTH: f64 = 20.0;

/// Largest total length of driving lanes in one map (m).
pub const MAX_LANE_LENGTH: f64 = 2_000_000.0;

/// Why an arc or spiral of curvature `k0` to `k1` over `length` m is refused, if it is.
pub(crate) fn curvature(k0: f64, k1: f64, length: f64) -> Option<String> {
    let k = k0.abs().max(k1.abs());
    if k > MAX_CURVATURE {
        return Some(format!(
            "curvature {k} 1/m is beyond {MAX_CURVATURE} 1/m (a radius under {} m: no road \
             turns that tightly)",
            1.0 / MAX_CURVATURE
        ));
    }
    // ∫ |κ| ds for κ linear from k0 to k1.
    let turn = if k0 * k1 >= 0.0 || k0 == k1 {
        0.5 * (k0 + k1).abs() * length
    } else {
        0.5 * (k0 * k0 + k1 * k1) / (k1 - k0).abs() * length
    };
    (turn > MAX_TURN).then(|| {
        format!(
            "turns {turn:.1} rad over its {length} m, more than one full circle ({MAX_TURN:.2} rad)"
        )
    })
}

/// The largest `abs` value of `c` for `ds` in `[from, to]` (its ends and its stationary points).
pub(crate) fn max_abs(c: &Cubic, from: f64, to: f64) -> f64 {
    let mut at = vec![from, to];
    // Roots of the derivative b + 2c u + 3d u² (u = s - start).
    let (a2, b2, c2) = (3.0 * c.d, 2.0 * c.c, c.b);
    if a2 != 0.0 {
        let disc = b2 * b2 - 4.0 * a2 * c2;
        if disc >= 0.0 {
            let r = disc.sqrt();
            at.extend([(-b2 + r) / (2.0 * a2), (-b2 - r) / (2.0 * a2)].map(|u| u + c.start));
        }
    } else if b2 != 0.0 {
        at.push(-c2 / b2 + c.start);
    }
    at.into_iter()
        .filter(|s| *s >= from && *s <= to)
        .map(|s| c.eval(s)[0].abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curvature_and_turning() {
        assert!(curvature(0.8, 0.8, 2.0).is_none());
        assert!(curvature(1e300, 1e300, 10.0).unwrap().contains("curvature"));
        assert!(curvature(0.1, 0.1, 99_999.0)
            .unwrap()
            .contains("full circle"));
        // Through zero: half of each side's turning.
        assert!(curvature(-1.0, 1.0, 6.0).is_none());
    }

    #[test]
    fn max_abs_finds_the_bump() {
        // 4 u (10 - u): 0 at both ends, 100 at u = 5.
        let c = Cubic {
            start: 0.0,
            a: 0.0,
            b: 40.0,
            c: -4.0,
            d: 0.0,
        };
        assert_eq!(max_abs(&c, 0.0, 10.0), 100.0);
        assert_eq!(max_abs(&c, 0.0, 1.0), 36.0);
    }
}
