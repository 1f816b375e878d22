//! Host geometry, in f64: [`kinematics`] (speed, the yaw-rate unit), the [`lateral`] tracker
//! (the reference polyline and its bounded forward search), the [`nearest`] frame index,
//! OpenDRIVE [`map`]s (docs/SCORE.md §14.3, docs/SCORE.md §3), whether a map serves a route ([`map_fit`]),
//! the run's [`town_maps`], the lane
//! [`corridor`] (the lateral value per frame) and the dense route's [`junctions`] (docs/SCORE.md §10.1's
//! junction credit).

pub mod corridor;
pub mod junctions;
pub mod kinematics;
pub mod lateral;
pub mod map;
pub mod map_fit;
pub mod nearest;
pub mod town_maps;
