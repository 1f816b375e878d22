//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit) and the [`lateral`] tracker
//! (the reference polyline and its bounded forward search).

pub mod kinematics;
pub mod lateral;
