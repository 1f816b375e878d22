//! Lane geometry: the lane offset, lane widths and the centre line of a lane (docs/SCORE.md
//! §14.3): the reference point moved along the left normal by
//! `t = laneOffset(s) + sign(k) (sum of the widths of lanes 1..|k|-1 + width_k / 2)`, with the
//! road's elevation as its height.

use super::reference_line::Pose;
use super::road::Road;

/// The centre-line point at lateral position `t` (with its s-derivatives) off the reference
/// pose, at height `z` (with derivatives): `C = R + t N`, `C' = (1 - t k) T + t' N`,
/// `C'' = -(2 t' k + t k') T + ((1 - t k) k + t'') N`.
#[inline]
pub(crate) fn centre_from(
    pose: &Pose,
    [t, dt, ddt]: [f64; 3],
    [z, dz, ddz]: [f64; 3],
) -> CentrePoint {
    let (tx, ty) = (pose.cos, pose.sin);
    let (nx, ny) = (-pose.sin, pose.cos);
    let along = 1.0 - t * pose.k;
    let d2t = -(2.0 * dt * pose.k + t * pose.dk);
    let d2n = along * pose.k + ddt;
    CentrePoint {
        p: [pose.x + t * nx, pose.y + t * ny, z],
        d1: [along * tx + dt * nx, along * ty + dt * ny, dz],
        d2: [d2t * tx + d2n * nx, d2t * ty + d2n * ny, ddz],
    }
}

/// A point of a lane's centre line with its first and second derivatives in road `s`
/// (OpenDRIVE frame; `p[2]` is the elevation).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CentrePoint {
    pub p: [f64; 3],
    pub d1: [f64; 3],
    pub d2: [f64; 3],
}

impl Road {
    /// The lane section holding `s`: `[s0, s1)`, the last one including the road's end.
    pub fn section_at(&self, s: f64) -> usize {
        self.sections
            .partition_point(|sec| sec.s0 <= s)
            .saturating_sub(1)
    }

    /// The `s` that selects the records for a point at `s` of section `sec`: `s` itself, except
    /// at or past the end of a section that is not the road's last, where the lane is the limit
    /// from inside its section (records starting at the section's end belong to the next one).
    #[inline]
    pub fn selector(&self, sec: usize, s: f64) -> f64 {
        let section = &self.sections[sec];
        if s >= section.s1 && sec + 1 < self.sections.len() {
            section.s1 - 1e-9 * section.s1.abs().max(1.0)
        } else {
            s
        }
    }

    /// Width of lane `id` of section `sec` at `s` (records chosen at `sel`), with derivatives.
    #[inline]
    pub fn lane_width_in(&self, sec: usize, id: i32, s: f64, sel: f64) -> [f64; 3] {
        let section = &self.sections[sec];
        match section.find(id) {
            Some((side, i)) => side[i].widths.eval_in(s - section.s0, sel - section.s0),
            None => [0.0; 3],
        }
    }

    /// Width of lane `id` of section `sec` at `s`.
    #[inline]
    pub fn lane_width(&self, sec: usize, id: i32, s: f64) -> [f64; 3] {
        self.lane_width_in(sec, id, s, self.selector(sec, s))
    }

    /// Lateral position `t` of lane `id`'s centre at `s` (left positive, records chosen at
    /// `sel`), with derivatives.
    #[inline(always)]
    pub fn lane_t_in(&self, sec: usize, id: i32, s: f64, sel: f64) -> [f64; 3] {
        let section = &self.sections[sec];
        let mut t = self.lane_offset.eval_in(s, sel);
        if let Some((side, i)) = section.find(id) {
            let (ds, dsel) = (s - section.s0, sel - section.s0);
            let sign = if id > 0 { 1.0 } else { -1.0 };
            for (j, lane) in side[..=i].iter().enumerate() {
                let w = lane.widths.eval_in(ds, dsel);
                let f = if j == i { 0.5 * sign } else { sign };
                t[0] += f * w[0];
                t[1] += f * w[1];
                t[2] += f * w[2];
            }
        }
        t
    }

    /// The centre line of lane `id` of section `sec` at `s`, every record chosen at `sel`.
    #[inline]
    pub fn centre_in(&self, sec: usize, id: i32, s: f64, sel: f64) -> CentrePoint {
        let pose = self.reference.pose_in(s, sel);
        let t = self.lane_t_in(sec, id, s, sel);
        let z = self.elevation.eval_in(s, sel);
        centre_from(&pose, t, z)
    }

    /// The point alone of [`Road::centre_in`] (the same arithmetic, so the same bits, without the
    /// derivatives) and the lane's width there (the value of [`Road::lane_width_in`]: its record
    /// is evaluated once, by the same call, for both).
    #[inline]
    pub fn centre_point_and_width_in(
        &self,
        sec: usize,
        id: i32,
        s: f64,
        sel: f64,
    ) -> ([f64; 3], f64) {
        let pose = self.reference.pose_in(s, sel);
        let section = &self.sections[sec];
        let mut t = self.lane_offset.eval_in(s, sel)[0];
        let mut width = 0.0;
        if let Some((side, i)) = section.find(id) {
            let (ds, dsel) = (s - section.s0, sel - section.s0);
            let sign = if id > 0 { 1.0 } else { -1.0 };
            for (j, lane) in side[..=i].iter().enumerate() {
                let w = lane.widths.eval_in(ds, dsel)[0];
                let f = if j == i { 0.5 * sign } else { sign };
                t += f * w;
                width = w;
            }
        }
        let z = self.elevation.eval_in(s, sel)[0];
        let (nx, ny) = (-pose.sin, pose.cos);
        ([pose.x + t * nx, pose.y + t * ny, z], width)
    }

    /// The centre line of lane `id` of section `sec` at `s`.
    #[inline]
    pub fn centre(&self, sec: usize, id: i32, s: f64) -> CentrePoint {
        self.centre_in(sec, id, s, self.selector(sec, s))
    }

    /// Where a record of the lane's geometry (reference line, elevation, lane offset, the widths
    /// of the lane and the lanes inside it) starts strictly inside section `sec`, sorted: the
    /// lane's centre line may bend or jump there.
    pub fn breakpoints(&self, sec: usize, id: i32) -> Vec<f64> {
        let section = &self.sections[sec];
        let (s0, s1) = (section.s0, section.s1);
        let mut out: Vec<f64> = self
            .reference
            .geometries
            .iter()
            .map(|g| g.s0)
            .chain(self.elevation.starts())
            .chain(self.lane_offset.starts())
            .collect();
        if let Some((side, i)) = section.find(id) {
            for lane in &side[..=i] {
                out.extend(lane.widths.starts().map(|d| s0 + d));
            }
        }
        out.retain(|&s| s > s0 && s < s1);
        out.sort_by(f64::total_cmp);
        out.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        out
    }
}
