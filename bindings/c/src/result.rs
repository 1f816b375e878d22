//! `sds_result`: the outcome of every fallible call, one code per failure.

use core::ffi::c_char;

use monitor_core::{ConfigError, Field, FrameError, MonitorError};

/// The outcome of every fallible `sds_` function: `SDS_RESULT_OK` (0), or why it refused.
/// Nothing changes when a call fails (a failed push leaves the monitor as it was).
///
/// The numbers are part of the ABI and never reused: configuration errors are 100..199, frame
/// errors 200..299, live-link errors 300..399.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub enum sds_result {
    /// Success.
    Ok = 0,
    /// A pointer argument was NULL.
    NullPointer = 1,
    /// The monitor buffer is smaller than `sds_monitor_size()`.
    BufferTooSmall = 2,
    /// The monitor buffer is not aligned to `sds_monitor_align()`.
    BufferMisaligned = 3,
    /// The monitor was never initialised with `sds_monitor_init` (or was overwritten).
    NotInitialized = 4,
    /// The route is finished: `sds_monitor_reset` starts the next one.
    Finished = 5,
    /// The route already has 2^32 - 1 frames.
    TooManyFrames = 6,
    /// A text output buffer is too small.
    OutputTooSmall = 7,
    /// The value is undefined (a comfort score of a route without a comfort chunk).
    Undefined = 8,
    /// A Rust panic was caught at the boundary (a bug: please report it). Host builds only;
    /// on a microcontroller there is no unwinding and a panic traps instead.
    Panic = 9,
    /// A pointer argument is not aligned for its type (a cast from a byte buffer?).
    MisalignedPointer = 10,
    /// An error this version of the C API does not know (the core is newer).
    Unknown = 99,
    /// `profile` is none of `SDS_PROFILE_PHYSICAL`, `SDS_PROFILE_B2D_LEGACY`, `SDS_PROFILE_AUTOWARE`.
    ConfigProfile = 100,
    /// `dt` must be finite and positive.
    ConfigDt = 101,
    /// `legacy_jerk_spacing` must be finite and positive.
    ConfigLegacySpacing = 102,
    /// `min_chunk` must be at least the filter window (7).
    ConfigMinChunk = 103,
    /// `chunk_len` must lie in `min_chunk ..= SDS_CAPACITY`.
    ConfigChunkLen = 104,
    /// `decel_window` must be at most `SDS_CAPACITY`.
    ConfigDecelWindow = 105,
    /// Bounds must be finite and positive, and `lon_acc_min < lon_acc_max`.
    ConfigBounds = 106,
    /// `slack` must be finite and not negative.
    ConfigSlack = 107,
    /// Need `0 <= anomalous_excess <= critical_excess`, both finite.
    ConfigExcessBands = 108,
    /// `decel_threshold` must be finite.
    ConfigDecelThreshold = 109,
    /// `stationary_speed` must be finite and not negative.
    ConfigStationarySpeed = 110,
    /// Factors must lie in `0 ..= 1` and the layout factor must be positive.
    ConfigFactor = 111,
    /// The monitor's capacity is over the core's maximum (1024 frames). The C monitor's
    /// `SDS_CAPACITY` (20) is checked against it when the library is built, so this library
    /// never returns it; the code exists so that every core error has one.
    ConfigCapacity = 112,
    /// `SDS_PROFILE_AUTOWARE` with the physical profile's default bounds: it would judge
    /// Autoware's profile against them; start from `sds_config_profile(SDS_PROFILE_AUTOWARE,
    /// &c)` (Autoware's bounds) or set the bounds.
    ConfigProfileBounds = 113,
    /// `a_lon` is NaN or infinite.
    FrameALonNotFinite = 200,
    /// `a_lat` is NaN or infinite.
    FrameALatNotFinite = 201,
    /// `a_mag` is NaN or infinite.
    FrameAMagNotFinite = 202,
    /// `yaw_rate` is NaN or infinite.
    FrameYawRateNotFinite = 203,
    /// `speed` is NaN or infinite.
    FrameSpeedNotFinite = 204,
    /// `lat_err` is NaN or infinite (and `has_lat_err` is set).
    FrameLatErrNotFinite = 205,
    /// `speed` is negative.
    FrameSpeedNegative = 206,
    /// `a_mag` is negative.
    FrameAMagNegative = 207,
    /// link: `max_delta` must be at least 1.
    LinkConfigMaxDelta = 300,
    /// link: `timeout` must be at least 1 frame period.
    LinkConfigTimeout = 301,
    /// link: `window` must lie in 1 ..= 32.
    LinkConfigWindow = 302,
    /// link: `max_errors` must be below `window`.
    LinkConfigMaxErrors = 303,
    /// link: the bytes are not one intact message of the link (COBS, length, data id, CRC or
    /// layout wrong: what the checker counts as `ERROR`).
    LinkMessage = 310,
}

