//! `sds_config`: every bound, threshold and factor, settable field by field, validated exactly
//! as `monitor_core::Config::validate` does.

use monitor_core::{Bounds, Config, Factors, Profile};

use crate::result::{code, sds_result};
use crate::{guard, usable, SDS_CAPACITY};

/// Which comfort definition to compute: `SDS_PROFILE_PHYSICAL`, `SDS_PROFILE_B2D_LEGACY` or `SDS_PROFILE_AUTOWARE`.
/// A plain integer, so that no value written by C is undefined behaviour in Rust.
#[allow(non_camel_case_types)]
pub type sds_profile = u32;

/// Physical units: yaw rate in rad/s, derivatives over the true step period `dt` (the default).
pub const SDS_PROFILE_PHYSICAL: sds_profile = 0;
/// Bench2Drive's published "Driving Smoothness", bugs included.
pub const SDS_PROFILE_B2D_LEGACY: sds_profile = 1;
/// Computed as physical, judged against Autoware's planning envelope: lon -1.0..1.0 m/s², lat
/// 1.0 m/s², jerks 1.0 m/s³. Start from `sds_config_profile(SDS_PROFILE_AUTOWARE, &c)`, which
/// sets those bounds; with the physical profile's default bounds it is refused
/// (`SDS_RESULT_CONFIG_PROFILE_BOUNDS`).
pub const SDS_PROFILE_AUTOWARE: sds_profile = 2;

/// The six strict comfort bounds (m/s², m/s³, rad/s², rad/s).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_bounds {
    /// Lower bound of longitudinal acceleration (default -4.05).
    pub lon_acc_min: f32,
    /// Upper bound of longitudinal acceleration (default 2.40).
    pub lon_acc_max: f32,
    /// Bound of |lateral acceleration| (default 4.89).
    pub lat_acc: f32,
    /// Bound of |jerk magnitude| (default 8.37).
    pub mag_jerk: f32,
    /// Bound of |longitudinal jerk| (default 4.13).
    pub lon_jerk: f32,
    /// Bound of |yaw acceleration| (default 1.93).
    pub yaw_acc: f32,
    /// Bound of |yaw rate| (default 0.95).
    pub yaw_rate: f32,
}

/// Penalty factors of DS_safe.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_factors {
    /// Factor of a work-zone contact (default 0.5).
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

/// The whole configuration. Start from `sds_config_default()`, change fields, and check with
/// `sds_config_validate` (`sds_monitor_init` checks it too).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_config {
    /// `SDS_PROFILE_PHYSICAL` (default), `SDS_PROFILE_B2D_LEGACY` or `SDS_PROFILE_AUTOWARE`.
    pub profile: sds_profile,
    /// Nominal step period in seconds (default 0.05, 20 Hz).
    pub dt: f32,
    /// Sample spacing of the legacy profile's jerks, seconds (default 0.1).
    pub legacy_jerk_spacing: f32,
    /// Frames per chunk (default 20), in `min_chunk ..= SDS_CAPACITY`.
    pub chunk_len: u16,
    /// Fewest frames of a route that still has one short comfort chunk (default 7, at least 7).
    pub min_chunk: u16,
    /// Comfort bounds.
    pub bounds: sds_bounds,
    /// Lateral slack `lane_half_width - ego_half_width`, m (default 0.82).
    pub slack: f32,
    /// Lower edge of the anomalous lateral band, m (default 0.25).
    pub anomalous_excess: f32,
    /// Lower edge of the critical lateral band, m (default 0.65).
    pub critical_excess: f32,
    /// `a_lon` at or below this counts as deceleration, m/s² (default -0.5).
    pub decel_threshold: f32,
    /// Frames before a collision searched for deceleration (default 20), at most `SDS_CAPACITY`.
    pub decel_window: u16,
    /// A collision below this speed is exempt, m/s (default 0.5).
    pub stationary_speed: f32,
    /// Penalty factors.
    pub factors: sds_factors,
}

impl From<Factors> for sds_factors {
    fn from(f: Factors) -> Self {
        sds_factors {
            workzone: f.workzone,
            layout: f.layout,
            nodecel: f.nodecel,
            anomalous: f.anomalous,
            critical: f.critical,
        }
    }
}

