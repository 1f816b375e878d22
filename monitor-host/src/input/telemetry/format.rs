//! Which reader a telemetry file needs: [`TelemetryFormat::of`] decides, [`read_telemetry`]
//! reads. The replay reads telemetry only through here.
//!
//! ```
//! use std::path::Path;
//! use monitor_host::input::telemetry::format::TelemetryFormat;
//! let f = TelemetryFormat::of(Path::new("runs/RouteScenario_1_rep0/metric_info.json"));
//! assert_eq!(f, TelemetryFormat::MetricInfo);
//! assert_eq!(f.name(), "metric_info.json");
//! ```

use std::path::Path;

use crate::input::telemetry::{Telemetry, TelemetryError};

/// The formats a telemetry file can be in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum TelemetryFormat {
    /// Bench2Drive's `metric_info.json`: one object per step number.
    MetricInfo,
}

impl TelemetryFormat {
    /// The format of the telemetry file at `path`. Every file is `metric_info.json` today;
    /// the choice is made here, and only here.
    pub fn of(_path: &Path) -> Self {
        TelemetryFormat::MetricInfo
    }

    /// The format's name (its file name).
    pub fn name(self) -> &'static str {
        match self {
            TelemetryFormat::MetricInfo => "metric_info.json",
        }
    }
}

/// Reads the telemetry file at `path` with the reader of its format ([`TelemetryFormat::of`]).
///
/// # Errors
/// [`TelemetryError`] naming the step and the field, or the file that cannot be read.
pub fn read_telemetry(path: &Path) -> Result<Telemetry, TelemetryError> {
    match TelemetryFormat::of(path) {
        TelemetryFormat::MetricInfo => crate::input::metric_info::read_metric_info(path),
    }
}