impl From<ConfigError> for sds_result {
    fn from(e: ConfigError) -> Self {
        // The core's errors are `#[non_exhaustive]`: the wildcard is required, and the test
        // `every_core_error_has_its_own_code` (over `ConfigError::ALL`, `MonitorError::ALL`)
        // fails when a new variant falls into it.
        match e {
            ConfigError::Dt => sds_result::ConfigDt,
            ConfigError::LegacySpacing => sds_result::ConfigLegacySpacing,
            ConfigError::MinChunk => sds_result::ConfigMinChunk,
            ConfigError::ChunkLen => sds_result::ConfigChunkLen,
            ConfigError::DecelWindow => sds_result::ConfigDecelWindow,
            ConfigError::Bounds => sds_result::ConfigBounds,
            ConfigError::Slack => sds_result::ConfigSlack,
            ConfigError::ExcessBands => sds_result::ConfigExcessBands,
            ConfigError::DecelThreshold => sds_result::ConfigDecelThreshold,
            ConfigError::StationarySpeed => sds_result::ConfigStationarySpeed,
            ConfigError::Factor => sds_result::ConfigFactor,
            ConfigError::Capacity => sds_result::ConfigCapacity,
            ConfigError::ProfileBounds => sds_result::ConfigProfileBounds,
            _ => sds_result::Unknown,
        }
    }
}

impl From<FrameError> for sds_result {
    fn from(e: FrameError) -> Self {
        match e {
            FrameError::NonFinite(field) => match field {
                Field::ALon => sds_result::FrameALonNotFinite,
                Field::ALat => sds_result::FrameALatNotFinite,
                Field::AMag => sds_result::FrameAMagNotFinite,
                Field::YawRate => sds_result::FrameYawRateNotFinite,
                Field::Speed => sds_result::FrameSpeedNotFinite,
                Field::LatErr => sds_result::FrameLatErrNotFinite,
            },
            FrameError::Negative(Field::Speed) => sds_result::FrameSpeedNegative,
            FrameError::Negative(Field::AMag) => sds_result::FrameAMagNegative,
            _ => sds_result::Unknown,
        }
    }
}

impl From<MonitorError> for sds_result {
    fn from(e: MonitorError) -> Self {
        match e {
            MonitorError::Frame(f) => f.into(),
            MonitorError::Finished => sds_result::Finished,
            MonitorError::TooManyFrames => sds_result::TooManyFrames,
            _ => sds_result::Unknown,
        }
    }
}

/// `Ok(())` as `SDS_RESULT_OK`, an error as its code.
pub(crate) fn code(r: Result<(), sds_result>) -> sds_result {
    match r {
        Ok(()) => sds_result::Ok,
        Err(e) => e,
    }
}