impl From<sds_factors> for Factors {
    fn from(f: sds_factors) -> Self {
        Factors {
            workzone: f.workzone,
            layout: f.layout,
            nodecel: f.nodecel,
            anomalous: f.anomalous,
            critical: f.critical,
        }
    }
}

impl From<Config> for sds_config {
    fn from(c: Config) -> Self {
        let b = c.bounds;
        sds_config {
            profile: match c.profile {
                Profile::Physical => SDS_PROFILE_PHYSICAL,
                Profile::B2dLegacy => SDS_PROFILE_B2D_LEGACY,
                Profile::Autoware => SDS_PROFILE_AUTOWARE,
            },
            dt: c.dt,
            legacy_jerk_spacing: c.legacy_jerk_spacing,
            chunk_len: c.chunk_len,
            min_chunk: c.min_chunk,
            bounds: sds_bounds {
                lon_acc_min: b.lon_acc_min,
                lon_acc_max: b.lon_acc_max,
                lat_acc: b.lat_acc,
                mag_jerk: b.mag_jerk,
                lon_jerk: b.lon_jerk,
                yaw_acc: b.yaw_acc,
                yaw_rate: b.yaw_rate,
            },
            slack: c.slack,
            anomalous_excess: c.anomalous_excess,
            critical_excess: c.critical_excess,
            decel_threshold: c.decel_threshold,
            decel_window: c.decel_window,
            stationary_speed: c.stationary_speed,
            factors: c.factors.into(),
        }
    }
}

impl sds_config {
    /// The core's configuration, checked as `Config::validate` checks it for `SDS_CAPACITY`.
    pub(crate) fn to_core(self) -> Result<Config, sds_result> {
        let profile = match self.profile {
            SDS_PROFILE_PHYSICAL => Profile::Physical,
            SDS_PROFILE_B2D_LEGACY => Profile::B2dLegacy,
            SDS_PROFILE_AUTOWARE => Profile::Autoware,
            _ => return Err(sds_result::ConfigProfile),
        };
        let b = self.bounds;
        let config = Config {
            profile,
            dt: self.dt,
            legacy_jerk_spacing: self.legacy_jerk_spacing,
            chunk_len: self.chunk_len,
            min_chunk: self.min_chunk,
            bounds: Bounds {
                lon_acc_min: b.lon_acc_min,
                lon_acc_max: b.lon_acc_max,
                lat_acc: b.lat_acc,
                mag_jerk: b.mag_jerk,
                lon_jerk: b.lon_jerk,
                yaw_acc: b.yaw_acc,
                yaw_rate: b.yaw_rate,
            },
            slack: self.slack,
            anomalous_excess: self.anomalous_excess,
            critical_excess: self.critical_excess,
            decel_threshold: self.decel_threshold,
            decel_window: self.decel_window,
            stationary_speed: self.stationary_speed,
            factors: self.factors.into(),
        };
        // The core refuses Autoware's profile with the physical default bounds
        // (`SDS_RESULT_CONFIG_PROFILE_BOUNDS`), as every front end does.
        config.validate(SDS_CAPACITY)?;
        Ok(config)
    }
}

/// The spec's defaults (always valid).
///
/// ```c
/// sds_config c = sds_config_default();
/// c.profile = SDS_PROFILE_B2D_LEGACY;   /* any field, then sds_config_validate */
/// ```
#[no_mangle]
pub extern "C" fn sds_config_default() -> sds_config {
    Config::DEFAULT.into()
}

/// The defaults of a profile: `sds_config_default()` with `profile` set and the bounds the
/// profile judges against (Autoware's planning envelope for `SDS_PROFILE_AUTOWARE`, the spec's
/// for the others), as `sds --profile` sets them. `SDS_RESULT_CONFIG_PROFILE` for an unknown
/// profile, `SDS_RESULT_NULL_POINTER` for a NULL `out` (nothing written on a failure).
///
/// ```c
/// sds_config c;
/// sds_config_profile(SDS_PROFILE_AUTOWARE, &c);   /* c.bounds.lon_acc_max == 1.0f */
/// ```
///
/// # Safety
/// `out` is NULL or points to a writable `sds_config`.
#[no_mangle]
pub unsafe extern "C" fn sds_config_profile(
    profile: sds_profile,
    out: *mut sds_config,
) -> sds_result {
    guard(|| {
        code((|| {
            usable(out)?;
            let profile = match profile {
                SDS_PROFILE_PHYSICAL => Profile::Physical,
                SDS_PROFILE_B2D_LEGACY => Profile::B2dLegacy,
                SDS_PROFILE_AUTOWARE => Profile::Autoware,
                _ => return Err(sds_result::ConfigProfile),
            };
            let config = Config {
                profile,
                bounds: Bounds::of(profile),
                ..Config::DEFAULT
            };
            // SAFETY: usable, and the caller promises a writable sds_config.
            unsafe { out.write(config.into()) };
            Ok(())
        })())
    })
}

