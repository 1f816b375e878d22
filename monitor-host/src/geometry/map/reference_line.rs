//! A road's reference line: its `planView` geometries (`line`, `arc`, `spiral`, `poly3`,
//! `paramPoly3`) evaluated exactly in f64, in OpenDRIVE's frame.
//!
//! `poly3` and `paramPoly3` are evaluated by arc length (docs/SCORE.md §14.3): the point at `s` is
//! the point of the curve whose arc length from the geometry's start is `s - s0`; `pRange` only
//! sets the parameter's range. Clothoid positions and polynomial arc lengths are integrated with
//! 8-point Gauss–Legendre over steps of at most [`KNOT`] m, exact to rounding.

use super::gauss;

/// Step of the stored integration knots (m of arc length, or of the parameter for polynomials).
const KNOT: f64 = 2.0;

/// Position, heading, curvature and its derivative of the reference line at some `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pose {
    pub x: f64,
    pub y: f64,
    pub hdg: f64,
    /// `cos(hdg)`, `sin(hdg)`.
    pub cos: f64,
    pub sin: f64,
    /// Curvature (1/m, positive to the left).
    pub k: f64,
    /// d(curvature)/ds (exact for lines, arcs and spirals; 0 for polynomials, which only slows
    /// the projection's Newton steps down, never its result).
    pub dk: f64,
}

/// The shape of one `<geometry>`.
#[derive(Debug, Clone)]
pub(crate) enum Shape {
    Line,
    Arc {
        k: f64,
    },
    /// Clothoid: curvature `k0 + dk u`. `knots[i]` is the offset of the point at `u = i KNOT`
    /// from the start.
    Spiral {
        k0: f64,
        dk: f64,
        knots: Vec<[f64; 2]>,
    },
    /// `(U(p), V(p))` in the local u/v frame (`poly3` is `U = p`). `table` holds `(p, arc
    /// length)` at the knots of `[0, p_end]`.
    Poly {
        u: [f64; 4],
        v: [f64; 4],
        table: Vec<[f64; 2]>,
    },
}

/// One `<geometry>` record.
#[derive(Debug, Clone)]
pub(crate) struct Geometry {
    pub s0: f64,
    pub x: f64,
    pub y: f64,
    pub hdg: f64,
    /// `cos(hdg)`, `sin(hdg)`, computed once.
    pub cos: f64,
    pub sin: f64,
    pub shape: Shape,
}

#[inline]
fn poly(c: &[f64; 4], p: f64) -> [f64; 3] {
    [
        c[0] + p * (c[1] + p * (c[2] + p * c[3])),
        c[1] + p * (2.0 * c[2] + p * 3.0 * c[3]),
        2.0 * c[2] + 6.0 * c[3] * p,
    ]
}

#[inline]
fn speed(u: &[f64; 4], v: &[f64; 4], p: f64) -> f64 {
    let du = poly(u, p)[1];
    let dv = poly(v, p)[1];
    du.hypot(dv)
}

impl Shape {
    /// A clothoid from `k0` to `k1` over `length`.
    pub fn spiral(hdg: f64, length: f64, k0: f64, k1: f64) -> Shape {
        let dk = if length > 0.0 {
            (k1 - k0) / length
        } else {
            0.0
        };
        let n = (length / KNOT).ceil().max(1.0) as usize;
        let mut knots = Vec::with_capacity(n + 1);
        let mut at = [0.0, 0.0];
        knots.push(at);
        for i in 0..n {
            let a = i as f64 * KNOT;
            let d = gauss::integrate2(a, a + KNOT, |u| {
                let th = hdg + u * (k0 + 0.5 * dk * u);
                [th.cos(), th.sin()]
            });
            at = [at[0] + d[0], at[1] + d[1]];
            knots.push(at);
        }
        Shape::Spiral { k0, dk, knots }
    }

