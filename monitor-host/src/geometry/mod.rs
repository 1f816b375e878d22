//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit), the [`lateral`] tracker
//! (the reference polyline and its bounded forward search), the [`nearest`] frame index,
//! OpenDRIVE [`map`]s (`SDS-SPEC.md` §1.4, §2), the run's [`town_maps`] and the lane
//! [`corridor`] (the lateral value per frame).

pub mod corridor;
pub mod kinematics;
pub mod lateral;
pub mod map;
pub mod nearest;
pub mod town_maps;
