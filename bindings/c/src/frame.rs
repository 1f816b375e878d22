//! `sds_frame`: one telemetry frame in the ego's body frame, as the monitor consumes it.

use monitor_core::{Collisions, Frame};

use crate::result::sds_result;
use crate::{guard, usable};

/// Collisions aligned to one frame, counted by kind.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct sds_collisions {
    /// Pedestrian collisions.
    pub pedestrian: u16,
    /// Vehicle collisions.
    pub vehicle: u16,
    /// Layout collisions that are not work-zone contacts.
    pub layout: u16,
    /// Work-zone contacts (layout collisions with work-zone objects).
    pub workzone: u16,
}

/// One frame. Zero-initialise it (`sds_frame f = {0};`) and set the fields you know.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct sds_frame {
    /// Longitudinal acceleration `acc · forward` (2-D), m/s².
    pub a_lon: f32,
    /// Lateral acceleration `acc · right` (2-D), m/s².
    pub a_lat: f32,
    /// Acceleration magnitude `hypot(acc_x, acc_y)`, m/s² (not negative).
    pub a_mag: f32,
    /// Yaw rate in **degrees per second** (CARLA's unit); the profile converts it.
    pub yaw_rate: f32,
    /// Planar speed, m/s (not negative).
    pub speed: f32,
    /// Unsigned distance to the route reference, m; read only when `has_lat_err` is true.
    pub lat_err: f32,
    /// False when the distance to the reference is unknown (no reference, a junction gap).
    pub has_lat_err: bool,
    /// Collisions aligned to this frame.
    pub collisions: sds_collisions,
}

impl From<sds_collisions> for Collisions {
    fn from(c: sds_collisions) -> Self {
        Collisions {
            pedestrian: c.pedestrian,
            vehicle: c.vehicle,
            layout: c.layout,
            workzone: c.workzone,
        }
    }
}

impl From<Collisions> for sds_collisions {
    fn from(c: Collisions) -> Self {
        sds_collisions {
            pedestrian: c.pedestrian,
            vehicle: c.vehicle,
            layout: c.layout,
            workzone: c.workzone,
        }
    }
}

impl From<&sds_frame> for Frame {
    fn from(f: &sds_frame) -> Self {
        Frame {
            a_lon: f.a_lon,
            a_lat: f.a_lat,
            a_mag: f.a_mag,
            yaw_rate: f.yaw_rate,
            speed: f.speed,
            lat_err: if f.has_lat_err { Some(f.lat_err) } else { None },
            collisions: f.collisions.into(),
        }
    }
}

/// Fills the signals of `out` from the 2-D parts of CARLA's `acceleration`, `forward_vector` and
/// `right_vector` (two floats each), with the same f32 kernels as the Rust tools, so that C and
/// Rust frames agree to the bit. Sets `yaw_rate` and `speed`; leaves `lat_err`, `has_lat_err` and
/// `collisions` as they were.
///
/// ```c
/// const float acc[2] = {1.5f, -0.25f}, fwd[2] = {0.6f, 0.8f}, right[2] = {0.8f, -0.6f};
/// sds_frame f = {0};
/// sds_frame_from_vectors(acc, fwd, right, 3.0f /* deg/s */, 7.0f /* m/s */, &f);
/// ```
///
/// # Safety
/// `acc`, `forward` and `right` are NULL or point to two readable floats each; `out` is NULL or
/// points to a writable `sds_frame`.
#[no_mangle]
pub unsafe extern "C" fn sds_frame_from_vectors(
    acc: *const f32,
    forward: *const f32,
    right: *const f32,
    yaw_rate_deg: f32,
    speed: f32,
    out: *mut sds_frame,
) -> sds_result {
    guard(|| {
        if let Err(e) = usable(acc)
            .and(usable(forward))
            .and(usable(right))
            .and(usable(out))
        {
            return e;
        }
        // SAFETY: each is usable and the caller promises two readable floats.
        let (acc, forward, right) = unsafe {
            (
                acc.cast::<[f32; 2]>().read(),
                forward.cast::<[f32; 2]>().read(),
                right.cast::<[f32; 2]>().read(),
            )
        };
        let f = Frame::from_vectors(
            acc,
            forward,
            right,
            yaw_rate_deg,
            speed,
            None,
            Collisions::NONE,
        );
        // SAFETY: usable, and the caller promises a writable sds_frame that nothing else uses.
        let frame = unsafe { &mut *out };
        frame.a_lon = f.a_lon;
        frame.a_lat = f.a_lat;
        frame.a_mag = f.a_mag;
        frame.yaw_rate = f.yaw_rate;
        frame.speed = f.speed;
        sds_result::Ok
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_vectors_matches_the_core() {
        let mut f = sds_frame {
            has_lat_err: true,
            lat_err: 0.5,
            ..Default::default()
        };
        let (acc, fwd, right) = ([1.5f32, -0.25], [0.6f32, 0.8], [0.8f32, -0.6]);
        // SAFETY: valid pointers to locals.
        let r = unsafe {
            sds_frame_from_vectors(acc.as_ptr(), fwd.as_ptr(), right.as_ptr(), 3.0, 7.0, &mut f)
        };
        assert_eq!(r, sds_result::Ok);
        let core = Frame::from_vectors(acc, fwd, right, 3.0, 7.0, Some(0.5), Collisions::NONE);
        assert_eq!(Frame::from(&f), core);
        // SAFETY: NULL is refused before any access.
        let r = unsafe {
            sds_frame_from_vectors(
                core::ptr::null(),
                fwd.as_ptr(),
                right.as_ptr(),
                0.0,
                0.0,
                &mut f,
            )
        };
        assert_eq!(r, sds_result::NullPointer);
    }
}
