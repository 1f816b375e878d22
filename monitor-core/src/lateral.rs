//! Lateral excess per chunk (docs/SCORE.md §7): the running maximum and its band.

use crate::config::Config;

/// The band of a chunk's maximum excess `m`; the bands are exclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Band {
    /// `m <= anomalous_excess`.
    Normal,
    /// `anomalous_excess < m <= critical_excess`.
    Anomalous,
    /// `m > critical_excess`.
    Critical,
}

impl Band {
    /// The band of maximum excess `m`.
    ///
    /// ```
    /// use monitor_core::{Band, Config};
    /// let c = Config::DEFAULT;
    /// assert_eq!(Band::of(0.25, &c), Band::Normal);
    /// assert_eq!(Band::of(0.65, &c), Band::Anomalous);
    /// assert_eq!(Band::of(0.66, &c), Band::Critical);
    /// ```
    pub fn of(m: f32, config: &Config) -> Band {
        if m > config.critical_excess {
            Band::Critical
        } else if m > config.anomalous_excess {
            Band::Anomalous
        } else {
            Band::Normal
        }
    }
}

/// The maximum excess over the frames of the current chunk with known excess.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LateralChunk {
    max: Option<f32>,
}

impl LateralChunk {
    /// A chunk with no scored frame yet.
    pub const fn new() -> Self {
        LateralChunk { max: None }
    }

    /// Adds a frame's excess.
    pub fn add(&mut self, excess: f32) {
        self.max = match self.max {
            Some(m) if m >= excess => Some(m),
            _ => Some(excess),
        };
    }

    /// The maximum so far; `None` when no frame had a known excess (the chunk is unscored).
    pub const fn max(&self) -> Option<f32> {
        self.max
    }
}