    /// A polynomial curve over `p` in `[0, p_end]`.
    pub fn poly(u: [f64; 4], v: [f64; 4], p_end: f64) -> Shape {
        let n = (p_end.abs() / KNOT).ceil().clamp(8.0, 1.0e6) as usize;
        let mut table = Vec::with_capacity(n + 1);
        let mut arc = 0.0;
        table.push([0.0, 0.0]);
        for i in 0..n {
            let a = p_end * i as f64 / n as f64;
            let b = p_end * (i + 1) as f64 / n as f64;
            arc += gauss::integrate(a, b, |p| speed(&u, &v, p));
            table.push([b, arc]);
        }
        Shape::Poly { u, v, table }
    }
}

impl Geometry {
    /// A geometry record (its `length` is already in `shape`; past it the shape goes on along
    /// its end tangent, or its own formula).
    pub fn new(s0: f64, x: f64, y: f64, hdg: f64, shape: Shape) -> Geometry {
        let (sin, cos) = hdg.sin_cos();
        Geometry {
            s0,
            x,
            y,
            hdg,
            cos,
            sin,
            shape,
        }
    }

    /// The pose at `sigma = s - s0` (extended along the end tangents outside `[0, length]`).
    #[inline]
    pub fn pose(&self, sigma: f64) -> Pose {
        let (c, sn) = (self.cos, self.sin);
        match &self.shape {
            Shape::Line => Pose {
                x: self.x + sigma * c,
                y: self.y + sigma * sn,
                hdg: self.hdg,
                cos: c,
                sin: sn,
                k: 0.0,
                dk: 0.0,
            },
            Shape::Arc { k } => {
                let half = 0.5 * k * sigma;
                let (sh, ch) = half.sin_cos();
                // Chord form: stable for tiny curvature.
                let chord = if half.abs() < 1e-9 {
                    sigma
                } else {
                    2.0 * sh / k
                };
                // Heading turned by half (the chord's direction), then by half again.
                let (dc, ds) = (c * ch - sn * sh, sn * ch + c * sh);
                Pose {
                    x: self.x + chord * dc,
                    y: self.y + chord * ds,
                    hdg: self.hdg + k * sigma,
                    cos: dc * ch - ds * sh,
                    sin: ds * ch + dc * sh,
                    k: *k,
                    dk: 0.0,
                }
            }
            Shape::Spiral { k0, dk, knots } => {
                let i = ((sigma / KNOT).floor().max(0.0) as usize).min(knots.len() - 1);
                let a = i as f64 * KNOT;
                let d = gauss::integrate2(a, sigma, |u| {
                    let th = self.hdg + u * (k0 + 0.5 * dk * u);
                    [th.cos(), th.sin()]
                });
                let hdg = self.hdg + sigma * (k0 + 0.5 * dk * sigma);
                let (sin, cos) = hdg.sin_cos();
                Pose {
                    x: self.x + knots[i][0] + d[0],
                    y: self.y + knots[i][1] + d[1],
                    hdg,
                    cos,
                    sin,
                    k: k0 + dk * sigma,
                    dk: *dk,
                }
            }
            Shape::Poly { u, v, table } => {
                let last = table[table.len() - 1];
                let (p, extra) = if sigma <= 0.0 {
                    (0.0, sigma)
                } else if sigma >= last[1] {
                    (last[0], sigma - last[1])
                } else {
                    (param_at(u, v, table, sigma), 0.0)
                };
                let [pu, du, ddu] = poly(u, p);
                let [pv, dv, ddv] = poly(v, p);
                let sp = du.hypot(dv);
                let (tu, tv) = if sp > 0.0 {
                    (du / sp, dv / sp)
                } else {
                    (1.0, 0.0)
                };
                let k = if sp > 0.0 {
                    (du * ddv - dv * ddu) / (sp * sp * sp)
                } else {
                    0.0
                };
                let lu = pu + extra * tu;
                let lv = pv + extra * tv;
                Pose {
                    x: self.x + c * lu - sn * lv,
                    y: self.y + sn * lu + c * lv,
                    hdg: self.hdg + tv.atan2(tu),
                    cos: c * tu - sn * tv,
                    sin: sn * tu + c * tv,
                    k: if extra == 0.0 { k } else { 0.0 },
                    dk: 0.0,
                }
            }
        }
    }
}

