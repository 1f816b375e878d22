//! Comfort per chunk (spec section 4): the chunk buffer and the chunk verdict.
//!
//! Frames only append to the buffer (O(1)); all filtering happens once, at the chunk's end,
//! which is therefore the monitor's worst frame.

use heapless::Vec;

use crate::config::{Config, Profile};
use crate::sg::{self, DERIVATIVE, VALUE};
use crate::signal;

/// Which of the six strict bounds a chunk violated (in report order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Failures {
    /// Longitudinal acceleration left `(lon_acc_min, lon_acc_max)`.
    pub lon_acc: bool,
    /// |lateral acceleration| reached its bound.
    pub lat_acc: bool,
    /// |jerk magnitude| reached its bound.
    pub mag_jerk: bool,
    /// |longitudinal jerk| reached its bound.
    pub lon_jerk: bool,
    /// |yaw acceleration| reached its bound.
    pub yaw_acc: bool,
    /// |yaw rate| reached its bound.
    pub yaw_rate: bool,
}

impl Failures {
    /// True when no bound failed: the chunk is comfortable.
    ///
    /// ```
    /// assert!(monitor_core::Failures::default().comfortable());
    /// ```
    pub const fn comfortable(&self) -> bool {
        !(self.lon_acc
            || self.lat_acc
            || self.mag_jerk
            || self.lon_jerk
            || self.yaw_acc
            || self.yaw_rate)
    }
}

/// True iff every value lies strictly inside `(lo, hi)`; NaN fails.
fn inside(values: &[f32], lo: f32, hi: f32) -> bool {
    // Branch-free: no early exit, so the loop vectorises; the answer is the same.
    values.iter().fold(true, |ok, &v| ok & (lo < v) & (v < hi))
}

/// The raw per-frame signals of the current chunk, at most `N` frames.
#[derive(Clone, Debug)]
pub(crate) struct ChunkBuffer<const N: usize> {
    a_lon: Vec<f32, N>,
    a_lat: Vec<f32, N>,
    a_mag: Vec<f32, N>,
    /// rad/s for the physical profile, raw deg/s for the legacy one (unwrapped at the end).
    yaw: Vec<f32, N>,
}

impl<const N: usize> ChunkBuffer<N> {
    /// An empty buffer.
    pub const fn new() -> Self {
        ChunkBuffer {
            a_lon: Vec::new(),
            a_lat: Vec::new(),
            a_mag: Vec::new(),
            yaw: Vec::new(),
        }
    }

    /// Frames held.
    pub fn len(&self) -> usize {
        self.a_lon.len()
    }

    /// True when no frame is held.
    pub fn is_empty(&self) -> bool {
        self.a_lon.is_empty()
    }

    /// Appends one frame's signals; `false` (and nothing stored) when full.
    pub fn push(&mut self, a_lon: f32, a_lat: f32, a_mag: f32, yaw: f32) -> bool {
        if self.a_lon.is_full() {
            return false;
        }
        // Cannot fail: the four vectors always have the same length.
        let _ = self.a_lon.push(a_lon);
        let _ = self.a_lat.push(a_lat);
        let _ = self.a_mag.push(a_mag);
        let _ = self.yaw.push(yaw);
        true
    }

    /// Forgets every frame.
    pub fn clear(&mut self) {
        self.a_lon.clear();
        self.a_lat.clear();
        self.a_mag.clear();
        self.yaw.clear();
    }

    /// Filters the held chunk and checks the six bounds. `None` when it holds fewer than
    /// [`sg::WINDOW`] frames.
    pub fn evaluate(&self, config: &Config) -> Option<Failures> {
        let n = self.len();
        let b = &config.bounds;
        let mut lon = [0.0f32; N];
        let mut mag = [0.0f32; N];
        let mut yaw = [0.0f32; N];
        let mut tmp = [0.0f32; N];
        let h = match config.profile {
            Profile::Physical | Profile::Autoware => config.dt,
            Profile::B2dLegacy => config.legacy_jerk_spacing,
        };
        let mut f = Failures::default();

        if !sg::filter(&self.a_lon, &VALUE, None, &mut lon) {
            return None;
        }
        let lon = lon.get(..n)?;
        f.lon_acc = !inside(lon, b.lon_acc_min, b.lon_acc_max);

        sg::filter(&self.a_lat, &VALUE, None, &mut tmp);
        f.lat_acc = !inside(tmp.get(..n)?, -b.lat_acc, b.lat_acc);

        sg::filter(lon, &DERIVATIVE, Some(h), &mut tmp);
        f.lon_jerk = !inside(tmp.get(..n)?, -b.lon_jerk, b.lon_jerk);

        sg::filter(&self.a_mag, &VALUE, None, &mut mag);
        let mag = mag.get(..n)?;
        sg::filter(mag, &DERIVATIVE, Some(h), &mut tmp);
        f.mag_jerk = !inside(tmp.get(..n)?, -b.mag_jerk, b.mag_jerk);

        match config.profile {
            Profile::Physical | Profile::Autoware => {
                sg::filter(&self.yaw, &VALUE, None, &mut yaw);
                let yaw = yaw.get(..n)?;
                f.yaw_rate = !inside(yaw, -b.yaw_rate, b.yaw_rate);
                sg::filter(yaw, &DERIVATIVE, Some(config.dt), &mut tmp);
                f.yaw_acc = !inside(tmp.get(..n)?, -b.yaw_acc, b.yaw_acc);
            }
            Profile::B2dLegacy => {
                // Bench2Drive unwraps deg/s with a 2π period per chunk, and compares the smoothed
                // yaw rate itself against the yaw-acceleration bound.
                signal::unwrap(&self.yaw, &mut tmp);
                sg::filter(tmp.get(..n)?, &VALUE, None, &mut yaw);
                let yaw = yaw.get(..n)?;
                f.yaw_rate = !inside(yaw, -b.yaw_rate, b.yaw_rate);
                f.yaw_acc = !inside(yaw, -b.yaw_acc, b.yaw_acc);
            }
        }
        Some(f)
    }
}

impl<const N: usize> Default for ChunkBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}
