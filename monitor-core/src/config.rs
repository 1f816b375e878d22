//! Every bound, threshold, window, period, slack and factor of the SDS definition.
//!
//! Defaults equal docs/SCORE.md. Fields marked **\[decision\]** are the spec's own
//! decisions: the default is the spec's, and a user may override it.

use crate::error::ConfigError;

/// Which comfort definition to compute (docs/SCORE.md §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Profile {
    /// Physical units: yaw rate in rad/s, derivatives over the true step period `dt`.
    #[cfg_attr(feature = "serde", serde(rename = "physical"))]
    Physical,
    /// Bench2Drive's published "Driving Smoothness", bugs included: yaw rate left in deg/s and
    /// phase-unwrapped per chunk, yaw acceleration not differentiated, jerks over 0.1 s spacing.
    #[cfg_attr(feature = "serde", serde(rename = "b2d-legacy"))]
    B2dLegacy,
    /// Computed as [`Profile::Physical`], judged against Autoware's planning envelope
    /// ([`Bounds::AUTOWARE`], docs/SCORE.md §2.4): passenger comfort on a vehicle rather than
    /// physical plausibility.
    #[cfg_attr(feature = "serde", serde(rename = "autoware"))]
    Autoware,
}

impl Profile {
    /// Every profile, in declaration order (what a front end lists and parses names against).
    ///
    /// ```
    /// assert_eq!(monitor_core::Profile::ALL.len(), 3);
    /// ```
    pub const ALL: [Profile; 3] = [Profile::Physical, Profile::B2dLegacy, Profile::Autoware];

    /// The name used on the command line and in reports (`physical`, `b2d-legacy`, `autoware`).
    ///
    /// ```
    /// assert_eq!(monitor_core::Profile::B2dLegacy.name(), "b2d-legacy");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Profile::Physical => "physical",
            Profile::B2dLegacy => "b2d-legacy",
            Profile::Autoware => "autoware",
        }
    }

    /// The yaw rate the comfort terms see, from a frame's yaw rate in deg/s (CARLA's unit):
    /// rad/s for [`Profile::Physical`], left in deg/s for [`Profile::B2dLegacy`] (docs/SCORE.md §5). The
    /// streaming monitor and the batch reference both call this one conversion.
    ///
    /// ```
    /// use monitor_core::Profile;
    /// assert_eq!(Profile::B2dLegacy.comfort_yaw_rate(90.0), 90.0);
    /// assert!((Profile::Physical.comfort_yaw_rate(180.0) - core::f32::consts::PI).abs() < 1e-6);
    /// ```
    #[inline]
    pub fn comfort_yaw_rate(self, yaw_rate_deg: f32) -> f32 {
        match self {
            Profile::Physical | Profile::Autoware => yaw_rate_deg * crate::signal::DEG_TO_RAD,
            Profile::B2dLegacy => yaw_rate_deg,
        }
    }
}

/// The six strict comfort bounds (docs/SCORE.md §5, nuPlan's values).
///
/// A filtered value `v` passes iff `lon_acc_min < v < lon_acc_max` (longitudinal acceleration)
/// or `-b < v < b` (every other signal). A value exactly on a bound fails.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Bounds {
    /// Lower bound of longitudinal acceleration, m/s² (default -4.05).
    pub lon_acc_min: f32,
    /// Upper bound of longitudinal acceleration, m/s² (default 2.40).
    pub lon_acc_max: f32,
    /// Bound of |lateral acceleration|, m/s² (default 4.89).
    pub lat_acc: f32,
    /// Bound of |jerk magnitude|, m/s³ (default 8.37).
    pub mag_jerk: f32,
    /// Bound of |longitudinal jerk|, m/s³ (default 4.13).
    pub lon_jerk: f32,
    /// Bound of |yaw acceleration|, rad/s² (default 1.93).
    pub yaw_acc: f32,
    /// Bound of |yaw rate|, rad/s (default 0.95).
    pub yaw_rate: f32,
}

impl Bounds {
    /// The spec's bounds.
    pub const DEFAULT: Bounds = Bounds {
        lon_acc_min: -4.05,
        lon_acc_max: 2.40,
        lat_acc: 4.89,
        mag_jerk: 8.37,
        lon_jerk: 4.13,
        yaw_acc: 1.93,
        yaw_rate: 0.95,
    };

    /// Autoware's planning envelope (docs/SCORE.md §2.4) **\[decision\]**: longitudinal acceleration
    /// -1.0..1.0 m/s², lateral acceleration 1.0 m/s², jerk magnitude and longitudinal jerk
    /// 1.0 m/s³; yaw rate and yaw acceleration as [`Bounds::DEFAULT`].
    ///
    /// ```
    /// use monitor_core::Bounds;
    /// assert_eq!((Bounds::AUTOWARE.lon_acc_min, Bounds::AUTOWARE.yaw_rate), (-1.0, 0.95));
    /// ```
    pub const AUTOWARE: Bounds = Bounds {
        lon_acc_min: -1.0,
        lon_acc_max: 1.0,
        lat_acc: 1.0,
        mag_jerk: 1.0,
        lon_jerk: 1.0,
        yaw_acc: Bounds::DEFAULT.yaw_acc,
        yaw_rate: Bounds::DEFAULT.yaw_rate,
    };

