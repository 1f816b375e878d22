//! # monitor-host
//!
//! The `sds` tool's library: reads real Bench2Drive / CARLA Leaderboard 2.0 artifacts, turns
//! each route's telemetry into [`monitor_core::Frame`]s, streams them through
//! [`monitor_core::Monitor`], and reports per-route and benchmark scores (`SDS-SPEC.md` §10).
//!
//! Data flows one way:
//!
//! ```text
//! results JSON ──> results ─┐
//! metric_info.json ─> telemetry ─┼─> align / route (f64) ─> replay: Frame (f32) ─> Monitor ─> report
//! route XML ──────> route ──┘                                   └─> batch (reference, must agree)
//! ```
#![deny(missing_docs)]

pub mod align;
pub mod batch;
pub mod cli;
pub mod demo;
pub mod geometry;
pub mod infraction;
pub mod replay;
pub mod report;
pub mod results;
pub mod route;
pub mod telemetry;
