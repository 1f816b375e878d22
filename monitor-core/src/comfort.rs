//! Comfort per chunk (docs/SCORE.md §5): the chunk buffer and the chunk verdict.
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

/// [`inside`] for the values `v / h`: a derivative whose tap sums `v` were kept unscaled, so
/// that two profiles with different spacings share them. `v / h` is the very division
/// [`sg::filter`] does with `Some(h)`, so the bits are the same.
fn inside_over(sums: &[f32], h: f32, lo: f32, hi: f32) -> bool {
    sums.iter().fold(true, |ok, &v| {
        let v = v / h;
        ok & (lo < v) & (v < hi)
    })
}

/// The sample spacing of a profile's derivatives (docs/SCORE.md §5): the step period, or
/// Bench2Drive's 0.1 s for the legacy jerks.
fn spacing(profile: Profile, config: &Config) -> f32 {
    match profile {
        Profile::Physical | Profile::Autoware => config.dt,
        Profile::B2dLegacy => config.legacy_jerk_spacing,
    }
}

/// The raw per-frame signals of the current chunk, at most `N` frames.
#[derive(Clone, Debug)]
pub(crate) struct ChunkBuffer<const N: usize> {
    a_lon: Vec<f32, N>,
    a_lat: Vec<f32, N>,
    a_mag: Vec<f32, N>,
    /// As the frame gives it, in deg/s; each profile converts it when the chunk is filtered.
    yaw: Vec<f32, N>,
}

/// What every profile shares in a chunk: the three smoothed accelerations' verdicts and the
/// tap sums of their derivatives, before the profile's spacing divides them.
struct Shared<'a> {
    lon_acc: bool,
    lat_acc: bool,
    lon_sums: &'a [f32],
    mag_sums: &'a [f32],
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

    /// Appends one frame's signals (the yaw rate in deg/s); `false` (and nothing stored) when
    /// full.
    pub fn push(&mut self, a_lon: f32, a_lat: f32, a_mag: f32, yaw_deg: f32) -> bool {
        if self.a_lon.is_full() {
            return false;
        }
        // Cannot fail: the four vectors always have the same length.
        let _ = self.a_lon.push(a_lon);
        let _ = self.a_lat.push(a_lat);
        let _ = self.a_mag.push(a_mag);
        let _ = self.yaw.push(yaw_deg);
        true
    }

    /// Forgets every frame.
    pub fn clear(&mut self) {
        self.a_lon.clear();
        self.a_lat.clear();
        self.a_mag.clear();
        self.yaw.clear();
    }

    /// Filters the held chunk and checks the six bounds under `config.profile` and, when asked,
    /// under a `second` profile too (the same bounds). The three accelerations and their
    /// derivatives' tap sums are computed once for both: every profile smooths them alike. `None`
    /// when the chunk holds fewer than [`sg::WINDOW`] frames.
    pub fn evaluate(
        &self,
        config: &Config,
        second: Option<Profile>,
    ) -> Option<(Failures, Option<Failures>)> {
        let n = self.len();
        let b = &config.bounds;
        // Four work arrays, reused: the stack a chunk end needs does not grow with `second`.
        let mut smooth = [0.0f32; N];
        let mut lon_sums = [0.0f32; N];
        let mut mag_sums = [0.0f32; N];
        let mut tmp = [0.0f32; N];

        if !sg::filter(&self.a_lon, &VALUE, None, &mut smooth) {
            return None;
        }
        let lon = smooth.get(..n)?;
        let lon_acc = !inside(lon, b.lon_acc_min, b.lon_acc_max);
        sg::filter(lon, &DERIVATIVE, None, &mut lon_sums);

        sg::filter(&self.a_lat, &VALUE, None, &mut smooth);
        let lat_acc = !inside(smooth.get(..n)?, -b.lat_acc, b.lat_acc);

        sg::filter(&self.a_mag, &VALUE, None, &mut smooth);
        sg::filter(smooth.get(..n)?, &DERIVATIVE, None, &mut mag_sums);

        let shared = Shared {
            lon_acc,
            lat_acc,
            lon_sums: lon_sums.get(..n)?,
            mag_sums: mag_sums.get(..n)?,
        };
        let first = self.verdict(&shared, config.profile, config, &mut smooth, &mut tmp)?;
        let second = match second {
            Some(p) => Some(self.verdict(&shared, p, config, &mut smooth, &mut tmp)?),
            None => None,
        };
        Some((first, second))
    }

    /// One profile's six verdicts from the shared part and the chunk's yaw rate.
    fn verdict(
        &self,
        shared: &Shared,
        profile: Profile,
        config: &Config,
        yaw: &mut [f32; N],
        tmp: &mut [f32; N],
    ) -> Option<Failures> {
        let n = self.len();
        let b = &config.bounds;
        let h = spacing(profile, config);
        let mut f = Failures {
            lon_acc: shared.lon_acc,
            lat_acc: shared.lat_acc,
            lon_jerk: !inside_over(shared.lon_sums, h, -b.lon_jerk, b.lon_jerk),
            mag_jerk: !inside_over(shared.mag_sums, h, -b.mag_jerk, b.mag_jerk),
            ..Failures::default()
        };
        match profile {
            Profile::Physical | Profile::Autoware => {
                for (w, &deg) in tmp.iter_mut().zip(&self.yaw) {
                    *w = profile.comfort_yaw_rate(deg);
                }
                sg::filter(tmp.get(..n)?, &VALUE, None, yaw);
                let yaw = yaw.get(..n)?;
                f.yaw_rate = !inside(yaw, -b.yaw_rate, b.yaw_rate);
                sg::filter(yaw, &DERIVATIVE, Some(h), tmp);
                f.yaw_acc = !inside(tmp.get(..n)?, -b.yaw_acc, b.yaw_acc);
            }
            Profile::B2dLegacy => {
                // Bench2Drive unwraps deg/s with a 2π period per chunk, and compares the smoothed
                // yaw rate itself against the yaw-acceleration bound.
                signal::unwrap(&self.yaw, tmp);
                sg::filter(tmp.get(..n)?, &VALUE, None, yaw);
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
