//! Lane geometry: the lane offset, lane widths and the centre line of a lane (`SDS-SPEC.md`
//! §1.4): the reference point moved along the left normal by
//! `t = laneOffset(s) + sign(k) (sum of the widths of lanes 1..|k|-1 + width_k / 2)`, with the
//! road's elevation as its height.

use super::road::Road;

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

    /// Width of lane `id` of section `sec` at `s`, with its derivatives (at the section's end:
    /// the limit from inside, as [`Road::lane_t`]).
    #[inline]
    pub fn lane_width(&self, sec: usize, id: i32, s: f64) -> [f64; 3] {
        let section = &self.sections[sec];
        let at_end = s >= section.s1 && sec + 1 < self.sections.len();
        match section.find(id) {
            Some((side, i)) if at_end => side[i]
                .widths
                .eval_before(s - section.s0, section.s1 - section.s0),
            Some((side, i)) => side[i].widths.eval(s - section.s0),
            None => [0.0; 3],
        }
    }

    /// Lateral position `t` of lane `id`'s centre at `s` (left positive), with derivatives.
    ///
    /// At the end of a lane section that is not the road's last, the lane is evaluated as the
    /// limit from inside its section: a `laneOffset` or `width` record starting exactly there
    /// belongs to the next section's lanes.
    #[inline]
    pub fn lane_t(&self, sec: usize, id: i32, s: f64) -> [f64; 3] {
        let section = &self.sections[sec];
        let at_end = s >= section.s1 && sec + 1 < self.sections.len();
        let mut t = if at_end {
            self.lane_offset.eval_before(s, section.s1)
        } else {
            self.lane_offset.eval(s)
        };
        if let Some((side, i)) = section.find(id) {
            let ds = s - section.s0;
            let sign = if id > 0 { 1.0 } else { -1.0 };
            for (j, lane) in side[..=i].iter().enumerate() {
                let w = if at_end {
                    lane.widths.eval_before(ds, section.s1 - section.s0)
                } else {
                    lane.widths.eval(ds)
                };
                let f = if j == i { 0.5 * sign } else { sign };
                t[0] += f * w[0];
                t[1] += f * w[1];
                t[2] += f * w[2];
            }
        }
        t
    }

    /// The centre line of lane `id` of section `sec` at `s`.
    #[inline]
    pub fn centre(&self, sec: usize, id: i32, s: f64) -> CentrePoint {
        let pose = self.reference.pose(s);
        let [t, dt, ddt] = self.lane_t(sec, id, s);
        let [z, dz, ddz] = self.elevation.eval(s);
        let (sn, c) = pose.hdg.sin_cos();
        let (tx, ty) = (c, sn);
        let (nx, ny) = (-sn, c);
        let along = 1.0 - t * pose.k;
        let d1t = along;
        let d1n = dt;
        let d2t = -(2.0 * dt * pose.k + t * pose.dk);
        let d2n = along * pose.k + ddt;
        CentrePoint {
            p: [pose.x + t * nx, pose.y + t * ny, z],
            d1: [d1t * tx + d1n * nx, d1t * ty + d1n * ny, dz],
            d2: [d2t * tx + d2n * nx, d2t * ty + d2n * ny, ddz],
        }
    }

    /// The centre point of lane `id` at `s` in 2-D only (OpenDRIVE frame).
    #[inline]
    pub fn centre_xy(&self, sec: usize, id: i32, s: f64) -> [f64; 2] {
        let pose = self.reference.pose(s);
        let t = self.lane_t(sec, id, s)[0];
        let (sn, c) = pose.hdg.sin_cos();
        [pose.x - t * sn, pose.y + t * c]
    }
}
