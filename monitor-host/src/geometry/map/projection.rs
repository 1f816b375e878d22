//! The exact projection of a point onto the lane network (docs/SCORE.md §14.3): the nearest point
//! of any driving lane's centre line, measured in 3-D with the road's elevation.
//!
//! A uniform grid holds short pieces of every lane's centre line (at most [`KNOT_STEP`] m of `s`),
//! each with its chord and a bound on how far the curve strays from the chord. A query visits
//! the grid cells ring by ring; a piece whose chord, less that bound, lies farther than the best
//! distance found so far (plus the tie tolerance) cannot hold the nearest point and is skipped;
//! every other piece is solved exactly: Newton's method on `d/ds |C(s) - p|² = 0`, safeguarded
//! by bisection, on the piece's `s` range. The search stops when the next ring lies beyond the
//! best distance, so the answer is the exact nearest point whatever the grid.
//!
//! [`KNOT_STEP`]: super::network::KNOT_STEP

use super::cubic::eval_coeffs;
use super::lanes::{centre_from, CentrePoint};
use super::network::Network;
use super::reference_line::Geometry;
use super::road::Road;

/// Side of a grid cell (m), unless the map is so large that the grid would exceed
/// [`MAX_CELLS`] cells a side.
const CELL: f64 = 2.0;
const MAX_CELLS: f64 = 1024.0;

/// A piece of a lane's centre line: `s` in `[s_a, s_b]`, chord `a`–`b` (3-D), and `slack`, an
/// upper bound on the distance of the curve from its chord. Between two breakpoints every
/// record is fixed, so the piece keeps its geometry's index and its lateral position `t` and
/// height `z` as single cubics in `s - s_a` (the sums of the records that make them).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Piece {
    pub node: u32,
    pub geometry: u32,
    pub s_a: f64,
    pub s_b: f64,
    pub a: [f64; 3],
    pub b: [f64; 3],
    pub slack: f64,
    pub t: [f64; 4],
    pub z: [f64; 4],
}

/// The grid of pieces, stored cell by cell.
#[derive(Debug, Clone, Default)]
pub(crate) struct Index {
    cell: f64,
    x0: f64,
    y0: f64,
    nx: i64,
    ny: i64,
    /// `starts[c]..starts[c + 1]` are the pieces of cell `c` (row-major).
    starts: Vec<u32>,
    pub pieces: Vec<Piece>,
    /// The centre line at both ends of each piece (every query solving the piece starts there).
    pub ends: Vec<[CentrePoint; 2]>,
    /// Every point of a piece lies within `reach[c]` of the cell `c` holding its chord's
    /// midpoint; `reach_max` is the largest.
    reach: Vec<f64>,
    reach_max: f64,
}

/// A lane found near the query point: the node, `s` of its nearest point and the 3-D distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    pub node: u32,
    pub s: f64,
    pub d: f64,
    pub piece: u32,
}