/// A static, NUL-terminated English description of a result code (any number: unknown codes
/// give "unknown result code"). Never NULL; the caller must not free it.
///
/// ```c
/// sds_result r = sds_monitor_push(m, &f, &ev);
/// if (r != SDS_RESULT_OK) fprintf(stderr, "frame skipped: %s\n", sds_result_str(r));
/// ```
#[no_mangle]
pub extern "C" fn sds_result_str(result: u32) -> *const c_char {
    let s: &'static core::ffi::CStr = match result {
        0 => c"ok",
        1 => c"a pointer argument is NULL",
        2 => c"the monitor buffer is smaller than sds_monitor_size()",
        3 => c"the monitor buffer is not aligned to sds_monitor_align()",
        4 => c"the monitor was not initialised with sds_monitor_init",
        5 => c"the route is already finished (sds_monitor_reset starts the next one)",
        6 => c"too many frames in one route",
        7 => c"the output buffer is too small",
        8 => c"undefined: the route has no comfort chunk",
        9 => c"a Rust panic was caught at the C boundary (a bug: please report it)",
        10 => c"a pointer argument is not aligned for its type",
        99 => c"an error this version of the C API does not know",
        100 => c"config: profile must be SDS_PROFILE_PHYSICAL, SDS_PROFILE_B2D_LEGACY or SDS_PROFILE_AUTOWARE",
        101 => c"config: dt must be finite and positive",
        102 => c"config: legacy_jerk_spacing must be finite and positive",
        103 => c"config: min_chunk must be at least the filter window (7)",
        104 => c"config: chunk_len must lie in min_chunk..=SDS_CAPACITY",
        105 => c"config: decel_window must be at most SDS_CAPACITY",
        106 => c"config: bounds must be finite and positive, lon_acc_min < lon_acc_max",
        107 => c"config: slack must be finite and not negative",
        108 => c"config: need 0 <= anomalous_excess <= critical_excess",
        109 => c"config: decel_threshold must be finite",
        110 => c"config: stationary_speed must be finite and not negative",
        111 => c"config: factors must lie in 0..=1 and layout must be positive",
        112 => c"config: the monitor capacity must be at most 1024 frames",
        113 => c"config: SDS_PROFILE_AUTOWARE with the physical default bounds: start from sds_config_profile(SDS_PROFILE_AUTOWARE, &c) or set the bounds",
        200 => c"frame: a_lon is not finite",
        201 => c"frame: a_lat is not finite",
        202 => c"frame: a_mag is not finite",
        203 => c"frame: yaw_rate is not finite",
        204 => c"frame: speed is not finite",
        205 => c"frame: lat_err is not finite",
        206 => c"frame: speed is negative",
        207 => c"frame: a_mag is negative",
        300 => c"link: max_delta must be at least 1",
        301 => c"link: timeout must be at least 1 frame period",
        302 => c"link: window must lie in 1..=32",
        303 => c"link: max_errors must be below window",
        310 => c"link: not one intact message of the link (COBS, length, data id, CRC or layout)",
        _ => c"unknown result code",
    };
    s.as_ptr()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_its_own_text() {
        let codes = [
            sds_result::Ok,
            sds_result::NullPointer,
            sds_result::BufferTooSmall,
            sds_result::BufferMisaligned,
            sds_result::NotInitialized,
            sds_result::Finished,
            sds_result::TooManyFrames,
            sds_result::OutputTooSmall,
            sds_result::Undefined,
            sds_result::Panic,
            sds_result::MisalignedPointer,
            sds_result::Unknown,
            sds_result::ConfigProfile,
            sds_result::ConfigDt,
            sds_result::ConfigLegacySpacing,
            sds_result::ConfigMinChunk,
            sds_result::ConfigChunkLen,
            sds_result::ConfigDecelWindow,
            sds_result::ConfigBounds,
            sds_result::ConfigSlack,
            sds_result::ConfigExcessBands,
            sds_result::ConfigDecelThreshold,
            sds_result::ConfigStationarySpeed,
            sds_result::ConfigFactor,
            sds_result::ConfigCapacity,
            sds_result::ConfigProfileBounds,
            sds_result::FrameALonNotFinite,
            sds_result::FrameALatNotFinite,
            sds_result::FrameAMagNotFinite,
            sds_result::FrameYawRateNotFinite,
            sds_result::FrameSpeedNotFinite,
            sds_result::FrameLatErrNotFinite,
            sds_result::FrameSpeedNegative,
            sds_result::FrameAMagNegative,
            sds_result::LinkConfigMaxDelta,
            sds_result::LinkConfigTimeout,
            sds_result::LinkConfigWindow,
            sds_result::LinkConfigMaxErrors,
            sds_result::LinkMessage,
        ];
        let unknown = sds_result_str(12345);
        let mut seen = std::vec::Vec::new();
        for c in codes {
            let p = sds_result_str(c as u32);
            assert_ne!(p, unknown, "{c:?} has no text");
            // SAFETY: sds_result_str returns static NUL-terminated strings.
            let s = unsafe { core::ffi::CStr::from_ptr(p) };
            assert!(!seen.contains(&s), "{c:?} shares its text");
            seen.push(s);
        }
    }

    /// Every value of every core error the C API sees has a code of its own: not `Unknown`,
    /// not shared with another error, with its own text.
    #[test]
    fn every_core_error_has_its_own_code() {
        let config = ConfigError::ALL
            .iter()
            .map(|e| (std::format!("{e:?}"), sds_result::from(*e)));
        let monitor = MonitorError::ALL
            .iter()
            .map(|e| (std::format!("{e:?}"), sds_result::from(*e)));
        let frame = FrameError::ALL
            .iter()
            .map(|e| (std::format!("{e:?}"), sds_result::from(*e)));
        let mapped: std::vec::Vec<_> = config.chain(monitor).collect();
        assert_eq!(
            mapped.len(),
            ConfigError::ALL.len() + MonitorError::ALL.len()
        );
        for (i, (name, code)) in mapped.iter().enumerate() {
            assert_ne!(*code, sds_result::Unknown, "{name} has no code of its own");
            assert_ne!(*code, sds_result::Ok, "{name} maps to OK");
            assert_ne!(
                sds_result_str(*code as u32),
                sds_result_str(12345),
                "{name}: no text"
            );
            for (other, c) in &mapped[..i] {
                assert_ne!(code, c, "{name} and {other} share a code");
            }
        }
        // A frame error has the same code on its own as inside MonitorError::Frame.
        for (e, (name, code)) in FrameError::ALL.iter().zip(frame) {
            assert_eq!(sds_result::from(MonitorError::Frame(*e)), code, "{name}");
        }
    }

    #[test]
    fn core_errors_map_to_their_codes() {
        assert_eq!(
            sds_result::from(MonitorError::Frame(FrameError::NonFinite(Field::LatErr))),
            sds_result::FrameLatErrNotFinite
        );
        assert_eq!(
            sds_result::from(MonitorError::Frame(FrameError::Negative(Field::AMag))),
            sds_result::FrameAMagNegative
        );
        assert_eq!(
            sds_result::from(MonitorError::Finished),
            sds_result::Finished
        );
        assert_eq!(
            sds_result::from(ConfigError::Factor),
            sds_result::ConfigFactor
        );
        assert_eq!(
            sds_result::from(ConfigError::Capacity),
            sds_result::ConfigCapacity
        );
        assert_eq!(
            sds_result::from(ConfigError::ProfileBounds),
            sds_result::ConfigProfileBounds
        );
    }
}