/// The parameter whose arc length from `p = 0` is `sigma` (inside the table's range).
fn param_at(u: &[f64; 4], v: &[f64; 4], table: &[[f64; 2]], sigma: f64) -> f64 {
    let i = table
        .partition_point(|e| e[1] <= sigma)
        .clamp(1, table.len() - 1)
        - 1;
    let [p0, a0] = table[i];
    let [p1, a1] = table[i + 1];
    let mut p = if a1 > a0 {
        p0 + (p1 - p0) * (sigma - a0) / (a1 - a0)
    } else {
        p0
    };
    // Newton on A(p) - sigma, safeguarded by the bracket [p0, p1].
    let (lo, hi) = if p0 <= p1 { (p0, p1) } else { (p1, p0) };
    for _ in 0..12 {
        let f = a0 + gauss::integrate(p0, p, |q| speed(u, v, q)) - sigma;
        let df = speed(u, v, p) * (p1 - p0).signum();
        if df == 0.0 || !df.is_finite() {
            break;
        }
        let next = (p - f / df).clamp(lo, hi);
        let done = (next - p).abs() <= 1e-13 * (1.0 + p.abs());
        p = next;
        if done {
            break;
        }
    }
    p
}

/// A road's reference line.
#[derive(Debug, Clone, Default)]
pub(crate) struct ReferenceLine {
    pub geometries: Vec<Geometry>,
}

impl ReferenceLine {
    /// The pose at road `s` of the geometry in force at `sel` (the one starting last at or
    /// before `sel`, else the first).
    #[inline]
    pub fn pose_in(&self, s: f64, sel: f64) -> Pose {
        let i = self
            .geometries
            .partition_point(|g| g.s0 <= sel)
            .saturating_sub(1);
        let g = &self.geometries[i];
        g.pose(s - g.s0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geom(shape: Shape) -> Geometry {
        Geometry::new(0.0, 1.0, 2.0, 0.3, shape)
    }

    #[test]
    fn arc_is_a_circle() {
        let k = 0.05;
        let g = geom(Shape::Arc { k });
        // Centre: start + left normal / k.
        let (cx, cy) = (1.0 - 0.3f64.sin() / k, 2.0 + 0.3f64.cos() / k);
        for i in 0..=40 {
            let p = g.pose(i as f64);
            assert!(((p.x - cx).hypot(p.y - cy) - 1.0 / k).abs() < 1e-12);
            assert!((p.hdg - (0.3 + k * i as f64)).abs() < 1e-15);
            assert!((p.cos - p.hdg.cos()).abs() < 1e-15 && (p.sin - p.hdg.sin()).abs() < 1e-15);
        }
    }

    #[test]
    fn spiral_with_constant_curvature_is_the_arc() {
        let a = geom(Shape::Arc { k: -0.02 });
        let s = geom(Shape::spiral(0.3, 100.0, -0.02, -0.02));
        for i in 0..=100 {
            let (p, q) = (a.pose(i as f64), s.pose(i as f64));
            assert!((p.x - q.x).abs() < 1e-11 && (p.y - q.y).abs() < 1e-11);
        }
    }

    #[test]
    fn straight_param_poly3_at_arc_length() {
        // U = p², V = 0 over normalized p: the point at arc length σ is at u = σ.
        let g = geom(Shape::poly([0.0, 0.0, 10.0, 0.0], [0.0; 4], 1.0));
        let p = g.pose(2.5);
        assert!((p.x - (1.0 + 2.5 * 0.3f64.cos())).abs() < 1e-12);
        assert!((p.y - (2.0 + 2.5 * 0.3f64.sin())).abs() < 1e-12);
    }
}
