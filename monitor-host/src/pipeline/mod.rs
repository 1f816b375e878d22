//! The per-route pipeline: [`prepare`] (record + telemetry → frames, with [`align`]ed collision
//! events) → [`replay`] (frames → `Monitor` → summary, checked against the batch reference) →
//! [`outcome`] (what became of the route, with its [`timeline`]).

pub mod align;
pub mod outcome;
pub mod prepare;
pub mod replay;
pub mod timeline;