    /// The bounds a profile judges against by default: [`Bounds::AUTOWARE`] for
    /// [`Profile::Autoware`], else [`Bounds::DEFAULT`].
    pub const fn of(profile: Profile) -> Bounds {
        match profile {
            Profile::Autoware => Bounds::AUTOWARE,
            Profile::Physical | Profile::B2dLegacy => Bounds::DEFAULT,
        }
    }

    /// Field-by-field equality usable in `const fn` (`PartialEq` is not).
    const fn same(&self, other: &Bounds) -> bool {
        self.lon_acc_min == other.lon_acc_min
            && self.lon_acc_max == other.lon_acc_max
            && self.lat_acc == other.lat_acc
            && self.mag_jerk == other.mag_jerk
            && self.lon_jerk == other.lon_jerk
            && self.yaw_acc == other.yaw_acc
            && self.yaw_rate == other.yaw_rate
    }
}

/// Penalty factors of DS_safe (docs/SCORE.md §8 and 8). Scores are f64: they combine with the
/// evaluator's f64 `score_route` and `score_penalty`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Factors {
    /// Factor of a work-zone contact (default 0.5) **\[decision\]**.
    pub workzone: f64,
    /// Bench2Drive's layout-collision factor that a work-zone contact replaces (default 0.65).
    pub layout: f64,
    /// Factor per collision without deceleration (default 0.8).
    pub nodecel: f64,
    /// Factor per anomalous lateral chunk (default 0.95).
    pub anomalous: f64,
    /// Factor per critical lateral chunk (default 0.9).
    pub critical: f64,
}

impl Factors {
    /// The spec's factors.
    pub const DEFAULT: Factors = Factors {
        workzone: 0.5,
        layout: 0.65,
        nodecel: 0.8,
        anomalous: 0.95,
        critical: 0.9,
    };
}

/// The whole configuration of the monitor. Build it from [`Config::DEFAULT`] and override fields.
///
/// ```
/// use monitor_core::{Config, Profile};
/// let config = Config { profile: Profile::B2dLegacy, ..Config::DEFAULT };
/// assert!(config.validate(20).is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Comfort profile (docs/SCORE.md §5; default `physical`).
    pub profile: Profile,
    /// Nominal step period in seconds (20 Hz: 0.05); derivatives of the physical profile use it.
    pub dt: f32,
    /// Sample spacing of the legacy profile's jerks, seconds (0.1: Bench2Drive's bug).
    pub legacy_jerk_spacing: f32,
    /// Frames per chunk (docs/SCORE.md §4; default 20). At most the monitor's capacity.
    pub chunk_len: u16,
    /// Fewest frames of a route that still has one (short) comfort chunk
    /// (default 7 = the filter window) **\[decision\]**. At least 7.
    pub min_chunk: u16,
    /// Comfort bounds.
    pub bounds: Bounds,
    /// Lateral slack `lane_half_width - ego_half_width` = 1.75 - 0.93 = 0.82 m **\[decision\]**.
    pub slack: f32,
    /// A chunk is anomalous iff `anomalous_excess < max excess <= critical_excess` (0.25 m)
    /// **\[decision\]**.
    pub anomalous_excess: f32,
    /// A chunk is critical iff `max excess > critical_excess` (0.65 m) **\[decision\]**.
    pub critical_excess: f32,
    /// `a_lon` at or below this counts as deceleration (-0.5 m/s²) **\[decision\]**.
    pub decel_threshold: f32,
    /// Frames before a collision searched for deceleration (20). At most the capacity.
    pub decel_window: u16,
    /// A collision below this speed is exempt (0.5 m/s: the ego was standing) **\[decision\]**.
    pub stationary_speed: f32,
    /// Penalty factors.
    pub factors: Factors,
}

impl Config {
    /// Every default of docs/SCORE.md.
    pub const DEFAULT: Config = Config {
        profile: Profile::Physical,
        dt: 0.05,
        legacy_jerk_spacing: 0.1,
        chunk_len: 20,
        min_chunk: 7,
        bounds: Bounds::DEFAULT,
        slack: 0.82,
        anomalous_excess: 0.25,
        critical_excess: 0.65,
        decel_threshold: -0.5,
        decel_window: 20,
        stationary_speed: 0.5,
        factors: Factors::DEFAULT,
    };

