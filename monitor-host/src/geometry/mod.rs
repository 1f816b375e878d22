//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit) and the [`lateral`] tracker
//! (the reference polyline and its bounded forward search), the [`nearest`] frame index.

pub mod kinematics;
pub mod lateral;
pub mod nearest;