/// Checks a configuration with the same rules as the Rust monitor, for a monitor of
/// `SDS_CAPACITY` frames per chunk: `SDS_RESULT_OK` or the `SDS_RESULT_CONFIG_*` code of the
/// first field that fails (`SDS_RESULT_NULL_POINTER` for a NULL `config`).
///
/// ```c
/// sds_config c = sds_config_default();
/// c.chunk_len = 40;
/// sds_config_validate(&c);   /* SDS_RESULT_CONFIG_CHUNK_LEN: more than SDS_CAPACITY */
/// ```
///
/// # Safety
/// `config` is NULL or points to a readable `sds_config`.
#[no_mangle]
pub unsafe extern "C" fn sds_config_validate(config: *const sds_config) -> sds_result {
    guard(|| {
        code((|| {
            usable(config)?;
            // SAFETY: usable, and the caller promises a readable sds_config; every bit pattern
            // of its fields is a valid value (plain integers and floats).
            unsafe { config.read() }.to_core().map(|_| ())
        })())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_round_trips_and_validates() {
        let c = sds_config_default();
        assert_eq!(c.to_core(), Ok(Config::DEFAULT));
        // SAFETY: a valid pointer to a local.
        assert_eq!(unsafe { sds_config_validate(&c) }, sds_result::Ok);
    }

    /// Issue 47 item 11: Autoware's profile gets Autoware's bounds from sds_config_profile,
    /// and is refused with the physical bounds (it judged a ±1.8 m/s² drive comfortable).
    #[test]
    fn r4_11_autoware_takes_its_own_bounds() {
        let mut c = sds_config_default();
        // SAFETY: valid pointers to locals throughout.
        unsafe {
            assert_eq!(
                sds_config_profile(SDS_PROFILE_AUTOWARE, &mut c),
                sds_result::Ok
            );
            assert_eq!(c.to_core().map(|k| k.bounds), Ok(Bounds::AUTOWARE));
            assert_eq!(c.profile, SDS_PROFILE_AUTOWARE);
            assert_eq!(
                sds_config_profile(SDS_PROFILE_B2D_LEGACY, &mut c),
                sds_result::Ok
            );
            assert_eq!(c.to_core().map(|k| k.bounds), Ok(Bounds::DEFAULT));
            let before = c;
            assert_eq!(sds_config_profile(7, &mut c), sds_result::ConfigProfile);
            assert_eq!(c, before, "nothing written on a failure");
            assert_eq!(
                sds_config_profile(SDS_PROFILE_PHYSICAL, core::ptr::null_mut()),
                sds_result::NullPointer
            );
        }
        let mut trap = sds_config_default();
        trap.profile = SDS_PROFILE_AUTOWARE;
        assert_eq!(trap.to_core(), Err(sds_result::ConfigProfileBounds));
        // Bounds of the caller's own choosing are the caller's.
        trap.bounds.lat_acc = 2.0;
        assert!(trap.to_core().is_ok());
    }

    #[test]
    fn validation_is_the_core_s() {
        let mut c = sds_config_default();
        c.chunk_len = 21;
        // SAFETY: a valid pointer to a local.
        assert_eq!(
            unsafe { sds_config_validate(&c) },
            sds_result::ConfigChunkLen
        );
        c = sds_config_default();
        c.factors.layout = 0.0;
        assert_eq!(c.to_core(), Err(sds_result::ConfigFactor));
        c = sds_config_default();
        c.profile = 7;
        assert_eq!(c.to_core(), Err(sds_result::ConfigProfile));
        c.profile = SDS_PROFILE_B2D_LEGACY;
        assert_eq!(c.to_core().map(|c| c.profile), Ok(Profile::B2dLegacy));
        // SAFETY: NULL is allowed and refused.
        assert_eq!(
            unsafe { sds_config_validate(core::ptr::null()) },
            sds_result::NullPointer
        );
    }
}
