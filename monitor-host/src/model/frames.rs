//! The monitor's input frames of one route and the host-side values behind them: what
//! [`crate::app::run::route_frames`] makes and `sds frames` and the long tables print.

use std::path::PathBuf;

use monitor_core::Frame;

use crate::input::warning::Warning;

/// The monitor's input frames of one route, as [`crate::score_run`] would stream them, and the warnings
/// met while reading its telemetry.
#[derive(Clone, Debug, PartialEq)]
pub struct RouteFrames {
    /// One frame per telemetry step, in step order.
    pub frames: Vec<Frame>,
    /// The telemetry step of each frame.
    pub steps: Vec<u64>,
    /// Per frame, the host-side lateral values behind `lat_err` (`None` where it is unknown).
    pub lateral: Vec<Option<crate::geometry::corridor::LateralSample>>,
    /// What the lateral error was measured against.
    pub reference: crate::geometry::corridor::ReferenceKind,
    /// The route's step period, s.
    pub dt: f32,
    /// Problems that did not stop the frames from being made.
    pub warnings: Vec<Warning>,
    /// Every input file read (results files, route XML, telemetry files), for front ends that
    /// must never write over an input.
    pub files_read: Vec<PathBuf>,
}
