//! The route summary: every count the score and the report need.

use crate::comfort::Failures;

/// Chunks that failed each bound (docs/SCORE.md §13, `comfort.failed`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FailureCounts {
    /// Chunks failing the longitudinal-acceleration bounds.
    pub lon_acc: u32,
    /// Chunks failing the lateral-acceleration bound.
    pub lat_acc: u32,
    /// Chunks failing the jerk-magnitude bound.
    pub mag_jerk: u32,
    /// Chunks failing the longitudinal-jerk bound.
    pub lon_jerk: u32,
    /// Chunks failing the yaw-acceleration bound.
    pub yaw_acc: u32,
    /// Chunks failing the yaw-rate bound.
    pub yaw_rate: u32,
}

impl FailureCounts {
    /// Counts one chunk's failures.
    ///
    /// ```
    /// use monitor_core::{FailureCounts, Failures};
    /// let mut c = FailureCounts::default();
    /// c.add(&Failures { yaw_rate: true, ..Default::default() });
    /// assert_eq!(c.yaw_rate, 1);
    /// ```
    pub fn add(&mut self, f: &Failures) {
        let inc = |n: &mut u32, b: bool| *n = n.saturating_add(b as u32);
        inc(&mut self.lon_acc, f.lon_acc);
        inc(&mut self.lat_acc, f.lat_acc);
        inc(&mut self.mag_jerk, f.mag_jerk);
        inc(&mut self.lon_jerk, f.lon_jerk);
        inc(&mut self.yaw_acc, f.yaw_acc);
        inc(&mut self.yaw_rate, f.yaw_rate);
    }
}

/// Comfort counts (docs/SCORE.md §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ComfortSummary {
    /// Comfort chunks (full chunks, or one short chunk).
    pub chunks: u32,
    /// Chunks within all six bounds.
    pub comfortable: u32,
    /// Chunks failing each bound.
    pub failed: FailureCounts,
}

impl ComfortSummary {
    /// No chunk yet (usable in a `const`).
    pub const ZERO: ComfortSummary = ComfortSummary {
        chunks: 0,
        comfortable: 0,
        failed: FailureCounts {
            lon_acc: 0,
            lat_acc: 0,
            mag_jerk: 0,
            lon_jerk: 0,
            yaw_acc: 0,
            yaw_rate: 0,
        },
    };

    /// Counts one chunk's verdict.
    ///
    /// ```
    /// use monitor_core::{ComfortSummary, Failures};
    /// let mut c = ComfortSummary::ZERO;
    /// c.count(&Failures::default());
    /// c.count(&Failures { lat_acc: true, ..Default::default() });
    /// assert_eq!((c.chunks, c.comfortable, c.failed.lat_acc), (2, 1, 1));
    /// ```
    pub fn count(&mut self, failed: &Failures) {
        self.chunks = self.chunks.saturating_add(1);
        if failed.comfortable() {
            self.comfortable = self.comfortable.saturating_add(1);
        }
        self.failed.add(failed);
    }

    /// Adds another span's counts to these (saturating): a route's figures are its segments'
    /// together (docs/SCORE.md §2.4).
    ///
    /// ```
    /// use monitor_core::{ComfortSummary, Failures};
    /// let (mut a, mut b) = (ComfortSummary::ZERO, ComfortSummary::ZERO);
    /// a.count(&Failures::default());
    /// b.count(&Failures { lat_acc: true, ..Default::default() });
    /// a.merge(&b);
    /// assert_eq!((a.chunks, a.comfortable, a.failed.lat_acc), (2, 1, 1));
    /// ```
    pub fn merge(&mut self, other: &ComfortSummary) {
        let add = |a: &mut u32, b: u32| *a = a.saturating_add(b);
        add(&mut self.chunks, other.chunks);
        add(&mut self.comfortable, other.comfortable);
        let (f, g) = (&mut self.failed, &other.failed);
        add(&mut f.lon_acc, g.lon_acc);
        add(&mut f.lat_acc, g.lat_acc);
        add(&mut f.mag_jerk, g.mag_jerk);
        add(&mut f.lon_jerk, g.lon_jerk);
        add(&mut f.yaw_acc, g.yaw_acc);
        add(&mut f.yaw_rate, g.yaw_rate);
    }
}

/// Lateral counts (docs/SCORE.md §7).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LateralSummary {
    /// Chunks including the trailing partial one: `ceil(frames / chunk_len)`.
    pub chunks: u32,
    /// Chunks with at least one frame of known excess.
    pub scored_chunks: u32,
    /// `N_anom`.
    pub anomalous: u32,
    /// `N_crit`.
    pub critical: u32,
}

/// Collision counts over aligned collisions (docs/SCORE.md §6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CollisionSummary {
    /// Collisions the monitor saw (aligned to a frame).
    pub aligned: u32,
    /// Of those, exempt (standing ego or first frame).
    pub exempt: u32,
    /// `N_nodecel`: aligned, not exempt, no deceleration before.
    pub nodecel: u32,
}

/// Everything the monitor learned about one route.
///
/// ```
/// let s = monitor_core::RouteSummary::default();
/// assert_eq!(s.comfort_score(), None); // no chunk: comfort undefined
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RouteSummary {
    /// Frames pushed.
    pub frames: u32,
    /// Comfort counts.
    pub comfort: ComfortSummary,
    /// Lateral counts.
    pub lateral: LateralSummary,
    /// Collision counts.
    pub collisions: CollisionSummary,
}

impl RouteSummary {
    /// All counts zero.
    pub const ZERO: RouteSummary = RouteSummary {
        frames: 0,
        comfort: ComfortSummary::ZERO,
        lateral: LateralSummary {
            chunks: 0,
            scored_chunks: 0,
            anomalous: 0,
            critical: 0,
        },
        collisions: CollisionSummary {
            aligned: 0,
            exempt: 0,
            nodecel: 0,
        },
    };

    /// Adds another span's counts to these (saturating): a route's figures are its segments'
    /// together (docs/SCORE.md §2.4), on the host as on the link's checker.
    ///
    /// ```
    /// use monitor_core::RouteSummary;
    /// let mut a = RouteSummary { frames: 40, ..RouteSummary::ZERO };
    /// a.merge(&RouteSummary { frames: u32::MAX, ..RouteSummary::ZERO });
    /// assert_eq!(a.frames, u32::MAX);
    /// ```
    pub fn merge(&mut self, other: &RouteSummary) {
        let add = |a: &mut u32, b: u32| *a = a.saturating_add(b);
        add(&mut self.frames, other.frames);
        self.comfort.merge(&other.comfort);
        let (l, m) = (&mut self.lateral, &other.lateral);
        add(&mut l.chunks, m.chunks);
        add(&mut l.scored_chunks, m.scored_chunks);
        add(&mut l.anomalous, m.anomalous);
        add(&mut l.critical, m.critical);
        let (c, d) = (&mut self.collisions, &other.collisions);
        add(&mut c.aligned, d.aligned);
        add(&mut c.exempt, d.exempt);
        add(&mut c.nodecel, d.nodecel);
    }

    /// `C_route = comfortable / chunks`; `None` when the route has no comfort chunk
    /// (fewer than `min_chunk` frames).
    pub fn comfort_score(&self) -> Option<f64> {
        if self.comfort.chunks == 0 {
            None
        } else {
            Some(self.comfort.comfortable as f64 / self.comfort.chunks as f64)
        }
    }
}
