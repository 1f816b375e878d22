//! `sds_summary`: every count the score and the report need, for one route.

use monitor_core::RouteSummary;

/// Chunks that failed each bound.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_failure_counts {
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

/// Comfort counts.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_comfort_summary {
    /// Comfort chunks (full chunks, or one short chunk).
    pub chunks: u32,
    /// Chunks within all six bounds.
    pub comfortable: u32,
    /// Chunks failing each bound.
    pub failed: sds_failure_counts,
}

/// Lateral counts.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_lateral_summary {
    /// Chunks including the trailing partial one.
    pub chunks: u32,
    /// Chunks with at least one frame of known excess.
    pub scored_chunks: u32,
    /// Anomalous chunks (`N_anom`).
    pub anomalous: u32,
    /// Critical chunks (`N_crit`).
    pub critical: u32,
}

/// Collision counts over the collisions aligned to a frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_collision_summary {
    /// Collisions the monitor saw.
    pub aligned: u32,
    /// Of those, exempt (standing ego or first frame).
    pub exempt: u32,
    /// Not exempt and no deceleration before (`N_nodecel`).
    pub nodecel: u32,
}

/// Everything the monitor learned about one route.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_summary {
    /// Frames pushed.
    pub frames: u32,
    /// Comfort counts.
    pub comfort: sds_comfort_summary,
    /// Lateral counts.
    pub lateral: sds_lateral_summary,
    /// Collision counts.
    pub collisions: sds_collision_summary,
}

impl From<&RouteSummary> for sds_summary {
    fn from(s: &RouteSummary) -> Self {
        let f = &s.comfort.failed;
        sds_summary {
            frames: s.frames,
            comfort: sds_comfort_summary {
                chunks: s.comfort.chunks,
                comfortable: s.comfort.comfortable,
                failed: sds_failure_counts {
                    lon_acc: f.lon_acc,
                    lat_acc: f.lat_acc,
                    mag_jerk: f.mag_jerk,
                    lon_jerk: f.lon_jerk,
                    yaw_acc: f.yaw_acc,
                    yaw_rate: f.yaw_rate,
                },
            },
            lateral: sds_lateral_summary {
                chunks: s.lateral.chunks,
                scored_chunks: s.lateral.scored_chunks,
                anomalous: s.lateral.anomalous,
                critical: s.lateral.critical,
            },
            collisions: sds_collision_summary {
                aligned: s.collisions.aligned,
                exempt: s.collisions.exempt,
                nodecel: s.collisions.nodecel,
            },
        }
    }
}

impl From<&sds_summary> for RouteSummary {
    fn from(s: &sds_summary) -> Self {
        let mut r = RouteSummary::ZERO;
        let f = &s.comfort.failed;
        r.frames = s.frames;
        r.comfort.chunks = s.comfort.chunks;
        r.comfort.comfortable = s.comfort.comfortable;
        r.comfort.failed.lon_acc = f.lon_acc;
        r.comfort.failed.lat_acc = f.lat_acc;
        r.comfort.failed.mag_jerk = f.mag_jerk;
        r.comfort.failed.lon_jerk = f.lon_jerk;
        r.comfort.failed.yaw_acc = f.yaw_acc;
        r.comfort.failed.yaw_rate = f.yaw_rate;
        r.lateral.chunks = s.lateral.chunks;
        r.lateral.scored_chunks = s.lateral.scored_chunks;
        r.lateral.anomalous = s.lateral.anomalous;
        r.lateral.critical = s.lateral.critical;
        r.collisions.aligned = s.collisions.aligned;
        r.collisions.exempt = s.collisions.exempt;
        r.collisions.nodecel = s.collisions.nodecel;
        r
    }
}
