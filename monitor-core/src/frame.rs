//! The per-frame input of the monitor (docs/SCORE.md §3) and its validation.

use crate::error::{Field, FrameError};
use crate::signal;

/// Collision events aligned to one frame, counted by kind (docs/SCORE.md §6 and 7).
///
/// `layout` counts layout collisions that are *not* work-zone contacts; `workzone` counts those
/// that are. All four kinds are collisions for the deceleration check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Collisions {
    /// Entries of `collisions_pedestrian` aligned to this frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub pedestrian: u16,
    /// Entries of `collisions_vehicle` aligned to this frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub vehicle: u16,
    /// Entries of `collisions_layout` (not work-zone objects) aligned to this frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub layout: u16,
    /// Work-zone contacts (a subset of `collisions_layout`) aligned to this frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub workzone: u16,
}

impl Collisions {
    /// No collision.
    pub const NONE: Collisions = Collisions {
        pedestrian: 0,
        vehicle: 0,
        layout: 0,
        workzone: 0,
    };

    /// All collisions of the frame.
    ///
    /// ```
    /// let c = monitor_core::Collisions { vehicle: 2, workzone: 1, ..Default::default() };
    /// assert_eq!(c.total(), 3);
    /// ```
    pub const fn total(&self) -> u32 {
        self.pedestrian as u32 + self.vehicle as u32 + self.layout as u32 + self.workzone as u32
    }
}

/// One telemetry frame in the body frame of the ego, as the monitor consumes it.
///
/// Build it from raw CARLA vectors with [`Frame::from_vectors`] so that every path computes the
/// signals with the same f32 kernels.
///
/// ```
/// use monitor_core::{Frame, Collisions};
/// let f = Frame::from_vectors([1.0, 0.0], [1.0, 0.0], [0.0, 1.0], 0.0, 5.0, Some(0.1),
///                             Collisions::NONE);
/// assert_eq!(f.a_lon, 1.0);
/// assert_eq!(f.a_lat, 0.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Frame {
    /// Longitudinal acceleration `acc · fwd` (2-D), m/s².
    pub a_lon: f32,
    /// Lateral acceleration `acc · right` (2-D), m/s².
    pub a_lat: f32,
    /// Acceleration magnitude `hypot(acc_x, acc_y)`, m/s².
    pub a_mag: f32,
    /// Yaw rate `angular_velocity[2]` in CARLA's unit, **degrees per second**; the profile decides
    /// whether it is converted to rad/s.
    pub yaw_rate: f32,
    /// Planar speed, m/s (docs/SCORE.md §3: 0 at the first frame).
    pub speed: f32,
    /// Unsigned distance to the route reference, m; `None` when unknown (no reference, or a
    /// junction gap).
    #[cfg_attr(feature = "serde", serde(default))]
    pub lat_err: Option<f32>,
    /// Collisions aligned to this frame.
    #[cfg_attr(feature = "serde", serde(default))]
    pub collisions: Collisions,
}

impl Frame {
    /// Builds a frame from the 2-D parts of CARLA's `acceleration`, `forward_vector` and
    /// `right_vector` with the shared kernels ([`signal::dot2`], [`signal::hypot2`]).
    pub fn from_vectors(
        acc: [f32; 2],
        fwd: [f32; 2],
        right: [f32; 2],
        yaw_rate_deg: f32,
        speed: f32,
        lat_err: Option<f32>,
        collisions: Collisions,
    ) -> Frame {
        Frame {
            a_lon: signal::dot2(acc, fwd),
            a_lat: signal::dot2(acc, right),
            a_mag: signal::hypot2(acc[0], acc[1]),
            yaw_rate: yaw_rate_deg,
            speed,
            lat_err,
            collisions,
        }
    }

    /// Checks that every number is finite and `speed`, `a_mag` are not negative.
    ///
    /// ```
    /// use monitor_core::{Field, Frame, FrameError};
    /// let f = Frame { speed: f32::NAN, ..Frame::default() };
    /// assert_eq!(f.validate(), Err(FrameError::NonFinite(Field::Speed)));
    /// ```
    pub fn validate(&self) -> Result<(), FrameError> {
        let fields = [
            (Field::ALon, self.a_lon),
            (Field::ALat, self.a_lat),
            (Field::AMag, self.a_mag),
            (Field::YawRate, self.yaw_rate),
            (Field::Speed, self.speed),
        ];
        for (field, v) in fields {
            if !v.is_finite() {
                return Err(FrameError::NonFinite(field));
            }
        }
        if let Some(l) = self.lat_err {
            if !l.is_finite() {
                return Err(FrameError::NonFinite(Field::LatErr));
            }
        }
        if self.speed < 0.0 {
            return Err(FrameError::Negative(Field::Speed));
        }
        if self.a_mag < 0.0 {
            return Err(FrameError::Negative(Field::AMag));
        }
        Ok(())
    }
}
