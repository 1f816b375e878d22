//! Piecewise cubic records (`elevation`, `laneOffset`, lane `width`): each record holds from its
//! start until the next one starts; a record that starts exactly at `s` applies at `s`.

/// One record: `a + b ds + c ds² + d ds³` with `ds = s - start`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cubic {
    pub start: f64,
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

impl Cubic {
    /// Value, first and second derivative at `s`.
    #[inline]
    pub fn eval(&self, s: f64) -> [f64; 3] {
        let u = s - self.start;
        [
            self.a + u * (self.b + u * (self.c + u * self.d)),
            self.b + u * (2.0 * self.c + u * 3.0 * self.d),
            2.0 * self.c + 6.0 * self.d * u,
        ]
    }
}

impl Cubic {
    /// The same polynomial as coefficients in `v = x - origin`.
    #[inline]
    pub fn shifted(&self, origin: f64) -> [f64; 4] {
        let [v, d1, d2] = self.eval(origin);
        [v, d1, 0.5 * d2, self.d]
    }
}

/// Value, first and second derivative at `v` of the cubic `c[0] + c[1] v + c[2] v² + c[3] v³`.
#[inline]
pub(crate) fn eval_coeffs(c: &[f64; 4], v: f64) -> [f64; 3] {
    [
        c[0] + v * (c[1] + v * (c[2] + v * c[3])),
        c[1] + v * (2.0 * c[2] + v * 3.0 * c[3]),
        2.0 * c[2] + 6.0 * c[3] * v,
    ]
}

/// Records sorted by start (stable: a later record with the same start wins, as in the file).
#[derive(Debug, Clone, Default)]
pub(crate) struct Piecewise(pub Vec<Cubic>);

impl Piecewise {
    /// Sorts the records by start, keeping file order among equal starts.
    pub fn new(mut records: Vec<Cubic>) -> Self {
        records.sort_by(|a, b| a.start.total_cmp(&b.start));
        Piecewise(records)
    }

    /// The record in force at `s`: the last one starting at or before `s`, else the first.
    #[inline]
    pub fn record(&self, s: f64) -> Option<&Cubic> {
        let n = self.0.partition_point(|c| c.start <= s);
        self.0.get(n.saturating_sub(1))
    }

    /// Value and derivatives at `s` of the record in force at `sel`: on a piece of a lane
    /// between two record starts, every point (its ends included) uses the piece's records, so
    /// a piece ending where a new record starts ends at the limit from inside.
    #[inline]
    pub fn eval_in(&self, s: f64, sel: f64) -> [f64; 3] {
        self.record(sel).map_or([0.0; 3], |c| c.eval(s))
    }

    /// Every record start.
    pub fn starts(&self) -> impl Iterator<Item = f64> + '_ {
        self.0.iter().map(|c| c.start)
    }

    /// Value and derivatives at `s` (zero without records).
    #[cfg(test)]
    pub fn eval(&self, s: f64) -> [f64; 3] {
        self.record(s).map_or([0.0; 3], |c| c.eval(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_starting_at_s_applies_at_s() {
        let p = Piecewise::new(vec![
            Cubic {
                start: 10.0,
                a: 2.0,
                b: 0.0,
                c: 0.0,
                d: 0.0,
            },
            Cubic {
                start: 0.0,
                a: 1.0,
                b: 1.0,
                c: 0.0,
                d: 0.0,
            },
        ]);
        assert_eq!(p.eval(9.5)[0], 10.5);
        assert_eq!(p.eval(10.0)[0], 2.0);
        assert_eq!(p.eval(-1.0)[0], 0.0); // before the first record: the first one, extended
        let c = Cubic {
            start: 1.0,
            a: 1.0,
            b: 2.0,
            c: 3.0,
            d: 4.0,
        };
        assert_eq!(c.eval(2.0), [10.0, 2.0 + 6.0 + 12.0, 6.0 + 24.0]);
    }
}
