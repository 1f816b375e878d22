//! Typed errors. The monitor never panics: bad input returns one of these and leaves its state
//! unchanged.

/// A field of [`crate::Frame`], named in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Field {
    /// `a_lon`
    ALon,
    /// `a_lat`
    ALat,
    /// `a_mag`
    AMag,
    /// `yaw_rate`
    YawRate,
    /// `speed`
    Speed,
    /// `lat_err`
    LatErr,
}

impl Field {
    /// The field's name as written in JSON frames.
    ///
    /// ```
    /// assert_eq!(monitor_core::Field::LatErr.name(), "lat_err");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Field::ALon => "a_lon",
            Field::ALat => "a_lat",
            Field::AMag => "a_mag",
            Field::YawRate => "yaw_rate",
            Field::Speed => "speed",
            Field::LatErr => "lat_err",
        }
    }
}

/// Why a frame was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum FrameError {
    /// The field is NaN or infinite.
    NonFinite(Field),
    /// The field must not be negative (`speed`, `a_mag`).
    Negative(Field),
}

/// Why a configuration was refused (see [`crate::Config::validate`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ConfigError {
    /// `dt` must lie in `Config::DT_MIN ..= Config::DT_MAX` (1 ms to 1 s).
    Dt,
    /// `legacy_jerk_spacing` must be finite and positive.
    LegacySpacing,
    /// `min_chunk` must be at least the filter window (7).
    MinChunk,
    /// `chunk_len` must lie in `min_chunk ..= capacity`.
    ChunkLen,
    /// The monitor's capacity `N` is over [`crate::MAX_CAPACITY`] (its chunk-end stack would be
    /// unbounded).
    Capacity,
    /// `decel_window` must be at most the capacity.
    DecelWindow,
    /// Bounds must be finite, positive, and `lon_acc_min < lon_acc_max`.
    Bounds,
    /// `slack` must be finite and not negative.
    Slack,
    /// Need `0 <= anomalous_excess <= critical_excess`, both finite.
    ExcessBands,
    /// `decel_threshold` must be finite.
    DecelThreshold,
    /// `stationary_speed` must be finite and not negative.
    StationarySpeed,
    /// Factors must lie in `0 ..= 1` and the layout factor must be positive.
    Factor,
}

/// Why [`crate::Monitor::push`] or [`crate::Monitor::finish`] refused to act.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum MonitorError {
    /// The frame is invalid.
    Frame(FrameError),
    /// The route has already been finished; call [`crate::Monitor::reset`] first.
    Finished,
    /// The route has `u32::MAX` frames already.
    TooManyFrames,
}

impl From<FrameError> for MonitorError {
    fn from(e: FrameError) -> Self {
        MonitorError::Frame(e)
    }
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FrameError::NonFinite(field) => write!(f, "{} is not finite", field.name()),
            FrameError::Negative(field) => write!(f, "{} is negative", field.name()),
        }
    }
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let s = match self {
            ConfigError::Dt => "dt must lie in 0.001..=1 s",
            ConfigError::LegacySpacing => "legacy_jerk_spacing must be finite and positive",
            ConfigError::MinChunk => "min_chunk must be at least the filter window (7)",
            ConfigError::ChunkLen => "chunk_len must lie in min_chunk..=capacity",
            ConfigError::Capacity => "the monitor capacity must be at most 1024 frames",
            ConfigError::DecelWindow => "decel_window must be at most the capacity",
            ConfigError::Bounds => "bounds must be finite and positive, lon_acc_min < lon_acc_max",
            ConfigError::Slack => "slack must be finite and not negative",
            ConfigError::ExcessBands => "need 0 <= anomalous_excess <= critical_excess",
            ConfigError::DecelThreshold => "decel_threshold must be finite",
            ConfigError::StationarySpeed => "stationary_speed must be finite and not negative",
            ConfigError::Factor => "factors must lie in 0..=1 and layout must be positive",
        };
        f.write_str(s)
    }
}

impl core::fmt::Display for MonitorError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MonitorError::Frame(e) => write!(f, "invalid frame: {e}"),
            MonitorError::Finished => f.write_str("the route is already finished"),
            MonitorError::TooManyFrames => f.write_str("too many frames in one route"),
        }
    }
}

impl core::error::Error for FrameError {}
impl core::error::Error for ConfigError {}
impl core::error::Error for MonitorError {}
