//! Typed errors. The monitor never panics: bad input returns one of these and leaves its state
//! unchanged.
//!
//! Each error type lists every value it can take (`ALL`), so that a front end mapping errors to
//! its own codes (the C ABI, the Python exceptions) can test that none is left unmapped: the
//! enums are `#[non_exhaustive]`, so outside this crate a `match` cannot prove it.

/// Declares a field-less enum and its `ALL` constant from one list of variants, so that `ALL`
/// is complete by construction.
macro_rules! listed_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident, )*
        }
    ) => {
        $(#[$meta])*
        pub enum $name {
            $( $(#[$vmeta])* $variant, )*
        }

        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: &'static [$name] = &[$($name::$variant,)*];
        }
    };
}

listed_enum! {
/// A field of [`crate::Frame`], named in errors.
///
/// ```
/// assert_eq!(monitor_core::Field::ALL.len(), 6);
/// ```
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

listed_enum! {
/// Why a configuration was refused (see [`crate::Config::validate`]).
///
/// ```
/// use monitor_core::ConfigError;
/// assert!(ConfigError::ALL.contains(&ConfigError::Capacity));
/// ```
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
    /// [`crate::Profile::Autoware`] with [`crate::Bounds::DEFAULT`] (the physical profile's
    /// bounds): it would judge Autoware's profile against them. Use
    /// `Bounds::of(Profile::Autoware)` or choose the bounds.
    ProfileBounds,
}
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

impl FrameError {
    /// Every error [`crate::Frame::validate`] can return: each field not finite, `speed` or
    /// `a_mag` negative (a test below checks that `validate` returns exactly these).
    ///
    /// ```
    /// use monitor_core::{Field, FrameError};
    /// assert!(FrameError::ALL.contains(&FrameError::Negative(Field::Speed)));
    /// ```
    pub const ALL: &'static [FrameError] = &[
        FrameError::NonFinite(Field::ALon),
        FrameError::NonFinite(Field::ALat),
        FrameError::NonFinite(Field::AMag),
        FrameError::NonFinite(Field::YawRate),
        FrameError::NonFinite(Field::Speed),
        FrameError::NonFinite(Field::LatErr),
        FrameError::Negative(Field::Speed),
        FrameError::Negative(Field::AMag),
    ];
}

impl MonitorError {
    /// Every error [`crate::Monitor::push`] and [`crate::Monitor::finish`] can return: each of
    /// [`FrameError::ALL`], then the other variants.
    ///
    /// ```
    /// use monitor_core::MonitorError;
    /// assert!(MonitorError::ALL.contains(&MonitorError::Finished));
    /// ```
    pub const ALL: &'static [MonitorError] = &{
        let mut all = [MonitorError::Finished; FrameError::ALL.len() + 2];
        let mut i = 0;
        while i < FrameError::ALL.len() {
            all[i] = MonitorError::Frame(FrameError::ALL[i]);
            i += 1;
        }
        all[i] = MonitorError::Finished;
        all[i + 1] = MonitorError::TooManyFrames;
        all
    };
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
            ConfigError::ProfileBounds => {
                "profile autoware with the physical profile's default bounds: use autoware's own \
                 bounds (Bounds::of(Profile::Autoware)) or set the bounds"
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Frame;

    // The matches below have no wildcard: a new variant stops this test from compiling until it
    // is handled here, and then the assertions make `ALL` list it.

    #[test]
    fn frame_error_all_is_what_validate_returns() {
        let mut seen = [false; 8];
        assert_eq!(seen.len(), FrameError::ALL.len());
        for field in Field::ALL {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.0] {
                let mut f = Frame {
                    speed: 5.0,
                    a_mag: 1.0,
                    lat_err: Some(0.0),
                    ..Frame::default()
                };
                match field {
                    Field::ALon => f.a_lon = bad,
                    Field::ALat => f.a_lat = bad,
                    Field::AMag => f.a_mag = bad,
                    Field::YawRate => f.yaw_rate = bad,
                    Field::Speed => f.speed = bad,
                    Field::LatErr => f.lat_err = Some(bad),
                }
                if let Err(e) = f.validate() {
                    let i = FrameError::ALL.iter().position(|a| *a == e);
                    let i = i.unwrap_or_else(|| panic!("{e:?} is missing from FrameError::ALL"));
                    seen[i] = true;
                    match e {
                        FrameError::NonFinite(_) | FrameError::Negative(_) => {}
                    }
                }
            }
        }
        assert!(
            seen.iter().all(|s| *s),
            "FrameError::ALL lists an error validate never returns"
        );
    }

    #[test]
    fn monitor_error_all_lists_every_variant() {
        let mut finished = 0;
        let mut too_many = 0;
        let mut frames = 0;
        for e in MonitorError::ALL {
            match e {
                MonitorError::Frame(_) => frames += 1,
                MonitorError::Finished => finished += 1,
                MonitorError::TooManyFrames => too_many += 1,
            }
        }
        assert_eq!((frames, finished, too_many), (FrameError::ALL.len(), 1, 1));
    }
}