#[inline]
pub(crate) fn seg_dist(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> f64 {
    seg_dist2(p, a, b).sqrt()
}

/// The square of [`seg_dist`] (which is its square root, so the two agree to the bit).
#[inline]
pub(crate) fn seg_dist2(p: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = if l2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// One piece of a lane's centre line, ready to evaluate.
#[derive(Clone, Copy)]
struct Curve<'a> {
    geometry: &'a Geometry,
    piece: &'a Piece,
}

/// The point of the piece's centre line at road `s`, with its derivatives.
#[inline]
fn centre_at(c: Curve, s: f64) -> CentrePoint {
    let pose = c.geometry.pose(s - c.geometry.s0);
    let v = s - c.piece.s_a;
    centre_from(
        &pose,
        eval_coeffs(&c.piece.t, v),
        eval_coeffs(&c.piece.z, v),
    )
}

/// `|D|²`, `D·C'` and `C'·C' + D·C''` with `D = C - p`.
#[inline]
fn objective_of(c: &CentrePoint, p: &[f64; 3]) -> [f64; 3] {
    let d = [c.p[0] - p[0], c.p[1] - p[1], c.p[2] - p[2]];
    let dot = |u: &[f64; 3], v: &[f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    [
        dot(&d, &d),
        dot(&d, &c.d1),
        dot(&c.d1, &c.d1) + dot(&d, &c.d2),
    ]
}

/// [`objective_of`] the point at `s`.
#[inline]
fn objective(c: Curve, s: f64, p: &[f64; 3]) -> [f64; 3] {
    objective_of(&centre_at(c, s), p)
}

/// The root of `g` in `[lo, hi]` where `g(lo) < 0 < g(hi)`: Newton steps, bisection when a step
/// leaves the bracket. Returns `(s, |D|²)`.
fn solve(curve: Curve, p: &[f64; 3], mut lo: f64, mut hi: f64, glo: f64, ghi: f64) -> (f64, f64) {
    let mut s = lo + (hi - lo) * (-glo / (ghi - glo)).clamp(0.0, 1.0);
    let mut f = f64::INFINITY;
    for _ in 0..60 {
        let [fs, g, gp] = objective(curve, s, p);
        f = fs;
        if g == 0.0 {
            break;
        }
        if g < 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        let newton = s - g / gp;
        let next = if gp > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - s).abs();
        s = next;
        if step < 1e-10 || hi - lo < 1e-10 {
            f = objective(curve, s, p)[0];
            break;
        }
    }
    (s, f)
}

/// The nearest point of a piece of a lane's centre line to `p`: `(s, |D|²)`, given the centre
/// line at the piece's ends (`Index::ends`).
pub(crate) fn nearest_on(
    geometry: &Geometry,
    piece: &Piece,
    p: &[f64; 3],
    ends: &[CentrePoint; 2],
) -> (f64, f64) {
    let curve = Curve { geometry, piece };
    let (a, b) = (piece.s_a, piece.s_b);
    let [fa, ga, _] = objective_of(&ends[0], p);
    let [fb, gb, _] = objective_of(&ends[1], p);
    let mut best = if fa <= fb { (a, fa) } else { (b, fb) };
    let mut consider = |r: (f64, f64)| {
        if r.1 < best.1 {
            best = r;
        }
    };
    if ga < 0.0 && gb > 0.0 {
        consider(solve(curve, p, a, b, ga, gb));
    } else {
        // No sign change at the ends: a minimum inside would show in the middle.
        let m = 0.5 * (a + b);
        let [_, gm, _] = objective(curve, m, p);
        if ga < 0.0 && gm > 0.0 {
            consider(solve(curve, p, a, m, ga, gm));
        }
        if gm < 0.0 && gb > 0.0 {
            consider(solve(curve, p, m, b, gm, gb));
        }
    }
    best
}

impl Index {
    pub fn build(roads: &[Road], net: &Network) -> Index {
        let mut pieces = Vec::new();
        let mut ends = Vec::new();
        for (ni, node) in net.nodes.iter().enumerate() {
            let road = &roads[node.road as usize];
            let sec = node.section as usize;
            let section = &road.sections[sec];
            for i in 1..node.knots.len() {
                let (s_a, s_b) = (node.knots[i - 1][0], node.knots[i][0]);
                let sel = 0.5 * (s_a + s_b);
                let geometry = road
                    .reference
                    .geometries
                    .partition_point(|g| g.s0 <= sel)
                    .saturating_sub(1);
                // t and z as single cubics in s - s_a: the records in force at sel, re-centred.
                let add = |acc: &mut [f64; 4], c: [f64; 4], f: f64| {
                    for k in 0..4 {
                        acc[k] += f * c[k];
                    }
                };
                let mut t = [0.0; 4];
                if let Some(r) = road.lane_offset.record(sel) {
                    add(&mut t, r.shifted(s_a), 1.0);
                }
                if let Some((side, li)) = section.find(node.lane) {
                    let sign = if node.lane > 0 { 1.0 } else { -1.0 };
                    for (j, lane) in side[..=li].iter().enumerate() {
                        if let Some(r) = lane.widths.record(sel - section.s0) {
                            let f = if j == li { 0.5 * sign } else { sign };
                            add(&mut t, r.shifted(s_a - section.s0), f);
                        }
                    }
                }
                let z = road
                    .elevation
                    .record(sel)
                    .map_or([0.0; 4], |r| r.shifted(s_a));
                let piece = |a: [f64; 3], b: [f64; 3], slack: f64| Piece {
                    node: ni as u32,
                    geometry: geometry as u32,
                    s_a,
                    s_b,
                    a,
                    b,
                    slack,
                    t,
                    z,
                };
                let geom = &road.reference.geometries[geometry];
                // As `centre_at` on the piece (the same arithmetic).
                let at = |s: f64| {
                    let v = s - s_a;
                    centre_from(
                        &geom.pose(s - geom.s0),
                        eval_coeffs(&t, v),
                        eval_coeffs(&z, v),
                    )
                };
                let (ca, cb) = (at(s_a), at(s_b));
                let (a, b) = (ca.p, cb.p);
                // The curve's deviation from its chord, measured at the middle and a quarter in;
                // bounded generously (a smooth curve over a short piece is close to a parabola,
                // whose deviation peaks in the middle).
                let mut dev: f64 = 0.0;
                for f in [0.25, 0.5, 0.75] {
                    dev = dev.max(seg_dist(&at(s_a + f * (s_b - s_a)).p, &a, &b));
                }
                if !(a.iter().chain(&b).all(|v| v.is_finite()) && dev.is_finite()) {
                    // A lane whose numbers overflow has no usable geometry here.
                    continue;
                }
                pieces.push(piece(a, b, 1.5 * dev + 1e-3));
                ends.push([ca, cb]);
            }
        }
        if pieces.is_empty() {
            return Index::default();
        }
        let mid = |p: &Piece| [0.5 * (p.a[0] + p.b[0]), 0.5 * (p.a[1] + p.b[1])];
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        for p in &pieces {
            let m = mid(p);
            x0 = x0.min(m[0]);
            y0 = y0.min(m[1]);
            x1 = x1.max(m[0]);
            y1 = y1.max(m[1]);
        }
        let cell = CELL.max((x1 - x0).max(y1 - y0) / MAX_CELLS);
        let nx = (((x1 - x0) / cell).floor() as i64)
            .saturating_add(1)
            .clamp(1, 4096);
        let ny = (((y1 - y0) / cell).floor() as i64)
            .saturating_add(1)
            .clamp(1, 4096);
        let cell_of = |p: &Piece| {
            let m = mid(p);
            let i = (((m[0] - x0) / cell).floor() as i64).clamp(0, nx - 1);
            let j = (((m[1] - y0) / cell).floor() as i64).clamp(0, ny - 1);
            (j * nx + i) as usize
        };
        let mut counts = vec![0u32; (nx * ny) as usize + 1];
        let mut reach = vec![0.0f64; (nx * ny) as usize];
        for p in &pieces {
            let c = cell_of(p);
            counts[c + 1] += 1;
            let half = 0.5 * (p.b[0] - p.a[0]).hypot(p.b[1] - p.a[1]);
            reach[c] = reach[c].max(half + p.slack);
        }
        let reach_max = reach.iter().copied().fold(0.0, f64::max);
        for c in 1..counts.len() {
            counts[c] += counts[c - 1];
        }
        let starts = counts.clone();
        let mut fill = counts;
        let mut sorted = pieces.clone();
        let mut sorted_ends = ends.clone();
        for (p, e) in pieces.iter().zip(&ends) {
            let c = cell_of(p);
            sorted[fill[c] as usize] = *p;
            sorted_ends[fill[c] as usize] = *e;
            fill[c] += 1;
        }
        Index {
            cell,
            x0,
            y0,
            nx,
            ny,
            starts,
            pieces: sorted,
            ends: sorted_ends,
            reach,
            reach_max,
        }
    }

    /// Calls `f(distance², reach, pieces)` for every cell within about `radius` (2-D) of `c`:
    /// the squared distance from `c` to the cell, its reach and the range of its pieces.
    pub fn cells_within(
        &self,
        c: [f64; 2],
        radius: f64,
        mut f: impl FnMut(f64, f64, std::ops::Range<u32>),
    ) {
        if self.pieces.is_empty() || !(c[0].is_finite() && c[1].is_finite()) {
            return;
        }
        let span = radius + self.reach_max;
        let cell_at = |v: f64, v0: f64, n: i64| {
            ((v - v0) / self.cell).floor().clamp(0.0, (n - 1) as f64) as i64
        };
        let (i0, i1) = (
            cell_at(c[0] - span, self.x0, self.nx),
            cell_at(c[0] + span, self.x0, self.nx),
        );
        let (j0, j1) = (
            cell_at(c[1] - span, self.y0, self.ny),
            cell_at(c[1] + span, self.y0, self.ny),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                let (cx0, cy0) = (
                    self.x0 + i as f64 * self.cell,
                    self.y0 + j as f64 * self.cell,
                );
                let dx = (cx0 - c[0]).max(c[0] - cx0 - self.cell).max(0.0);
                let dy = (cy0 - c[1]).max(c[1] - cy0 - self.cell).max(0.0);
                let k = (j * self.nx + i) as usize;
                f(
                    dx * dx + dy * dy,
                    self.reach[k],
                    self.starts[k]..self.starts[k + 1],
                );
            }
        }
    }

    /// The order in which [`Index::search`] around `p` visits piece `k`: ring, row, column,
    /// piece (among pieces at exactly equal distances of one lane, the first visited holds).
    pub fn visit_key(&self, k: u32, p: &[f64; 3]) -> (i64, i64, i64, u32) {
        let c = self.starts.partition_point(|&s| s <= k).saturating_sub(1) as i64;
        let (i, j) = (c % self.nx, c / self.nx);
        let ci = ((p[0] - self.x0) / self.cell).floor().clamp(-1e15, 1e15) as i64;
        let cj = ((p[1] - self.y0) / self.cell).floor().clamp(-1e15, 1e15) as i64;
        ((i - ci).abs().max((j - cj).abs()), j, i, k)
    }

    /// Every lane whose nearest point to `p` lies within `tol` of the nearest distance, each
    /// lane (node) once, in `out` (cleared first). `hint`: a piece likely to be near (e.g. the
    /// previous frame's), whose distance bounds the search from the start; it never changes the
    /// result.
    pub fn search(
        &self,
        roads: &[Road],
        net: &Network,
        p: &[f64; 3],
        tol: f64,
        hint: Option<u32>,
        out: &mut Vec<Candidate>,
    ) {
        out.clear();
        if self.pieces.is_empty() || !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
            return;
        }
        let mut best = f64::INFINITY;
        let try_piece = |k: u32, best: &mut f64, out: &mut Vec<Candidate>| {
            let piece = &self.pieces[k as usize];
            if seg_dist(p, &piece.a, &piece.b) - piece.slack > *best + tol {
                return;
            }
            let node = &net.nodes[piece.node as usize];
            let geometry = &roads[node.road as usize].reference.geometries[piece.geometry as usize];
            let (s, f) = nearest_on(geometry, piece, p, &self.ends[k as usize]);
            let d = f.sqrt();
            if d > *best + tol {
                return;
            }
            *best = best.min(d);
            match out.iter_mut().find(|c| c.node == piece.node) {
                Some(c) => {
                    if d < c.d {
                        *c = Candidate {
                            node: piece.node,
                            s,
                            d,
                            piece: k,
                        };
                    }
                }
                None => out.push(Candidate {
                    node: piece.node,
                    s,
                    d,
                    piece: k,
                }),
            }
        };
        if let Some(h) = hint.filter(|&h| (h as usize) < self.pieces.len()) {
            // The hint's chord plus its slack bounds the nearest distance from above: no piece
            // farther than that can hold the answer. (The answer itself is still found below.)
            let piece = &self.pieces[h as usize];
            let bound = seg_dist(p, &piece.a, &piece.b) + piece.slack;
            if bound.is_finite() {
                best = bound;
            }
        }
        let ci = ((p[0] - self.x0) / self.cell).floor().clamp(-1e15, 1e15) as i64;
        let cj = ((p[1] - self.y0) / self.cell).floor().clamp(-1e15, 1e15) as i64;
        // Beyond this ring no cell of the grid is left.
        let r_max = [ci, self.nx - 1 - ci, cj, self.ny - 1 - cj]
            .iter()
            .map(|v| v.abs())
            .max()
            .unwrap_or(0);
        let r_min = [-ci, ci - (self.nx - 1), -cj, cj - (self.ny - 1), 0]
            .into_iter()
            .max()
            .unwrap_or(0);
        let mut r = r_min;
        while r <= r_max {
            let ring_lb = (r - 1).max(0) as f64 * self.cell - self.reach_max;
            if ring_lb > best + tol {
                break;
            }
            let (j0, j1) = ((cj - r).max(0), (cj + r).min(self.ny - 1));
            for j in j0..=j1 {
                let edge_row = j == cj - r || j == cj + r;
                let (i0, i1) = ((ci - r).max(0), (ci + r).min(self.nx - 1));
                let visit = |i: i64, best: &mut f64, out: &mut Vec<Candidate>| {
                    // Distance from p to the cell's rectangle.
                    let (cx0, cy0) = (
                        self.x0 + i as f64 * self.cell,
                        self.y0 + j as f64 * self.cell,
                    );
                    let dx = (cx0 - p[0]).max(p[0] - cx0 - self.cell).max(0.0);
                    let dy = (cy0 - p[1]).max(p[1] - cy0 - self.cell).max(0.0);
                    let c = (j * self.nx + i) as usize;
                    if dx.hypot(dy) - self.reach[c] <= *best + tol {
                        for k in self.starts[c]..self.starts[c + 1] {
                            try_piece(k, best, out);
                        }
                    }
                };
                if edge_row {
                    for i in i0..=i1 {
                        visit(i, &mut best, out);
                    }
                } else {
                    for i in [ci - r, ci + r] {
                        if (0..self.nx).contains(&i) {
                            visit(i, &mut best, out);
                        }
                    }
                }
            }
            r += 1;
        }
        out.retain(|c| c.d <= best + tol);
    }
}
