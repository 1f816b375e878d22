//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit) and the [`lateral`] tracker
//! (the reference polyline and its bounded forward search), and the dense route's [`junctions`]
//! (§8.2's junction credit).

pub mod junctions;
pub mod kinematics;
pub mod lateral;