    /// The shortest step period accepted (1 ms, 1 kHz): a shorter one turns every centimetre of
    /// motion into an absurd speed (`--set dt=1e-45` made every moving route invalid).
    pub const DT_MIN: f32 = 1e-3;
    /// The longest step period accepted (1 s, 1 Hz).
    pub const DT_MAX: f32 = 1.0;

    /// Checks that the configuration makes sense for a monitor of `capacity` frames per chunk.
    ///
    /// ```
    /// use monitor_core::{Config, ConfigError};
    /// let bad = Config { chunk_len: 40, ..Config::DEFAULT };
    /// assert_eq!(bad.validate(20), Err(ConfigError::ChunkLen));
    /// ```
    pub const fn validate(&self, capacity: usize) -> Result<(), ConfigError> {
        let c = self;
        if capacity > crate::MAX_CAPACITY {
            return Err(ConfigError::Capacity);
        }
        if !(c.dt >= Config::DT_MIN && c.dt <= Config::DT_MAX) {
            return Err(ConfigError::Dt);
        }
        if !(c.legacy_jerk_spacing.is_finite() && c.legacy_jerk_spacing > 0.0) {
            return Err(ConfigError::LegacySpacing);
        }
        if (c.min_chunk as usize) < crate::sg::WINDOW {
            return Err(ConfigError::MinChunk);
        }
        if c.chunk_len < c.min_chunk || c.chunk_len as usize > capacity {
            return Err(ConfigError::ChunkLen);
        }
        if c.decel_window as usize > capacity {
            return Err(ConfigError::DecelWindow);
        }
        let b = &c.bounds;
        if !(b.lon_acc_min.is_finite()
            && b.lon_acc_max.is_finite()
            && b.lon_acc_min < b.lon_acc_max)
        {
            return Err(ConfigError::Bounds);
        }
        let sym = [b.lat_acc, b.mag_jerk, b.lon_jerk, b.yaw_acc, b.yaw_rate];
        let mut i = 0;
        while i < sym.len() {
            if !(sym[i].is_finite() && sym[i] > 0.0) {
                return Err(ConfigError::Bounds);
            }
            i += 1;
        }
        // `Config { profile: Autoware, ..Config::DEFAULT }` would judge Autoware's profile
        // against the physical bounds: 20/20 comfortable where Autoware's own bounds say 0/20
        // (docs/SCORE.md §2.4). Bounds of the caller's own choosing are the caller's.
        if matches!(c.profile, Profile::Autoware) && b.same(&Bounds::DEFAULT) {
            return Err(ConfigError::ProfileBounds);
        }
        if !(c.slack.is_finite() && c.slack >= 0.0) {
            return Err(ConfigError::Slack);
        }
        if !(c.anomalous_excess.is_finite()
            && c.critical_excess.is_finite()
            && c.anomalous_excess >= 0.0
            && c.anomalous_excess <= c.critical_excess)
        {
            return Err(ConfigError::ExcessBands);
        }
        if !c.decel_threshold.is_finite() {
            return Err(ConfigError::DecelThreshold);
        }
        if !(c.stationary_speed.is_finite() && c.stationary_speed >= 0.0) {
            return Err(ConfigError::StationarySpeed);
        }
        let f = &c.factors;
        let all = [f.workzone, f.layout, f.nodecel, f.anomalous, f.critical];
        let mut i = 0;
        while i < all.len() {
            if !(all[i] >= 0.0 && all[i] <= 1.0) {
                return Err(ConfigError::Factor);
            }
            i += 1;
        }
        if f.layout <= 0.0 {
            return Err(ConfigError::Factor);
        }
        Ok(())
    }
}

impl Default for Config {
    fn default() -> Self {
        Config::DEFAULT
    }
}

// The defaults must always be a valid configuration for the default capacity.
const _: () = assert!(Config::DEFAULT.validate(crate::DEFAULT_CAPACITY).is_ok());

#[cfg(test)]
mod tests {
    use super::*;

    /// Autoware's profile with the physical profile's default bounds is refused by every front
    /// end alike (it judged a ±1.8 m/s² drive comfortable); its own bounds, or any bounds the
    /// caller chose, pass.
    #[test]
    fn autoware_with_the_physical_default_bounds_is_refused() {
        let trap = Config {
            profile: Profile::Autoware,
            ..Config::DEFAULT
        };
        assert_eq!(trap.validate(20), Err(ConfigError::ProfileBounds));
        let own = Config {
            bounds: Bounds::of(Profile::Autoware),
            ..trap
        };
        assert_eq!(own.validate(20), Ok(()));
        let chosen = Config {
            bounds: Bounds {
                lat_acc: 2.0,
                ..Bounds::DEFAULT
            },
            ..trap
        };
        assert_eq!(chosen.validate(20), Ok(()));
        for profile in [Profile::Physical, Profile::B2dLegacy] {
            let c = Config {
                profile,
                ..Config::DEFAULT
            };
            assert_eq!(c.validate(20), Ok(()), "{profile:?}");
        }
    }
}
