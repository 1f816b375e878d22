//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit), the [`lateral`] tracker
//! (the reference polyline and its bounded forward search), the [`nearest`] frame index and
//! OpenDRIVE [`map`]s (`SDS-SPEC.md` §1.4, §2).

pub mod kinematics;
pub mod lateral;
pub mod map;
pub mod nearest;
